//! `kessler run [SCENARIO]` (and plain `kessler`): the window, or, in a
//! build without it, a short headless run of the same scene.

use super::{Failure, RunArgs};

/// Updates `kessler run` simulates when the window is not built.
#[cfg(not(feature = "gui"))]
const RUN_UPDATES: u64 = 600;

/// Runs the command.
#[cfg(not(feature = "gui"))]
pub fn run(args: RunArgs) -> Result<(), Failure> {
    use crate::scenario::Scenario;

    if args.frames.is_some()
        || args.screenshot.is_some()
        || args.render.is_some()
        || args.vsync.is_some()
        || args.ups.is_some()
        || args.frame_report.is_some()
        || args.dump.is_some()
        || args.actions.is_some()
        || args.offscreen
        || args.frames_out.is_some()
    {
        return Err(Failure::input(
            "this kessler was built without the window (cargo feature `gui`); \
             --frames, --screenshot, --render, --vsync, --ups, --frame-report, --dump, --actions, --offscreen and \
             --frames-out need it",
        ));
    }
    let mut scenario = Scenario::load_or_default(args.scenario.as_deref())?;
    if let Some(count) = args.bodies {
        scenario = scenario
            .with_generated(count)
            .map_err(|e| Failure::from(e).context("--bodies"))?;
    }
    let execution = super::headless::execution(&args.execution)?;
    // Said once everything is checked (the bodies too), so that a bad
    // input is one line.
    scenario.bodies()?;
    eprintln!(
        "kessler: the interactive window is not part of this build (cargo feature `gui`); \
         simulating {RUN_UPDATES} updates headless instead (see `kessler headless --help`)"
    );
    super::headless::simulate(&scenario, execution, RUN_UPDATES, crate::simulation::Outputs::default())
}

/// Runs the command: opens the window.
#[cfg(feature = "gui")]
pub fn run(args: RunArgs) -> Result<(), Failure> {
    use crate::ui::WindowOptions;

    let options = WindowOptions {
        scenario: args.scenario,
        frames: args.frames,
        screenshot: args.screenshot,
        settings: args.settings,
        render: args.render.map(Into::into),
        bodies: args.bodies,
        paused: args.paused,
        vsync: args.vsync.map(Into::into),
        execution: args.execution,
        ups: args.ups,
        frame_report: args.frame_report,
        dump: args.dump,
        actions: args.actions,
        offscreen: args.offscreen,
        frames_out: args.frames_out,
        every: args.every,
    };
    crate::ui::run(options).map_err(Failure::from)
}
