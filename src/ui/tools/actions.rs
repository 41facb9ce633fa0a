//! The tools: launch, fire, break up, remove, rewind. The panel's buttons,
//! their keys and a scripted run (`--actions`) send the same
//! [`ToolAction`] message; each tool makes the event it stands for at the
//! update the run is at and records it ([`record_event`]), so that the
//! window and a saved session go through one path (docs/design.md,
//! "Events").

use std::path::PathBuf;

use bevy::math::DVec3;
use bevy::prelude::*;
use serde::Deserialize;

use super::rewind::rewind;
use crate::components::{BodyId, BodyState, BodyStateQuery, GravityRole, Mass};
use crate::maths;
use crate::resources::SimulationSettings;
use crate::scenario::{Body, Breakup, Event, Fire, Remove, Shape, Spawn, Template};
use crate::systems::UpdateCount;
use crate::timed_events::{EventLog, EventQueue, Queued, record_event};
use crate::ui::session::{SandboxState, SnapshotSave};
use crate::ui::view::{MainCamera, Selection};

/// What a tool does, as the buttons, the keys and a script ask for it.
#[derive(Message, Clone, Debug, PartialEq, Deserialize)]
pub enum ToolAction {
    /// Satellites on circular orbits around the heaviest source: `count`
    /// evenly spaced on one ring (1: one satellite), `altitude` above its
    /// surface, the ring tilted `inclination` degrees from its equator
    /// (the x–z plane), each a cube of half extent `half_size` and `mass`.
    Launch {
        /// Above the source's surface.
        altitude: f32,
        /// Degrees from the equator.
        inclination: f32,
        /// Satellites on the ring.
        count: u32,
        /// Half the edge of each.
        half_size: f32,
        /// Mass of each.
        mass: f32,
    },
    /// An impactor at the selected body, `distance` away, `speed` towards
    /// it; from where the camera is (`from_camera`) or a seeded direction.
    Fire {
        /// Towards the target, relative to it.
        speed: f32,
        /// From the target's center.
        distance: f32,
        /// From the camera's side, else a seeded direction.
        from_camera: bool,
    },
    /// The selected body explodes into `fragments` at about `speed`.
    Breakup {
        /// How many fragments.
        fragments: u32,
        /// About how fast they fly apart.
        speed: f32,
    },
    /// The selected body is taken away.
    Remove,
    /// Back to the previous checkpoint; the events recorded after it are
    /// dropped.
    Rewind,
    /// Selects the body with this id (scripts; a click selects in the
    /// window).
    Select(u64),
    /// *Save session…*: the scenario the scene started from with every
    /// event so far, to this new file.
    SaveSession(PathBuf),
}

/// Applies the tool actions sent this frame, in order.
pub fn apply_tool_actions(world: &mut World) {
    let actions: Vec<ToolAction> = world.resource_mut::<Messages<ToolAction>>().drain().collect();
    for action in actions {
        let outcome = apply_action(world, &action);
        if let Err(why) = &outcome {
            warn!("{why}");
        }
        world.resource_mut::<SandboxState>().tool_problem = outcome.err();
    }
}

/// One action: the event it makes, recorded and applied at once (or the
/// rewind, or the selection); why not, if it cannot.
fn apply_action(world: &mut World, action: &ToolAction) -> Result<(), String> {
    let update = world.resource::<UpdateCount>().0;
    let event = match *action {
        ToolAction::Launch {
            altitude,
            inclination,
            count,
            half_size,
            mass,
        } => {
            let source = heaviest_source(world).ok_or("launch: there is no source to orbit")?;
            let settings = world.resource::<SimulationSettings>();
            let (g, max_bodies) = (settings.gravitational_constant, settings.max_bodies);
            // Counted before the ring is built: a count past the budget
            // would only be refused after it was made.
            if u64::from(count) > max_bodies {
                return Err(format!(
                    "launch: {count} satellites would be more than `max_bodies` ({max_bodies})"
                ));
            }
            Event::Spawn(Spawn {
                update,
                bodies: ring(&source, g, altitude, inclination, count, half_size, mass),
                generators: Vec::new(),
            })
        }
        ToolAction::Fire {
            speed,
            distance,
            from_camera,
        } => {
            let target = selected(world).ok_or("fire: select a body first")?;
            let from = if from_camera {
                camera_side(world, target.position)
            } else {
                None
            };
            Event::Fire(Fire {
                update,
                target: target.id.0,
                speed,
                distance,
                from,
                body: Template::default(),
            })
        }
        ToolAction::Breakup { fragments, speed } => {
            let target = selected(world).ok_or("break up: select a body first")?;
            Event::Breakup(Breakup {
                update,
                body: target.id.0,
                fragments,
                speed,
                sizes: None,
            })
        }
        ToolAction::Remove => {
            let target = selected(world).ok_or("remove: select a body first")?;
            Event::Remove(Remove {
                update,
                body: target.id.0,
            })
        }
        ToolAction::Rewind => return rewind(world),
        ToolAction::Select(id) => {
            let entity = world
                .query::<(Entity, &BodyId)>()
                .iter(world)
                .find(|(_, b)| b.0 == id)
                .map(|(e, _)| e)
                .ok_or_else(|| format!("select: there is no body {id}"))?;
            let scene = world.resource::<SandboxState>().generation;
            world.resource_mut::<Selection>().select(BodyId(id), entity, scene);
            return Ok(());
        }
        ToolAction::SaveSession(ref path) => {
            world
                .resource_mut::<SnapshotSave>()
                .session_requested
                .push(path.clone());
            return Ok(());
        }
    };
    record_checked(world, event)
}

/// Records a tool's `event` and applies it, held to a file event's rules
/// first; one that is refused or skipped is not recorded (a saved session
/// holds only what happened, and `validate` accepts it).
fn record_checked(world: &mut World, event: Event) -> Result<(), String> {
    // What a file's event may not hold, a tool's may not either.
    event
        .check()
        .map_err(|problem| format!("{}: {problem}", event.kind()))?;
    let before = world.resource::<EventLog>().clone();
    record_event(world, event);
    // Applied last of its update's events: if it was skipped, it is the
    // last skipped.
    let mut log = world.resource::<EventLog>().clone();
    let ours = log.skipped > before.skipped
        && log
            .last_skipped
            .as_deref()
            .is_some_and(|why| why.starts_with(Queued::RECORDED));
    if ours {
        // It did nothing: not recorded, so that a saved session holds only
        // what happened (and `validate` accepts it).
        world.resource_mut::<EventQueue>().forget_last_applied_recorded();
        let why = log.last_skipped.clone().unwrap_or_default();
        log.skipped -= 1;
        if before.first_skipped.is_none() && log.skipped == before.skipped {
            log.first_skipped = None;
        }
        log.last_skipped = before.last_skipped;
        world.insert_resource(log);
        return Err(why);
    }
    world.resource_mut::<SandboxState>().edits += 1;
    Ok(())
}

/// The selected body's state, if it still exists.
fn selected(world: &mut World) -> Option<BodyState> {
    let Selection { id, entity, .. } = *world.resource::<Selection>();
    let mut query = world.query::<BodyStateQuery>();
    let body = query.get(world, entity?).ok().map(BodyState::from_components)?;
    // The entity is found again after each simulation step: it holds the
    // selected body unless something in between rewrote the rows.
    (Some(body.id) == id).then_some(body)
}

/// The direction from `target` to the camera, if there is a camera away
/// from it.
fn camera_side(world: &mut World, target: Vec3) -> Option<[f32; 3]> {
    let mut cameras = world.query_filtered::<&GlobalTransform, With<MainCamera>>();
    let camera = cameras.iter(world).next()?.translation();
    let side = (camera - target).normalize_or_zero();
    (side != Vec3::ZERO).then(|| side.to_array())
}

/// The heaviest body that attracts (the planet a launch orbits).
fn heaviest_source(world: &mut World) -> Option<BodyState> {
    let mut sources = world.query::<(Entity, &BodyId, &Mass, Option<&GravityRole>)>();
    let (heaviest, ..) = sources
        .iter(world)
        .filter(|(.., role)| GravityRole::of(*role).is_source())
        .max_by(|(_, a_id, a, _), (_, b_id, b, _)| a.0.total_cmp(&b.0).then(b_id.cmp(a_id)))?;
    let mut bodies = world.query::<BodyStateQuery>();
    bodies.get(world, heaviest).ok().map(BodyState::from_components)
}

/// `count` satellites evenly spaced on a circular orbit `altitude` above
/// `source`'s surface (its half extent along x: a ball's radius), its plane
/// the equator (x–z) tilted `inclination` degrees about the x axis; each at
/// exactly the circular speed `√(G·M/r)` relative to the source, prograde
/// as a `Shell`'s orbits.
pub fn ring(
    source: &BodyState,
    g: f32,
    altitude: f32,
    inclination: f32,
    count: u32,
    half_size: f32,
    mass: f32,
) -> Vec<Body> {
    let r = f64::from(source.half_extents.x) + f64::from(altitude) + f64::from(half_size) * 3f64.sqrt();
    let speed = (f64::from(g) * f64::from(source.mass) / r).sqrt();
    let plane = maths::rotation_x(f64::from(inclination).to_radians());
    let normal = plane * DVec3::Y;
    let (center, center_velocity) = (source.position.as_dvec3(), source.velocity.as_dvec3());
    (0..count.max(1))
        .map(|k| {
            let angle = std::f64::consts::TAU * f64::from(k) / f64::from(count.max(1));
            let (sin, cos) = maths::sin_cos(angle);
            let radial = plane * DVec3::new(cos, 0.0, sin);
            Body {
                id: None,
                position: (center + radial * r).as_vec3().to_array(),
                previous_position: None,
                velocity: (center_velocity + normal.cross(radial) * speed).as_vec3().to_array(),
                half_extents: Some([half_size; 3]),
                shape: Shape::Box,
                mass,
                role: GravityRole::Adopter,
                interacts: true,
                absorbs: false,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_launched_ring_is_evenly_spaced_on_circular_orbits() {
        let planet = BodyState {
            spherical: true,
            ..BodyState::new_box(
                BodyId(0),
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
                4000.0,
                Vec3::splat(430.0),
                GravityRole::Source,
                false,
            )
        };
        let bodies = ring(&planet, 6.674, 300.0, 30.0, 12, 1.0, 2.0);
        assert_eq!(bodies.len(), 12);
        for body in &bodies {
            let offset = Vec3::from_array(body.position) - planet.position;
            let relative = Vec3::from_array(body.velocity) - planet.velocity;
            let r = offset.length();
            assert!((r - (430.0 + 300.0 + 3f32.sqrt())).abs() < 1e-2, "{r}");
            // Circular: r·v² = G·M, the velocity across the radius.
            assert!((r * relative.length_squared() / (6.674 * 4000.0) - 1.0).abs() < 1e-5);
            assert!(offset.dot(relative).abs() < 1e-2);
            // In the plane tilted 30° from the equator.
            let normal = offset.cross(relative).normalize();
            assert!(
                (normal.dot(Vec3::Y) - 30f32.to_radians().cos()).abs() < 1e-4,
                "{normal}"
            );
        }
        let first = Vec3::from_array(bodies[0].position) - planet.position;
        let second = Vec3::from_array(bodies[1].position) - planet.position;
        assert!((first.angle_between(second) - std::f32::consts::TAU / 12.0).abs() < 1e-4);
    }
}
