//! `kessler validate SCENARIO`.

use std::path::Path;

use super::{Failure, load_scenario};

/// Checks the file and every body it generates; prints a one-line verdict.
pub fn validate(path: &Path) -> Result<(), Failure> {
    let (scenario, origin) = load_scenario(Some(path))?;
    let bodies = scenario.bodies(&origin).map_err(Failure::input)?;
    println!("{origin}: ok — \"{}\", {} bodies", scenario.name, bodies.len());
    Ok(())
}
