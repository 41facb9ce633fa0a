//! Gravity + integration of N adopters around one source, sequential vs
//! parallel: `cargo bench --bench update`.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use kessler::Simulation;
use kessler::resources::{Execution, ExecutionMode, available_threads};
use kessler::scenario::Scenario;

/// N unit cubes on orbits between 800 and 1400 around a fixed planet.
fn orbiting(count: u64, mode: ExecutionMode) -> Simulation {
    let text = format!(
        "Scenario(bodies: [Body(position: (0, 0, 0), half_extents: (430, 430, 430), mass: 4000, role: Source, interacts: false)],
                  generators: [Shell(count: {count}, around: 0, inner_radius: 800, outer_radius: 1400, inclination: 30)])"
    );
    let scenario = Scenario::parse(&text, "bench").unwrap();
    let execution = Execution::new(mode, available_threads()).unwrap();
    Simulation::from_scenario(&scenario, "bench", execution).unwrap()
}

fn gravity_and_integration(c: &mut Criterion) {
    let mut group = c.benchmark_group("gravity_integrate");
    for count in [1_000, 10_000, 100_000, 1_000_000] {
        if count >= 100_000 {
            group.sample_size(20);
        }
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            let mut sim = orbiting(count, mode);
            group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
                b.iter(|| sim.step(1))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, gravity_and_integration);
criterion_main!(benches);
