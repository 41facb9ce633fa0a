//! Allocation of fresh body ids.

use bevy::prelude::*;

use crate::components::BodyId;

/// The bound on ids: every body's id is below it and the next id to hand
/// out at most it, 2^62 — far below `u64`'s limit, so that no id ever
/// wraps. Scenario files are held to it when they load (`id`, `next_id`,
/// and the ids generators hand out), and a shatter that would hand out an
/// id past it bounces instead (see the response's `ShatterBudget`), so
/// that every snapshot a run writes loads back.
pub const MAX_ID: u64 = 1 << 62;

/// The next unused [`BodyId`]; ids are handed out in increasing order and
/// never reused.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NextBodyId(pub u64);

impl NextBodyId {
    /// Takes the next id.
    pub fn allocate(&mut self) -> BodyId {
        // Loaded ids are at most MAX_ID, and the shatters keep them there.
        let id = BodyId(self.0);
        self.0 = self.0.saturating_add(1);
        id
    }

    /// Whether `count` more ids can be handed out without the next id
    /// passing [`MAX_ID`].
    pub fn has_room_for(self, count: u64) -> bool {
        self.0.checked_add(count).is_some_and(|next| next <= MAX_ID)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_is_counted_up_to_the_bound() {
        assert!(NextBodyId(MAX_ID - 5).has_room_for(5));
        assert!(!NextBodyId(MAX_ID - 4).has_room_for(5));
        assert!(NextBodyId(MAX_ID).has_room_for(0));
        assert!(!NextBodyId(u64::MAX).has_room_for(1));
    }
}
