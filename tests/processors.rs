//! One scenario, one trajectory, on every processor: the same runs on this
//! machine and under QEMU's user-mode emulation of two older x86-64
//! processors — `qemu64` (the baseline: SSE2, no AVX, so the plain gravity
//! kernel) and `Haswell` (AVX2, no AVX-512, so the AVX kernel) — give the
//! same state hash, and a snapshot saved here continues there to the very
//! bytes of the straight run here. Where this machine has AVX-512 (as CI's
//! does), each of the three runs another kernel.
//!
//! Without `qemu-x86_64` (Debian's `qemu-user`), or on a machine that is not
//! x86-64, the tests print one line saying they were skipped and why, and
//! pass — unless `KESSLER_REQUIRE_QEMU_TESTS=1` (as in CI), where that fails
//! them. Emulation is 50–100 times slower, so the runs are short.

mod common {
    pub mod binary;
    pub mod skip;
}

use std::path::{Path, PathBuf};

use common::binary::{KESSLER, isolated, kessler};
use common::skip::Needs;

/// The emulated processors, as QEMU names them.
const PROCESSORS: [&str; 2] = ["qemu64", "Haswell"];

/// The scenes and their updates: a tree-gravity collapse that shatters,
/// through its 8th update (343 shatters, fragments in the contacts of the
/// update they are made in; its 9th and 10th, the densest, take three
/// fifths of its 50 updates' time, fourteen times its first 8, and
/// emulated most of this file's), a tree-gravity ring, the default scene
/// and the thesis scene.
const SCENES: [(&str, &str); 4] = [
    ("collapse", "8"),
    ("debris_ring", "50"),
    ("debris_orbit", "50"),
    ("thesis_cloud", "50"),
];

fn scene(name: &str) -> String {
    format!("{}/scenarios/{name}.ron", env!("CARGO_MANIFEST_DIR"))
}

/// Why the emulated runs cannot be made here, if they cannot.
fn missing_qemu() -> Option<String> {
    if !cfg!(all(target_arch = "x86_64", target_os = "linux")) {
        return Some("this is not an x86-64 Linux machine".into());
    }
    let on_path = std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join("qemu-x86_64").is_file()));
    (!on_path).then(|| "`qemu-x86_64` is not installed".into())
}

/// What the emulated-processor tests need.
const QEMU: Needs = Needs {
    test: "processor test",
    tests: "emulated-processor tests",
    require: "KESSLER_REQUIRE_QEMU_TESTS",
    install: "apt install qemu-user",
};

/// Whether `test` can run under emulation; if not, says so on the
/// terminal (past the harness's capture) or, when required, fails.
fn qemu_available(test: &str) -> bool {
    QEMU.available(test, missing_qemu())
}

/// `kessler ARGS` here (`processor` none) or under QEMU emulating it;
/// returns the summary line, failing the test if the run fails.
fn run_on(processor: Option<&str>, args: &[&str]) -> String {
    let mut command = match processor {
        None => kessler(),
        Some(cpu) => {
            let mut qemu = isolated("qemu-x86_64");
            qemu.args(["-cpu", cpu, KESSLER]);
            assert_cmd::Command::from_std(qemu)
        }
    };
    let out = command.args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{processor:?} {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The state hash a summary line ends with.
fn hash(summary: &str) -> String {
    let (_, hash) = summary
        .trim_end()
        .rsplit_once("state hash ")
        .unwrap_or_else(|| panic!("no hash in {summary}"));
    hash.to_owned()
}

fn headless<'a>(scene: &'a str, mode: &'a str, steps: &'a str) -> [&'a str; 8] {
    ["headless", scene, "--steps", steps, "--mode", mode, "--threads", "2"]
}

/// Every scene in both modes under `processor` gives the hash it gives
/// here in both modes.
fn hashes_agree(processor: &str) {
    for (name, steps) in SCENES {
        let path = scene(name);
        let native = run_on(None, &headless(&path, "sequential", steps));
        if name == "collapse" {
            assert!(!native.contains(" 0 shatters"), "the collapse shatters: {native}");
        }
        let expected = hash(&native);
        assert_eq!(hash(&run_on(None, &headless(&path, "parallel", steps))), expected);
        for mode in ["sequential", "parallel"] {
            let got = hash(&run_on(Some(processor), &headless(&path, mode, steps)));
            assert_eq!(got, expected, "{name}, {mode}, under {processor}");
        }
    }
}

#[test]
fn the_baseline_processor_gives_the_native_hashes() {
    if qemu_available("the_baseline_processor_gives_the_native_hashes") {
        hashes_agree("qemu64");
    }
}

#[test]
fn a_haswell_gives_the_native_hashes() {
    if qemu_available("a_haswell_gives_the_native_hashes") {
        hashes_agree("Haswell");
    }
}

/// A collapse saved here after 30 updates and continued for 20 under each
/// emulated processor dumps the bytes of the straight 50 updates here.
#[test]
fn a_snapshot_saved_here_continues_alike_elsewhere() {
    if !qemu_available("a_snapshot_saved_here_continues_alike_elsewhere") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str| -> PathBuf { dir.path().join(name) };
    let text = |p: &Path| p.to_str().unwrap().to_owned();
    let (straight, saved) = (file("straight.csv"), file("saved.ron"));
    let path = scene("collapse");
    run_on(
        None,
        &[&headless(&path, "parallel", "50")[..], &["--dump", &text(&straight)]].concat(),
    );
    run_on(
        None,
        &[
            &headless(&path, "parallel", "30")[..],
            &["--save-scenario", &text(&saved)],
        ]
        .concat(),
    );
    let straight = std::fs::read(&straight).unwrap();
    for processor in PROCESSORS {
        let continued = file(&format!("continued-{processor}.csv"));
        run_on(
            Some(processor),
            &[
                &headless(&text(&saved), "sequential", "20")[..],
                &["--dump", &text(&continued)],
            ]
            .concat(),
        );
        assert!(
            std::fs::read(&continued).unwrap() == straight,
            "the snapshot continued under {processor} differs from the straight run"
        );
    }
}
