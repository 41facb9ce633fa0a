//! Where the broad phase reads its boxes: a plain slice, or the bodies'
//! table columns in place (so a million bodies need no copy of their boxes),
//! each body's box where the update ends or swept along its path.

use std::ops::Range;

use bevy::prelude::*;

use crate::components::{BodyId, HalfExtents, Position, PreviousPosition};
use crate::physics::Aabb;

/// A sequence of boxes the broad phase can read in order.
pub trait BoxSource: Sync {
    /// Number of boxes.
    fn len(&self) -> usize;

    /// Calls `f` with the index and box of every box in `range`, in order.
    fn for_each_in(&self, range: Range<usize>, f: impl FnMut(usize, Aabb));

    /// The box with this index (`index < len()`).
    fn get(&self, index: usize) -> Aabb;

    /// The boxes of `range`, in order, written into `out` (as long as the
    /// range).
    fn copy_into(&self, range: Range<usize>, out: &mut [Aabb]) {
        let first = range.start;
        self.for_each_in(range, |index, aabb| out[index - first] = aabb);
    }

    /// True when there are no boxes.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl BoxSource for [Aabb] {
    fn len(&self) -> usize {
        <[Aabb]>::len(self)
    }

    #[inline]
    fn for_each_in(&self, range: Range<usize>, mut f: impl FnMut(usize, Aabb)) {
        let first = range.start;
        for (k, &aabb) in self[range].iter().enumerate() {
            f(first + k, aabb);
        }
    }

    #[inline]
    fn get(&self, index: usize) -> Aabb {
        self[index]
    }

    fn copy_into(&self, range: Range<usize>, out: &mut [Aabb]) {
        out.copy_from_slice(&self[range]);
    }
}

/// One table's columns the broad phase reads.
pub type TableColumns<'a> = (
    &'a [Entity],
    &'a [BodyId],
    &'a [Position],
    &'a [PreviousPosition],
    &'a [HalfExtents],
);

/// The columns the broad phase reads: entity, id, position, previous
/// position, half extents.
pub type BroadPhaseQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static BodyId,
        &'static Position,
        &'static PreviousPosition,
        &'static HalfExtents,
    ),
>;

/// The box a body swept over the update: the smallest box holding its box
/// at `previous` and at `position` (a body at rest: its box).
#[inline]
pub fn swept_box(previous: Vec3, position: Vec3, half_extents: Vec3) -> Aabb {
    Aabb {
        min: previous.min(position) - half_extents,
        max: previous.max(position) + half_extents,
    }
}

/// The bodies' table columns read as one sequence, table after table:
/// each body's box where the update ends, or (`SWEPT`) swept along its
/// path over the update ([`swept_box`]). A parameter of the type, not a
/// field: a choice made per box in the filing's loops had cost the sort a
/// quarter of its time.
pub struct BodyColumns<'a, const SWEPT: bool> {
    /// Index of each table's first body.
    starts: Vec<usize>,
    tables: Vec<TableColumns<'a>>,
    len: usize,
}

impl<'a, const SWEPT: bool> BodyColumns<'a, SWEPT> {
    /// The tables in the order given.
    pub fn new(tables: impl Iterator<Item = TableColumns<'a>>) -> Self {
        let (mut starts, mut all, mut len) = (Vec::new(), Vec::new(), 0);
        for table in tables {
            starts.push(len);
            len += table.0.len();
            all.push(table);
        }
        Self {
            starts,
            tables: all,
            len,
        }
    }

    /// The table and row of the body with this index.
    #[inline]
    fn locate(&self, index: usize) -> (usize, usize) {
        // Bodies lie in one table or a few (the planet's, a marker's): the
        // tables that start at or before the index, counted without
        // branching, where a search's branches went either way.
        let table = self.starts[1..].iter().map(|&s| usize::from(s <= index)).sum::<usize>();
        (table, index - self.starts[table])
    }

    /// The longest distance a body moved over the update (from its
    /// previous position to its position), and that body's largest edge.
    pub fn longest_travel(&self) -> (f32, f32) {
        let mut longest = (0.0f32, 0.0f32);
        for (_, _, positions, previous, half_extents) in &self.tables {
            for ((p, q), h) in positions.iter().zip(previous.iter()).zip(half_extents.iter()) {
                let distance = p.0.distance(q.0);
                if distance > longest.0 {
                    longest = (distance, 2.0 * h.0.max_element());
                }
            }
        }
        longest
    }

    /// The id and entity of the body with this index.
    pub fn body(&self, index: usize) -> (BodyId, Entity) {
        let (table, row) = self.locate(index);
        (self.tables[table].1[row], self.tables[table].0[row])
    }
}

impl<const SWEPT: bool> BoxSource for BodyColumns<'_, SWEPT> {
    fn len(&self) -> usize {
        self.len
    }

    /// Walks the columns table by table, without locating every index.
    #[inline]
    fn for_each_in(&self, range: Range<usize>, mut f: impl FnMut(usize, Aabb)) {
        for (&start, &(_, _, positions, previous, halves)) in self.starts.iter().zip(&self.tables) {
            let end = start + positions.len();
            let (from, to) = (range.start.max(start), range.end.min(end));
            if from >= to {
                continue;
            }
            let rows = from - start..to - start;
            let (positions, halves) = (&positions[rows.clone()], &halves[rows.clone()]);
            if SWEPT {
                let bodies = positions.iter().zip(&previous[rows]).zip(halves);
                for (k, ((p, q), h)) in bodies.enumerate() {
                    f(from + k, swept_box(q.0, p.0, h.0));
                }
            } else {
                for (k, (p, h)) in positions.iter().zip(halves).enumerate() {
                    f(from + k, Aabb::new(p.0, h.0));
                }
            }
        }
    }

    #[inline]
    fn get(&self, index: usize) -> Aabb {
        let (table, row) = self.locate(index);
        let (_, _, positions, previous, halves) = self.tables[table];
        if SWEPT {
            swept_box(previous[row].0, positions[row].0, halves[row].0)
        } else {
            Aabb::new(positions[row].0, halves[row].0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_of_several_tables_read_as_one_sequence() {
        let entities: Vec<Entity> = (1..=5).map(Entity::from_raw_u32).map(Option::unwrap).collect();
        let ids: Vec<BodyId> = (0..5).map(BodyId).collect();
        let positions: Vec<Position> = (0..5).map(|i| Position(Vec3::splat(i as f32))).collect();
        // Each body came from 3 below on x.
        let previous: Vec<PreviousPosition> = positions
            .iter()
            .map(|p| PreviousPosition(p.0 - Vec3::X * 3.0))
            .collect();
        let halves = [HalfExtents(Vec3::ONE); 5];
        let tables = || {
            [
                (&entities[..2], &ids[..2], &positions[..2], &previous[..2], &halves[..2]),
                (&entities[2..], &ids[2..], &positions[2..], &previous[2..], &halves[2..]),
            ]
            .into_iter()
        };
        let columns = BodyColumns::<false>::new(tables());
        assert_eq!(columns.len(), 5);
        let mut seen = Vec::new();
        columns.for_each_in(1..4, |i, b| seen.push((i, b.min.x)));
        assert_eq!(seen, [(1, 0.0), (2, 1.0), (3, 2.0)]);
        assert_eq!(columns.get(3).min.x, 2.0);
        assert_eq!(columns.body(3), (BodyId(3), entities[3]));
        // Swept: from the previous box's lower corner to the box's upper one.
        let swept = BodyColumns::<true>::new(tables());
        let mut seen = Vec::new();
        swept.for_each_in(1..4, |i, b| seen.push((i, b.min.x, b.max.x, b.min.y)));
        assert_eq!(seen, [(1, -3.0, 2.0, 0.0), (2, -2.0, 3.0, 1.0), (3, -1.0, 4.0, 2.0)]);
        let expected = Aabb {
            min: Vec3::new(-1.0, 2.0, 2.0),
            max: Vec3::new(4.0, 4.0, 4.0),
        };
        assert_eq!(swept.get(3), expected);
    }
}
