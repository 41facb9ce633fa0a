//! The kernel of the sweep stage, and [`sweep_and_prune`], which runs the
//! whole broad phase (sort, then sweep) on any [`BoxSource`].

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::components::BodyId;
use crate::execution::{Execution, StageExecution};
use crate::systems::SimulationSystems;
use crate::systems::pipeline::{TooManyPairs, pair_limit};
use crate::systems::sort::{BoxSource, Grid, SortedBoxes, sort_boxes};

/// Pairs found so far by all chunks of one sweep, against the limit.
/// Chunks report in batches; the sweep fails exactly when the total of
/// all pairs exceeds the limit, whichever chunk notices (every pair is
/// counted once, and a total above the limit makes some report exceed it),
/// so the outcome is the same in both modes.
struct PairBudget {
    found: AtomicUsize,
    limit: usize,
}

/// Pairs a chunk finds between two reports to the [`PairBudget`].
const BUDGET_BATCH: usize = 4096;

impl PairBudget {
    /// Counts `pairs` more; whether the total is still within the limit.
    fn take(&self, pairs: usize) -> bool {
        self.found.fetch_add(pairs, Ordering::Relaxed) + pairs <= self.limit
    }
}

/// Kernel: the overlapping pairs `(i, j)` of input indices found in the
/// `cells`, cell after cell, visiting each cell's boxes in the sweep order
/// the sort stage put them in: each box scans forward while the next starts
/// before it ends on x. `None` once the sweep's pairs exceed the budget.
fn sweep_cells(sorted: &SortedBoxes, grid: &Grid, cells: Range<usize>, budget: &PairBudget) -> Option<Vec<(u32, u32)>> {
    let mut pairs = Vec::new();
    for cell in cells {
        let mut rest = sorted.in_sweep_order(cell);
        while let Some((a, after)) = rest.split_first() {
            rest = after;
            for b in after {
                if b.aabb.min.x > a.aabb.max.x {
                    break;
                }
                if a.aabb.overlaps_yz(&b.aabb) && grid.owner(&a.aabb, &b.aabb) == cell as u32 {
                    pairs.push((a.index, b.index));
                    if pairs.len().is_multiple_of(BUDGET_BATCH) && !budget.take(BUDGET_BATCH) {
                        return None;
                    }
                }
            }
        }
    }
    budget.take(pairs.len() % BUDGET_BATCH).then_some(pairs)
}

/// The sweep stage's work: every overlapping pair of the sorted boxes
/// exactly once, as input indices `(i, j)` with box `i` first in sweep
/// order, cell after cell; ranges of cells are the chunks. Fails, in both
/// modes alike, when there are more than `limit` pairs.
pub fn sweep_sorted(
    sorted: &SortedBoxes,
    stage: StageExecution<'_>,
    limit: usize,
) -> Result<Vec<(u32, u32)>, TooManyPairs> {
    let Some(grid) = sorted.grid() else {
        return Ok(Vec::new());
    };
    let too_many = TooManyPairs::piled(limit, sorted.len());
    let budget = PairBudget {
        found: AtomicUsize::new(0),
        limit: too_many.limit,
    };
    let chunks = stage.map_chunks(0..grid.cell_count(), |cells| sweep_cells(sorted, grid, cells, &budget));
    let chunks: Option<Vec<_>> = chunks.into_iter().collect();
    Ok(chunks.ok_or(too_many)?.concat())
}

/// Sweep and prune over `boxes` (any order): the sort stage's and the sweep
/// stage's work, each split as `execution`'s policy says for that stage.
/// Every overlapping pair of indices into `boxes` exactly once, as `(i, j)`
/// with `boxes[i]` first in sweep order; the same pairs in the same order
/// (or the same failure: more than [`pair_limit`] pairs) in both execution
/// modes and under every split policy.
pub fn sweep_and_prune<B: BoxSource + ?Sized>(
    boxes: &B,
    execution: &Execution,
    sorted: &mut SortedBoxes,
) -> Result<Vec<(u32, u32)>, TooManyPairs> {
    sort_boxes(
        boxes,
        execution.for_stage(SimulationSystems::Sort.name(), boxes.len()),
        sorted,
    );
    sweep_sorted(
        sorted,
        execution.for_stage(SimulationSystems::Sweep.name(), boxes.len()),
        pair_limit(boxes.len()),
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
    use crate::systems::pipeline::pair_limit::MIN_PAIR_LIMIT;
    use bevy::prelude::*;

    use crate::execution::{ExecutionMode, SplitPolicy};
    use crate::maths::Rng;
    use crate::physics::Aabb;

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

    /// Parallel runs split every step into small chunks, so that every
    /// cell's boxes are placed by many chunks, each into its own slots.
    fn run(boxes: &[Aabb], mode: ExecutionMode) -> Vec<(u32, u32)> {
        let exec = Execution::new(mode, 3).unwrap().fine_grained();
        sweep_and_prune(boxes, &exec, &mut SortedBoxes::default()).unwrap()
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
            let found = sweep_and_prune(boxes.as_slice(), &exec, &mut scratch).unwrap();
            assert_eq!(normalized(found), brute_force(&boxes), "{count} boxes");
        }
    }

    /// A sort that starts from the last one's filing (boxes moving a little
    /// each update, some removed as a despawn would, some new, a shuffle)
    /// finds the same pairs as a fresh one, in both modes (in another order
    /// where the repaired filing kept an older grid: the sweep stage sorts
    /// them).
    #[test]
    fn a_sort_from_the_last_order_equals_a_fresh_one() {
        let mut rng = Rng::new(21);
        let mut boxes = random_boxes(6000, 5);
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            let exec = Execution::new(mode, 2).unwrap().with_split(SplitPolicy::Always);
            let mut kept = SortedBoxes::default();
            for update in 0..12 {
                for b in &mut boxes {
                    let step = Vec3::new(
                        rng.symmetric(0.4) as f32,
                        rng.symmetric(0.4) as f32,
                        rng.symmetric(0.4) as f32,
                    );
                    *b = Aabb {
                        min: b.min + step,
                        max: b.max + step,
                    };
                }
                match update % 4 {
                    1 => {
                        for k in 0..40 {
                            boxes.swap_remove(k * 97);
                        }
                    }
                    2 => boxes.extend(random_boxes(300, update)),
                    3 => boxes.swap(10, 4000),
                    _ => {}
                }
                let kept_pairs = sweep_and_prune(boxes.as_slice(), &exec, &mut kept).unwrap();
                let fresh = sweep_and_prune(boxes.as_slice(), &exec, &mut SortedBoxes::default()).unwrap();
                let expected = brute_force(&boxes);
                assert_eq!(normalized(fresh.clone()), expected, "{mode:?}, update {update}");
                // The same pairs, each the same way round (first in sweep order).
                let (mut kept_pairs, mut fresh) = (kept_pairs, fresh);
                kept_pairs.sort_unstable();
                fresh.sort_unstable();
                assert_eq!(kept_pairs, fresh, "{mode:?}, update {update}");
            }
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
            let found = sweep_and_prune(boxes.as_slice(), &exec, &mut SortedBoxes::default()).unwrap();
            assert_eq!(found, whole, "split {split}");
        }
    }

    /// Boxes on one point overlap in N² / 2 pairs: the sweep stops at the
    /// limit in both modes, and a crowd just under it still passes.
    #[test]
    fn a_pile_up_stops_at_the_pair_limit_in_both_modes() {
        // 2 000 coincident boxes: 1 999 000 pairs, above the 1 Mi floor.
        let piled = vec![Aabb::new(Vec3::ZERO, Vec3::ONE); 2000];
        assert!(2000 * 1999 / 2 > pair_limit(2000));
        // 1 400 of them: 979 300 pairs, just under it.
        let crowd = vec![Aabb::new(Vec3::ZERO, Vec3::ONE); 1400];
        assert!(1400 * 1399 / 2 <= pair_limit(1400));
        for mode in [ExecutionMode::Sequential, ExecutionMode::Parallel] {
            let exec = Execution::new(mode, 3).unwrap().fine_grained();
            let failed = sweep_and_prune(piled.as_slice(), &exec, &mut SortedBoxes::default());
            assert_eq!(failed, Err(TooManyPairs::piled(MIN_PAIR_LIMIT, 2000)), "{mode:?}");
            let found = sweep_and_prune(crowd.as_slice(), &exec, &mut SortedBoxes::default()).unwrap();
            assert_eq!(found.len(), 1400 * 1399 / 2, "{mode:?}");
        }
        assert_eq!(pair_limit(1_000_000), 16_000_000);
    }
}
