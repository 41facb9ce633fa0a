//! The error corpora under `tests/` (a file of bad input each, its first
//! line saying what its error must mention) and the one clear line an
//! error must be.

use std::path::{Path, PathBuf};

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
