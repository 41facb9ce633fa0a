//! `kessler pairs SCENARIO`: the overlapping pairs of the initial state.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::headless::execution;
use super::{ExecutionArgs, Failure};
use crate::components::BodyId;
use crate::scenario::Scenario;
use crate::systems::{Aabb, SortedBoxes, id_pairs, sweep_and_prune};

/// Prints `a,b` and then one line per overlapping pair, lower id first,
/// sorted.
pub fn pairs(path: &Path, args: &ExecutionArgs) -> Result<(), Failure> {
    let bodies = Scenario::load(path)?.bodies()?;
    let boxes: Vec<Aabb> = bodies.iter().map(|b| Aabb::new(b.position, b.half_extents)).collect();
    let ids: Vec<BodyId> = bodies.iter().map(|b| b.id).collect();
    let found = sweep_and_prune(boxes.as_slice(), &execution(args)?, &mut SortedBoxes::default())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))?;
    let mut out = BufWriter::new(std::io::stdout().lock());
    let written = (|| {
        writeln!(out, "a,b")?;
        for (a, b) in id_pairs(&found, &ids) {
            writeln!(out, "{},{}", a.0, b.0)?;
        }
        out.flush()
    })();
    written.map_err(|e| Failure::other(format!("writing the pairs: {e}")))
}
