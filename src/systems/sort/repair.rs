//! The sort stage's coherent path: last update's filing repaired on its
//! grid instead of made anew. A body moves a small part of a cell in an
//! update, so almost every box stays in its cell and nearly in its place
//! there: each cell's boxes are read again where they lie (fresh corners,
//! by index), those that still cover only that cell stay and are put back
//! in sweep order by insertion (a few moves an update in all), and those
//! that left, or cover several cells, or are new, are filed afresh and
//! merged in.
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

/// What [`keep_stayers`] found in one run of cells.
#[derive(Default)]
pub struct Stayers {
    /// How many boxes stay, per cell of the run: now at the front of the
    /// cell's old place, in sweep order.
    pub per_cell: Vec<u32>,
    /// The input indices of the boxes that left a cell of the run (a box
    /// that covered several cells: once for each).
    pub left: Vec<u32>,
}

/// Kernel: the boxes of the old filing's cells in `runs` read again from
/// `boxes`. A box that covered only its cell and still does stays, with
/// its fresh corners, moved to the front of the cell's place in sweep
/// order; every other box leaves (one whose index is past the input's end
/// is gone).
pub fn keep_stayers<B: BoxSource + ?Sized>(boxes: &B, bounds: &CellBounds, runs: CellRuns<'_>) -> Stayers {
    let len = boxes.len();
    let mut found = Stayers::default();
    for (cell, filed) in runs.cells() {
        let within = bounds.cell(cell as u32);
        let (mut kept, mut last_key) = (0, 0);
        for k in 0..filed.len() {
            let old = filed[k];
            let index = old.index as usize;
            if index >= len {
                continue;
            }
            // A box filed under several cells is filed afresh in all.
            if !within.holds(&old.aabb) {
                found.left.push(old.index);
                continue;
            }
            let aabb = boxes.get(index);
            if !within.holds(&aabb) {
                found.left.push(old.index);
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

/// The boxes to file afresh, filed as a fresh sort files them: every
/// index in `left` (sorted and made unique here) and every index from
/// `old_len` to the input's end (new bodies), each under every cell it
/// covers. Noted in index order into `noted`, counted into `starts` (cell
/// `c`'s arrivals are `filed[starts[c]..starts[c + 1]]`), placed by cell
/// into `filed` (in index order within a cell) and each cell put in sweep
/// order, as the fresh sort does.
pub fn file_afresh<B: BoxSource + ?Sized>(
    boxes: &B,
    grid: &Grid,
    left: &mut Vec<u32>,
    old_len: usize,
    noted: &mut Vec<(u32, CellBox)>,
    starts: &mut Vec<u32>,
    filed: &mut Vec<CellBox>,
) {
    left.sort_unstable();
    left.dedup();
    noted.clear();
    let mut file = |index: u32, aabb| grid.for_each_cell(&aabb, |cell| noted.push((cell, CellBox { index, aabb })));
    for &index in left.iter() {
        file(index, boxes.get(index as usize));
    }
    // New bodies come after every old index.
    boxes.for_each_in(old_len.min(boxes.len())..boxes.len(), |index, aabb| {
        file(index as u32, aabb)
    });
    starts.clear();
    starts.resize(grid.cell_count() + 1, 0);
    for &(cell, _) in noted.iter() {
        starts[cell as usize + 1] += 1;
    }
    for cell in 0..grid.cell_count() {
        starts[cell + 1] += starts[cell];
    }
    filed.clear();
    filed.resize(noted.len(), CellBox::default());
    let mut next: Vec<u32> = starts[..grid.cell_count()].to_vec();
    for &(cell, b) in noted.iter() {
        let slot = &mut next[cell as usize];
        filed[*slot as usize] = b;
        *slot += 1;
    }
    order_cells(CellRuns::new(starts, filed));
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
