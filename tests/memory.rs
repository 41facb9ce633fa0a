//! Memory is a budget too: a run whose shatters would outgrow the memory it
//! may use stops with one clear line and exit 3, never an allocation abort,
//! and says at load that its `max_bodies` would not fit.

mod common {
    pub mod binary;
}

use common::binary::kessler;

/// Every value in range (the floor and budget `thesis_cloud.ron` uses):
/// 2 000 bodies become millions within a few updates. Found where updates
/// end: swept along their paths, a thousand fragments of each shatter
/// moving apart would overlap in more pairs than the sweep holds (a
/// pile-up, which stops the run first).
const BOOM: &str = "Scenario(
    name: \"Memory boom\",
    collision_detection: Discrete,
    shatter_fragments: 1000,
    shatter_threshold: 0.0,
    min_fragment_size: 0.0,
    max_bodies: 20000000,
    generators: [Cloud(count: 2000, center: (0, 0, 0), half_size: (60, 60, 60), max_speed: 2)],
)";

#[test]
#[cfg(target_os = "linux")]
fn a_run_that_would_outgrow_its_address_space_stops_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("boom.ron");
    std::fs::write(&scenario, BOOM).unwrap();
    let dump = dir.path().join("state.csv");
    std::fs::write(&dump, "precious").unwrap();
    // 1.5 GB of address space: a few million bodies at most.
    let out = common::binary::isolated("sh")
        .arg("-c")
        .arg("ulimit -v 1500000 && exec \"$0\" headless \"$1\" --steps 10 --dump \"$2\"")
        .arg(common::binary::KESSLER)
        .arg(&scenario)
        .arg(&dump)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 2, "{stderr}");
    assert!(
        lines[0].starts_with("kessler: warning: ") && lines[0].contains("max_bodies 20000000 would take about 10.0 GB"),
        "{stderr}"
    );
    assert!(
        lines[1].contains("more than the") && lines[1].contains("address-space limit") && lines[1].contains("stopped"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("memory allocation"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&dump).unwrap(), "precious", "nothing written");
}

#[test]
fn within_memory_nothing_is_said() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("small.ron");
    std::fs::write(&scenario, BOOM.replace("max_bodies: 20000000", "max_bodies: 30000")).unwrap();
    let out = kessler()
        .args(["headless", "--steps", "3"])
        .arg(&scenario)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}
