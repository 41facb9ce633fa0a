//! [`UpdateCount`]: how many updates the run has started.

use bevy::prelude::*;

/// Updates started so far: counted by [`run_updates`](super::run_updates),
/// set back by a rewind. The events of a scenario and the window's tools
/// are timed by it; a fault is dated by it.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub struct UpdateCount(pub u64);
