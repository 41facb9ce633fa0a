//! The walks' kernel (`kernel.rs`) with AVX-512: sixteen
//! `f32` lanes in one 512-bit register, and `1/r` from the processor's
//! approximate reciprocal square root (`vrsqrt14ps`, 14 bits) refined by
//! one Newton step, instead of a division and a square root: those run on
//! one unit of the core and bound the 256-bit kernel, while the estimate
//! and the step take a cycle or two. The step brings `1/r` (or, for a
//! source's pull, `1/r³` directly) to about `f32`'s precision; each term
//! is added with a fused multiply-add, so the pull differs from the plain
//! kernel's in the last bits. Every run on one processor takes the same
//! kernel, so sequential and parallel still give the same bits. Each
//! body's sum depends on the lists it is given alone, summed in a fixed
//! order: blocks of [`BLOCK`] registers in `f32`, carried into `f64`, the
//! lanes added at the end.

use std::arch::x86_64::*;

use bevy::math::DVec3;

use super::columns::{BLOCK, GroupLists, PAD_TO};
use super::source::GravitySource;

/// Entries in a register.
const WIDE: usize = 16;

const _: () = assert!(PAD_TO.is_multiple_of(WIDE), "padded lists are whole registers");

/// Bodies that go down a list together, sharing the loads (their `f32`
/// block sums take twelve of the 32 registers; more gained nothing).
const BODIES: usize = 4;

/// Sixteen values in one register.
#[inline]
#[target_feature(enable = "avx512f")]
fn load(a: &[f32; WIDE]) -> __m512 {
    _mm512_set_ps(
        a[15], a[14], a[13], a[12], a[11], a[10], a[9], a[8], a[7], a[6], a[5], a[4], a[3], a[2], a[1], a[0],
    )
}

/// `|d|²`.
#[inline]
#[target_feature(enable = "avx512f")]
fn length2(d: [__m512; 3]) -> __m512 {
    _mm512_fmadd_ps(d[2], d[2], _mm512_fmadd_ps(d[1], d[1], _mm512_mul_ps(d[0], d[0])))
}

/// The slots where `s`, a squared distance, is finite (not the padding far
/// away, nor a source or node so far that its squared distance overflows
/// `f32`: its pull is dropped), among those of `among`.
#[inline]
#[target_feature(enable = "avx512f")]
fn finite(among: __mmask16, s: __m512) -> __mmask16 {
    _mm512_mask_cmp_ps_mask::<_CMP_LT_OQ>(among, s, _mm512_set1_ps(f32::INFINITY))
}

/// Adds `kernel::near_term` in each slot to `sum`: `G·m·d/s^{3/2}`
/// with `s = |d|² + ε²`. From the estimate `y ≈ 1/√s`, `1/s^{3/2}` is
/// `y³·(5/2 − (3/2)·s·y²)`, a Newton step taken on `y³` (relative error
/// `7.5·e²` for an estimate off by `e` ≤ 2⁻¹⁴: below `f32`'s rounding).
/// `SOFTENED`: the caller has checked that `ε² ≥ 10⁻³⁰` and that no
/// source's `G·m/ε³` comes near `f32`'s range (see [`softened`]), so that
/// the term of the body itself (`d = 0`) is exactly 0 without being masked
/// out.
#[inline]
#[target_feature(enable = "avx512f")]
fn add_near<const SOFTENED: bool>(sum: &mut [__m512; 3], gm: __m512, d: [__m512; 3], softening2: __m512) {
    // Nothing from beyond f32's range; unless softened, nothing from the
    // body itself (r² = 0) either.
    let (s, keep) = if SOFTENED {
        let s = _mm512_fmadd_ps(
            d[2],
            d[2],
            _mm512_fmadd_ps(d[1], d[1], _mm512_fmadd_ps(d[0], d[0], softening2)),
        );
        (s, finite(!0, s))
    } else {
        let r2 = length2(d);
        let s = _mm512_add_ps(r2, softening2);
        (s, finite(_mm512_cmp_ps_mask::<_CMP_GT_OQ>(r2, _mm512_setzero_ps()), s))
    };
    let y = _mm512_rsqrt14_ps(s);
    let y2 = _mm512_mul_ps(y, y);
    let step = _mm512_fnmadd_ps(_mm512_mul_ps(s, y2), _mm512_set1_ps(1.5), _mm512_set1_ps(2.5));
    let f = _mm512_maskz_mul_ps(keep, _mm512_mul_ps(_mm512_mul_ps(gm, y), y2), step);
    for (sum, d) in sum.iter_mut().zip(d) {
        *sum = _mm512_fmadd_ps(d, f, *sum);
    }
}

/// Whether the near list may be summed [`SOFTENED`](add_near): `ε²` (in
/// `f32`, as summed) is at least 10⁻³⁰, so that `1/ε²` is far inside
/// `f32`'s range, and the largest `G·m` over `ε³` is below 10³⁶, so that
/// the body's own term is finite, even with the estimate's error.
fn softened(gm: &[f32], softening2: f32) -> bool {
    let most = gm.iter().fold(0.0f32, |most, &g| most.max(g));
    softening2 >= 1e-30 && f64::from(most) * f64::from(softening2).powf(-1.5) < 1e36
}

/// The near sums of the bodies at `at` into `totals`.
#[inline]
#[target_feature(enable = "avx512f")]
fn near_sums<const SOFTENED: bool>(lists: &GroupLists, at: &[DVec3], totals: &mut [DVec3; BATCH], softening2: __m512) {
    let columns = lists.near.each_ref().map(|c| &c[..]);
    list_sums(lists, columns, at, totals, |sum, [x, y, z, gm], [px, py, pz]| {
        let d = [_mm512_sub_ps(x, px), _mm512_sub_ps(y, py), _mm512_sub_ps(z, pz)];
        add_near::<SOFTENED>(sum, gm, d, softening2);
    });
}

/// Adds `kernel::far_term` in each slot to `sum`, in its form:
/// `G·m/r²` times ratios of lengths (not `G·m/r⁴` on its own), so that no
/// intermediate overflows or falls into `f32`'s subnormal range unless the
/// term itself would; nothing where `r²` overflows.
#[inline]
#[target_feature(enable = "avx512f")]
fn add_far(sum: &mut [__m512; 3], gm: __m512, q: [__m512; 6], r: [__m512; 3], softening2: __m512) {
    let [xx, yy, zz, xy, xz, yz] = q;
    let s = _mm512_add_ps(length2(r), softening2);
    // 1/r by one Newton step, y·(3/2 − s·y²/2); nothing is added beyond
    // f32's range (the padding among them), however large the quadrupole.
    let keep = finite(!0, s);
    let y = _mm512_rsqrt14_ps(s);
    let half_s_y = _mm512_mul_ps(_mm512_mul_ps(s, _mm512_set1_ps(0.5)), y);
    let inv1 = _mm512_maskz_mul_ps(keep, y, _mm512_fnmadd_ps(half_s_y, y, _mm512_set1_ps(1.5)));
    let inv2 = _mm512_mul_ps(inv1, inv1);
    let n = r.map(|r| _mm512_mul_ps(r, inv1));
    let dot = |a: [__m512; 3]| _mm512_fmadd_ps(a[2], n[2], _mm512_fmadd_ps(a[1], n[1], _mm512_mul_ps(a[0], n[0])));
    let qn = [dot([xx, xy, xz]), dot([xy, yy, yz]), dot([xz, yz, zz])];
    let radial = _mm512_fmadd_ps(_mm512_mul_ps(dot(qn), inv2), _mm512_set1_ps(2.5), _mm512_set1_ps(1.0));
    let scale = _mm512_mul_ps(gm, inv2);
    for ((sum, qn), n) in sum.iter_mut().zip(qn).zip(n) {
        let ratio = _mm512_fmsub_ps(qn, inv2, _mm512_mul_ps(n, radial));
        *sum = _mm512_mask3_fmadd_ps(scale, ratio, *sum, keep);
    }
}

/// One body's partial sums in `f64` (slots 0–7 and 8–15 of the `f32`
/// lanes), into which each block's `f32` sums are carried.
#[derive(Clone, Copy)]
struct Sums([[__m512d; 2]; 3]);

impl Sums {
    #[inline]
    #[target_feature(enable = "avx512f")]
    fn new() -> Self {
        Self([[_mm512_setzero_pd(); 2]; 3])
    }

    #[inline]
    #[target_feature(enable = "avx512f")]
    fn carry(&mut self, block: [__m512; 3]) {
        for (sum, block) in self.0.iter_mut().zip(block) {
            let high = _mm256_castpd_ps(_mm512_extractf64x4_pd::<1>(_mm512_castps_pd(block)));
            sum[0] = _mm512_add_pd(sum[0], _mm512_cvtps_pd(_mm512_castps512_ps256(block)));
            sum[1] = _mm512_add_pd(sum[1], _mm512_cvtps_pd(high));
        }
    }

    #[inline]
    #[target_feature(enable = "avx512f")]
    fn total(&self) -> DVec3 {
        let [x, y, z] = self.0.map(|[low, high]| _mm512_reduce_add_pd(_mm512_add_pd(low, high)));
        DVec3::new(x, y, z)
    }
}

/// The sums of `add`'s terms over the registers of `columns` (all of one
/// length, a multiple of [`WIDE`]) for each of `B` bodies at `p`: blocks
/// of [`BLOCK`] registers summed in `f32`, each block then carried into
/// the `f64` sums.
#[inline]
#[target_feature(enable = "avx512f")]
fn block_sums<const B: usize, const N: usize>(
    columns: [&[f32]; N],
    p: [[__m512; 3]; B],
    add: impl Fn(&mut [__m512; 3], [__m512; N], [__m512; 3]),
) -> [Sums; B] {
    let registers = columns[0].len() / WIDE;
    let columns = columns.map(|c| &c.as_chunks::<WIDE>().0[..registers]);
    let mut sums = [Sums::new(); B];
    let mut start = 0;
    while start < registers {
        let end = (start + BLOCK).min(registers);
        let mut block = [[_mm512_setzero_ps(); 3]; B];
        #[expect(clippy::needless_range_loop, reason = "k indexes each of the N columns in turn")]
        for k in start..end {
            let values: [__m512; N] = std::array::from_fn(|c| load(&columns[c][k]));
            for (block, p) in block.iter_mut().zip(p) {
                add(block, values, p);
            }
        }
        for (sums, block) in sums.iter_mut().zip(block) {
            sums.carry(block);
        }
        start = end;
    }
    sums
}

/// Bodies summed list by list: each list is run down by all of them
/// before the next, so that it stays in the core's first-level cache
/// (a group's two lists together may not fit).
const BATCH: usize = 64;

/// The sums of `add`'s terms over `columns` for each body at `at` (at most
/// [`BATCH`]) into `totals`, [`BODIES`] at a time sharing the loads.
#[inline]
#[target_feature(enable = "avx512f")]
fn list_sums<const N: usize>(
    lists: &GroupLists,
    columns: [&[f32]; N],
    at: &[DVec3],
    totals: &mut [DVec3; BATCH],
    add: impl Fn(&mut [__m512; 3], [__m512; N], [__m512; 3]) + Copy,
) {
    let p = |p: DVec3| lists.relative(p).map(|c| _mm512_set1_ps(c));
    let mut together = at.chunks_exact(BODIES);
    let mut k = 0;
    for bodies in &mut together {
        let sums = block_sums(columns, std::array::from_fn::<_, BODIES, _>(|b| p(bodies[b])), add);
        for sum in sums {
            totals[k] = sum.total();
            k += 1;
        }
    }
    for &body in together.remainder() {
        totals[k] = block_sums(columns, [p(body)], add)[0].total();
        k += 1;
    }
}

/// `kernel::group_pulls` with AVX-512: the near sum, then the far
/// sum, added in `f64`.
#[target_feature(enable = "avx512f")]
pub fn group_pulls(lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<DVec3>) {
    let softened = softened(&lists.near[3], softening2 as f32);
    let softening2 = _mm512_set1_ps(softening2 as f32);
    let (mut near, mut far) = ([DVec3::ZERO; BATCH], [DVec3::ZERO; BATCH]);
    for batch in members.chunks(BATCH) {
        let mut at = [DVec3::ZERO; BATCH];
        for (at, s) in at.iter_mut().zip(batch) {
            *at = s.position;
        }
        let at = &at[..batch.len()];
        if softened {
            near_sums::<true>(lists, at, &mut near, softening2);
        } else {
            near_sums::<false>(lists, at, &mut near, softening2);
        }
        let columns = lists.far.each_ref().map(|c| &c[..]);
        list_sums(
            lists,
            columns,
            at,
            &mut far,
            |sum, [x, y, z, gm, q @ ..], [px, py, pz]| {
                let r = [_mm512_sub_ps(px, x), _mm512_sub_ps(py, y), _mm512_sub_ps(pz, z)];
                add_far(sum, gm, q, r, softening2);
            },
        );
        out.extend(near.iter().zip(&far).take(batch.len()).map(|(&near, &far)| near + far));
    }
}
