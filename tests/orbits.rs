//! Gravity and integration against analytic expectations: the thesis's
//! orbit cases under both integrators, exact cancellation between
//! symmetric sources, the leapfrog's round orbits, bounded energy and
//! Kepler's period, and energy conservation of an eccentric orbit.

mod common {
    pub mod simulation;
}

use common::simulation::sim;
use kessler::Simulation;

/// The integrators, as scenario files name them.
const INTEGRATORS: [&str; 2] = ["Leapfrog", "SemiImplicitEuler"];

/// A source of `mass` at the origin and an adopter at `position` with
/// `velocity` (the thesis's test set-up, G = 6.674, dt = 1), moved by
/// `integrator`.
fn two_body(integrator: &str, mass: f32, position: [f32; 3], velocity: [f32; 3]) -> Simulation {
    sim(&format!(
        "Scenario(integrator: {integrator}, bodies: [
            Body(position: (0, 0, 0), mass: {mass}, role: Source, interacts: false),
            Body(position: ({}, {}, {}), velocity: ({}, {}, {})),
        ])",
        position[0], position[1], position[2], velocity[0], velocity[1], velocity[2]
    ))
}

/// Each case is a circular orbit (v² = G·M/r) whose period rounds to the
/// update count: after one revolution the body is back where it started,
/// under either integrator.
#[test]
fn thesis_orbits_return_after_one_period() {
    for integrator in INTEGRATORS {
        thesis_orbits_under(integrator);
    }
}

fn thesis_orbits_under(integrator: &str) {
    let cases = [
        // mass, start, velocity, updates, axis of the start coordinate
        (2.0, [20.0, 0.0, 0.0], [0.0, 0.81694555, 0.0], 154, 0),
        (6.0, [0.0, 36.0, 0.0], [0.0, 0.0, 1.054672], 214, 1),
        (80.0, [0.0, 0.0, 600.0], [0.9433274, 0.0, 0.0], 3996, 2),
    ];
    for (mass, start, velocity, updates, axis) in cases {
        // The set-up really is circular: v² = G·M/r to f32 precision.
        let r = start[axis];
        let v2: f32 = velocity.iter().map(|v| v * v).sum();
        assert!(
            (v2 - 6.674 * mass / r).abs() < 1e-5 * v2,
            "case mass {mass} is not circular"
        );

        let mut s = two_body(integrator, mass, start, velocity);
        s.step(updates);
        let body = s.snapshot()[1];
        let end = body.position.to_array();
        assert_eq!(
            end[axis].round(),
            r,
            "{integrator}, mass {mass}: after {updates} updates the body is at {end:?}"
        );
        // Still on the circle.
        assert!(
            (body.position.length() - r).abs() < 0.01 * r,
            "{integrator}, mass {mass}: radius drifted to {}",
            body.position.length()
        );
    }
}

#[test]
fn symmetric_sources_cancel_exactly() {
    let mut s = sim("Scenario(bodies: [
        Body(position: (100, 100, 100), mass: 50, role: Source, interacts: false),
        Body(position: (-100, -100, -100), mass: 50, role: Source, interacts: false),
        Body(position: (0, 0, 0)),
    ])");
    s.step(1000);
    let body = s.snapshot()[2];
    assert_eq!(body.position.to_array(), [0.0; 3]);
    assert_eq!(body.velocity.to_array(), [0.0; 3]);
}

#[test]
fn inert_and_non_adopting_bodies_only_drift() {
    let mut s = sim("Scenario(bodies: [
        Body(position: (0, 0, 0), mass: 1000, role: Source, interacts: false),
        Body(position: (50, 0, 0), velocity: (0, 1, 0), role: Inert),
        Body(position: (0, 50, 0), velocity: (1, 0, 0), role: Source, interacts: false),
        Body(position: (0, 0, 50), role: SourceAndAdopter),
    ])");
    // (Within ten updates the falling body meets the first source's box
    // and bounces off it.)
    s.step(2);
    assert!(
        s.snapshot()[3].position.z < 50.0,
        "a SourceAndAdopter falls towards the sources"
    );
    s.step(8);
    let b = s.snapshot();
    assert_eq!(
        b[0].position.to_array(),
        [0.0; 3],
        "a source without velocity stays put"
    );
    assert_eq!(b[1].position.to_array(), [50.0, 10.0, 0.0]);
    assert_eq!(b[2].position.to_array(), [10.0, 50.0, 0.0]);
}

/// Semi-implicit Euler (the thesis's) is symplectic: the energy of an
/// eccentric orbit oscillates but does not drift, over 60 revolutions.
#[test]
fn eccentric_orbit_energy_stays_bounded() {
    let (gm, r0) = (6.674_f64 * 6.0, 36.0_f64);
    let v0 = 0.8 * (gm / r0).sqrt(); // 0.8 × circular speed: eccentricity 0.36
    let dt = 0.25;
    let mut s = sim(&format!(
        "Scenario(time_step: {dt}, integrator: SemiImplicitEuler, bodies: [
            Body(position: (0, 0, 0), mass: 6, role: Source, interacts: false),
            Body(position: ({r0}, 0, 0), velocity: (0, 0, {v0})),
        ])"
    ));
    // Analytic: E = v²/2 − GM/r, a = −GM/(2E), T = 2π·sqrt(a³/GM).
    let e0 = v0 * v0 / 2.0 - gm / r0;
    let a = -gm / (2.0 * e0);
    let period_updates = (std::f64::consts::TAU * (a * a * a / gm).sqrt() / dt).round() as u64;
    let orbits = 60;
    let mut energies = Vec::new();
    for _ in 0..orbits * period_updates {
        s.step(1);
        let b = s.snapshot()[1];
        let (p, v) = (b.position.as_dvec3(), b.velocity.as_dvec3());
        energies.push(v.length_squared() / 2.0 - gm / p.length());
    }
    let worst = energies.iter().map(|e| ((e - e0) / e0).abs()).fold(0.0, f64::max);
    assert!(
        worst < 0.02,
        "energy strayed {:.3} % from the analytic value",
        worst * 100.0
    );
    let mean = |xs: &[f64]| xs.iter().sum::<f64>() / xs.len() as f64;
    let span = (5 * period_updates) as usize;
    let (first, last) = (mean(&energies[..span]), mean(&energies[energies.len() - span..]));
    assert!(
        ((last - first) / e0).abs() < 1e-4,
        "energy drifted from {first} to {last} over {orbits} orbits"
    );
}

/// A virialised cluster under the Barnes–Hut tree: 200 bodies whose
/// velocities are scaled so that 2·KE = −PE (softened), collisions off.
/// Over 1000 updates (about ten crossing times) the total energy stays
/// within 5 % of its start: the tree's force error does not pump energy in.
#[test]
fn a_virialised_cluster_keeps_its_energy_under_the_tree() {
    let (g, softening, count) = (0.05f64, 2.0f64, 200);
    let mut rng = 12345u64;
    let mut next = || {
        rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let positions: Vec<[f64; 3]> = (0..count)
        .map(|_| {
            loop {
                let p = [next() * 60.0, next() * 60.0, next() * 60.0];
                if p.iter().map(|x| x * x).sum::<f64>() < 3600.0 {
                    break p;
                }
            }
        })
        .collect();
    let potential = |ps: &[[f64; 3]]| -> f64 {
        let mut pe = 0.0;
        for i in 0..ps.len() {
            for j in i + 1..ps.len() {
                let r2: f64 = (0..3).map(|k| (ps[i][k] - ps[j][k]) * (ps[i][k] - ps[j][k])).sum();
                pe -= g / (r2 + softening * softening).sqrt();
            }
        }
        pe
    };
    let pe = potential(&positions);
    // Random directions, speed so that KE = −PE/2 (unit masses).
    let speed = (-pe / count as f64).sqrt();
    let bodies: Vec<String> = positions
        .iter()
        .map(|p| {
            let d = [next(), next(), next()];
            let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            let v = d.map(|x| x / n * speed);
            format!(
                "Body(position: ({}, {}, {}), velocity: ({}, {}, {}), role: SourceAndAdopter)",
                p[0], p[1], p[2], v[0], v[1], v[2]
            )
        })
        .collect();
    let mut s = sim(&format!(
        "Scenario(gravitational_constant: {g}, softening: {softening}, gravity: Tree(theta: 0.5), bodies: [{}])",
        bodies.join(",")
    ));
    s.settings_mut().stages.collisions = false;
    let energy = |s: &mut Simulation| {
        let bodies = s.snapshot();
        let ps: Vec<[f64; 3]> = bodies.iter().map(|b| b.position.as_dvec3().to_array()).collect();
        s.totals().kinetic_energy + potential(&ps)
    };
    let start = energy(&mut s);
    assert!(start < 0.0, "bound: {start}");
    for _ in 0..20 {
        s.step(50);
        let now = energy(&mut s);
        assert!(
            ((now - start) / start).abs() < 0.05,
            "energy {now} drifted from {start}"
        );
    }
}

/// The default scene's orbits: radius 200 at 5 units an update (dt = 1),
/// so `G·M = v²·r = 5000`; with G = 6.674 the planet's mass is 5000/G.
const GM: f64 = 5000.0;
const RADIUS: f64 = 200.0;

/// A planet of `G·M` = [`GM`] at the origin and a cube at (r, 0, 0) moving
/// along y at `speed`, moved by `integrator` for `updates` updates: the
/// cube's distance from the planet and its specific energy
/// `v²/2 − G·M/r` after each update, in f64.
fn orbit(integrator: &str, speed: f64, updates: u64) -> Vec<(f64, f64)> {
    let mass = GM / 6.674;
    let mut s = sim(&format!(
        "Scenario(integrator: {integrator}, bodies: [
            Body(position: (0, 0, 0), mass: {mass}, role: Source, interacts: false),
            Body(position: ({RADIUS}, 0, 0), velocity: (0, {speed}, 0)),
        ])"
    ));
    (0..updates)
        .map(|_| {
            s.step(1);
            let b = s.snapshot()[1];
            let (p, v) = (b.position.as_dvec3(), b.velocity.as_dvec3());
            (p.length(), v.length_squared() / 2.0 - GM / p.length())
        })
        .collect()
}

/// The widest swing of the distance from `r0`, as a share of it.
fn radial_band(track: &[(f64, f64)], r0: f64) -> f64 {
    track.iter().map(|(r, _)| ((r - r0) / r0).abs()).fold(0.0, f64::max)
}

/// A circular orbit at the default step stays within 0.1 % of its radius
/// over three orbits with the leapfrog; semi-implicit Euler, first order,
/// swings by more than 1 % (about 2.5 %: more than a cube's edge).
#[test]
fn the_leapfrog_keeps_a_circular_orbit_round() {
    let circular = (GM / RADIUS).sqrt();
    let period = std::f64::consts::TAU * RADIUS / circular;
    let updates = (3.0 * period).ceil() as u64;
    let leapfrog = radial_band(&orbit("Leapfrog", circular, updates), RADIUS);
    let euler = radial_band(&orbit("SemiImplicitEuler", circular, updates), RADIUS);
    assert!(
        leapfrog < 1e-3,
        "leapfrog: the radius swung by {:.4} %",
        leapfrog * 100.0
    );
    assert!(euler > 1e-2, "Euler: the radius swung by only {:.4} %", euler * 100.0);
}

/// The eccentric orbit of the tests below, starting at [`RADIUS`] at 1.15
/// times the circular speed: that speed, its specific energy
/// `v²/2 − G·M/r`, and Kepler's period `2π·sqrt(a³/GM)` with the semi-major
/// axis `a = −G·M/(2E)`, in updates.
fn eccentric() -> (f64, f64, f64) {
    let v0 = 1.15 * (GM / RADIUS).sqrt();
    let e0 = v0 * v0 / 2.0 - GM / RADIUS;
    let a = -GM / (2.0 * e0);
    (v0, e0, std::f64::consts::TAU * (a * a * a / GM).sqrt())
}

/// An eccentric orbit (1.15 × circular speed) over 20 orbits: the
/// leapfrog's energy error stays within 2e-3 of the analytic start value,
/// with no drift between the first and the last three orbits.
#[test]
fn the_leapfrogs_energy_stays_bounded_without_drift() {
    let (v0, e0, period) = eccentric();
    let orbits = 20;
    let track = orbit("Leapfrog", v0, (orbits as f64 * period).ceil() as u64);
    let errors: Vec<f64> = track.iter().map(|(_, e)| (e - e0) / e0.abs()).collect();
    let worst = errors.iter().fold(0.0, |w: f64, e| w.max(e.abs()));
    assert!(
        worst < 2e-3,
        "energy strayed {:.4} % from the analytic value",
        worst * 100.0
    );
    let span = (3.0 * period) as usize;
    let mean = |xs: &[f64]| xs.iter().sum::<f64>() / xs.len() as f64;
    let drift = mean(&errors[errors.len() - span..]) - mean(&errors[..span]);
    assert!(
        drift.abs() < 1e-4,
        "energy drifted by {drift:e} of itself over {orbits} orbits"
    );
}

/// Kepler's third law: the leapfrog's eccentric orbit comes back to its
/// start angle every `2π·sqrt(a³/GM)` (a from the analytic energy), to
/// within 0.1 % (second order: the error at this step is about 1e-5).
#[test]
fn the_leapfrogs_period_is_keplers() {
    let (v0, _, kepler) = eccentric();
    let mass = GM / 6.674;
    let mut s = sim(&format!(
        "Scenario(bodies: [
            Body(position: (0, 0, 0), mass: {mass}, role: Source, interacts: false),
            Body(position: ({RADIUS}, 0, 0), velocity: (0, {v0}, 0)),
        ])"
    ));
    // The times the cube crosses the +x axis upwards (y from < 0 to >= 0,
    // x > 0), each between two updates by linear interpolation.
    let mut crossings = Vec::new();
    let mut before = s.snapshot()[1].position.as_dvec3();
    for update in 1..=(5.2 * kepler) as u64 {
        s.step(1);
        let now = s.snapshot()[1].position.as_dvec3();
        if before.y < 0.0 && now.y >= 0.0 && now.x > 0.0 {
            crossings.push(update as f64 - 1.0 + before.y / (before.y - now.y));
        }
        before = now;
    }
    assert_eq!(crossings.len(), 5, "five returns in 5.2 periods");
    let measured = (crossings[4] - crossings[0]) / 4.0;
    assert!(
        ((measured - kepler) / kepler).abs() < 1e-3,
        "period {measured} updates, Kepler's {kepler}"
    );
}

/// Switching integrators is defined between any two updates: a `Set`
/// event at update 40 gives the bits of a run switched by hand there.
#[test]
fn the_integrator_switches_between_updates() {
    let body = "bodies: [
        Body(position: (0, 0, 0), mass: 700, role: Source, interacts: false),
        Body(position: (200, 0, 0), velocity: (0, 5.1, 0.3)),
    ]";
    let mut by_event = sim(&format!(
        "Scenario({body}, events: [Set(update: 40, integrator: SemiImplicitEuler)])"
    ));
    let mut by_hand = sim(&format!("Scenario({body})"));
    by_event.step(80);
    by_hand.step(40);
    let (leapfrog_at_40, mut leapfrog_on) = (by_hand.snapshot(), sim(&format!("Scenario({body})")));
    by_hand.settings_mut().integrator = kessler::resources::Integrator::SemiImplicitEuler;
    by_hand.step(40);
    leapfrog_on.step(80);
    let bits = |s: &mut Simulation| s.snapshot()[1].position.to_array().map(f32::to_bits);
    assert_eq!(bits(&mut by_event), bits(&mut by_hand));
    assert_ne!(
        bits(&mut by_event),
        bits(&mut leapfrog_on),
        "the switch changed the run"
    );
    assert_ne!(leapfrog_at_40[1].position, by_hand.snapshot()[1].position);
}
