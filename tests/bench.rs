//! `kessler bench` through the real binary.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common {
    pub mod binary;
    pub mod errors;
}

use common::binary::kessler;
use common::errors::{assert_one_clear_line, corpus, expectation};
use kessler::bench::REFERENCES;
use kessler::scenario::scenario_text;

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

/// A thread sweep: its runs (sequential, then parallel on 1 up to every
/// hardware thread) in the results, and its speed-ups (sequential's time
/// over each parallel run's, from those same results) in
/// `<stem>-threads.csv` and its plot.
#[test]
fn a_thread_sweep_writes_the_speedup_per_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("sweep.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    std::fs::write(
        &config,
        format!(
            r#"Bench(scenario: "{scenario}", runs: [Threads(bodies: 300, updates: 4), Run(bodies: 50, updates: 2)])"#
        ),
    )
    .unwrap();
    let out = dir.path().join("sweep-results.csv");
    let result = kessler()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let hardware = std::thread::available_parallelism().map_or(1, |n| n.get());
    let csv = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2 + hardware, "{csv}");
    assert_eq!(&rows[0][4..6], ["sequential", "1"]);
    for (k, row) in rows[1..=hardware].iter().enumerate() {
        assert_eq!(&row[4..6], ["parallel", &(k + 1).to_string()], "{csv}");
    }
    let threads = std::fs::read_to_string(dir.path().join("sweep-results-threads.csv")).unwrap();
    let lines: Vec<&str> = threads.lines().collect();
    assert_eq!(
        lines[0],
        "bodies,threads,update_speedup,gravity_speedup,integrate_speedup,sort_speedup,sweep_speedup,response_speedup,shatter_speedup"
    );
    assert_eq!(lines.len(), 1 + hardware, "{threads}");
    let ns = |row: &[&str]| row[6].parse::<f64>().unwrap();
    for (k, line) in lines[1..].iter().enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(&cells[..2], ["300", &(k + 1).to_string()]);
        let expected = ns(&rows[0]) / ns(&rows[1 + k]);
        let got: f64 = cells[2].parse().unwrap();
        assert!(
            (got - expected).abs() <= 6e-4 * expected.max(1.0),
            "{got} against {expected} (written to 3 decimals)"
        );
    }
    for plot in ["sweep-results-threads.svg", "sweep-results-threads.png"] {
        assert!(dir.path().join(plot).is_file(), "{plot} missing");
    }
    // A benchmark without a sweep writes none of these.
    let plain = dir.path().join("plain.csv");
    let result = run_tiny(dir.path(), &plain);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    assert!(!dir.path().join("plain-threads.csv").exists());
}

fn tiny_config(dir: &Path) -> PathBuf {
    let path = dir.join("tiny.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    std::fs::write(
        &path,
        format!(
            r#"Bench(scenario: "{scenario}", runs: [
                Run(bodies: 50, updates: 5, mode: Sequential),
                Run(bodies: 50, updates: 5, mode: Parallel, threads: 1, split: Always),
                Run(bodies: 500, updates: 3, mode: Parallel, threads: 2, stages: (collisions: false),
                    seed: 7, shatter_fragments: 3, shatter_threshold: 2.5),
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
fn writes_results_passes_overhead_machine_and_plot() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tiny-results.csv");
    let result = run_tiny(dir.path(), &out);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));

    assert_results_rows(&out);
    assert_overhead_rows(dir.path());
    let passes = std::fs::read_to_string(dir.path().join("tiny-results-passes.csv")).unwrap();
    assert!(passes.starts_with("pass,run,bodies_start,"), "{passes}");
    assert_eq!(passes.lines().count(), 4, "{passes}");
    assert_machine_file(dir.path());
    // Split on one thread never has a second thread to gain from, but the
    // crossover of the one count is reported all the same.
    let crossover = std::fs::read_to_string(dir.path().join("tiny-results-crossover.csv")).unwrap();
    assert!(
        crossover.lines().skip(1).all(|l| l.split(',').nth(1) == Some("1")),
        "{crossover}"
    );
    let svg = std::fs::read_to_string(dir.path().join("tiny-results.svg")).unwrap();
    assert!(svg.contains("<polyline"), "{svg}");
    let png = std::fs::read(dir.path().join("tiny-results.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

/// The results: the contract's header, a row per run, the broad phase its
/// sort and sweep, no stage longer than the update.
fn assert_results_rows(out: &Path) {
    let csv = std::fs::read_to_string(out).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        csv.lines().next().unwrap(),
        "run,bodies_start,bodies_end,updates,mode,threads,update_ns,broad_phase_ns,response_ns,gravity_ns,integrate_ns,sort_ns,sweep_ns"
    );
    assert_eq!(rows.len(), 4, "{csv}");
    for row in &rows[1..] {
        // The broad phase is its sort and its sweep.
        let [broad, sort, sweep] = [7, 11, 12].map(|k| row[k].parse::<i64>().unwrap());
        assert!((broad - sort - sweep).abs() <= 1, "{row:?}");
    }
    // 50 cubes and the planet; the third run had collisions off.
    assert_eq!(&rows[1][..6], ["1", "51", "51", "5", "sequential", "1"]);
    assert_eq!(&rows[2][4..6], ["parallel", "1"]);
    assert_eq!(&rows[3][..6], ["3", "501", "501", "3", "parallel", "2"]);
    assert_eq!(rows[3][7], "0", "broad phase was off");
    for row in &rows[1..] {
        let update: f64 = row[6].parse().unwrap();
        let stages: f64 = row[7..11].iter().map(|v| v.parse::<f64>().unwrap()).sum();
        assert!(
            update > 0.0 && stages <= update,
            "stages {stages} exceed the update {update}: {row:?}"
        );
    }
}

/// The overhead rows: the whole update and each stage at 50 bodies, and
/// the bare step on each pool.
fn assert_overhead_rows(dir: &Path) {
    let overhead = std::fs::read_to_string(dir.join("tiny-results-overhead.csv")).unwrap();
    assert!(
        overhead
            .starts_with("bodies,stage,threads,with_overhead_us,without_overhead_us,overhead_us,overhead_percent\n")
    );
    // The header, the whole update and each stage at 50 bodies (whole
    // against split on one thread), then the bare step on Bevy's pool and
    // on Kessler's with 1, 2, Bevy's count and every hardware thread.
    let stages = kessler::systems::STAGES;
    let hardware = std::thread::available_parallelism().map_or(1, usize::from);
    let kessler_steps = overhead.lines().filter(|l| l.starts_with("0,empty_step,")).count();
    assert_eq!(
        overhead.lines().count(),
        1 + 1 + stages.len() + kessler_steps + 1,
        "{overhead}"
    );
    assert!((2..=4).contains(&kessler_steps), "{overhead}");
    assert!(overhead.contains("\n50,update,1,"), "{overhead}");
    for stage in stages {
        assert!(overhead.contains(&format!("\n50,{},1,", stage.name)), "{overhead}");
    }
    for threads in [1, 2, hardware] {
        let row = overhead
            .lines()
            .find(|l| l.starts_with(&format!("0,empty_step,{threads},")))
            .unwrap_or_else(|| panic!("no empty step on {threads} threads: {overhead}"));
        let us: Vec<f64> = row.split(',').skip(3).map(|v| v.parse().unwrap()).collect();
        assert!(us[0] > 0.0 && us[1] >= 0.0, "{row}");
    }
    let bevy = overhead
        .lines()
        .find(|l| l.starts_with("0,empty_step_bevy,"))
        .unwrap_or_else(|| panic!("no empty step on Bevy's pool: {overhead}"));
    let us: Vec<f64> = bevy.split(',').skip(3).map(|v| v.parse().unwrap()).collect();
    assert!(us[0] > 0.0 && us[1] >= 0.0, "{bevy}");
}

/// The machine file: every key, the checkout's commit, and the reference
/// run's hash as the command line computes it.
fn assert_machine_file(dir: &Path) {
    let machine = std::fs::read_to_string(dir.join("tiny-results-machine.txt")).unwrap();
    for key in [
        "cpu: ",
        "hardware threads: ",
        "os: ",
        "rustc: ",
        "kessler: ",
        "gravity kernel: ",
        "date: ",
        "command: ",
        "split auto: ",
    ] {
        assert!(machine.contains(key), "{key} missing: {machine}");
    }
    // The commit named is the checkout's (where there is one): a stale
    // build script's would name one whose code did not run.
    let head = std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|h| h.status.success());
    if let Some(head) = head {
        let head = String::from_utf8_lossy(&head.stdout);
        assert!(
            machine.contains(&format!("(commit {}", head.trim())),
            "the machine file names another commit than HEAD ({}): {machine}",
            head.trim()
        );
    }
    // Each reference run's hash is the hash of that run on the command
    // line, in parallel: its scenario with its settings, written to a file.
    for reference in &REFERENCES {
        let scenario = dir.join(format!("{}.ron", reference.key.replace(' ', "-")));
        std::fs::write(&scenario, scenario_text(&reference.scenario().unwrap()).unwrap()).unwrap();
        let headless = kessler()
            .arg("headless")
            .arg(&scenario)
            .args(["--steps", &reference.updates.to_string(), "--mode", "parallel"])
            .output()
            .unwrap();
        let summary = String::from_utf8(headless.stdout).unwrap();
        let (_, hash) = summary.trim_end().rsplit_once("state hash ").unwrap();
        assert!(
            machine.contains(&format!(
                "{}: {hash} ({}, {} updates",
                reference.key,
                reference.run(),
                reference.updates
            )),
            "{machine}"
        );
    }
}

/// The results in benches/results were measured on code that behaves as
/// this code does: every machine file's reference runs hash as they do
/// here. A change that alters the physics fails this until the results are
/// measured again (docs/benchmarks.md, "Regenerating the results"); one
/// that keeps every bit lands without.
#[test]
fn the_shipped_results_were_measured_on_code_that_behaves_as_this_code() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/results");
    let here: Vec<_> = REFERENCES.iter().map(|r| r.state_hash().unwrap()).collect();
    let mut files = 0;
    for entry in std::fs::read_dir(&folder).unwrap() {
        let path = entry.unwrap().path();
        if !path.to_string_lossy().ends_with("-machine.txt") {
            continue;
        }
        files += 1;
        let report = std::fs::read_to_string(&path).unwrap();
        for (reference, here) in REFERENCES.iter().zip(&here) {
            let recorded = reference.recorded_in(&report);
            assert_eq!(
                recorded,
                Some(*here),
                "{}: its `{}` ({}, {} updates) is not this code's {here}: the physics changed since these \
                 results were measured; measure benches/results again (docs/benchmarks.md, \
                 \"Regenerating the results\")",
                path.display(),
                reference.key,
                reference.run(),
                reference.updates,
            );
        }
    }
    assert!(files > 0, "{} holds no machine file", folder.display());
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
    // Every pass of every run, as measured.
    let passes = std::fs::read_to_string(dir.path().join("repeat-passes.csv")).unwrap();
    let order: Vec<(&str, &str)> = passes
        .lines()
        .skip(1)
        .map(|l| {
            let mut fields = l.split(',');
            (fields.next().unwrap(), fields.next().unwrap())
        })
        .collect();
    assert_eq!(
        order,
        [("1", "1"), ("1", "2"), ("2", "1"), ("2", "2"), ("3", "1"), ("3", "2")]
    );
}

#[test]
fn the_crossover_names_where_always_beats_sequential_and_marks_the_plot() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("cross.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    let mut runs = String::new();
    for bodies in [10, 20_000] {
        for run in [
            "mode: Sequential",
            "mode: Parallel, threads: 2, split: Always",
            "mode: Parallel, threads: 2",
        ] {
            runs.push_str(&format!("Run(bodies: {bodies}, updates: 3, {run}),\n"));
        }
    }
    std::fs::write(
        &config,
        format!(r#"Bench(scenario: "{scenario}", repeat: 2, runs: [{runs}])"#),
    )
    .unwrap();
    let out = dir.path().join("cross.csv");
    let result = kessler()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let crossover = std::fs::read_to_string(dir.path().join("cross-crossover.csv")).unwrap();
    let lines: Vec<&str> = crossover.lines().collect();
    assert_eq!(
        lines[0],
        "stage,threads,crossover_bodies,counts,auto_worst_percent,auto_worst_bodies"
    );
    assert_eq!(lines.len(), 2 + kessler::systems::STAGES.len(), "{crossover}");
    let update: Vec<&str> = lines[1].split(',').collect();
    assert_eq!((update[0], update[1], update[3]), ("update", "2", "2"), "{crossover}");
    // Whatever this machine's crossover, it is one of the measured counts
    // or none, and Auto was compared at both counts.
    assert!(["", "10", "20000"].contains(&update[2]), "{crossover}");
    assert!(
        update[4].parse::<f64>().is_ok() && ["10", "20000"].contains(&update[5]),
        "{crossover}"
    );
    if !update[2].is_empty() {
        let svg = std::fs::read_to_string(dir.path().join("cross.svg")).unwrap();
        assert!(svg.contains(&format!("crossover: {}", update[2])), "the plot marks it");
    }
}

/// `--out r.svg` names the plot's own path (and `--out q.png` the PNG's):
/// refused at once, nothing written, rather than the plot over the results.
#[test]
fn results_named_like_the_plot_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, what) in [("r.svg", "SVG plot"), ("q.png", "PNG plot")] {
        let out = dir.path().join(name);
        let result = run_tiny(dir.path(), &out);
        assert_eq!(result.status.code(), Some(2), "{name}");
        assert_one_clear_line(&result.stderr, &["--out", name, what]);
        let written: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n != "tiny.ron")
            .collect();
        assert!(written.is_empty(), "{name}: wrote {written:?}");
    }
}

#[test]
fn a_bad_split_flag_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results.csv");
    for bad in ["sometimes", "-5", "1.5"] {
        let result = kessler()
            .arg("bench")
            .arg(tiny_config(dir.path()))
            .arg("--out")
            .arg(&out)
            .args(["--split", bad])
            .output()
            .unwrap();
        assert_eq!(result.status.code(), Some(2), "--split {bad}");
        assert_one_clear_line(&result.stderr, &["--split", bad]);
        assert!(!out.exists());
    }
}

#[cfg(not(feature = "gui"))]
#[test]
fn render_runs_need_the_window_build() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("render.ron");
    std::fs::write(
        &config,
        "Bench(runs: [Run(bodies: 10, updates: 2), Render(bodies: 10, frames: 5, method: Instanced)])",
    )
    .unwrap();
    let out = dir.path().join("results.csv");
    let result = kessler()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
    assert_one_clear_line(&result.stderr, &["render.ron", "runs[1]", "window"]);
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "only the config is there"
    );
}

/// Every config shipped in `benches/` loads as the docs write configs:
/// flat execution options and settings beside a run's own fields. A
/// build without the window refuses only the window's `Render` runs.
#[test]
fn the_shipped_configs_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "ron") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        if !text.contains("Bench(") {
            continue; // a scenario kept beside the configs
        }
        match kessler::bench::BenchConfig::load(&path) {
            Ok(config) => assert!(!config.runs.is_empty(), "{}", path.display()),
            Err(e) if !kessler::WINDOW_BUILD && e.to_string().contains("`Render` runs open the window") => {}
            Err(e) => panic!("{e}"),
        }
        checked += 1;
    }
    assert!(checked >= 7, "{checked} configs in {}", dir.display());
}
