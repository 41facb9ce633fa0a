//! What a finished member's `summary.ron` holds, and reading it back.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::input::{InputError, parse_ron, read_text};

/// What `members/<index>/summary.ron` holds.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename = "Member")]
pub struct MemberSummary {
    /// The member's index in the ensemble.
    pub index: u64,
    /// Its combination of settings (`index / members`).
    pub combination: u64,
    /// Its place in the combination (`index % members`), which its seed is
    /// mixed from.
    pub member: u64,
    /// Its seed.
    pub seed: u64,
    /// Its combination in words (`key=value ...`).
    pub settings: String,
    /// Updates run.
    pub steps: u64,
    /// Bodies at the start.
    pub bodies_start: u64,
    /// Bodies at the end.
    pub bodies: u64,
    /// Shatters over the run.
    pub shatters: u64,
    /// Shatters refused over the run.
    pub refused_shatters: u64,
    /// The final state's hash (docs/design.md, "State hash").
    pub state_hash: String,
    /// Seconds the member took, from loading the scenario to its last
    /// file.
    pub wall_seconds: f64,
}

impl MemberSummary {
    /// The summary at `path`.
    pub fn read(path: &Path) -> Result<Self, InputError> {
        parse_ron(
            &read_text(path)?,
            &path.display().to_string(),
            ron::extensions::Extensions::empty(),
        )
    }
}
