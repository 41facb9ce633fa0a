//! The shatter stage: pairs marked by the response are removed and
//! replaced by fragments (docs/design.md, "Shatter"), and the bodies an
//! absorber took are removed.
//!
//! `c` fragments share the pair's mass equally, keep its total box volume
//! (half-extent `l = ∛((h1x·h1y·h1z + h2x·h2y·h2z)/c)`) and its momentum: each
//! starts at the center of mass plus an offset, with the center-of-mass
//! velocity plus an outward spread whose mean is subtracted. Offsets are
//! well-spread directions scaled so that no two fragments touch. The random
//! rotation and speeds come from a stream keyed by the pair's ids, and
//! fragments get fresh ids in pair order, so the result does not depend on
//! how the stage is executed.

use bevy::math::DVec3;
use bevy::prelude::*;

use crate::components::{BodyId, BodyState, GravityRole};
use crate::maths;
use crate::resources::{MemoryBudget, NextBodyId, SimulationSettings};
use crate::rng::Rng;
use crate::systems::{Fault, Reentering, SimulationFault, SimulationSystems, SimulationUpdate, Stage};

/// Two bodies to shatter, in pair order, for the shatter stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShatterPair {
    /// The two bodies' entities, to despawn.
    pub entities: [Entity; 2],
    /// Their state at the impact.
    pub bodies: [BodyState; 2],
}

/// Pairs the response marked for shattering this update, in pair order.
#[derive(Resource, Clone, Debug, Default)]
pub struct PendingShatters(pub Vec<ShatterPair>);

/// Clearance between neighboring fragments, as a share of their edge.
const CLEARANCE: f64 = 0.05;

/// Replaces shattered pairs by fragments in [`SimulationSystems::Shatter`].
pub struct ShatterPlugin;

impl Plugin for ShatterPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PendingShatters>()
            .init_resource::<MemoryBudget>()
            .add_systems(SimulationUpdate, shatter.in_set(SimulationSystems::Shatter));
    }
}

/// `count` points spread evenly over the unit sphere (a Fibonacci lattice).
fn sphere_points(count: u32) -> Vec<DVec3> {
    let n = f64::from(count);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|i| {
            let y = 1.0 - (f64::from(i) + 0.5) * 2.0 / n;
            let r = (1.0 - y * y).sqrt();
            let (sin, cos) = maths::sin_cos(golden * f64::from(i));
            DVec3::new(r * cos, y, r * sin)
        })
        .collect()
}

/// Half the edge of each of the `count` fragment cubes of two boxes: the
/// cubes keep the pair's volume, `∛((h1x·h1y·h1z + h2x·h2y·h2z)/count)`.
pub fn fragment_half_extent(a: Vec3, b: Vec3, count: u32) -> f64 {
    let volume = |h: Vec3| f64::from(h.x) * f64::from(h.y) * f64::from(h.z);
    maths::cbrt((volume(a) + volume(b)) / f64::from(count.max(2)))
}

/// Kernel: the fragments of bodies `a` and `b`, with ids from `first_id`.
/// `count` is at least 2 (scenarios reject less, and the response does not
/// shatter with less); a smaller count is taken as 2. `spread` is the
/// fragments' speed away from their center of mass as a share of the impact
/// speed (the thesis's "Streuung"), each fragment's between half of it and
/// all of it.
pub fn fragments(a: &BodyState, b: &BodyState, count: u32, spread: f32, seed: u64, first_id: BodyId) -> Vec<BodyState> {
    let count = count.max(2);
    let (m1, m2) = (f64::from(a.mass), f64::from(b.mass));
    let total = m1 + m2;
    let center = (a.position.as_dvec3() * m1 + b.position.as_dvec3() * m2) / total;
    let velocity = (a.velocity.as_dvec3() * m1 + b.velocity.as_dvec3() * m2) / total;
    let half = fragment_half_extent(a.half_extents, b.half_extents, count);
    let impact = (a.velocity - b.velocity).as_dvec3().length();

    let (low, high) = (a.id.0.min(b.id.0), a.id.0.max(b.id.0));
    let mut rng = Rng::stream(Rng::stream(seed, low).next_u64(), high);
    let turn = maths::rotation_yxz(
        rng.range(0.0, std::f64::consts::TAU),
        rng.range(0.0, std::f64::consts::TAU),
        rng.range(0.0, std::f64::consts::TAU),
    );
    let directions: Vec<DVec3> = sphere_points(count).into_iter().map(|d| turn * d).collect();
    // Scale the directions so that every two boxes are apart on some axis.
    let mut closest = f64::INFINITY;
    for (i, p) in directions.iter().enumerate() {
        for q in &directions[i + 1..] {
            closest = closest.min((*p - *q).abs().max_element());
        }
    }
    // Keep the clearance after rounding to f32: a few f32 steps at the center.
    let rounding = 4.0 * f64::from(f32::EPSILON) * center.abs().max_element();
    let radius = (2.0 * half * (1.0 + CLEARANCE) + rounding) / closest;
    let spreads: Vec<DVec3> = directions
        .iter()
        .map(|d| *d * impact * f64::from(spread) * rng.range(0.5, 1.0))
        .collect();
    let mean_spread = spreads.iter().copied().sum::<DVec3>() / f64::from(count);

    let role = match (
        a.role.is_source() || b.role.is_source(),
        a.role.is_adopter() || b.role.is_adopter(),
    ) {
        (true, true) => GravityRole::SourceAndAdopter,
        (true, false) => GravityRole::Source,
        (false, true) => GravityRole::Adopter,
        (false, false) => GravityRole::Inert,
    };
    directions
        .iter()
        .zip(&spreads)
        .enumerate()
        .map(|(i, (d, s))| {
            BodyState::new_box(
                BodyId(first_id.0 + i as u64),
                (center + *d * radius).as_vec3(),
                (velocity + *s - mean_spread).as_vec3(),
                (total / f64::from(count)) as f32,
                Vec3::splat(half as f32),
                role,
                true,
            )
        })
        .collect()
}

#[expect(
    clippy::too_many_arguments,
    reason = "a Bevy system's parameters are its data access"
)]
fn shatter(
    settings: Res<SimulationSettings>,
    mut stage: Stage,
    mut pending: ResMut<PendingShatters>,
    mut reentering: ResMut<Reentering>,
    mut next_id: ResMut<NextBodyId>,
    budget: Res<MemoryBudget>,
    bodies: Query<(), With<BodyId>>,
    mut fault: ResMut<SimulationFault>,
    mut commands: Commands,
) {
    let clock = stage.start(SimulationSystems::Shatter);
    for entity in reentering.0.drain(..) {
        commands.entity(entity).despawn();
    }
    let count = settings.shatter_fragments;
    // Only an update that shatters can outgrow the memory.
    let shatters = pending.0.len() as u64;
    let after = || {
        (bodies.iter().len() as u64)
            .saturating_sub(2 * shatters)
            .saturating_add(shatters * u64::from(count))
    };
    if shatters > 0
        && let Some(limit) = budget.limit
        && let after = after()
        && after > limit.bodies()
    {
        // Stopped before the allocation that would fail.
        pending.0.clear();
        fault.stop(Fault::OutOfMemory { bodies: after, limit });
        return;
    }
    for pair in pending.0.drain(..) {
        for entity in pair.entities {
            commands.entity(entity).despawn();
        }
        let [a, b] = &pair.bodies;
        let first = BodyId(next_id.0);
        next_id.0 += u64::from(count);
        commands.spawn_batch(
            fragments(a, b, count, settings.fragment_spread, settings.seed, first)
                .into_iter()
                .map(|f| f.bundle()),
        );
    }
    clock.finish();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::Aabb;

    fn body(id: u64, position: [f32; 3], velocity: [f32; 3], mass: f32, half: [f32; 3]) -> BodyState {
        BodyState::new_box(
            BodyId(id),
            Vec3::from_array(position),
            Vec3::from_array(velocity),
            mass,
            Vec3::from_array(half),
            GravityRole::Adopter,
            true,
        )
    }

    #[test]
    fn keeps_mass_volume_and_momentum() {
        let a = body(3, [10.0, 0.0, 0.0], [4.0, 1.0, 0.0], 1.0, [1.0, 1.0, 1.0]);
        let b = body(8, [11.5, 0.5, 0.0], [-2.0, 0.0, 0.5], 3.0, [1.0, 0.5, 2.0]);
        for count in [2, 3, 5, 8, 27, 100] {
            let f = fragments(&a, &b, count, 0.2, 1, BodyId(100));
            assert_eq!(f.len(), count as usize);
            let mass: f64 = f.iter().map(|x| f64::from(x.mass)).sum();
            assert!((mass - 4.0).abs() < 1e-5, "mass {mass}");
            let volume: f64 = f
                .iter()
                .map(|x| f64::from(x.half_extents.x) * f64::from(x.half_extents.x) * f64::from(x.half_extents.x))
                .sum();
            assert!((volume - 2.0).abs() < 1e-5, "half-volume {volume}");
            let momentum: DVec3 = f.iter().map(|x| x.velocity.as_dvec3() * f64::from(x.mass)).sum();
            let expected = DVec3::new(4.0 - 6.0, 1.0, 1.5);
            assert!(
                (momentum - expected).length() < 1e-5,
                "{count}: momentum {momentum} vs {expected}"
            );
            assert!(f.iter().enumerate().all(|(i, x)| x.id == BodyId(100 + i as u64)));
        }
    }

    #[test]
    fn fragments_do_not_touch_each_other() {
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        for count in [2, 5, 12, 64, 300] {
            let f = fragments(&a, &b, count, 0.2, 7, BodyId(2));
            let boxes: Vec<Aabb> = f.iter().map(|x| Aabb::new(x.position, x.half_extents)).collect();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    assert!(!boxes[i].overlaps(&boxes[j]), "{count} fragments: {i} and {j} touch");
                }
            }
        }
    }

    #[test]
    fn fragments_far_from_the_origin_do_not_touch_either() {
        let a = body(0, [3.0e6, -2.0e6, 0.0], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [3.0e6 + 1.75, -2.0e6, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        for count in [2, 5, 12] {
            let boxes: Vec<Aabb> = fragments(&a, &b, count, 0.2, 3, BodyId(2))
                .iter()
                .map(|x| Aabb::new(x.position, x.half_extents))
                .collect();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    assert!(!boxes[i].overlaps(&boxes[j]), "{count} fragments: {i} and {j} touch");
                }
            }
        }
    }

    #[test]
    fn spread_is_seeded_and_keyed_by_the_pair() {
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        assert_eq!(
            fragments(&a, &b, 5, 0.2, 1, BodyId(2)),
            fragments(&b, &a, 5, 0.2, 1, BodyId(2))
        );
        assert_ne!(
            fragments(&a, &b, 5, 0.2, 1, BodyId(2)),
            fragments(&a, &b, 5, 0.2, 2, BodyId(2))
        );
    }

    #[test]
    fn the_spread_is_the_fragments_speed_apart_as_a_share_of_the_impact() {
        // Equal masses meeting head-on at 6: the center of mass rests.
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let speeds = |spread: f32| -> Vec<f64> {
            fragments(&a, &b, 8, spread, 1, BodyId(2))
                .iter()
                .map(|f| f.velocity.as_dvec3().length())
                .collect()
        };
        assert!(
            speeds(0.0).iter().all(|&v| v < 1e-6),
            "no spread: the fragments move together"
        );
        let (single, double) = (speeds(0.2), speeds(0.4));
        for (s, d) in single.iter().zip(&double) {
            assert!((d - 2.0 * s).abs() < 1e-5, "twice the spread, twice the speed: {s} {d}");
        }
        // Each fragment moves at up to the spread's share of the impact speed
        // (less the small mean that keeps the momentum).
        let mean = single.iter().sum::<f64>() / single.len() as f64;
        assert!(
            mean > 0.2 * 6.0 * 0.4 && single.iter().all(|&v| v < 0.2 * 6.0 * 1.2),
            "{single:?}"
        );
    }
}
