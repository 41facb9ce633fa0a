//! The sort stage's work on any [`BoxSource`]: a grid fitted to the boxes,
//! the boxes filed by cell (chunks of boxes), and each cell put in sweep
//! order where it lies (chunks of cells) — [`SortedBoxes`], ready for the
//! sweep.

use std::sync::{Mutex, PoisonError};

use bevy::prelude::*;

use super::BoxSource;
use super::filing::{
    CellBox, ChunkCount, cell_starts, corner_bounds, corner_sample, count_by_cell, place_by_cell, placings,
};
use super::grid::{GRID_SAMPLES, Grid, SampledBox};
use super::ordering::{CellRuns, order_cells};
use crate::execution::StageExecution;

/// The sort stage's result: the grid and every cell's boxes in sweep
/// order, in one array, cell after cell. Its buffers are kept and reused
/// by the next sort, so that a million boxes do not fault in fresh pages
/// every update: about 32 bytes per box (a box is filed once per cell it
/// covers, mostly one), run whole or split.
#[derive(Resource, Default)]
pub struct SortedBoxes {
    grid: Option<Grid>,
    /// Cell `c`'s boxes are `boxes[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    boxes: Vec<CellBox>,
    /// The last sort's counts, one per chunk of boxes.
    counts: Vec<ChunkCount>,
    /// Count buffers the last sort did not need.
    spare_counts: Vec<ChunkCount>,
    len: usize,
}

impl SortedBoxes {
    /// The grid of the last sort; `None` before the first or after
    /// [`clear`](Self::clear).
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// `cell`'s boxes in sweep order.
    #[inline]
    pub fn in_sweep_order(&self, cell: usize) -> &[CellBox] {
        &self.boxes[self.starts[cell] as usize..self.starts[cell + 1] as usize]
    }

    /// Number of boxes sorted.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when no boxes are sorted.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Forgets the boxes (keeping the buffers).
    pub fn clear(&mut self) {
        self.grid = None;
        self.len = 0;
    }
}

/// Boxes a chunk of the filing holds at least per grid cell: every chunk
/// counts into, and places from, one slot per cell, so that cost stays a
/// small share of its own boxes' work however many threads there are (at
/// a million boxes, 64 chunks for 16 threads cost a million slots).
const BOXES_PER_COUNTED_CELL: usize = 4;

/// Sorts `boxes` into `sorted`, reusing its buffers: an even sample of
/// the boxes' lower y–z corners, the grid fitted to them, the filing by cell
/// (counted by chunks of boxes, laid out, placed by the same chunks), then
/// the ordering of each cell on x where it lies (by chunks of cells), each
/// step whole or in chunks as `stage` says.
pub fn sort_boxes<B: BoxSource + ?Sized>(boxes: &B, stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
    // An even sample of the corners to fit the grid to their bulk: a few
    // far-flung boxes must not stretch it. Their true bounds only where
    // the sample cannot place the grid alone. The sample (at most
    // GRID_SAMPLES boxes) is read whole: cut into chunks, the grid's fit
    // took 25 µs against 18 at 10 000 boxes on 2 threads.
    let stride = boxes.len() / GRID_SAMPLES + 1;
    let sample: Vec<SampledBox> = corner_sample(boxes, stride);
    let grid = Grid::fit_to_bulk(&sample, boxes.len(), || {
        stage
            .map_chunks(0..boxes.len(), |range| corner_bounds(boxes, range))
            .into_iter()
            .fold(
                (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
                |(lo, hi), (l, h)| (lo.min(l), hi.max(h)),
            )
    });
    let spare = Spare::new(&mut sorted.spare_counts, &mut sorted.counts);
    let least = grid.cell_count() * BOXES_PER_COUNTED_CELL;
    sorted.counts = stage.map_chunks_of_at_least(0..boxes.len(), least, |range| {
        count_by_cell(boxes, range, &grid, spare.take())
    });
    sorted.spare_counts = spare.into_inner();
    let filed = cell_starts(&sorted.counts, grid.cell_count(), &mut sorted.starts);
    // Same length as last update's in a steady state: nothing to write here.
    sorted.boxes.resize(filed, CellBox::default());
    stage.for_chunks(placings(&sorted.counts, &mut sorted.boxes).as_mut_slice(), |chunks| {
        place_by_cell(boxes, &grid, chunks);
    });
    stage.for_chunks(CellRuns::new(&sorted.starts, &mut sorted.boxes), order_cells);
    sorted.grid = Some(grid);
    sorted.len = boxes.len();
}

/// Buffers to reuse, handed out to the chunks of a step.
struct Spare<T>(Mutex<Vec<T>>);

impl<T: Default> Spare<T> {
    /// The spare buffers and those of the last sort.
    fn new(spare: &mut Vec<T>, used: &mut Vec<T>) -> Self {
        let mut all = std::mem::take(spare);
        all.append(used);
        Self(Mutex::new(all))
    }

    /// A buffer, reused if any is left.
    fn take(&self) -> T {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop()
            .unwrap_or_default()
    }

    /// The buffers no chunk took.
    fn into_inner(self) -> Vec<T> {
        self.0.into_inner().unwrap_or_else(PoisonError::into_inner)
    }
}
