//! Swept collision detection through the whole simulation, against
//! analytic outcomes: pairs that meet between two updates' ends collide
//! at the time they touch, pairs whose paths only come near do not, and a
//! crossing-rings scene at the thesis's step finds the collisions a much
//! finer step finds.

mod common {
    pub mod simulation;
}

use bevy::math::{DVec3, Vec3};
use common::simulation::sim;
use kessler::components::BodyState;
use kessler::maths;

fn momentum(bodies: &[BodyState]) -> DVec3 {
    bodies.iter().map(|b| b.velocity.as_dvec3() * f64::from(b.mass)).sum()
}

fn energy(bodies: &[BodyState]) -> f64 {
    bodies
        .iter()
        .map(|b| 0.5 * f64::from(b.mass) * b.velocity.as_dvec3().length_squared())
        .sum()
}

/// Two unit cubes 11 apart, each at 10 units an update (no gravity, no
/// shattering): discrete detection never sees them overlap and they swap
/// sides untouched; swept detection finds them touching at 9/20 of the
/// first update and bounces them: velocities exchanged, each back on its
/// own side, 13 apart after it (−6.5 and 6.5).
#[test]
fn a_head_on_pair_bounces_instead_of_passing_through() {
    let scene = |detection: &str| {
        sim(&format!(
            "Scenario(gravitational_constant: 0, shatter_threshold: 1000, collision_detection: {detection}, bodies: [
                Body(position: (-5.5, 0, 0), velocity: (10, 0, 0)),
                Body(position: (5.5, 0, 0), velocity: (-10, 0, 0)),
            ])"
        ))
    };
    let mut discrete = scene("Discrete");
    discrete.step(3);
    let b = discrete.snapshot();
    assert_eq!((b[0].position.x, b[0].velocity.x), (24.5, 10.0), "passed through");
    let mut swept = scene("Swept");
    swept.step(1);
    let b = swept.snapshot();
    assert_eq!(swept.collision_stats().responses, 1);
    assert_eq!((b[0].velocity.x, b[1].velocity.x), (-10.0, 10.0));
    // Touching at x = ∓1 after 0.45, then apart at 10 each for 0.55.
    assert!(
        (b[0].position.x + 6.5).abs() < 1e-5 && (b[1].position.x - 6.5).abs() < 1e-5,
        "{b:?}"
    );
    swept.step(2);
    let b = swept.snapshot();
    assert!(
        b[0].position.x < -26.0 && b[1].position.x > 26.0,
        "each on its own side: {b:?}"
    );
}

/// Two cubes crossing at right angles, meeting between two updates'
/// ends: a bounce on the axis that closed last, momentum kept exactly and
/// kinetic energy to rounding.
#[test]
fn a_right_angle_crossing_collides_between_updates() {
    let mut s = sim("Scenario(gravitational_constant: 0, shatter_threshold: 1000, bodies: [
            Body(position: (-6, 0.5, 0), velocity: (12, 0, 0), mass: 1),
            Body(position: (0, -6, 0), velocity: (0, 12, 0), mass: 3),
        ])");
    let before = s.snapshot();
    s.step(1);
    let after = s.snapshot();
    assert_eq!(s.collision_stats().responses, 1, "they met");
    assert_ne!(after[0].velocity.y, 0.0, "the bounce is on y, which closed last");
    assert_eq!(after[0].velocity.x, 12.0, "x kept");
    assert_eq!(momentum(&after), momentum(&before));
    let (e0, e1) = (energy(&before), energy(&after));
    assert!(((e1 - e0) / e0).abs() < 1e-6, "energy {e0} then {e1}");
    // Apart at the end, each on the side it came from (18 and 6 on y).
    assert!(after[0].position.y - after[1].position.y > 2.0, "{after:?}");
}

/// Paths that come near but never touch: a passes the crossing before b
/// arrives. Their swept boxes overlap (a pair for the broad phase), but no
/// collision is made of it.
#[test]
fn a_near_miss_is_no_collision() {
    let mut s = sim("Scenario(gravitational_constant: 0, bodies: [
            Body(position: (-10, 0, 0), velocity: (20, 0, 0)),
            Body(position: (0, -16, 0), velocity: (0, 20, 0)),
        ])");
    s.step(1);
    assert_eq!(s.collision_stats().pairs, 1, "the swept boxes overlap");
    assert_eq!(s.collision_stats().responses + s.collision_stats().shatters, 0);
    let b = s.snapshot();
    assert_eq!(
        (b[0].position, b[1].position),
        (Vec3::new(10.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0))
    );
}

/// Ten targets at rest, each with an impactor 6 units off that passes
/// right through it within one update (12 an update): every one hits.
#[test]
fn every_impactor_of_a_stream_hits_its_target() {
    let bodies: Vec<String> = (0..10)
        .flat_map(|k| {
            let y = 10 * k;
            [
                format!("Body(position: (0, {y}, 0))"),
                format!("Body(position: (-6, {y}, 0.3), velocity: (12, 0, 0))"),
            ]
        })
        .collect();
    let mut s = sim(&format!(
        "Scenario(gravitational_constant: 0, shatter_threshold: 1000, bodies: [{}])",
        bodies.join(", ")
    ));
    s.step(1);
    assert_eq!(s.collision_stats().responses, 10);
    // Equal masses head-on on x: each target took its impactor's speed.
    for pair in s.snapshot().chunks(2) {
        assert_eq!((pair[0].velocity.x, pair[1].velocity.x), (12.0, 0.0), "{pair:?}");
        assert!(pair[1].position.x < pair[0].position.x - 2.0, "{pair:?}");
    }
}

/// A cube at 50 units an update towards a planet of radius 20 (a ball),
/// which it would cross between two updates' ends: it bounces off the
/// surface and never enters the ball.
#[test]
fn a_fast_cube_does_not_tunnel_into_a_planet() {
    let mut s = sim("Scenario(gravitational_constant: 0, bodies: [
            Body(position: (0, 0, 0), shape: Sphere(radius: 20), mass: 1000, role: Source, interacts: false),
            Body(position: (-30, 0, 0), velocity: (50, 0, 0)),
        ])");
    for _ in 0..4 {
        s.step(1);
        let cube = s.snapshot()[1];
        assert!(cube.position.x < -21.0, "outside the ball: {}", cube.position);
    }
    assert_eq!(s.snapshot()[1].velocity, Vec3::new(-50.0, 0.0, 0.0));
}

/// Two rings of 100 unit cubes on circular orbits of radius 200 at 5 units
/// an update (`dt` = 1), one in the x–y plane, one in the x–z plane, so
/// they cross at right angles twice an orbit (an orbit is about 251 time
/// units), the second ring `phase` of a spacing on; no shattering. Around
/// a point mass, or with `planet` around a ball of radius 100 that absorbs
/// what reaches it. At time step `dt` with `detection`.
fn crossing_rings(dt: f64, detection: &str, phase: f64, planet: bool) -> String {
    let (radius, speed) = (200.0f64, 5.0f64);
    let mass = speed * speed * radius / 6.674;
    let ball = if planet {
        ", shape: Sphere(radius: 100), absorbs: true"
    } else {
        ""
    };
    let mut bodies = vec![format!(
        "Body(position: (0, 0, 0), mass: {mass}, role: Source, interacts: false{ball})"
    )];
    for k in 0..100 {
        let a = std::f64::consts::TAU * f64::from(k) / 100.0;
        let (s, c) = maths::sin_cos(a);
        bodies.push(format!(
            "Body(position: ({}, {}, 0), velocity: ({}, {}, 0))",
            radius * c,
            radius * s,
            -speed * s,
            speed * c
        ));
        // The second ring `phase` of a spacing on.
        let (s, c) = maths::sin_cos(a + phase * std::f64::consts::TAU / 100.0);
        bodies.push(format!(
            "Body(position: ({}, 0, {}), velocity: ({}, 0, {}))",
            radius * c,
            radius * s,
            -speed * s,
            speed * c
        ));
    }
    format!(
        "Scenario(time_step: {dt}, shatter_threshold: 1000, collision_detection: {detection}, bodies: [{}])",
        bodies.join(", ")
    )
}

/// How many cubes of the crossing rings around a point mass
/// ([`crossing_rings`]) `time` time units leave more than a unit from
/// where they would be without collisions.
fn deflected_by_crossing_rings(dt: f64, detection: &str, phase: f64, time: f64) -> usize {
    let text = crossing_rings(dt, detection, phase, false);
    let updates = (time / dt).round() as u64;
    let mut colliding = sim(&text);
    let mut free = sim(&text);
    free.settings_mut().stages.collisions = false;
    colliding.step(updates);
    free.step(updates);
    let (with, without) = (colliding.snapshot(), free.snapshot());
    assert_eq!(with.len(), 201);
    with.iter()
        .zip(&without)
        .skip(1)
        .filter(|(a, b)| a.position.distance(b.position) > 1.0)
        .count()
}

/// How many contacts (bounces) the crossing rings around the absorbing
/// planet ([`crossing_rings`]) make in `time` time units: a count that
/// does not saturate, as the deflected cubes do over an orbit (each cube
/// is struck several times).
fn contacts_of_crossing_rings(dt: f64, detection: &str, phase: f64, time: f64) -> u64 {
    let mut rings = sim(&crossing_rings(dt, detection, phase, true));
    let mut contacts = 0;
    for _ in 0..(time / dt).round() as u64 {
        rings.step(1);
        contacts += rings.collision_stats().responses as u64;
    }
    contacts
}

/// Swept detection at the thesis's step finds the crossings a step 64
/// times finer finds (where nothing can pass unseen), within 10 %, over
/// the rings' first crossing (60 time units), where the counts stay well
/// below the 200 cubes: for the second ring 0, 0.15, 0.3 and 0.85 of a
/// spacing on (from 0.35 to 0.65 of a spacing on, the cubes pass between
/// one another: none meets). Discrete detection at the thesis's step
/// misses most where the cubes meet off-center.
#[test]
fn crossing_rings_at_the_thesis_step_collide_as_at_a_fine_step() {
    for phase in [0.0, 0.15, 0.3, 0.85] {
        let reference = deflected_by_crossing_rings(1.0 / 64.0, "Discrete", phase, 60.0);
        let swept = deflected_by_crossing_rings(1.0, "Swept", phase, 60.0);
        assert!(
            (80..=150).contains(&reference),
            "phase {phase}: the reference deflects {reference}"
        );
        let error = (swept as f64 - reference as f64).abs() / reference as f64;
        assert!(
            error <= 0.10,
            "phase {phase}: swept at dt = 1 deflects {swept}, the reference {reference}"
        );
    }
    let reference = deflected_by_crossing_rings(1.0 / 64.0, "Discrete", 0.3, 60.0);
    let discrete = deflected_by_crossing_rings(1.0, "Discrete", 0.3, 60.0);
    assert!(
        discrete < reference / 2,
        "discrete at dt = 1: {discrete}, the reference {reference}"
    );
    assert_eq!(
        deflected_by_crossing_rings(1.0, "Swept", 0.5, 260.0),
        0,
        "no false contacts"
    );
}

/// Over a whole orbit nearly every cube is deflected, so the deflected
/// count saturates; the contacts do not. Around a planet that absorbs what
/// reaches it (around a bare point mass, cubes knocked onto plunging orbits
/// pass the singular center, where `dt = 1` integrates them poorly and
/// they come back fast: that is the integrator's error, not the
/// contacts'), swept detection at the thesis's step makes within 10 % of
/// the contacts a step 64 times finer makes, at the 12 phases where the
/// rings meet off-center (0.05–0.3 and 0.7–0.95 of a spacing; at 0 they
/// meet squarely, once each; between, not at all); discrete detection at
/// the thesis's step makes fewer than a fifth of them.
#[test]
fn crossing_rings_around_a_planet_meet_over_an_orbit_as_at_a_fine_step() {
    for phase in [0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95] {
        let reference = contacts_of_crossing_rings(1.0 / 64.0, "Discrete", phase, 251.0);
        let swept = contacts_of_crossing_rings(1.0, "Swept", phase, 251.0);
        let discrete = contacts_of_crossing_rings(1.0, "Discrete", phase, 251.0);
        assert!(
            reference > 400,
            "phase {phase}: the reference makes {reference} contacts"
        );
        let error = (swept as f64 - reference as f64).abs() / reference as f64;
        assert!(
            error <= 0.10,
            "phase {phase}: swept at dt = 1 makes {swept} contacts, the reference {reference}"
        );
        assert!(
            discrete * 5 < reference,
            "phase {phase}: discrete at dt = 1 makes {discrete} contacts, the reference {reference}"
        );
    }
}

/// The window's Fire tool at every speed its panel offers (0.1 to 100 an
/// update) still hits its target: one shatter (any hit shatters here),
/// the target gone.
#[test]
fn a_fired_impactor_hits_at_any_speed_the_panel_allows() {
    for speed in [0.1f32, 1.0, 8.0, 30.0, 100.0] {
        let distance = 40.0;
        let updates = (distance / speed).ceil() as u64 + 3;
        let mut s = sim(&format!(
            "Scenario(gravitational_constant: 0, shatter_threshold: 0, bodies: [Body(position: (0, 0, 0))],
                events: [Fire(update: 1, target: 0, speed: {speed}, distance: {distance}, from: (0.6, 0, 0.8))])"
        ));
        s.step(1 + updates);
        assert_eq!(s.collision_stats().shatters_total, 1, "speed {speed}");
        assert!(
            s.snapshot().iter().all(|b| b.id.0 != 0),
            "speed {speed}: the target shattered"
        );
    }
}

/// An impactor fired through a body that lies in its way meets that body
/// first; found only where updates end, it passed through it and hit its
/// target, placed so that an update ends inside it.
#[test]
fn a_fired_impactor_meets_what_lies_in_its_way() {
    for (detection, shattered) in [("Swept", 1), ("Discrete", 0)] {
        // The impactor starts 100 off on −x at 50 an update; the obstacle
        // lies 37 short of the target, passed during the third update
        // (the impactor joins the world after the first).
        let mut s = sim(&format!(
            "Scenario(gravitational_constant: 0, collision_detection: {detection}, bodies: [
                Body(position: (0, 0, 0)),
                Body(position: (-37, 0, 0)),
            ], events: [Fire(update: 1, target: 0, speed: 50, distance: 100, from: (-1, 0, 0))])"
        ));
        s.step(3);
        let left: Vec<u64> = s.snapshot().iter().map(|b| b.id.0).filter(|&id| id < 2).collect();
        assert_eq!(s.collision_stats().shatters_total, 1, "{detection}");
        assert_eq!(left, [1 - shattered], "{detection}: the body left whole");
    }
}

/// The scene of equal or given cubes on the x axis (G = 0, no shatters),
/// one update of `dt` = 1 under `detection`: each body's (x, vx) after it.
fn row(detection: &str, bodies: &[(f32, f32, f32)]) -> Vec<(f32, f32)> {
    let listed: Vec<String> = bodies
        .iter()
        .map(|(x, v, m)| format!("Body(position: ({x}, 0, 0), velocity: ({v}, 0, 0), mass: {m})"))
        .collect();
    let mut s = sim(&format!(
        "Scenario(gravitational_constant: 0, shatter_threshold: 1000, collision_detection: {detection}, bodies: [{}])",
        listed.join(", ")
    ));
    s.step(1);
    s.snapshot().iter().map(|b| (b.position.x, b.velocity.x)).collect()
}

fn assert_row(got: &[(f32, f32)], expected: &[(f32, f32)]) {
    for (k, (g, e)) in got.iter().zip(expected).enumerate() {
        assert!(
            (g.0 - e.0).abs() < 1e-4 && (g.1 - e.1).abs() < 1e-4,
            "body {k}: got {g:?}, expected {e:?} (all: {got:?})"
        );
    }
}

/// A Newton's cradle of three unit cubes: A at 0 moving at 10 an update,
/// B at 4 and C at 6.5 at rest. A touches B at 0.2 of the update and
/// stops there (x = 2); B moves on, touches C at 0.25 and stops (4.5); C
/// moves on at 10 for the rest: 6.5 + 7.5 = 14. B no longer passes
/// through C.
#[test]
fn a_cradle_of_three_ends_as_the_elastic_sequence_does() {
    let got = row("Swept", &[(0.0, 10.0, 1.0), (4.0, 0.0, 1.0), (6.5, 0.0, 1.0)]);
    assert_row(&got, &[(2.0, 0.0), (4.5, 0.0), (14.0, 10.0)]);
}

/// A chain of five equal cubes 0.5 apart (faces), the first at 10 an
/// update: each stops where it touched the next, 0.05 of the update
/// later each, and the last moves on from 0.25: 10.5 + 7.5 = 18.
#[test]
fn a_chain_of_five_passes_the_motion_to_the_last() {
    let got = row(
        "Swept",
        &[
            (0.0, 10.0, 1.0),
            (3.0, 0.0, 1.0),
            (5.5, 0.0, 1.0),
            (8.0, 0.0, 1.0),
            (10.5, 0.0, 1.0),
        ],
    );
    assert_row(&got, &[(1.0, 0.0), (3.5, 0.0), (6.0, 0.0), (8.5, 0.0), (18.0, 10.0)]);
}

/// Unequal masses 1, 2, 3: A (at 0, 10 an update) touches B at 0.2 and
/// rebounds at −10/3 while B leaves at 20/3; B touches C 0.075 later and
/// rebounds at −4/3 while C leaves at 16/3. Momentum and energy are kept
/// to rounding and the bodies stay in their order, apart.
#[test]
fn a_chain_of_unequal_masses_keeps_momentum_energy_and_order() {
    let bodies = [(0.0, 10.0, 1.0), (4.0, 0.0, 2.0), (6.5, 0.0, 3.0)];
    let got = row("Swept", &bodies);
    let expected = [
        (2.0 - 10.0 / 3.0 * 0.8, -10.0 / 3.0),
        (4.5 - 4.0 / 3.0 * 0.725, -4.0 / 3.0),
        (6.5 + 16.0 / 3.0 * 0.725, 16.0 / 3.0),
    ];
    assert_row(&got, &expected);
    let sum = |f: &dyn Fn(f64, f64) -> f64| -> f64 {
        got.iter()
            .zip(&bodies)
            .map(|((_, v), (_, _, m))| f(f64::from(*m), f64::from(*v)))
            .sum()
    };
    assert!((sum(&|m, v| m * v) - 10.0).abs() < 1e-5, "momentum");
    assert!((sum(&|m, v| 0.5 * m * v * v) - 50.0).abs() < 1e-4, "energy");
    assert!(
        got[0].0 + 2.0 <= got[1].0 && got[1].0 + 2.0 <= got[2].0,
        "in order, apart: {got:?}"
    );
}

/// B at rest between A (coming from the left) and C (from the right) is
/// struck by A, then by C, then meets A again, all in one update: A ends
/// at −2 moving left, B at rest at 5, C at 14 moving right.
#[test]
fn a_body_struck_twice_in_one_update_meets_each_in_turn() {
    let got = row("Swept", &[(0.0, 10.0, 1.0), (5.0, 0.0, 1.0), (12.0, -10.0, 1.0)]);
    assert_row(&got, &[(-2.0, -10.0), (5.0, 0.0), (14.0, 10.0)]);
}

/// A cube turned twice in one update, by a wall and then by a ceiling
/// (walls of mass 10⁹, taking no part in collisions between themselves),
/// comes back below its first turn, where a small cube rests that neither
/// its first path's box nor its second's overlaps, though the box around
/// both does: its third path meets that cube (at 14/15 of the update),
/// passes it its downward speed, and neither ends inside the other.
#[test]
fn a_body_turned_twice_meets_what_lies_beside_its_earlier_paths() {
    let mut s = sim("Scenario(gravitational_constant: 0, shatter_threshold: 1000, bodies: [
            Body(position: (0, 0, 0), velocity: (10, 10, 0), half_extents: (0.5, 0.5, 0.5)),
            Body(position: (11.5, 0, 0), half_extents: (8, 50, 5), mass: 1e9, interacts: false),
            Body(position: (-11.8, 16.5, 0), half_extents: (15.2, 10, 5), mass: 1e9, interacts: false),
            Body(position: (-3.5, 1.9, 0), half_extents: (0.3, 0.3, 0.3)),
        ])");
    s.step(1);
    let got = s.snapshot();
    let (cube, resting) = (&got[0], &got[3]);
    let apart = (cube.position - resting.position).abs() - (cube.half_extents + resting.half_extents);
    assert!(
        apart.max_element() >= -1e-4,
        "the cube ends inside the resting one: {got:?}"
    );
    assert!(resting.velocity.y < -1.0, "the resting cube was struck: {got:?}");
    assert!((cube.velocity.x + 10.0).abs() < 1e-4, "{got:?}");
}

/// Two cubes overlapping where the update starts and moving apart part
/// freely under both detections, on every axis and on a diagonal, fast
/// (apart at the update's end) or slowly (still overlapping then).
#[test]
fn overlapping_pairs_that_move_apart_part_freely() {
    let directions = [
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::ONE.normalize(),
        Vec3::new(1.0, -1.0, 0.5).normalize(),
    ];
    for detection in ["Swept", "Discrete"] {
        for direction in directions {
            for (apart, speed) in [(1.5, 2.5), (1.0, 0.2)] {
                let (a, b) = (Vec3::ZERO, direction * apart);
                let v = direction * speed;
                let mut s = sim(&format!(
                    "Scenario(gravitational_constant: 0, shatter_threshold: 1000, collision_detection: {detection}, bodies: [
                        Body(position: ({}, {}, {}), velocity: ({}, {}, {})),
                        Body(position: ({}, {}, {}), velocity: ({}, {}, {})),
                    ])",
                    a.x, a.y, a.z, -v.x, -v.y, -v.z, b.x, b.y, b.z, v.x, v.y, v.z
                ));
                s.step(1);
                let got = s.snapshot();
                let case = format!("{detection}, {direction}, {apart} apart at {speed}");
                assert!((got[0].position - (a - v)).length() < 1e-5, "{case}: {got:?}");
                assert!((got[1].position - (b + v)).length() < 1e-5, "{case}: {got:?}");
                assert_eq!((got[0].velocity, got[1].velocity), (-v, v), "{case}");
            }
        }
    }
}

/// Fast bodies far apart: 2 600 cubes about 70 apart, each moving up to
/// 20 000 an update, so that their swept boxes overlap in more pairs than
/// the pile-up limit (2²⁰ here) while the bodies where the update ends
/// overlap in none. Swept detection grows its pairs' storage and runs on.
/// (Bodies really piled up still stop the run: tests/bad_input.rs.)
#[test]
fn long_swept_boxes_are_no_pile_up() {
    let mut fast = sim(
        "Scenario(gravitational_constant: 0, shatter_threshold: 1e9, generators: [
            Cloud(count: 2600, center: (0, 0, 0), half_size: (500, 500, 500), max_speed: 20000),
        ])",
    );
    fast.step(1);
    assert_eq!(fast.fault(), None);
    let pairs = fast.collision_stats().pairs;
    assert!(pairs > 1 << 20, "{pairs} pairs: past the pile-up limit");
}

/// Two cubes meeting head on at 10 (past `shatter_threshold` 5) while both
/// fall at 20 an update towards a slab at `slab_z` (an immovable body),
/// and `third`, after one update.
fn shatter_above_sim(slab_z: f32, third: &str) -> kessler::Simulation {
    let mut s = sim(&format!(
        "Scenario(gravitational_constant: 0, shatter_threshold: 5, shatter_fragments: 4, min_fragment_size: 0, bodies: [
            Body(position: (-2.5, 0, 11), velocity: (5, 0, -20)),
            Body(position: (2.5, 0, 11), velocity: (-5, 0, -20)),
            Body(position: (0, 0, {slab_z}), half_extents: (30, 30, 1), mass: 1000, interacts: false),
            {third}
        ])"
    ));
    s.step(1);
    s
}

/// The bodies and the collision counts after [`shatter_above_sim`].
fn shatter_above(slab_z: f32, third: &str) -> (Vec<BodyState>, kessler::systems::CollisionStats) {
    let mut s = shatter_above_sim(slab_z, third);
    (s.snapshot(), s.collision_stats())
}

fn overlaps(a: &BodyState, b: &BodyState) -> bool {
    ((a.position - b.position).abs() - (a.half_extents + b.half_extents)).max_element() < 0.0
}

/// A pair that shatters in mid-update above an immovable slab: its
/// fragments, made where the pair met (3/10 of the update in), move on for
/// the rest of it and meet the slab on their way (they used to drift on
/// into it and end the update inside). The slab reverses each fragment's
/// fall and keeps its speed, so the fragments end outside it with the
/// kinetic energy and the sideways momentum they had when made: those of
/// the same fragments with the slab out of reach (its ids, hence the
/// fragments' random spread, the same).
#[test]
fn fragments_meet_what_lies_in_their_way_in_the_update_they_are_made() {
    let fragments =
        |bodies: &[BodyState]| -> Vec<BodyState> { bodies.iter().filter(|b| b.id.0 >= 3).copied().collect() };
    let (free, free_stats) = shatter_above(-1000.0, "");
    let (met, stats) = shatter_above(0.0, "");
    assert_eq!((free_stats.shatters, stats.shatters), (1, 1));
    let (free, met_fragments) = (fragments(&free), fragments(&met));
    assert_eq!((free.len(), met_fragments.len()), (4, 4));
    let slab = met.iter().find(|b| b.id.0 == 2).expect("the slab");
    assert!(
        free.iter().any(|f| f.position.z - f.half_extents.z < 1.0),
        "without the slab some fragment ends below its top: the test can fail"
    );
    for f in &met_fragments {
        assert!(!overlaps(f, slab), "a fragment ended inside the slab: {f:?}");
        assert!(
            f.position.z - f.half_extents.z >= 1.0 - 1e-5,
            "below the slab's top: {f:?}"
        );
    }
    let (e_free, e_met) = (energy(&free), energy(&met_fragments));
    assert!((e_free - e_met).abs() <= 1e-6 * e_free, "energy {e_free} → {e_met}");
    let (p_free, p_met) = (momentum(&free), momentum(&met_fragments));
    assert!(
        (p_free.x - p_met.x).abs() < 1e-4 && (p_free.y - p_met.y).abs() < 1e-4,
        "{p_free} {p_met}"
    );
    assert!(
        p_free.z < -39.0 && p_met.z > 0.0,
        "the fall reversed: {p_free} → {p_met}"
    );
}

/// A fragment made in an update shatters no more in it (without a size
/// floor a cascade could otherwise go on without end within one update):
/// the pair's fragments meet a cube in their way at 20 (past the
/// threshold) and bounce off it, counted as refused shatters; nothing
/// ends the update inside anything.
#[test]
fn a_fragment_bounces_in_the_update_it_is_made() {
    let (bodies, stats) = shatter_above(-1000.0, "Body(position: (0, 0, 1), half_extents: (6, 6, 1)),");
    assert_eq!(stats.shatters, 1, "only the first pair shatters");
    assert!(stats.refused_shatters >= 1, "{stats:?}");
    let cube = bodies.iter().find(|b| b.id.0 == 3).expect("the cube is whole");
    assert!(cube.velocity.z < -1.0, "struck from above: {cube:?}");
    for (k, a) in bodies.iter().enumerate() {
        for b in &bodies[k + 1..] {
            assert!(!overlaps(a, b), "{a:?} inside {b:?}");
        }
    }
}

/// Fragments that fall onto an absorber in the update they are made in
/// are taken at their touch: never added, their mass and momentum in the
/// absorbed totals, so that the pair's mass (2) and momentum ((0, 0, −40):
/// no gravity) are all still there; their ids are used up all the same.
#[test]
fn fragments_an_absorber_takes_in_their_first_update_are_accounted_for() {
    let mut s = shatter_above_sim(
        -1000.0,
        "Body(position: (0, 0, -8), shape: Sphere(radius: 8), mass: 1000, interacts: false, absorbs: true),",
    );
    let stats = s.collision_stats();
    assert_eq!(stats.shatters, 1);
    assert!(stats.reentries >= 1, "{stats:?}");
    let fragments: Vec<BodyState> = s.snapshot().into_iter().filter(|b| b.id.0 >= 4).collect();
    assert_eq!(fragments.len() + stats.reentries, 4, "each fragment kept or absorbed");
    assert_eq!(s.next_body_id(), 8, "four ids handed out");
    let absorbed = s.absorbed();
    let mass = fragments.iter().map(|f| f64::from(f.mass)).sum::<f64>() + absorbed.mass;
    assert!((mass - 2.0).abs() < 1e-6, "mass {mass}");
    let p = momentum(&fragments) + absorbed.momentum;
    assert!((p - DVec3::new(0.0, 0.0, -40.0)).length() < 1e-4, "momentum {p}");
}

/// A cube caught between two walls (non-interacting boxes) 0.1 wider
/// than it, at 50 units an update: it crosses the gap 500 times an
/// update, past the swept contacts' bound (`MAX_CONTACTS_PER_BODY` for
/// each of the three bodies). The contacts past it wait for the next
/// update and are counted, in the collision statistics and the
/// timeline's `deferred` column; the cube never ends an update outside
/// the gap, and its speed is kept (the walls do not move). Also where
/// the scene lies far from the origin, so that positions round to coarse
/// floats.
#[test]
fn a_cube_caught_between_two_walls_defers_its_contacts_and_stays_between_them() {
    let scene = |x: f32| {
        sim(&format!(
            "Scenario(gravitational_constant: 0, shatter_threshold: 1000, bodies: [
                Body(position: ({x}, 0, 0), velocity: (50, 0, 0)),
                Body(position: ({}, 0, 0), half_extents: (1, 10, 10), interacts: false),
                Body(position: ({}, 0, 0), half_extents: (1, 10, 10), interacts: false),
            ])",
            x - 2.05,
            x + 2.05
        ))
    };
    for x in [0.0f32, 1000.3, -7777.7] {
        let mut s = scene(x);
        let mut deferred = Vec::new();
        for update in 1..=20 {
            s.step(1);
            deferred.push(s.collision_stats().deferred as u64);
            let cube = s.snapshot()[0];
            let slack = 0.05 + 4.0 * f32::EPSILON * x.abs();
            assert!(
                (cube.position.x - x).abs() <= slack + 1e-5,
                "update {update}, scene at {x}: {cube:?}"
            );
            assert!(
                (cube.velocity.length() - 50.0).abs() < 1e-4,
                "update {update}: {cube:?}"
            );
        }
        assert!(deferred.iter().all(|&d| d > 0), "scene at {x}: {deferred:?}");
        // The timeline's column counts the same contacts, update by update.
        let mut timeline = kessler::simulation::Timeline::new(1);
        timeline.run(&mut scene(x), 20, |_| {});
        let column: Vec<u64> = timeline.rows()[1..].iter().map(|r| r.deferred).collect();
        assert_eq!(column, deferred, "scene at {x}");
    }
}
