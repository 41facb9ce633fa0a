//! "Save scenario…" in the panel: the running state written as a snapshot
//! scenario (`crate::scenario::write_snapshot`), the same file
//! `kessler headless --save-scenario` writes, with the events still to
//! come; and "Save session…": the scenario the scene started from with
//! every event of the run, the scenario's and those the tools recorded
//! (`crate::scenario::write_session`), which replays to the window's
//! states. A file that exists already is never overwritten: the panel says
//! so instead. A save that fails is said on stderr too, and the run ends
//! with exit status 1 ([`OutputFailures`]), scripted or not.

use std::path::PathBuf;

use bevy::ecs::system::SystemParam;
use bevy::prelude::*;

use super::output_failures::OutputFailures;
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
    /// Where to save the session at the end of this frame: each, in the
    /// order asked (a script may ask for several in one frame).
    pub session_requested: Vec<PathBuf>,
    /// What happened to the last save, for the panel.
    pub outcome: Option<Result<String, String>>,
}

/// Saves the running state when the panel asks.
pub struct SnapshotSavePlugin;

impl Plugin for SnapshotSavePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SnapshotSave>()
            .init_resource::<OutputFailures>()
            .init_resource::<EventQueue>()
            .init_resource::<UpdateCount>()
            .add_systems(Update, save_snapshot.after(SandboxSystems::Simulate));
    }
}

/// What a save writes: the run's updates, physics, next id, events and
/// bodies.
#[derive(SystemParam)]
struct RunNow<'w, 's> {
    updates: Res<'w, UpdateCount>,
    physics: Res<'w, SimulationSettings>,
    next_id: Res<'w, NextBodyId>,
    queue: Res<'w, EventQueue>,
    bodies: Query<'w, 's, BodyStateQuery>,
}

/// Saves the state, or the session, where the panel asked.
fn save_snapshot(mut save: ResMut<SnapshotSave>, state: Res<SandboxState>, run: RunNow, failures: Res<OutputFailures>) {
    let RunNow {
        updates,
        physics,
        next_id,
        queue,
        bodies,
    } = run;
    for path in std::mem::take(&mut save.session_requested) {
        let session = queue.session(&state.started_from);
        let outcome = check_new("the file", &path, "choose another name: saves never overwrite")
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
        if let Err(e) = &outcome {
            failures.failed(format_args!("cannot save the session: {e}"));
        }
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
    let outcome = check_new("the file", &path, "choose another name: saves never overwrite")
        .map_err(|e| e.to_string())
        .and_then(|()| write_atomically(&path, |w| write_snapshot(&snapshot, w)).map_err(|e| e.to_string()))
        .map(|()| format!("saved {} bodies to {}", states.len(), path.display()));
    if let Err(e) = &outcome {
        failures.failed(format_args!("cannot save the scenario: {e}"));
    }
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
