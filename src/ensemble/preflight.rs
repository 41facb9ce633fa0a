//! Starting (or resuming) an ensemble: the config read and checked, every
//! combination's scenario built once (so that a bad value fails before any
//! member runs), the output folder checked, and its record written — or,
//! where the folder holds an ensemble already, its record compared with
//! this config's: the same runs resume, other runs are refused, naming
//! what differs.

use std::path::Path;

use super::EnsembleError;
use super::config::EnsembleConfig;
use super::folder::{Census, EnsembleFolder, Record};
use super::seeds::member_seed;
use crate::input::{InputError, read_text};
use crate::scenario::{DEFAULT_SCENARIO, DEFAULT_SCENARIO_NAME, Scenario};

/// An ensemble ready to run: its folder, its record, where its members
/// stand, and a warning for the user if any.
#[derive(Clone, Debug)]
pub struct Started {
    /// The folder.
    pub folder: EnsembleFolder,
    /// Its record.
    pub record: Record,
    /// Where each member stands.
    pub census: Census,
    /// Whether the folder held this ensemble already.
    pub resumed: bool,
    /// Something the user should know (another Kessler commit made the
    /// finished members).
    pub warning: Option<String>,
}

/// Reads the config at `config_path`, checks it and the folder `out`
/// before any work, and writes the folder's record if it is new.
pub fn start(config_path: &Path, out: &Path) -> Result<Started, EnsembleError> {
    let config = EnsembleConfig::load(config_path)?;
    let origin = config_path.display().to_string();
    let (scenario_source, text) = match config.scenario_path(config_path) {
        Some(path) => (
            std::fs::canonicalize(&path)
                .unwrap_or_else(|_| path.clone())
                .display()
                .to_string(),
            read_text(&path).map_err(|e| InputError::new(&origin, format!("field `scenario`: {e}")))?,
        ),
        None => (DEFAULT_SCENARIO_NAME.to_owned(), DEFAULT_SCENARIO.to_owned()),
    };
    let scenario = Scenario::parse(&text, &scenario_source)
        .map_err(|e| InputError::new(&origin, format!("field `scenario`: {e}")))?;
    // Every combination's start, with the first member's seed (the events
    // of update 0 applied): a value that breaks the scenario (a pile-up,
    // an overflowing pull) fails now.
    for combination in 0..config.vary.combinations() {
        let mut this = scenario.clone();
        config.vary.apply(combination, &mut this.physics);
        this.physics.seed = member_seed(config.seed, 0);
        crate::simulation::Simulation::check_start(&this).map_err(|e| {
            InputError::new(
                &origin,
                format!("field `vary`: with {}: {e}", config.vary.label(combination)),
            )
        })?;
    }
    let record = Record::new(&config, config_path, &scenario_source, &text);
    let (folder, existing) = EnsembleFolder::prepare(out)?;
    folder.check_layout()?;
    let mut warning = None;
    let resumed = existing.is_some();
    match &existing {
        Some(theirs) => {
            let differences = record.differences(theirs);
            if !differences.is_empty() {
                let said: Vec<String> = differences
                    .iter()
                    .map(|(field, theirs, mine)| format!("`{field}` is {theirs} there, {mine} here"))
                    .collect();
                return Err(EnsembleError::Arguments(format!(
                    "--out {}: holds another ensemble ({}); give another --out, or the config it was started with ({})",
                    out.display(),
                    said.join("; "),
                    theirs.source
                )));
            }
            if theirs.commit != record.commit {
                warning = Some(format!(
                    "{}: its finished members were run by Kessler commit {}, this is {}; they are kept, and where the physics changed between the two the members differ",
                    out.display(),
                    theirs.commit,
                    record.commit
                ));
            }
        }
        None => folder.write_record(&record, &text)?,
    }
    let census = folder.checked_census(&existing.as_ref().unwrap_or(&record).config);
    Ok(Started {
        // The folder's own record: its source names the config that
        // started it.
        record: existing.unwrap_or(record),
        folder,
        census,
        resumed,
        warning,
    })
}
