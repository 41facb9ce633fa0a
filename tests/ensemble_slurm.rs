//! `kessler ensemble --executor slurm` against a real Slurm cluster: the
//! job array it writes and submits, `--wait`, and members equal, bit for
//! bit, to those of the same ensemble run by the local executor; resuming
//! submits only the missing members.
//!
//! Where no Slurm cluster answers (`sinfo` missing or failing), each test
//! prints one line saying it was skipped and why, and passes — unless
//! `KESSLER_REQUIRE_SLURM_TESTS=1` (as in CI, which starts a one-node
//! cluster with `.ci/slurm up`), where that fails it. Slurm's clients
//! find the cluster as usual (`SLURM_CONF`, or `/etc/slurm/slurm.conf`).

use std::io::Write as _;
use std::path::Path;
use std::process::Command;

/// The binary, blind to the user's own settings and calibration.
fn kessler() -> assert_cmd::Command {
    let mut command = assert_cmd::Command::cargo_bin("kessler").unwrap();
    command.env(
        "XDG_CONFIG_HOME",
        std::env::temp_dir().join("kessler-tests-without-config"),
    );
    command
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

/// Whether the test may run; says on stderr why not.
fn slurm_here(test: &str) -> bool {
    let Some(missing) = missing_slurm() else {
        return true;
    };
    if std::env::var_os("KESSLER_REQUIRE_SLURM_TESTS").is_some_and(|v| v == "1") {
        panic!("{test}: {missing}, and KESSLER_REQUIRE_SLURM_TESTS=1 requires the Slurm tests");
    }
    let line = format!(
        "Slurm test `{test}` skipped: {missing} (apt install slurmctld slurmd munge, then `.ci/slurm up DIR`; \
         KESSLER_REQUIRE_SLURM_TESTS=1 turns this into a failure)\n"
    );
    let _ = std::io::stderr().write_all(line.as_bytes());
    false
}

fn read(path: impl AsRef<Path>) -> String {
    std::fs::read_to_string(path.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", path.as_ref().display()))
}

/// A member's timeline and its summary without the wall time.
fn results(dir: &Path, index: u64) -> (String, String) {
    let member = dir.join("members").join(index.to_string());
    assert!(
        member.join("done").is_file(),
        "member {index} not done in {}",
        dir.display()
    );
    let summary = read(member.join("summary.ron"))
        .lines()
        .filter(|l| !l.contains("wall_seconds"))
        .collect::<Vec<_>>()
        .join("\n");
    (read(member.join("timeline.csv")), summary)
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
    let ran = kessler()
        .arg("ensemble")
        .arg(&config)
        .arg("--out")
        .arg(&local)
        .output()
        .unwrap();
    assert!(ran.status.success(), "{}", String::from_utf8_lossy(&ran.stderr));

    let slurm = std::path::absolute(tmp.path().join("slurm")).unwrap();
    let submitted = kessler()
        .arg("ensemble")
        .arg(&config)
        .arg("--out")
        .arg(&slurm)
        .args(["--executor", "slurm", "--jobs", "2", "--wait", "--slurm-arg=--time=10"])
        .output()
        .unwrap();
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
    let exe = std::fs::canonicalize(env!("CARGO_BIN_EXE_kessler")).unwrap();
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
    let resumed = kessler()
        .arg("ensemble")
        .arg(&config)
        .arg("--out")
        .arg(&slurm)
        .args(["--executor", "slurm", "--wait"])
        .output()
        .unwrap();
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
    let refused = kessler()
        .arg("ensemble")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .args(["--executor", "slurm", "--slurm-arg=--partition=no_such_partition"])
        .output()
        .unwrap();
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
