//! The second kernel of the sort stage: each cell's boxes — gathered from
//! every filed chunk — put in sweep order: by lower x bound, ties by their
//! position in the cell, which is input order.

use std::ops::Range;

use super::filing::{CellBox, FiledChunk};

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

/// The boxes of `cell`: the runs of every filed chunk one after the other
/// (input order), gathered into `scratch` when there are several chunks.
pub fn gather_cell<'a>(filed: &'a [FiledChunk], cell: usize, scratch: &'a mut Vec<CellBox>) -> &'a [CellBox] {
    match filed {
        [only] => only.in_cell(cell),
        _ => {
            scratch.clear();
            for chunk in filed {
                scratch.extend_from_slice(chunk.in_cell(cell));
            }
            scratch
        }
    }
}

/// A range of cells with their boxes in sweep order: for cell
/// `cells.start + c`, `boxes[starts[c]..starts[c + 1]]`. A copy, so that
/// the sweep reads each cell's boxes in order, in one piece.
#[derive(Default)]
pub struct CellOrder {
    /// The cells this part covers.
    pub cells: Range<usize>,
    starts: Vec<u32>,
    boxes: Vec<CellBox>,
}

impl CellOrder {
    /// `cell`'s boxes in sweep order (`cell` in [`Self::cells`]).
    #[inline]
    pub fn of(&self, cell: usize) -> &[CellBox] {
        let c = cell - self.cells.start;
        &self.boxes[self.starts[c] as usize..self.starts[c + 1] as usize]
    }
}

/// Kernel: every cell in `cells` with its boxes in sweep order, into the
/// reused `out`, for boxes filed in several chunks.
pub fn order_cells(filed: &[FiledChunk], cells: Range<usize>, mut out: CellOrder) -> CellOrder {
    let mut gathered = Vec::new();
    let mut keys: Vec<u64> = Vec::new();
    out.starts.clear();
    out.boxes.clear();
    out.starts.push(0);
    for cell in cells.clone() {
        let boxes = gather_cell(filed, cell, &mut gathered);
        sweep_keys(boxes, &mut keys);
        out.boxes.extend(keys.iter().map(|&key| boxes[key as u32 as usize]));
        out.starts.push(out.boxes.len() as u32);
    }
    out.cells = cells;
    out
}

/// Kernel: every cell of the one `filed` chunk put in sweep order where it
/// lies, for boxes filed in one chunk (the stage ran whole): no copy.
pub fn order_in_place(filed: &mut FiledChunk) {
    let (mut keys, mut ordered) = (Vec::new(), Vec::new());
    filed.for_each_cell_mut(|boxes| {
        sweep_keys(boxes, &mut keys);
        ordered.clear();
        ordered.extend(keys.iter().map(|&key| boxes[key as u32 as usize]));
        boxes.copy_from_slice(&ordered);
    });
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
    use crate::systems::Aabb;
    use crate::systems::broad_phase::filing::file_by_cell;
    use crate::systems::broad_phase::grid::Grid;

    #[test]
    fn order_key_preserves_float_order() {
        let xs = [-1e30f32, -5.0, -1.0, -0.0, 0.0, 1e-40, 1.0, 2.5, 1e30];
        for w in xs.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} vs {}", w[0], w[1]);
        }
    }

    #[test]
    fn cells_are_ordered_on_x_across_chunks_with_ties_in_input_order() {
        let grid = Grid::fit(Vec2::ZERO, Vec2::ZERO, 1);
        let at = |x: f32| Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::splat(0.1));
        let boxes = [at(3.0), at(1.0), at(2.0), at(1.0), at(0.0)];
        let whole = [file_by_cell(boxes.as_slice(), 0..5, &grid, FiledChunk::default())];
        let split = [
            file_by_cell(boxes.as_slice(), 0..2, &grid, FiledChunk::default()),
            file_by_cell(boxes.as_slice(), 2..5, &grid, FiledChunk::default()),
        ];
        for filed in [whole.as_slice(), split.as_slice()] {
            let order = order_cells(filed, 0..1, CellOrder::default());
            let indices: Vec<u32> = order.of(0).iter().map(|b| b.index).collect();
            assert_eq!(indices, [4, 1, 3, 2, 0]);
        }
        // One chunk is put in the same order where it lies.
        let [mut only] = whole;
        order_in_place(&mut only);
        let indices: Vec<u32> = only.in_cell(0).iter().map(|b| b.index).collect();
        assert_eq!(indices, [4, 1, 3, 2, 0]);
    }
}
