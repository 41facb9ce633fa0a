//! Scenario files (docs/design.md, "Scenario files"): the format, its
//! checks, the generators, the events, loading, and the built-in scenes.

mod builtin;
mod contents;
mod event_checks;
pub mod events;
pub mod field_checks;
mod fields;
mod format;
pub mod generators;
mod initial_state;
mod listed;
mod load;
mod ron_form;
mod scale;
mod snapshot;

pub use builtin::{DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME, THESIS_SCENARIO, THESIS_SCENARIO_NAME};
pub use contents::Scenario;
pub use events::{Breakup, Event, Fire, Remove, Set, Spawn};
pub use field_checks::{MAX_BODIES, MAX_FRAGMENTS};
pub use format::{Body, Cloud, Generator, Shape, Shell, Template};
pub use initial_state::check_start;
pub use scale::CannotResize;
pub use snapshot::{Snapshot, not_a_scenario, scenario_text, write_session, write_snapshot};
