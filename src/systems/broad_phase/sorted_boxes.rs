//! The sort stage's work on any [`BoxSource`]: a grid fitted to the boxes,
//! the boxes filed by cell (chunks of boxes), and each cell put in sweep
//! order (chunks of cells) — [`SortedBoxes`], ready for the sweep.

use std::sync::{Mutex, PoisonError};

use bevy::prelude::*;

use super::BoxSource;
use super::filing::CellBox;
use super::filing::{FiledChunk, corner_bounds, corner_sample, file_by_cell};
use super::grid::{GRID_SAMPLES, Grid, SampledBox};
use super::ordering::{CellOrder, order_cells, order_in_place};
use crate::execution::StageExecution;

/// The sort stage's result: the grid and every cell's boxes in sweep
/// order. Run whole, the stage files the boxes in one `FiledChunk` and
/// orders each cell there, in place; split, it files one chunk per chunk
/// of boxes and copies each cell's boxes in order into parts of contiguous
/// cells. Its buffers are kept and reused by the next sort, so that a
/// million boxes do not fault in fresh pages every update: about 32 bytes
/// per box run whole, 60 split (a box is filed once per cell it covers,
/// mostly one).
#[derive(Resource, Default)]
pub struct SortedBoxes {
    grid: Option<Grid>,
    chunks: Vec<FiledChunk>,
    /// Empty where the one filed chunk was ordered in place.
    orders: Vec<CellOrder>,
    /// Buffers the last sort did not need.
    spare_chunks: Vec<FiledChunk>,
    spare_orders: Vec<CellOrder>,
    len: usize,
}

impl SortedBoxes {
    /// The grid of the last sort; `None` before the first or after
    /// [`clear`](Self::clear).
    pub fn grid(&self) -> Option<&Grid> {
        self.grid.as_ref()
    }

    /// `cell`'s boxes in sweep order. `part` is where to start looking for
    /// the part of the copy that holds it (0, or the last cell's, for
    /// cells asked for in order).
    #[inline]
    pub fn in_sweep_order(&self, cell: usize, part: &mut usize) -> &[CellBox] {
        match (self.orders.as_slice(), self.chunks.as_slice()) {
            ([], [only]) => only.in_cell(cell),
            (orders, _) => {
                while orders[*part].cells.end <= cell {
                    *part += 1;
                }
                orders[*part].of(cell)
            }
        }
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

/// Sorts `boxes` into `sorted`, reusing its buffers: the bounds of the
/// boxes' lower y–z corners, the grid fitted to them, the filing by cell,
/// then the ordering of each cell on x, each step whole or in chunks as
/// `stage` says.
pub fn sort_boxes<B: BoxSource + ?Sized>(boxes: &B, stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
    // An even sample of the corners to fit the grid to their bulk: a few
    // far-flung boxes must not stretch it. Their true bounds only where
    // the sample cannot place the grid alone.
    let stride = boxes.len() / GRID_SAMPLES + 1;
    let sample: Vec<SampledBox> = stage
        .map_chunks(0..boxes.len(), |range| corner_sample(boxes, range, stride))
        .concat();
    let grid = Grid::fit_to_bulk(&sample, boxes.len(), || {
        stage
            .map_chunks(0..boxes.len(), |range| corner_bounds(boxes, range))
            .into_iter()
            .fold(
                (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
                |(lo, hi), (l, h)| (lo.min(l), hi.max(h)),
            )
    });
    let chunks = Spare::new(&mut sorted.spare_chunks, &mut sorted.chunks);
    sorted.chunks = stage.map_chunks(0..boxes.len(), |range| file_by_cell(boxes, range, &grid, chunks.take()));
    sorted.spare_chunks = chunks.into_inner();
    if let [only] = sorted.chunks.as_mut_slice() {
        order_in_place(only);
        sorted.spare_orders.append(&mut sorted.orders);
    } else {
        let orders = Spare::new(&mut sorted.spare_orders, &mut sorted.orders);
        let filed = &sorted.chunks;
        sorted.orders = stage.map_chunks(0..grid.cell_count(), |cells| order_cells(filed, cells, orders.take()));
        sorted.spare_orders = orders.into_inner();
    }
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
