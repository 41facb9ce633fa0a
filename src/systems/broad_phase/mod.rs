//! The broad phase's kernels, which the sort and sweep stages
//! (`systems/sort.rs`, `systems/sweep.rs`) run: sweep and prune over a y–z
//! grid — every pair of overlapping boxes (docs/design.md, "Broad phase").
//!
//! A single sweep along x degrades when many boxes share an x range (a dense
//! cloud of a million cubes puts hundreds in every box's x range), so the
//! sweep runs per cell of a grid over y and z:
//!
//! 1. **Sort** (`sorted_boxes.rs`, `filing.rs`, `ordering.rs`; stage
//!    [`SortPlugin`](crate::systems::SortPlugin)): the boxes are filed
//!    under every cell their y–z extent covers, into one array, by a
//!    counting sort that reads the bodies' columns in order, twice (count,
//!    then place), and never gathers at random; then each cell's boxes are
//!    put in order by their lower x bound where they lie (ties by input
//!    order, so the order is one fixed permutation), and the sweep reads
//!    each cell in one piece, in order.
//! 2. **Sweep** (`sweep_pairs.rs`; stage
//!    [`SweepPlugin`](crate::systems::SweepPlugin)): in each cell, each box
//!    scans forward while the next box starts before it ends on x,
//!    and confirms y and z. Touching counts as overlap. A pair found in
//!    several cells is reported only by the cell holding the lower corner of
//!    the pair's y–z intersection, so every pair comes out exactly once. A
//!    big box (the planet) joins the cells it covers and scans only the
//!    boxes inside its x-slab there, so the cost stays near-linear.
//!
//! In parallel, contiguous ranges of boxes are counted, and then placed,
//! by their own chunk: within a cell, each chunk's boxes get the slots
//! after those of the chunks before it, which is input order again, so
//! the filing is the same array as one sequential pass. Contiguous ranges
//! of cells are then ordered, and swept, by their own chunk, and the pairs
//! are concatenated in cell order: the same pairs in the same order as one
//! sequential pass.

mod aabb;
mod boxes;
mod filing;
mod grid;
mod ordering;
mod sorted_boxes;
mod sweep_pairs;

pub use aabb::Aabb;
pub use boxes::{BodyColumns, BoxSource, BroadPhaseQuery, TableColumns, swept_box};
pub use sorted_boxes::{SortedBoxes, sort_boxes};
pub use sweep_pairs::{
    MIN_PAIR_LIMIT, PAIRS_PER_BOX, TooManyPairs, id_pairs, pair_limit, sweep_and_prune, sweep_sorted,
};
