//! The Slurm executor: the members still to run as one job array,
//! `DIR/slurm/ensemble.sbatch`, submitted with `sbatch`; each array task
//! runs `kessler ensemble member DIR $SLURM_ARRAY_TASK_ID` with this
//! binary's absolute path. Waiting polls `squeue` for the job and counts
//! the members done meanwhile. Kessler schedules nothing itself: Slurm
//! does. `DIR` must be on a file system every node sees.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

use super::EnsembleError;
use super::folder::EnsembleFolder;
use crate::output::{WriteError, write_atomically};

/// How often `--wait` asks Slurm about the job.
const POLL: Duration = Duration::from_secs(2);

/// `indices` (sorted) as Slurm's `--array` list: runs as `a-b`, the rest
/// alone, separated by commas (`0-3,7,9-12`).
pub fn array_spec(indices: &[u64]) -> String {
    let mut spec = String::new();
    let mut k = 0;
    while k < indices.len() {
        let first = indices[k];
        let mut last = first;
        while k + 1 < indices.len() && indices[k + 1] == last + 1 {
            k += 1;
            last = indices[k];
        }
        if !spec.is_empty() {
            spec.push(',');
        }
        if first == last {
            let _ = write!(spec, "{first}");
        } else {
            let _ = write!(spec, "{first}-{last}");
        }
        k += 1;
    }
    spec
}

/// `text` in single quotes for the shell.
fn quoted(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// The job script: an array task per member in `indices`, at most
/// `throttle` running at once, `threads` CPUs each.
pub fn sbatch_script(
    folder: &EnsembleFolder,
    exe: &Path,
    indices: &[u64],
    throttle: Option<usize>,
    threads: usize,
) -> Result<String, String> {
    let root = folder.root().display().to_string();
    let exe = exe.display().to_string();
    // `#SBATCH` lines are not shell: their paths must need no quoting.
    if let Some(c) = root
        .chars()
        .find(|c| c.is_whitespace() || c.is_control() || ['"', '\'', '\\', '%'].contains(c))
    {
        return Err(format!(
            "--out {root}: Slurm's job script cannot name a folder with {c:?} in it; give a folder whose path has none"
        ));
    }
    let logs = folder.slurm_dir().join("logs").display().to_string();
    let array = match throttle {
        Some(k) => format!("{}%{k}", array_spec(indices)),
        None => array_spec(indices),
    };
    let (kessler, dir) = (quoted(&exe), quoted(&root));
    Ok(format!(
        r#"#!/bin/bash
# Written by `kessler ensemble --executor slurm`: one array task a member.
# Submit it again by hand with `sbatch {root}/slurm/ensemble.sbatch`;
# `kessler ensemble status {root}` counts the members done.
#SBATCH --job-name=kessler-ensemble
#SBATCH --array={array}
#SBATCH --ntasks=1
#SBATCH --cpus-per-task={threads}
#SBATCH --output={logs}/%A_%a.out
#SBATCH --error={logs}/%A_%a.err
set -u
kessler={kessler}
dir={dir}
index="$SLURM_ARRAY_TASK_ID"
"$kessler" ensemble member "$dir" "$index"
status=$?
# A member that ended without saying why (a signal, a crash) is recorded as failed.
if [ "$status" -ne 0 ] && [ ! -e "$dir/members/$index/failed" ]; then
    mkdir -p "$dir/members/$index"
    last="$(grep -v '^[[:space:]]*$' "$dir/slurm/logs/${{SLURM_ARRAY_JOB_ID}}_${{index}}.err" 2>/dev/null | tail -n 1)"
    printf 'exited with code %s on %s: %s\n' "$status" "$(hostname)" "$last" > "$dir/members/$index/failed"
fi
exit "$status"
"#
    ))
}

/// Writes the job script and submits it with `sbatch --parsable`, passing
/// `slurm_args` before it; returns the job id, which `DIR/slurm/jobs`
/// gains a line with.
pub fn submit(
    folder: &EnsembleFolder,
    script: &str,
    slurm_args: &[String],
    indices: &[u64],
) -> Result<String, EnsembleError> {
    let dir = folder.slurm_dir();
    let logs = dir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|source| WriteError { path: logs, source })?;
    let script_path = dir.join("ensemble.sbatch");
    write_atomically(&script_path, |w| w.write_all(script.as_bytes()))?;
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(slurm_args)
        .arg(&script_path)
        .output()
        .map_err(|e| {
            EnsembleError::Failed(format!(
                "--executor slurm: `sbatch` could not be run ({e}); is Slurm's client installed and on PATH?"
            ))
        })?;
    if !out.status.success() {
        let said = String::from_utf8_lossy(&out.stderr);
        let said = said
            .lines()
            .filter(|l| !l.trim().is_empty())
            .collect::<Vec<_>>()
            .join("; ");
        return Err(EnsembleError::Failed(format!(
            "--executor slurm: sbatch refused {}: {said}",
            script_path.display()
        )));
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    // `--parsable` prints `id` or `id;cluster`.
    let id = stdout.trim().split(';').next().unwrap_or_default().to_owned();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(EnsembleError::Failed(format!(
            "--executor slurm: sbatch gave no job id (it said {:?})",
            stdout.trim()
        )));
    }
    let jobs = dir.join("jobs");
    let mut lines = std::fs::read_to_string(&jobs).unwrap_or_default();
    let _ = writeln!(lines, "{id} {}", array_spec(indices));
    write_atomically(&jobs, |w| w.write_all(lines.as_bytes()))?;
    Ok(id)
}

/// Whether Slurm still holds tasks of job `id` (pending or running).
fn job_is_queued(id: &str) -> Result<bool, EnsembleError> {
    let out = Command::new("squeue")
        .args(["--noheader", "--format=%i", "--jobs", id])
        .output()
        .map_err(|e| EnsembleError::Failed(format!("--wait: `squeue` could not be run ({e})")))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if out.status.success() {
        return Ok(stdout.lines().any(|l| !l.trim().is_empty()));
    }
    // A job Slurm no longer knows has ended.
    let stderr = String::from_utf8_lossy(&out.stderr);
    if stderr.contains("Invalid job id") {
        return Ok(false);
    }
    Err(EnsembleError::Failed(format!(
        "--wait: squeue failed for job {id}: {}",
        stderr.trim()
    )))
}

/// Waits until Slurm holds no task of job `id`, showing the members of
/// `indices` done meanwhile.
pub fn wait(folder: &EnsembleFolder, id: &str, indices: &[u64]) -> Result<f64, EnsembleError> {
    let progress = ProgressBar::new(indices.len() as u64).with_style(
        ProgressStyle::with_template("{spinner} job {msg}: {pos}/{len} members [{bar:30}] {elapsed} eta {eta}")
            .expect("template is valid")
            .progress_chars("=> "),
    );
    progress.set_message(id.to_owned());
    let start = Instant::now();
    loop {
        let queued = job_is_queued(id)?;
        let done = indices.iter().filter(|&&i| folder.done_marker(i).is_file()).count();
        progress.set_position(done as u64);
        if !queued {
            break;
        }
        std::thread::sleep(POLL);
    }
    progress.finish_and_clear();
    Ok(start.elapsed().as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_become_slurm_array_ranges() {
        assert_eq!(array_spec(&[0, 1, 2, 3, 7, 9, 10, 11, 12]), "0-3,7,9-12");
        assert_eq!(array_spec(&[5]), "5");
        assert_eq!(array_spec(&[]), "");
        assert_eq!(array_spec(&[0, 2, 4]), "0,2,4");
    }

    #[test]
    fn the_script_runs_this_binary_on_each_task_and_records_crashes() {
        let folder = EnsembleFolder::at(Path::new("/shared/ens"));
        let script = sbatch_script(&folder, Path::new("/opt/it's/kessler"), &[0, 1, 2, 5], Some(4), 2).unwrap();
        for line in [
            "#SBATCH --array=0-2,5%4",
            "#SBATCH --cpus-per-task=2",
            "#SBATCH --output=/shared/ens/slurm/logs/%A_%a.out",
            "kessler='/opt/it'\\''s/kessler'",
            "dir='/shared/ens'",
            "\"$kessler\" ensemble member \"$dir\" \"$index\"",
        ] {
            assert!(script.lines().any(|l| l == line), "missing {line}:\n{script}");
        }
        assert!(
            sbatch_script(&folder, Path::new("/k"), &[0], None, 1)
                .unwrap()
                .contains("#SBATCH --array=0\n")
        );
        let spaced = EnsembleFolder::at(Path::new("/my ens"));
        assert!(
            sbatch_script(&spaced, Path::new("/k"), &[0], None, 1)
                .unwrap_err()
                .contains("' '")
        );
    }
}
