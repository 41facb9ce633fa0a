//! Allocation of fresh body ids.

use bevy::prelude::*;

use crate::components::BodyId;

/// The next unused [`BodyId`]; ids are handed out in increasing order and
/// never reused.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NextBodyId(pub u64);

impl NextBodyId {
    /// Takes the next id.
    pub fn allocate(&mut self) -> BodyId {
        // Loaded ids are at most 2^62 (scenario checks): a run would need
        // more than 2^62 fragments to get near the end.
        let id = BodyId(self.0);
        self.0 = self.0.saturating_add(1);
        id
    }
}
