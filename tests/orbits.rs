//! Gravity and integration against analytic expectations: the thesis's
//! orbit cases, exact cancellation between symmetric sources, and energy
//! conservation of an eccentric orbit.

use kessler::Simulation;
use kessler::execution::{Execution, ExecutionMode};
use kessler::scenario::Scenario;

fn sim(text: &str) -> Simulation {
    let scenario = Scenario::parse(text, "test").expect("test scenario parses");
    let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
    Simulation::from_scenario(&scenario, execution).unwrap()
}

/// A source of `mass` at the origin and an adopter at `position` with
/// `velocity` (the thesis's test set-up, G = 6.674, dt = 1).
fn two_body(mass: f32, position: [f32; 3], velocity: [f32; 3]) -> Simulation {
    sim(&format!(
        "Scenario(bodies: [
            Body(position: (0, 0, 0), mass: {mass}, role: Source, interacts: false),
            Body(position: ({}, {}, {}), velocity: ({}, {}, {})),
        ])",
        position[0], position[1], position[2], velocity[0], velocity[1], velocity[2]
    ))
}

/// Each case is a circular orbit (v² = G·M/r) whose period rounds to the
/// update count: after one revolution the body is back where it started.
#[test]
fn thesis_orbits_return_after_one_period() {
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

        let mut s = two_body(mass, start, velocity);
        s.step(updates);
        let body = s.snapshot()[1];
        let end = body.position.to_array();
        assert_eq!(
            end[axis].round(),
            r,
            "mass {mass}: after {updates} updates the body is at {end:?}"
        );
        // Still on the circle.
        assert!(
            (body.position.length() - r).abs() < 0.01 * r,
            "mass {mass}: radius drifted to {}",
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
    s.step(10);
    let b = s.snapshot();
    assert_eq!(
        b[0].position.to_array(),
        [0.0; 3],
        "a source without velocity stays put"
    );
    assert_eq!(b[1].position.to_array(), [50.0, 10.0, 0.0]);
    assert_eq!(b[2].position.to_array(), [10.0, 50.0, 0.0]);
    assert!(b[3].position.z < 50.0, "a SourceAndAdopter falls towards the sources");
}

/// Semi-implicit Euler is symplectic: the energy of an eccentric orbit
/// oscillates but does not drift, over 60 revolutions.
#[test]
fn eccentric_orbit_energy_stays_bounded() {
    let (gm, r0) = (6.674_f64 * 6.0, 36.0_f64);
    let v0 = 0.8 * (gm / r0).sqrt(); // 0.8 × circular speed: eccentricity 0.36
    let dt = 0.25;
    let mut s = sim(&format!(
        "Scenario(time_step: {dt}, bodies: [
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
    s.settings_mut().collisions = false;
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
