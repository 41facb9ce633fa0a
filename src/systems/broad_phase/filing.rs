//! The first kernel of the sort stage: a chunk of boxes filed by grid cell
//! with a stable counting sort, into buffers kept between updates.

use std::ops::Range;

use bevy::prelude::*;

use super::grid::{Grid, SampledBox};
use super::{Aabb, BoxSource};

/// A box filed under a grid cell: its index in the input and its corners.
#[derive(Clone, Copy, Debug, Default)]
pub struct CellBox {
    /// Index of the box in the broad phase's input.
    pub index: u32,
    /// Its corners.
    pub aabb: Aabb,
}

/// One chunk's boxes filed by cell: `boxes[starts[c]..starts[c + 1]]` are
/// the chunk's boxes in cell `c`, in input order.
#[derive(Default)]
pub struct FiledChunk {
    starts: Vec<u32>,
    cursor: Vec<u32>,
    /// The one cell of each box in the chunk, or [`SEVERAL_CELLS`].
    cells: Vec<u32>,
    boxes: Vec<CellBox>,
}

impl FiledChunk {
    /// The chunk's boxes in `cell`, in input order.
    #[inline]
    pub fn in_cell(&self, cell: usize) -> &[CellBox] {
        &self.boxes[self.starts[cell] as usize..self.starts[cell + 1] as usize]
    }

    /// Calls `f` with the chunk's boxes in every cell, cell after cell, to
    /// be reordered in place.
    pub fn for_each_cell_mut(&mut self, mut f: impl FnMut(&mut [CellBox])) {
        let mut rest = self.boxes.as_mut_slice();
        for run in self.starts.windows(2) {
            let (cell, after) = rest.split_at_mut((run[1] - run[0]) as usize);
            f(cell);
            rest = after;
        }
    }
}

/// Noted for a box that covers more than one cell.
const SEVERAL_CELLS: u32 = u32::MAX;

/// Kernel: the corners and extents of the boxes in `range` whose index is
/// a multiple of `stride` (so the sample does not depend on how the boxes
/// are cut into chunks). Reads only those boxes.
pub fn corner_sample<B: BoxSource + ?Sized>(boxes: &B, range: Range<usize>, stride: usize) -> Vec<SampledBox> {
    let stride = stride.max(1);
    // The first multiple of `stride` in the range.
    let first = range.start.div_ceil(stride) * stride;
    (first..range.end)
        .step_by(stride)
        .map(|i| {
            let b = boxes.get(i);
            SampledBox {
                corner: Vec2::new(b.min.y, b.min.z),
                extent: Vec2::new(b.max.y - b.min.y, b.max.z - b.min.z),
            }
        })
        .collect()
}

/// Kernel: the bounds of the lower y–z corners of the boxes in `range`.
pub fn corner_bounds<B: BoxSource + ?Sized>(boxes: &B, range: Range<usize>) -> (Vec2, Vec2) {
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
pub fn file_by_cell<B: BoxSource + ?Sized>(
    boxes: &B,
    range: Range<usize>,
    grid: &Grid,
    mut out: FiledChunk,
) -> FiledChunk {
    let FiledChunk {
        starts,
        cursor,
        cells,
        boxes: filed,
    } = &mut out;
    let cell_count = grid.cell_count();
    starts.clear();
    starts.resize(cell_count + 1, 0);
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
    for cell in 0..cell_count {
        starts[cell + 1] += starts[cell];
    }
    cursor.clear();
    cursor.extend_from_slice(&starts[..cell_count]);
    // Same length as last update's in a steady state: nothing to write here.
    filed.resize(starts[cell_count] as usize, CellBox::default());
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::broad_phase::grid::BOXES_PER_CELL;

    #[test]
    fn boxes_are_filed_by_cell_in_input_order() {
        let grid = Grid::fit(Vec2::ZERO, Vec2::splat(4.0), BOXES_PER_CELL * 16);
        let boxes = [
            Aabb::new(Vec3::new(0.5, 3.5, 3.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 0.5, 0.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 2.0, 0.5), Vec3::new(0.1, 1.0, 0.1)),
            Aabb::new(Vec3::new(0.0, 3.2, 3.6), Vec3::splat(0.1)),
        ];
        let filed = file_by_cell(boxes.as_slice(), 0..4, &grid, FiledChunk::default());
        let indices = |cell: usize| filed.in_cell(cell).iter().map(|b| b.index).collect::<Vec<_>>();
        assert_eq!(indices(15), [0, 3]);
        assert_eq!(indices(0), [1]);
        // The tall box covers three cells on y.
        assert_eq!((indices(4), indices(8), indices(12)), (vec![2], vec![2], vec![2]));
        assert_eq!((0..16).map(|c| filed.in_cell(c).len()).sum::<usize>(), 6);
    }
}
