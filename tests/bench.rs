//! `kessler bench` through the real binary.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

use common::{assert_one_clear_line, corpus, expectation, kessler};

#[test]
fn bad_configs_are_clear_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results.csv");
    for file in corpus("bad_benches") {
        let result = kessler()
            .arg("bench")
            .arg(&file)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(result.status.code(), Some(2), "{}", file.display());
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        assert_one_clear_line(&result.stderr, &[&name, &expectation(&file)]);
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "{} wrote files",
            file.display()
        );
    }
}

fn tiny_config(dir: &Path) -> PathBuf {
    let path = dir.join("tiny.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    std::fs::write(
        &path,
        format!(
            r#"Bench(scenario: "{scenario}", runs: [
                Run(bodies: 50, updates: 5, mode: Sequential),
                Run(bodies: 50, updates: 5, mode: Parallel, threads: 1),
                Run(bodies: 500, updates: 3, mode: Parallel, threads: 2, stages: (collisions: false)),
            ])"#
        ),
    )
    .unwrap();
    path
}

/// Runs the tiny config with `--out out`.
fn run_tiny(dir: &Path, out: &Path) -> Output {
    kessler()
        .arg("bench")
        .arg(tiny_config(dir))
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn writes_results_overhead_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tiny-results.csv");
    let result = run_tiny(dir.path(), &out);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));

    let csv = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        csv.lines().next().unwrap(),
        "run,bodies_start,bodies_end,updates,mode,threads,update_ns,broad_phase_ns,response_ns,gravity_ns,integrate_ns"
    );
    assert_eq!(rows.len(), 4, "{csv}");
    // 50 cubes and the planet; the third run had collisions off.
    assert_eq!(&rows[1][..6], ["1", "51", "51", "5", "sequential", "1"]);
    assert_eq!(&rows[2][4..6], ["parallel", "1"]);
    assert_eq!(&rows[3][..6], ["3", "501", "501", "3", "parallel", "2"]);
    assert_eq!(rows[3][7], "0", "broad phase was off");
    for row in &rows[1..] {
        let update: f64 = row[6].parse().unwrap();
        let stages: f64 = row[7..].iter().map(|v| v.parse::<f64>().unwrap()).sum();
        assert!(
            update > 0.0 && stages <= update,
            "stages {stages} exceed the update {update}: {row:?}"
        );
    }

    let overhead = std::fs::read_to_string(dir.path().join("tiny-results-overhead.csv")).unwrap();
    assert!(overhead.starts_with("bodies,stage,sequential_ns,parallel_1_thread_ns,overhead_ns,overhead_percent\n"));
    // The header, the whole update and each stage column of the results.
    let columns = kessler::bench::columns_in_stage_order();
    assert_eq!(overhead.lines().count(), 2 + columns.len(), "{overhead}");
    for column in columns {
        assert!(overhead.contains(&format!(",{column},")), "{overhead}");
    }
    let svg = std::fs::read_to_string(dir.path().join("tiny-results.svg")).unwrap();
    assert!(svg.contains("<polyline"), "{svg}");
    let png = std::fs::read(dir.path().join("tiny-results.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn never_overwrites_existing_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results.csv");
    std::fs::write(dir.path().join("results.svg"), "my old plot").unwrap();
    let result = run_tiny(dir.path(), &out);
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains("results.svg exists"));
    assert!(!out.exists());
    assert_eq!(
        std::fs::read_to_string(dir.path().join("results.svg")).unwrap(),
        "my old plot"
    );
}

#[test]
fn repeated_passes_measure_every_run_each_time_and_write_one_row_per_run() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("repeat.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    std::fs::write(
        &config,
        format!(
            r#"Bench(scenario: "{scenario}", repeat: 3, runs: [
                Run(bodies: 40, updates: 4, mode: Sequential),
                Run(bodies: 40, updates: 4, mode: Parallel, threads: 2),
            ])"#
        ),
    )
    .unwrap();
    let out = dir.path().join("repeat.csv");
    let result = kessler()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    // Passes go through the runs in turn.
    let stderr = String::from_utf8_lossy(&result.stderr);
    let order: Vec<&str> = stderr
        .lines()
        .filter_map(|l| l.strip_prefix("run "))
        .map(|l| l.split(':').next().unwrap().trim())
        .collect();
    assert_eq!(
        order,
        [
            "1 (pass 1/3)",
            "2 (pass 1/3)",
            "1 (pass 2/3)",
            "2 (pass 2/3)",
            "1 (pass 3/3)",
            "2 (pass 3/3)"
        ],
        "{stderr}"
    );
    let csv = std::fs::read_to_string(&out).unwrap();
    let runs: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(runs, ["1", "2"], "{csv}");
}
