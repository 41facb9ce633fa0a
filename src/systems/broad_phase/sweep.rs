//! The kernel of the sweep stage, and [`sweep_and_prune`], which runs the
//! whole broad phase (sort, then sweep) on any [`BoxSource`].

use std::ops::Range;

use super::BoxSource;
use super::grid::Grid;
use super::ordering::gather_cell;
use super::sort::{SortedBoxes, sort_boxes};
use crate::components::BodyId;
use crate::execution::{Execution, StageExecution};
use crate::systems::SimulationSystems;

/// Kernel: the overlapping pairs `(i, j)` of input indices found in the
/// `cells`, cell after cell, visiting each cell's boxes in the sweep order
/// the sort stage found: each box scans forward while the next starts
/// before it ends on x.
fn sweep_cells(sorted: &SortedBoxes, grid: &Grid, cells: Range<usize>) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    let mut scratch = Vec::new();
    let orders = sorted.orders();
    // The part of the order holding the first cell; later cells follow.
    let mut part = orders.partition_point(|o| o.cells.end <= cells.start);
    for cell in cells {
        while orders[part].cells.end <= cell {
            part += 1;
        }
        let order = orders[part].of(cell);
        if order.len() < 2 {
            continue;
        }
        let boxes = gather_cell(sorted.chunks(), cell, &mut scratch);
        for (k, &first) in order.iter().enumerate() {
            let a = &boxes[first as usize];
            for &second in &order[k + 1..] {
                let b = &boxes[second as usize];
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

/// The sweep stage's work: every overlapping pair of the sorted boxes
/// exactly once, as input indices `(i, j)` with box `i` first in sweep
/// order, cell after cell; ranges of cells are the chunks.
pub fn sweep_sorted(sorted: &SortedBoxes, stage: StageExecution<'_>) -> Vec<(u32, u32)> {
    let Some(grid) = sorted.grid() else {
        return Vec::new();
    };
    stage
        .map_chunks(0..grid.cell_count(), |cells| sweep_cells(sorted, grid, cells))
        .concat()
}

/// Sweep and prune over `boxes` (any order): the sort stage's and the sweep
/// stage's work, each split as `execution`'s policy says for that stage.
/// Every overlapping pair of indices into `boxes` exactly once, as `(i, j)`
/// with `boxes[i]` first in sweep order; the same pairs in the same order
/// in both execution modes and under every split policy.
pub fn sweep_and_prune<B: BoxSource + ?Sized>(
    boxes: &B,
    execution: &Execution,
    sorted: &mut SortedBoxes,
) -> Vec<(u32, u32)> {
    sort_boxes(
        boxes,
        execution.for_stage(SimulationSystems::Sort.name(), boxes.len()),
        sorted,
    );
    sweep_sorted(
        sorted,
        execution.for_stage(SimulationSystems::Sweep.name(), boxes.len()),
    )
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
    use bevy::prelude::*;

    use crate::execution::{ExecutionMode, SplitPolicy};
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
        sweep_and_prune(boxes, &exec, &mut SortedBoxes::default())
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

    /// Far-flung boxes are clamped into the grid's edge cells: pairs among
    /// them, and with huge boxes reaching back into the crowd, are still
    /// found, once each.
    #[test]
    fn matches_brute_force_with_far_outliers() {
        let mut boxes = random_boxes(4000, 9);
        for k in 0..12 {
            let far = 1e6 * (1.0 + (k / 2) as f32);
            // In pairs that overlap each other, on every side of the crowd.
            let center = match k % 4 {
                0 | 1 => Vec3::new(30.0, far, -far),
                _ => Vec3::new(-far, -far, 30.0),
            } + Vec3::splat((k % 2) as f32 * 0.5);
            boxes.push(Aabb::new(center, Vec3::ONE));
        }
        // One long box from far away into the crowd.
        boxes.push(Aabb::new(Vec3::new(30.0, 5e5, 30.0), Vec3::new(1.0, 5e5, 1.0)));
        let expected = brute_force(&boxes);
        assert!(expected.iter().any(|&(i, j)| i >= 4000 && j >= 4000), "far pairs exist");
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            assert_eq!(normalized(run(&boxes, mode)), expected, "{mode:?}");
        }
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
        let mut scratch = SortedBoxes::default();
        for (count, seed) in [(4000, 7), (2500, 8), (4000, 9)] {
            let boxes = random_boxes(count, seed);
            let found = sweep_and_prune(boxes.as_slice(), &exec, &mut scratch);
            assert_eq!(normalized(found), brute_force(&boxes), "{count} boxes");
        }
    }

    #[test]
    fn every_split_policy_finds_the_same_pairs_in_the_same_order() {
        let boxes = random_boxes(20_000, 11);
        let whole = run(&boxes, ExecutionMode::Sequential);
        for split in [
            SplitPolicy::Always,
            SplitPolicy::Above(5_000),
            SplitPolicy::Above(50_000),
            SplitPolicy::Auto,
        ] {
            let exec = Execution::new(ExecutionMode::Parallel, 2).unwrap().with_split(split);
            let found = sweep_and_prune(boxes.as_slice(), &exec, &mut SortedBoxes::default());
            assert_eq!(found, whole, "split {split}");
        }
    }
}
