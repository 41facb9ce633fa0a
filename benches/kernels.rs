//! Each stage's kernel on its own, without an App, sequential vs parallel
//! (all hardware threads, split at every count), and the bare cost of one
//! parallel step: `cargo bench --bench kernels`.

use bevy::math::DVec3;
use bevy::prelude::*;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use kessler::components::{BodyId, BodyState, GravityRole, Position, PreviousPosition, Velocity};
use kessler::execution::{Execution, ExecutionMode, SplitPolicy, available_threads};
use kessler::maths;
use kessler::maths::Rng;
use kessler::physics::{Aabb, fragments};
use kessler::resources::{GravityMethod, Integrator};
use kessler::systems::{
    ContactBody, GravitySource, Octree, Pull, PullScratch, Roles, SortedBoxes, gravity_kernel, prepare_pull, respond,
    sort_boxes, sweep_and_prune,
};

const COUNTS: [usize; 3] = [1_000, 10_000, 100_000];
const MODES: [ExecutionMode; 2] = [ExecutionMode::Sequential, ExecutionMode::Parallel];

fn execution(mode: ExecutionMode) -> Execution {
    Execution::new(mode, available_threads())
        .unwrap()
        .with_split(SplitPolicy::Always)
}

/// Centers uniform in [1, 5000]³, as in the thesis scene.
fn centers(count: usize) -> Vec<Vec3> {
    let mut rng = Rng::new(1);
    (0..count)
        .map(|_| {
            Vec3::new(
                rng.range(1.0, 5000.0) as f32,
                rng.range(1.0, 5000.0) as f32,
                rng.range(1.0, 5000.0) as f32,
            )
        })
        .collect()
}

fn gravity(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel_gravity");
    let sources = [GravitySource {
        id: BodyId(0),
        position: DVec3::splat(2500.0),
        gm: 6.674 * 4000.0,
    }];
    for count in COUNTS {
        let ids: Vec<BodyId> = (1..=count as u64).map(BodyId).collect();
        let mut positions: Vec<Position> = centers(count).into_iter().map(Position).collect();
        let mut previous = vec![PreviousPosition::default(); count];
        let roles = vec![GravityRole::Adopter; count];
        let mut velocities = vec![Velocity::default(); count];
        for mode in MODES {
            let exec = execution(mode);
            group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
                b.iter(|| {
                    // The thesis's kick (semi-implicit Euler): positions stay.
                    let columns = (
                        ids.as_slice(),
                        Roles::Each(&roles),
                        positions.as_mut_slice(),
                        previous.as_mut_slice(),
                        velocities.as_mut_slice(),
                    );
                    exec.for_stage("gravity", count).for_chunks(columns, |cols| {
                        gravity_kernel(cols, Pull::Direct(&sources), 0.0, 1.0, Integrator::SemiImplicitEuler);
                    });
                })
            });
        }
    }
    group.finish();
}

/// Every body a source: the tree's pull (build and every source's
/// acceleration, θ = 0.5) over 10 000 sources: a uniform cloud in a cube
/// of edge 1000, as `benches/self_gravity.ron`; and a clustered one, a
/// dense core in a sparse halo out to 20 000 units, like the collapsed
/// cluster of `scenarios/collapse.ron` (its halo's leaves are as big as
/// their distance: the case the regions' local expansions are for).
fn gravity_tree(c: &mut Criterion) {
    let count = 10_000;
    let mut rng = Rng::new(3);
    let uniform = uniform_cloud(count, &mut rng);
    let clustered: Vec<GravitySource> = (0..count)
        .map(|i| {
            let direction = DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)).normalize_or_zero();
            // Radius from 10 to 20 000, uniform in its logarithm: a density
            // falling as r⁻³, the same number of sources in every octave.
            let r = 10.0 * maths::pow(2000.0, rng.range(0.0, 1.0));
            GravitySource {
                id: BodyId(i as u64),
                position: (direction * r).as_vec3().as_dvec3(),
                gm: 6.674 * rng.range(0.5, 2.0),
            }
        })
        .collect();
    let mut group = c.benchmark_group("kernel_gravity_tree");
    tree_pulls(&mut group, &uniform);
    group.finish();
    let mut group = c.benchmark_group("kernel_gravity_tree_clustered");
    tree_pulls(&mut group, &clustered);
    group.finish();
}

/// `count` sources uniform in the cube of edge 1000 of
/// `benches/self_gravity.ron`, at `f32` positions as bodies have.
fn uniform_cloud(count: usize, rng: &mut Rng) -> Vec<GravitySource> {
    (0..count)
        .map(|i| GravitySource {
            id: BodyId(i as u64),
            position: DVec3::new(rng.symmetric(500.0), rng.symmetric(500.0), rng.symmetric(500.0))
                .as_vec3()
                .as_dvec3(),
            gm: 6.674,
        })
        .collect()
}

/// The tree's pull over `sources` (θ = 0.5, every source an adopter), each
/// mode in `group`.
fn tree_pulls(group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>, sources: &[GravitySource]) {
    let (count, method) = (sources.len(), GravityMethod::Tree { theta: 0.5 });
    for mode in MODES {
        let exec = execution(mode);
        let mut scratch = PullScratch::default();
        group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
            b.iter(|| {
                prepare_pull(method, sources, count, 1.0, &exec, &mut scratch);
            })
        });
    }
}

/// The tree's pull at the 100 000-source goal: a uniform cloud in the
/// cube of edge 1000 of `benches/self_gravity.ron` (ten times denser than
/// at 10 000), θ = 0.5, as one update's gravity stage computes it before
/// the kick.
fn gravity_tree_100k(c: &mut Criterion) {
    let sources = uniform_cloud(100_000, &mut Rng::new(4));
    let mut group = c.benchmark_group("kernel_gravity_tree_100k");
    group.sample_size(10);
    tree_pulls(&mut group, &sources);
    group.finish();
}

/// The tree's build alone (sorting into octants, moments, regions and
/// groups) over uniform clouds, as `benches/self_gravity.ron`'s (the same
/// density at every count).
fn gravity_tree_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel_gravity_tree_build");
    for count in COUNTS {
        let mut rng = Rng::new(3);
        let edge = 500.0 * maths::cbrt(count as f64 / 10_000.0);
        let sources: Vec<GravitySource> = (0..count)
            .map(|i| GravitySource {
                id: BodyId(i as u64),
                position: DVec3::new(rng.symmetric(edge), rng.symmetric(edge), rng.symmetric(edge)),
                gm: 6.674,
            })
            .collect();
        for mode in MODES {
            let exec = execution(mode);
            let mut tree = Octree::default();
            group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
                b.iter(|| tree.rebuild_split(&sources, exec.for_stage("gravity", count)))
            });
        }
    }
    group.finish();
}

fn sweep(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel_sweep_and_prune");
    for count in COUNTS {
        let mut boxes: Vec<Aabb> = centers(count).into_iter().map(|p| Aabb::new(p, Vec3::ONE)).collect();
        boxes.push(Aabb::new(Vec3::splat(2500.0), Vec3::splat(430.0)));
        for mode in MODES {
            let exec = execution(mode);
            let mut scratch = SortedBoxes::default();
            group.bench_with_input(BenchmarkId::new(mode.name(), count), &count, |b, _| {
                b.iter(|| sweep_and_prune(boxes.as_slice(), &exec, &mut scratch))
            });
        }
    }
    group.finish();
}

fn response(c: &mut Criterion) {
    let mut group = c.benchmark_group("kernel_response_per_1000_pairs");
    let mut rng = Rng::new(3);
    let mut r = |lo: f64, hi: f64| rng.range(lo, hi) as f32;
    let contacts: Vec<(ContactBody, ContactBody)> = (0..1000)
        .map(|_| {
            let v = Vec3::new(r(-1.0, 1.0), r(-1.0, 1.0), r(-1.0, 1.0));
            let a = ContactBody {
                position: Vec3::ZERO,
                previous: -v,
                velocity: v,
                mass: 1.0,
                half_extents: Vec3::ONE,
                interacts: true,
                spherical: false,
            };
            let p = Vec3::new(r(1.0, 1.9), r(-1.0, 1.0), r(-1.0, 1.0));
            let b = ContactBody {
                position: p,
                previous: p + v,
                velocity: -v,
                ..a
            };
            (a, b)
        })
        .collect();
    group.bench_function("respond", |b| {
        b.iter(|| {
            contacts
                .iter()
                .map(|(a, b)| respond(a, b, 3.0, 1.0))
                .collect::<Vec<_>>()
        })
    });
    group.finish();
}

fn shatter(c: &mut Criterion) {
    let body = |id, x: f32, vx| {
        BodyState::new_box(
            BodyId(id),
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(vx, 0.0, 0.0),
            1.0,
            Vec3::ONE,
            GravityRole::Adopter,
            true,
        )
    };
    let (a, b) = (body(0, 0.0, 3.0), body(1, 1.9, -3.0));
    let mut group = c.benchmark_group("kernel_shatter");
    for count in [5, 50] {
        group.bench_with_input(BenchmarkId::new("fragments", count), &count, |bench, &count| {
            bench.iter(|| fragments(&a, &b, count, 0.2, 1, BodyId(2)))
        });
    }
    group.finish();
}

/// One parallel step of a near-empty kernel on 1 and 2 threads, against
/// the same kernel called whole: what handing work to the pool costs.
fn dispatch(c: &mut Criterion) {
    let mut group = c.benchmark_group("dispatch");
    let kernel = |r: std::ops::Range<usize>| r.len();
    for threads in [1, 2] {
        let exec = Execution::new(ExecutionMode::Parallel, threads)
            .unwrap()
            .with_split(SplitPolicy::Always);
        let items = threads * 4;
        group.bench_function(BenchmarkId::new("split", threads), |b| {
            b.iter(|| exec.for_stage("dispatch", 0).map_chunks(0..items, kernel))
        });
    }
    group.bench_function("whole", |b| {
        let exec = execution(ExecutionMode::Sequential);
        b.iter(|| exec.for_stage("dispatch", 0).map_chunks(0..8, kernel))
    });
    group.finish();
}

/// The sort stage (sequential) beside what this machine's memory allows
/// for the same boxes: one read of every box in order, the boxes written
/// to their cells (cells known, 28 bytes a box: the filing's scattered
/// writes alone), one copy of the filing, and the sort of the same boxes
/// stored in cell order. docs/benchmarks.md, "The update near its
/// limit", compares them.
fn sort_against_memory(c: &mut Criterion) {
    /// A filed box as the sort writes it: index and corners.
    #[derive(Clone, Copy, Default)]
    struct Filed {
        _index: u32,
        _corners: [f32; 6],
    }
    let mut group = c.benchmark_group("sort_against_memory");
    group.sample_size(10);
    for count in [10_000, 1_000_000] {
        let boxes: Vec<Aabb> = centers(count).into_iter().map(|p| Aabb::new(p, Vec3::ONE)).collect();
        let exec = execution(ExecutionMode::Sequential);
        let mut sorted = SortedBoxes::default();
        group.bench_with_input(BenchmarkId::new("sort", count), &count, |b, _| {
            b.iter(|| sort_boxes(boxes.as_slice(), exec.for_stage("sort", count), &mut sorted))
        });
        group.bench_with_input(BenchmarkId::new("read_in_order", count), &count, |b, _| {
            b.iter(|| boxes.iter().map(|b| b.min.y + b.max.z).sum::<f32>())
        });
        // The grid the sort fits: about 64 boxes a cell over y and z.
        let side = ((count / 64) as f64).sqrt() as usize;
        let axis = |v: f32| (((v - 1.0) / 4999.0 * side as f32) as usize).min(side - 1);
        let cells: Vec<usize> = boxes.iter().map(|b| axis(b.min.y) * side + axis(b.min.z)).collect();
        let mut starts = vec![0; side * side + 1];
        for &cell in &cells {
            starts[cell + 1] += 1;
        }
        for cell in 0..side * side {
            starts[cell + 1] += starts[cell];
        }
        let mut filing = vec![Filed::default(); count];
        group.bench_with_input(BenchmarkId::new("write_to_cells", count), &count, |b, _| {
            b.iter(|| {
                let mut next = starts.clone();
                for (i, (b, &cell)) in boxes.iter().zip(&cells).enumerate() {
                    filing[next[cell]] = Filed {
                        _index: i as u32,
                        _corners: [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z],
                    };
                    next[cell] += 1;
                }
            })
        });
        let mut copy = filing.clone();
        group.bench_with_input(BenchmarkId::new("copy_filing", count), &count, |b, _| {
            b.iter(|| copy.copy_from_slice(&filing))
        });
        // The same boxes stored in about the order the filing reads them
        // back (by the cells above, then lower x bound), as they are and
        // after each moved up to 5 units on each axis (one update at the
        // thesis scene's top speed): what the sort would gain from bodies
        // stored near their cell (docs/benchmarks.md, "What storage order
        // would give"). A million only: at 10 000 the sort of boxes that
        // do not change is a repair with nothing to do.
        if count < 1_000_000 {
            continue;
        }
        let mut by_cell = boxes.clone();
        by_cell.sort_by_key(|b| {
            (((axis(b.min.y) * side + axis(b.min.z)) as u64) << 32) | u64::from(maths::order_key(b.min.x))
        });
        let mut rng = Rng::new(2);
        let mut moved = by_cell.clone();
        for b in &mut moved {
            let step = Vec3::new(
                rng.range(-5.0, 5.0) as f32,
                rng.range(-5.0, 5.0) as f32,
                rng.range(-5.0, 5.0) as f32,
            );
            *b = Aabb::new((b.min + b.max) * 0.5 + step, Vec3::ONE);
        }
        for (name, stored) in [("sort_stored_by_cell", &by_cell), ("sort_stored_by_cell_moved", &moved)] {
            let mut sorted = SortedBoxes::default();
            group.bench_with_input(BenchmarkId::new(name, count), &count, |b, _| {
                b.iter(|| sort_boxes(stored.as_slice(), exec.for_stage("sort", count), &mut sorted))
            });
        }
    }
    group.finish();
}

criterion_group!(
    benches,
    gravity,
    gravity_tree,
    gravity_tree_100k,
    gravity_tree_build,
    sweep,
    response,
    shatter,
    dispatch,
    sort_against_memory
);
criterion_main!(benches);
