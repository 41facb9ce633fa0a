//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};

use assert_cmd::Command;

/// The `kessler` binary, blind to the user's own files (settings and split
/// calibration), so that tests do not depend on them.
pub fn kessler() -> Command {
    let mut command = Command::cargo_bin("kessler").unwrap();
    command.env(
        "XDG_CONFIG_HOME",
        std::env::temp_dir().join("kessler-tests-without-config"),
    );
    command
}

/// The files of an error corpus under `tests/`, sorted.
pub fn corpus(folder: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join(folder))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

/// What a corpus file's error must mention, from its first line
/// (`// expect: ...`).
pub fn expectation(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let first = text.lines().next().unwrap_or_default();
    first
        .strip_prefix("// expect: ")
        .unwrap_or_else(|| panic!("{} lacks an expect line", path.display()))
        .to_owned()
}

/// Asserts that `stderr` is one line, no panic, mentioning every needle.
pub fn assert_one_clear_line(stderr: &[u8], must_contain: &[&str]) {
    let stderr = String::from_utf8_lossy(stderr);
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
    for needle in must_contain {
        assert!(stderr.contains(needle), "{stderr:?} does not mention {needle:?}");
    }
}
