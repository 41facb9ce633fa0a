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
    // The commit moves when HEAD names another branch, when the branch's
    // ref file (or, once packed, `packed-refs`) changes, and the tree's
    // state with the index: watch each file itself (a folder's time does
    // not change when a file inside it does). Git says where each lives: in
    // a worktree `.git` is a file, HEAD and the index are the worktree's
    // own and the refs are shared. (Two checkouts of the same package
    // built into one target folder share this script's last run, and with
    // it the files it watched: after building the other, `touch build.rs`.)
    let mut watched = vec!["HEAD".to_owned(), "index".to_owned(), "packed-refs".to_owned()];
    watched.extend(output_of("git", &["symbolic-ref", "-q", "HEAD"]));
    for name in watched {
        if let Some(path) = output_of("git", &["rev-parse", "--git-path", &name])
            && std::path::Path::new(&path).exists()
        {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
