//! The sums of the tree's walks (docs/design.md, "Gravity"), over
//! columns: a region or a group gathers the sources it sums one by one and
//! the nodes it takes whole into [`GroupLists`] once, and each of its
//! bodies then runs down them in [`LANES`] independent partial sums, the
//! slots of a SIMD register. The lanes are added in one fixed order at the
//! end, so a body's sum over a set of lists depends on those lists alone
//! (`walk.rs` adds a body's region's and group's sums and the local
//! expansion).
//!
//! The lists hold `f32` positions relative to a center near their bodies
//! (the region's or the group's), so no precision is lost to the distance
//! from the origin, and the terms are `f32` ([`near_term`], [`far_term`]):
//! right to about 10⁻⁷, the precision of the `f32` positions and of the
//! result, while `f32`'s division and square root cost a fraction of
//! `f64`'s and a register holds twice the lanes. Each lane's `f32` partial
//! sum is carried over into `f64` every [`BLOCK`] terms.
//!
//! Which [`Kernel`] runs depends on the processor: `avx512.rs`'s (the
//! sixteen lanes in one register), `avx.rs`'s (in two) or lane by lane
//! here. All three do the same correctly rounded IEEE-754 operations in
//! each lane in the same order, written once in [`near_term`] and
//! [`far_term`]: additions, multiplications, one division and one square
//! root a term, no fused multiply-add (which not every processor has) and
//! no approximate reciprocal or reciprocal square root. So every
//! processor gives the same bits (docs/design.md, "What is bit-identical").

use bevy::math::DVec3;

use super::columns::{BLOCK, GroupLists, LANES, lanes_total};
use super::source::GravitySource;

/// The pull of a source `G·m` = `gm` at `d` from the body (`ε²` =
/// `softening2`): `G·m·d/(|d|² + ε²)^{3/2}`, or nothing at distance 0 (the
/// body itself).
#[inline(always)]
pub fn near_term(gm: f32, d: [f32; 3], softening2: f32) -> [f32; 3] {
    let [dx, dy, dz] = d;
    let r2 = dx * dx + dy * dy + dz * dz;
    let inv2 = 1.0 / (r2 + softening2);
    let f = gm * (inv2 * inv2.sqrt());
    let f = if r2 > 0.0 { f } else { 0.0 };
    [dx * f, dy * f, dz * f]
}

/// The pull of a node, a point mass `gm` with quadrupole `gm·q` (`q` =
/// xx, yy, zz, xy, xz, yz, per unit of `G·m`), on a body at `r` from its
/// center of mass (`r² = |r|² + ε²`, `ε²` = `softening2`): `−gm·r/r³ +
/// gm·q·r/r⁵ − (5/2)·gm·(rᵀqr)·r/r⁷`. It is computed as `gm/r² · ((q·n)/r²
/// − (1 + (5/2)·(nᵀqn)/r²)·n)` with `n = r/r`, so that every intermediate
/// is a ratio of lengths or `gm/r²`: none overflows or falls into `f32`'s
/// subnormal range (where arithmetic is many times slower) unless the term
/// itself would. A node so far that `r²` overflows `f32` pulls nothing
/// (not NaN, whatever its quadrupole).
#[inline(always)]
pub fn far_term(gm: f32, q: [f32; 6], r: [f32; 3], softening2: f32) -> [f32; 3] {
    let [xx, yy, zz, xy, xz, yz] = q;
    let [rx, ry, rz] = r;
    let inv2 = 1.0 / (rx * rx + ry * ry + rz * rz + softening2);
    let inv1 = inv2.sqrt();
    let [nx, ny, nz] = [rx * inv1, ry * inv1, rz * inv1];
    let qx = xx * nx + xy * ny + xz * nz;
    let qy = xy * nx + yy * ny + yz * nz;
    let qz = xz * nx + yz * ny + zz * nz;
    let radial = 1.0 + 2.5 * (nx * qx + ny * qy + nz * qz) * inv2;
    let scale = gm * inv2;
    if inv2 > 0.0 {
        [
            scale * (qx * inv2 - nx * radial),
            scale * (qy * inv2 - ny * radial),
            scale * (qz * inv2 - nz * radial),
        ]
    } else {
        [0.0; 3]
    }
}

/// The per-lane sums of `term(i)` over the `chunks` chunks of [`LANES`]
/// entries, entry `i` in lane `i % LANES`: blocks of [`BLOCK`] chunks summed
/// in `f32`, each block then carried into the `f64` sums (as the AVX
/// kernel's `block_sums`).
fn lane_sums(chunks: usize, term: impl Fn(usize) -> [f32; 3]) -> [[f64; LANES]; 3] {
    let mut sums = [[0.0; LANES]; 3];
    for start in (0..chunks).step_by(BLOCK) {
        let mut block = [[0.0f32; LANES]; 3];
        for k in start..(start + BLOCK).min(chunks) {
            for l in 0..LANES {
                for (b, t) in block.iter_mut().zip(term(k * LANES + l)) {
                    b[l] += t;
                }
            }
        }
        for (sum, block) in sums.iter_mut().zip(block) {
            for (s, b) in sum.iter_mut().zip(block) {
                *s += f64::from(b);
            }
        }
    }
    sums
}

/// The pull of the lists on a body at `p`, lane by lane: the near sum,
/// then the far sum, added in `f64`.
fn pull_on(lists: &GroupLists, p: DVec3, softening2: f32) -> DVec3 {
    let [px, py, pz] = lists.relative(p);
    let (near_chunks, far_chunks) = lists.chunks();
    let [x, y, z, gm] = &lists.near;
    let near = lane_sums(near_chunks, |i| {
        near_term(gm[i], [x[i] - px, y[i] - py, z[i] - pz], softening2)
    });
    let [x, y, z, gm, q @ ..] = &lists.far;
    let far = lane_sums(far_chunks, |i| {
        let quad = [q[0][i], q[1][i], q[2][i], q[3][i], q[4][i], q[5][i]];
        far_term(gm[i], quad, [px - x[i], py - y[i], pz - z[i]], softening2)
    });
    lanes_total(near) + lanes_total(far)
}

/// [`group_pulls`] lane by lane, on any processor.
fn group_pulls_plain(lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<DVec3>) {
    out.extend(members.iter().map(|s| pull_on(lists, s.position, softening2 as f32)));
}

/// A version of the group kernel, for one kind of processor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// The lanes in one AVX-512 register (`avx512.rs`): the same bits
    /// as [`Plain`](Self::Plain).
    Avx512,
    /// The lanes in two AVX registers (`avx.rs`): the same bits as
    /// [`Plain`](Self::Plain).
    Avx,
    /// Lane by lane, on any processor.
    Plain,
}

impl Kernel {
    /// The kernels this processor can run, fastest first.
    pub fn available() -> impl Iterator<Item = Kernel> {
        [Kernel::Avx512, Kernel::Avx, Kernel::Plain]
            .into_iter()
            .filter(|k| k.supported())
    }

    /// The kernel every group runs on this processor: the fastest.
    pub fn best() -> Kernel {
        Kernel::available().next().unwrap_or(Kernel::Plain)
    }

    /// Its name, as the bench's machine file gives it.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Avx512 => "AVX-512",
            Kernel::Avx => "AVX",
            Kernel::Plain => "plain",
        }
    }

    /// Whether this processor has what the kernel needs.
    fn supported(self) -> bool {
        match self {
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx => std::arch::is_x86_feature_detected!("avx"),
            Kernel::Plain => true,
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The pull of `lists` on each of `members`, appended to `out` (`ε²` =
    /// `softening2`); lane by lane where the processor lacks what the
    /// kernel needs.
    pub fn run(self, lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<DVec3>) {
        match self {
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 if self.supported() => {
                #[expect(unsafe_code, reason = "the AVX-512 kernel, called where the processor has AVX-512")]
                // SAFETY: the processor has AVX-512 Foundation, checked just
                // above, the one requirement of the AVX-512 kernel.
                unsafe {
                    super::avx512::group_pulls(lists, members, softening2, out);
                }
            }
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx if self.supported() => {
                #[expect(unsafe_code, reason = "the AVX kernel, called where the processor has AVX")]
                // SAFETY: the processor has AVX, checked just above, the one
                // requirement of the AVX kernel.
                unsafe {
                    super::avx::group_pulls(lists, members, softening2, out);
                }
            }
            _ => group_pulls_plain(lists, members, softening2, out),
        }
    }
}

/// Kernel: the pull of `lists` on each of `members`, appended to `out`
/// (`ε²` = `softening2`), with the [best](Kernel::best) kernel.
pub fn group_pulls(lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<DVec3>) {
    Kernel::best().run(lists, members, softening2, out);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::BodyId;
    use crate::maths::Rng;
    use crate::systems::gravity::columns::LeafSources;
    use crate::systems::gravity::source::add_pulls;
    use bevy::math::Vec3;

    fn sources(count: u64) -> Vec<GravitySource> {
        (0..count)
            .map(|i| GravitySource {
                id: BodyId(i),
                position: DVec3::new(i as f64, (i * i) as f64 * 0.5, -(i as f64)),
                gm: 1.0 + i as f64,
            })
            .collect()
    }

    fn columns(sources: &[GravitySource]) -> LeafSources {
        let mut columns = LeafSources::default();
        columns.fill(sources);
        columns
    }

    #[test]
    fn the_near_list_sums_what_the_sources_pull_skipping_the_body_itself() {
        let sources = sources(11);
        let mut lists = GroupLists::default();
        lists.clear(DVec3::new(2.0, 1.0, -3.0));
        lists.push_near(&columns(&sources), 0..sources.len());
        lists.pad();
        let at = sources[3].position;
        let mut expected = DVec3::ZERO;
        add_pulls(&mut expected, BodyId(3), at, &sources, 0.25);
        let got = pull_on(&lists, at, 0.25);
        assert!(
            (got - expected).length() <= 1e-6 * expected.length(),
            "{got} vs {expected}"
        );
        // Softening 0: the body's own entry must add nothing, not NaN; nor
        // may the padding, wherever the body is.
        assert!(pull_on(&lists, at, 0.0).is_finite());
        assert!(pull_on(&lists, DVec3::splat(-1e30), 0.0).is_finite());
    }

    #[test]
    fn the_far_term_of_a_point_mass_is_newtons_and_padding_adds_nothing() {
        let r = [3.0, -4.0, 12.0];
        let got = Vec3::from_array(far_term(2.0, [0.0; 6], r, 0.0));
        let expected = -Vec3::from_array(r) * 2.0 / (13.0 * 13.0 * 13.0);
        assert!((got - expected).length() <= 1e-6 * expected.length(), "{got}");
        let q = [0.1, -0.2, 0.1, 0.0, 0.05, 0.0];
        let mut lists = GroupLists::default();
        lists.clear(DVec3::ZERO);
        lists.push_far(DVec3::new(10.0, 0.0, 0.0), 3.0, q);
        lists.pad();
        let one = Vec3::from_array(far_term(3.0, q, [-10.0, 0.0, 0.0], 1.0));
        assert_eq!(pull_on(&lists, DVec3::ZERO, 1.0), one.as_dvec3());
        assert!(pull_on(&lists, DVec3::splat(1e30), 0.0).is_finite());
    }

    /// Random lists longer than a block (of `BLOCK` chunks, and of as many
    /// 512-bit registers), with the body itself, sources on top of each
    /// other, softening 0, a softening below `f32`'s normal range with
    /// massless sources, and distances beyond `f32`'s range: the pulls of
    /// each kernel the processor has, and lane by lane.
    fn every_kernel(mut check: impl FnMut(Kernel, &[DVec3], &[DVec3], usize)) {
        let mut rng = Rng::new(9);
        for round in 0..36 {
            let count = 1 + round * 9;
            let massless = round % 8 == 3;
            let mut all: Vec<GravitySource> = (0..count)
                .map(|i| GravitySource {
                    id: BodyId(i as u64),
                    position: DVec3::new(rng.symmetric(50.0), rng.symmetric(50.0), rng.symmetric(50.0)),
                    gm: if massless { 0.0 } else { rng.range(0.0, 10.0) },
                })
                .collect();
            all[0].position = all[count - 1].position;
            if round % 4 == 1 {
                all[0].position.x = 1e25;
            }
            let softening2 = match round % 2 {
                _ if massless => 1e-40,
                0 => 0.0,
                _ => 0.3,
            };
            let mut lists = GroupLists::default();
            lists.clear(DVec3::new(3.0, -20.0, 7.5));
            lists.push_near(&columns(&all), 0..all.len());
            for s in &all {
                let q = std::array::from_fn(|_| rng.symmetric(s.gm) as f32);
                lists.push_far(s.position * 4.0 + DVec3::splat(300.0), s.gm as f32, q);
            }
            lists.pad();
            let mut plain = Vec::new();
            group_pulls_plain(&lists, &all, softening2, &mut plain);
            for kernel in Kernel::available() {
                let mut got = Vec::new();
                kernel.run(&lists, &all, softening2, &mut got);
                check(kernel, &plain, &got, round);
            }
        }
    }

    /// A node taken whole, very near and very heavy, or very far and light:
    /// every kernel's pull is finite and lane by lane's (the far term keeps
    /// to `G·m/r²` times ratios of lengths, so neither overflows nor falls
    /// into `f32`'s subnormal range).
    #[test]
    fn the_far_term_holds_at_extreme_scales() {
        for (distance, gm) in [(1e-6, 1e18), (1e10, 6.674), (1e15, 1e-6), (3.0, 1.0)] {
            let body = GravitySource {
                id: BodyId(0),
                position: DVec3::ZERO,
                gm: 1.0,
            };
            let q = [0.3, -0.1, -0.2, 0.05, -0.04, 0.02].map(|q| (q * distance * distance * 0.1) as f32);
            let mut lists = GroupLists::default();
            lists.clear(DVec3::ZERO);
            lists.push_far(DVec3::new(0.6, -0.48, 0.64) * distance, gm as f32, q);
            lists.pad();
            let mut plain = Vec::new();
            group_pulls_plain(&lists, &[body], 0.0, &mut plain);
            // Newton's pull and the quadrupole's tenth of it.
            let newton = gm / (distance * distance);
            assert!(
                (plain[0].length() / newton - 1.0).abs() < 0.5,
                "{distance}: {}",
                plain[0]
            );
            for kernel in Kernel::available() {
                let mut got = Vec::new();
                kernel.run(&lists, &[body], 0.0, &mut got);
                let error = (got[0] - plain[0]).length() / plain[0].length();
                assert!(
                    error <= 1e-6,
                    "{kernel:?} at {distance}: {} against {}",
                    got[0],
                    plain[0]
                );
            }
        }
    }

    /// A node so far that `r²` overflows `f32`, however large its
    /// quadrupole, pulls exactly nothing in every kernel (not NaN).
    #[test]
    fn a_node_beyond_f32s_squares_pulls_nothing() {
        let body = GravitySource {
            id: BodyId(0),
            position: DVec3::ZERO,
            gm: 1.0,
        };
        let most = f32::MAX / 16.0;
        let mut lists = GroupLists::default();
        lists.clear(DVec3::ZERO);
        lists.push_far(DVec3::new(1e20, 0.0, 3e19), 1e18, [most, -most, 0.0, most, 0.0, -most]);
        lists.pad();
        for kernel in Kernel::available() {
            let mut got = Vec::new();
            kernel.run(&lists, &[body], 0.0, &mut got);
            assert_eq!(got, [DVec3::ZERO], "{kernel:?}");
        }
    }

    /// Every kernel gives the bits of lane by lane, never NaN.
    #[test]
    fn every_kernel_gives_the_bits_of_lane_by_lane() {
        let mut tried = Vec::new();
        every_kernel(|kernel, plain, got, round| {
            tried.push(kernel);
            let bits = |v: &[DVec3]| {
                v.iter()
                    .flat_map(|a| a.to_array().map(f64::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(plain), bits(got), "{kernel:?}, round {round}");
            assert!(got.iter().all(|a| a.is_finite()), "{kernel:?}, round {round}");
        });
        eprintln!(
            "kernels this processor has: {:?}",
            Kernel::available().map(Kernel::name).collect::<Vec<_>>()
        );
        assert!(tried.contains(&Kernel::Plain));
    }
}
