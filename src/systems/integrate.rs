//! Stage 2: semi-implicit Euler integration (DESIGN §2.2).
//!
//! Adopters first take `v += a·dt`, then every body moves `p += v·dt`; the
//! position before the move is kept for the collision response.

use std::time::Instant;

use bevy::prelude::*;

use crate::components::{Acceleration, GravityRole, PreviousPosition, Velocity};
use crate::resources::{Execution, SimulationSettings, StageTimings};
use crate::systems::{SimulationSystems, SimulationUpdate};

/// The columns the integration kernel reads and writes.
pub type IntegrateColumns<'a> = (
    &'a [GravityRole],
    &'a [Acceleration],
    &'a mut [Velocity],
    &'a mut [Transform],
    &'a mut [PreviousPosition],
);

/// Bodies per parallel chunk.
const GRAIN: usize = 32_768;

/// Moves every body in [`SimulationSystems::Integrate`].
pub struct IntegratePlugin;

impl Plugin for IntegratePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimulationUpdate, integrate.in_set(SimulationSystems::Integrate));
    }
}

/// Kernel: one semi-implicit Euler step for the bodies in the columns.
/// `kick` says whether accelerations apply (gravity on).
pub fn integrate_kernel(
    (roles, accelerations, velocities, transforms, previous): IntegrateColumns<'_>,
    dt: f32,
    kick: bool,
) {
    let columns = roles
        .iter()
        .zip(accelerations)
        .zip(velocities)
        .zip(transforms)
        .zip(previous);
    for ((((role, a), v), t), prev) in columns {
        if kick && role.is_adopter() {
            v.0 += a.0 * dt;
        }
        prev.0 = t.translation;
        t.translation += v.0 * dt;
    }
}

fn integrate(
    settings: Res<SimulationSettings>,
    execution: Res<Execution>,
    mut timings: ResMut<StageTimings>,
    mut bodies: Query<(
        &GravityRole,
        &Acceleration,
        &mut Velocity,
        &mut Transform,
        &mut PreviousPosition,
    )>,
) {
    let start = Instant::now();
    let (dt, kick) = (settings.time_step, settings.gravity);
    let tables = bodies.contiguous_iter_mut().expect("body components are table-stored");
    for (roles, accelerations, mut velocities, mut transforms, mut previous) in tables {
        let columns = (
            roles,
            accelerations,
            velocities.bypass_change_detection(),
            transforms.bypass_change_detection(),
            previous.bypass_change_detection(),
        );
        execution.for_chunks(columns, GRAIN, |columns| integrate_kernel(columns, dt, kick));
    }
    timings.record(SimulationSystems::Integrate, start.elapsed());
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(role: GravityRole, kick: bool) -> (Vec3, Vec3, Vec3) {
        let mut v = [Velocity(Vec3::new(1.0, 0.0, 0.0))];
        let mut t = [Transform::from_xyz(10.0, 0.0, 0.0)];
        let mut prev = [PreviousPosition::default()];
        let a = [Acceleration(Vec3::new(0.0, 2.0, 0.0))];
        integrate_kernel((&[role], &a, &mut v, &mut t, &mut prev), 0.5, kick);
        (v[0].0, t[0].translation, prev[0].0)
    }

    #[test]
    fn adopters_kick_then_drift() {
        let (v, p, prev) = step(GravityRole::Adopter, true);
        assert_eq!(v, Vec3::new(1.0, 1.0, 0.0));
        // Semi-implicit: the new velocity moves the body.
        assert_eq!(p, Vec3::new(10.5, 0.5, 0.0));
        assert_eq!(prev, Vec3::new(10.0, 0.0, 0.0));
    }

    #[test]
    fn non_adopters_and_gravity_off_only_drift() {
        for (role, kick) in [
            (GravityRole::Inert, true),
            (GravityRole::Source, true),
            (GravityRole::Adopter, false),
        ] {
            let (v, p, _) = step(role, kick);
            assert_eq!(
                (v, p),
                (Vec3::new(1.0, 0.0, 0.0), Vec3::new(10.5, 0.0, 0.0)),
                "{role:?} {kick}"
            );
        }
    }
}
