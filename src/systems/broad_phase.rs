//! Stage 3: sweep and prune (DESIGN §2.3) — every pair of overlapping boxes.
//!
//! Boxes are sorted by their lower x bound (a stable radix sort, so ties keep
//! their input order and the result is one fixed permutation). A single sweep
//! along x degrades when many boxes share an x range (a dense cloud of a
//! million cubes puts hundreds in every box's x range), so the sweep runs per
//! cell of a grid over y and z: each box joins every cell its y–z extent
//! covers (a stable counting sort keeps each cell in x order), each entry
//! scans forward in its cell while the next box starts before it ends on x,
//! and confirms y and z. Touching counts as overlap. A pair found in several
//! cells is reported only by the cell holding the lower corner of the pair's
//! y–z intersection, so every pair comes out exactly once. A big box (the
//! planet) joins the cells it covers and scans only the boxes inside its
//! x-slab there, so the cost stays near-linear. The scans read only sorted
//! arrays; they run in parallel on contiguous ranges of entries and their
//! pairs are concatenated in order.

use std::time::Instant;

use bevy::prelude::*;

use crate::components::{BodyId, HalfExtents};
use crate::resources::{Execution, SimulationSettings, StageTimings};
use crate::systems::{SimulationSystems, SimulationUpdate};

/// Boxes (or grid entries) per parallel chunk of the gather and of the
/// sweep. Below two grains a step runs whole: on these small inputs the
/// dispatch and the cache traffic between cores cost more than they save.
const GRAIN: usize = 32_768;

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

/// Buffers of the sweep, kept between updates.
#[derive(Default)]
pub struct SweepScratch {
    keys: Vec<(u32, u32)>,
    keys_tmp: Vec<(u32, u32)>,
    sorted: Vec<Aabb>,
    entries: Vec<(u32, u32)>,
    entries_tmp: Vec<(u32, u32)>,
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
    fn fit(boxes: &[Aabb]) -> Self {
        let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        for b in boxes {
            let corner = Vec2::new(b.min.y, b.min.z);
            lo = lo.min(corner);
            hi = hi.max(corner);
        }
        let n = ((boxes.len() / BOXES_PER_CELL) as f64)
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
        for y in y0..=y1 {
            for z in z0..=z1 {
                f(y * self.cells_per_axis + z);
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

/// Stable LSD radix sort of `(key, payload)` by key, 11 bits per pass.
pub fn radix_sort(items: &mut Vec<(u32, u32)>, tmp: &mut Vec<(u32, u32)>) {
    const BITS: u32 = 11;
    // Clearing 3 × 2048 counters costs more than sorting a few items; a
    // stable comparison sort gives the same order.
    if items.len() < 512 {
        items.sort_by_key(|&(k, _)| k);
        return;
    }
    for pass in 0..3 {
        let shift = pass * BITS;
        counting_sort(items, tmp, 1 << BITS, |k| ((k >> shift) as usize) & ((1 << BITS) - 1));
    }
}

/// Stable counting sort of `items` by `bucket(key)` < `buckets`.
fn counting_sort(
    items: &mut Vec<(u32, u32)>,
    tmp: &mut Vec<(u32, u32)>,
    buckets: usize,
    bucket: impl Fn(u32) -> usize,
) {
    let mut offsets = vec![0usize; buckets];
    for &(k, _) in items.iter() {
        offsets[bucket(k)] += 1;
    }
    let mut sum = 0;
    for o in offsets.iter_mut() {
        let count = *o;
        *o = sum;
        sum += count;
    }
    tmp.clear();
    tmp.resize(items.len(), (0, 0));
    for &item in items.iter() {
        let d = bucket(item.0);
        tmp[offsets[d]] = item;
        offsets[d] += 1;
    }
    std::mem::swap(items, tmp);
}

/// Kernel: the overlapping pairs `(i, j)` of boxes in `sorted` (ordered by
/// `min.x`), for the scans of the `entries` (cell, box) in `range`. Entries
/// are grouped by cell, in x order within a cell.
fn sweep(sorted: &[Aabb], entries: &[(u32, u32)], grid: &Grid, range: std::ops::Range<usize>) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for e in range {
        let (cell, i) = entries[e];
        let a = &sorted[i as usize];
        for &(other_cell, j) in &entries[e + 1..] {
            let b = &sorted[j as usize];
            if other_cell != cell || b.min.x > a.max.x {
                break;
            }
            if a.overlaps_yz(b) && grid.owner(a, b) == cell {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// Sweep and prune over `boxes` (any order): every overlapping pair of
/// indices into `boxes` exactly once, as `(i, j)` in sweep order. The same
/// pairs in the same order in both execution modes.
pub fn sweep_and_prune(boxes: &[Aabb], execution: &Execution, scratch: &mut SweepScratch) -> Vec<(u32, u32)> {
    let SweepScratch {
        keys,
        keys_tmp,
        sorted,
        entries,
        entries_tmp,
    } = scratch;
    keys.resize(boxes.len(), (0, 0));
    execution.for_chunks(
        (0..boxes.len(), keys.as_mut_slice()),
        GRAIN,
        |(range, keys): (_, &mut [(u32, u32)])| {
            for (i, key) in range.zip(keys) {
                *key = (order_key(boxes[i].min.x), i as u32);
            }
        },
    );
    radix_sort(keys, keys_tmp);
    sorted.resize(boxes.len(), Aabb::default());
    execution.for_chunks(
        (keys.as_slice(), sorted.as_mut_slice()),
        GRAIN,
        |(keys, out): (&[(u32, u32)], &mut [Aabb])| {
            for (&(_, i), out) in keys.iter().zip(out) {
                *out = boxes[i as usize];
            }
        },
    );
    let grid = Grid::fit(sorted);
    entries.clear();
    for (i, b) in sorted.iter().enumerate() {
        grid.for_each_cell(b, |cell| entries.push((cell, i as u32)));
    }
    counting_sort(entries, entries_tmp, grid.cell_count(), |cell| cell as usize);
    let (sorted, entries) = (&*sorted, &*entries);
    let chunks = execution.map_chunks(0..entries.len(), GRAIN, |range| sweep(sorted, entries, &grid, range));
    let order = &*keys;
    chunks
        .into_iter()
        .flatten()
        .map(|(i, j)| (order[i as usize].1, order[j as usize].1))
        .collect()
}

/// An index pair reordered so that the lower id comes first.
#[inline]
pub fn by_id((i, j): (u32, u32), ids: &[BodyId]) -> (usize, usize) {
    let (i, j) = (i as usize, j as usize);
    if ids[i] < ids[j] { (i, j) } else { (j, i) }
}

/// Index pairs as id pairs `(lower, higher)`, sorted.
pub fn id_pairs(index_pairs: &[(u32, u32)], ids: &[BodyId]) -> Vec<(BodyId, BodyId)> {
    let mut pairs: Vec<(BodyId, BodyId)> = index_pairs
        .iter()
        .map(|&p| {
            let (i, j) = by_id(p, ids);
            (ids[i], ids[j])
        })
        .collect();
    pairs.sort_unstable();
    pairs
}

/// What the broad phase gathers from the tables, in table order.
#[derive(Default)]
struct Gathered {
    boxes: Vec<Aabb>,
    ids: Vec<BodyId>,
    entities: Vec<Entity>,
}

fn broad_phase(
    execution: Res<Execution>,
    mut timings: ResMut<StageTimings>,
    mut pairs: ResMut<OverlappingPairs>,
    mut gathered: Local<Gathered>,
    mut scratch: Local<SweepScratch>,
    bodies: Query<(Entity, &BodyId, &Transform, &HalfExtents)>,
) {
    let start = Instant::now();
    let Gathered { boxes, ids, entities } = &mut *gathered;
    let tables = bodies.contiguous_iter().expect("body components are table-stored");
    let count = bodies.iter().len();
    boxes.resize(count, Aabb::default());
    ids.clear();
    entities.clear();
    let mut offset = 0;
    for (table_entities, table_ids, transforms, halves) in tables {
        let n = table_ids.len();
        ids.extend_from_slice(table_ids);
        entities.extend_from_slice(table_entities);
        let columns = (transforms, halves, &mut boxes[offset..offset + n]);
        execution.for_chunks(
            columns,
            GRAIN,
            |(transforms, halves, out): (&[Transform], &[HalfExtents], &mut [Aabb])| {
                for ((t, h), out) in transforms.iter().zip(halves).zip(out) {
                    *out = Aabb::new(t.translation, h.0);
                }
            },
        );
        offset += n;
    }
    let index_pairs = sweep_and_prune(boxes, &execution, &mut scratch);
    pairs.0.clear();
    pairs.0.extend(index_pairs.iter().map(|&p| {
        let (i, j) = by_id(p, ids);
        Pair {
            a: ids[i],
            b: ids[j],
            entity_a: entities[i],
            entity_b: entities[j],
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

    fn run(boxes: &[Aabb], mode: ExecutionMode) -> Vec<(u32, u32)> {
        let exec = Execution::new(mode, 3).unwrap();
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
    fn radix_sort_is_a_stable_sort() {
        let mut rng = Rng::new(5);
        let mut items: Vec<(u32, u32)> = (0..10_000)
            .map(|i| ((rng.next_u64() % 3000) as u32 * 1_000_003, i))
            .collect();
        let mut expected = items.clone();
        expected.sort_by_key(|&(k, _)| k);
        radix_sort(&mut items, &mut Vec::new());
        assert_eq!(items, expected);
    }

    #[test]
    fn order_key_preserves_float_order() {
        let xs = [-1e30f32, -5.0, -1.0, -0.0, 0.0, 1e-40, 1.0, 2.5, 1e30];
        for w in xs.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} vs {}", w[0], w[1]);
        }
    }
}
