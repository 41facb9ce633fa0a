//! Axis-aligned boxes.

use bevy::prelude::*;

/// An axis-aligned box by its corners, in length units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    /// The lower corner.
    pub min: Vec3,
    /// The upper corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box of a body at `center` with `half_extents`.
    pub fn new(center: Vec3, half_extents: Vec3) -> Self {
        Self {
            min: center - half_extents,
            max: center + half_extents,
        }
    }

    /// Overlap on y and z, bounds inclusive.
    #[inline]
    pub fn overlaps_yz(&self, other: &Self) -> bool {
        self.min.y <= other.max.y && other.min.y <= self.max.y && self.min.z <= other.max.z && other.min.z <= self.max.z
    }

    /// Overlap on all axes, bounds inclusive (touching counts).
    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.x <= other.max.x && other.min.x <= self.max.x && self.overlaps_yz(other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_boxes_overlap_and_apart_ones_do_not() {
        let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert!(a.overlaps(&Aabb::new(Vec3::new(2.0, 0.0, 0.0), Vec3::ONE)));
        assert!(!a.overlaps(&Aabb::new(Vec3::new(2.001, 0.0, 0.0), Vec3::ONE)));
        assert!(!a.overlaps(&Aabb::new(Vec3::new(0.0, 0.0, -2.5), Vec3::ONE)));
    }
}
