//! The local executor: up to `jobs` member processes at once on this
//! machine, each `kessler ensemble member DIR INDEX`, with a progress bar.
//! A member that fails is recorded as failed (its own message, or the last
//! line of its stderr, or the signal that ended it) and the others go on.
//! Ctrl-C stops cleanly: the running members are ended and their
//! unfinished folders removed, the finished ones kept.
//!
//! Members run in a process group of their own, so that Ctrl-C in the
//! terminal reaches this process alone, which then ends them itself; a
//! SIGTERM or SIGHUP is taken as Ctrl-C is. Should the executor die without
//! a word (SIGKILL), the kernel ends its members too (Linux's parent-death
//! signal), so that none goes on writing into a folder a resume uses.

use std::os::unix::process::{CommandExt as _, ExitStatusExt as _};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use super::EnsembleError;
use super::folder::{EnsembleFolder, MemberState};
use crate::output::{WriteError, printable, write_atomically};

/// How often the executor looks at its members.
const POLL: Duration = Duration::from_millis(5);

/// What a local run did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LocalRun {
    /// Members that finished.
    pub done: u64,
    /// Members that failed: index and the last line of their error.
    pub failed: Vec<(u64, String)>,
    /// Seconds from the first member's start to the last one's end.
    pub seconds: f64,
}

/// Runs `indices` of the ensemble in `folder`, `jobs` at a time, with the
/// binary `exe`.
pub fn run_local(folder: &EnsembleFolder, indices: &[u64], jobs: usize, exe: &Path) -> Result<LocalRun, EnsembleError> {
    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let interrupted = Arc::clone(&interrupted);
        // Only the first handler of a process is set; a second local run in
        // one process keeps the first's flag, which is never set twice.
        let _ = ctrlc::set_handler(move || interrupted.store(true, Ordering::SeqCst));
    }
    let logs = folder.root().join("logs");
    std::fs::create_dir_all(&logs).map_err(|source| WriteError { path: logs, source })?;

    let progress = ProgressBar::new(indices.len() as u64).with_style(
        ProgressStyle::with_template("{spinner} {pos}/{len} members [{bar:30}] {elapsed} eta {eta}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    let start = Instant::now();
    let mut run = LocalRun::default();
    let mut waiting = indices.iter().copied();
    let mut running: Vec<(u64, Child)> = Vec::new();
    loop {
        if interrupted.load(Ordering::SeqCst) {
            progress.finish_and_clear();
            let ended = running.len();
            for (index, mut child) in running {
                let _ = child.kill();
                let _ = child.wait();
                let _ = std::fs::remove_dir_all(folder.member_dir(index));
                let _ = std::fs::remove_file(folder.log(index));
            }
            return Err(EnsembleError::Interrupted(format!(
                "interrupted: {} members finished and kept, {ended} running ended and removed, {} not started; run the same command again to resume",
                run.done,
                waiting.count()
            )));
        }
        while running.len() < jobs {
            let Some(index) = waiting.next() else { break };
            running.push((index, spawn(folder, exe, index)?));
        }
        if running.is_empty() {
            break;
        }
        let mut k = 0;
        while k < running.len() {
            let status = running[k]
                .1
                .try_wait()
                .map_err(|e| EnsembleError::Failed(format!("member {}: could not be watched: {e}", running[k].0)))?;
            match status {
                Some(status) => {
                    let (index, _) = running.swap_remove(k);
                    match settle(folder, index, status) {
                        Ok(()) => run.done += 1,
                        Err(why) => run.failed.push((index, why)),
                    }
                    progress.inc(1);
                }
                None => k += 1,
            }
        }
        std::thread::sleep(POLL);
    }
    progress.finish_and_clear();
    // The logs of failed members stay; an empty folder goes.
    let _ = std::fs::remove_dir(folder.root().join("logs"));
    run.failed.sort_unstable();
    run.seconds = start.elapsed().as_secs_f64();
    Ok(run)
}

/// Starts member `index`: stdout nowhere, stderr into its log.
fn spawn(folder: &EnsembleFolder, exe: &Path, index: u64) -> Result<Child, EnsembleError> {
    let log = folder.log(index);
    let stderr = std::fs::File::create(&log).map_err(|source| WriteError {
        path: log.clone(),
        source,
    })?;
    let mut command = Command::new(exe);
    command
        .arg("ensemble")
        .arg("member")
        .arg(folder.root())
        .arg(index.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(stderr)
        .process_group(0);
    #[cfg(target_os = "linux")]
    end_with_this_process(&mut command);
    command
        .spawn()
        .map_err(|e| EnsembleError::Failed(format!("member {index}: {} could not start: {e}", exe.display())))
}

/// What member `index`'s end means: done, or failed with the reason, which
/// its `failed` marker then holds. A finished member's log is removed.
fn settle(folder: &EnsembleFolder, index: u64, status: ExitStatus) -> Result<(), String> {
    let state = folder.member_state(index);
    if status.success() && state == MemberState::Done {
        let _ = std::fs::remove_file(folder.log(index));
        return Ok(());
    }
    if let MemberState::Failed(why) = state {
        return Err(why);
    }
    // It ended without saying why (a signal, a crash): its stderr's last
    // line, or how it ended.
    let log = std::fs::read_to_string(folder.log(index)).unwrap_or_default();
    let last = log.lines().rev().find(|l| !l.trim().is_empty()).map(str::trim);
    let how = match (status.code(), status.signal()) {
        (_, Some(signal)) => format!("ended by signal {signal}"),
        (Some(code), _) => format!("exited with code {code}"),
        _ => "ended".to_owned(),
    };
    let why = printable(&match last {
        Some(line) => format!("{how}: {line}"),
        None => how,
    });
    let _ = std::fs::create_dir_all(folder.member_dir(index));
    let _ = write_atomically(&folder.failed_marker(index), |w| writeln!(w, "{why}"));
    Err(why)
}

/// Has the member `command` starts killed when this process dies, however
/// it dies (`PR_SET_PDEATHSIG`). The signal follows the thread that spawns
/// the member: the executor spawns from the command's own thread, which
/// lives as long as the process.
#[cfg(target_os = "linux")]
fn end_with_this_process(command: &mut Command) {
    let executor = libc::pid_t::try_from(std::process::id()).unwrap_or(0);
    #[expect(
        unsafe_code,
        reason = "prctl and getppid between fork and exec, both async-signal-safe"
    )]
    unsafe {
        command.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL as libc::c_ulong, 0, 0, 0) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            // The executor died before the prctl: end now.
            if libc::getppid() != executor {
                return Err(std::io::Error::from_raw_os_error(libc::ESRCH));
            }
            Ok(())
        });
    }
}
