//! `kessler validate SCENARIO`.

use std::path::Path;

use super::Failure;
use crate::execution::{Execution, ExecutionMode};
use crate::scenario::Scenario;
use crate::simulation::Simulation;

/// Checks the file, every body it generates and the start the events of
/// update 0 leave, as a run starts it; prints a one-line verdict.
pub fn validate(path: &Path) -> Result<(), Failure> {
    let scenario = Scenario::load(path)?;
    let execution = Execution::all_cores(ExecutionMode::Parallel)?;
    let bodies = Simulation::from_scenario(&scenario, execution)?.body_count();
    let events = match scenario.events.len() {
        0 => String::new(),
        1 => ", 1 event".to_owned(),
        n => format!(", {n} events"),
    };
    let verdict = format!(
        "{}: ok — \"{}\", {} bodies{events}",
        scenario.origin, scenario.name, bodies
    );
    println!("{}", crate::output::printable(&verdict));
    Ok(())
}
