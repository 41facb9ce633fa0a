//! Scripted tool actions (`kessler run --actions FILE`): each sent at its
//! frame through the same message the panel's buttons send, so that a test
//! (or a demonstration) drives the tools as a user would; and, with
//! `--dump`, the state written when a scripted run closes.

use std::path::{Path, PathBuf};

use bevy::prelude::*;
use serde::Deserialize;

use super::actions::ToolAction;
use crate::components::{BodyState, BodyStateQuery};
use crate::input::{InputError, load_ron};
use crate::output::write_atomically;
use crate::record::StateHash;
use crate::resources::NextBodyId;
use crate::systems::{SimulationFault, UpdateCount};
use crate::ui::measure::FrameStats;
use crate::ui::session::OutputFailures;

/// One scripted action.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScriptedAction {
    /// The frame at which it is sent (counted from 0).
    pub frame: u64,
    /// What the panel would send.
    pub action: ToolAction,
}

/// The actions still to send, by frame.
#[derive(Resource, Clone, Debug, Default)]
pub struct ActionScript(pub Vec<ScriptedAction>);

impl ActionScript {
    /// Reads a script: a RON list of `(frame: N, action: ...)`.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let mut actions: Vec<ScriptedAction> = load_ron(path, ron::extensions::Extensions::empty())?;
        actions.sort_by_key(|a| a.frame);
        Ok(Self(actions))
    }
}

/// Sends the actions due at this frame.
pub fn send_scripted_actions(
    mut script: ResMut<ActionScript>,
    stats: Res<FrameStats>,
    mut actions: MessageWriter<ToolAction>,
) {
    let due = script.0.partition_point(|a| a.frame <= stats.frames);
    for scripted in script.0.drain(..due) {
        actions.write(scripted.action);
    }
}

/// Where a scripted run writes the state at its close.
#[derive(Resource, Clone, Debug)]
pub struct DumpAtClose(pub PathBuf);

/// At the close: the state as `headless --dump` writes it, and one line
/// with the update count and the state's hash (what a replay of the
/// session with `--steps` of that count must reach).
pub fn dump_at_close(
    mut exits: MessageReader<AppExit>,
    dump: Res<DumpAtClose>,
    updates: Res<UpdateCount>,
    next_id: Res<NextBodyId>,
    bodies: Query<BodyStateQuery>,
    failures: Res<OutputFailures>,
    fault: Res<SimulationFault>,
) {
    // A stopped run writes no state: it is half an update
    // (`stopped_at_close` says why the run ends so).
    if exits.read().next().is_none() || fault.fault.is_some() {
        return;
    }
    let states = BodyState::sorted_by_id(bodies.iter());
    let hash = StateHash::of_slice(&states, next_id.0);
    match write_atomically(&dump.0, |w| crate::record::write_csv(&states, w)) {
        Ok(()) => println!(
            "kessler: closed after {} updates of the scene; state hash {hash}; state written to {}",
            updates.0,
            dump.0.display()
        ),
        Err(e) => failures.failed(format_args!("--dump {e}")),
    }
}
