//! Ensembles: `cargo bench --bench ensemble` (docs/benchmarks.md,
//! "Ensembles"; the executor's own goal is measured by
//! `benches/ensemble_executor.sh`).
//!
//! - `ensemble_aggregate/1000x200`: `kessler ensemble aggregate`'s work on
//!   1 000 finished members of 200 timeline rows each, in two
//!   combinations: reading the timelines, the percentiles, the CSV and the
//!   plot. The folder is made up (real files, invented numbers). Goal:
//!   under 2 s.
//! - `ensemble_member_overhead/<scene>`: a member process that runs 0
//!   updates — starting the process, loading and checking the scenario,
//!   making the simulation, writing the timeline, summary and marker:
//!   everything a member costs beyond its simulation. Goal: at most 50 ms.

use std::path::Path;
use std::process::Command;

use bevy::math::DVec3;
use criterion::{Criterion, criterion_group, criterion_main};
use kessler::ensemble::{EnsembleConfig, EnsembleFolder, Record, aggregate};
use kessler::output::write_csv;
use kessler::physics::Totals;
use kessler::record::StateHash;
use kessler::simulation::TimelineRow;

/// A folder of `members` finished members with `rows` timeline rows each.
fn made_up_folder(dir: &Path, members: u64, rows: u64) -> (EnsembleFolder, Record) {
    let config = EnsembleConfig::parse(
        &format!(
            "Ensemble(steps: {}, every: 100, members: {}, vary: (shatter_threshold: [2.0, 4.0]))",
            (rows - 1) * 100,
            members / 2
        ),
        "bench",
    )
    .unwrap();
    let scenario = "Scenario(bodies: [Body(position: (0, 0, 0))])";
    let record = Record::new(&config, Path::new("bench.ron"), "bench", scenario);
    let (folder, _) = EnsembleFolder::prepare(dir).unwrap();
    folder.write_record(&record, scenario).unwrap();
    for index in 0..members {
        std::fs::create_dir_all(folder.member_dir(index)).unwrap();
        let timeline: Vec<TimelineRow> = (0..rows)
            .map(|r| TimelineRow {
                update: r * 100,
                pairs: r % 7,
                shatters: (r * 31 + index) % 5,
                refused_shatters: 0,
                totals: Totals {
                    bodies: 20_000 + r * 3 + (index * 17 + r * 13) % 41,
                    mass: 24_050.0,
                    kinetic_energy: 3.1e5 + (index * 7919 % 1000) as f64 + r as f64,
                    momentum: DVec3::new(0.1, -0.2, 0.3),
                },
                reentries: r % 3,
                absorbed_mass: r as f64,
                deferred: 0,
                state_hash: StateHash(index << 32 | r),
            })
            .collect();
        let file = std::fs::File::create(folder.timeline(index)).unwrap();
        write_csv(std::io::BufWriter::new(file), &timeline).unwrap();
        std::fs::write(folder.done_marker(index), "").unwrap();
    }
    (folder, record)
}

fn aggregation(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let (folder, record) = made_up_folder(&dir.path().join("ens"), 1000, 200);
    let done = folder.census(record.config.total_members()).done;
    let mut group = c.benchmark_group("ensemble_aggregate");
    group.sample_size(10);
    group.bench_function("1000x200", |b| {
        b.iter(|| {
            let summed = aggregate(&folder, &record, &done).unwrap();
            assert_eq!((summed.members, summed.rows), (1000, 400));
        })
    });
    group.finish();
}

fn member_overhead(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut group = c.benchmark_group("ensemble_member_overhead");
    group.sample_size(20);
    for scene in ["two_body", "cascade", "debris_orbit"] {
        let dir = tempfile::tempdir().unwrap();
        let config = dir.path().join("c.ron");
        let scenario = root.join(format!("scenarios/{scene}.ron"));
        std::fs::write(
            &config,
            format!(
                "Ensemble(scenario: {:?}, steps: 0, members: 1)",
                scenario.display().to_string()
            ),
        )
        .unwrap();
        let out = dir.path().join("ens");
        let kessler = || Command::new(env!("CARGO_BIN_EXE_kessler"));
        assert!(
            kessler()
                .arg("ensemble")
                .arg(&config)
                .arg("--out")
                .arg(&out)
                .status()
                .unwrap()
                .success()
        );
        group.bench_function(scene, |b| {
            b.iter(|| {
                let status = kessler()
                    .args(["ensemble", "member"])
                    .arg(&out)
                    .arg("0")
                    .output()
                    .unwrap();
                assert!(status.status.success());
            })
        });
    }
    group.finish();
}

criterion_group!(benches, aggregation, member_overhead);
criterion_main!(benches);
