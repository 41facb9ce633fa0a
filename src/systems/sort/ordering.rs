//! The last kernel of the sort stage: each cell's boxes put in sweep order
//! where they lie: by lower x bound, ties by their position in the cell,
//! which is input order.

use super::filing::CellBox;
use crate::execution::Split;
use crate::maths::order_key;

/// A filed box's place in sweep order: the order key of its lower x bound
/// above its index in the input, so that ties go by input order.
#[inline]
pub(super) fn sweep_key(b: &CellBox) -> u64 {
    (u64::from(order_key(b.aabb.min.x)) << 32) | u64::from(b.index)
}

/// Contiguous cells of the filing and their boxes: the `c`-th cell holds
/// `boxes[starts[c] - starts[0]..starts[c + 1] - starts[0]]`. Cut by
/// cells, so that chunks of cells order their boxes side by side.
pub struct CellRuns<'a> {
    /// The grid cell of the first run.
    first: usize,
    starts: &'a [u32],
    boxes: &'a mut [CellBox],
}

impl<'a> CellRuns<'a> {
    /// Every cell of a filing: `starts` has one entry per cell and one
    /// more, and `boxes` is as long as its last says.
    pub fn new(starts: &'a [u32], boxes: &'a mut [CellBox]) -> Self {
        Self {
            first: 0,
            starts,
            boxes,
        }
    }

    /// Each cell (its index in the grid) and its boxes, in order.
    pub fn cells(self) -> impl Iterator<Item = (usize, &'a mut [CellBox])> {
        let (first, mut rest) = (self.first, self.boxes);
        self.starts.windows(2).enumerate().map(move |(k, run)| {
            let (boxes, after) = std::mem::take(&mut rest).split_at_mut((run[1] - run[0]) as usize);
            rest = after;
            (first + k, boxes)
        })
    }
}

impl Split for CellRuns<'_> {
    fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    fn split_at(self, mid: usize) -> (Self, Self) {
        let cut = (self.starts[mid] - self.starts[0]) as usize;
        let (first, second) = self.boxes.split_at_mut(cut);
        (
            Self {
                first: self.first,
                starts: &self.starts[..=mid],
                boxes: first,
            },
            Self {
                first: self.first + mid,
                starts: &self.starts[mid..],
                boxes: second,
            },
        )
    }
}

/// Kernel: every cell in `runs` put in sweep order where it lies.
pub fn order_cells(runs: CellRuns<'_>) {
    // Scratch for the fullest cell, allocated once: a worker that grew it
    // cell by cell would take the allocator's lock (one heap for all
    // threads, see `memory/heap.rs`) a few times a chunk.
    let fullest = runs.starts.windows(2).map(|run| run[1] - run[0]).max().unwrap_or(0) as usize;
    let (mut keys, mut ordered) = (Vec::with_capacity(fullest), Vec::with_capacity(fullest));
    for (_, boxes) in runs.cells() {
        sweep_keys(boxes, &mut keys);
        ordered.clear();
        ordered.extend(keys.iter().map(|&key| boxes[key as u32 as usize]));
        boxes.copy_from_slice(&ordered);
    }
}

/// The sweep order of one cell's `boxes` as sorted keys, into `keys`: the
/// order key of the lower x bound above the position, so ties keep input
/// order; the low 32 bits of each are the box's position.
fn sweep_keys(boxes: &[CellBox], keys: &mut Vec<u64>) {
    keys.clear();
    keys.extend(
        boxes
            .iter()
            .enumerate()
            .map(|(k, b)| (u64::from(order_key(b.aabb.min.x)) << 32) | k as u64),
    );
    keys.sort_unstable();
}

#[cfg(test)]
mod tests {
    use bevy::prelude::*;

    use super::*;
    use crate::physics::Aabb;

    #[test]
    fn cells_are_ordered_on_x_with_ties_in_input_order_however_they_are_cut() {
        let at = |index: u32, x: f32| CellBox {
            index,
            aabb: Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::splat(0.1)),
        };
        // Two cells: [3, 1, 2, 1, 0] on x, then [5, -5].
        let filed = [
            at(0, 3.0),
            at(1, 1.0),
            at(2, 2.0),
            at(3, 1.0),
            at(4, 0.0),
            at(5, 5.0),
            at(6, -5.0),
        ];
        let starts = [0, 5, 7];
        for cut in 0..=2 {
            let mut boxes = filed;
            let (first, second) = CellRuns::new(&starts, &mut boxes).split_at(cut);
            assert_eq!((first.len(), second.len()), (cut, 2 - cut));
            order_cells(first);
            order_cells(second);
            let indices: Vec<u32> = boxes.iter().map(|b| b.index).collect();
            assert_eq!(indices, [4, 1, 3, 2, 0, 6, 5], "cut after {cut} cells");
        }
    }
}
