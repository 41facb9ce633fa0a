//! [`SimulationFault`]: why a run stopped. A stage that finds the state can
//! no longer be computed — a body whose position or velocity is no longer
//! finite, or bodies piled so densely that their pairs cannot be held —
//! records it here; the stages after it and every later update are then
//! skipped ([`no_fault`] guards each stage), and whoever drives the
//! simulation reports it: the headless run exits non-zero without writing
//! its outputs, the window pauses and shows it.

use bevy::prelude::*;

use super::TooManyPairs;
use crate::components::{BodyId, Position, Velocity};
use crate::memory::{BYTES_PER_BODY, MemoryLimit};
use crate::resources::gigabytes;

/// What stopped the run.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum Fault {
    /// A body's state overflowed `f32` (or became NaN).
    #[error(
        "body {} has a non-finite {what} ({}, {}, {}): a value overflowed \
         (look for extreme speeds, masses, time steps or gravitational constants)",
        id.0, value.x, value.y, value.z
    )]
    NonFinite {
        /// The body (the lowest id among those affected).
        id: BodyId,
        /// `"position"` or `"velocity"`.
        what: &'static str,
        /// The value.
        value: Vec3,
    },
    /// The sweep found more pairs than it may hold.
    #[error("{0}")]
    PileUp(TooManyPairs),
    /// The bodies would outgrow the memory the run may use.
    #[error(
        "the shatters of this update would make {bodies} bodies, more than the {} left under {} \
         holds at {} bytes a body (at most {}); lower max_bodies, raise min_fragment_size (without a \
         floor a shattering cascade runs away: more and smaller fragments meet ever more often), or give \
         the run more memory",
        gigabytes(limit.free_bytes), limit.kind, BYTES_PER_BODY, limit.bodies()
    )]
    OutOfMemory {
        /// The bodies there would be.
        bodies: u64,
        /// The limit.
        limit: MemoryLimit,
    },
}

/// The run's fault, if any, and the update it happened in.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct SimulationFault {
    /// What stopped the run, in update `stopped_at`.
    pub fault: Option<Fault>,
    /// The update the fault happened in: dated by
    /// [`run_updates`](super::run_updates) as that update ends (a stage
    /// that stops the run does not know its number).
    pub stopped_at: Option<u64>,
}

impl SimulationFault {
    /// Records `fault`, unless an earlier one is recorded.
    pub fn stop(&mut self, fault: Fault) {
        if self.fault.is_none() {
            self.fault = Some(fault);
        }
    }

    /// Dates a fault recorded and not yet dated: it happened in update
    /// `update`.
    pub fn date(&mut self, update: u64) {
        if self.fault.is_some() && self.stopped_at.is_none() {
            self.stopped_at = Some(update);
        }
    }

    /// The fault as one line naming the update, if there is one.
    pub fn message(&self) -> Option<String> {
        self.fault.map(|fault| match self.stopped_at {
            Some(update) => format!("update {update}: {fault}; the simulation stopped"),
            None => format!("{fault}; the simulation stopped"),
        })
    }

    /// Forgets the fault (a new scene starts).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

/// Run condition of every stage: no fault yet.
pub fn no_fault(fault: Res<SimulationFault>) -> bool {
    fault.fault.is_none()
}

/// The first body, by id, whose position or velocity is not finite.
pub fn first_non_finite<'a>(bodies: impl Iterator<Item = (&'a BodyId, &'a Position, &'a Velocity)>) -> Option<Fault> {
    bodies
        .filter_map(|(id, p, v)| {
            if !p.0.is_finite() {
                Some((*id, "position", p.0))
            } else if !v.0.is_finite() {
                Some((*id, "velocity", v.0))
            } else {
                None
            }
        })
        .min_by_key(|(id, _, _)| *id)
        .map(|(id, what, value)| Fault::NonFinite { id, what, value })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lowest_id_is_named_and_the_first_fault_kept() {
        let ids = [BodyId(7), BodyId(3), BodyId(5)];
        let positions = [
            Position(Vec3::new(f32::INFINITY, 0.0, 0.0)),
            Position(Vec3::ONE),
            Position(Vec3::ONE),
        ];
        let velocities = [
            Velocity(Vec3::ZERO),
            Velocity(Vec3::ZERO),
            Velocity(Vec3::new(0.0, f32::NAN, 0.0)),
        ];
        let bodies = || ids.iter().zip(&positions).zip(&velocities).map(|((i, p), v)| (i, p, v));
        let fault = first_non_finite(bodies()).unwrap();
        assert!(matches!(
            fault,
            Fault::NonFinite {
                id: BodyId(5),
                what: "velocity",
                ..
            }
        ));
        assert_eq!(first_non_finite(bodies().skip(1).take(1)), None);

        let mut state = SimulationFault::default();
        state.stop(fault);
        state.date(12);
        state.stop(first_non_finite(bodies().take(1)).unwrap());
        state.date(13);
        let message = state.message().unwrap();
        assert!(
            message.starts_with("update 12: body 5 has a non-finite velocity (0, NaN, 0)"),
            "{message}"
        );
    }
}
