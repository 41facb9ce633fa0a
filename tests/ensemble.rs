//! `kessler ensemble` through the binary: with the local executor a run,
//! its folder and aggregate (the percentiles against a hand computation),
//! resuming, a member killed half-way, Ctrl-C, and bad input; with the
//! Slurm executor against a real cluster, the job array, `--wait`, and
//! members equal, bit for bit, to the local executor's, and resuming
//! submits only the missing members.
//!
//! Where no Slurm cluster answers (`sinfo` missing or failing), each Slurm
//! test prints one line saying it was skipped and why, and passes — unless
//! `KESSLER_REQUIRE_SLURM_TESTS=1` (as in CI, which starts a one-node
//! cluster with `.ci/slurm up`), where that fails it. Slurm's clients find
//! the cluster as usual (`SLURM_CONF`, or `/etc/slurm/slurm.conf`).

mod common {
    pub mod binary;
    pub mod errors;
    pub mod skip;
}

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::binary::{KESSLER, isolated, kessler};
use common::errors::{assert_one_clear_line, corpus, expectation};
use common::skip::Needs;

/// The cascade scene, relative to a config in a temporary folder.
fn cascade() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/cascade.ron")
}

/// Writes a config into `dir` and returns its path.
fn config(dir: &Path, name: &str, fields: &str) -> PathBuf {
    let path = dir.join(name);
    let text = format!("Ensemble(scenario: {:?}, {fields})", cascade().display().to_string());
    std::fs::write(&path, text).unwrap();
    path
}

/// A small ensemble: two thresholds, three members each, 60 updates.
const SMALL: &str = "steps: 60, every: 10, members: 3, seed: 5, vary: (shatter_threshold: [2.0, 4.0]), threads: 1";

/// `kessler ensemble CONFIG --out OUT ARGS...`, run to its end.
fn ensemble(config: &Path, out: &Path, args: &[&str]) -> std::process::Output {
    kessler()
        .arg("ensemble")
        .arg(config)
        .arg("--out")
        .arg(out)
        .args(args)
        .output()
        .unwrap()
}

/// `kessler ensemble CONFIG --out OUT --jobs 1` started, to signal.
fn start_ensemble(config: &Path, out: &Path) -> Child {
    spawn(&[
        "ensemble".as_ref(),
        config.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--jobs".as_ref(),
        "1".as_ref(),
    ])
}

/// The binary as a plain command (to spawn and signal), blind to the
/// user's own files like `kessler()`.
fn spawn(args: &[&std::ffi::OsStr]) -> Child {
    isolated(KESSLER)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn read(path: impl AsRef<Path>) -> String {
    std::fs::read_to_string(path.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", path.as_ref().display()))
}

/// A member's files that must not depend on how or where it ran: its
/// timeline, and its summary without the wall time.
fn results(dir: &Path, index: u64) -> (String, String) {
    let member = dir.join("members").join(index.to_string());
    assert!(
        member.join("done").is_file(),
        "member {index} not done in {}",
        dir.display()
    );
    let summary: String = read(member.join("summary.ron"))
        .lines()
        .filter(|l| !l.contains("wall_seconds"))
        .collect::<Vec<_>>()
        .join("\n");
    (read(member.join("timeline.csv")), summary)
}

/// A CSV file's cells of `column`, by row.
fn column(text: &str, column: &str) -> Vec<String> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header
        .iter()
        .position(|c| *c == column)
        .unwrap_or_else(|| panic!("no column {column}"));
    lines.map(|l| l.split(',').nth(k).unwrap().to_owned()).collect()
}

fn numbers(text: &str, name: &str) -> Vec<f64> {
    column(text, name).iter().map(|c| c.parse().unwrap()).collect()
}

#[test]
fn an_ensemble_runs_sums_up_by_hand_and_resumes_without_rerunning() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "small.ron", SMALL);
    let out = tmp.path().join("ens");
    let run = ensemble(&cfg, &out, &[]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let said = String::from_utf8_lossy(&run.stdout);
    assert!(said.contains("from 6 members in 2 combinations"), "{said}");
    for file in [
        "ensemble.ron",
        "scenario.ron",
        "aggregate.csv",
        "bodies.svg",
        "bodies.png",
    ] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let record = read(out.join("ensemble.ron"));
    for field in ["config_hash: \"", "scenario_hash: \"", "kessler: \"", "commit: \""] {
        assert!(record.contains(field), "ensemble.ron lacks {field}:\n{record}");
    }

    assert_members_have_seeds_of_their_own(&out);
    assert_aggregate_is_the_members_by_hand(&out);
    let before = assert_nothing_reruns(&cfg, &out);
    // Another config for the same folder is refused, naming what differs.
    let other = config(tmp.path(), "other.ron", &SMALL.replace("steps: 60", "steps: 70"));
    let refused = ensemble(&other, &out, &[]);
    assert_eq!(refused.status.code(), Some(2));
    assert_one_clear_line(
        &refused.stderr,
        &["holds another ensemble", "`steps` is 60 there, 70 here"],
    );
    assert_eq!(results(&out, 4), before);
}

/// Every member has a seed of its own, the same seed at the same place in
/// both combinations.
fn assert_members_have_seeds_of_their_own(out: &Path) {
    let seed = |i: u64| {
        let summary = read(out.join(format!("members/{i}/summary.ron")));
        let line = summary
            .lines()
            .find(|l| l.trim().starts_with("seed:"))
            .unwrap()
            .to_owned();
        line.trim()
            .trim_start_matches("seed:")
            .trim()
            .trim_end_matches(',')
            .parse::<u64>()
            .unwrap()
    };
    let seeds: Vec<u64> = (0..6).map(seed).collect();
    assert_eq!(&seeds[..3], &seeds[3..], "common random numbers");
    assert!(seeds[0] != seeds[1] && seeds[1] != seeds[2] && seeds[0] != seeds[2]);
    assert!(!seeds.contains(&5) && !seeds.contains(&6), "not seed + index");
}

/// The aggregate against a hand computation from the members' timelines:
/// with three members, sorted a ≤ b ≤ c, the 5th percentile is
/// a + 0.1·(b − a), the median b, the 95th b + 0.9·(c − b).
fn assert_aggregate_is_the_members_by_hand(out: &Path) {
    let aggregate = read(out.join("aggregate.csv"));
    let combination = column(&aggregate, "combination");
    assert_eq!(aggregate.lines().count(), 1 + 2 * 7);
    for c in 0..2u64 {
        let timelines: Vec<String> = (0..3)
            .map(|m| read(out.join(format!("members/{}/timeline.csv", c * 3 + m))))
            .collect();
        let rows: Vec<usize> = (0..combination.len())
            .filter(|&r| combination[r] == c.to_string())
            .collect();
        assert_eq!(rows.len(), 7);
        for (metric, member_column) in [
            ("bodies", "bodies"),
            ("kinetic_energy", "kinetic_energy"),
            ("shatters", "shatters"),
        ] {
            let per_member: Vec<Vec<f64>> = timelines
                .iter()
                .map(|t| {
                    let values = numbers(t, member_column);
                    if metric == "shatters" {
                        // Shatters since the previous row, summed up.
                        values
                            .iter()
                            .scan(0.0, |so_far, s| {
                                *so_far += s;
                                Some(*so_far)
                            })
                            .collect()
                    } else {
                        values
                    }
                })
                .collect();
            let p5 = numbers(&aggregate, &format!("{metric}_p5"));
            let median = numbers(&aggregate, &format!("{metric}_median"));
            let p95 = numbers(&aggregate, &format!("{metric}_p95"));
            let mean = numbers(&aggregate, &format!("{metric}_mean"));
            for (k, &r) in rows.iter().enumerate() {
                let mut v = [per_member[0][k], per_member[1][k], per_member[2][k]];
                v.sort_by(f64::total_cmp);
                let [a, b, c3] = v;
                let close = |x: f64, y: f64| (x - y).abs() <= 1e-9 * y.abs().max(1.0);
                assert!(
                    close(p5[r], a + 0.1 * (b - a)),
                    "{metric} p5 row {r}: {} vs {v:?}",
                    p5[r]
                );
                assert!(close(median[r], b), "{metric} median row {r}");
                assert!(
                    close(p95[r], b + 0.9 * (c3 - b)),
                    "{metric} p95 row {r}: {} vs {v:?}",
                    p95[r]
                );
                assert!(close(mean[r], (a + b + c3) / 3.0), "{metric} mean row {r}");
            }
        }
    }
    assert_eq!(column(&aggregate, "settings")[0], "shatter_threshold=2");
    assert!(column(&aggregate, "members").iter().all(|m| m == "3"));
}

/// Status says every member is done; the same command again reruns none,
/// and a member's own rerun gives the same bits. Returns member 4's
/// results.
fn assert_nothing_reruns(cfg: &Path, out: &Path) -> (String, String) {
    let status = kessler().args(["ensemble", "status"]).arg(out).output().unwrap();
    assert!(String::from_utf8_lossy(&status.stdout).contains("6 done, 0 failed, 0 missing of 6 members"));
    let before = results(out, 4);
    let stamp = std::fs::metadata(out.join("members/4/done"))
        .unwrap()
        .modified()
        .unwrap();
    let again = ensemble(cfg, out, &[]);
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("all 6 members are done"));
    assert_eq!(
        std::fs::metadata(out.join("members/4/done"))
            .unwrap()
            .modified()
            .unwrap(),
        stamp
    );
    assert_eq!(results(out, 4), before);

    // A member's own rerun gives the same bits.
    let member = kessler()
        .args(["ensemble", "member"])
        .arg(out)
        .arg("4")
        .output()
        .unwrap();
    assert!(member.status.success(), "{}", String::from_utf8_lossy(&member.stderr));
    assert_eq!(results(out, 4), before);

    before
}

/// The pid of the running `kessler ensemble member DIR INDEX`.
fn member_pid(dir: &Path, index: u64) -> Option<u32> {
    let wanted = [
        "ensemble".to_owned(),
        "member".to_owned(),
        dir.display().to_string(),
        index.to_string(),
    ];
    for entry in std::fs::read_dir("/proc").ok()?.flatten() {
        let Ok(pid) = entry.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(cmdline) = std::fs::read(entry.path().join("cmdline")) else {
            continue;
        };
        let args: Vec<String> = cmdline
            .split(|&b| b == 0)
            .filter(|a| !a.is_empty())
            .map(|a| String::from_utf8_lossy(a).into_owned())
            .collect();
        if args.len() >= 5 && args[1..5] == wanted {
            return Some(pid);
        }
    }
    None
}

/// Waits (at most a minute) until `ready` holds.
fn wait_until(what: &str, mut ready: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "timed out waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(pid: u32, name: &str) {
    let status = Command::new("kill")
        .arg(format!("-{name}"))
        .arg(pid.to_string())
        .status()
        .unwrap();
    assert!(status.success());
}

/// Members that take a second or two each.
const SLOW: &str = "steps: 1500, every: 100, members: 3, seed: 9, threads: 1";

#[cfg(target_os = "linux")]
#[test]
fn a_member_killed_half_way_fails_alone_and_resumes_equal_to_an_uninterrupted_one() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "slow.ron", SLOW);
    let straight = tmp.path().join("straight");
    let ok = ensemble(&cfg, &straight, &[]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));

    let out = std::path::absolute(tmp.path().join("killed")).unwrap();
    let executor = start_ensemble(&cfg, &out);
    let mut pid = None;
    wait_until("member 1 to run", || {
        pid = member_pid(&out, 1);
        pid.is_some()
    });
    std::thread::sleep(Duration::from_millis(300));
    signal(pid.unwrap(), "KILL");
    let ended = executor.wait_with_output().unwrap();
    assert_eq!(
        ended.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&ended.stderr)
    );
    let stderr = String::from_utf8_lossy(&ended.stderr);
    assert!(stderr.contains("member 1 failed: ended by signal 9"), "{stderr}");
    assert!(stderr.contains("2 done, 1 failed, 0 missing of 3 members"), "{stderr}");
    assert!(read(out.join("members/1/failed")).starts_with("ended by signal 9"));
    assert!(out.join("logs/1.err").is_file(), "a failed member's log stays");
    // The others went on and were summed up.
    assert!(out.join("aggregate.csv").is_file());
    let status = kessler().args(["ensemble", "status"]).arg(&out).output().unwrap();
    let status = String::from_utf8_lossy(&status.stdout);
    assert!(
        status.contains("2 done, 1 failed") && status.contains("member 1 failed: ended by signal 9"),
        "{status}"
    );

    let resumed = ensemble(&cfg, &out, &[]);
    assert!(resumed.status.success(), "{}", String::from_utf8_lossy(&resumed.stderr));
    assert!(String::from_utf8_lossy(&resumed.stderr).contains("1 to run"));
    for index in 0..3 {
        assert_eq!(results(&out, index), results(&straight, index), "member {index}");
    }
    assert!(!out.join("members/1/failed").exists());
    assert_eq!(read(out.join("aggregate.csv")), read(straight.join("aggregate.csv")));
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_keeps_the_finished_members_and_removes_the_running_one() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "slow.ron", SLOW);
    let out = std::path::absolute(tmp.path().join("stopped")).unwrap();
    let executor = start_ensemble(&cfg, &out);
    wait_until("member 1 to run", || member_pid(&out, 1).is_some());
    signal(executor.id(), "INT");
    let ended = executor.wait_with_output().unwrap();
    assert_eq!(ended.status.code(), Some(130));
    // The line the run starts with, then the one it ends with.
    let stderr = String::from_utf8_lossy(&ended.stderr);
    let last = stderr.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.starts_with("kessler: error: interrupted: 1 members finished and kept, 1 running ended and removed"),
        "{stderr}"
    );
    assert!(out.join("members/0/done").is_file());
    assert!(
        !out.join("members/1").exists(),
        "the running member's folder is removed"
    );
    assert!(member_pid(&out, 1).is_none(), "the running member is ended");
    let status = kessler().args(["ensemble", "status"]).arg(&out).output().unwrap();
    assert!(String::from_utf8_lossy(&status.stdout).contains("1 done, 0 failed, 2 missing of 3 members"));
}

#[test]
fn every_malformed_ensemble_config_is_a_clear_error_before_any_work() {
    let files = corpus("bad_ensembles");
    assert!(files.len() >= 8, "corpus has only {} files", files.len());
    let tmp = tempfile::tempdir().unwrap();
    for file in files {
        let name = file.display().to_string();
        let out = tmp.path().join("never");
        let run = ensemble(&file, &out, &[]);
        assert_eq!(
            run.status.code(),
            Some(2),
            "{name}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert_one_clear_line(&run.stderr, &[&name, &expectation(&file)]);
        assert!(!out.exists(), "{name}: the folder was made");
    }
}

#[test]
fn output_folders_that_cannot_hold_an_ensemble_are_refused_untouched() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "small.ron", SMALL);
    let file = tmp.path().join("a-file");
    std::fs::write(&file, "precious").unwrap();
    let busy = tmp.path().join("busy");
    std::fs::create_dir(&busy).unwrap();
    std::fs::write(busy.join("notes.txt"), "precious").unwrap();
    let mut cases: Vec<(PathBuf, &str)> = vec![
        (file.clone(), "is a file; give a folder"),
        (busy.clone(), "holds files but no ensemble.ron"),
        (tmp.path().join("no/such/folder"), "does not exist"),
        (PathBuf::from("/proc"), "cannot write in folder /proc"),
    ];
    #[cfg(unix)]
    {
        let fifo = tmp.path().join("fifo");
        assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        cases.push((fifo, "is a FIFO (named pipe); give a folder"));
    }
    for (out, expected) in cases {
        let run = ensemble(&cfg, &out, &[]);
        assert_eq!(run.status.code(), Some(2), "{}", out.display());
        assert_one_clear_line(&run.stderr, &["--out", expected]);
    }
    assert_eq!(read(&file), "precious");
    assert_eq!(std::fs::read_dir(&busy).unwrap().count(), 1);

    // Options that do not go with the local executor, and a member index
    // past the ensemble.
    for (args, expected) in [
        (&["--wait"][..], "--wait: goes with --executor slurm"),
        (
            &["--slurm-arg=--partition=x"][..],
            "--slurm-arg --partition=x: goes with --executor slurm",
        ),
        (&["--jobs", "0"][..], "must be a whole number from 1 to 1000000"),
    ] {
        let out = tmp.path().join("fresh");
        let run = ensemble(&cfg, &out, args);
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        assert_one_clear_line(&run.stderr, &[expected]);
    }
    let out = tmp.path().join("ens");
    let ran = ensemble(&cfg, &out, &[]);
    assert!(ran.status.success());
    let past = kessler()
        .args(["ensemble", "member"])
        .arg(&out)
        .arg("6")
        .output()
        .unwrap();
    assert_eq!(past.status.code(), Some(2));
    assert_one_clear_line(&past.stderr, &["INDEX 6: the ensemble in", "has 6 members, 0 to 5"]);
    let not_one = kessler().args(["ensemble", "status"]).arg(tmp.path()).output().unwrap();
    assert_eq!(not_one.status.code(), Some(2));
    assert_one_clear_line(&not_one.stderr, &["is not an ensemble's folder"]);
}

/// Why Slurm cannot be used here, if it cannot.
fn missing_slurm() -> Option<String> {
    match Command::new("sinfo").args(["--noheader", "--format=%T"]).output() {
        Err(e) => Some(format!("`sinfo` cannot be run ({e})")),
        Ok(out) if !out.status.success() => Some(format!(
            "`sinfo` failed: {}",
            String::from_utf8_lossy(&out.stderr).lines().last().unwrap_or_default()
        )),
        Ok(out)
            if !String::from_utf8_lossy(&out.stdout)
                .lines()
                .any(|l| l.starts_with("idle") || l.starts_with("mixed")) =>
        {
            Some(format!(
                "no Slurm node takes jobs (sinfo: {})",
                String::from_utf8_lossy(&out.stdout).trim()
            ))
        }
        Ok(_) => None,
    }
}

/// What the Slurm tests need.
const SLURM: Needs = Needs {
    test: "Slurm test",
    tests: "Slurm tests",
    require: "KESSLER_REQUIRE_SLURM_TESTS",
    install: "apt install slurmctld slurmd munge, then `.ci/slurm up DIR`",
};

/// Whether the test may run; says on stderr why not.
fn slurm_here(test: &str) -> bool {
    SLURM.available(test, missing_slurm())
}

#[test]
fn a_slurm_job_array_gives_the_local_executors_members_and_resumes_the_missing() {
    if !slurm_here("a_slurm_job_array_gives_the_local_executors_members_and_resumes_the_missing") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/cascade.ron");
    let config = tmp.path().join("small.ron");
    std::fs::write(
        &config,
        format!(
            "Ensemble(scenario: {:?}, steps: 80, every: 20, members: 3, seed: 11, vary: (fragment_spread: [0.1, 0.4]))",
            scenario.display().to_string()
        ),
    )
    .unwrap();
    let local = tmp.path().join("local");
    let ran = ensemble(&config, &local, &[]);
    assert!(ran.status.success(), "{}", String::from_utf8_lossy(&ran.stderr));

    let slurm = std::path::absolute(tmp.path().join("slurm")).unwrap();
    let submitted = ensemble(
        &config,
        &slurm,
        &["--executor", "slurm", "--jobs", "2", "--wait", "--slurm-arg=--time=10"],
    );
    let said = String::from_utf8_lossy(&submitted.stdout);
    assert!(
        submitted.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&submitted.stderr)
    );
    assert!(
        said.contains("submitted job array") && said.contains("6 members (`0-5`)"),
        "{said}"
    );
    let script = read(slurm.join("slurm/ensemble.sbatch"));
    for line in ["#SBATCH --array=0-5%2", "#SBATCH --cpus-per-task=1"] {
        assert!(script.lines().any(|l| l == line), "missing {line}:\n{script}");
    }
    let exe = std::fs::canonicalize(KESSLER).unwrap();
    assert!(script.contains(&format!("kessler='{}'", exe.display())), "{script}");
    assert!(
        std::fs::read_dir(slurm.join("slurm/logs")).unwrap().count() >= 6,
        "a log per task"
    );
    for index in 0..6 {
        assert_eq!(results(&slurm, index), results(&local, index), "member {index}");
    }
    assert_eq!(read(slurm.join("aggregate.csv")), read(local.join("aggregate.csv")));

    // Two members lost: resuming submits those two alone.
    for index in [1, 4] {
        std::fs::remove_dir_all(slurm.join("members").join(index.to_string())).unwrap();
    }
    let resumed = ensemble(&config, &slurm, &["--executor", "slurm", "--wait"]);
    let said = String::from_utf8_lossy(&resumed.stdout);
    assert!(
        resumed.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert!(said.contains("2 members (`1,4`)"), "{said}");
    assert!(read(slurm.join("slurm/ensemble.sbatch")).contains("#SBATCH --array=1,4\n"));
    assert_eq!(
        read(slurm.join("slurm/jobs")).lines().count(),
        2,
        "a line per job submitted"
    );
    for index in 0..6 {
        assert_eq!(results(&slurm, index), results(&local, index), "member {index}");
    }
}

#[test]
fn sbatch_refusing_the_job_is_one_clear_line() {
    if !slurm_here("sbatch_refusing_the_job_is_one_clear_line") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let config = tmp.path().join("c.ron");
    std::fs::write(
        &config,
        format!(
            "Ensemble(scenario: {:?}, steps: 1, members: 1)",
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("scenarios/two_body.ron")
                .display()
                .to_string()
        ),
    )
    .unwrap();
    let out = tmp.path().join("ens");
    let refused = ensemble(
        &config,
        &out,
        &["--executor", "slurm", "--slurm-arg=--partition=no_such_partition"],
    );
    assert_eq!(refused.status.code(), Some(1));
    // The line the run starts with, then the one it ends with.
    let stderr = String::from_utf8_lossy(&refused.stderr);
    let last = stderr.trim_end().lines().last().unwrap_or_default();
    assert!(
        last.starts_with("kessler: error: --executor slurm: sbatch refused") && last.contains("no_such_partition"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"));
    let status = kessler().args(["ensemble", "status"]).arg(&out).output().unwrap();
    assert!(String::from_utf8_lossy(&status.stdout).contains("0 done, 0 failed, 1 missing of 1 members"));
}

/// `ensemble aggregate` keeps the output rule of every command: what is
/// not a regular file where its outputs go (a FIFO, a symbolic link) is
/// left alone, the command fails, and none of its outputs is written.
#[cfg(unix)]
#[test]
fn aggregate_replaces_only_regular_files() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "one.ron", "steps: 20, every: 10, members: 1, threads: 1");
    let out = tmp.path().join("ens");
    let run = ensemble(&cfg, &out, &[]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let plot = out.join("bodies.png");
    let before = std::fs::read(&plot).unwrap();
    for (taken, what) in [("aggregate.csv", "a FIFO"), ("bodies.svg", "a symbolic link")] {
        let path = out.join(taken);
        std::fs::remove_file(&path).unwrap();
        if what == "a FIFO" {
            assert!(isolated("mkfifo").arg(&path).status().unwrap().success());
        } else {
            std::os::unix::fs::symlink(tmp.path().join("elsewhere.svg"), &path).unwrap();
        }
        let again = kessler().args(["ensemble", "aggregate"]).arg(&out).output().unwrap();
        let stderr = String::from_utf8_lossy(&again.stderr);
        assert_eq!(again.status.code(), Some(2), "{taken}: {stderr}");
        assert!(stderr.contains(taken) && stderr.contains(what), "{taken}: {stderr}");
        let kind = std::fs::symlink_metadata(&path).unwrap().file_type();
        assert!(!kind.is_file(), "{taken} was replaced");
        assert_eq!(std::fs::read(&plot).unwrap(), before, "{taken}: the plot was written");
        std::fs::remove_file(&path).unwrap();
    }
    assert!(!tmp.path().join("elsewhere.svg").exists(), "written through the link");
}

/// The small ensemble run twice in `dir`: its config, a folder to keep
/// clean and one to damage.
fn two_small_runs(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let cfg = config(dir, "small.ron", SMALL);
    let (clean, out) = (dir.join("clean"), dir.join("damaged"));
    for dir in [&clean, &out] {
        let run = ensemble(&cfg, dir, &[]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    }
    (cfg, clean, out)
}

/// Resumes the ensemble in `out`, which runs `to_run` members, and checks
/// that every member and the aggregate are then those of `clean`.
fn resumes_to_the_clean_run(cfg: &Path, out: &Path, clean: &Path, to_run: usize) {
    let resumed = ensemble(cfg, out, &[]);
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{stderr}");
    assert!(stderr.contains(&format!("{to_run} to run")), "{stderr}");
    for index in 0..6 {
        assert_eq!(results(out, index), results(clean, index), "member {index}");
    }
    assert_eq!(read(out.join("aggregate.csv")), read(clean.join("aggregate.csv")));
}

/// A finished member whose files were damaged afterwards is found and run
/// again, bit-equal to an undamaged run: its timeline cut short, deleted,
/// made a FIFO or given a NaN, its folder made a file. `status` names each,
/// `aggregate` leaves them out saying what runs them, and the resume puts
/// every member back as it was.
#[cfg(unix)]
#[test]
fn damaged_members_are_found_and_run_again_bit_equal() {
    let tmp = tempfile::tempdir().unwrap();
    let (cfg, clean, out) = two_small_runs(tmp.path());
    let timeline = |i: u64| out.join(format!("members/{i}/timeline.csv"));
    let text = read(timeline(0));
    let first_rows: Vec<&str> = text.lines().take(4).collect();
    std::fs::write(timeline(0), first_rows.join("\n") + "\n").unwrap();
    std::fs::remove_file(timeline(1)).unwrap();
    std::fs::remove_file(timeline(2)).unwrap();
    assert!(isolated("mkfifo").arg(timeline(2)).status().unwrap().success());
    let text = read(timeline(3));
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let mut cells: Vec<&str> = lines[2].split(',').collect();
    cells[1] = "NaN";
    lines[2] = cells.join(",");
    std::fs::write(timeline(3), lines.join("\n") + "\n").unwrap();
    std::fs::remove_dir_all(out.join("members/4")).unwrap();
    std::fs::write(out.join("members/4"), "not a folder").unwrap();

    let status = kessler().args(["ensemble", "status"]).arg(&out).output().unwrap();
    let said = String::from_utf8_lossy(&status.stdout);
    assert!(said.contains("1 done, 4 failed, 1 missing of 6 members"), "{said}");
    for what in [
        "rows, not the",
        "timeline.csv is missing",
        "a FIFO",
        "`NaN` is not a finite number",
    ] {
        assert!(said.contains(what), "{what} not in {said}");
    }
    let summed = kessler().args(["ensemble", "aggregate"]).arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&summed.stderr);
    assert!(summed.status.success(), "{stderr}");
    assert!(
        stderr.contains("5 member(s) left out") && stderr.contains("--out"),
        "{stderr}"
    );

    resumes_to_the_clean_run(&cfg, &out, &clean, 5);
}

/// A done member whose summary was damaged afterwards (garbage, or a state
/// hash that is not its timeline's) is a damaged member: `status` names
/// it, and the resume runs it again bit-equal to an undamaged run.
#[test]
fn damaged_summaries_are_damaged_members_run_again_bit_equal() {
    let tmp = tempfile::tempdir().unwrap();
    let (cfg, clean, out) = two_small_runs(tmp.path());
    let summary = |i: u64| out.join(format!("members/{i}/summary.ron"));
    std::fs::write(summary(1), "Member(index: 1, garbage").unwrap();
    let hash = column(&read(out.join("members/4/timeline.csv")), "state_hash")
        .pop()
        .unwrap();
    let text = read(summary(4));
    assert!(text.contains(&hash), "{text}");
    std::fs::write(summary(4), text.replace(&hash, "0123456789abcdef")).unwrap();

    let status = kessler().args(["ensemble", "status"]).arg(&out).output().unwrap();
    let said = String::from_utf8_lossy(&status.stdout);
    assert!(said.contains("4 done, 2 failed, 0 missing of 6 members"), "{said}");
    assert!(said.contains("summary.ron:1:"), "the damage located: {said}");
    assert!(
        said.contains(&format!(
            "summary.ron says state_hash 0123456789abcdef, where its ensemble and timeline say {hash}"
        )),
        "{said}"
    );
    resumes_to_the_clean_run(&cfg, &out, &clean, 2);
}

/// A file where the ensemble keeps a folder (`members`, `logs`, `slurm`,
/// `slurm/logs`) is named with what to do, by the resume and by `status`
/// alike, exit 2, the file untouched; moved away, the resume finishes the
/// ensemble as an uninterrupted run does.
#[test]
fn a_file_where_the_ensemble_keeps_a_folder_is_named_with_what_to_do() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "small.ron", SMALL);
    let clean = tmp.path().join("clean");
    assert!(ensemble(&cfg, &clean, &[]).status.success());
    for name in ["members", "logs", "slurm", "slurm/logs"] {
        let out = tmp.path().join(name.replace('/', "_"));
        assert!(ensemble(&cfg, &out, &[]).status.success());
        let path = out.join(name);
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, "precious").unwrap();
        for run in [
            ensemble(&cfg, &out, &[]),
            kessler().args(["ensemble", "status"]).arg(&out).output().unwrap(),
        ] {
            assert_eq!(
                run.status.code(),
                Some(2),
                "{name}: {}",
                String::from_utf8_lossy(&run.stderr)
            );
            assert_one_clear_line(
                &run.stderr,
                &[
                    &path.display().to_string(),
                    "is a file, where the ensemble keeps",
                    "move it away (or remove it), then run the same command again",
                ],
            );
        }
        assert_eq!(read(&path), "precious", "{name}");
        std::fs::remove_file(&path).unwrap();
        let resumed = ensemble(&cfg, &out, &[]);
        assert!(
            resumed.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&resumed.stderr)
        );
        for index in 0..6 {
            assert_eq!(results(&out, index), results(&clean, index), "{name}: member {index}");
        }
    }
}

/// The local executor's members end with it however it ends: SIGTERM is
/// taken as Ctrl-C is (the running member ended, its folder removed), and
/// after SIGKILL the kernel ends them (none goes on writing); a resume
/// after either is the uninterrupted run.
#[cfg(target_os = "linux")]
#[test]
fn the_executors_members_end_with_it() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = config(tmp.path(), "slow.ron", SLOW);
    let straight = tmp.path().join("straight");
    let ok = ensemble(&cfg, &straight, &[]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    for name in ["TERM", "KILL"] {
        let out = std::path::absolute(tmp.path().join(name)).unwrap();
        let executor = start_ensemble(&cfg, &out);
        let mut pid = None;
        wait_until("member 1 to run", || {
            pid = member_pid(&out, 1);
            pid.is_some()
        });
        signal(executor.id(), name);
        let ended = executor.wait_with_output().unwrap();
        if name == "TERM" {
            assert_eq!(
                ended.status.code(),
                Some(130),
                "{}",
                String::from_utf8_lossy(&ended.stderr)
            );
        }
        wait_until("member 1 to end", || {
            std::fs::read_to_string(format!("/proc/{}/cmdline", pid.unwrap())).map_or(true, |c| c.is_empty())
        });
        assert!(!out.join("members/1/done").exists(), "{name}: member 1 went on");
        let resumed = ensemble(&cfg, &out, &[]);
        assert!(
            resumed.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&resumed.stderr)
        );
        for index in 0..3 {
            assert_eq!(
                results(&out, index),
                results(&straight, index),
                "{name}: member {index}"
            );
        }
    }
}

/// Messages that say what was meant: a file given where an ensemble's
/// folder goes, a subcommand misspelt (once taken for the config, with
/// clap's complaint about what followed it).
#[test]
fn a_file_for_a_folder_and_a_misspelt_subcommand_are_named() {
    let tmp = tempfile::tempdir().unwrap();
    let file = config(tmp.path(), "small.ron", SMALL);
    let status = kessler().args(["ensemble", "status"]).arg(&file).output().unwrap();
    assert_eq!(status.status.code(), Some(2));
    assert_one_clear_line(&status.stderr, &["is a file, not an ensemble's folder", "--out DIR"]);
    for (typo, meant) in [("stauts", "status"), ("agregate", "aggregate")] {
        let out = kessler().args(["ensemble", typo]).arg(tmp.path()).output().unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert_one_clear_line(&out.stderr, &[&format!("did you mean `kessler ensemble {meant}`?")]);
    }
}

/// Every ensemble shipped in `ensembles/` loads as the docs write them.
#[test]
fn the_shipped_ensembles_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("ensembles");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ron") {
            let config = kessler::ensemble::EnsembleConfig::load(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(config.total_members() > 0, "{}", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 2, "{checked} ensembles in {}", dir.display());
}
