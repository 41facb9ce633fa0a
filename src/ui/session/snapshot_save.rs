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
use crate::simulation::Simulation;
use crate::systems::{SimulationFault, UpdateCount};
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
            .init_resource::<SimulationFault>()
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
    fault: Res<'w, SimulationFault>,
}

/// Saves the state, or the session, where the panel asked.
fn save_snapshot(mut save: ResMut<SnapshotSave>, state: Res<SandboxState>, run: RunNow, failures: Res<OutputFailures>) {
    let RunNow {
        updates,
        physics,
        next_id,
        queue,
        bodies,
        fault,
    } = run;
    for path in std::mem::take(&mut save.session_requested) {
        let session = queue.session(&state.started_from);
        let outcome = check_new("the file", &path, "choose another name: saves never overwrite")
            .map_err(|e| e.to_string())
            // What is written loads back: a start the events of update 0
            // leave that would stop at once is no session (its bodies were
            // checked when the scene was built).
            .and_then(|()| {
                Simulation::check_start_events(&session).map_err(|e| format!("{}: {}", path.display(), e.message))
            })
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
    let states = BodyState::sorted_by_id(bodies.iter());
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
    let stopped = fault.message().map(|m| {
        format!(
            "{}: the simulation is stopped ({m}): its state is half an update; restart or rewind the scene, then save",
            path.display()
        )
    });
    let outcome = stopped
        .map_or_else(
            || check_new("the file", &path, "choose another name: saves never overwrite").map_err(|e| e.to_string()),
            Err,
        )
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
        assert_eq!(
            app.world().resource::<OutputFailures>().count(),
            1,
            "the refusal is said"
        );

        // A stopped run's state is half an update: not saved.
        app.world_mut()
            .resource_mut::<SimulationFault>()
            .stop(crate::systems::Fault::NonFinite {
                id: crate::components::BodyId(3),
                what: "position",
                value: Vec3::INFINITY,
            });
        let stopped = dir.path().join("stopped.ron");
        app.world_mut().resource_mut::<SnapshotSave>().requested = Some(stopped.clone());
        app.update();
        let outcome = app.world_mut().resource_mut::<SnapshotSave>().outcome.take();
        assert!(
            matches!(&outcome, Some(Err(e)) if e.contains("the simulation is stopped") && e.contains("half an update")),
            "{outcome:?}"
        );
        assert!(!stopped.exists());
        assert_eq!(app.world().resource::<OutputFailures>().count(), 2);
    }

    /// A session whose events of update 0 leave a start that would stop at
    /// once (a pile-up) is not written: it would not load back.
    #[test]
    fn a_session_that_would_not_load_back_is_not_saved() {
        let dir = tempfile::tempdir().unwrap();
        let scenario = Scenario::parse(
            "Scenario(gravitational_constant: 0, bodies: [Body(position: (0, 0, 0))], events: [Spawn(update: 0, \
             generators: [Cloud(count: 2000, center: (50, 0, 0), half_size: (0, 0, 0))])])",
            "pile.ron",
        )
        .unwrap();
        let mut app = App::new();
        app.add_plugins(MinimalPlugins)
            .insert_resource(SandboxState::new(scenario.clone(), &SandboxSettings::default()))
            .insert_resource(scenario.settings())
            .init_resource::<NextBodyId>()
            .add_plugins(SnapshotSavePlugin);
        crate::timed_events::install_events(app.world_mut(), &scenario);
        let path = dir.path().join("session.ron");
        app.world_mut()
            .resource_mut::<SnapshotSave>()
            .session_requested
            .push(path.clone());
        app.update();
        let outcome = app.world_mut().resource_mut::<SnapshotSave>().outcome.take();
        assert!(
            matches!(&outcome, Some(Err(e)) if e.contains("with the events of update 0 applied")),
            "{outcome:?}"
        );
        assert!(!path.exists());
        assert_eq!(app.world().resource::<OutputFailures>().count(), 1);
    }
}
