//! `kessler pairs SCENARIO`: the overlapping pairs of the initial state.

use std::io::BufWriter;
use std::path::Path;

use super::Failure;
use super::headless::execution;
use crate::components::BodyId;
use crate::input::ExecutionOptions;
use crate::output::write_csv;
use crate::physics::Aabb;
use crate::scenario::Scenario;
use crate::systems::{SortedBoxes, id_pairs, sweep_and_prune};

/// Prints `a,b` and then one line per overlapping pair, lower id first,
/// sorted.
pub fn pairs(path: &Path, args: &ExecutionOptions) -> Result<(), Failure> {
    let bodies = Scenario::load(path)?.bodies()?;
    let boxes: Vec<Aabb> = bodies.iter().map(|b| Aabb::new(b.position, b.half_extents)).collect();
    let ids: Vec<BodyId> = bodies.iter().map(|b| b.id).collect();
    let found = sweep_and_prune(boxes.as_slice(), &execution(args)?, &mut SortedBoxes::default())
        .map_err(|e| Failure::input(format!("{}: {e}", path.display())))?;
    let rows: Vec<PairRow> = id_pairs(&found, &ids).into_iter().map(|(a, b)| PairRow(a, b)).collect();
    write_csv(BufWriter::new(std::io::stdout().lock()), &rows)
        .map_err(|e| Failure::other(format!("writing the pairs: {e}")))
}

/// One overlapping pair, lower id first.
struct PairRow(BodyId, BodyId);

crate::csv_row!(PairRow, |p| { a: p.0.0, b: p.1.0 });
