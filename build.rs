//! Records the compiler's version and the git commit for the machine
//! report of benchmarks (`src/bench/machine.rs`); "unknown" where either
//! cannot be found (e.g. building from a source archive).

use std::process::Command;

fn output_of(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    let text = String::from_utf8(out.stdout).ok()?;
    (out.status.success() && !text.trim().is_empty()).then(|| text.trim().to_owned())
}

fn main() {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = output_of(&rustc, &["--version"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=KESSLER_RUSTC_VERSION={version}");
    let commit = output_of("git", &["rev-parse", "--short=12", "HEAD"]).map_or("unknown".into(), |c| {
        let dirty = output_of("git", &["status", "--porcelain", "--untracked-files=no"]).is_some();
        if dirty {
            format!("{c} (with uncommitted changes)")
        } else {
            c
        }
    });
    println!("cargo:rustc-env=KESSLER_GIT_COMMIT={commit}");
    for path in [".git/HEAD", ".git/index", ".git/refs"] {
        if std::path::Path::new(path).exists() {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
