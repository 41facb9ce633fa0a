//! A whole scenario file's contents (docs/design.md, "Scenario files"):
//! its name, physics settings, bodies, generators and events. Read and
//! written field by field in `fields.rs`.

use super::events::Event;
use super::format::{Body, Generator};
use crate::resources::SimulationSettings;

/// A whole scenario: physics settings, explicit bodies and generators. The
/// physics settings are fields of the file itself, one per setting, read
/// and written by their rules ([`crate::resources::rules`])
/// (`scenario/fields.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Where the scenario was read from, for messages (not part of the file).
    pub origin: String,
    /// Shown in summaries and plot titles; default "Unnamed scenario".
    pub name: String,
    /// The physics settings; each omitted one at its default. The stage
    /// switches are not part of a file and stay on.
    pub physics: SimulationSettings,
    /// The first id fresh bodies (fragments) get; default: one past the
    /// highest id. Snapshots set it, so that a continued run hands out the
    /// same ids as the run it was saved from.
    pub next_id: Option<u64>,
    /// Explicitly placed bodies: ids 0, 1, 2… in file order, or each its
    /// own `id` (all of them or none).
    pub bodies: Vec<Body>,
    /// Seeded random bodies, ids after the explicit ones.
    pub generators: Vec<Generator>,
    /// Timed events (docs/design.md, "Events"), in file order.
    pub events: Vec<Event>,
}

impl Default for Scenario {
    fn default() -> Self {
        Self {
            origin: String::new(),
            name: "Unnamed scenario".to_owned(),
            physics: SimulationSettings::DEFAULT,
            next_id: None,
            bodies: Vec::new(),
            generators: Vec::new(),
            events: Vec::new(),
        }
    }
}
