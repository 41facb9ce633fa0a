//! `kessler validate SCENARIO`.

use std::path::Path;

use super::Failure;
use crate::scenario::Scenario;

/// Checks the file and every body it generates; prints a one-line verdict.
pub fn validate(path: &Path) -> Result<(), Failure> {
    let scenario = Scenario::load(path)?;
    let bodies = scenario.bodies()?;
    println!(
        "{}: ok — \"{}\", {} bodies",
        scenario.origin,
        scenario.name,
        bodies.len()
    );
    Ok(())
}
