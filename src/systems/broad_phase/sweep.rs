//! The sweep step of the broad phase, and [`sweep_and_prune`], which runs
//! the whole broad phase on any [`BoxSource`].

use std::ops::Range;

use bevy::prelude::*;

use super::filing::{CellBox, FiledChunk, corner_bounds, file_by_cell};
use super::grid::{BOXES_PER_CELL, Grid};
use super::{BoxSource, SweepScratch};
use crate::components::BodyId;
use crate::execution::Execution;

/// Boxes per parallel chunk of the filing. Below two grains a step runs
/// whole: on these small inputs the dispatch and the cache traffic between
/// cores cost more than they save.
const GRAIN: usize = 8_192;

/// Cells per parallel chunk of the sweep (about [`GRAIN`] boxes).
const CELL_GRAIN: usize = GRAIN / BOXES_PER_CELL;

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
            cell_boxes.extend_from_slice(chunk.in_cell(cell));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::execution::ExecutionMode;
    use crate::rng::Rng;
    use crate::systems::Aabb;

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

    fn unit_boxes(centers: &[[f32; 3]]) -> Vec<Aabb> {
        centers
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
                let center = Vec3::new(grid(60.0), grid(60.0), grid(60.0));
                let half = if i % 97 == 0 {
                    Vec3::new(grid(12.0) + 0.25, grid(12.0) + 0.25, grid(12.0) + 0.25)
                } else {
                    Vec3::new(grid(1.5) + 0.25, grid(1.5) + 0.25, grid(1.5) + 0.25)
                };
                Aabb::new(center, half)
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
