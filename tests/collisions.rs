//! Collisions through the whole simulation: bounces, walls, shattering,
//! one response per body per update, and bit-identical modes with real
//! shattering happening.

mod common {
    pub mod binary;
    pub mod simulation;
}

use bevy::math::{DVec3, Vec3};
use common::binary::kessler;
use common::simulation::sim;
use kessler::Simulation;
use kessler::components::{BodyId, BodyState};
use kessler::execution::{AutoSplit, Execution, ExecutionMode, SplitPolicy};
use kessler::scenario::Scenario;

fn momentum(bodies: &[BodyState]) -> DVec3 {
    bodies.iter().map(|b| b.velocity.as_dvec3() * f64::from(b.mass)).sum()
}

/// Under either detection: the velocities swap; discrete pushes them back
/// to where they touched, swept moves them apart from there for the rest
/// of the update (they touched after a quarter of it: 0.75 at 2 apart).
#[test]
fn equal_cubes_meeting_head_on_swap_velocities() {
    for (detection, gap, later) in [("Discrete", 0.0, -11.0), ("Swept", 1.5, -11.75)] {
        // 0.5 apart; they meet during the first update.
        let mut s = sim(&format!(
            "Scenario(gravitational_constant: 0, collision_detection: {detection}, bodies: [
                Body(position: (-1.25, 0, 0), velocity: (1, 0, 0)),
                Body(position: (1.25, 0, 0), velocity: (-1, 0, 0)),
            ])"
        ));
        s.step(1);
        let b = s.snapshot();
        assert_eq!(s.collision_stats().responses, 1);
        assert_eq!(
            (b[0].velocity, b[1].velocity),
            (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0))
        );
        assert!(
            (b[1].position.x - b[0].position.x - 2.0 - gap).abs() < 1e-6,
            "{detection}: {b:?}"
        );
        s.step(10);
        assert_eq!(s.snapshot()[0].position.x, later, "{detection}");
    }
}

/// Discrete pushes the cube back to the surface; swept finds it touching
/// after 0.75 of the update and moves it out for the rest (0.5).
#[test]
fn a_cube_bounces_straight_back_off_the_planet() {
    for (detection, x) in [("Discrete", 101.0), ("Swept", 101.5)] {
        let mut s = sim(&format!(
            "Scenario(gravitational_constant: 0, collision_detection: {detection}, bodies: [
                Body(position: (0, 0, 0), half_extents: (100, 100, 100), mass: 4000, role: Source, interacts: false),
                Body(position: (102.5, 3, -7), velocity: (-2, 0, 0)),
            ])"
        ));
        s.step(1);
        let b = s.snapshot();
        assert_eq!(b[0].position, Vec3::ZERO, "the planet never moves");
        assert_eq!(b[1].velocity, Vec3::new(2.0, 0.0, 0.0));
        assert!((b[1].position.x - x).abs() < 1e-5, "{detection}: {}", b[1].position);
        assert_eq!((b[1].position.y, b[1].position.z), (3.0, -7.0));
    }
}

#[test]
fn many_cubes_hit_the_planet_in_the_same_update() {
    let mut s = sim("Scenario(gravitational_constant: 0, bodies: [
        Body(position: (0, 0, 0), half_extents: (100, 100, 100), role: Source, interacts: false),
        Body(position: (102.5, 0, 0), velocity: (-2, 0, 0)),
        Body(position: (-102.5, 0, 0), velocity: (2, 0, 0)),
        Body(position: (0, 102.5, 0), velocity: (0, -2, 0)),
    ])");
    s.step(1);
    let v: Vec<Vec3> = s.snapshot()[1..].iter().map(|b| b.velocity).collect();
    assert_eq!(
        v,
        [
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(-2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0)
        ]
    );
}

/// A ball's bounding box reaches `r·(√3 − 1)` beyond the ball at its
/// corners. A cube flying through that corner region, inside the box but
/// outside the ball, flies straight on.
#[test]
fn a_cube_through_a_balls_corner_region_passes_untouched() {
    let mut s = sim("Scenario(gravitational_constant: 0, bodies: [
        Body(position: (0, 0, 0), shape: Sphere(radius: 100), mass: 4000, role: Source, interacts: false),
        Body(position: (95, 95, 130), velocity: (0, 0, -2)),
    ])");
    // Its path x = y = 95 stays (95 − 1)·√2 − 100 = 32.9 units from the
    // ball, while its box overlaps the ball's for 100 updates.
    let mut overlapping = 0;
    for _ in 0..130 {
        s.step(1);
        overlapping += s.collision_stats().pairs;
    }
    assert!(overlapping >= 100, "the broad phase saw the pair {overlapping} times");
    let b = s.snapshot()[1];
    assert_eq!(b.velocity, Vec3::new(0.0, 0.0, -2.0), "never bounced");
    assert_eq!(b.position, Vec3::new(95.0, 95.0, 130.0 - 260.0));
}

/// A cube falling onto a ball off-center bounces off the surface: after the
/// update it touches the ball (discrete detection pushes it back there),
/// its velocity's normal part reversed and its tangential part kept (the
/// normal runs from the center to the cube's nearest point).
#[test]
fn a_cube_hitting_a_ball_bounces_off_its_surface() {
    let mut s = sim(
        "Scenario(gravitational_constant: 0, collision_detection: Discrete, bodies: [
        Body(position: (0, 0, 0), shape: Sphere(radius: 100), mass: 4000, role: Source, interacts: false),
        Body(position: (60, 82, 0), velocity: (0, -3, 0)),
    ])",
    );
    s.step(1);
    let b = s.snapshot()[1];
    let nearest = b.position - b.position.signum() * Vec3::ONE.min(b.position.abs());
    let distance = nearest.length();
    assert!((distance - 100.0).abs() < 1e-3, "touching: {distance}");
    let normal = nearest / distance;
    let before = Vec3::new(0.0, -3.0, 0.0);
    assert!(
        (b.velocity.dot(normal) + before.dot(normal)).abs() < 1e-5,
        "{}",
        b.velocity
    );
    let tangential = |v: Vec3| v - v.dot(normal) * normal;
    assert!((tangential(b.velocity) - tangential(before)).length() < 1e-5);
    assert!(
        b.velocity.y > 0.0 && b.velocity.x > 0.0,
        "up and outwards: {}",
        b.velocity
    );
    // And flies away without touching it again.
    s.step(20);
    assert_eq!(s.collision_stats().pairs, 0);
}

/// Cubes raining onto a moving moon from every side: both modes agree bit
/// for bit.
#[test]
fn balls_bounce_bit_identically_in_both_modes() {
    let text = "Scenario(bodies: [
        Body(position: (0, 0, 0), shape: Sphere(radius: 40), mass: 200, role: Source, interacts: false),
        Body(position: (150, 0, 0), velocity: (0, 0, -0.9), shape: Sphere(radius: 12), mass: 5, role: SourceAndAdopter, interacts: false),
    ], generators: [
        Cloud(count: 2000, center: (0, 0, 0), half_size: (180, 180, 180), max_speed: 1.0),
    ])";
    let scenario = Scenario::parse(text, "test").unwrap();
    let run = |mode, threads| {
        let mut s = Simulation::from_scenario(&scenario, Execution::new(mode, threads).unwrap()).unwrap();
        s.execution_mut().set_split(SplitPolicy::Always);
        let mut bounces = 0;
        for _ in 0..200 {
            s.step(1);
            bounces += s.collision_stats().responses;
        }
        (s.snapshot(), bounces)
    };
    let (sequential, bounces) = run(ExecutionMode::Sequential, 1);
    assert!(bounces > 100, "only {bounces} responses");
    let (parallel, _) = run(ExecutionMode::Parallel, 3);
    let bits = |b: &[BodyState]| -> Vec<(u64, [u32; 6])> {
        b.iter()
            .map(|b| {
                let (p, v) = (b.position, b.velocity);
                (b.id.0, [p.x, p.y, p.z, v.x, v.y, v.z].map(f32::to_bits))
            })
            .collect()
    };
    assert!(bits(&sequential) == bits(&parallel), "parallel differs");
}

/// What the panel's totals show: in a cloud without sources, bouncing and
/// shattering keep the total mass and momentum (to f32 rounding of each
/// body's state), while a shatter is inelastic: at the default spread
/// (fragments part at 0.2 of the impact speed) it loses kinetic energy.
#[test]
fn totals_keep_mass_and_momentum_through_a_cascade_without_sources() {
    let mut s = sim(
        "Scenario(gravitational_constant: 0, shatter_threshold: 1.0, generators: [
        Cloud(count: 3000, center: (0, 0, 0), half_size: (60, 60, 60), max_speed: 2.0),
    ])",
    );
    let before = s.totals();
    s.step(200);
    let after = s.totals();
    assert!(s.collision_stats().shatters_total > 100, "{:?}", s.collision_stats());
    assert!(
        after.bodies > before.bodies + 300,
        "{} -> {}",
        before.bodies,
        after.bodies
    );
    assert!(
        (after.mass - before.mass).abs() < 1e-9 * before.mass.max(1.0) + 1e-3,
        "{before:?} {after:?}"
    );
    let scale = before.kinetic_energy.sqrt() * (before.mass).sqrt();
    assert!(
        (after.momentum - before.momentum).length() < 1e-4 * scale,
        "momentum {} -> {}",
        before.momentum,
        after.momentum
    );
    assert!(after.kinetic_energy < before.kinetic_energy, "shatters are inelastic");
}

/// Two unit cubes meeting at 4 (threshold 3) would make five fragments of
/// edge 2·∛(2/5) = 1.47. Below a floor above that, or beyond a budget of
/// four bodies, they bounce instead (velocities swapped), and the refusal
/// is counted.
#[test]
fn shatters_below_the_size_floor_or_over_the_budget_bounce_and_are_counted() {
    let pair = |limits: &str| {
        let mut s = sim(&format!(
            "Scenario(gravitational_constant: 0, {limits} bodies: [
                Body(position: (-1.5, 0, 0), velocity: (2, 0, 0)),
                Body(position: (1.5, 0, 0), velocity: (-2, 0, 0)),
            ])"
        ));
        s.step(1);
        (s.collision_stats(), s.snapshot())
    };
    for limits in ["min_fragment_size: 1.5,", "max_bodies: 4,"] {
        let (stats, bodies) = pair(limits);
        assert_eq!(
            (stats.shatters, stats.refused_shatters, stats.refused_total),
            (0, 1, 1),
            "{limits}"
        );
        assert_eq!(bodies.len(), 2);
        assert_eq!(
            (bodies[0].velocity.x, bodies[1].velocity.x),
            (-2.0, 2.0),
            "{limits}: a bounce"
        );
    }
    for limits in ["min_fragment_size: 1.4,", "max_bodies: 5,", "min_fragment_size: 0,"] {
        let (stats, bodies) = pair(limits);
        assert_eq!((stats.shatters, stats.refused_shatters), (1, 0), "{limits}");
        assert_eq!(bodies.len(), 5, "{limits}");
    }
}

/// A collapsing cluster with the default floor: 300 unit cubes that fall
/// together and shatter in the crush. Every fragment keeps an edge of at
/// least the floor (1), so the volume, which shattering keeps, bounds the
/// count: at most 300·2³ bodies. The floor is what stops it: shatters are
/// refused long before the budget matters.
#[test]
fn a_collapse_with_the_default_floor_stays_within_its_volume_bound() {
    let mut s = sim("Scenario(softening: 1.0, gravity: Tree(theta: 0.5), generators: [
        Cloud(count: 300, center: (0, 0, 0), half_size: (40, 40, 40), max_speed: 0.5,
              body: (role: SourceAndAdopter)),
    ])");
    s.step(150);
    let (bodies, stats) = (s.snapshot(), s.collision_stats());
    assert!(stats.shatters_total > 100, "only {} shatters", stats.shatters_total);
    assert!(stats.refused_total > 100, "only {} refused", stats.refused_total);
    let edges = bodies.iter().map(|b| 2.0 * b.half_extents.min_element());
    assert!(edges.fold(f32::INFINITY, f32::min) >= 1.0, "a fragment under the floor");
    // Kept up to the rounding of each fragment's edge to f32.
    let volume: f64 = bodies
        .iter()
        .map(|b| 8.0 * b.half_extents.as_dvec3().element_product())
        .sum();
    assert!((volume / 2400.0 - 1.0).abs() < 1e-5, "volume {volume}");
    assert!(bodies.len() <= 2400, "{} bodies", bodies.len());
}

#[test]
fn a_fast_impact_shatters_keeping_mass_volume_and_momentum() {
    let mut s = sim("Scenario(gravitational_constant: 0, shatter_fragments: 6, bodies: [
        Body(position: (-1.5, 0, 0), velocity: (2.5, 0.5, 0), mass: 1.0),
        Body(position: (1.5, 0.2, 0), velocity: (-1.5, 0, 0), half_extents: (1, 2, 0.5), mass: 3.0),
    ])");
    let before = s.snapshot();
    s.step(1);
    let after = s.snapshot();
    assert_eq!(s.collision_stats().shatters, 1);
    assert_eq!(
        after.iter().map(|b| b.id).collect::<Vec<_>>(),
        (2..8).map(BodyId).collect::<Vec<_>>()
    );
    let mass: f32 = after.iter().map(|b| b.mass).sum();
    assert!((mass - 4.0).abs() < 1e-5);
    let volume: f32 = after
        .iter()
        .map(|b| b.half_extents.x * b.half_extents.y * b.half_extents.z)
        .sum();
    assert!((volume - 2.0).abs() < 1e-5, "half-extent volume {volume}");
    assert!((momentum(&after) - momentum(&before)).length() < 1e-5);
}

#[test]
fn below_the_threshold_nothing_shatters() {
    let mut s = sim("Scenario(gravitational_constant: 0, shatter_threshold: 3.0, bodies: [
        Body(position: (-1.5, 0, 0), velocity: (1.49, 0, 0)),
        Body(position: (1.5, 0, 0), velocity: (-1.49, 0, 0)),
    ])");
    s.step(1);
    assert_eq!(s.body_count(), 2);
    assert_eq!(s.collision_stats().shatters, 0);
    assert_eq!(s.collision_stats().responses, 1);
}

/// Body 1 at rest is met from both sides at the same moment (0.4 of the
/// update). Swept detection takes every contact in time order (ties in
/// pair order): 0 hands its velocity to 1, 1 meets 2 and takes its, 1
/// hands that back to 0: the outer two leave, the middle one rests, as the
/// elastic sequence ends.
#[test]
fn a_body_met_from_both_sides_at_once_hands_both_motions_on() {
    let mut s = sim("Scenario(gravitational_constant: 0, shatter_threshold: 100, bodies: [
        Body(position: (-2.2, 0, 0), velocity: (0.5, 0, 0)),
        Body(position: (0, 0, 0)),
        Body(position: (2.2, 0, 0), velocity: (-0.5, 0, 0)),
    ])");
    s.step(1);
    let stats = s.collision_stats();
    assert_eq!((stats.pairs, stats.responses), (2, 3));
    let b = s.snapshot();
    assert_eq!(b.iter().map(|b| b.velocity.x).collect::<Vec<_>>(), [-0.5, 0.0, 0.5]);
    assert!(b[1].position.x - b[0].position.x >= 2.0 - 1e-6, "apart: {b:?}");
    assert!(b[2].position.x - b[1].position.x >= 2.0 - 1e-6, "apart: {b:?}");
}

#[test]
fn each_body_responds_at_most_once_per_update_under_discrete_detection() {
    // Body 1 touches both 0 and 2; pair (0,1) goes first, (1,2) waits.
    let mut s = sim(
        "Scenario(gravitational_constant: 0, shatter_threshold: 100, collision_detection: Discrete, bodies: [
        Body(position: (-2.2, 0, 0), velocity: (0.5, 0, 0)),
        Body(position: (0, 0, 0)),
        Body(position: (2.2, 0, 0), velocity: (-0.5, 0, 0)),
    ])",
    );
    s.step(1);
    let stats = s.collision_stats();
    assert_eq!((stats.pairs, stats.responses), (2, 1));
    let b = s.snapshot();
    assert_eq!(b[0].velocity.x, 0.0, "0 handed its velocity to 1");
    assert_eq!(b[2].velocity.x, -0.5, "2 waits for the next update");
    // Update 2: 1 and 2 overlapped already at their previous positions, so
    // they are only separated (docs/design.md, "Response": velocities unchanged) ...
    s.step(1);
    let b = s.snapshot();
    assert_eq!((b[1].velocity.x, b[2].velocity.x), (0.5, -0.5));
    assert!(b[2].position.x - b[1].position.x >= 2.0 - 1e-6, "separated: {b:?}");
    // ... and update 3, meeting from a touching position, they bounce.
    s.step(1);
    let b = s.snapshot();
    assert_eq!((b[1].velocity.x, b[2].velocity.x), (-0.5, 0.5));
}

fn dump(
    scenario: &str,
    (mode, threads, split): (&str, &str, &str),
    updates: &str,
    dir: &std::path::Path,
) -> (Vec<u8>, String) {
    let path = dir.join(format!("{mode}-{threads}-{split}.csv"));
    let scenario = format!("{}/scenarios/{scenario}", env!("CARGO_MANIFEST_DIR"));
    // Blind to the user's files: no calibration of this machine, so `auto`
    // uses the fallback.
    let out = kessler()
        .args([
            "headless",
            &scenario,
            "--steps",
            updates,
            "--mode",
            mode,
            "--threads",
            threads,
            "--split",
            split,
            "--dump",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (std::fs::read(&path).unwrap(), String::from_utf8(out.stdout).unwrap())
}

fn shatters(summary: &str) -> u64 {
    let before = summary.split(" shatters").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap()
}

/// Returns the sequential run's summary.
fn assert_dumps_identical(scenario: &str, min_shatters: u64) -> String {
    let dir = tempfile::tempdir().unwrap();
    let (sequential, summary) = dump(scenario, ("sequential", "1", "auto"), "300", dir.path());
    assert!(
        shatters(&summary) >= min_shatters,
        "too little shattering to prove anything: {summary}"
    );
    let parallel = [
        ("1", "always"),
        ("2", "always"),
        ("3", "always"),
        ("2", "auto"),
        ("2", "1000"),
    ];
    for (threads, split) in parallel {
        let (dumped, _) = dump(scenario, ("parallel", threads, split), "300", dir.path());
        assert!(
            sequential == dumped,
            "{scenario}: parallel on {threads} threads, split {split}, differs from sequential"
        );
    }
    summary
}

/// The thesis scene (10 000 cubes), 300 updates: byte-identical dumps.
#[test]
fn thesis_cloud_dumps_are_identical_in_both_modes() {
    assert_dumps_identical("thesis_cloud.ron", 1);
}

/// 3000 cubes with thousands of shatters: byte-identical dumps; and no
/// contact left for the next update at swept detection's bound (the
/// summary would count them: docs/design.md, "Contacts in time order").
#[test]
fn cascade_dumps_are_identical_in_both_modes() {
    let summary = assert_dumps_identical("cascade.ron", 1000);
    assert!(!summary.contains("deferred"), "{summary}");
}

/// Split policies that split some stages and not others, at body counts
/// that change as the cascade shatters: the state matches sequential bit
/// for bit.
#[test]
fn cascade_is_bit_identical_under_every_split_policy() {
    let scenario = Scenario::load(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/cascade.ron").as_ref()).unwrap();
    let run = |execution: Execution| {
        let mut s = Simulation::from_scenario(&scenario, execution).unwrap();
        s.step(100);
        s.snapshot()
    };
    let bits = |bodies: Vec<BodyState>| -> Vec<(u64, [u32; 3], [u32; 3])> {
        bodies
            .iter()
            .map(|x| {
                (
                    x.id.0,
                    x.position.to_array().map(f32::to_bits),
                    x.velocity.to_array().map(f32::to_bits),
                )
            })
            .collect()
    };
    let sequential = bits(run(Execution::new(ExecutionMode::Sequential, 1).unwrap()));
    let calibrated = AutoSplit::calibrated(
        vec![("gravity".into(), 0), ("sort".into(), 3500), ("response".into(), 1)],
        "test",
    );
    for split in [SplitPolicy::Always, SplitPolicy::Above(3500), SplitPolicy::Auto] {
        let execution = Execution::new(ExecutionMode::Parallel, 2)
            .unwrap()
            .with_split(split)
            .with_auto_split(calibrated.clone());
        assert!(
            bits(run(execution)) == sequential,
            "split {split} differs from sequential"
        );
    }
}

/// Every kernel split into many small chunks (not just the large inputs):
/// the cascade's state still matches sequential bit for bit.
#[test]
fn cascade_is_bit_identical_with_every_kernel_split() {
    let scenario = Scenario::load(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/cascade.ron").as_ref()).unwrap();
    let run = |execution: Execution| {
        let mut s = Simulation::from_scenario(&scenario, execution).unwrap();
        s.step(150);
        (s.snapshot(), s.collision_stats().shatters_total)
    };
    let (sequential, shattered) = run(Execution::new(ExecutionMode::Sequential, 1).unwrap());
    assert!(shattered > 100, "only {shattered} shatters");
    let (parallel, _) = run(Execution::new(ExecutionMode::Parallel, 3).unwrap().fine_grained());
    assert_eq!(sequential.len(), parallel.len());
    for (a, b) in sequential.iter().zip(&parallel) {
        let bits = |x: &BodyState| {
            (
                x.id,
                x.position.to_array().map(f32::to_bits),
                x.velocity.to_array().map(f32::to_bits),
            )
        };
        assert_eq!(bits(a), bits(b));
    }
}

/// Runs `kessler headless` with `args`; panics unless it succeeds. Returns
/// stdout.
fn headless(args: &[&str]) -> String {
    let out = kessler().arg("headless").args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// A snapshot continues its run exactly: 120 updates of the cascade at
/// once give the same dump, byte for byte, as 60 updates, a snapshot, and
/// 60 more from it — in both modes, with shattering before and after the
/// snapshot (fragments keep getting the same fresh ids).
#[test]
fn a_snapshot_continues_the_cascade_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = format!("{}/scenarios/cascade.ron", env!("CARGO_MANIFEST_DIR"));
    for (mode, split) in [("sequential", "auto"), ("parallel", "always")] {
        let path = |name: &str| dir.path().join(format!("{mode}-{name}")).display().to_string();
        let run = |from: &str, steps: &str, extra: &[&str]| {
            let mut args = vec![
                from,
                "--steps",
                steps,
                "--mode",
                mode,
                "--threads",
                "2",
                "--split",
                split,
            ];
            args.extend_from_slice(extra);
            headless(&args)
        };
        let whole = run(&scenario, "120", &["--dump", &path("whole.csv")]);
        let first = run(&scenario, "60", &["--save-scenario", &path("snapshot.ron")]);
        let second = run(&path("snapshot.ron"), "60", &["--dump", &path("continued.csv")]);
        assert!(
            shatters(&first) > 100 && shatters(&whole) > shatters(&first),
            "shattering before and after the snapshot: {first} / {whole}"
        );
        assert!(
            second.contains("Cascade"),
            "the snapshot keeps the scenario's name: {second}"
        );
        let (whole, continued) = (
            std::fs::read(path("whole.csv")).unwrap(),
            std::fs::read(path("continued.csv")).unwrap(),
        );
        assert!(
            whole == continued,
            "{mode}: the continued run differs from the whole run"
        );
    }
}

/// The default scene's planet and moon are balls, and its cubes have
/// moved: a snapshot keeps their shape, holds no previous position (every
/// update's drift sets it before anything reads it), and continuing from
/// it is exact in both modes.
#[test]
fn a_snapshot_of_the_default_scene_keeps_balls_and_continues_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = format!("{}/scenarios/debris_orbit.ron", env!("CARGO_MANIFEST_DIR"));
    for mode in ["sequential", "parallel"] {
        let path = |name: &str| dir.path().join(format!("{mode}-{name}")).display().to_string();
        let run = |from: &str, steps: &str, extra: &[&str]| {
            let mut args = vec![from, "--steps", steps, "--mode", mode, "--split", "always"];
            args.extend_from_slice(extra);
            headless(&args)
        };
        run(&scenario, "80", &["--dump", &path("whole.csv")]);
        run(&scenario, "40", &["--save-scenario", &path("snapshot.ron")]);
        let text = std::fs::read_to_string(path("snapshot.ron")).unwrap();
        assert!(
            text.contains("shape: Sphere(radius: 430.0)") && text.contains("shape: Sphere(radius: 60.0)"),
            "the planet and the moon stay balls"
        );
        let bodies = text.matches("Body(id: ").count();
        assert!(bodies >= 20_000, "{bodies} bodies");
        assert_eq!(
            text.matches("previous_position").count(),
            0,
            "no previous position: the state between two updates does not hold it"
        );
        run(&path("snapshot.ron"), "40", &["--dump", &path("continued.csv")]);
        assert!(
            std::fs::read(path("whole.csv")).unwrap() == std::fs::read(path("continued.csv")).unwrap(),
            "{mode}: the continued run differs from the whole run"
        );
    }
}

/// Runs `text` headless for `steps` updates through the binary, saving its
/// last state as a snapshot that `kessler validate` must accept, and
/// returns the summary and the bodies' masses and smallest half-edges.
fn run_and_validate(text: &str, steps: &str) -> (String, Vec<(f32, f32)>) {
    let dir = tempfile::tempdir().unwrap();
    let (scene, dump, saved) = (
        dir.path().join("s.ron"),
        dir.path().join("d.csv"),
        dir.path().join("saved.ron"),
    );
    std::fs::write(&scene, text).unwrap();
    let out = kessler()
        .arg("headless")
        .arg(&scene)
        .args(["--steps", steps, "--dump"])
        .arg(&dump)
        .arg("--save-scenario")
        .arg(&saved)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let validated = kessler().arg("validate").arg(&saved).output().unwrap();
    assert!(
        validated.status.success(),
        "the snapshot is refused: {}",
        String::from_utf8_lossy(&validated.stderr)
    );
    let bodies = std::fs::read_to_string(&dump)
        .unwrap()
        .lines()
        .skip(1)
        .map(|line| {
            let c: Vec<f32> = line.split(',').skip(7).take(4).map(|x| x.parse().unwrap()).collect();
            (c[0], c[1].min(c[2]).min(c[3]))
        })
        .collect();
    (String::from_utf8(out.stdout).unwrap(), bodies)
}

/// Accepted settings make no body a file may not hold: power-law fragments
/// with a floor far below the bodies' size (or an exponent that overflows
/// the law's powers), and breakups into 1 000 repeated until the pieces are
/// lighter than an `f32` holds, each give bodies of finite, positive mass
/// and size, and a snapshot `validate` accepts.
#[test]
fn no_valid_input_makes_a_body_without_mass_or_size() {
    let sound = |bodies: &[(f32, f32)], what: &str| {
        for &(mass, half) in bodies {
            assert!(
                mass.is_normal() && half.is_normal() && mass > 0.0 && half > 0.0,
                "{what}: mass {mass}, half-edge {half}"
            );
        }
    };
    for (floor, exponent) in [("1e-15", "1.71"), ("1e-30", "1.71"), ("1e-38", "10"), ("0", "0.01")] {
        let text = format!(
            "Scenario(gravitational_constant: 0, shatter_fragments: 1000, max_bodies: 100000,
                fragment_sizes: PowerLaw(exponent: {exponent}), min_fragment_size: {floor}, bodies: [
                Body(position: (-10, 0, 0), velocity: (20, 0, 0), mass: 1e-20),
                Body(position: (10, 0, 0), velocity: (-20, 0, 0), half_extents: (4, 4, 4)),
            ])"
        );
        let (summary, bodies) = run_and_validate(&text, "3");
        assert!(
            bodies.len() > 2,
            "floor {floor}, exponent {exponent}: no shatter: {summary}"
        );
        sound(&bodies, &format!("floor {floor}, exponent {exponent}"));
    }
    // Breakups into 1000, each of the last fragment of the one before:
    // the mass falls a thousandfold a time, from 1e-30 to below the
    // smallest normal f32 at the third, which is skipped (and the fourth,
    // whose body is not there).
    let breakups: Vec<String> = (0..4)
        .map(|k| {
            format!(
                "Breakup(update: {}, body: {}, fragments: 1000, speed: 0.01)",
                k + 1,
                1000 * k
            )
        })
        .collect();
    let text = format!(
        "Scenario(gravitational_constant: 0, min_fragment_size: 0, max_bodies: 100000,
            bodies: [Body(position: (0, 0, 0), mass: 1e-30, half_extents: (1, 1, 1))],
            events: [{}])",
        breakups.join(", ")
    );
    let (summary, bodies) = run_and_validate(&text, "6");
    assert_eq!(bodies.len(), 1 + 999 + 999, "{summary}");
    sound(&bodies, "breakups");
}
