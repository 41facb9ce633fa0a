//! The bodies whose paths left the boxes the broad phase knows them by
//! (a bounce that sends a body elsewhere, a fragment the grid never saw),
//! filed so that a changed path finds those it may reach (docs/design.md,
//! "Contacts in time order").
//!
//! The broad phase's grid has cells over y and z only: each is a column
//! through the whole scene along x. Filed by column alone, a dense cascade
//! put thousands of bodies in one column, and every changed path there
//! scanned them all (three fifths of the contacts' time in the contacts
//! issue's fast cloud). So each column is cut along x into slabs a
//! quarter as wide as the grid's finest cells ([`SLABS_PER_CELL`]), and a
//! region is filed by column and slab; one longer than [`MAX_SLABS`]
//! slabs is filed by column alone (its slabs would cost more than they
//! save). What is found does not depend on the filing: the caller keeps
//! each body once and sorts them.

use bevy::platform::collections::{HashMap, HashSet};

use crate::physics::Aabb;

/// Calls its `f` with every cell of the broad phase's grid that a region
/// covers.
pub(super) type Cells<'a> = &'a dyn Fn(&Aabb, &mut dyn FnMut(u32));

/// Slabs along x per grid cell's width: the fast cloud's first 33
/// updates took about 0.85 times as long as filed by column alone, slabs
/// a cell wide half that saving (docs/benchmarks.md, "A cascade without a
/// size floor").
const SLABS_PER_CELL: f64 = 4.0;

/// Most slabs a region is filed in (or searched) one by one; a region
/// over more is filed, and searched, by its columns alone.
const MAX_SLABS: i64 = 16;

/// Marks a key that names a column's long regions.
const LONG: u64 = 1 << 63;

/// Marks a key that names everything filed in a column.
const EVERY: u64 = 1 << 62;

/// The key of slab `s` (within the i32 range) of `column`.
fn slab_key(column: u64, s: i64) -> u64 {
    column << 32 | u64::from(s as i32 as u32)
}

/// Bodies filed by grid column and slab along x.
#[derive(Debug, Default)]
pub(super) struct Escaped {
    /// Slabs per unit length along x (0: one slab).
    slab_scale: f64,
    /// By column and slab (`column << 32 | slab`), a region over at most
    /// [`MAX_SLABS`] slabs; by `LONG | column`, one over more; by
    /// `EVERY | column`, every region in the column (for a long search).
    lists: HashMap<u64, Vec<u32>>,
    /// Each (key, body) filed, so that a body whose paths cover a place
    /// more than once is filed there once.
    filed: HashSet<(u64, u32)>,
}

impl Escaped {
    /// An empty filing whose slabs are [`SLABS_PER_CELL`] to a grid cell
    /// of `cells_per_unit` cells per unit length (0: one slab).
    pub fn new(cells_per_unit: f32) -> Self {
        Self {
            slab_scale: SLABS_PER_CELL * f64::from(cells_per_unit),
            ..Self::default()
        }
    }

    /// The slabs `region` spans, if it spans at most [`MAX_SLABS`].
    fn slabs(&self, region: &Aabb) -> Option<(i64, i64)> {
        let slab = |x: f32| {
            let s = (f64::from(x) * self.slab_scale).floor();
            s.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i64
        };
        let (lo, hi) = (slab(region.min.x), slab(region.max.x));
        (hi - lo < MAX_SLABS).then_some((lo, hi))
    }

    /// Files body `i`, whose path sweeps `region`.
    pub fn file(&mut self, i: u32, region: &Aabb, cells: Cells<'_>) {
        let slabs = self.slabs(region);
        let Self { lists, filed, .. } = self;
        let mut put = |key: u64| {
            if filed.insert((key, i)) {
                lists.entry(key).or_default().push(i);
            }
        };
        cells(region, &mut |cell| {
            let column = u64::from(cell);
            match slabs {
                Some((lo, hi)) => (lo..=hi).for_each(|s| put(slab_key(column, s))),
                None => put(LONG | column),
            }
            put(EVERY | column);
        });
    }

    /// Calls `f` with every body filed where `region` lies (a body may
    /// come more than once, and some whose regions do not overlap it).
    pub fn near(&self, region: &Aabb, cells: Cells<'_>, f: &mut impl FnMut(u32)) {
        let slabs = self.slabs(region);
        let mut list = |key: u64| {
            for &m in self.lists.get(&key).map_or(&[][..], Vec::as_slice) {
                f(m);
            }
        };
        cells(region, &mut |cell| {
            let column = u64::from(cell);
            match slabs {
                Some((lo, hi)) => {
                    (lo..=hi).for_each(|s| list(slab_key(column, s)));
                    list(LONG | column);
                }
                None => list(EVERY | column),
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use bevy::prelude::*;

    use super::*;

    /// A grid of columns 10 wide on y (z ignored).
    fn columns(region: &Aabb, f: &mut dyn FnMut(u32)) {
        let column = |y: f32| (y / 10.0).floor().clamp(0.0, 9.0) as u32;
        (column(region.min.y)..=column(region.max.y)).for_each(f);
    }

    /// Its cells per unit length.
    const COLUMNS: f32 = 0.1;

    /// A cube of half edge `half` at (`x`, `y`, 0).
    fn cube(x: f32, y: f32, half: f32) -> Aabb {
        Aabb {
            min: Vec3::new(x - half, y - half, -half),
            max: Vec3::new(x + half, y + half, half),
        }
    }

    /// The bodies a search of `region` brings, each once, in order.
    fn found(escaped: &Escaped, region: &Aabb) -> Vec<u32> {
        let mut all = Vec::new();
        escaped.near(region, &columns, &mut |m| all.push(m));
        all.sort_unstable();
        all.dedup();
        all
    }

    /// Slabs cut a column: what lies far along it is not brought.
    #[test]
    fn a_search_finds_what_overlaps_it_and_not_what_lies_far_along_the_column() {
        let mut escaped = Escaped::new(COLUMNS);
        escaped.file(0, &cube(5.0, 5.0, 1.0), &columns);
        escaped.file(1, &cube(500.0, 5.0, 1.0), &columns);
        escaped.file(2, &cube(5.0, 55.0, 1.0), &columns);
        // Across a slab's edge (every 2.5 on x) and a column's (every 10 on y).
        let near = found(&escaped, &cube(6.5, 5.0, 1.0));
        assert!(
            near.contains(&0) && !near.contains(&1) && !near.contains(&2),
            "{near:?}"
        );
        assert_eq!(found(&escaped, &cube(499.0, 8.0, 1.0)), [1]);
        assert!(found(&escaped, &cube(5.0, 50.5, 1.0)).contains(&2));
    }

    /// Boxes of every size filed along a column, searched by boxes of every
    /// size at every place: each search finds every box it overlaps.
    #[test]
    fn every_overlapping_box_is_found_whatever_the_sizes() {
        let mut escaped = Escaped::new(COLUMNS);
        let filed: Vec<Aabb> = (0..60)
            .map(|k| cube(k as f32 * 3.3 - 50.0, 5.0, 0.2 + (k % 7) as f32 * 4.0))
            .collect();
        for (i, region) in filed.iter().enumerate() {
            escaped.file(i as u32, region, &columns);
        }
        for k in 0..400 {
            let search = cube(k as f32 * 0.61 - 60.0, 5.0, 0.1 + (k % 11) as f32 * 3.7);
            let found = found(&escaped, &search);
            for (i, region) in filed.iter().enumerate() {
                assert!(
                    !region.overlaps(&search) || found.contains(&(i as u32)),
                    "{i} {region:?} {search:?}"
                );
            }
        }
    }

    /// A region over more than [`MAX_SLABS`] slabs is filed by column.
    #[test]
    fn long_regions_are_found_by_short_searches_and_long_searches_find_everything_in_their_columns() {
        let mut escaped = Escaped::new(COLUMNS);
        // A path along x through the whole column, and a cube in it.
        escaped.file(
            0,
            &Aabb {
                min: Vec3::new(-1000.0, 4.0, -1.0),
                max: Vec3::new(1000.0, 6.0, 1.0),
            },
            &columns,
        );
        escaped.file(1, &cube(300.0, 5.0, 1.0), &columns);
        assert_eq!(found(&escaped, &cube(-700.0, 5.0, 1.0)), [0]);
        assert_eq!(found(&escaped, &cube(300.0, 5.0, 1.0)), [0, 1]);
        let long = Aabb {
            min: Vec3::new(0.0, 5.0, -1.0),
            max: Vec3::new(900.0, 5.0, 1.0),
        };
        assert_eq!(found(&escaped, &long), [0, 1]);
        // A body filed twice over the same place is listed there once.
        escaped.file(1, &cube(300.5, 5.0, 1.0), &columns);
        let mut times = 0;
        escaped.near(&cube(300.2, 5.0, 0.1), &columns, &mut |m| times += usize::from(m == 1));
        assert_eq!(times, 1);
    }

    /// Slabs past the i32 range are clamped to its ends, not wrapped
    /// around to slabs near 0: a body 2³² slabs out is not brought to a
    /// search at the origin, and regions at both ends and across the whole
    /// range are found.
    #[test]
    fn far_regions_are_clamped_not_wrapped() {
        let mut escaped = Escaped::new(COLUMNS);
        // x · 0.4 slabs a unit = 2³² exactly: wrapped, slab 0.
        escaped.file(0, &cube(1.073_741_8e10, 5.0, 1.0), &columns);
        escaped.file(1, &cube(-3.0e38, 5.0, 1.0e37), &columns);
        assert_eq!(found(&escaped, &cube(1.0, 5.0, 0.1)), Vec::<u32>::new());
        assert_eq!(found(&escaped, &cube(1.073_741_8e10, 5.0, 1.0)), [0]);
        assert_eq!(found(&escaped, &cube(-3.0e38, 5.0, 1.0)), [1]);
        let everything = Aabb {
            min: Vec3::new(-3.0e38, 4.0, -1.0),
            max: Vec3::new(3.0e38, 6.0, 1.0),
        };
        assert_eq!(found(&escaped, &everything), [0, 1]);
    }
}
