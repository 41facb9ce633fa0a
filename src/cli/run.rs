//! `kessler run [SCENARIO]` (and plain `kessler`): the window, or, in a
//! build without it, a short headless run of the same scene.

use super::{Failure, RunArgs};

/// Updates `kessler run` simulates when the window is not built.
#[cfg(not(feature = "gui"))]
const RUN_UPDATES: u64 = 600;

/// Runs the command.
#[cfg(not(feature = "gui"))]
pub fn run(args: RunArgs) -> Result<(), Failure> {
    use crate::execution::{Execution, ExecutionMode};
    use crate::scenario::Scenario;

    if args.frames.is_some() || args.screenshot.is_some() || args.render.is_some() {
        return Err(Failure::input(
            "this kessler was built without the window (cargo feature `gui`); \
             --frames, --screenshot and --render need it",
        ));
    }
    eprintln!(
        "kessler: the interactive window is not part of this build (cargo feature `gui`); \
         simulating {RUN_UPDATES} updates headless instead (see `kessler headless --help`)"
    );
    let mut scenario = Scenario::load_or_default(args.scenario.as_deref())?;
    if let Some(count) = args.bodies {
        scenario = scenario
            .with_generated(count)
            .map_err(|e| Failure::from(e).context("--bodies"))?;
    }
    let execution = Execution::all_cores(ExecutionMode::default())?;
    super::headless::simulate(&scenario, execution, RUN_UPDATES, None)
}

/// Runs the command: opens the window.
#[cfg(feature = "gui")]
pub fn run(args: RunArgs) -> Result<(), Failure> {
    use super::RenderArg;
    use crate::ui::{RenderMethod, WindowOptions};

    let options = WindowOptions {
        scenario: args.scenario,
        frames: args.frames,
        screenshot: args.screenshot,
        settings: args.settings,
        render: args.render.map(|r| match r {
            RenderArg::Instanced => RenderMethod::Instanced,
            RenderArg::Meshes => RenderMethod::Meshes,
        }),
        bodies: args.bodies,
        paused: args.paused,
    };
    crate::ui::run(options).map_err(Failure::from)
}
