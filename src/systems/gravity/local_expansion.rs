//! A region's local expansion (docs/design.md, "Gravity"): the pull of
//! sources far from a region of the tree, compared with the region's size,
//! as a Taylor series about the region's center to second order. It is
//! summed once for the region, however many bodies the region has, and
//! each body then evaluates the series at its offset from the center: a
//! handful of operations instead of one term per source.
//!
//! For a source `G·m` at `u` from the center (`r² = |u|² + ε²`) the pull at
//! offset `x` is `a(x) = G·m·(u − x)/(|u − x|² + ε²)^{3/2}`, and
//! `a(x) ≈ A + J·x + ½·K[x, x]` with
//! - `A_i = G·m·u_i/r³`,
//! - `J_ij = G·m·(3·u_i·u_j/r⁵ − δ_ij/r³)`,
//! - `K_ijk = G·m·(15·u_i·u_j·u_k/r⁷ − 3·(δ_ij·u_k + δ_ik·u_j + δ_jk·u_i)/r⁵)`,
//!
//! `J` and `K` symmetric. The terms left out are of order `(|x|/r)³` of
//! the source's pull: along the line to the source they sum to `4·t³ +
//! 5·t⁴ + …` of it, `t = |x|/r`.

use bevy::math::DVec3;

use super::columns::{LANES, lane_total};

/// The symmetric `K`'s components, in this order.
const K: usize = 10;

/// A region's local expansion, `a(x) ≈ A + J·x + ½·K[x, x]` for `x` the
/// offset from the region's center (see the module's documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LocalExpansion {
    /// `A`: the pull at the center.
    a: DVec3,
    /// `J` as xx, yy, zz, xy, xz, yz.
    j: [f64; 6],
    /// `K` as xxx, yyy, zzz, xxy, xxz, xyy, yyz, xzz, yzz, xyz.
    k: [f64; K],
}

/// A local expansion about `center`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Where the series is taken about.
    pub center: DVec3,
    /// The series.
    pub expansion: LocalExpansion,
}

impl Local {
    /// The pull at `p`.
    #[inline]
    pub fn at(&self, p: DVec3) -> DVec3 {
        self.expansion.at(p - self.center)
    }
}

/// The sources of a local expansion as columns: position relative to the
/// region's center (`f64`) and `G·m`, padded to a multiple of [`LANES`]
/// with massless entries.
#[derive(Clone, Debug, Default)]
pub struct LocalSources {
    columns: [Vec<f64>; 4],
    /// Sources pushed (the padding not counted).
    count: usize,
}

/// Padding: a massless source this far from the center adds exactly 0 to
/// every coefficient (no term overflows or divides 0 by 0).
const PADDING: f64 = 1e30;

impl LocalSources {
    /// Forgets the sources, keeping the memory.
    pub fn clear(&mut self) {
        self.columns.iter_mut().for_each(Vec::clear);
        self.count = 0;
    }

    /// Adds a source `gm` at `u` from the center.
    #[inline]
    pub fn push(&mut self, u: DVec3, gm: f64) {
        self.push_entry(u, gm);
        self.count += 1;
    }

    fn push_entry(&mut self, u: DVec3, gm: f64) {
        let [x, y, z, g] = &mut self.columns;
        x.push(u.x);
        y.push(u.y);
        z.push(u.z);
        g.push(gm);
    }

    /// Pads to a multiple of [`LANES`].
    pub fn pad(&mut self) {
        while !self.columns[3].len().is_multiple_of(LANES) {
            self.push_entry(DVec3::splat(PADDING), 0.0);
        }
    }

    /// Number of sources, the padding not counted.
    #[cfg(test)]
    pub fn count(&self) -> usize {
        self.count
    }

    /// Number of sources, padding included.
    pub fn len(&self) -> usize {
        self.columns[3].len()
    }

    /// True when there is no source.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The coefficients one source adds: `A` (3), `J` (6), `K` (10).
#[inline(always)]
fn source_terms(u: [f64; 3], gm: f64, softening2: f64) -> [f64; 19] {
    let [x, y, z] = u;
    let r2 = x * x + y * y + z * z + softening2;
    let inv2 = 1.0 / r2;
    // g = G·m/r³, h = 3·G·m/r⁵, m = 15·G·m/r⁷.
    let g = gm * inv2 * inv2.sqrt();
    let h = 3.0 * g * inv2;
    let m = 5.0 * h * inv2;
    let (xx, yy, zz) = (x * x, y * y, z * z);
    [
        g * x,
        g * y,
        g * z,
        h * xx - g,
        h * yy - g,
        h * zz - g,
        h * (x * y),
        h * (x * z),
        h * (y * z),
        m * (xx * x) - 3.0 * h * x,
        m * (yy * y) - 3.0 * h * y,
        m * (zz * z) - 3.0 * h * z,
        m * (xx * y) - h * y,
        m * (xx * z) - h * z,
        m * (x * yy) - h * x,
        m * (yy * z) - h * z,
        m * (x * zz) - h * x,
        m * (y * zz) - h * y,
        m * (x * y * z),
    ]
}

impl LocalExpansion {
    /// Kernel: the expansion of `sources` (padded) about the center (`ε²`
    /// = `softening2`), summed in [`LANES`] lanes, source `i` in lane
    /// `i % LANES`, the lanes added in one fixed order.
    pub fn of(sources: &LocalSources, softening2: f64) -> Self {
        let [x, y, z, gm] = &sources.columns;
        let mut sums = [[0.0; LANES]; 19];
        for (((x, y), z), gm) in x
            .as_chunks::<LANES>()
            .0
            .iter()
            .zip(y.as_chunks::<LANES>().0)
            .zip(z.as_chunks::<LANES>().0)
            .zip(gm.as_chunks::<LANES>().0)
        {
            for l in 0..LANES {
                let t = source_terms([x[l], y[l], z[l]], gm[l], softening2);
                for (sum, t) in sums.iter_mut().zip(t) {
                    sum[l] += t;
                }
            }
        }
        let c = sums.map(lane_total);
        Self {
            a: DVec3::new(c[0], c[1], c[2]),
            j: [c[3], c[4], c[5], c[6], c[7], c[8]],
            k: [c[9], c[10], c[11], c[12], c[13], c[14], c[15], c[16], c[17], c[18]],
        }
    }

    /// The pull at offset `x` from the center: `A + J·x + ½·K[x, x]`.
    #[inline]
    pub fn at(&self, x: DVec3) -> DVec3 {
        let [jxx, jyy, jzz, jxy, jxz, jyz] = self.j;
        let [kxxx, kyyy, kzzz, kxxy, kxxz, kxyy, kyyz, kxzz, kyzz, kxyz] = self.k;
        let (xx, yy, zz) = (x.x * x.x, x.y * x.y, x.z * x.z);
        let (xy, xz, yz) = (2.0 * x.x * x.y, 2.0 * x.x * x.z, 2.0 * x.y * x.z);
        let jx = DVec3::new(
            jxx * x.x + jxy * x.y + jxz * x.z,
            jxy * x.x + jyy * x.y + jyz * x.z,
            jxz * x.x + jyz * x.y + jzz * x.z,
        );
        let kxx = DVec3::new(
            kxxx * xx + kxyy * yy + kxzz * zz + kxxy * xy + kxxz * xz + kxyz * yz,
            kxxy * xx + kyyy * yy + kyzz * zz + kxyy * xy + kxyz * xz + kyyz * yz,
            kxxz * xx + kyyz * yy + kzzz * zz + kxyz * xy + kxzz * xz + kyzz * yz,
        );
        self.a + jx + 0.5 * kxx
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::maths::Rng;

    /// The exact pull of a source `gm` at `u` on a body at `x`.
    fn exact(u: DVec3, gm: f64, x: DVec3, softening2: f64) -> DVec3 {
        let d = u - x;
        let r2 = d.length_squared() + softening2;
        d * (gm / (r2 * r2.sqrt()))
    }

    fn expansion(sources: &[(DVec3, f64)], softening2: f64) -> LocalExpansion {
        let mut list = LocalSources::default();
        for &(u, gm) in sources {
            list.push(u, gm);
        }
        list.pad();
        LocalExpansion::of(&list, softening2)
    }

    /// At the center the series is the sum of the pulls; off center its
    /// error is of third order: halving the offset divides it by about 8.
    #[test]
    fn the_series_is_the_pull_at_the_center_and_third_order_off_it() {
        let mut rng = Rng::new(3);
        for softening2 in [0.0, 2.0] {
            let sources: Vec<(DVec3, f64)> = (0..13)
                .map(|_| {
                    let dir = DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)).normalize();
                    (dir * rng.range(80.0, 120.0), rng.range(0.5, 3.0))
                })
                .collect();
            let local = expansion(&sources, softening2);
            let sum = |x: DVec3| {
                sources
                    .iter()
                    .map(|&(u, gm)| exact(u, gm, x, softening2))
                    .sum::<DVec3>()
            };
            assert!((local.at(DVec3::ZERO) - sum(DVec3::ZERO)).length() <= 1e-14 * sum(DVec3::ZERO).length());
            for _ in 0..20 {
                let x = DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)).normalize() * 10.0;
                let error = |x: DVec3| (local.at(x) - sum(x)).length();
                let (big, small) = (error(x), error(x * 0.5));
                let scale = sources.iter().map(|&(u, gm)| gm / u.length_squared()).sum::<f64>();
                assert!(big <= 8.0 * (0.125 * 0.125 * 0.125) * scale, "{big} at {x}");
                assert!(small > big / 12.0 && small < big / 5.0, "{big} then {small}");
            }
        }
    }

    /// Padding adds nothing: one source's expansion is its terms, bit
    /// for bit.
    #[test]
    fn padding_adds_exactly_nothing() {
        let (u, gm) = (DVec3::new(50.0, -20.0, 3.0), 2.0);
        let mut list = LocalSources::default();
        list.push(u, gm);
        list.pad();
        list.pad();
        assert_eq!(list.len(), LANES);
        let local = LocalExpansion::of(&list, 0.0);
        let terms = source_terms(u.to_array(), gm, 0.0);
        let coefficients: Vec<f64> = local.a.to_array().into_iter().chain(local.j).chain(local.k).collect();
        assert_eq!(coefficients, terms);
        assert_eq!(
            LocalExpansion::of(&LocalSources::default(), 0.0),
            LocalExpansion::default()
        );
    }
}
