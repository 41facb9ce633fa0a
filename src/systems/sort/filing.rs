//! The first kernels of the sort stage: the boxes filed by grid cell with a
//! stable counting sort (count by chunk, lay out, place by chunk) into one
//! array kept between updates.

use std::ops::Range;

use bevy::prelude::*;

use super::BoxSource;
use super::grid::{Grid, SampledBox};
use crate::physics::Aabb;

/// A box filed under a grid cell: its index in the input and its corners.
#[derive(Clone, Copy, Debug, Default)]
pub struct CellBox {
    /// Index of the box in the broad phase's input.
    pub index: u32,
    /// Its corners.
    pub aabb: Aabb,
}

/// One chunk of boxes counted by cell: the filing's first pass, kept for
/// its second.
#[derive(Default)]
pub struct ChunkCount {
    /// The boxes counted.
    range: Range<usize>,
    /// The chunk's boxes in each cell.
    per_cell: Vec<u32>,
    /// The one cell of each box in the chunk, or [`WORK_OUT_AGAIN`]: two
    /// bytes a box, where the grid has at most 65 536 cells.
    cells: Vec<u16>,
}

/// Noted for a box that covers more than one cell, or whose one cell is
/// the last of the most a grid has (its index does not fit below this).
const WORK_OUT_AGAIN: u16 = u16::MAX;

/// Kernel: the corners and extents of the boxes whose index is a multiple
/// of `stride`. Reads only those boxes, whole (a few hundred: less than a
/// parallel step's hand-off costs).
pub fn corner_sample<B: BoxSource + ?Sized>(boxes: &B, stride: usize) -> Vec<SampledBox> {
    (0..boxes.len())
        .step_by(stride.max(1))
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

/// Kernel: the boxes in `range` counted under every cell they cover, into
/// the reused `out`. Each box's cell is noted, so that the place pass need
/// not work it out again; a box covering several cells is noted as
/// [`WORK_OUT_AGAIN`] and its cells are worked out again.
pub fn count_by_cell<B: BoxSource + ?Sized>(
    boxes: &B,
    range: Range<usize>,
    grid: &Grid,
    mut out: ChunkCount,
) -> ChunkCount {
    let ChunkCount {
        range: counted,
        per_cell,
        cells,
    } = &mut out;
    per_cell.clear();
    per_cell.resize(grid.cell_count(), 0);
    cells.clear();
    boxes.for_each_in(range.clone(), |_, aabb| {
        let mut count = 0;
        let mut only = 0;
        grid.for_each_cell(&aabb, |cell| {
            per_cell[cell as usize] += 1;
            count += 1;
            only = cell;
        });
        let noted = u16::try_from(only).unwrap_or(WORK_OUT_AGAIN);
        cells.push(if count == 1 { noted } else { WORK_OUT_AGAIN });
    });
    *counted = range;
    out
}

/// Where each cell's boxes start in the filing, from the chunks' counts
/// (`starts[c]..starts[c + 1]` for cell `c`), into the reused `starts`.
/// Returns the boxes filed (a box once per cell it covers).
pub fn cell_starts(counts: &[ChunkCount], cell_count: usize, starts: &mut Vec<u32>) -> usize {
    starts.clear();
    starts.reserve(cell_count + 1);
    let mut at = 0u32;
    starts.push(at);
    for cell in 0..cell_count {
        at += counts.iter().map(|chunk| chunk.per_cell[cell]).sum::<u32>();
        starts.push(at);
    }
    at as usize
}

/// One chunk's share of the filing, ready to be placed: the chunk's count
/// and, for every cell, the slots its boxes in that cell go to.
pub struct Placing<'a> {
    count: &'a ChunkCount,
    slots: Vec<std::slice::IterMut<'a, CellBox>>,
}

/// The filing `filed` (as long as [`cell_starts`] says) cut into every
/// chunk's slots: within a cell, the chunks' slots follow one another in
/// chunk order, which is input order.
pub fn placings<'a>(counts: &'a [ChunkCount], filed: &'a mut [CellBox]) -> Vec<Placing<'a>> {
    let cell_count = counts.first().map_or(0, |chunk| chunk.per_cell.len());
    let mut out: Vec<Placing<'a>> = counts
        .iter()
        .map(|count| Placing {
            count,
            slots: Vec::with_capacity(cell_count),
        })
        .collect();
    let mut rest = filed;
    for cell in 0..cell_count {
        for placing in &mut out {
            let (slots, after) = rest.split_at_mut(placing.count.per_cell[cell] as usize);
            placing.slots.push(slots.iter_mut());
            rest = after;
        }
    }
    out
}

/// Kernel: places the boxes of each chunk in `placings` in their slots,
/// in input order: the filing's second pass.
pub fn place_by_cell<B: BoxSource + ?Sized>(boxes: &B, grid: &Grid, placings: &mut [Placing<'_>]) {
    for Placing { count, slots } in placings {
        let mut noted = count.cells.iter();
        boxes.for_each_in(count.range.clone(), |i, aabb| {
            let mut place = |cell: u32| {
                let slot = slots[cell as usize]
                    .next()
                    .expect("the count pass counted a slot for every box in its cell");
                *slot = CellBox { index: i as u32, aabb };
            };
            match noted.next() {
                Some(&cell) if cell != WORK_OUT_AGAIN => place(u32::from(cell)),
                _ => grid.for_each_cell(&aabb, place),
            }
        });
        debug_assert!(
            slots.iter().all(|slot| slot.as_slice().is_empty()),
            "the count pass counted a box the place pass did not place"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::systems::sort::grid::BOXES_PER_CELL;

    /// Files `boxes` cut into the chunks that `cuts` start: the cells'
    /// starts and the filed boxes' indices.
    fn filed(boxes: &[Aabb], grid: &Grid, cuts: &[usize]) -> (Vec<u32>, Vec<u32>) {
        let ends = cuts.iter().skip(1).copied().chain([boxes.len()]);
        let counts: Vec<ChunkCount> = cuts
            .iter()
            .zip(ends)
            .map(|(&start, end)| count_by_cell(boxes, start..end, grid, ChunkCount::default()))
            .collect();
        let mut starts = Vec::new();
        let total = cell_starts(&counts, grid.cell_count(), &mut starts);
        let mut out = vec![CellBox::default(); total];
        place_by_cell(boxes, grid, &mut placings(&counts, &mut out));
        (starts, out.iter().map(|b| b.index).collect())
    }

    #[test]
    fn boxes_are_filed_by_cell_in_input_order_however_they_are_cut() {
        let grid = Grid::fit(Vec2::ZERO, Vec2::splat(4.0), BOXES_PER_CELL * 16);
        let boxes = [
            Aabb::new(Vec3::new(0.5, 3.5, 3.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 0.5, 0.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 2.0, 0.5), Vec3::new(0.1, 1.0, 0.1)),
            Aabb::new(Vec3::new(0.0, 3.2, 3.6), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 0.6, 0.4), Vec3::splat(0.1)),
        ];
        for cuts in [&[0][..], &[0, 1], &[0, 2, 3], &[0, 1, 2, 3, 4]] {
            let (starts, indices) = filed(&boxes, &grid, cuts);
            let in_cell = |cell: usize| &indices[starts[cell] as usize..starts[cell + 1] as usize];
            assert_eq!(in_cell(15), [0, 3], "cuts {cuts:?}");
            assert_eq!(in_cell(0), [1, 4], "cuts {cuts:?}");
            // The tall box covers three cells on y.
            assert_eq!((in_cell(4), in_cell(8), in_cell(12)), (&[2][..], &[2][..], &[2][..]));
            assert_eq!(indices.len(), 7);
        }
    }

    #[test]
    fn boxes_in_the_last_cells_of_the_finest_grid_are_filed_there() {
        // 256 × 256 cells, the most a grid has: the last cell's index does
        // not fit in a noted cell, and is worked out again.
        let grid = Grid::fit(Vec2::ZERO, Vec2::splat(256.0), BOXES_PER_CELL * 65_536);
        assert_eq!(grid.cell_count(), 65_536);
        let boxes = [
            Aabb::new(Vec3::new(0.0, 255.5, 255.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 255.5, 254.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(0.0, 0.5, 0.5), Vec3::splat(0.1)),
            Aabb::new(Vec3::new(1.0, 255.5, 255.5), Vec3::splat(0.1)),
        ];
        for cuts in [&[0][..], &[0, 1, 3]] {
            let (starts, indices) = filed(&boxes, &grid, cuts);
            let in_cell = |cell: usize| &indices[starts[cell] as usize..starts[cell + 1] as usize];
            assert_eq!(in_cell(65_535), [0, 3], "cuts {cuts:?}");
            assert_eq!(in_cell(65_534), [1], "cuts {cuts:?}");
            assert_eq!(in_cell(0), [2], "cuts {cuts:?}");
        }
    }
}
