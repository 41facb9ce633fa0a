//! A simulation in the test's own process, from a scenario's text.

use kessler::Simulation;
use kessler::execution::{Execution, ExecutionMode};
use kessler::scenario::Scenario;

/// The scenario `text` (which must parse) as a sequential simulation on
/// one thread.
pub fn sim(text: &str) -> Simulation {
    let scenario = Scenario::parse(text, "test").unwrap_or_else(|e| panic!("{e}\n{text}"));
    Simulation::from_scenario(&scenario, Execution::new(ExecutionMode::Sequential, 1).unwrap()).unwrap()
}
