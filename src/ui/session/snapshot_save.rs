//! "Save scenario…" in the panel: the running state written as a snapshot
//! scenario (`crate::scenario::write_snapshot`), the same file
//! `kessler headless --save-scenario` writes, with the events still to
//! come; and "Save session…": the scenario the scene started from with
//! every event of the run, the scenario's and those the tools recorded
//! (`crate::scenario::write_session`), which replays to the window's
//! states. A file that exists already is never overwritten: the panel says
//! so instead.

use std::path::PathBuf;

use bevy::prelude::*;

use super::scene::SandboxState;
use crate::components::{BodyState, BodyStateQuery};
use crate::output::{check_new, write_atomically};
use crate::resources::{NextBodyId, SimulationSettings};
use crate::scenario::{Snapshot, write_session, write_snapshot};
use crate::systems::UpdateCount;
use crate::timed_events::EventQueue;
use crate::ui::sets::SandboxSystems;

/// A save the panel asked for, and how the last one went.
#[derive(Resource, Debug, Default)]
pub struct SnapshotSave {
    /// Where to save the state at the end of this frame.
    pub requested: Option<PathBuf>,
    /// Where to save the session at the end of this frame.
    pub session_requested: Option<PathBuf>,
    /// What happened to the last save, for the panel.
    pub outcome: Option<Result<String, String>>,
}

/// Saves the running state when the panel asks.
pub struct SnapshotSavePlugin;

impl Plugin for SnapshotSavePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SnapshotSave>()
            .init_resource::<EventQueue>()
            .init_resource::<UpdateCount>()
            .add_systems(Update, save_snapshot.after(SandboxSystems::Simulate));
    }
}

/// Saves the state, or the session, where the panel asked.
fn save_snapshot(
    mut save: ResMut<SnapshotSave>,
    state: Res<SandboxState>,
    updates: Res<UpdateCount>,
    physics: Res<SimulationSettings>,
    next_id: Res<NextBodyId>,
    queue: Res<EventQueue>,
    bodies: Query<BodyStateQuery>,
) {
    if let Some(path) = save.session_requested.take() {
        let session = queue.session(&state.started_from);
        let outcome = check_new("save", &path, "choose another name: saves never overwrite")
            .map_err(|e| e.to_string())
            .and_then(|()| {
                write_atomically(&path, |w| write_session(&session, updates.0, w)).map_err(|e| e.to_string())
            })
            .map(|()| {
                format!(
                    "saved the session ({} events) to {}",
                    session.events.len(),
                    path.display()
                )
            });
        save.outcome = Some(outcome);
    }
    let Some(path) = save.requested.take() else {
        return;
    };
    let mut states: Vec<BodyState> = bodies.iter().map(BodyState::from_components).collect();
    states.sort_unstable_by_key(|b| b.id);
    let pending = queue.pending(updates.0, &states, next_id.0);
    let snapshot = Snapshot {
        name: &state.scenario.name,
        updates: updates.0,
        settings: &physics,
        bodies: &states,
        next_id: next_id.0,
        events: &pending.events,
        left_out: &pending.left_out,
    };
    let outcome = check_new("save", &path, "choose another name: saves never overwrite")
        .map_err(|e| e.to_string())
        .and_then(|()| write_atomically(&path, |w| write_snapshot(&snapshot, w)).map_err(|e| e.to_string()))
        .map(|()| format!("saved {} bodies to {}", states.len(), path.display()));
    save.outcome = Some(outcome);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;
    use crate::simulation::spawn_bodies;
    use crate::ui::session::sandbox_settings::SandboxSettings;

    #[test]
    fn a_saved_snapshot_loads_back_and_an_existing_file_is_kept() {
        let dir = tempfile::tempdir().unwrap();
        let scenario = Scenario::builtin_default().with_generated(50).unwrap();
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .insert_resource(SandboxState::new(scenario.clone(), &SandboxSettings::default()))
            .insert_resource(scenario.settings())
            .add_plugins(SnapshotSavePlugin);
        spawn_bodies(app.world_mut(), &scenario.bodies().unwrap());
        let path = dir.path().join("saved.ron");
        app.world_mut().resource_mut::<SnapshotSave>().requested = Some(path.clone());
        app.update();
        let outcome = app.world_mut().resource_mut::<SnapshotSave>().outcome.take();
        assert!(matches!(outcome, Some(Ok(_))), "{outcome:?}");
        let loaded = Scenario::load(&path).unwrap();
        assert_eq!(loaded.bodies().unwrap(), scenario.bodies().unwrap());
        assert_eq!(loaded.name, scenario.name);

        let before = std::fs::read_to_string(&path).unwrap();
        app.world_mut().resource_mut::<SnapshotSave>().requested = Some(path.clone());
        app.update();
        let outcome = app.world_mut().resource_mut::<SnapshotSave>().outcome.take();
        assert!(
            matches!(&outcome, Some(Err(e)) if e.contains("exists already")),
            "{outcome:?}"
        );
        assert_eq!(std::fs::read_to_string(&path).unwrap(), before);
    }
}
