//! Stage 3: sweep and prune (DESIGN §2.3) — every pair of overlapping boxes.
//!
//! A single sweep along x degrades when many boxes share an x range (a dense
//! cloud of a million cubes puts hundreds in every box's x range), so the
//! sweep runs per cell of a grid over y and z. Boxes are filed under every
//! cell their y–z extent covers by a counting sort that reads the bodies'
//! columns in order, twice (count, then place), and never gathers at random.
//! Each cell's boxes are then sorted by their lower x bound (ties by input
//! index, so the order is one fixed permutation), each box scans forward
//! while the next box starts before it ends on x, and confirms y and z.
//! Touching counts as overlap. A pair found in several cells is reported
//! only by the cell holding the lower corner of the pair's y–z intersection,
//! so every pair comes out exactly once. A big box (the planet) joins the
//! cells it covers and scans only the boxes inside its x-slab there, so the
//! cost stays near-linear.
//!
//! In parallel, contiguous ranges of boxes are filed by their own chunk and
//! contiguous ranges of cells are swept by their own chunk; a cell reads its
//! boxes chunk after chunk, which is input order again, and the pairs are
//! concatenated in cell order: the same pairs in the same order as one
//! sequential pass.

use std::ops::Range;
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

use bevy::prelude::*;

use crate::components::{BodyId, HalfExtents, Position};
use crate::resources::{Execution, SimulationSettings, StageTimings};
use crate::systems::{SimulationSystems, SimulationUpdate};

/// Boxes per parallel chunk of the filing. Below two grains a step runs
/// whole: on these small inputs the dispatch and the cache traffic between
/// cores cost more than they save.
const GRAIN: usize = 8_192;

/// Cells per parallel chunk of the sweep (about [`GRAIN`] boxes).
const CELL_GRAIN: usize = GRAIN / BOXES_PER_CELL;

/// An axis-aligned box by its corners.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub fn new(center: Vec3, half_extents: Vec3) -> Self {
        Self {
            min: center - half_extents,
            max: center + half_extents,
        }
    }

    /// Overlap on y and z, bounds inclusive.
    #[inline]
    fn overlaps_yz(&self, other: &Self) -> bool {
        self.min.y <= other.max.y && other.min.y <= self.max.y && self.min.z <= other.max.z && other.min.z <= self.max.z
    }

    /// Overlap on all axes, bounds inclusive.
    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.x <= other.max.x && other.min.x <= self.max.x && self.overlaps_yz(other)
    }
}

/// Two overlapping bodies: ids `a < b` and their entities.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pair {
    pub a: BodyId,
    pub b: BodyId,
    pub entity_a: Entity,
    pub entity_b: Entity,
}

/// The broad phase's output: overlapping pairs of this update, sorted by
/// `(a, b)`.
#[derive(Resource, Clone, Debug, Default)]
pub struct OverlappingPairs(pub Vec<Pair>);

/// Where the sweep reads its boxes, in order: a plain slice, or the bodies'
/// table columns in place (so a million bodies need no copy of their boxes).
pub trait BoxSource: Sync {
    fn len(&self) -> usize;

    /// Calls `f` with the index and box of every box in `range`, in order.
    fn for_each_in(&self, range: Range<usize>, f: impl FnMut(usize, Aabb));

    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl BoxSource for [Aabb] {
    fn len(&self) -> usize {
        <[Aabb]>::len(self)
    }

    #[inline]
    fn for_each_in(&self, range: Range<usize>, mut f: impl FnMut(usize, Aabb)) {
        let first = range.start;
        for (k, &aabb) in self[range].iter().enumerate() {
            f(first + k, aabb);
        }
    }
}

/// A box filed under a grid cell: its index in the input and its corners.
#[derive(Clone, Copy, Debug, Default)]
struct CellBox {
    index: u32,
    aabb: Aabb,
}

/// One chunk's boxes filed by cell: `boxes[starts[c]..starts[c + 1]]` are
/// the chunk's boxes in cell `c`, in input order.
#[derive(Default)]
struct FiledChunk {
    starts: Vec<u32>,
    cursor: Vec<u32>,
    /// The one cell of each box in the chunk, or [`SEVERAL_CELLS`].
    cells: Vec<u32>,
    boxes: Vec<CellBox>,
}

/// Buffers of the sweep, kept between updates so that a million boxes do
/// not fault in fresh pages every update: about 28 bytes per box (a box is
/// filed once per cell it covers, mostly one).
#[derive(Default)]
pub struct SweepScratch {
    spare: Mutex<Vec<FiledChunk>>,
}

impl SweepScratch {
    fn take(&self) -> FiledChunk {
        self.spare
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop()
            .unwrap_or_default()
    }

    fn give_back(&self, chunks: Vec<FiledChunk>) {
        self.spare.lock().unwrap_or_else(PoisonError::into_inner).extend(chunks);
    }
}

/// Boxes per grid cell the grid aims for.
const BOXES_PER_CELL: usize = 64;

/// Most cells per axis of the grid.
const MAX_CELLS_PER_AXIS: usize = 256;

/// A grid over y and z, fitted to the lower corners of the boxes.
#[derive(Clone, Copy, Debug)]
struct Grid {
    lo: Vec2,
    /// Cells per unit length on y and z (0 if all boxes share a coordinate).
    scale: Vec2,
    cells_per_axis: u32,
}

impl Grid {
    /// A grid for `count` boxes whose lower y–z corners lie in `lo..=hi`.
    fn fit(lo: Vec2, hi: Vec2, count: usize) -> Self {
        let n = ((count / BOXES_PER_CELL) as f64)
            .sqrt()
            .clamp(1.0, MAX_CELLS_PER_AXIS as f64) as u32;
        let extent = hi - lo;
        let scale = |e: f32| if e.is_finite() && e > 0.0 { n as f32 / e } else { 0.0 };
        Self {
            lo,
            scale: Vec2::new(scale(extent.x), scale(extent.y)),
            cells_per_axis: n,
        }
    }

    /// Cell coordinate of `v` on the axis with origin `lo` and `scale`;
    /// monotonic in `v`, clamped to the grid.
    #[inline]
    fn coordinate(&self, v: f32, lo: f32, scale: f32) -> u32 {
        // `as` saturates: below the grid (and NaN) → 0.
        (((v - lo) * scale) as u32).min(self.cells_per_axis - 1)
    }

    #[inline]
    fn cell(&self, y: f32, z: f32) -> u32 {
        self.coordinate(y, self.lo.x, self.scale.x) * self.cells_per_axis + self.coordinate(z, self.lo.y, self.scale.y)
    }

    fn cell_count(&self) -> usize {
        (self.cells_per_axis * self.cells_per_axis) as usize
    }

    /// Calls `f` with every cell the box's y–z extent covers.
    #[inline]
    fn for_each_cell(&self, b: &Aabb, mut f: impl FnMut(u32)) {
        let (y0, y1) = (
            self.coordinate(b.min.y, self.lo.x, self.scale.x),
            self.coordinate(b.max.y, self.lo.x, self.scale.x),
        );
        let (z0, z1) = (
            self.coordinate(b.min.z, self.lo.y, self.scale.y),
            self.coordinate(b.max.z, self.lo.y, self.scale.y),
        );
        let n = self.cells_per_axis;
        if y0 == y1 && z0 == z1 {
            // Almost every box: one cell.
            f(y0 * n + z0);
            return;
        }
        for y in y0..=y1 {
            for z in z0..=z1 {
                f(y * n + z);
            }
        }
    }

    /// The one cell that reports the overlapping pair `a`, `b`.
    #[inline]
    fn owner(&self, a: &Aabb, b: &Aabb) -> u32 {
        self.cell(a.min.y.max(b.min.y), a.min.z.max(b.min.z))
    }
}

/// Finds [`OverlappingPairs`] in [`SimulationSystems::BroadPhase`].
pub struct BroadPhasePlugin;

impl Plugin for BroadPhasePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<OverlappingPairs>().add_systems(
            SimulationUpdate,
            (
                broad_phase.run_if(|s: Res<SimulationSettings>| s.collisions),
                (|mut pairs: ResMut<OverlappingPairs>| pairs.0.clear())
                    .run_if(|s: Res<SimulationSettings>| !s.collisions),
            )
                .in_set(SimulationSystems::BroadPhase),
        );
    }
}

/// Maps an f32 to a u32 with the same order (for all non-NaN values).
#[inline]
fn order_key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits & 0x8000_0000 != 0 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

/// The bounds of the lower y–z corners of the boxes in `range`.
fn corner_bounds<B: BoxSource + ?Sized>(boxes: &B, range: Range<usize>) -> (Vec2, Vec2) {
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    boxes.for_each_in(range, |_, b| {
        let corner = Vec2::new(b.min.y, b.min.z);
        lo = lo.min(corner);
        hi = hi.max(corner);
    });
    (lo, hi)
}

/// Kernel: files the boxes in `range` under every cell they cover (a stable
/// counting sort by cell: count, then place), into the reused `out`.
fn file_by_cell<B: BoxSource + ?Sized>(boxes: &B, range: Range<usize>, grid: &Grid, mut out: FiledChunk) -> FiledChunk {
    let FiledChunk {
        starts,
        cursor,
        cells,
        boxes: filed,
    } = &mut out;
    starts.clear();
    starts.resize(grid.cell_count() + 1, 0);
    // The count pass notes each box's cell, so that the place pass need
    // not work it out again; a box covering several cells is noted as
    // `SEVERAL_CELLS` and its cells are worked out again.
    cells.clear();
    boxes.for_each_in(range.clone(), |_, aabb| {
        let mut count = 0;
        let mut only = 0;
        grid.for_each_cell(&aabb, |cell| {
            starts[cell as usize + 1] += 1;
            count += 1;
            only = cell;
        });
        cells.push(if count == 1 { only } else { SEVERAL_CELLS });
    });
    for cell in 0..grid.cell_count() {
        starts[cell + 1] += starts[cell];
    }
    cursor.clear();
    cursor.extend_from_slice(&starts[..grid.cell_count()]);
    // Same length as last update's in a steady state: nothing to write here.
    filed.resize(starts[grid.cell_count()] as usize, CellBox::default());
    let mut noted = cells.iter();
    boxes.for_each_in(range, |i, aabb| {
        let mut place = |cell: u32| {
            let at = &mut cursor[cell as usize];
            filed[*at as usize] = CellBox { index: i as u32, aabb };
            *at += 1;
        };
        match noted.next() {
            Some(&cell) if cell != SEVERAL_CELLS => place(cell),
            _ => grid.for_each_cell(&aabb, place),
        }
    });
    out
}

/// Noted for a box that covers more than one cell.
const SEVERAL_CELLS: u32 = u32::MAX;

/// Kernel: the overlapping pairs `(i, j)` of input indices found in the
/// `cells`, cell after cell, from the filed chunks (in input order).
fn sweep_cells(filed: &[FiledChunk], grid: &Grid, cells: Range<usize>) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    let mut cell_boxes: Vec<CellBox> = Vec::new();
    // Sort keys: the lower x bound's order key above the position in
    // `cell_boxes`, which is input order, so ties keep input order.
    let mut order: Vec<u64> = Vec::new();
    for cell in cells {
        cell_boxes.clear();
        for chunk in filed {
            let (start, end) = (chunk.starts[cell] as usize, chunk.starts[cell + 1] as usize);
            cell_boxes.extend_from_slice(&chunk.boxes[start..end]);
        }
        order.clear();
        order.extend(
            cell_boxes
                .iter()
                .enumerate()
                .map(|(k, b)| (u64::from(order_key(b.aabb.min.x)) << 32) | k as u64),
        );
        order.sort_unstable();
        for (k, &first) in order.iter().enumerate() {
            let a = &cell_boxes[first as u32 as usize];
            for &second in &order[k + 1..] {
                let b = &cell_boxes[second as u32 as usize];
                if b.aabb.min.x > a.aabb.max.x {
                    break;
                }
                if a.aabb.overlaps_yz(&b.aabb) && grid.owner(&a.aabb, &b.aabb) == cell as u32 {
                    pairs.push((a.index, b.index));
                }
            }
        }
    }
    pairs
}

/// Sweep and prune over `boxes` (any order): every overlapping pair of
/// indices into `boxes` exactly once, as `(i, j)` with `boxes[i]` first in
/// sweep order. The same pairs in the same order in both execution modes.
pub fn sweep_and_prune<B: BoxSource + ?Sized>(
    boxes: &B,
    execution: &Execution,
    scratch: &mut SweepScratch,
) -> Vec<(u32, u32)> {
    let (lo, hi) = execution
        .map_chunks(0..boxes.len(), GRAIN, |range| corner_bounds(boxes, range))
        .into_iter()
        .fold(
            (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
            |(lo, hi), (l, h)| (lo.min(l), hi.max(h)),
        );
    let grid = Grid::fit(lo, hi, boxes.len());
    let scratch = &*scratch;
    let filed = execution.map_chunks(0..boxes.len(), GRAIN, |range| {
        file_by_cell(boxes, range, &grid, scratch.take())
    });
    let pairs = execution.map_chunks(0..grid.cell_count(), CELL_GRAIN, |cells| {
        sweep_cells(&filed, &grid, cells)
    });
    scratch.give_back(filed);
    pairs.concat()
}

/// Index pairs as id pairs `(lower, higher)`, sorted.
pub fn id_pairs(index_pairs: &[(u32, u32)], ids: &[BodyId]) -> Vec<(BodyId, BodyId)> {
    let mut pairs: Vec<(BodyId, BodyId)> = index_pairs
        .iter()
        .map(|&(i, j)| {
            let (a, b) = (ids[i as usize], ids[j as usize]);
            (a.min(b), a.max(b))
        })
        .collect();
    pairs.sort_unstable();
    pairs
}

/// One table's columns the broad phase reads.
type TableColumns<'a> = (&'a [Entity], &'a [BodyId], &'a [Position], &'a [HalfExtents]);

/// The bodies' table columns read as one sequence, table after table.
struct BodyColumns<'a> {
    /// Index of each table's first body.
    starts: Vec<usize>,
    tables: Vec<TableColumns<'a>>,
    len: usize,
}

impl<'a> BodyColumns<'a> {
    fn new(tables: impl Iterator<Item = TableColumns<'a>>) -> Self {
        let (mut starts, mut all, mut len) = (Vec::new(), Vec::new(), 0);
        for table in tables {
            starts.push(len);
            len += table.0.len();
            all.push(table);
        }
        Self {
            starts,
            tables: all,
            len,
        }
    }

    /// The table and row of the body with this index.
    #[inline]
    fn locate(&self, index: usize) -> (usize, usize) {
        // Bodies usually share one table; then this is one comparison.
        let table = if self.starts.len() == 1 {
            0
        } else {
            self.starts.partition_point(|&s| s <= index) - 1
        };
        (table, index - self.starts[table])
    }

    fn body(&self, index: usize) -> (BodyId, Entity) {
        let (t, row) = self.locate(index);
        (self.tables[t].1[row], self.tables[t].0[row])
    }
}

impl BoxSource for BodyColumns<'_> {
    fn len(&self) -> usize {
        self.len
    }

    /// Walks the columns table by table, without locating every index.
    #[inline]
    fn for_each_in(&self, range: Range<usize>, mut f: impl FnMut(usize, Aabb)) {
        for (&start, &(_, _, positions, halves)) in self.starts.iter().zip(&self.tables) {
            let end = start + positions.len();
            let (from, to) = (range.start.max(start), range.end.min(end));
            if from >= to {
                continue;
            }
            let rows = from - start..to - start;
            for (k, (p, h)) in positions[rows.clone()].iter().zip(&halves[rows]).enumerate() {
                f(from + k, Aabb::new(p.0, h.0));
            }
        }
    }
}

fn broad_phase(
    execution: Res<Execution>,
    mut timings: ResMut<StageTimings>,
    mut pairs: ResMut<OverlappingPairs>,
    mut scratch: Local<SweepScratch>,
    bodies: Query<(Entity, &BodyId, &Position, &HalfExtents)>,
) {
    let start = Instant::now();
    let columns = BodyColumns::new(bodies.contiguous_iter().expect("body components are table-stored"));
    let index_pairs = sweep_and_prune(&columns, &execution, &mut scratch);
    pairs.0.clear();
    pairs.0.extend(index_pairs.iter().map(|&(i, j)| {
        let (first, second) = (columns.body(i as usize), columns.body(j as usize));
        let ((a, entity_a), (b, entity_b)) = if first < second {
            (first, second)
        } else {
            (second, first)
        };
        Pair {
            a,
            b,
            entity_a,
            entity_b,
        }
    }));
    pairs.0.sort_unstable_by_key(|p| (p.a, p.b));
    timings.record(SimulationSystems::BroadPhase, start.elapsed());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::ExecutionMode;
    use crate::rng::Rng;

    fn brute_force(boxes: &[Aabb]) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if boxes[i].overlaps(&boxes[j]) {
                    pairs.push((i as u32, j as u32));
                }
            }
        }
        pairs
    }

    fn normalized(mut pairs: Vec<(u32, u32)>) -> Vec<(u32, u32)> {
        for p in &mut pairs {
            *p = (p.0.min(p.1), p.0.max(p.1));
        }
        pairs.sort_unstable();
        pairs
    }

    /// Parallel runs split every step into small chunks, so that cells
    /// gather their boxes from many filed chunks.
    fn run(boxes: &[Aabb], mode: ExecutionMode) -> Vec<(u32, u32)> {
        let exec = Execution::new(mode, 3).unwrap().fine_grained();
        sweep_and_prune(boxes, &exec, &mut SweepScratch::default())
    }

    fn unit_boxes(centres: &[[f32; 3]]) -> Vec<Aabb> {
        centres
            .iter()
            .map(|c| Aabb::new(Vec3::from_array(*c), Vec3::ONE))
            .collect()
    }

    #[test]
    fn thesis_case_1() {
        let boxes = unit_boxes(&[
            [0.0, -5.40142, 0.0],
            [1.19985, -2.96523, -1.18883],
            [-1.36591, -1.35558, 0.969402],
            [0.020946, -0.334908, -0.316789],
            [-0.971955, -4.24241, 2.78168],
            [3.40919, 1.00089, 0.245847],
            [-0.306667, -0.456765, 4.26992],
            [0.491334, -3.66383, 1.29069],
            [1.80999, 1.32266, 2.5045],
        ]);
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            assert_eq!(normalized(run(&boxes, mode)), vec![(0, 7), (2, 3), (4, 7)]);
        }
    }

    #[test]
    fn thesis_case_2() {
        let boxes = unit_boxes(&[
            [-1.81922, 0.13185, 1.43538],
            [0.0, 2.0, 0.0],
            [-0.570769, -0.697269, 0.466469],
            [-2.56339, 1.2581, 2.37958],
            [-1.30461, 2.89979, 1.12968],
            [-2.7742, -1.23996, 1.75068],
            [-0.848593, -3.80494, 1.73219],
        ]);
        let expected = vec![(0, 1), (0, 2), (0, 3), (0, 5), (1, 4), (2, 3), (3, 4)];
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            assert_eq!(normalized(run(&boxes, mode)), expected);
        }
    }

    /// Mixed sizes on a coarse grid, so many boxes touch exactly.
    fn random_boxes(count: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng::new(seed);
        let mut grid = |scale: f64| (rng.range(0.0, scale) as f32 * 4.0).round() / 4.0;
        (0..count)
            .map(|i| {
                let centre = Vec3::new(grid(60.0), grid(60.0), grid(60.0));
                let half = if i % 97 == 0 {
                    Vec3::new(grid(12.0) + 0.25, grid(12.0) + 0.25, grid(12.0) + 0.25)
                } else {
                    Vec3::new(grid(1.5) + 0.25, grid(1.5) + 0.25, grid(1.5) + 0.25)
                };
                Aabb::new(centre, half)
            })
            .collect()
    }

    #[test]
    fn matches_brute_force_on_random_mixed_boxes_with_touches() {
        for seed in 0..3 {
            let boxes = random_boxes(3000 + seed as usize * 1000, seed);
            let expected = brute_force(&boxes);
            let touching = expected
                .iter()
                .filter(|&&(i, j)| {
                    let (a, b) = (boxes[i as usize], boxes[j as usize]);
                    (0..3).any(|k| a.max[k] == b.min[k] || b.max[k] == a.min[k])
                })
                .count();
            assert!(touching > 50, "only {touching} exact touches: the test lost its edge");
            let sequential = run(&boxes, ExecutionMode::Sequential);
            let parallel = run(&boxes, ExecutionMode::Parallel);
            assert_eq!(sequential, parallel, "modes disagree");
            assert_eq!(normalized(sequential), expected);
        }
    }

    #[test]
    fn reused_scratch_gives_the_same_pairs_when_the_box_count_changes() {
        let exec = Execution::new(ExecutionMode::Parallel, 2).unwrap().fine_grained();
        let mut scratch = SweepScratch::default();
        for (count, seed) in [(4000, 7), (2500, 8), (4000, 9)] {
            let boxes = random_boxes(count, seed);
            let found = sweep_and_prune(boxes.as_slice(), &exec, &mut scratch);
            assert_eq!(normalized(found), brute_force(&boxes), "{count} boxes");
        }
    }

    #[test]
    fn order_key_preserves_float_order() {
        let xs = [-1e30f32, -5.0, -1.0, -0.0, 0.0, 1e-40, 1.0, 2.5, 1e30];
        for w in xs.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} vs {}", w[0], w[1]);
        }
    }
}
