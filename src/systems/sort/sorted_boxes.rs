//! The sort stage's work on any [`BoxSource`]: a grid fitted to the boxes,
//! the boxes filed by cell (chunks of boxes), and each cell put in sweep
//! order where it lies (chunks of cells) — [`SortedBoxes`], ready for the
//! sweep; or, between two such fresh sorts, last update's filing repaired
//! on its grid (`repair.rs`), which gives the same filing.

use std::sync::{Mutex, PoisonError};

use bevy::prelude::*;

use super::BoxSource;
use super::filing::{
    CellBox, ChunkCount, cell_starts, corner_bounds, corner_sample, count_by_cell, place_by_cell, placings,
};
use super::grid::{CellBounds, GRID_SAMPLES, Grid, SampledBox};
use super::ordering::{CellRuns, order_cells};
use super::repair::{Arrivals, keep_stayers, merge_cells};
use crate::execution::{StageExecution, ThreadCopies};
use crate::physics::Aabb;

/// The sort stage's result: the grid and every cell's boxes in sweep
/// order, in one array, cell after cell. Its buffers are kept and reused
/// by the next sort, so that a million boxes do not fault in fresh pages
/// every update: about 32 bytes per box (a box is filed once per cell it
/// covers, mostly one), run whole or split; up to [`REPAIR_UP_TO`] boxes,
/// as much again for the repair's second filing and 24 bytes a box for its
/// copy of the boxes (split on two threads, twice more: each thread's).
#[derive(Resource, Default)]
pub struct SortedBoxes {
    grid: Option<Grid>,
    /// The grid's cells as ranges of values, for the repair.
    bounds: CellBounds,
    /// Sorts since the last fresh sort that started a period of
    /// [`REFIT_EVERY`] updates.
    since_fit: u32,
    /// False once a repair in this period had to file too many boxes
    /// afresh to pay ([`ARRIVALS_TO_PAY`]): fresh sorts until the next.
    repairs_pay: bool,
    /// Whether the last sort was a repair.
    repaired: bool,
    /// Cell `c`'s boxes are `boxes[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    boxes: Vec<CellBox>,
    /// The last sort's counts, one per chunk of boxes.
    counts: Vec<ChunkCount>,
    /// Count buffers the last sort did not need.
    spare_counts: Vec<ChunkCount>,
    /// A repair's new filing, before it becomes `starts` and `boxes`.
    next_starts: Vec<u32>,
    next: Vec<CellBox>,
    /// A repair's copy of the boxes, in input order, and in parallel each
    /// thread's own copy of that.
    copied: Vec<Aabb>,
    thread_copies: ThreadCopies<Aabb>,
    /// A repair's stayers per cell, and the boxes that left.
    stays: Vec<u32>,
    left: Vec<CellBox>,
    /// A repair's boxes filed afresh.
    arrivals: Arrivals,
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

    /// Calls `f` with the input index of every sorted box that overlaps
    /// `region` (touching counts); a box filed in several cells comes once
    /// for each of those `region` covers. Nothing before the first sort.
    pub fn overlapping(&self, region: &Aabb, mut f: impl FnMut(u32)) {
        let Some(grid) = &self.grid else {
            return;
        };
        grid.for_each_cell(region, |cell| {
            // In sweep order, by the boxes' lower x: none after the first
            // that starts past the region's end.
            for filed in self.in_sweep_order(cell as usize) {
                if filed.aabb.min.x > region.max.x {
                    break;
                }
                if filed.aabb.overlaps(region) {
                    f(filed.index);
                }
            }
        });
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

/// Updates a grid serves before the boxes are sorted afresh on a grid
/// fitted to them again: the bodies drift, and a grid that no longer fits
/// them fills some cells and empties others.
const REFIT_EVERY: u32 = 32;

/// Most boxes whose filing is repaired: the repair reads each box by its
/// index in cell order, a random walk over the bodies' columns that pays
/// while they stay in the caches, and keeps a second filing. Past this, a
/// fresh sort, which reads the columns in order, runs every update. In the
/// thesis scene on the Intel VM (docs/benchmarks.md) the repair made the
/// sort 0.63 of a fresh one at 10 000 bodies, 0.8 at 20 000, no faster at
/// 50 000 (slower in parallel) and slower at 100 000 and a million, where
/// a fifth of the bodies change cell every update.
pub const REPAIR_UP_TO: usize = 25_000;

/// A repair pays while it files at most this share of the boxes afresh
/// (those whose cells changed, or are new; counted once per cell): in the
/// thesis scene at 10 000 bodies 2.4 % an update, and the repair took 0.65
/// of a fresh sort's time; in the default scene (`debris_orbit.ron`,
/// swept boxes, 20 000 bodies) 11 % (6 % of the boxes change cells), and
/// it took 0.9–1.25 of a fresh sort.
const ARRIVALS_TO_PAY: usize = 16;

/// Most threads of a split repair that each read the boxes from a copy
/// of their own: each copies all the boxes and reads its share, so the
/// copy pays where that share is large (half the boxes on two threads,
/// half of them in the other core's caches) and not where it is small
/// (a sixteenth on sixteen threads); there the threads read the shared
/// copy and the work does not grow with the threads.
const OWN_COPIES_UP_TO: usize = 2;

/// Sorts `boxes` into `sorted`, reusing its buffers, whole or in chunks as
/// `stage` says. Every [`REFIT_EVERY`] updates (and when the boxes grew or
/// shrank by an eighth) a fresh sort fits the grid again; between, the
/// last filing is repaired, until a repair files more than one box in
/// [`ARRIVALS_TO_PAY`] afresh: fresh sorts then, until the next period.
/// Both give the same filing on a grid, and the sweep's pairs do not
/// depend on the grid.
pub fn sort_boxes<B: BoxSource + ?Sized>(boxes: &B, stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
    if sorted.grid.is_none() || sorted.since_fit >= REFIT_EVERY {
        sorted.since_fit = 0;
        sorted.repairs_pay = true;
    }
    sorted.repaired = sorted.grid.is_some()
        && sorted.since_fit > 0
        && sorted.repairs_pay
        && boxes.len() <= REPAIR_UP_TO
        && boxes.len().abs_diff(sorted.len) <= sorted.len / 8;
    if sorted.repaired {
        repair_filing(boxes, stage, sorted);
    } else {
        sort_afresh(boxes, stage, sorted);
    }
    sorted.since_fit += 1;
}

/// Last sort's filing repaired for `boxes` on its grid (`repair.rs`): the
/// boxes copied in input order (chunks of boxes), then those that stay in
/// their cells kept in place and put in order by insertion (chunks of
/// cells), those whose cells changed or are new filed afresh (whole), both
/// merged cell by cell into the new filing (chunks of cells).
///
/// The repair reads each box by its index, in cell order, from the copy:
/// one compact slice, where each read from the bodies' columns found the
/// body's table and two columns. Split, each thread reads from a copy of
/// the copy of its own, made in order (`ThreadCopies`): half of the shared
/// copy lies in the other core's caches, and its reads at random each
/// fetched a line from there. The shared copy is made by the threads that
/// just moved its bodies: reading the columns at random, or each thread
/// all of them, drew the lines a core had just written away from it for
/// its next update (docs/benchmarks.md, "Copies to read from").
fn repair_filing<B: BoxSource + ?Sized>(boxes: &B, stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
    let mut copied = std::mem::take(&mut sorted.copied);
    copied.resize(boxes.len(), Aabb::default());
    stage.for_chunks((0..boxes.len(), copied.as_mut_slice()), |(range, out)| {
        boxes.copy_into(range, out);
    });
    repair_from_copy(&copied, stage, sorted);
    sorted.copied = copied;
}

/// [`repair_filing`]'s work after the copy, on the copied boxes.
fn repair_from_copy(boxes: &[Aabb], stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
    let grid = sorted.grid.expect("a repair follows a sort");
    let bounds = &sorted.bounds;
    // One thread has all the shared copy in its own caches.
    let runners = stage.runners();
    let own_copies = stage.splits() && (2..=OWN_COPIES_UP_TO).contains(&runners);
    if own_copies {
        sorted.thread_copies.renew(runners);
    }
    let copies = &sorted.thread_copies;
    let found = stage.map_chunks(CellRuns::new(&sorted.starts, &mut sorted.boxes), |runs| {
        if own_copies {
            copies.read(boxes, |mine| keep_stayers(mine, &grid, bounds, runs))
        } else {
            keep_stayers(boxes, &grid, bounds, runs)
        }
    });
    let (stays, left) = (&mut sorted.stays, &mut sorted.left);
    stays.clear();
    left.clear();
    for chunk in found {
        stays.extend(chunk.per_cell);
        left.extend(chunk.left);
    }
    sorted.arrivals.file(boxes, &grid, left, sorted.len);
    let arrivals = &sorted.arrivals;
    let next_starts = &mut sorted.next_starts;
    next_starts.clear();
    next_starts.push(0);
    let mut filed = 0;
    for (cell, &stay) in stays.iter().enumerate() {
        filed += stay + arrivals.in_cell(cell).len() as u32;
        next_starts.push(filed);
    }
    sorted.next.resize(filed as usize, CellBox::default());
    let (old, old_starts) = (&sorted.boxes, &sorted.starts);
    stage.for_chunks(CellRuns::new(next_starts, &mut sorted.next), |runs| {
        merge_cells(
            runs,
            |cell| {
                let start = old_starts[cell] as usize;
                &old[start..start + stays[cell] as usize]
            },
            |cell| arrivals.in_cell(cell),
        );
    });
    std::mem::swap(&mut sorted.boxes, &mut sorted.next);
    std::mem::swap(&mut sorted.starts, &mut sorted.next_starts);
    sorted.repairs_pay = sorted.arrivals.len() <= boxes.len() / ARRIVALS_TO_PAY;
    sorted.len = boxes.len();
}

/// The boxes sorted afresh: an even sample of the boxes' lower y–z
/// corners, the grid fitted to them, the filing by cell (counted by chunks
/// of boxes, laid out, placed by the same chunks), then the ordering of
/// each cell on x where it lies (by chunks of cells).
fn sort_afresh<B: BoxSource + ?Sized>(boxes: &B, stage: StageExecution<'_>, sorted: &mut SortedBoxes) {
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
    sorted.bounds = grid.bounds();
    sorted.len = boxes.len();
    if boxes.len() > REPAIR_UP_TO {
        // No repair at this size: its second filing and copy go back.
        sorted.next = Vec::new();
        sorted.copied = Vec::new();
        sorted.thread_copies.free();
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::{Execution, ExecutionMode, SplitPolicy};
    use crate::physics::Aabb;

    /// The filing a fresh sort makes of `boxes` on `grid`.
    fn fresh_on(grid: &Grid, boxes: &[Aabb]) -> (Vec<u32>, Vec<(u32, Aabb)>) {
        let counts = [count_by_cell(boxes, 0..boxes.len(), grid, ChunkCount::default())];
        let mut starts = Vec::new();
        let filed = cell_starts(&counts, grid.cell_count(), &mut starts);
        let mut out = vec![CellBox::default(); filed];
        place_by_cell(boxes, grid, &mut placings(&counts, &mut out));
        order_cells(CellRuns::new(&starts, &mut out));
        (starts, out.iter().map(|b| (b.index, b.aabb)).collect())
    }

    /// A repeatable stream of numbers in `0..1`.
    fn stream(seed: u64) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn past_the_repairs_limit_every_sort_is_fresh_and_keeps_one_filing() {
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let mut next = stream(3);
        for (count, repaired) in [(REPAIR_UP_TO, true), (REPAIR_UP_TO + 1, false)] {
            let boxes: Vec<Aabb> = (0..count)
                .map(|_| Aabb::new(Vec3::new(next(), next(), next()) * 1000.0, Vec3::splat(0.1)))
                .collect();
            let mut sorted = SortedBoxes::default();
            for _ in 0..3 {
                sort_boxes(boxes.as_slice(), execution.for_stage("sort", count), &mut sorted);
            }
            assert_eq!(sorted.repaired, repaired, "{count} boxes");
            assert_eq!(sorted.next.capacity() > 0, repaired, "{count} boxes");
            assert_eq!(sorted.copied.capacity() > 0, repaired, "{count} boxes");
            assert_eq!(sorted.thread_copies.capacity_bytes(), 0, "{count} boxes, sequential");
        }
    }

    #[test]
    fn a_repair_that_files_many_boxes_afresh_ends_the_repairs_until_the_next_period() {
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let mut next = stream(9);
        let mut sorted = SortedBoxes::default();
        let mut repairs = Vec::new();
        for update in 0..2 * REFIT_EVERY {
            // Every box somewhere new each update.
            let boxes: Vec<Aabb> = (0..3000)
                .map(|_| Aabb::new(Vec3::new(next(), next(), next()) * 1000.0, Vec3::ONE))
                .collect();
            sort_boxes(boxes.as_slice(), execution.for_stage("sort", boxes.len()), &mut sorted);
            if sorted.repaired {
                repairs.push(update);
            }
        }
        // The update after each period's fresh sort tries a repair, once.
        assert_eq!(repairs, [1, REFIT_EVERY + 1]);
    }

    /// Boxes drifting a little each update, a few jumping far, a few
    /// growing over several cells (and staying there), bodies leaving and
    /// arriving, the last box taking a grown box's index: every
    /// repaired filing is the fresh filing on its grid, sequential and
    /// split alike (on 2 threads each reading its own copy of the boxes,
    /// on 1 and 3 the shared copy), and most updates are repairs.
    #[test]
    fn a_repaired_filing_is_the_fresh_filing_on_its_grid() {
        let split_on = |threads| {
            Execution::new(ExecutionMode::Parallel, threads)
                .unwrap()
                .with_split(SplitPolicy::Always)
                .as_if_hardware_threads(threads)
        };
        for execution in [
            Execution::new(ExecutionMode::Sequential, 1).unwrap(),
            split_on(1),
            split_on(OWN_COPIES_UP_TO),
            split_on(OWN_COPIES_UP_TO + 1),
        ] {
            let mut next = stream(7);
            let mut centers: Vec<Vec3> = (0..4000).map(|_| Vec3::new(next(), next(), next()) * 1000.0).collect();
            let mut halves: Vec<Vec3> = (0..4000).map(|_| Vec3::splat(0.1 + 0.4 * next())).collect();
            let mut sorted = SortedBoxes::default();
            let (mut repairs, mut multi_cell_kept) = (0, false);
            for update in 0..80 {
                for (k, (center, half)) in centers.iter_mut().zip(&mut halves).enumerate() {
                    *center += (Vec3::new(next(), next(), next()) - 0.5) * 2.0;
                    if k % 397 == update % 397 {
                        *center = Vec3::new(next(), next(), next()) * 1000.0;
                    }
                    if k % 1001 == 0 && update == 20 {
                        *half = Vec3::splat(150.0);
                    }
                }
                if update == 30 {
                    centers.truncate(3700);
                    halves.truncate(3700);
                }
                if update == 40 {
                    // The last box takes a grown box's index.
                    centers.swap_remove(1001);
                    halves.swap_remove(1001);
                }
                if update == 50 {
                    centers.extend((0..250).map(|_| Vec3::new(next(), next(), next()) * 1000.0));
                    halves.extend((0..250).map(|_| Vec3::ONE));
                }
                let boxes: Vec<Aabb> = centers.iter().zip(&halves).map(|(&c, &h)| Aabb::new(c, h)).collect();
                sort_boxes(boxes.as_slice(), execution.for_stage("sort", boxes.len()), &mut sorted);
                repairs += usize::from(sorted.repaired);
                let (starts, filed) = fresh_on(sorted.grid().unwrap(), &boxes);
                let repaired: Vec<(u32, Aabb)> =
                    sorted.boxes[..filed.len()].iter().map(|b| (b.index, b.aabb)).collect();
                if sorted.repaired {
                    // The entries of the boxes grown at update 20 (filed
                    // under several cells), and how many of them were
                    // filed afresh: fewer, where such a box stayed.
                    let mut entries = vec![0; boxes.len()];
                    for &(index, _) in &filed {
                        entries[index as usize] += 1;
                    }
                    let several = |index: u32| update > 20 && index.is_multiple_of(1001) && entries[index as usize] > 1;
                    let filed_afresh = (0..sorted.grid().unwrap().cell_count())
                        .flat_map(|cell| sorted.arrivals.in_cell(cell))
                        .filter(|b| several(b.index))
                        .count();
                    let in_several = filed.iter().filter(|&&(index, _)| several(index)).count();
                    multi_cell_kept |= filed_afresh < in_several;
                }
                assert_eq!(sorted.starts, starts, "update {update}");
                assert_eq!(repaired, filed, "update {update}");
                assert_eq!(sorted.len(), boxes.len());
            }
            assert!(repairs > 60, "{repairs} repairs in 80 updates");
            assert!(multi_cell_kept, "a box covering several cells stayed in them");
            let own_copies = execution.mode() == ExecutionMode::Parallel
                && (2..=OWN_COPIES_UP_TO).contains(&execution.step_threads());
            assert_eq!(sorted.thread_copies.capacity_bytes() > 0, own_copies, "{execution:?}");
        }
    }
}
