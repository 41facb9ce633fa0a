//! Scenario files (DESIGN §4): format, checks, generators and loading.

pub mod checked;
mod format;
pub mod generators;
mod load;
mod scale;

pub use format::*;
pub use load::*;

/// The scenario used when none is given: a debris field in orbit.
pub const DEFAULT_SCENARIO: &str = include_str!("../../scenarios/debris_orbit.ron");

/// Name of [`DEFAULT_SCENARIO`] in messages.
pub const DEFAULT_SCENARIO_NAME: &str = "scenarios/debris_orbit.ron (built in)";

/// The thesis scene, the default of benchmark configs.
pub const THESIS_SCENARIO: &str = include_str!("../../scenarios/thesis_cloud.ron");

/// Name of [`THESIS_SCENARIO`] in messages.
pub const THESIS_SCENARIO_NAME: &str = "scenarios/thesis_cloud.ron (built in)";
