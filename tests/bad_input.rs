//! Bad input through the real binary: one clear line on stderr, exit code 2,
//! no panic, nothing overwritten.

mod common;

use common::{assert_one_clear_line, corpus, expectation, kessler};

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

#[test]
fn bad_arguments_are_clear_errors() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/two_body.ron");
    let cases: [(&[&str], &str); 18] = [
        (&["headless", scenario, "--steps", "-5"], "--steps"),
        (&["headless", scenario, "--steps", "ten"], "--steps"),
        (&["headless", scenario], "--steps"),
        (&["headless", scenario, "--steps", "1", "--mode", "fast"], "--mode"),
        (&["headless", scenario, "--steps", "1", "--threads", "0"], "--threads"),
        (
            &["headless", scenario, "--steps", "1", "--threads", "-1"],
            "not in 1..=256",
        ),
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
    for (args, needle) in cases {
        let out = kessler().args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_one_clear_line(&out.stderr, &[needle]);
    }
}

#[test]
fn missing_file_is_a_clear_error() {
    let out = kessler().args(["validate", "no_such_scenario.ron"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert_one_clear_line(&out.stderr, &["no_such_scenario.ron", "cannot read"]);
}
