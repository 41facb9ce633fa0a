//! What every file of gravity works with: a source as the sums see it,
//! and the one formula of gravity between two bodies, summed directly
//! (docs/design.md, "Gravity").

use bevy::math::DVec3;
use bevy::prelude::*;

use crate::components::BodyId;

/// A body that attracts others, as the kernel sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GravitySource {
    /// The source's id (a body does not pull itself).
    pub id: BodyId,
    /// Where it is, in f64.
    pub position: DVec3,
    /// `G·m`.
    pub gm: f64,
}

/// Acceleration of the body `id` at `position` due to `sources`.
/// `softening2` is `ε²`. Non-finite input gives non-finite output; the
/// caller keeps positions finite.
#[inline]
pub fn acceleration_at(id: BodyId, position: Vec3, sources: &[GravitySource], softening2: f64) -> Vec3 {
    let mut a = DVec3::ZERO;
    add_pulls(&mut a, id, position.as_dvec3(), sources, softening2);
    a.as_vec3()
}

/// The factor `G·m / (r² + ε²)^{3/2}` by which a source at squared
/// distance `r2` pulls along the distance vector: the one formula of
/// gravity between two bodies.
#[inline(always)]
pub fn pull_factor(r2: f64, gm: f64, softening2: f64) -> f64 {
    let r2 = r2 + softening2;
    gm / (r2 * r2.sqrt())
}

/// Adds the pull of each of `sources` in order to `a`, for the body `id`
/// at `p`: all but itself and sources at its very position.
#[inline]
pub fn add_pulls(a: &mut DVec3, id: BodyId, p: DVec3, sources: &[GravitySource], softening2: f64) {
    for s in sources {
        let d = s.position - p;
        let r2 = d.length_squared();
        if s.id == id || r2 == 0.0 {
            continue;
        }
        *a += d * pull_factor(r2, s.gm, softening2);
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A source `id` at `p` with `G·m` = `gm`.
    pub(in crate::systems::gravity) fn source(id: u64, p: [f64; 3], gm: f64) -> GravitySource {
        GravitySource {
            id: BodyId(id),
            position: DVec3::from_array(p),
            gm,
        }
    }

    #[test]
    fn inverse_square_towards_the_source() {
        let sources = [source(0, [0.0, 0.0, 0.0], 8.0)];
        let a = acceleration_at(BodyId(1), Vec3::new(2.0, 0.0, 0.0), &sources, 0.0);
        assert_eq!(a, Vec3::new(-2.0, 0.0, 0.0)); // 8 / 2² towards the origin
    }

    #[test]
    fn skips_itself_and_coincident_sources() {
        let sources = [source(0, [0.0, 0.0, 0.0], 1.0), source(1, [3.0, 0.0, 0.0], 1.0)];
        assert_eq!(
            acceleration_at(BodyId(1), Vec3::new(3.0, 0.0, 0.0), &sources[1..], 0.0),
            Vec3::ZERO
        );
        assert_eq!(acceleration_at(BodyId(7), Vec3::ZERO, &sources[..1], 0.0), Vec3::ZERO);
    }

    #[test]
    fn softening_bounds_the_pull_at_close_range() {
        let sources = [source(0, [0.0, 0.0, 0.0], 1.0)];
        let close = Vec3::new(1e-3, 0.0, 0.0);
        let hard = acceleration_at(BodyId(1), close, &sources, 0.0).length();
        let soft = acceleration_at(BodyId(1), close, &sources, 1.0).length();
        assert!(hard > 1e5);
        // |a| = r / (r² + ε²)^{3/2} ≈ r for ε = 1.
        assert!((soft - 1e-3).abs() < 1e-6, "softened pull {soft}");
    }
}
