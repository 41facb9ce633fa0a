//! What each event does to the world (docs/design.md, "Events"). Each
//! either happens in full or is skipped with the reason (the body it names
//! is gone, or what it would make is refused as a shatter would be); it
//! never half happens.

use bevy::math::DVec3;
use bevy::prelude::*;

use crate::components::{BodyId, BodyState, BodyStateQuery, NonInteracting, spawn_states};
use crate::maths;
use crate::maths::Rng;
use crate::physics::{LEAST_SOUND, box_volume, breakup_fragments, fragments_sound, smallest_fragment_edge};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::generators::{self, Obstacles};
use crate::scenario::{Body, Breakup, Event, Fire, Generator, Spawn, Template};

/// The key of the spawns' generator streams and of the impactors' default
/// directions, each then keyed by the first fresh id it hands out (never
/// the same twice, and the same in a run continued from a snapshot).
const SPAWN_STREAM: u64 = u64::MAX - 1;
/// See [`SPAWN_STREAM`].
const FIRE_STREAM: u64 = u64::MAX - 2;

/// Applies `event` to `world`; `around` maps the scenario's explicit body
/// indices to ids (a `Shell`'s `around`). `Err`: why it was skipped.
pub fn apply(world: &mut World, event: &Event, around: &[u64]) -> Result<(), String> {
    match event {
        Event::Spawn(spawn) => apply_spawn(world, spawn, around),
        Event::Fire(fire) => apply_fire(world, fire),
        Event::Breakup(breakup) => apply_breakup(world, breakup),
        Event::Remove(remove) => {
            let (entity, _) = find(world, remove.body)?;
            world.despawn(entity);
            Ok(())
        }
        Event::Set(set) => {
            set.apply(&mut world.resource_mut::<SimulationSettings>());
            Ok(())
        }
    }
}

/// The entity and state of the body with id `id`, or why there is none.
fn find(world: &mut World, id: u64) -> Result<(Entity, BodyState), String> {
    world
        .query::<(Entity, BodyStateQuery)>()
        .iter(world)
        .find(|(_, body)| body.id.0 == id)
        .map(|(entity, body)| (entity, BodyState::from_components(body)))
        .ok_or_else(|| format!("there is no body {id} (it shattered, re-entered or was removed)"))
}

/// Number of bodies now.
fn body_count(world: &mut World) -> u64 {
    world.query::<&BodyId>().iter(world).len() as u64
}

/// Spawns `made` (ids from the next id on), if the budget and the ids
/// allow; else why not.
fn add(world: &mut World, made: &[BodyState], removed: u64, what: &str) -> Result<(), String> {
    let settings = world.resource::<SimulationSettings>();
    let max_bodies = settings.max_bodies;
    let after = (body_count(world) - removed).saturating_add(made.len() as u64);
    if after > max_bodies {
        return Err(format!(
            "{what} would make {after} bodies, past `max_bodies` ({max_bodies})"
        ));
    }
    let mut next = world.resource_mut::<NextBodyId>();
    if !next.has_room_for(made.len() as u64) {
        return Err(format!("{what} would hand out ids past the largest"));
    }
    next.0 += made.len() as u64;
    spawn_states(world, made);
    Ok(())
}

/// A Spawn: its bodies, then its generators' bodies, with fresh ids in
/// that order.
fn apply_spawn(world: &mut World, spawn: &Spawn, around: &[u64]) -> Result<(), String> {
    let settings = world.resource::<SimulationSettings>().clone();
    let first = world.resource::<NextBodyId>().0;
    let mut made: Vec<BodyState> = spawn
        .bodies
        .iter()
        .enumerate()
        .map(|(j, body)| body.state(first + j as u64))
        .collect();
    let mut query = world.query_filtered::<BodyStateQuery, With<NonInteracting>>();
    let mut planets: Vec<Body> = query
        .iter(world)
        .map(|body| Body::from_state(&BodyState::from_components(body)))
        .collect();
    planets.sort_by_key(|b| b.id);
    // As a scenario's own bodies are held: none that interacts starts
    // inside one that does not (the first update would fling it out).
    let obstacles = Obstacles::new(&planets);
    for (i, body) in made.iter().enumerate().filter(|(_, b)| b.interacts) {
        if let Some(j) = obstacles.overlapped(body.position.as_dvec3(), body.half_extents.as_dvec3()) {
            return Err(format!(
                "bodies[{i}] would start inside body {} ({}), which does not interact",
                planets[j].id.unwrap_or_default(),
                planets[j].described()
            ));
        }
    }
    for (j, generator) in spawn.generators.iter().enumerate() {
        let id = first + made.len() as u64;
        let mut rng = Rng::stream(Rng::stream(settings.seed, SPAWN_STREAM).next_u64(), id);
        match generator {
            Generator::Cloud(cloud) => generators::cloud(cloud, &mut rng, id, &planets, &mut made)
                .map_err(|e| format!("generators[{j}] (Cloud): {e}"))?,
            Generator::Shell(shell) => {
                // The load checked that the index names a body.
                let source_id = around.get(shell.around).copied().unwrap_or(u64::MAX);
                let (_, source) = find(world, source_id)
                    .map_err(|e| format!("generators[{j}] (Shell) orbits bodies[{}]: {e}", shell.around))?;
                let obstacles = Obstacles::new(&planets);
                generators::shell(
                    shell,
                    &mut rng,
                    id,
                    &Body::from_state(&source),
                    &obstacles,
                    settings.gravitational_constant,
                    &mut made,
                )
                .map_err(|e| {
                    format!(
                        "generators[{j}] (Shell): body {} of the shell would start inside body {}",
                        e.body,
                        planets[e.obstacle].id.unwrap_or_default()
                    )
                })?;
            }
        }
    }
    add(world, &made, 0, "the spawn")
}

/// A Fire: the impactor about `distance` from the target in the
/// direction `from` (or a seeded one), moving at the target's velocity
/// plus `speed` towards it.
fn apply_fire(world: &mut World, fire: &Fire) -> Result<(), String> {
    let (_, target) = find(world, fire.target)?;
    let settings = world.resource::<SimulationSettings>();
    let (seed, time_step) = (settings.seed, settings.time_step);
    let id = world.resource::<NextBodyId>().0;
    let direction = match fire.from {
        Some(from) => DVec3::from_array(from.map(f64::from)).normalize(),
        None => random_direction(&mut Rng::stream(Rng::stream(seed, FIRE_STREAM).next_u64(), id)),
    };
    let impactor = impactor(&target, direction, fire, time_step, id);
    add(world, &[impactor], 0, "the impactor")
}

/// The impactor of `fire` at `target`, from `direction` (a unit vector),
/// with id `id`: `distance` away, rounded to a whole number (at least 1) of
/// updates' travel at `speed` (`time_step` long), so that its center would
/// meet the target's at an update rather than pass it between two (the
/// broad phase sees where bodies are after each update, not on the way).
pub fn impactor(target: &BodyState, direction: DVec3, fire: &Fire, time_step: f32, id: u64) -> BodyState {
    let Template {
        half_extents,
        mass,
        role,
        interacts,
    } = fire.body;
    let travel = f64::from(fire.speed) * f64::from(time_step);
    let distance = if travel > 0.0 {
        (f64::from(fire.distance) / travel).round().max(1.0) * travel
    } else {
        f64::from(fire.distance)
    };
    let position = target.position.as_dvec3() + direction * distance;
    let velocity = target.velocity.as_dvec3() - direction * f64::from(fire.speed);
    BodyState::new_box(
        BodyId(id),
        position.as_vec3(),
        velocity.as_vec3(),
        mass,
        Vec3::from_array(half_extents),
        role,
        interacts,
    )
}

/// A direction uniform on the unit sphere.
fn random_direction(rng: &mut Rng) -> DVec3 {
    let z = rng.range(-1.0, 1.0);
    let (sin, cos) = maths::sin_cos(rng.range(0.0, std::f64::consts::TAU));
    let r = (1.0 - z * z).sqrt();
    DVec3::new(r * cos, r * sin, z)
}

/// A Breakup: the body replaced by its fragments, unless they would be
/// below `min_fragment_size`, too light or small for a body, or past
/// `max_bodies` (as a shatter would be refused).
fn apply_breakup(world: &mut World, breakup: &Breakup) -> Result<(), String> {
    let (entity, body) = find(world, breakup.body)?;
    if !body.interacts {
        return Err(format!(
            "body {} does not interact (a planet): only interacting bodies break up",
            breakup.body
        ));
    }
    let settings = world.resource::<SimulationSettings>().clone();
    let sizes = breakup.sizes.unwrap_or(settings.fragment_sizes);
    let volume = box_volume(body.half_extents);
    let edge = smallest_fragment_edge(volume, sizes, breakup.fragments);
    if edge < f64::from(settings.min_fragment_size) {
        return Err(format!(
            "its fragments' edge, {edge:.3}, would be below `min_fragment_size` ({})",
            settings.min_fragment_size
        ));
    }
    if !fragments_sound(volume, f64::from(body.mass), sizes, breakup.fragments) {
        return Err(format!(
            "its fragments would be lighter or smaller than a body may be (mass and half-edge at least {LEAST_SOUND:e})"
        ));
    }
    let first = world.resource::<NextBodyId>().0;
    let made = breakup_fragments(
        &body,
        breakup.fragments,
        breakup.speed,
        sizes,
        settings.min_fragment_size,
        settings.seed,
        BodyId(first),
    );
    add(world, &made, 1, "the breakup")?;
    world.despawn(entity);
    Ok(())
}
