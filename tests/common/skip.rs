//! Tests that need a tool this machine may lack (Xvfb and a Vulkan driver,
//! QEMU, a Slurm cluster): where it is missing, such a test prints one line
//! saying it was skipped and why, and passes — unless the tests are
//! required (`KESSLER_REQUIRE_..._TESTS=1`, as in CI), where it fails.

use std::io::Write as _;

/// What a group of tests needs, as its messages name it.
pub struct Needs {
    /// What a skipped test is, in its line: "window test".
    pub test: &'static str,
    /// What the variable requires, in the failure: "window tests".
    pub tests: &'static str,
    /// The variable that, set to `1`, requires the tests.
    pub require: &'static str,
    /// How to get what is missing: "apt install ...".
    pub install: &'static str,
}

impl Needs {
    /// Whether `test` can run, `missing` saying why not. If it cannot, says
    /// so on the terminal (past the test harness's capture of
    /// `eprintln!`) or, when the tests are required, fails.
    pub fn available(&self, test: &str, missing: Option<String>) -> bool {
        let Some(missing) = missing else {
            return true;
        };
        let require = self.require;
        if std::env::var_os(require).is_some_and(|v| v == "1") {
            panic!("{test}: {missing}, and {require}=1 requires the {}", self.tests);
        }
        let line = format!(
            "{} `{test}` skipped: {missing} ({}; {require}=1 turns this into a failure)\n",
            self.test, self.install
        );
        let _ = std::io::stderr().write_all(line.as_bytes());
        false
    }
}
