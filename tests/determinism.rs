//! Sequential and parallel execution give bit-identical state, at every
//! thread count and split, whatever order the bodies are stored in.

use kessler::Simulation;
use kessler::components::BodyState;
use kessler::execution::{Execution, ExecutionMode, SplitPolicy, WorkerPool};
use kessler::scenario::Scenario;

fn run(text: &str, mode: ExecutionMode, threads: usize, updates: u64) -> Vec<BodyState> {
    let scenario = Scenario::parse(text, "test").unwrap();
    // Cut for every thread, as a machine with that many cores would.
    let execution = Execution::new(mode, threads).unwrap().as_if_hardware_threads(threads);
    // Parallel runs split every kernel finely, so chunk boundaries are tested.
    let execution = if mode == ExecutionMode::Parallel {
        execution.fine_grained()
    } else {
        execution
    };
    let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
    // Gravity and integration only: self-gravitating debris that shatters
    // re-collapses and shatters again, which is a different test.
    sim.settings_mut().stages.collisions = false;
    sim.step(updates);
    sim.snapshot()
}

fn bits(bodies: &[BodyState]) -> Vec<[u32; 6]> {
    bodies
        .iter()
        .map(|b| {
            let (p, v) = (b.position, b.velocity);
            [p.x, p.y, p.z, v.x, v.y, v.z].map(f32::to_bits)
        })
        .collect()
}

fn assert_modes_agree(text: &str, updates: u64) {
    let sequential = run(text, ExecutionMode::Sequential, 1, updates);
    for threads in [2, 3] {
        let parallel = run(text, ExecutionMode::Parallel, threads, updates);
        assert_eq!(sequential.len(), parallel.len());
        let ids = |b: &[BodyState]| b.iter().map(|b| b.id).collect::<Vec<_>>();
        assert_eq!(ids(&sequential), ids(&parallel));
        let (s, p) = (bits(&sequential), bits(&parallel));
        let first_difference = s.iter().zip(&p).position(|(a, b)| a != b);
        assert_eq!(
            first_difference, None,
            "{threads} threads: body differs from sequential"
        );
    }
}

/// 2000 bodies all pulling on each other (4 million interactions per update).
#[test]
fn n_body_cloud_is_bit_identical_in_both_modes() {
    let text = "Scenario(softening: 2.0, generators: [
        Cloud(count: 2000, center: (0, 0, 0), half_size: (500, 500, 500), max_speed: 0.5,
              body: (mass: 5.0, role: SourceAndAdopter)),
    ])";
    assert_modes_agree(text, 200);
    // And the bodies really moved under each other's pull.
    let start = run(text, ExecutionMode::Sequential, 1, 0);
    let end = run(text, ExecutionMode::Sequential, 1, 200);
    let moved = start.iter().zip(&end).filter(|(a, b)| a.velocity != b.velocity).count();
    assert_eq!(moved, 2000);
}

/// Enough bodies that integration is split across threads too.
#[test]
fn large_adopter_field_is_bit_identical_in_both_modes() {
    let text = "Scenario(bodies: [
        Body(position: (0, 0, 0), half_extents: (50, 50, 50), mass: 4000, role: Source, interacts: false),
        Body(position: (3000, 0, 0), velocity: (0, 0, -3), mass: 50, role: SourceAndAdopter, interacts: false),
    ], generators: [
        Shell(count: 150000, around: 0, inner_radius: 800, outer_radius: 1400, inclination: 30, speed_jitter: 0.1),
    ])";
    assert_modes_agree(text, 20);
}

/// The Barnes–Hut tree with shattering on: 300 heavy cubes collapse, crash
/// and shatter; every mode and thread count gives the same bits, and the
/// same fragments.
#[test]
fn the_gravity_tree_is_bit_identical_with_shattering() {
    let bodies = collapse_is_bit_identical("gravity: Tree(theta: 0.5),", 300);
    // Each shatter of a pair into five adds three bodies.
    assert!(bodies > 300 + 3 * 50, "only {bodies} bodies: few shatters");
}

/// The same with the default gravity, `Auto`: 400 cubes summed directly
/// until their fragments pass 512, then through the tree.
#[test]
fn auto_gravity_is_bit_identical_as_it_moves_to_the_tree() {
    let bodies = collapse_is_bit_identical("", 400);
    // Well past the count, so that updates ran through the tree.
    assert!(
        bodies > kessler::resources::AUTO_TREE_FROM + 100,
        "{bodies} bodies: never moved"
    );
}

/// Runs a collapse of `count` cubes with the `gravity` setting given for
/// 40 updates in every mode, checks that they agree, and returns the
/// number of bodies at the end.
fn collapse_is_bit_identical(gravity: &str, count: usize) -> usize {
    let text = format!(
        "Scenario(softening: 1.0, {gravity} generators: [
        Cloud(count: {count}, center: (0, 0, 0), half_size: (40, 40, 40), max_speed: 0.5,
              body: (role: SourceAndAdopter)),
    ])"
    );
    let scenario = Scenario::parse(&text, "test").unwrap();
    let run = |mode, threads| {
        let execution = Execution::new(mode, threads).unwrap().as_if_hardware_threads(threads);
        let execution = if mode == ExecutionMode::Parallel {
            execution.fine_grained()
        } else {
            execution
        };
        let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
        sim.step(40);
        (sim.snapshot(), sim.collision_stats().shatters_total)
    };
    let (sequential, shatters) = run(ExecutionMode::Sequential, 1);
    assert!(shatters > 50, "only {shatters} shatters");
    let ids = |b: &[BodyState]| b.iter().map(|b| b.id).collect::<Vec<_>>();
    for threads in [2, 3] {
        let (parallel, _) = run(ExecutionMode::Parallel, threads);
        assert_eq!(ids(&sequential), ids(&parallel), "{threads} threads: other fragments");
        assert!(bits(&sequential) == bits(&parallel), "{threads} threads differ");
    }
    // The same kernels on Bevy's ComputeTaskPool, in one-item chunks.
    let execution = Execution::new(ExecutionMode::Parallel, 2)
        .unwrap()
        .fine_grained()
        .with_pool(WorkerPool::Bevy);
    let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
    sim.step(40);
    let bevy = sim.snapshot();
    assert_eq!(ids(&sequential), ids(&bevy), "Bevy's pool: other fragments");
    assert!(bits(&sequential) == bits(&bevy), "Bevy's pool differs");
    sequential.len()
}

/// A shattering collapse under tree gravity: thread counts 1, 2, 3 and 7
/// (each cut as on a machine with as many cores; on fewer, a step runs on
/// only as many threads as there are cores) and splits `Always`, `Auto`
/// and a number give one state hash, sequential's.
#[test]
fn one_hash_for_every_thread_count_and_split() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/collapse.ron");
    let scenario = Scenario::load(std::path::Path::new(path)).unwrap();
    let hash = |execution: Execution| {
        let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
        sim.step(40);
        assert!(sim.collision_stats().shatters_total > 100, "the collapse shatters");
        sim.state_hash()
    };
    let sequential = hash(Execution::new(ExecutionMode::Sequential, 1).unwrap());
    for threads in [1, 2, 3, 7] {
        for split in [SplitPolicy::Always, SplitPolicy::Auto, SplitPolicy::Above(100)] {
            let execution = Execution::new(ExecutionMode::Parallel, threads)
                .unwrap()
                .as_if_hardware_threads(threads)
                .with_split(split);
            assert_eq!(hash(execution), sequential, "{threads} threads, split {split}");
        }
    }
}

/// The same bodies spawned in another order (the world's tables keep
/// bodies in the order they came, and a despawn moves the last into the
/// gap) give the same state: a shattering collapse spawned as listed,
/// reversed and interleaved, sequential and split on 2 threads.
#[test]
fn one_hash_whatever_order_the_bodies_are_stored_in() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/collapse.ron");
    let scenario = Scenario::load(std::path::Path::new(path)).unwrap();
    let listed = scenario.bodies().unwrap();
    let reversed: Vec<BodyState> = listed.iter().rev().copied().collect();
    let (evens, odds): (Vec<_>, Vec<_>) = listed.iter().enumerate().partition(|(k, _)| k % 2 == 0);
    let interleaved: Vec<BodyState> = odds.into_iter().chain(evens).map(|(_, &b)| b).collect();
    for execution in [
        Execution::new(ExecutionMode::Sequential, 1).unwrap(),
        Execution::new(ExecutionMode::Parallel, 2)
            .unwrap()
            .as_if_hardware_threads(2)
            .with_split(SplitPolicy::Always),
    ] {
        let hash = |bodies: &[BodyState]| {
            let mut sim = Simulation::new(bodies, scenario.settings(), execution.clone());
            sim.step(40);
            assert!(sim.collision_stats().shatters_total > 100, "the collapse shatters");
            sim.state_hash()
        };
        let as_listed = hash(&listed);
        assert_eq!(hash(&reversed), as_listed, "reversed, {execution:?}");
        assert_eq!(hash(&interleaved), as_listed, "interleaved, {execution:?}");
    }
}

/// Debris hitting an absorbing ball and shattering on the way: every
/// thread count gives sequential's state hash and absorbed mass.
#[test]
fn absorbing_a_shattering_cloud_is_bit_identical() {
    let text = "Scenario(shatter_threshold: 0.5, bodies: [
        Body(position: (0, 0, 0), shape: Sphere(radius: 40), mass: 3000, role: Source, interacts: false, absorbs: true),
    ], generators: [
        Cloud(count: 3000, center: (0, 0, 0), half_size: (120, 120, 120), max_speed: 1.0),
    ])";
    let scenario = Scenario::parse(text, "test").unwrap();
    let run = |execution: Execution| {
        let mut sim = Simulation::from_scenario(&scenario, execution.fine_grained()).unwrap();
        sim.step(30);
        let stats = sim.collision_stats();
        (
            sim.state_hash(),
            sim.absorbed().mass.to_bits(),
            stats.reentries_total,
            stats.shatters_total,
        )
    };
    let sequential = run(Execution::new(ExecutionMode::Sequential, 1).unwrap());
    assert!(
        sequential.2 > 1000 && sequential.3 > 50,
        "absorbs and shatters: {sequential:?}"
    );
    for threads in [2, 3] {
        let parallel = run(Execution::new(ExecutionMode::Parallel, threads)
            .unwrap()
            .as_if_hardware_threads(threads));
        assert_eq!(parallel, sequential, "{threads} threads");
    }
}

/// The collapse with power-law fragment sizes: fragments of many sizes,
/// every thread count the same bits.
#[test]
fn power_law_breakups_are_bit_identical_in_both_modes() {
    let bodies = collapse_is_bit_identical(
        "fragment_sizes: PowerLaw(exponent: 1.71), min_fragment_size: 0.05,",
        300,
    );
    assert!(bodies > 300, "{bodies}");
}
