//! Whole simulation updates, sequential vs parallel (all hardware threads):
//! `cargo bench --bench update`.
//!
//! - `thesis_update/*/N`: the thesis scene (N cubes in [1, 5000]³ around the
//!   planet, shattering on) — every stage.
//! - `gravity_integrate/*/N`: N adopters in orbit around one source with
//!   collisions off — gravity and integration only.

use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use kessler::Simulation;
use kessler::execution::{Execution, ExecutionMode, available_threads};
use kessler::scenario::Scenario;

const MODES: [ExecutionMode; 2] = [ExecutionMode::Sequential, ExecutionMode::Parallel];

fn simulation(text: &str, mode: ExecutionMode) -> Simulation {
    let scenario = Scenario::parse(text, "bench").unwrap();
    Simulation::from_scenario(&scenario, Execution::new(mode, available_threads()).unwrap()).unwrap()
}

/// The thesis scene with `count` cubes.
fn thesis(count: u64, mode: ExecutionMode) -> Simulation {
    simulation(
        &format!(
            "Scenario(bodies: [Body(position: (2500, 2500, 2500), half_extents: (430, 430, 430), mass: 4000, role: Source, interacts: false)],
                      generators: [Cloud(count: {count}, center: (2500.5, 2500.5, 2500.5), half_size: (2499.5, 2499.5, 2499.5), max_speed: 5.0)])"
        ),
        mode,
    )
}

/// `count` cubes on orbits between 800 and 1400 around a fixed planet.
fn orbiting(count: u64, mode: ExecutionMode) -> Simulation {
    let mut sim = simulation(
        &format!(
            "Scenario(bodies: [Body(position: (0, 0, 0), half_extents: (430, 430, 430), mass: 4000, role: Source, interacts: false)],
                      generators: [Shell(count: {count}, around: 0, inner_radius: 800, outer_radius: 1400, inclination: 30)])"
        ),
        mode,
    );
    sim.settings_mut().stages.collisions = false;
    sim
}

/// Updates measured on one copy of a scene before it is made afresh. The
/// thesis cloud falls onto its planet within about a thousand updates and
/// then collides and shatters far more; measuring thousands of updates on
/// one copy would compare a different scene in each mode (the faster mode
/// runs more iterations). Like `kessler bench`, every copy gets one
/// unmeasured warm-up update.
const UPDATES_PER_COPY: u64 = 100;

fn bench_updates(c: &mut Criterion, group: &str, counts: &[u64], make: fn(u64, ExecutionMode) -> Simulation) {
    let mut group = c.benchmark_group(group);
    for &count in counts {
        if count >= 100_000 {
            group.sample_size(20);
        }
        for mode in MODES {
            let fresh = || {
                let mut sim = make(count, mode);
                sim.step(1);
                sim
            };
            let mut sim = fresh();
            let mut done_on_copy = 0;
            group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
                b.iter_custom(|iterations| {
                    let mut measured = Duration::ZERO;
                    let mut left = iterations;
                    while left > 0 {
                        if done_on_copy == UPDATES_PER_COPY {
                            sim = fresh();
                            done_on_copy = 0;
                        }
                        let batch = left.min(UPDATES_PER_COPY - done_on_copy);
                        let start = Instant::now();
                        sim.step(batch);
                        measured += start.elapsed();
                        done_on_copy += batch;
                        left -= batch;
                    }
                    measured
                })
            });
        }
    }
    group.finish();
}

fn thesis_update(c: &mut Criterion) {
    bench_updates(c, "thesis_update", &[1_000, 10_000, 100_000], thesis);
}

fn gravity_integrate(c: &mut Criterion) {
    bench_updates(c, "gravity_integrate", &[1_000, 10_000, 100_000, 1_000_000], orbiting);
}

criterion_group!(benches, thesis_update, gravity_integrate);
criterion_main!(benches);
