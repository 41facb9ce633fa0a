//! The `kessler` binary, run isolated: blind to the user's own files (the
//! window's settings and the machine's split calibration), so that no test
//! depends on them.
//!
//! Kessler finds those files in the platform's configuration folder
//! (`src/input/user_files.rs`): on Linux `$XDG_CONFIG_HOME/kessler`, else
//! `~/.config/kessler`. Every command made here points `XDG_CONFIG_HOME`
//! at [`NO_CONFIG`], a folder that nothing creates. A test that wants a
//! configuration of its own (a calibration, say) sets `XDG_CONFIG_HOME`
//! again, to a folder of its own.

use std::ffi::OsStr;
use std::path::PathBuf;

/// The binary under test.
pub const KESSLER: &str = env!("CARGO_BIN_EXE_kessler");

/// The configuration folder every command here is given: one that does not
/// exist, so there are no settings and no calibration in it.
fn no_config() -> PathBuf {
    std::env::temp_dir().join("kessler-tests-without-config")
}

/// `program` as a plain command, blind to the user's own files; for
/// [`KESSLER`] itself when it must be spawned, or for what runs it
/// (`xvfb-run`, `qemu-x86_64`, a shell).
pub fn isolated(program: impl AsRef<OsStr>) -> std::process::Command {
    let mut command = std::process::Command::new(program);
    command.env("XDG_CONFIG_HOME", no_config());
    command
}

/// The binary, blind to the user's own files.
pub fn kessler() -> assert_cmd::Command {
    assert_cmd::Command::from_std(isolated(KESSLER))
}
