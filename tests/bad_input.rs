//! Bad input through the real binary: one clear line on stderr, exit code 2,
//! no panic, nothing overwritten.

mod common {
    pub mod binary;
    pub mod errors;
}

use common::binary::kessler;
use common::errors::{assert_one_clear_line, corpus, expectation};

#[test]
fn every_malformed_scenario_is_a_clear_error() {
    let files = corpus("bad_scenarios");
    assert!(files.len() >= 15, "corpus has only {} files", files.len());
    let dir = tempfile::tempdir().unwrap();
    let dump = dir.path().join("state.csv");
    for file in files {
        let name = file.display().to_string();
        let expected = expectation(&file);
        let out = kessler().arg("validate").arg(&file).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "validate {name}");
        assert_one_clear_line(&out.stderr, &[&name, &expected]);

        std::fs::write(&dump, "precious").unwrap();
        let out = kessler()
            .args(["headless", "--steps", "1", "--dump"])
            .arg(&dump)
            .arg(&file)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "headless {name}");
        assert_one_clear_line(&out.stderr, &[&name, &expected]);
        assert_eq!(
            std::fs::read_to_string(&dump).unwrap(),
            "precious",
            "{name} overwrote the dump"
        );
    }
}

/// Each command line gets exit code 2 and one clear line holding its
/// needle.
fn assert_refused(cases: &[(&[&str], &str)]) {
    for &(args, needle) in cases {
        let out = kessler().args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_one_clear_line(&out.stderr, &[needle]);
    }
}

#[test]
fn bad_counts_and_choices_are_clear_errors() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let cases: [(&[&str], &str); 13] = [
        (
            &["headless", scenario, "--steps", "-5"],
            "invalid value '-5' for '--steps <STEPS>': must be a whole number from 0 to 1000000000000",
        ),
        (
            &["headless", scenario, "--steps", "18446744073709551615"],
            "--steps <STEPS>': must be a whole number from 0 to 1000000000000",
        ),
        (
            &["run", "--bodies", "100000000"],
            "--bodies <N>': must be a whole number from 0 to 2000000",
        ),
        (
            &["run", "--bodies", "18446744073709551615"],
            "--bodies <N>': must be a whole number from 0 to 2000000",
        ),
        (&["run", "--bodies", "-1"], "--bodies <N>': must be a whole number"),
        (
            &["headless", scenario, "--steps", "1", "--threads", "2.5"],
            "--threads <THREADS>': must be a whole number from 1 to 256",
        ),
        (
            &["run", "--frames", "-5"],
            "--frames <N>': must be a whole number from 1 to 1000000000000",
        ),
        (
            &["run", "--ups", "-3"],
            "--ups <UPS>': must be a whole number from 1 to 600",
        ),
        (&["headless", scenario, "--steps", "ten"], "--steps"),
        (&["headless", scenario], "--steps"),
        (&["headless", scenario, "--steps", "1", "--mode", "fast"], "--mode"),
        (&["headless", scenario, "--steps", "1", "--threads", "0"], "--threads"),
        (
            &["headless", scenario, "--steps", "1", "--threads", "-1"],
            "must be a whole number from 1 to 256",
        ),
    ];
    assert_refused(&cases);
}

#[test]
fn bad_outputs_options_and_commands_are_clear_errors() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let cases: [(&[&str], &str); 12] = [
        (
            &["headless", scenario, "--steps", "1", "--dump", "/no/such/folder/x.csv"],
            "/no/such/folder",
        ),
        (&["launch"], "launch"),
        (
            &["headless", scenario, "--steps", "1", "--split", "sometimes"],
            "--split",
        ),
        (&["headless", scenario, "--steps", "1", "--split", "-5"], "--split"),
        (&["calibrate", "--threads", "0"], "--threads"),
        (
            &[
                "headless",
                scenario,
                "--steps",
                "1",
                "--save-scenario",
                "/no/such/folder/s.ron",
            ],
            "--save-scenario",
        ),
        (
            &[
                "headless",
                scenario,
                "--steps",
                "1",
                "--timeline",
                "t.csv",
                "--every",
                "0",
            ],
            "--every",
        ),
        (
            &[
                "headless",
                scenario,
                "--steps",
                "1",
                "--timeline",
                "t.csv",
                "--every",
                "-2",
            ],
            "--every",
        ),
        (&["headless", scenario, "--steps", "1", "--every", "5"], "--timeline"),
        (
            &["headless", scenario, "--steps", "1", "--gravity", "barnes"],
            "--gravity",
        ),
        (
            &["headless", scenario, "--steps", "1", "--gravity", "tree:-1"],
            "--gravity",
        ),
        (
            &[
                "headless",
                scenario,
                "--steps",
                "1",
                "--timeline",
                "/no/such/folder/t.csv",
            ],
            "--timeline",
        ),
    ];
    assert_refused(&cases);
}

#[test]
fn missing_file_is_a_clear_error() {
    let out = kessler().args(["validate", "no_such_scenario.ron"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_one_clear_line(&out.stderr, &["no_such_scenario.ron", "cannot read"]);
}

/// A file that is not UTF-8 (saved as Latin-1) is named with the line and
/// column of the first byte that is not, by every command that reads it.
#[test]
fn a_file_that_is_not_utf8_is_located() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("latin1.ron");
    std::fs::write(&path, b"Scenario(\n    name: \"Caf\xe9 orbit\",\n)\n").unwrap();
    for command in [&["validate"][..], &["headless", "--steps", "1"]] {
        let out = kessler().args(command).arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{command:?}");
        assert_one_clear_line(&out.stderr, &["latin1.ron:2:15: byte 0xe9 is not UTF-8 text"]);
    }
}

/// A command on `path` that must answer exit 2 at once, naming the path
/// and the problem.
fn refused_at_once(args: &[&std::ffi::OsStr], needles: &[&str]) {
    let start = std::time::Instant::now();
    let out = kessler()
        .args(args)
        .timeout(std::time::Duration::from_secs(60))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {out:?}");
    assert_one_clear_line(&out.stderr, needles);
    assert!(start.elapsed().as_secs() < 30, "{args:?} took {:?}", start.elapsed());
}

#[cfg(unix)]
fn make_fifo(path: &std::path::Path) {
    let made = std::process::Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

fn os(s: &str) -> &std::ffi::OsStr {
    std::ffi::OsStr::new(s)
}

/// A FIFO would block every reader until someone writes, `/dev/zero` never
/// ends: inputs are regular files, refused otherwise at once.
#[cfg(unix)]
#[test]
fn special_files_as_inputs_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("f.ron");
    make_fifo(&fifo);
    let fifo_text = fifo.to_str().unwrap();
    for command in [
        &[os("validate"), fifo.as_os_str()][..],
        &[os("headless"), fifo.as_os_str(), os("--steps"), os("1")],
        &[os("pairs"), fifo.as_os_str()],
    ] {
        refused_at_once(command, &[fifo_text, "is a FIFO (named pipe), not a regular file"]);
    }
    for device in ["/dev/zero", "/dev/urandom"] {
        refused_at_once(&[os("validate"), os(device)], &[device, "is a character device"]);
    }
    // A benchmark config naming a FIFO as its scenario.
    let config = dir.path().join("b.ron");
    std::fs::write(
        &config,
        format!("Bench(scenario: {fifo_text:?}, runs: [Run(bodies: 10, updates: 1)])"),
    )
    .unwrap();
    let out = dir.path().join("r.csv");
    refused_at_once(
        &[os("bench"), config.as_os_str(), os("--out"), out.as_os_str()],
        &[fifo_text, "not a regular file"],
    );
    assert!(!out.exists());
}

/// Outputs replace regular files only: a FIFO, a device or a link is
/// refused and left as it was; a path that cannot be written is found
/// before any work.
#[cfg(unix)]
#[test]
fn outputs_that_are_not_regular_files_or_cannot_be_written_are_refused_before_work() {
    use std::os::unix::fs::FileTypeExt;

    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("bench.ron");
    std::fs::write(&config, "Bench(runs: [Run(bodies: 10, updates: 1)])").unwrap();
    let bench = config.to_str().unwrap();
    let fifo = dir.path().join("f.csv");
    make_fifo(&fifo);
    let target = dir.path().join("target.csv");
    std::fs::write(&target, "precious").unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let existing_slash = format!("{}/", target.display());
    let new_dir_slash = format!("{}/newdir/", dir.path().display());
    for (flag, path, needle) in [
        (
            "--dump",
            fifo.to_str().unwrap(),
            "is a FIFO (named pipe); outputs replace regular files only",
        ),
        (
            "--dump",
            "/dev/null",
            "is a character device; outputs replace regular files only",
        ),
        (
            "--timeline",
            link.to_str().unwrap(),
            "is a symbolic link; outputs replace regular files only",
        ),
        ("--save-scenario", link.to_str().unwrap(), "is a symbolic link"),
        ("--dump", &existing_slash, "is a directory; give a file name"),
        ("--dump", "/proc/x.csv", "cannot write in folder /proc"),
        // A file there, the folder there: neither is said to be missing.
        (
            "--dump",
            "/proc/version",
            "cannot write in folder /proc: the folder exists, but its file system makes no new files",
        ),
    ] {
        refused_at_once(
            &[
                os("headless"),
                os(scenario),
                os("--steps"),
                os("100000000"),
                os(flag),
                os(path),
            ],
            &[flag, path, needle],
        );
    }
    for (path, needle) in [
        ("/proc/x.csv", "cannot write in folder /proc"),
        (new_dir_slash.as_str(), "is a directory; give a file name"),
    ] {
        refused_at_once(&[os("bench"), os(bench), os("--out"), os(path)], &["--out", needle]);
    }
    assert!(
        std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(),
        "the FIFO was replaced"
    );
    assert!(
        std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(),
        "the link was replaced"
    );
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "precious");
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
}

/// Runs the valid scenario `text` (saved as `name`) for `steps` updates in
/// both modes with every output asked for: exit 3, one line holding each
/// of `needles`, no output written or touched.
fn assert_run_stops(name: &str, text: &str, steps: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join(name);
    std::fs::write(&scenario, text).unwrap();
    let out = kessler().arg("validate").arg(&scenario).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "valid at the start: {out:?}");
    let dump = dir.path().join("state.csv");
    std::fs::write(&dump, "precious").unwrap();
    let (timeline, snapshot) = (dir.path().join("timeline.csv"), dir.path().join("snapshot.ron"));
    for mode in ["sequential", "parallel"] {
        let out = kessler()
            .args(["headless", "--steps", steps, "--mode", mode, "--dump"])
            .arg(&dump)
            .arg("--timeline")
            .arg(&timeline)
            .arg("--save-scenario")
            .arg(&snapshot)
            .arg(&scenario)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(3), "{mode}: {out:?}");
        assert_one_clear_line(&out.stderr, needles);
        assert_eq!(std::fs::read_to_string(&dump).unwrap(), "precious", "{mode}");
        assert!(!timeline.exists() && !snapshot.exists(), "{mode}");
    }
}

/// A scene valid at the start whose bodies then pile up (a cold cloud of
/// non-interacting cubes collapsing under its own gravity): the run stops
/// with one line naming the update, exit 3, and writes none of its outputs.
#[test]
fn a_run_whose_bodies_pile_up_stops_with_a_message_and_writes_nothing() {
    assert_run_stops(
        "pile.ron",
        "Scenario(gravitational_constant: 1.0, time_step: 0.1, softening: 0.5, generators: [Cloud(count: 3000, \
         center: (0, 0, 0), half_size: (50, 50, 50), body: (half_extents: (3, 3, 3), role: SourceAndAdopter, \
         interacts: false))])",
        "300",
        &[
            "pile.ron: update ",
            "overlap in more than 1048576 pairs",
            "piled on one another",
            "the simulation stopped",
        ],
    );
}

/// A thousand fragments a shatter, with no threshold and no floor: the body
/// budget holds the cascade (it used to grow until memory ran out).
#[test]
fn a_cascade_without_floor_or_threshold_stays_within_the_budget() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("cascade.ron");
    std::fs::write(
        &scenario,
        "Scenario(generators: [Cloud(count: 2000, center: (0, 0, 0), half_size: (20, 20, 20), max_speed: 1.0)], \
         shatter_fragments: 1000, shatter_threshold: 0, min_fragment_size: 0, max_bodies: 30000)",
    )
    .unwrap();
    let out = kessler()
        .args(["headless", "--steps", "20"])
        .arg(&scenario)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let summary = String::from_utf8_lossy(&out.stdout);
    let at_end: u64 = summary
        .split(" at the end")
        .next()
        .and_then(|s| s.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no body count in {summary}"));
    assert!((2000..=30_000).contains(&at_end), "{at_end} bodies: {summary}");
    assert!(!summary.contains(" 0 refused"), "the budget refused nothing: {summary}");
}

/// Messages stay one line of sane length whatever the input put in them.
#[test]
fn echoes_of_the_input_are_cut_and_kept_on_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let long = dir.path().join("long.ron");
    std::fs::write(&long, format!("Scenario({}: 1)", "a".repeat(100_000))).unwrap();
    let out = kessler().arg("validate").arg(&long).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_one_clear_line(&out.stderr, &["long.ron", "characters cut]"]);
    assert!(out.stderr.len() < 1000, "{} bytes", out.stderr.len());

    let odd = dir.path().join("two\nlines.ron");
    std::fs::write(&odd, "Scenario(mass: 1)").unwrap();
    let out = kessler().arg("validate").arg(&odd).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_one_clear_line(&out.stderr, &["two\\nlines.ron"]);
}

/// In a build without the window, `run` checks its input before it says
/// that it runs headless instead: a bad input is one line.
#[cfg(not(feature = "gui"))]
#[test]
fn headless_run_with_bad_input_is_one_line() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let out = kessler().args(["run", scenario, "--bodies", "10"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_one_clear_line(&out.stderr, &["--bodies"]);
}

#[test]
fn a_sequential_summary_says_one_thread() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let out = kessler()
        .args([
            "headless",
            scenario,
            "--steps",
            "3",
            "--mode",
            "sequential",
            "--threads",
            "2",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(summary.contains("sequential on 1 thread"), "{summary}");
}

/// A valid scene whose state overflows during the run (an adopter 1e-10
/// from a heavy source without softening: the first kick, 1e38, is still
/// finite, the fourth drift is not): the run stops naming the update and
/// the body, exit 3, in both modes, and writes none of its outputs.
#[test]
fn a_run_that_overflows_stops_naming_the_update_and_the_body() {
    assert_run_stops(
        "overflow.ron",
        "Scenario(gravitational_constant: 1e6, bodies: [\
         Body(position: (0, 0, 0), mass: 1e12, role: Source, interacts: false),\
         Body(position: (1e-10, 0, 0), interacts: false)])",
        "10",
        &[
            "overflow.ron: update 4: body 1 has a non-finite position (-inf, 0, 0)",
            "the simulation stopped",
        ],
    );
}

/// What Kessler writes, Kessler loads: bodies spawned at one point at
/// update 3 make a state no scenario may start from (a pile-up), so a
/// snapshot of it is refused as one beyond ±1e30 is (exit 3, nothing
/// written); a snapshot before the spawn is written and validates.
#[test]
fn a_snapshot_that_would_not_load_back_is_not_written() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("spawn.ron");
    std::fs::write(
        &scenario,
        "Scenario(gravitational_constant: 0, bodies: [Body(position: (0, 0, 0))], events: [Spawn(update: 3, \
         generators: [Cloud(count: 2000, center: (50, 0, 0), half_size: (0, 0, 0))])])",
    )
    .unwrap();
    let snapshot = dir.path().join("snapshot.ron");
    let out = kessler()
        .args(["headless", "--steps", "3", "--save-scenario"])
        .arg(&snapshot)
        .arg(&scenario)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3), "{out:?}");
    assert_one_clear_line(
        &out.stderr,
        &[
            "spawn.ron: after 3 updates, the state would not load back as a scenario",
            "the 2001 bodies overlap in more than",
            "--save-scenario",
            "no output was written",
        ],
    );
    assert!(!snapshot.exists());
    let out = kessler()
        .args(["headless", "--steps", "2", "--save-scenario"])
        .arg(&snapshot)
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    let out = kessler().arg("validate").arg(&snapshot).output().unwrap();
    assert!(out.status.success(), "{out:?}");
}

/// A run whose outputs cannot all be written writes none of them. A body
/// at 1e30 moving at 1e30 is still finite after one update (2e30), but
/// beyond what a scenario holds: the snapshot cannot be written, so the
/// dump and the timeline, which could be, are not either. The state out of
/// range stops the run (exit 3), and every target keeps its old bytes.
#[test]
fn a_run_whose_snapshot_cannot_be_written_writes_none_of_its_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("far.ron");
    std::fs::write(
        &scenario,
        "Scenario(bodies: [Body(position: (1e30, 0, 0), velocity: (1e30, 0, 0))])",
    )
    .unwrap();
    let out = kessler().arg("validate").arg(&scenario).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "valid at the start: {out:?}");
    let targets = ["state.csv", "timeline.csv", "snapshot.ron"].map(|name| dir.path().join(name));
    for target in &targets {
        std::fs::write(target, "precious").unwrap();
    }
    let [dump, timeline, snapshot] = &targets;
    for mode in ["sequential", "parallel"] {
        let out = kessler()
            .args(["headless", "--steps", "1", "--mode", mode, "--dump"])
            .arg(dump)
            .arg("--timeline")
            .arg(timeline)
            .arg("--save-scenario")
            .arg(snapshot)
            .arg(&scenario)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(3), "{mode}: {out:?}");
        assert_one_clear_line(
            &out.stderr,
            &[
                "far.ron: after 1 updates, body 0 is beyond ±1e30",
                "--save-scenario",
                "no output was written",
            ],
        );
        for target in &targets {
            assert_eq!(
                std::fs::read(target).unwrap(),
                b"precious",
                "{mode}: {}",
                target.display()
            );
        }
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            4,
            "{mode}: a temporary file was left behind"
        );
    }
    // Without the snapshot, the same run writes both the others.
    let out = kessler()
        .args(["headless", "--steps", "1", "--dump"])
        .arg(dump)
        .arg("--timeline")
        .arg(timeline)
        .arg(&scenario)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(std::fs::read_to_string(dump).unwrap().starts_with("id,x,y,z,"));
    assert!(std::fs::read_to_string(timeline).unwrap().starts_with("update,"));
    assert_eq!(std::fs::read(snapshot).unwrap(), b"precious");
}

/// No output replaces a file the command reads: a dump, a timeline or a
/// snapshot over the scenario being run (named the same, relative against
/// absolute, through a link or `..`), an output over the split calibration,
/// a benchmark's results or side files over its config or the scenario the
/// config names. One line, exit 2, nothing written.
#[cfg(unix)]
#[test]
fn no_output_replaces_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron")).unwrap();
    let scenario = dir.path().join("scen.ron");
    std::fs::write(&scenario, &text).unwrap();
    let link = dir.path().join("link.ron");
    std::os::unix::fs::symlink(&scenario, &link).unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let absolute = scenario.to_str().unwrap();
    let dotted = format!("{}/sub/../scen.ron", dir.path().display());
    let headless = |input: &str, flag: &str, output: &str, needle: &str| {
        let out = kessler()
            .current_dir(dir.path())
            .args(["headless", input, "--steps", "1", flag, output])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{input} {flag} {output}: {out:?}");
        assert_one_clear_line(&out.stderr, &[flag, output, needle]);
    };
    for flag in ["--dump", "--timeline", "--save-scenario"] {
        for (input, output) in [
            (absolute, absolute),
            ("scen.ron", absolute),
            (absolute, "./scen.ron"),
            ("link.ron", "scen.ron"),
            (&dotted, "scen.ron"),
        ] {
            headless(input, flag, output, "is the scenario this command reads");
        }
    }
    assert_eq!(
        std::fs::read_to_string(&scenario).unwrap(),
        text,
        "the scenario was replaced"
    );

    // The split calibration every command reads.
    let config = dir.path().join("config");
    std::fs::create_dir_all(config.join("kessler")).unwrap();
    let calibration = config.join("kessler").join("calibration.ron");
    std::fs::write(&calibration, "Calibration(").unwrap();
    let out = kessler()
        .env("XDG_CONFIG_HOME", &config)
        .args(["headless", absolute, "--steps", "1", "--dump"])
        .arg(&calibration)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert_one_clear_line(&out.stderr, &["--dump", "is the split calibration this command reads"]);
    assert_eq!(std::fs::read_to_string(&calibration).unwrap(), "Calibration(");

    // A benchmark's outputs against its config and its scenario, a side
    // file (the PNG plot beside `--out r.csv`) included.
    let png_scenario = dir.path().join("r.png");
    std::fs::write(&png_scenario, &text).unwrap();
    let bench = dir.path().join("bench.ron");
    let bench_text = "Bench(scenario: \"r.png\", runs: [Run(bodies: 2, updates: 1)])";
    std::fs::write(&bench, bench_text).unwrap();
    for (out_path, needle) in [
        (bench.clone(), "is the bench config this command reads"),
        (
            dir.path().join("r.csv"),
            "is the scenario the bench config names this command reads",
        ),
    ] {
        let out = kessler()
            .arg("bench")
            .arg(&bench)
            .arg("--out")
            .arg(&out_path)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{out:?}");
        assert_one_clear_line(&out.stderr, &["--out", needle]);
    }
    assert_eq!(std::fs::read_to_string(&bench).unwrap(), bench_text);
    assert_eq!(std::fs::read_to_string(&png_scenario).unwrap(), text);
    assert!(!dir.path().join("r.csv").exists() && !dir.path().join("r-machine.txt").exists());
}
