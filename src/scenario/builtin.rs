//! The scenarios built into the binary, and the choice between a file and
//! the built-in default.

use std::path::Path;

use super::Scenario;
use crate::input::InputError;

/// The scenario used when none is given: a debris field in orbit.
pub const DEFAULT_SCENARIO: &str = include_str!("../../scenarios/debris_orbit.ron");

/// Name of [`DEFAULT_SCENARIO`] in messages.
pub const DEFAULT_SCENARIO_NAME: &str = "scenarios/debris_orbit.ron (built in)";

/// The thesis scene, the default of benchmark configs.
pub const THESIS_SCENARIO: &str = include_str!("../../scenarios/thesis_cloud.ron");

/// Name of [`THESIS_SCENARIO`] in messages.
pub const THESIS_SCENARIO_NAME: &str = "scenarios/thesis_cloud.ron (built in)";

impl Scenario {
    /// The built-in debris field ([`DEFAULT_SCENARIO`]).
    pub fn builtin_default() -> Self {
        Self::parse(DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME).expect("the built-in scenario is valid (tested)")
    }

    /// The built-in thesis scene ([`THESIS_SCENARIO`]).
    pub fn builtin_thesis() -> Self {
        Self::parse(THESIS_SCENARIO, THESIS_SCENARIO_NAME).expect("the built-in scenario is valid (tested)")
    }

    /// The scenario at `path`, or the built-in default when there is none.
    pub fn load_or_default(path: Option<&Path>) -> Result<Self, InputError> {
        match path {
            Some(path) => Self::load(path),
            None => Ok(Self::builtin_default()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_scenarios_parse_and_name_their_origin() {
        let default = Scenario::builtin_default();
        assert_eq!(default.origin, DEFAULT_SCENARIO_NAME);
        assert!(default.bodies().is_ok());
        assert_eq!(Scenario::builtin_thesis().origin, THESIS_SCENARIO_NAME);
        assert_eq!(Scenario::load_or_default(None).unwrap(), default);
    }
}
