//! An ensemble's folder, which holds everything about it:
//!
//! ```text
//! DIR/ensemble.ron            the resolved config, its hash, Kessler's version and commit
//! DIR/scenario.ron            the scenario every member runs (a copy)
//! DIR/members/<index>/        timeline.csv, summary.ron, then `done`
//!                             (or `failed`: the last line of its error)
//! DIR/logs/<index>.err        a local member's stderr while it runs (kept if it fails)
//! DIR/slurm/                  ensemble.sbatch, jobs (the ids submitted), logs/
//! DIR/aggregate.csv, bodies.svg, bodies.png
//! ```
//!
//! A member is done when its `done` marker is there: its other files were
//! each written atomically before it. Anything else in its folder is what
//! a member that stopped half-way left, and is removed when it runs again.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use ron::extensions::Extensions;
use serde::{Deserialize, Serialize};

use super::config::EnsembleConfig;
use super::summary::MemberSummary;
use crate::input::{InputError, node_kind, parse_ron, read_text};
use crate::output::CsvTable;
use crate::output::{OutputError, OutputProblem, WriteError, probe, write_atomically};
use crate::simulation::{TimelineRow, row_updates};

/// What `DIR/ensemble.ron` holds.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename = "EnsembleFolder")]
pub struct Record {
    /// The config, its scenario the copy in the folder (`scenario.ron`).
    pub config: EnsembleConfig,
    /// The config file it was read from (for the reader; not compared).
    pub source: String,
    /// Where the scenario came from (for the reader; not compared).
    pub scenario_source: String,
    /// xxHash64 of the scenario copy's text, 16 hex digits.
    pub scenario_hash: String,
    /// xxHash64 of the config as written here and the scenario's hash.
    pub config_hash: String,
    /// The Kessler version that started the ensemble.
    pub kessler: String,
    /// Its commit.
    pub commit: String,
}

/// Name of the scenario copy in the folder.
pub const SCENARIO_COPY: &str = "scenario.ron";

/// 16 hex digits of xxHash64 (seed 0) of `bytes`.
pub fn hash_text(bytes: &[u8]) -> String {
    format!("{:016x}", twox_hash::XxHash64::oneshot(0, bytes))
}

impl Record {
    /// The record of `config` (read from `source`) whose scenario text is
    /// `scenario_text` (from `scenario_source`).
    pub fn new(config: &EnsembleConfig, source: &Path, scenario_source: &str, scenario_text: &str) -> Self {
        let config = EnsembleConfig {
            scenario: Some(PathBuf::from(SCENARIO_COPY)),
            ..config.clone()
        };
        let scenario_hash = hash_text(scenario_text.as_bytes());
        let config_text = ron::to_string(&config).unwrap_or_default();
        Self {
            config_hash: hash_text(format!("{config_text}\n{scenario_hash}").as_bytes()),
            config,
            source: std::path::absolute(source)
                .unwrap_or_else(|_| source.to_owned())
                .display()
                .to_string(),
            scenario_source: scenario_source.to_owned(),
            scenario_hash,
            kessler: env!("CARGO_PKG_VERSION").to_owned(),
            commit: env!("KESSLER_GIT_COMMIT").to_owned(),
        }
    }

    /// How this record's ensemble differs from `other`'s, field by field
    /// (`field`: theirs, ours); empty where the members are the same runs.
    pub fn differences(&self, other: &Self) -> Vec<(&'static str, String, String)> {
        let mut found: Vec<_> = self
            .config
            .fields()
            .into_iter()
            .zip(other.config.fields())
            .filter(|((_, mine), (_, theirs))| mine != theirs)
            .map(|((field, mine), (_, theirs))| (field, theirs, mine))
            .collect();
        if self.scenario_hash != other.scenario_hash {
            found.push((
                "scenario",
                format!("{} (hash {})", other.scenario_source, other.scenario_hash),
                format!("{} (hash {})", self.scenario_source, self.scenario_hash),
            ));
        }
        found
    }
}

/// Where a member stands.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MemberState {
    /// Its results are complete.
    Done,
    /// It ran and failed: the last line of its error.
    Failed(String),
    /// Not run yet, or stopped before it finished.
    Missing,
}

/// How many members are done, failed and missing.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Census {
    /// Indices of the members that are done.
    pub done: Vec<u64>,
    /// Indices of the members that failed, with the last line of their error.
    pub failed: Vec<(u64, String)>,
    /// Indices of the members not run or not finished.
    pub missing: Vec<u64>,
}

impl Census {
    /// The members still to run: the failed and the missing, in order.
    pub fn to_run(&self) -> Vec<u64> {
        let mut indices: Vec<u64> = self
            .failed
            .iter()
            .map(|(i, _)| *i)
            .chain(self.missing.iter().copied())
            .collect();
        indices.sort_unstable();
        indices
    }

    /// One line: `N done, F failed, M missing of T`.
    pub fn line(&self) -> String {
        let total = self.done.len() + self.failed.len() + self.missing.len();
        format!(
            "{} done, {} failed, {} missing of {total} members",
            self.done.len(),
            self.failed.len(),
            self.missing.len()
        )
    }
}

/// An ensemble's folder (see the module's documentation).
#[derive(Clone, Debug)]
pub struct EnsembleFolder {
    root: PathBuf,
}

impl EnsembleFolder {
    /// The folder at `root` (nothing checked).
    pub fn at(root: &Path) -> Self {
        Self {
            root: std::path::absolute(root).unwrap_or_else(|_| root.to_owned()),
        }
    }

    /// The folder's path, absolute.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `DIR/ensemble.ron`.
    pub fn record_path(&self) -> PathBuf {
        self.root.join("ensemble.ron")
    }

    /// `DIR/scenario.ron`, the scenario copy.
    pub fn scenario_path(&self) -> PathBuf {
        self.root.join(SCENARIO_COPY)
    }

    /// `DIR/members/<index>/`.
    pub fn member_dir(&self, index: u64) -> PathBuf {
        self.root.join("members").join(index.to_string())
    }

    /// A member's timeline.
    pub fn timeline(&self, index: u64) -> PathBuf {
        self.member_dir(index).join("timeline.csv")
    }

    /// A member's summary.
    pub fn summary(&self, index: u64) -> PathBuf {
        self.member_dir(index).join("summary.ron")
    }

    /// A member's completion marker, written last.
    pub fn done_marker(&self, index: u64) -> PathBuf {
        self.member_dir(index).join("done")
    }

    /// A member's failure marker: the last line of its error.
    pub fn failed_marker(&self, index: u64) -> PathBuf {
        self.member_dir(index).join("failed")
    }

    /// `DIR/logs/<index>.err`: a local member's stderr.
    pub fn log(&self, index: u64) -> PathBuf {
        self.root.join("logs").join(format!("{index}.err"))
    }

    /// `DIR/slurm/`.
    pub fn slurm_dir(&self) -> PathBuf {
        self.root.join("slurm")
    }

    /// `DIR/aggregate.csv`.
    pub fn aggregate_csv(&self) -> PathBuf {
        self.root.join("aggregate.csv")
    }

    /// `DIR/bodies.<extension>`: the plot.
    pub fn plot(&self, extension: &str) -> PathBuf {
        self.root.join(format!("bodies.{extension}"))
    }

    /// Checks, before any work, that `out` (given as `--out`) can hold an
    /// ensemble: a folder (made here if only it is missing) in which files
    /// can be made, empty or holding an ensemble already; returns the
    /// record there, if any.
    pub fn prepare(out: &Path) -> Result<(Self, Option<Record>), OutputError> {
        let fail = |problem| OutputError {
            flag: "--out".to_owned(),
            path: out.to_owned(),
            problem,
        };
        match out.symlink_metadata() {
            // A folder, or a link to one.
            Ok(_) if out.is_dir() => {}
            Ok(meta) => return Err(fail(OutputProblem::NotAFolder(node_kind(meta.file_type())))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                let parent = out
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
                if !parent.is_dir() {
                    return Err(fail(OutputProblem::FolderMissing(parent.to_owned())));
                }
                std::fs::create_dir(out).map_err(|e| fail(OutputProblem::FolderUnwritable(parent.to_owned(), e)))?;
            }
            Err(e) => return Err(fail(OutputProblem::Unusable(e))),
        }
        let folder = Self::at(out);
        // The very temporary file a write of the record would make.
        if let Err(e) = probe(&folder.record_path()) {
            return Err(fail(OutputProblem::FolderUnwritable(out.to_owned(), e)));
        }
        if folder.record_path().exists() {
            let record = folder.record().map_err(|e| {
                fail(OutputProblem::Unusable(std::io::Error::other(format!(
                    "holds an ensemble.ron that cannot be read ({e})"
                ))))
            })?;
            return Ok((folder, Some(record)));
        }
        let holds_something = std::fs::read_dir(out)
            .map_err(|e| fail(OutputProblem::Unusable(e)))?
            .next()
            .is_some();
        if holds_something {
            return Err(fail(OutputProblem::Exists(
                "it holds files but no ensemble.ron; give a new or empty folder",
            )));
        }
        Ok((folder, None))
    }

    /// The folders an ensemble keeps its files in, with what each holds.
    const SUBFOLDERS: [(&'static str, &'static str); 4] = [
        ("members", "its members' results"),
        ("logs", "its local members' stderr"),
        ("slurm", "its Slurm job script and ids"),
        ("slurm/logs", "its Slurm members' output"),
    ];

    /// Checks that each folder the ensemble keeps files in is a folder (or
    /// a link to one) or missing (it is made when needed): a file or
    /// anything else there is named, with what to do.
    pub fn check_layout(&self) -> Result<(), InputError> {
        for (name, holds) in Self::SUBFOLDERS {
            let path = self.root.join(name);
            let kind = match path.symlink_metadata() {
                // A folder, or a link to one.
                Ok(_) if path.is_dir() => continue,
                Ok(meta) => node_kind(meta.file_type()),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Err(e) => {
                    return Err(InputError::new(path.display().to_string(), e.to_string()));
                }
            };
            return Err(InputError::new(
                path.display().to_string(),
                format!(
                    "is {kind}, where the ensemble keeps {holds} in a folder; move it away (or remove it), then run the same command again"
                ),
            ));
        }
        Ok(())
    }

    /// The folder at `dir`, which must hold an ensemble, and its record.
    pub fn open(dir: &Path) -> Result<(Self, Record), InputError> {
        let folder = Self::at(dir);
        if !dir.is_dir() {
            let problem = match dir.symlink_metadata() {
                Ok(found) => format!(
                    "is {}, not an ensemble's folder; give the folder `kessler ensemble CONFIG --out DIR` made",
                    node_kind(found.file_type())
                ),
                Err(_) => "is not an ensemble's folder (no such folder)".to_owned(),
            };
            return Err(InputError::new(dir.display().to_string(), problem));
        }
        if !folder.record_path().is_file() {
            return Err(InputError::new(
                dir.display().to_string(),
                "is not an ensemble's folder (it holds no ensemble.ron; `kessler ensemble CONFIG --out DIR` makes one)",
            ));
        }
        let record = folder.record()?;
        folder.check_layout()?;
        Ok((folder, record))
    }

    /// Reads `DIR/ensemble.ron`.
    pub fn record(&self) -> Result<Record, InputError> {
        let path = self.record_path();
        parse_ron(
            &read_text(&path)?,
            &path.display().to_string(),
            Extensions::IMPLICIT_SOME | Extensions::UNWRAP_VARIANT_NEWTYPES,
        )
    }

    /// Writes `DIR/ensemble.ron` and the scenario copy.
    pub fn write_record(&self, record: &Record, scenario_text: &str) -> Result<(), WriteError> {
        std::fs::create_dir_all(self.root.join("members")).map_err(|source| WriteError {
            path: self.root.join("members"),
            source,
        })?;
        write_atomically(&self.scenario_path(), |w| w.write_all(scenario_text.as_bytes()))?;
        let pretty = ron::ser::PrettyConfig::new()
            .struct_names(true)
            .extensions(Extensions::IMPLICIT_SOME);
        let text = ron::ser::to_string_pretty(record, pretty).map_err(|e| WriteError {
            path: self.record_path(),
            source: std::io::Error::other(e),
        })?;
        write_atomically(&self.record_path(), |w| {
            writeln!(
                w,
                "// An ensemble's folder, written by `kessler ensemble`: the config its members run.\n// Running the same command again resumes it; `kessler ensemble status` counts its members."
            )?;
            writeln!(w, "{text}")
        })
    }

    /// Where member `index` stands.
    pub fn member_state(&self, index: u64) -> MemberState {
        if self.done_marker(index).is_file() {
            MemberState::Done
        } else if let Ok(text) = std::fs::read_to_string(self.failed_marker(index)) {
            MemberState::Failed(text.trim().to_owned())
        } else {
            MemberState::Missing
        }
    }

    /// Where each of the `total` members stands: one listing of
    /// `DIR/members/` and a look into the folders it names.
    pub fn census(&self, total: u64) -> Census {
        let mut census = Census::default();
        let mut started = vec![false; total as usize];
        if let Ok(entries) = std::fs::read_dir(self.root.join("members")) {
            for entry in entries.flatten() {
                if let Some(index) = entry.file_name().to_str().and_then(|n| n.parse::<u64>().ok())
                    && index < total
                {
                    started[index as usize] = true;
                }
            }
        }
        for (index, started) in started.into_iter().enumerate() {
            let index = index as u64;
            match started.then(|| self.member_state(index)) {
                Some(MemberState::Done) => census.done.push(index),
                Some(MemberState::Failed(why)) => census.failed.push((index, why)),
                Some(MemberState::Missing) | None => census.missing.push(index),
            }
        }
        census
    }

    /// Where each member of `config` stands, as [`Self::census`] says,
    /// with every done member's results checked ([`Self::check_done`]):
    /// one whose files were damaged after it finished counts as failed,
    /// saying what is wrong, and so runs again on resume.
    pub fn checked_census(&self, config: &EnsembleConfig) -> Census {
        let mut census = self.census(config.total_members());
        let checks: Vec<(u64, Result<(), String>)> = census
            .done
            .par_iter()
            .map(|&index| (index, self.check_done(index, config)))
            .collect();
        census.done.clear();
        for (index, check) in checks {
            match check {
                Ok(()) => census.done.push(index),
                Err(why) => census.failed.push((
                    index,
                    format!("its results were damaged after it finished: {why}; it runs again"),
                )),
            }
        }
        census.failed.sort_unstable();
        census
    }

    /// Whether done member `index`'s results are whole: its summary and
    /// timeline regular files, the timeline a row at every update a
    /// finished member of `config` records one at, each number finite, the
    /// summary readable and agreeing with the timeline's last row.
    pub fn check_done(&self, index: u64, config: &EnsembleConfig) -> Result<(), String> {
        for path in [self.timeline(index), self.summary(index)] {
            let name = path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
            match path.symlink_metadata() {
                Ok(found) if found.is_file() => {}
                Ok(found) => return Err(format!("{name} is {}", node_kind(found.file_type()))),
                Err(_) => return Err(format!("{name} is missing")),
            }
        }
        let text = read_text(&self.timeline(index)).map_err(|e| e.to_string())?;
        let table = CsvTable::parse::<TimelineRow>(&text).map_err(|e| format!("timeline.csv: {e}"))?;
        let expected = row_updates(config.steps, config.every);
        let updates = table.column("update").unwrap_or_default();
        let whole = updates.len() == expected.len()
            && updates
                .iter()
                .zip(&expected)
                .all(|(cell, u)| cell.parse::<u64>().ok() == Some(*u));
        if !whole {
            return Err(format!(
                "timeline.csv has {} rows, not the {} of a finished member",
                updates.len(),
                expected.len()
            ));
        }
        for (r, row) in table.rows().iter().enumerate() {
            // Every column but the last, the state's hash, is a number.
            let numbers = &row[..row.len().saturating_sub(1)];
            if let Some(cell) = numbers.iter().find(|c| !c.parse::<f64>().is_ok_and(f64::is_finite)) {
                return Err(format!("timeline.csv row {}: `{cell}` is not a finite number", r + 1));
            }
        }
        // The summary reads back and says what the timeline's last row
        // says: the member, its updates, its bodies and its state's hash.
        let summary = MemberSummary::read(&self.summary(index)).map_err(|e| e.to_string())?;
        let last = |column: &str| {
            table
                .column(column)
                .and_then(|cells| cells.last().map(|c| (*c).to_owned()))
                .unwrap_or_default()
        };
        let (combination, member) = config.place(index);
        let disagreements = [
            ("index", summary.index.to_string(), index.to_string()),
            ("combination", summary.combination.to_string(), combination.to_string()),
            ("member", summary.member.to_string(), member.to_string()),
            ("steps", summary.steps.to_string(), config.steps.to_string()),
            ("bodies", summary.bodies.to_string(), last("bodies")),
            ("state_hash", summary.state_hash.clone(), last("state_hash")),
        ];
        if let Some((field, said, expected)) = disagreements.into_iter().find(|(_, said, expected)| said != expected) {
            return Err(format!(
                "summary.ron says {field} {said}, where its ensemble and timeline say {expected}"
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(text: &str) -> EnsembleConfig {
        EnsembleConfig::parse(text, "e.ron").unwrap()
    }

    #[test]
    fn records_differ_by_the_fields_that_change_the_runs() {
        let a = Record::new(
            &config("Ensemble(steps: 10, members: 2)"),
            Path::new("a.ron"),
            "s.ron",
            "S()",
        );
        let moved = Record::new(
            &config("Ensemble(steps: 10, members: 2)"),
            Path::new("b/a.ron"),
            "t.ron",
            "S()",
        );
        assert_eq!(a.differences(&moved), []);
        assert_eq!(a.config_hash, moved.config_hash);
        let b = Record::new(
            &config("Ensemble(steps: 20, members: 2, vary: (time_step: [0.5]))"),
            Path::new("a.ron"),
            "s.ron",
            "S(seed: 2)",
        );
        let fields: Vec<_> = b.differences(&a).into_iter().map(|(field, ..)| field).collect();
        assert_eq!(fields, ["steps", "vary", "scenario"]);
        assert_eq!(b.differences(&a)[0], ("steps", "10".to_owned(), "20".to_owned()));
        assert_ne!(a.config_hash, b.config_hash);
    }

    #[test]
    fn the_folder_is_checked_made_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ens");
        let (folder, none) = EnsembleFolder::prepare(&out).unwrap();
        assert!(none.is_none() && out.is_dir());
        let record = Record::new(
            &config("Ensemble(steps: 10, members: 2)"),
            Path::new("a.ron"),
            "s.ron",
            "S()",
        );
        folder.write_record(&record, "S()").unwrap();
        let (_, again) = EnsembleFolder::prepare(&out).unwrap();
        assert_eq!(again, Some(record.clone()));
        assert_eq!(EnsembleFolder::open(&out).unwrap().1, record);
        assert_eq!(std::fs::read_to_string(folder.scenario_path()).unwrap(), "S()");

        let census = folder.census(3);
        assert_eq!(census.missing, [0, 1, 2]);
        std::fs::create_dir_all(folder.member_dir(1)).unwrap();
        std::fs::write(folder.done_marker(1), "").unwrap();
        std::fs::create_dir_all(folder.member_dir(2)).unwrap();
        std::fs::write(folder.failed_marker(2), "boom\n").unwrap();
        let census = folder.census(3);
        assert_eq!(census.done, [1]);
        assert_eq!(census.failed, [(2, "boom".to_owned())]);
        assert_eq!(census.to_run(), [0, 2]);
        assert_eq!(census.line(), "1 done, 1 failed, 1 missing of 3 members");

        let file = dir.path().join("file");
        std::fs::write(&file, "x").unwrap();
        let e = EnsembleFolder::prepare(&file).unwrap_err().to_string();
        assert!(e.contains("is a file; give a folder"), "{e}");
        let busy = dir.path().join("busy");
        std::fs::create_dir(&busy).unwrap();
        std::fs::write(busy.join("x"), "x").unwrap();
        let e = EnsembleFolder::prepare(&busy).unwrap_err().to_string();
        assert!(e.contains("holds files but no ensemble.ron"), "{e}");
        let e = EnsembleFolder::prepare(&dir.path().join("no/such"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
    }
}
