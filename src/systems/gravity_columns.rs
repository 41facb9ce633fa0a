//! The sums of the tree's group walk (docs/design.md, "Gravity"), over
//! columns: a group gathers the sources it sums one by one and the nodes it
//! takes whole into plain `f64` columns once, and each of its bodies then
//! runs down them in [`LANES`] independent partial sums, which the compiler
//! keeps in SIMD registers. The lanes are added in one fixed order at the
//! end, so a body's sum does not depend on anything but its group's lists.

use bevy::math::DVec3;

use super::gravity::{GravitySource, pull_factor};

/// Partial sums per component.
pub const LANES: usize = 4;

/// `(x + y) + (z + w)` of the four lanes of each component.
#[inline]
fn lanes_total(a: [[f64; LANES]; 3]) -> DVec3 {
    let total = |l: [f64; LANES]| (l[0] + l[1]) + (l[2] + l[3]);
    DVec3::new(total(a[0]), total(a[1]), total(a[2]))
}

/// Sources summed one by one, as columns padded with massless entries to
/// a multiple of [`LANES`].
#[derive(Clone, Debug, Default)]
pub struct NearColumns {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    gm: Vec<f64>,
}

impl NearColumns {
    /// Empties the columns, keeping their memory.
    pub fn clear(&mut self) {
        for column in [&mut self.x, &mut self.y, &mut self.z, &mut self.gm] {
            column.clear();
        }
    }

    /// Appends `sources`.
    pub fn extend(&mut self, sources: &[GravitySource]) {
        for s in sources {
            self.x.push(s.position.x);
            self.y.push(s.position.y);
            self.z.push(s.position.z);
            self.gm.push(s.gm);
        }
    }

    /// Pads the columns to a multiple of [`LANES`] with massless entries
    /// (they add exactly nothing).
    pub fn pad(&mut self) {
        while !self.x.len().is_multiple_of(LANES) {
            for column in [&mut self.x, &mut self.y, &mut self.z, &mut self.gm] {
                column.push(0.0);
            }
        }
    }

    /// The pull of every source on a body at `p`: all but those at its very
    /// position (itself), as [`add_pulls`](super::add_pulls) sums them.
    pub fn pull_on(&self, p: DVec3, softening2: f64) -> DVec3 {
        let mut a = [[0.0; LANES]; 3];
        let columns = self
            .x
            .chunks_exact(LANES)
            .zip(self.y.chunks_exact(LANES))
            .zip(self.z.chunks_exact(LANES))
            .zip(self.gm.chunks_exact(LANES));
        for (((x, y), z), gm) in columns {
            for l in 0..LANES {
                let (dx, dy, dz) = (x[l] - p.x, y[l] - p.y, z[l] - p.z);
                let r2 = dx * dx + dy * dy + dz * dz;
                let f = pull_factor(r2, gm[l], softening2);
                let f = if r2 > 0.0 { f } else { 0.0 };
                a[0][l] += dx * f;
                a[1][l] += dy * f;
                a[2][l] += dz * f;
            }
        }
        lanes_total(a)
    }
}

/// The pull of a point mass `gm` with quadrupole `q` (xx, yy, zz, xy, xz,
/// yz) on a body at `r` from its center of mass (`r2 = |r|² + ε²`):
/// `−gm·r/r³ + Q·r/r⁵ − (5/2)·(rᵀQr)·r/r⁷`.
#[inline]
pub fn far_field(gm: f64, q: [f64; 6], r: DVec3, r2: f64) -> DVec3 {
    let [xx, yy, zz, xy, xz, yz] = q;
    let qr = DVec3::new(
        xx * r.x + xy * r.y + xz * r.z,
        xy * r.x + yy * r.y + yz * r.z,
        xz * r.x + yz * r.y + zz * r.z,
    );
    let inv_r2 = 1.0 / r2;
    let inv_r3 = inv_r2 * inv_r2.sqrt();
    let inv_r5 = inv_r3 * inv_r2;
    -r * (gm * inv_r3) + qr * inv_r5 - r * (2.5 * r.dot(qr) * inv_r5 * inv_r2)
}

/// Nodes taken whole, as columns (center of mass, `G·m`, quadrupole)
/// padded to a multiple of [`LANES`].
#[derive(Clone, Debug, Default)]
pub struct FarColumns {
    com: [Vec<f64>; 3],
    gm: Vec<f64>,
    quad: [Vec<f64>; 6],
}

impl FarColumns {
    /// Empties the columns, keeping their memory.
    pub fn clear(&mut self) {
        self.com.iter_mut().chain(self.quad.iter_mut()).for_each(Vec::clear);
        self.gm.clear();
    }

    /// Appends a node.
    pub fn push(&mut self, com: DVec3, gm: f64, quad: [f64; 6]) {
        for (column, v) in self.com.iter_mut().zip(com.to_array()) {
            column.push(v);
        }
        self.gm.push(gm);
        for (column, v) in self.quad.iter_mut().zip(quad) {
            column.push(v);
        }
    }

    /// Pads the columns to a multiple of [`LANES`] with massless nodes as
    /// far away as `f64` goes (they add exactly nothing: no mass, no
    /// quadrupole, an infinite distance, no NaN).
    pub fn pad(&mut self) {
        while !self.gm.len().is_multiple_of(LANES) {
            self.push(DVec3::splat(f64::MAX), 0.0, [0.0; 6]);
        }
    }

    /// The pull of every node on a body at `p`.
    #[expect(
        clippy::needless_range_loop,
        reason = "ten columns are read at one index, and the lane picks the partial sum"
    )]
    pub fn pull_on(&self, p: DVec3, softening2: f64) -> DVec3 {
        let mut a = [[0.0; LANES]; 3];
        let n = self.gm.len();
        let [cx, cy, cz] = [&self.com[0][..n], &self.com[1][..n], &self.com[2][..n]];
        let q: [&[f64]; 6] = std::array::from_fn(|i| &self.quad[i][..n]);
        for start in (0..n).step_by(LANES) {
            for l in 0..LANES {
                let k = start + l;
                let r = DVec3::new(p.x - cx[k], p.y - cy[k], p.z - cz[k]);
                let quad = [q[0][k], q[1][k], q[2][k], q[3][k], q[4][k], q[5][k]];
                let f = far_field(self.gm[k], quad, r, r.length_squared() + softening2);
                a[0][l] += f.x;
                a[1][l] += f.y;
                a[2][l] += f.z;
            }
        }
        lanes_total(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::BodyId;
    use crate::systems::add_pulls;

    #[test]
    fn columns_sum_what_the_sources_pull_skipping_the_body_itself() {
        let sources: Vec<GravitySource> = (0..7)
            .map(|i| GravitySource {
                id: BodyId(i),
                position: DVec3::new(i as f64, (i * i) as f64 * 0.5, -(i as f64)),
                gm: 1.0 + i as f64,
            })
            .collect();
        let mut columns = NearColumns::default();
        columns.extend(&sources);
        columns.pad();
        let at = sources[3].position;
        let mut expected = DVec3::ZERO;
        add_pulls(&mut expected, BodyId(3), at, &sources, 0.25);
        let got = columns.pull_on(at, 0.25);
        assert!(
            (got - expected).length() <= 1e-15 * expected.length(),
            "{got} vs {expected}"
        );
        // Softening 0: the body's own entry must add nothing, not NaN.
        assert!(columns.pull_on(at, 0.0).is_finite());
    }

    #[test]
    fn padding_adds_nothing_to_the_far_sum() {
        let mut far = FarColumns::default();
        far.push(DVec3::new(10.0, 0.0, 0.0), 3.0, [0.1, -0.2, 0.1, 0.0, 0.05, 0.0]);
        far.pad();
        let one = far.pull_on(DVec3::ZERO, 1.0);
        let direct = far_field(
            3.0,
            [0.1, -0.2, 0.1, 0.0, 0.05, 0.0],
            DVec3::new(-10.0, 0.0, 0.0),
            101.0,
        );
        assert_eq!(one, direct);
    }
}
