//! `kessler validate SCENARIO`.

use std::path::Path;

use super::Failure;
use crate::scenario::Scenario;

/// Checks the file and every body it generates; prints a one-line verdict.
pub fn validate(path: &Path) -> Result<(), Failure> {
    let scenario = Scenario::load(path)?;
    let bodies = scenario.bodies()?;
    let events = match scenario.events.len() {
        0 => String::new(),
        1 => ", 1 event".to_owned(),
        n => format!(", {n} events"),
    };
    let verdict = format!(
        "{}: ok — \"{}\", {} bodies{events}",
        scenario.origin,
        scenario.name,
        bodies.len()
    );
    println!("{}", crate::output::printable(&verdict));
    Ok(())
}
