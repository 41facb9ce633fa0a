//! Trails: the recent path of the selected body and, on request, of the
//! fastest bodies or the newest fragments, drawn as fading lines (one
//! line-list mesh for all of them). With no body selected and the choice
//! off, the systems return at once and keep nothing.

use std::collections::VecDeque;

use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::mesh::PrimitiveTopology;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;

use crate::components::{BodyId, NonInteracting, Position, Velocity};
use crate::systems::UpdateCount;
use crate::ui::session::SandboxState;
use crate::ui::session::UpdateClock;
use crate::ui::session::{SandboxSettings, TrailChoice};
use crate::ui::sets::SandboxSystems;
use crate::ui::view::{Selection, find_holders, follow_selection};

/// Positions kept per trail: one per frame that ran updates.
pub const TRAIL_POINTS: usize = 300;
/// Updates between two choices of the fastest or newest bodies.
const CHOOSE_EVERY: u64 = 30;

/// The paths being recorded.
#[derive(Resource, Debug, Default)]
pub struct Trails {
    /// Recent positions of each tracked body, oldest first.
    paths: HashMap<BodyId, VecDeque<Vec3>>,
    /// The bodies the choice picked (each with the entity that held it
    /// when last looked up, see `ui/view/selection.rs`), and when.
    chosen: Vec<(BodyId, Entity)>,
    chosen_at: Option<(u64, TrailChoice, u32)>,
    /// The update count at the last recording, and the scene it was in.
    recorded_at: (u64, u64),
    /// The simulation's own update count then: less now after a rewind.
    simulated: u64,
    /// True when the lines need rebuilding.
    dirty: bool,
}

impl Trails {
    /// Number of bodies with a trail.
    pub fn len(&self) -> usize {
        self.paths.len()
    }

    /// True when no body has a trail.
    pub fn is_empty(&self) -> bool {
        self.paths.is_empty()
    }
}

/// The one mesh that draws every trail.
#[derive(Component, Debug)]
pub struct TrailLines;

/// Records and draws trails.
pub struct TrailsPlugin;

impl Plugin for TrailsPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Trails>()
            .add_systems(Startup, spawn_trail_lines)
            .add_systems(
                Update,
                (record_trails, draw_trails)
                    .chain()
                    .after(follow_selection)
                    .before(SandboxSystems::View),
            );
    }
}

/// Kernel: the bodies a choice picks, at most `count`: the fastest
/// interacting bodies (fastest first), or the fragments (ids from
/// `first_fragment_id`) born last (newest first). Ties go to the lower id.
pub fn pick(
    choice: TrailChoice,
    count: usize,
    first_fragment_id: u64,
    bodies: impl Iterator<Item = (Entity, BodyId, Vec3, bool)>,
) -> Vec<(BodyId, Entity)> {
    // Sorted by the first two, ties to the lower second.
    let mut candidates: Vec<(f32, u64, BodyId, Entity)> = match choice {
        TrailChoice::Off => return Vec::new(),
        TrailChoice::Fastest => bodies
            .filter(|&(.., interacts)| interacts)
            .map(|(e, id, v, _)| (-v.length_squared(), id.0, id, e))
            .collect(),
        TrailChoice::Newest => bodies
            .filter(|&(_, id, ..)| id.0 >= first_fragment_id)
            .map(|(e, id, ..)| (0.0, u64::MAX - id.0, id, e))
            .collect(),
    };
    let order =
        |a: &(f32, u64, BodyId, Entity), b: &(f32, u64, BodyId, Entity)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    if candidates.len() > count && count > 0 {
        candidates.select_nth_unstable_by(count - 1, order);
    }
    candidates.truncate(count);
    candidates.sort_unstable_by(order);
    candidates.into_iter().map(|(.., id, e)| (id, e)).collect()
}

fn spawn_trail_lines(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.spawn((
        Name::new("Trails"),
        TrailLines,
        Mesh3d(meshes.add(lines(&HashMap::default(), None))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::WHITE,
            unlit: true,
            alpha_mode: AlphaMode::Blend,
            ..default()
        })),
        Transform::default(),
        NoFrustumCulling,
        Visibility::Hidden,
    ));
}

/// Adds the bodies' positions after each frame that ran updates; forgets
/// paths of bodies no longer tracked (shattered, deselected, not chosen).
fn record_trails(
    mut trails: ResMut<Trails>,
    settings: Res<SandboxSettings>,
    selection: Res<Selection>,
    clock: Res<UpdateClock>,
    state: Res<SandboxState>,
    bodies: Query<(Entity, &BodyId, &Position, &Velocity, Has<NonInteracting>)>,
    simulated: Res<UpdateCount>,
) {
    if settings.trails == TrailChoice::Off && selection.id.is_none() {
        if !trails.paths.is_empty() {
            trails.paths.clear();
            trails.chosen.clear();
            trails.chosen_at = None;
            trails.dirty = true;
        }
        return;
    }
    let now = (clock.updates_total, state.generation);
    if trails.recorded_at == now && !trails.paths.is_empty() {
        return;
    }
    // A scene built anew, or a rewind: the paths so far lead elsewhere.
    if trails.recorded_at.1 != now.1 || simulated.0 < trails.simulated {
        trails.paths.clear();
        trails.chosen_at = None;
    }
    trails.recorded_at = now;
    trails.simulated = simulated.0;
    let wanted = (settings.trails, settings.trail_count);
    let due = match trails.chosen_at {
        Some((at, choice, count)) => (choice, count) != wanted || now.0 >= at + CHOOSE_EVERY,
        None => true,
    };
    if due {
        trails.chosen = pick(
            settings.trails,
            settings.trail_count as usize,
            state.first_fragment_id,
            bodies
                .iter()
                .map(|(e, id, _, v, non_interacting)| (e, *id, v.0, !non_interacting)),
        );
        trails.chosen_at = Some((now.0, wanted.0, wanted.1));
    }
    // Where a chosen body came to be held by another entity, it is found
    // again; one gone (shattered, absorbed) is no longer tracked.
    find_holders(
        &mut trails.chosen,
        |entity| bodies.get(entity).ok().map(|(_, id, ..)| *id),
        bodies.iter().map(|(entity, id, ..)| (entity, *id)),
    );
    trails.chosen.retain(|&(_, entity)| entity != Entity::PLACEHOLDER);
    let mut tracked = trails.chosen.clone();
    tracked.extend(selection.id.zip(selection.entity));
    trails
        .paths
        .retain(|id, _| tracked.iter().any(|(tracked, _)| tracked == id));
    for (id, entity) in tracked {
        if let Ok((_, _, position, ..)) = bodies.get(entity) {
            let path = trails.paths.entry(id).or_default();
            path.push_back(position.0);
            if path.len() > TRAIL_POINTS {
                path.pop_front();
            }
        }
    }
    trails.dirty = true;
}

/// A line list of every path, each fading from transparent (oldest) to
/// opaque (newest); the selected body's in gold, the others in cyan.
fn lines(paths: &HashMap<BodyId, VecDeque<Vec3>>, selected: Option<BodyId>) -> Mesh {
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut colors: Vec<[f32; 4]> = Vec::new();
    for (id, path) in paths {
        let [r, g, b] = if Some(*id) == selected {
            [1.0, 0.8, 0.2]
        } else {
            [0.3, 0.85, 1.0]
        };
        let n = path.len() as f32;
        for (i, pair) in path.iter().collect::<Vec<_>>().windows(2).enumerate() {
            for (k, point) in pair.iter().enumerate() {
                positions.push(point.to_array());
                colors.push([r, g, b, (i + k) as f32 / n]);
            }
        }
    }
    if positions.is_empty() {
        // A mesh without vertices has no place in the GPU's vertex slabs.
        positions = vec![[0.0; 3]; 2];
        colors = vec![[0.0; 4]; 2];
    }
    Mesh::new(
        PrimitiveTopology::LineList,
        RenderAssetUsages::RENDER_WORLD | RenderAssetUsages::MAIN_WORLD,
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colors)
}

fn draw_trails(
    mut trails: ResMut<Trails>,
    selection: Res<Selection>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut line_mesh: Query<(&Mesh3d, &mut Visibility), With<TrailLines>>,
) {
    if !std::mem::take(&mut trails.dirty) {
        return;
    }
    for (mesh, mut visibility) in &mut line_mesh {
        let empty = trails.paths.values().all(|p| p.len() < 2);
        visibility.set_if_neq(if empty {
            Visibility::Hidden
        } else {
            Visibility::Inherited
        });
        if !empty && let Err(e) = meshes.insert(&mesh.0, lines(&trails.paths, selection.id)) {
            warn!("trails: {e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bodies() -> Vec<(Entity, BodyId, Vec3, bool)> {
        (0..10u32)
            .map(|i| {
                let speed = [3.0, 9.0, 1.0, 7.0, 5.0, 8.0, 2.0, 6.0, 4.0, 0.5][i as usize];
                (
                    Entity::from_raw_u32(i + 1).unwrap(),
                    BodyId(u64::from(i) * 10),
                    Vec3::new(0.0, speed, 0.0),
                    i != 1,
                )
            })
            .collect()
    }

    #[test]
    fn picks_the_fastest_interacting_bodies_fastest_first() {
        let picked = pick(TrailChoice::Fastest, 3, 0, bodies().into_iter());
        // Body 1 (speed 9) does not interact: 5 (8), 3 (7), 7 (6).
        let ids: Vec<u32> = picked.iter().map(|(_, e)| e.index_u32() - 1).collect();
        assert_eq!(ids, [5, 3, 7]);
        assert_eq!(picked[0].0, BodyId(50));
    }

    #[test]
    fn picks_the_newest_fragments_newest_first() {
        let picked = pick(TrailChoice::Newest, 4, 65, bodies().into_iter());
        // Fragments: ids 70, 80, 90 only.
        let ids: Vec<u32> = picked.iter().map(|(_, e)| e.index_u32() - 1).collect();
        assert_eq!(ids, [9, 8, 7]);
        assert_eq!(picked[0].0, BodyId(90));
        assert!(pick(TrailChoice::Off, 4, 0, bodies().into_iter()).is_empty());
    }

    #[test]
    fn paths_become_fading_segments() {
        let mut paths = HashMap::default();
        paths.insert(BodyId(1), VecDeque::from([Vec3::ZERO, Vec3::X, Vec3::Y]));
        let mesh = lines(&paths, Some(BodyId(1)));
        assert_eq!(mesh.count_vertices(), 4, "two segments");
        let Some(bevy::mesh::VertexAttributeValues::Float32x4(colors)) = mesh.attribute(Mesh::ATTRIBUTE_COLOR) else {
            panic!("colors");
        };
        let alphas: Vec<f32> = colors.iter().map(|c| c[3]).collect();
        assert!(alphas.windows(2).all(|w| w[0] <= w[1]), "older is fainter: {alphas:?}");
    }
}
