//! The calibration file: `calibration.ron` beside the settings, written by
//! `kessler calibrate`, read wherever split policy `Auto` is used. A
//! missing file means the fallback; a broken one gives a warning and the
//! fallback, never a failure (like the settings file).

use std::collections::BTreeMap;

use std::path::Path;

use ron::extensions::Extensions;
use serde::{Deserialize, Serialize};

use crate::execution::AutoSplit;
use crate::input::default_calibration_path;
use crate::input::{parse_ron, read_text_if_present};
use crate::output::{WriteError, through_link, write_atomically};

/// A calibration of this machine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// Worker threads it was measured with.
    pub threads: usize,
    /// When it was measured (UTC).
    pub date: String,
    /// The CPU it was measured on.
    pub cpu: String,
    /// Per stage name: the body count from which splitting paid.
    pub split_from: BTreeMap<String, u64>,
}

impl Calibration {
    /// The counts as `Auto` uses them, described with `path`.
    pub fn auto_split(&self, path: &Path) -> AutoSplit {
        AutoSplit::calibrated(
            self.split_from.iter().map(|(k, &v)| (k.clone(), v)).collect(),
            format!(
                "calibrated on {} thread{} ({}, {})",
                self.threads,
                if self.threads == 1 { "" } else { "s" },
                path.display(),
                self.date
            ),
        )
    }

    /// Writes the calibration to `path` (replacing an older one; through
    /// a symbolic link there, to the file it names).
    pub fn save(&self, path: &Path) -> Result<(), WriteError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| WriteError {
                path: path.to_owned(),
                source,
            })?;
        }
        let text = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .expect("a calibration always serializes");
        write_atomically(&through_link(path)?, |w| {
            writeln!(
                w,
                "// This machine's split calibration, written by `kessler calibrate`;\n\
                 // split policy `Auto` splits a stage from its `split_from` body count."
            )?;
            writeln!(w, "{text}")
        })
    }
}

/// The calibration at `path`: `Ok(None)` if there is none, an error message
/// naming the file and the problem if it cannot be used.
pub fn load_calibration(path: &Path) -> Result<Option<Calibration>, String> {
    let Some(text) = read_text_if_present(path).map_err(|e| e.to_string())? else {
        return Ok(None);
    };
    parse_ron(&text, &path.display().to_string(), Extensions::empty())
        .map(Some)
        .map_err(|e| e.to_string())
}

/// What `Auto` uses with the calibration at `path`, and a warning when the
/// file is there but cannot be used (then: the fallback).
pub fn auto_split_from(path: &Path) -> (AutoSplit, Option<String>) {
    match load_calibration(path) {
        Ok(Some(calibration)) => (calibration.auto_split(path), None),
        Ok(None) => (AutoSplit::fallback(), None),
        Err(e) => (
            AutoSplit::fallback(),
            Some(format!(
                "{e}; split policy `auto` uses the fallback (run `kessler calibrate` to measure this machine again)"
            )),
        ),
    }
}

/// What `Auto` uses on this machine: the calibration beside the settings,
/// else the fallback; a broken file is reported on stderr and skipped.
pub fn machine_auto_split() -> AutoSplit {
    let (auto, warning) = auto_split_from(&default_calibration_path());
    if let Some(warning) = warning {
        eprintln!("kessler: warning: {}", crate::output::printable(&warning));
    }
    auto
}

#[cfg(test)]
mod tests {
    use super::*;

    fn calibration() -> Calibration {
        Calibration {
            threads: 2,
            date: "2026-11-30 12:00:00 UTC".into(),
            cpu: "test cpu".into(),
            split_from: [("gravity".to_owned(), 2000), ("sort".to_owned(), 8000)].into(),
        }
    }

    #[test]
    fn a_saved_calibration_is_what_auto_uses() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nested").join("calibration.ron");
        calibration().save(&path).unwrap();
        assert_eq!(load_calibration(&path), Ok(Some(calibration())));
        let (auto, warning) = auto_split_from(&path);
        assert_eq!(warning, None);
        assert_eq!((auto.split_from("gravity"), auto.split_from("sort")), (2000, 8000));
        assert!(auto.origin().contains("calibrated on 2 threads"), "{}", auto.origin());
    }

    #[test]
    fn no_file_means_the_fallback_and_a_broken_one_a_warning_too() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("calibration.ron");
        assert_eq!(auto_split_from(&path), (AutoSplit::fallback(), None));
        std::fs::write(&path, "Calibration(threads: 2, split_from: {\"sort\": -5})").unwrap();
        let (auto, warning) = auto_split_from(&path);
        assert_eq!(auto, AutoSplit::fallback());
        let warning = warning.unwrap();
        assert!(
            warning.contains("calibration.ron") && warning.contains("fallback"),
            "{warning}"
        );
    }
}
