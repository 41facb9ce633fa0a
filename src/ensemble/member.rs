//! One member (`kessler ensemble member DIR INDEX`, what every executor's
//! processes run): the folder's scenario with the member's combination of
//! settings and its own seed, run for the ensemble's updates with a
//! timeline row every `every`; its timeline and summary written
//! atomically, then the `done` marker. A member that fails writes its
//! `failed` marker instead, with its error.

use std::time::Instant;

use super::EnsembleError;
use super::folder::{EnsembleFolder, Record, hash_text};
use super::seeds::member_seed;
use super::summary::MemberSummary;
use crate::Simulation;
use crate::calibration::machine_auto_split;
use crate::input::{InputError, read_text};
use crate::output::{WriteError, printable, write_atomically};
use crate::scenario::Scenario;
use crate::simulation::Timeline;

/// The scenario member `index` of `record`'s ensemble runs: the folder's
/// copy with the member's combination and seed.
pub fn member_scenario(folder: &EnsembleFolder, record: &Record, index: u64) -> Result<Scenario, EnsembleError> {
    let path = folder.scenario_path();
    let text = read_text(&path)?;
    if hash_text(text.as_bytes()) != record.scenario_hash {
        return Err(EnsembleError::Input(InputError::new(
            path.display().to_string(),
            "changed since the ensemble started (its hash is not the one ensemble.ron names); start a new ensemble in another folder",
        )));
    }
    let mut scenario = Scenario::parse(&text, &path.display().to_string())?;
    let config = &record.config;
    let (combination, member) = config.place(index);
    config.vary.apply(combination, &mut scenario.physics);
    scenario.physics.seed = member_seed(config.seed, member);
    Ok(scenario)
}

/// Runs member `index` and writes its files; on failure, writes its
/// `failed` marker (the error in one line) and returns the error.
pub fn run_member(folder: &EnsembleFolder, record: &Record, index: u64) -> Result<MemberSummary, EnsembleError> {
    let total = record.config.total_members();
    if index >= total {
        return Err(EnsembleError::Arguments(format!(
            "INDEX {index}: the ensemble in {} has {total} members, 0 to {}",
            folder.root().display(),
            total - 1
        )));
    }
    // Whatever an earlier, unfinished (or damaged) run of this member left
    // goes first, folder or not.
    let dir = folder.member_dir(index);
    let cleared = match dir.symlink_metadata() {
        Ok(found) if found.is_dir() => std::fs::remove_dir_all(&dir),
        Ok(_) => std::fs::remove_file(&dir),
        Err(_) => Ok(()),
    };
    cleared.map_err(|source| WriteError {
        path: dir.clone(),
        source,
    })?;
    std::fs::create_dir_all(&dir).map_err(|source| WriteError {
        path: dir.clone(),
        source,
    })?;
    let result = simulate_member(folder, record, index);
    if let Err(e) = &result {
        // Best effort: a member that cannot write its marker is still not
        // done, and runs again on resume.
        let _ = write_atomically(&folder.failed_marker(index), |w| {
            writeln!(w, "{}", printable(&e.to_string()))
        });
    }
    result
}

fn simulate_member(folder: &EnsembleFolder, record: &Record, index: u64) -> Result<MemberSummary, EnsembleError> {
    let start = Instant::now();
    let config = &record.config;
    let scenario = member_scenario(folder, record, index)?;
    let execution = config.member_execution().build(machine_auto_split())?;
    let mut sim = Simulation::from_scenario(&scenario, execution)?;
    let bodies_start = sim.body_count() as u64;
    let mut timeline = Timeline::new(config.every);
    timeline.run(&mut sim, config.steps, |_| {});
    if let Some(fault) = sim.check_state() {
        return Err(EnsembleError::Stopped(format!("member {index}: {fault}")));
    }
    let stats = sim.collision_stats();
    let (combination, member) = config.place(index);
    write_atomically(&folder.timeline(index), |w| timeline.write_csv(w))?;
    let summary = MemberSummary {
        index,
        combination,
        member,
        seed: scenario.physics.seed,
        settings: config.vary.label(combination),
        steps: config.steps,
        bodies_start,
        bodies: sim.body_count() as u64,
        shatters: stats.shatters_total,
        refused_shatters: stats.refused_total,
        state_hash: sim.state_hash().to_string(),
        wall_seconds: start.elapsed().as_secs_f64(),
    };
    let text = ron::ser::to_string_pretty(&summary, ron::ser::PrettyConfig::new().struct_names(true))
        .map_err(|e| EnsembleError::Failed(format!("member {index}: its summary: {e}")))?;
    write_atomically(&folder.summary(index), |w| writeln!(w, "{text}"))?;
    write_atomically(&folder.done_marker(index), |_| Ok(()))?;
    Ok(summary)
}
