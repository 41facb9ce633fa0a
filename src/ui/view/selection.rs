//! Selecting a body: a click casts a ray from the camera, the nearest box it
//! hits is selected and shown in the panel; the follow camera tracks it.
//! The selection is the body's id ([`BodyId`]), not its entity: an entity
//! is where a body is stored, and a body can come to be stored by another
//! (a rewind or a restarted scene spawns every body anew), so the entity
//! is checked, and looked up again where it changed, after every
//! simulation step ([`follow_selection`]). The window's other holders of a
//! body — trails, the celestial spheres — do the same.

use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;

use super::main_camera::MainCamera;
use crate::components::{BodyId, GravityRole, HalfExtents, Mass, Position, Velocity};
use crate::ui::session::SandboxState;
use crate::ui::sets::SandboxSystems;

/// The selected body, if any.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    /// Its id.
    pub id: Option<BodyId>,
    /// The entity that holds it now, found again after each simulation
    /// step ([`follow_selection`]); `None` once the body is gone (it
    /// shattered, or was removed).
    pub entity: Option<Entity>,
    /// The scene it was selected in (`SandboxState::generation`): in a
    /// scene built anew its id names another body.
    pub scene: u64,
}

impl Selection {
    /// Selects body `id`, held by `entity`, in scene `scene`.
    pub fn select(&mut self, id: BodyId, entity: Entity, scene: u64) {
        *self = Self {
            id: Some(id),
            entity: Some(entity),
            scene,
        };
    }

    /// Selects nothing.
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

/// Picking a body with the mouse.
pub struct SelectionPlugin;

impl Plugin for SelectionPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Selection>().add_systems(
            Update,
            (
                follow_selection
                    .after(SandboxSystems::Simulate)
                    .before(SandboxSystems::View),
                select_on_click.in_set(SandboxSystems::View),
            ),
        );
    }
}

/// Cursor travel in pixels up to which a press and release count as a click
/// (more is a camera drag).
const CLICK_SLOP: f32 = 4.0;

/// Distance along the ray (`origin + t·direction`) at which it enters the
/// box `center ± half`, if it hits it in front of the origin (slab test).
pub fn ray_box(origin: Vec3, direction: Vec3, center: Vec3, half: Vec3) -> Option<f32> {
    let inv = direction.recip();
    let t1 = (center - half - origin) * inv;
    let t2 = (center + half - origin) * inv;
    let near = t1.min(t2).max_element();
    let far = t1.max(t2).min_element();
    (far >= near.max(0.0) && !near.is_nan()).then_some(near.max(0.0))
}

/// Index and distance of the nearest box hit by the ray.
pub fn nearest_hit(origin: Vec3, direction: Vec3, boxes: impl Iterator<Item = (Vec3, Vec3)>) -> Option<(usize, f32)> {
    boxes
        .enumerate()
        .filter_map(|(i, (c, h))| ray_box(origin, direction, c, h).map(|t| (i, t)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Finds the entity that holds the selected body now: the same as before
/// unless the body came to be held by another (one pass over the bodies
/// then); clears the selection when the body is gone, or the scene was
/// built anew (where the ids name other bodies).
pub fn follow_selection(
    mut selection: ResMut<Selection>,
    bodies: Query<(Entity, &BodyId)>,
    state: Option<Res<SandboxState>>,
) {
    let Some(id) = selection.id else {
        return;
    };
    if state.is_some_and(|state| state.generation != selection.scene) {
        selection.clear();
        return;
    }
    let mut held = [(id, selection.entity.unwrap_or(Entity::PLACEHOLDER))];
    find_holders(
        &mut held,
        |entity| bodies.get(entity).ok().map(|(_, id)| *id),
        bodies.iter().map(|(entity, id)| (entity, *id)),
    );
    let [(_, entity)] = held;
    if entity == Entity::PLACEHOLDER {
        selection.clear();
    } else if selection.entity != Some(entity) {
        let scene = selection.scene;
        selection.select(id, entity, scene);
    }
}

/// Makes each `(id, entity)` of `followed` name the entity that holds
/// body `id` now: kept where `holds(entity)` is `id` (every frame, as a
/// rule), else found in one pass over `all` (each body's entity and id);
/// [`Entity::PLACEHOLDER`] where the body is gone. The selection and the
/// trails follow their bodies with it.
pub fn find_holders(
    followed: &mut [(BodyId, Entity)],
    holds: impl Fn(Entity) -> Option<BodyId>,
    all: impl IntoIterator<Item = (Entity, BodyId)>,
) {
    if followed.iter().all(|&(id, entity)| holds(entity) == Some(id)) {
        return;
    }
    let mut found: HashMap<BodyId, Entity> = followed.iter().map(|&(id, _)| (id, Entity::PLACEHOLDER)).collect();
    for (entity, id) in all {
        if let Some(slot) = found.get_mut(&id) {
            *slot = entity;
        }
    }
    for (id, entity) in followed {
        *entity = found[id];
    }
}

/// Selects the body under the cursor on a left click that was not a drag
/// and not on the panel.
pub fn select_on_click(
    buttons: Res<ButtonInput<MouseButton>>,
    window: Single<&Window>,
    camera: Single<(&Camera, &GlobalTransform), With<MainCamera>>,
    egui: Res<EguiWantsInput>,
    bodies: Query<(Entity, &BodyId, &Position, &HalfExtents)>,
    mut pressed_at: Local<Option<Vec2>>,
    // The selection, and the scene it is made in.
    (mut selection, state): (ResMut<Selection>, Res<SandboxState>),
) {
    let cursor = window.cursor_position();
    if buttons.just_pressed(MouseButton::Left) {
        *pressed_at = cursor.filter(|_| !egui.wants_pointer_input());
    }
    if !buttons.just_released(MouseButton::Left) {
        return;
    }
    let (Some(start), Some(end)) = (pressed_at.take(), cursor) else {
        return;
    };
    if start.distance(end) > CLICK_SLOP {
        return;
    }
    let (camera, camera_transform) = *camera;
    let Ok(ray) = camera.viewport_to_world(camera_transform, end) else {
        return;
    };
    let candidates: Vec<(Entity, BodyId, Vec3, Vec3)> = bodies
        .iter()
        .map(|(entity, id, position, half)| (entity, *id, position.0, half.0))
        .collect();
    let hit = nearest_hit(ray.origin, *ray.direction, candidates.iter().map(|&(.., c, h)| (c, h)));
    match hit.map(|(i, _)| candidates[i]) {
        Some((entity, id, ..)) => selection.select(id, entity, state.generation),
        None => selection.clear(),
    }
}

/// What the panel shows of the selected body.
#[derive(Clone, Copy, Debug)]
pub struct SelectedInfo {
    /// Its id.
    pub id: BodyId,
    /// Its mass.
    pub mass: f32,
    /// Its speed, length units per unit of time.
    pub speed: f32,
    /// Where it is.
    pub position: Vec3,
    /// Its gravity role.
    pub role: GravityRole,
}

/// The selected body's data, or `None` (and the selection cleared) if it
/// no longer exists, e.g. because it shattered.
pub fn selected_info(
    selection: &mut Selection,
    bodies: &Query<(&BodyId, &Mass, &Velocity, &Position, Option<&GravityRole>)>,
) -> Option<SelectedInfo> {
    let entity = selection.entity?;
    match bodies.get(entity) {
        Ok((id, mass, velocity, position, role)) => Some(SelectedInfo {
            id: *id,
            mass: mass.0,
            speed: velocity.0.length(),
            position: position.0,
            role: GravityRole::of(role),
        }),
        Err(_) => {
            selection.clear();
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A world of bodies with ids `ids`, spawned anew (as a rewind does),
    /// and the entity holding each.
    fn respawn(world: &mut World, ids: &[u64]) -> Vec<(BodyId, Entity)> {
        let old: Vec<Entity> = world.query_filtered::<Entity, With<BodyId>>().iter(world).collect();
        for entity in old {
            world.despawn(entity);
        }
        ids.iter()
            .map(|&id| (BodyId(id), world.spawn(BodyId(id)).id()))
            .collect()
    }

    /// Runs the world's one `follow_selection` (registered on the first
    /// call, so that it keeps its state); the selection after it.
    fn follow(world: &mut World) -> Selection {
        let system = match world.get_resource::<Follow>() {
            Some(Follow(system)) => *system,
            None => {
                let system = world.register_system(follow_selection);
                world.insert_resource(Follow(system));
                system
            }
        };
        world.run_system(system).unwrap();
        *world.resource::<Selection>()
    }

    #[derive(Resource)]
    struct Follow(bevy::ecs::system::SystemId);

    #[test]
    fn the_selection_follows_its_body_to_another_entity_and_ends_with_it() {
        let mut world = World::new();
        world.init_resource::<Selection>();
        let before = respawn(&mut world, &[0, 1, 2, 3, 4]);
        world.resource_mut::<Selection>().select(before[3].0, before[3].1, 0);
        assert_eq!(follow(&mut world).entity, Some(before[3].1), "held where it was");
        // Every body spawned anew, in another order: id 3 is held by
        // another entity now.
        let after = respawn(&mut world, &[4, 3, 2, 1, 0]);
        assert_ne!(after[1].1, before[3].1);
        let followed = follow(&mut world);
        assert_eq!((followed.id, followed.entity), (Some(BodyId(3)), Some(after[1].1)));
        // Gone (shattered): nothing selected.
        world.despawn(after[1].1);
        assert_eq!(follow(&mut world), Selection::default());
    }

    #[test]
    fn a_scene_built_anew_ends_the_selection() {
        let mut world = World::new();
        world.init_resource::<Selection>();
        let settings = crate::ui::session::SandboxSettings::default();
        world.insert_resource(SandboxState::new(
            crate::scenario::Scenario::builtin_default(),
            &settings,
        ));
        let bodies = respawn(&mut world, &[0, 1, 2]);
        world.resource_mut::<Selection>().select(bodies[1].0, bodies[1].1, 0);
        assert_eq!(follow(&mut world).id, Some(BodyId(1)), "a rewind keeps it");
        // Another scene: its body 1 is another body.
        respawn(&mut world, &[0, 1, 2]);
        world.resource_mut::<SandboxState>().generation += 1;
        assert_eq!(follow(&mut world), Selection::default());
    }

    #[test]
    fn ray_enters_box_at_its_near_face() {
        let t = ray_box(Vec3::new(-10.0, 0.5, 0.0), Vec3::X, Vec3::ZERO, Vec3::ONE).unwrap();
        assert!((t - 9.0).abs() < 1e-6, "{t}");
    }

    #[test]
    fn ray_misses_box_beside_it_and_behind_it() {
        assert!(ray_box(Vec3::new(-10.0, 2.5, 0.0), Vec3::X, Vec3::ZERO, Vec3::ONE).is_none());
        assert!(ray_box(Vec3::new(10.0, 0.0, 0.0), Vec3::X, Vec3::ZERO, Vec3::ONE).is_none());
    }

    #[test]
    fn ray_from_inside_hits_at_zero() {
        assert_eq!(ray_box(Vec3::ZERO, Vec3::Y, Vec3::ZERO, Vec3::ONE), Some(0.0));
    }

    #[test]
    fn diagonal_ray_hits_a_corner_region() {
        let dir = Vec3::new(1.0, 1.0, 1.0).normalize();
        let t = ray_box(Vec3::splat(-5.0), dir, Vec3::ZERO, Vec3::ONE).unwrap();
        // Enters at (-1, -1, -1): distance sqrt(3) * 4.
        assert!((t - 4.0 * 3f32.sqrt()).abs() < 1e-5, "{t}");
    }

    #[test]
    fn nearest_of_several_boxes_on_the_ray_wins() {
        let boxes = [
            (Vec3::new(30.0, 0.0, 0.0), Vec3::ONE),
            (Vec3::new(10.0, 0.0, 0.0), Vec3::ONE),
            (Vec3::new(20.0, 0.0, 0.0), Vec3::splat(5.0)),
            (Vec3::new(5.0, 9.0, 0.0), Vec3::ONE),
        ];
        let (i, t) = nearest_hit(Vec3::ZERO, Vec3::X, boxes.into_iter()).unwrap();
        assert_eq!(i, 1);
        assert!((t - 9.0).abs() < 1e-6);
    }
}
