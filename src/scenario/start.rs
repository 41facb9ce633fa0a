//! Checks of a scenario's initial state, made when its bodies are made:
//! what no single field shows, but would stop the run at once.
//!
//! - every body's state is finite (a generator's output included);
//! - the bodies are not piled on one another: their overlapping pairs stay
//!   within the sweep's [`pair_limit`](crate::systems::pair_limit) (bodies
//!   placed at one point are N² pairs);
//! - no two overlapping sources pull each other so hard that one time step
//!   overflows (two sources 1e-45 apart without softening).

use crate::components::BodyState;
use crate::execution::{Execution, ExecutionMode};
use crate::resources::SimulationSettings;
use crate::systems::{Aabb, GravitySource, SortedBoxes, acceleration_at, sweep_and_prune};

/// What is wrong with the initial state, in words naming the bodies by id.
pub fn check_start(bodies: &[BodyState], settings: &SimulationSettings) -> Result<(), String> {
    if let Some(b) = bodies
        .iter()
        .find(|b| !(b.position.is_finite() && b.velocity.is_finite()))
    {
        return Err(format!(
            "body {} starts with a non-finite state (position {}, velocity {})",
            b.id.0, b.position, b.velocity
        ));
    }
    let boxes: Vec<Aabb> = bodies.iter().map(|b| Aabb::new(b.position, b.half_extents)).collect();
    let execution = Execution::new(ExecutionMode::Sequential, 1).map_err(|e| e.to_string())?;
    let pairs = sweep_and_prune(boxes.as_slice(), &execution, &mut SortedBoxes::default())
        .map_err(|e| format!("at the start, {e}"))?;
    let softening2 = f64::from(settings.softening).powi(2);
    for (i, j) in pairs {
        let (a, b) = (&bodies[i as usize], &bodies[j as usize]);
        for (pulled, source) in [(a, b), (b, a)] {
            if !(pulled.role.is_adopter() && source.role.is_source()) {
                continue;
            }
            let source = GravitySource {
                id: source.id,
                position: source.position.as_dvec3(),
                gm: f64::from(settings.gravitational_constant) * f64::from(source.mass),
            };
            let kick = acceleration_at(pulled.id, pulled.position, &[source], softening2) * settings.time_step;
            if !(pulled.velocity + kick).is_finite() {
                return Err(format!(
                    "bodies {} and {} are {:e} apart: the first pull between them overflows; \
                     move them apart or set `softening`",
                    pulled.id.0,
                    source.id.0,
                    pulled.position.distance(source.position.as_vec3())
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::{BodyId, GravityRole};

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
        assert!(e.starts_with("bodies 0 and 1 are 9.999973e-21 apart"), "{e}");
        let softened = SimulationSettings {
            softening: 1.0,
            ..settings.clone()
        };
        assert_eq!(check_start(&close, &softened), Ok(()));
        // Adopters pull nothing.
        let adopters = [body(0, 0.0, GravityRole::Adopter), body(1, 1e-20, GravityRole::Adopter)];
        assert_eq!(check_start(&adopters, &settings), Ok(()));
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
