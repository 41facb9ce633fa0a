//! Checks of a scenario's initial state, made when its bodies are made:
//! what no single field shows, but would stop the run at once.
//!
//! - every body's state is finite (a generator's output included);
//! - the first update's kick and drift, computed by the gravity and
//!   integration kernels themselves, leave every position and velocity
//!   finite (two sources 1e-45 apart without softening, or many sources
//!   whose pulls add up past f32, fail here);
//! - the bodies are not piled on one another: their overlapping pairs stay
//!   within the sweep's pair limit (`systems/pipeline/pair_limit.rs`: bodies
//!   placed at one point are N² pairs).

use crate::components::{BodyId, BodyState, GravityRole, Mass, Position, PreviousPosition, Velocity};
use crate::execution::{Execution, ExecutionMode};
use crate::physics::Aabb;
use crate::resources::{SimulationSettings, Stages};
use crate::systems::{
    Drift, PullScratch, Roles, SortedBoxes, collect_sources, first_non_finite, gravity_kernel, integrate_kernel,
    prepare_pull, sweep_and_prune,
};

/// What is wrong with the initial state, in words naming the body by id.
pub fn check_start(bodies: &[BodyState], settings: &SimulationSettings) -> Result<(), String> {
    if let Some(b) = bodies.iter().find(|b| !b.is_finite()) {
        return Err(format!(
            "body {} starts with a non-finite state (position {}, velocity {})",
            b.id.0, b.position, b.velocity
        ));
    }
    let execution = Execution::all_cores(ExecutionMode::Parallel).map_err(|e| e.to_string())?;
    first_update_stays_finite(bodies, settings, &execution)?;
    let boxes: Vec<Aabb> = bodies.iter().map(|b| Aabb::new(b.position, b.half_extents)).collect();
    sweep_and_prune(boxes.as_slice(), &execution, &mut SortedBoxes::default())
        .map_err(|e| format!("at the start, {e}"))?;
    Ok(())
}

/// Runs the first update's kick and drift on copies of the bodies' columns
/// with the stages' own kernels, and names the first body (by id) they
/// leave non-finite.
fn first_update_stays_finite(
    bodies: &[BodyState],
    settings: &SimulationSettings,
    execution: &Execution,
) -> Result<(), String> {
    let ids: Vec<BodyId> = bodies.iter().map(|b| b.id).collect();
    let roles: Vec<GravityRole> = bodies.iter().map(|b| b.role).collect();
    let masses: Vec<Mass> = bodies.iter().map(|b| Mass(b.mass)).collect();
    let mut positions: Vec<Position> = bodies.iter().map(|b| Position(b.position)).collect();
    let mut velocities: Vec<Velocity> = bodies.iter().map(|b| Velocity(b.velocity)).collect();
    let mut previous = vec![PreviousPosition::default(); bodies.len()];
    let mut sources = Vec::new();
    let table = (
        ids.as_slice(),
        positions.as_slice(),
        velocities.as_slice(),
        masses.as_slice(),
        Some(roles.as_slice()),
    );
    let (integrator, dt) = (settings.integrator, settings.time_step);
    collect_sources(
        std::iter::once(table),
        f64::from(settings.gravitational_constant),
        integrator,
        dt,
        &mut sources,
    );
    let softening = f64::from(settings.softening);
    let softening2 = softening * softening;
    let mut scratch = PullScratch::default();
    let (pull, stage) = prepare_pull(
        settings.gravity_method,
        &sources,
        bodies.len(),
        softening2,
        execution,
        &mut scratch,
    );
    let columns = (
        ids.as_slice(),
        Roles::Each(&roles),
        positions.as_mut_slice(),
        previous.as_mut_slice(),
        velocities.as_mut_slice(),
    );
    stage.for_chunks(columns, |columns| {
        gravity_kernel(columns, pull, softening2, dt, integrator);
    });
    // The gravity stage runs whatever its switch: a scenario's file has none.
    let drift = Drift::of(&SimulationSettings {
        stages: Stages {
            gravity: true,
            ..settings.stages
        },
        ..settings.clone()
    });
    if integrate_kernel((&velocities, &mut positions, &mut previous), dt, drift) {
        return Ok(());
    }
    let fault = first_non_finite(ids.iter().zip(&positions).zip(&velocities).map(|((i, p), v)| (i, p, v)))
        .expect("a non-finite value was seen");
    Err(format!("the first update overflows: {fault}"))
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;

    fn body(id: u64, x: f32, role: GravityRole) -> BodyState {
        BodyState::new_box(
            BodyId(id),
            Vec3::new(x, 0.0, 0.0),
            Vec3::ZERO,
            1e12,
            Vec3::ONE,
            role,
            true,
        )
    }

    #[test]
    fn sources_nearly_on_one_point_are_refused_unless_softened() {
        let close = [
            body(0, 0.0, GravityRole::SourceAndAdopter),
            body(1, 1e-20, GravityRole::SourceAndAdopter),
        ];
        let settings = SimulationSettings {
            gravitational_constant: 1e6,
            ..SimulationSettings::default()
        };
        let e = check_start(&close, &settings).unwrap_err();
        assert!(
            e.starts_with("the first update overflows: body 0 has a non-finite"),
            "{e}"
        );
        let softened = SimulationSettings {
            softening: 1.0,
            ..settings.clone()
        };
        assert_eq!(check_start(&close, &softened), Ok(()));
        // Adopters pull nothing.
        let adopters = [body(0, 0.0, GravityRole::Adopter), body(1, 1e-20, GravityRole::Adopter)];
        assert_eq!(check_start(&adopters, &settings), Ok(()));
    }

    /// Each pull alone is finite; their sum, or the drift after it, is not.
    #[test]
    fn pulls_that_add_up_past_f32_and_an_overflowing_drift_are_refused() {
        let settings = SimulationSettings {
            gravitational_constant: 1e6,
            ..SimulationSettings::default()
        };
        // 1e18 / (1e-10)² = 1e38 each: two of them are 2e38, four 4e38.
        let mut crowd = vec![body(9, 0.0, GravityRole::Adopter)];
        crowd.extend((0..4).map(|i| body(i, -1e-10, GravityRole::Source)));
        let e = check_start(&crowd, &settings).unwrap_err();
        assert!(e.contains("body 9 has a non-finite"), "{e}");
        // One of them: a finite kick of 1e38 · dt (2), but semi-implicit
        // Euler's whole drift 2e38 · dt overflows (the leapfrog's half
        // drift, 2e38 · dt/2, does not).
        let drift = SimulationSettings {
            time_step: 2.0,
            integrator: crate::resources::Integrator::SemiImplicitEuler,
            ..settings.clone()
        };
        let leapfrog = SimulationSettings {
            integrator: crate::resources::Integrator::Leapfrog,
            ..drift.clone()
        };
        assert_eq!(check_start(&crowd[..2], &leapfrog), Ok(()));
        let e = check_start(&crowd[..2], &drift).unwrap_err();
        assert!(e.contains("body 9 has a non-finite"), "{e}");
        assert_eq!(check_start(&crowd[..2], &settings), Ok(()));
    }

    #[test]
    fn a_pile_up_and_a_non_finite_body_are_refused() {
        let settings = SimulationSettings::default();
        let piled: Vec<BodyState> = (0..2000).map(|i| body(i, 0.0, GravityRole::Adopter)).collect();
        let e = check_start(&piled, &settings).unwrap_err();
        assert!(
            e.starts_with("at the start, the 2000 bodies overlap in more than"),
            "{e}"
        );
        let mut broken = vec![body(0, 0.0, GravityRole::Adopter), body(1, 5.0, GravityRole::Adopter)];
        broken[1].velocity.y = f32::INFINITY;
        let e = check_start(&broken, &settings).unwrap_err();
        assert!(e.starts_with("body 1 starts with a non-finite state"), "{e}");
    }
}
