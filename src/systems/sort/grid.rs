//! The grid over y and z that the sweep runs in, one cell at a time.

use bevy::prelude::*;

use crate::maths::{from_order_key, order_key};
use crate::physics::Aabb;

/// Boxes per grid cell the grid aims for.
pub const BOXES_PER_CELL: usize = 64;

/// Most cells per axis of the grid.
const MAX_CELLS_PER_AXIS: usize = 256;

/// Corners sampled to place the grid.
pub const GRID_SAMPLES: usize = 1024;

/// Share of the sampled corners left outside the grid at each end of an
/// axis: far-flung bodies (escaped fragments) are clamped into the edge
/// cells instead of stretching the grid over empty space.
const OUTSIDE_SHARE: f64 = 0.005;

/// Most cells the sampled boxes may cover on average: a grid finer than
/// its boxes (bodies piled near one point, or boxes far larger than their
/// spacing) would file each box in up to 256² cells, so it is made coarser
/// until they fit.
const MAX_CELLS_PER_BOX: f64 = 4.0;

/// A box of the even sample the grid is fitted to: its lower y–z corner
/// and its extent on y and z.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SampledBox {
    /// The lower corner (y, z).
    pub corner: Vec2,
    /// The extent (y, z).
    pub extent: Vec2,
}

/// A grid over y and z, fitted to the lower corners of the boxes.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    lo: Vec2,
    /// Cells per unit length on y and z (0 if all boxes share a coordinate).
    scale: Vec2,
    cells_per_axis: u32,
}

/// The span of the bulk of the corners on one axis: from the sample's
/// [`OUTSIDE_SHARE`] quantile to its `1 − OUTSIDE_SHARE` quantile (within
/// the true bounds, as the sample is drawn from the corners). `None` for a
/// sample too small to leave any corner outside (then it is every box) or
/// one with non-finite corners: the true bounds are the span.
fn bulk_span(values: &mut [f32]) -> Option<(f32, f32)> {
    let outside = (values.len() as f64 * OUTSIDE_SHARE) as usize;
    if outside == 0 {
        return None;
    }
    // Two selections, not a sort: linear in the sample.
    let last = values.len() - 1;
    let q_hi = *values.select_nth_unstable_by(last - outside, f32::total_cmp).1;
    let q_lo = *values[..last - outside]
        .select_nth_unstable_by(outside, f32::total_cmp)
        .1;
    (q_lo.is_finite() && q_hi.is_finite() && q_lo <= q_hi).then_some((q_lo, q_hi))
}

impl Grid {
    /// A grid for `count` boxes, fitted to the bulk of `sample` (boxes
    /// drawn evenly from them): boxes beyond it share the edge cells; and
    /// no finer than the sampled boxes cover [`MAX_CELLS_PER_BOX`] cells on
    /// average. `bounds` gives the true bounds of all lower y–z corners,
    /// asked for only where the sample cannot place the grid alone (a few
    /// boxes, all of them sampled; non-finite corners).
    pub fn fit_to_bulk(sample: &[SampledBox], count: usize, bounds: impl FnOnce() -> (Vec2, Vec2)) -> Self {
        let mut ys: Vec<f32> = sample.iter().map(|b| b.corner.x).collect();
        let mut zs: Vec<f32> = sample.iter().map(|b| b.corner.y).collect();
        let (lo, hi) = match (bulk_span(&mut ys), bulk_span(&mut zs)) {
            (Some((y_lo, y_hi)), Some((z_lo, z_hi))) => (Vec2::new(y_lo, z_lo), Vec2::new(y_hi, z_hi)),
            (y, z) => {
                let (lo, hi) = bounds();
                let (y_lo, y_hi) = y.unwrap_or((lo.x, hi.x));
                let (z_lo, z_hi) = z.unwrap_or((lo.y, hi.y));
                (Vec2::new(y_lo, z_lo), Vec2::new(y_hi, z_hi))
            }
        };
        let mut grid = Self::fit(lo, hi, count);
        while grid.cells_per_axis > 1 && grid.mean_cells(sample) > MAX_CELLS_PER_BOX {
            grid = Self::with_cells(lo, hi, grid.cells_per_axis / 2);
        }
        grid
    }

    /// The mean number of cells the sampled boxes cover.
    fn mean_cells(&self, sample: &[SampledBox]) -> f64 {
        let covered = |b: &SampledBox| {
            let (y0, y1) = (
                self.coordinate(b.corner.x, self.lo.x, self.scale.x),
                self.coordinate(b.corner.x + b.extent.x, self.lo.x, self.scale.x),
            );
            let (z0, z1) = (
                self.coordinate(b.corner.y, self.lo.y, self.scale.y),
                self.coordinate(b.corner.y + b.extent.y, self.lo.y, self.scale.y),
            );
            f64::from(y1 - y0 + 1) * f64::from(z1 - z0 + 1)
        };
        sample.iter().map(covered).sum::<f64>() / sample.len().max(1) as f64
    }

    /// A grid for `count` boxes whose lower y–z corners lie in `lo..=hi`.
    pub fn fit(lo: Vec2, hi: Vec2, count: usize) -> Self {
        let n = ((count / BOXES_PER_CELL) as f64)
            .sqrt()
            .clamp(1.0, MAX_CELLS_PER_AXIS as f64) as u32;
        Self::with_cells(lo, hi, n)
    }

    /// A grid of `n` × `n` cells over `lo..=hi`.
    fn with_cells(lo: Vec2, hi: Vec2, n: u32) -> Self {
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

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        (self.cells_per_axis * self.cells_per_axis) as usize
    }

    /// The cells the box's y–z extent covers: `[y0, y1, z0, z1]`, the
    /// first and last coordinate on each axis.
    #[inline]
    pub fn span(&self, b: &Aabb) -> [u32; 4] {
        [
            self.coordinate(b.min.y, self.lo.x, self.scale.x),
            self.coordinate(b.max.y, self.lo.x, self.scale.x),
            self.coordinate(b.min.z, self.lo.y, self.scale.y),
            self.coordinate(b.max.z, self.lo.y, self.scale.y),
        ]
    }

    /// Calls `f` with every cell the box's y–z extent covers.
    #[inline]
    pub fn for_each_cell(&self, b: &Aabb, mut f: impl FnMut(u32)) {
        let [y0, y1, z0, z1] = self.span(b);
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

    /// Cells per unit length on the finer of y and z (0 where all boxes
    /// share both coordinates).
    pub fn cells_per_unit(&self) -> f32 {
        self.scale.x.max(self.scale.y)
    }

    /// The one cell that reports the overlapping pair `a`, `b`.
    #[inline]
    pub fn owner(&self, a: &Aabb, b: &Aabb) -> u32 {
        self.cell(a.min.y.max(b.min.y), a.min.z.max(b.min.z))
    }

    /// Where each cell begins on y and on z, exactly: see [`CellBounds`].
    pub fn bounds(&self) -> CellBounds {
        let axis = |lo: f32, scale: f32| {
            (0..=self.cells_per_axis)
                .map(|k| self.first_at_least(k, lo, scale))
                .collect()
        };
        CellBounds {
            y: axis(self.lo.x, self.scale.x),
            z: axis(self.lo.y, self.scale.y),
            cells_per_axis: self.cells_per_axis,
        }
    }

    /// The least finite value whose coordinate on the axis is at least `k`
    /// (−∞ for 0; +∞ where none is): a search over the floats in order, as
    /// the coordinate never falls as the value grows.
    fn first_at_least(&self, k: u32, lo: f32, scale: f32) -> f32 {
        if k == 0 {
            return f32::NEG_INFINITY;
        }
        let reaches = |key: u32| self.coordinate(from_order_key(key), lo, scale) >= k;
        let (mut below, mut at) = (order_key(f32::MIN), order_key(f32::MAX));
        if k >= self.cells_per_axis || !reaches(at) {
            return f32::INFINITY;
        }
        if reaches(below) {
            return f32::MIN;
        }
        // `below` never reaches k, `at` does.
        while at - below > 1 {
            let mid = below + (at - below) / 2;
            if reaches(mid) {
                at = mid;
            } else {
                below = mid;
            }
        }
        from_order_key(at)
    }
}

/// A grid's cells as ranges of values: cell `(y, z)` holds exactly the
/// values `y[k] <= v < y[k + 1]` on y (its coordinate is `k`), likewise
/// on z. So whether a box covers one given cell only is four comparisons
/// instead of four coordinates worked out; a NaN or infinite corner never
/// passes them, and such a box is judged by its coordinates
/// ([`Grid::span`]).
#[derive(Clone, Debug, Default)]
pub struct CellBounds {
    y: Vec<f32>,
    z: Vec<f32>,
    cells_per_axis: u32,
}

impl CellBounds {
    /// The values `cell` holds.
    #[inline]
    pub fn cell(&self, cell: u32) -> CellRange {
        let (y, z) = (
            (cell / self.cells_per_axis) as usize,
            (cell % self.cells_per_axis) as usize,
        );
        CellRange {
            lo: Vec2::new(self.y[y], self.z[z]),
            hi: Vec2::new(self.y[y + 1], self.z[z + 1]),
        }
    }
}

/// The y–z values one cell holds: `lo <= v < hi` on each axis.
#[derive(Clone, Copy, Debug)]
pub struct CellRange {
    lo: Vec2,
    hi: Vec2,
}

impl CellRange {
    /// Whether the box's y–z extent lies in this cell alone.
    #[inline]
    pub fn holds(&self, b: &Aabb) -> bool {
        self.lo.x <= b.min.y && b.max.y < self.hi.x && self.lo.y <= b.min.z && b.max.z < self.hi.y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_bounds_agree_with_the_cells_a_box_is_filed_in() {
        let mut rng = crate::maths::Rng::new(5);
        // A grid with an odd origin and scale, one flat on z, one of 256².
        let grids = [
            Grid::fit(Vec2::new(-3.7, 11.3), Vec2::new(401.9, 733.1), BOXES_PER_CELL * 300),
            Grid::fit(Vec2::new(0.0, 5.0), Vec2::new(10.0, 5.0), BOXES_PER_CELL * 16),
            Grid::fit(Vec2::ZERO, Vec2::splat(256.0), BOXES_PER_CELL * 65_536),
        ];
        for grid in grids {
            let bounds = grid.bounds();
            let mut boxes: Vec<Aabb> = (0..4_000)
                .map(|_| {
                    let at = Vec3::new(0.0, rng.range(-50.0, 800.0) as f32, rng.range(-50.0, 800.0) as f32);
                    Aabb::new(at, Vec3::splat(rng.range(0.0, 3.0) as f32))
                })
                .collect();
            // Corners right on the cells' edges, and beyond any.
            for k in 0..=grid.cells_per_axis as usize {
                for v in [bounds.y[k], bounds.z[k]].into_iter().filter(|v| v.is_finite()) {
                    for w in [v.next_down(), v, v.next_up()] {
                        boxes.push(Aabb {
                            min: Vec3::new(0.0, w, w),
                            max: Vec3::new(0.0, w, w),
                        });
                    }
                }
            }
            for v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, f32::MIN] {
                boxes.push(Aabb {
                    min: Vec3::new(0.0, v, 1.0),
                    max: Vec3::new(0.0, v, 1.0),
                });
            }
            for b in &boxes {
                let mut cells = Vec::new();
                grid.for_each_cell(b, |c| cells.push(c));
                for cell in 0..grid.cell_count() as u32 {
                    let only = cells == [cell];
                    // Never in a cell it is not only in; in its one cell
                    // whenever its corners are finite.
                    if bounds.cell(cell).holds(b) {
                        assert!(only, "{b:?} in cell {cell} of {cells:?}");
                    } else if only {
                        let finite = [b.min.y, b.min.z, b.max.y, b.max.z].iter().all(|v| v.is_finite());
                        assert!(!finite, "{b:?} not found in its cell {cell}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_box_spanning_cells_is_filed_in_each_and_owned_once() {
        // 64 · 16 boxes → 4 × 4 cells over [0, 4]².
        let grid = Grid::fit(Vec2::ZERO, Vec2::splat(4.0), BOXES_PER_CELL * 16);
        assert_eq!(grid.cell_count(), 16);
        let wide = Aabb::new(Vec3::new(0.0, 2.0, 0.5), Vec3::new(1.0, 1.0, 0.25));
        let mut cells = Vec::new();
        grid.for_each_cell(&wide, |c| cells.push(c));
        assert_eq!(cells, [4, 8, 12]);
        let small = Aabb::new(Vec3::new(0.0, 2.5, 0.5), Vec3::splat(0.1));
        assert_eq!(grid.owner(&wide, &small), 8);
        assert_eq!(grid.owner(&small, &wide), 8);
    }

    #[test]
    fn coordinates_outside_the_grid_clamp_to_its_edge() {
        let grid = Grid::fit(Vec2::ZERO, Vec2::splat(4.0), BOXES_PER_CELL * 16);
        let far = Aabb::new(Vec3::new(0.0, 1e9, -1e9), Vec3::ONE);
        let mut cells = Vec::new();
        grid.for_each_cell(&far, |c| cells.push(c));
        assert_eq!(cells, [12]);
    }

    #[test]
    fn a_few_far_corners_do_not_stretch_the_grid() {
        // 10 000 corners in [0, 100]², 10 of them a million away.
        let mut rng = crate::maths::Rng::new(3);
        let mut corners: Vec<Vec2> = (0..10_000)
            .map(|_| Vec2::new(rng.range(0.0, 100.0) as f32, rng.range(0.0, 100.0) as f32))
            .collect();
        for k in 0..10 {
            corners[k * 997] = Vec2::new(1e6, -1e6 * k as f32);
        }
        let (lo, hi) = corners
            .iter()
            .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(l, h), c| (l.min(*c), h.max(*c)));
        let stride = corners.len() / GRID_SAMPLES + 1;
        let sample: Vec<SampledBox> = corners
            .iter()
            .step_by(stride)
            .map(|&corner| SampledBox {
                corner,
                extent: Vec2::splat(0.1),
            })
            .collect();
        let grid = Grid::fit_to_bulk(&sample, corners.len(), || (lo, hi));
        let mut per_cell = vec![0usize; grid.cell_count()];
        for c in &corners {
            per_cell[grid.cell(c.x, c.y) as usize] += 1;
        }
        let fullest = per_cell.iter().max().copied().unwrap_or(0);
        assert!(
            fullest <= 3 * BOXES_PER_CELL,
            "{fullest} corners in one cell of {} cells",
            grid.cell_count()
        );
        // Without the sample's help, one cell would hold almost all.
        let stretched = Grid::fit(lo, hi, corners.len());
        let mut per_cell = vec![0usize; stretched.cell_count()];
        for c in &corners {
            per_cell[stretched.cell(c.x, c.y) as usize] += 1;
        }
        assert!(per_cell.iter().max().copied().unwrap_or(0) > 9000);
    }

    /// The sample places the grid alone (no pass over every box for their
    /// bounds) except where it is too small to leave a corner outside,
    /// which is where it holds every box; then the bounds are the sample's.
    #[test]
    fn the_true_bounds_are_read_only_for_a_few_boxes() {
        let mut rng = crate::maths::Rng::new(9);
        for count in [1usize, 50, 199, 200, 10_000, 1_000_000] {
            let stride = count / GRID_SAMPLES + 1;
            let sample: Vec<SampledBox> = (0..count.div_ceil(stride))
                .map(|_| SampledBox {
                    corner: Vec2::new(rng.range(0.0, 10.0) as f32, rng.range(-5.0, 5.0) as f32),
                    extent: Vec2::splat(0.01),
                })
                .collect();
            let (lo, hi) = sample.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(l, h), b| {
                (l.min(b.corner), h.max(b.corner))
            });
            let mut asked = false;
            Grid::fit_to_bulk(&sample, count, || {
                asked = true;
                (lo, hi)
            });
            assert_eq!(asked, count < 200, "{count} boxes");
        }
    }

    /// Boxes piled near one point, or far larger than their spacing, would
    /// each cover up to 256² cells of a grid fitted to their corners alone.
    #[test]
    fn a_grid_is_no_finer_than_its_boxes() {
        let mut rng = crate::maths::Rng::new(5);
        let sample: Vec<SampledBox> = (0..4096)
            .map(|_| SampledBox {
                corner: Vec2::new(rng.range(0.0, 0.01) as f32, rng.range(0.0, 0.01) as f32),
                extent: Vec2::splat(2.0),
            })
            .collect();
        let (lo, hi) = (Vec2::ZERO, Vec2::splat(0.01));
        let fine = Grid::fit(lo, hi, 1_000_000);
        assert!(
            fine.mean_cells(&sample) > 1000.0,
            "the corners alone ask for a fine grid"
        );
        let grid = Grid::fit_to_bulk(&sample, 1_000_000, || (lo, hi));
        assert!(
            grid.mean_cells(&sample) <= MAX_CELLS_PER_BOX,
            "{}",
            grid.mean_cells(&sample)
        );
        assert!(grid.cell_count() <= 16, "{} cells", grid.cell_count());
    }
}
