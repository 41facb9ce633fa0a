//! `kessler calibrate [--threads T] [--out FILE]`.

use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};

use super::Failure;
use crate::calibration::{calibrate, load_calibration, threads_to_measure};
use crate::execution::available_threads;
use crate::input::default_calibration_path;
use crate::output::{Output, check_outputs, through_link};

/// Runs the command.
pub fn calibrate_command(threads: Option<usize>, out: Option<&Path>) -> Result<(), Failure> {
    let (threads, bounded) = threads_to_measure(threads.unwrap_or_else(available_threads), available_threads());
    // A path given is checked before the measuring, as every output is.
    // The default file is the user's own, like the settings: written
    // through a symbolic link there (a dotfiles setup keeps its link), so
    // the file the link names is what is checked, where something is there
    // already (else its folder is made).
    let path = out.map_or_else(default_calibration_path, Path::to_owned);
    match out {
        Some(out) => check_outputs(&[Output::replacing("--out", out)], &[])?,
        None if path.symlink_metadata().is_ok() => {
            let target = through_link(&path).map_err(Failure::from)?;
            let named = if target == path {
                "the calibration file".to_owned()
            } else {
                format!("the calibration file {}, a link to", path.display())
            };
            check_outputs(&[Output::replacing(&named, &target)], &[])?;
        }
        None => {}
    }
    if let Some(warning) = bounded {
        eprintln!("kessler: warning: {warning}");
    }
    let bar = ProgressBar::new(0).with_style(
        ProgressStyle::with_template("{spinner} calibrating [{bar:30}] {pos}/{len} runs, eta {eta}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    let calibration = calibrate(threads, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(|e| Failure::from(e).context("calibrate"))?;
    bar.finish_and_clear();
    let previous = load_calibration(&path).ok().flatten();
    calibration.save(&path).map_err(Failure::from)?;
    println!(
        "split calibration for {threads} thread{} written to {}{}:",
        if threads == 1 { "" } else { "s" },
        path.display(),
        if previous.is_some() {
            " (replacing the previous one)"
        } else {
            ""
        }
    );
    for (stage, from) in &calibration.split_from {
        let before = previous
            .as_ref()
            .and_then(|p| p.split_from.get(stage))
            .map_or(String::new(), |b| format!(" (was {b})"));
        println!("  {stage:<10} splits from {from} bodies{before}");
    }
    Ok(())
}
