//! The sort stage's coherent path: last update's filing repaired on its
//! grid instead of made anew. A body moves a small part of a cell in an
//! update, so almost every box stays in its cell and nearly in its place
//! there: each cell's boxes are read again where they lie (fresh corners,
//! by index, from a copy of the boxes: `sorted_boxes.rs`), those that
//! still cover the cells they covered stay and are put back in sweep order
//! by insertion (a few moves an update in all), and those that left a
//! cell, or now cover others, or are new, are filed afresh and merged in.
//!
//! The result is the filing a fresh sort makes on that grid, bit for bit:
//! each cell holds every box covering it, in sweep order (lower x bound,
//! ties by input index), and that order is unique however it was reached.
//! A body's index may change between updates (a despawn moves the last
//! body into the gap): every box is read again by index, so a filing entry
//! stands for whichever body has that index now.

use super::BoxSource;
use super::filing::CellBox;
use super::grid::{CellBounds, Grid};
use super::ordering::{CellRuns, order_cells, sweep_key};
use crate::execution::Split;
use crate::physics::Aabb;

/// What [`keep_stayers`] found in one run of cells.
pub struct Stayers {
    /// How many boxes stay, per cell of the run: now at the front of the
    /// cell's old place, in sweep order.
    pub per_cell: Vec<u32>,
    /// The boxes that left a cell of the run, by input index, with their
    /// fresh corners (a box that covered several cells: once for each of
    /// them in the run).
    pub left: Vec<CellBox>,
}

/// Kernel: the boxes of the old filing's cells in `runs` read again from
/// `boxes`. A box that covers the same cells as where it was filed stays,
/// with its fresh corners, moved to the front of the cell's place in sweep
/// order; every other box leaves, with its fresh corners (one whose index
/// is past the input's end is gone). Whether a box covers its one cell
/// alone is four comparisons against the cell's bounds; a box filed under
/// several cells (or with a corner that is not finite, which those
/// comparisons never pass) compares its cells on `grid` before and now,
/// so each of them keeps it, or none.
pub fn keep_stayers<B: BoxSource + ?Sized>(boxes: &B, grid: &Grid, bounds: &CellBounds, runs: CellRuns<'_>) -> Stayers {
    let len = boxes.len();
    // Sized once (a few boxes a cell leave in an update; in the thesis
    // scene fewer than two): grown as they came, the workers took the
    // allocator's one lock (`memory/heap.rs`) by turns.
    let mut found = Stayers {
        per_cell: Vec::with_capacity(runs.len()),
        left: Vec::with_capacity(runs.len() * 4),
    };
    for (cell, filed) in runs.cells() {
        let within = bounds.cell(cell as u32);
        let (mut kept, mut last_key) = (0, 0);
        for k in 0..filed.len() {
            let old = filed[k];
            let index = old.index as usize;
            if index >= len {
                continue;
            }
            let aabb = boxes.get(index);
            let stays = if within.holds(&old.aabb) {
                within.holds(&aabb)
            } else {
                // Filed under several cells (or a corner not finite): it
                // stays in each while it covers the same cells (every one
                // of them decides alike).
                grid.span(&aabb) == grid.span(&old.aabb)
            };
            if !stays {
                leaves(&mut found.left, old.index, aabb);
                continue;
            }
            let staying = CellBox { index: old.index, aabb };
            let key = sweep_key(&staying);
            if kept == 0 || key > last_key {
                // Still in order: almost every box.
                filed[kept] = staying;
                last_key = key;
            } else {
                // Insertion among the stayers so far (slots up to `k`, read).
                let mut at = kept;
                while at > 0 && sweep_key(&filed[at - 1]) > key {
                    filed[at] = filed[at - 1];
                    at -= 1;
                }
                filed[at] = staying;
            }
            kept += 1;
        }
        found.per_cell.push(kept as u32);
    }
    found
}

/// Notes a box that leaves its cell: out of the loop over the stayers,
/// which it kept from the registers it needs (the sort took 10 % longer).
#[cold]
#[inline(never)]
fn leaves(left: &mut Vec<CellBox>, index: u32, aabb: Aabb) {
    left.push(CellBox { index, aabb });
}

/// The boxes a repair files afresh, filed by cell in sweep order as a
/// fresh sort files them, and the buffers that file them (kept between
/// repairs).
#[derive(Default)]
pub struct Arrivals {
    /// Each box with a cell it covers, in index order.
    noted: Vec<(u32, CellBox)>,
    /// Cell `c`'s arrivals are `filed[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    /// The next free slot of each cell, while filing.
    cursors: Vec<u32>,
    filed: Vec<CellBox>,
}

impl Arrivals {
    /// Files every box in `left` (sorted by index and made unique here)
    /// and every box from `old_len` to the input's end (new bodies), each
    /// under every cell of `grid` it covers: noted in index order, counted,
    /// placed by cell (in index order within a cell) and each cell put in
    /// sweep order, as the fresh sort does.
    pub fn file<B: BoxSource + ?Sized>(&mut self, boxes: &B, grid: &Grid, left: &mut Vec<CellBox>, old_len: usize) {
        left.sort_unstable_by_key(|b| b.index);
        left.dedup_by_key(|b| b.index);
        let noted = &mut self.noted;
        noted.clear();
        let mut file = |index: u32, aabb| grid.for_each_cell(&aabb, |cell| noted.push((cell, CellBox { index, aabb })));
        for b in left.iter() {
            file(b.index, b.aabb);
        }
        // New bodies come after every old index.
        boxes.for_each_in(old_len.min(boxes.len())..boxes.len(), |index, aabb| {
            file(index as u32, aabb)
        });
        let (starts, cells) = (&mut self.starts, grid.cell_count());
        starts.clear();
        starts.resize(cells + 1, 0);
        for &(cell, _) in noted.iter() {
            starts[cell as usize + 1] += 1;
        }
        for cell in 0..cells {
            starts[cell + 1] += starts[cell];
        }
        self.filed.clear();
        self.filed.resize(noted.len(), CellBox::default());
        self.cursors.clear();
        self.cursors.extend_from_slice(&starts[..cells]);
        for &(cell, b) in noted.iter() {
            let slot = &mut self.cursors[cell as usize];
            self.filed[*slot as usize] = b;
            *slot += 1;
        }
        order_cells(CellRuns::new(starts, &mut self.filed));
    }

    /// The boxes filed under `cell`, in sweep order.
    pub fn in_cell(&self, cell: usize) -> &[CellBox] {
        &self.filed[self.starts[cell] as usize..self.starts[cell + 1] as usize]
    }

    /// How many boxes were filed, counting each once per cell it covers.
    pub fn len(&self) -> usize {
        self.filed.len()
    }
}

/// Kernel: each cell of `runs` (the new filing) filled by merging its
/// stayers (`stayers(cell)`, in sweep order) with the boxes filed afresh
/// under it (`arrivals(cell)`, in sweep order).
pub fn merge_cells<'a>(
    runs: CellRuns<'_>,
    stayers: impl Fn(usize) -> &'a [CellBox],
    arrivals: impl Fn(usize) -> &'a [CellBox],
) {
    for (cell, out) in runs.cells() {
        let (stay, arrive) = (stayers(cell), arrivals(cell));
        if arrive.is_empty() {
            out.copy_from_slice(stay);
            continue;
        }
        let (mut s, mut a) = (0, 0);
        for slot in out {
            let from_stayers = a == arrive.len() || (s < stay.len() && sweep_key(&stay[s]) < sweep_key(&arrive[a]));
            if from_stayers {
                *slot = stay[s];
                s += 1;
            } else {
                *slot = arrive[a];
                a += 1;
            }
        }
    }
}
