//! The walks' kernel (`kernel.rs`) with AVX-512: the [`LANES`] lanes in
//! the sixteen `f32` slots of one 512-bit register, every operation the
//! one the plain kernel does in that lane, in the same order: correctly
//! rounded additions, multiplications, divisions and square roots, no
//! fused multiply-add and no approximate reciprocal, so it gives the plain
//! kernel's bits (a test in `kernel.rs` holds it to them). Four bodies go
//! down a list together, sharing the loads and giving the processor
//! independent work between divisions. Each body's sum depends on the
//! lists it is given alone, summed in a fixed order: blocks of [`BLOCK`]
//! registers in `f32`, carried into `f64`, the lanes added at the end
//! (`lanes_total`).

use std::arch::x86_64::*;

use bevy::math::DVec3;

use super::columns::{BLOCK, GroupLists, LANES, lanes_total};
use super::source::GravitySource;

/// Entries in a register: one lane each.
const WIDE: usize = 16;

const _: () = assert!(LANES == WIDE, "one lane an f32 slot of a 512-bit register");

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

/// `a·x + b·y + c·z`, summed left to right.
#[inline]
#[target_feature(enable = "avx512f")]
fn dot(a: [__m512; 3], x: [__m512; 3]) -> __m512 {
    _mm512_add_ps(
        _mm512_add_ps(_mm512_mul_ps(a[0], x[0]), _mm512_mul_ps(a[1], x[1])),
        _mm512_mul_ps(a[2], x[2]),
    )
}

/// Adds `kernel::near_term` in each slot to `sum`.
#[inline]
#[target_feature(enable = "avx512f")]
fn add_near(sum: &mut [__m512; 3], gm: __m512, d: [__m512; 3], softening2: __m512) {
    let r2 = dot(d, d);
    let inv2 = _mm512_div_ps(_mm512_set1_ps(1.0), _mm512_add_ps(r2, softening2));
    // Zero where r2 > 0 fails (the body itself), as the plain branch.
    let keep = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(r2, _mm512_setzero_ps());
    let f = _mm512_maskz_mul_ps(keep, gm, _mm512_mul_ps(inv2, _mm512_sqrt_ps(inv2)));
    for (sum, d) in sum.iter_mut().zip(d) {
        *sum = _mm512_add_ps(*sum, _mm512_mul_ps(d, f));
    }
}

/// The near sums of the bodies at `at` into `totals`.
#[inline]
#[target_feature(enable = "avx512f")]
fn near_sums(lists: &GroupLists, at: &[DVec3], totals: &mut [DVec3; BATCH], softening2: __m512) {
    let columns = lists.near.each_ref().map(|c| &c[..]);
    list_sums(lists, columns, at, totals, |sum, [x, y, z, gm], [px, py, pz]| {
        let d = [_mm512_sub_ps(x, px), _mm512_sub_ps(y, py), _mm512_sub_ps(z, pz)];
        add_near(sum, gm, d, softening2);
    });
}

/// Adds `kernel::far_term` in each slot to `sum`; nothing where `r²`
/// overflows (`1/r² = 0`), as the plain branch.
#[inline]
#[target_feature(enable = "avx512f")]
fn add_far(sum: &mut [__m512; 3], gm: __m512, q: [__m512; 6], r: [__m512; 3], softening2: __m512) {
    let [xx, yy, zz, xy, xz, yz] = q;
    let inv2 = _mm512_div_ps(_mm512_set1_ps(1.0), _mm512_add_ps(dot(r, r), softening2));
    let inv1 = _mm512_sqrt_ps(inv2);
    let n = r.map(|r| _mm512_mul_ps(r, inv1));
    let qn = [dot([xx, xy, xz], n), dot([xy, yy, yz], n), dot([xz, yz, zz], n)];
    let radial = _mm512_add_ps(
        _mm512_set1_ps(1.0),
        _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(2.5), dot(n, qn)), inv2),
    );
    let scale = _mm512_mul_ps(gm, inv2);
    let keep = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(inv2, _mm512_setzero_ps());
    for ((sum, qn), n) in sum.iter_mut().zip(qn).zip(n) {
        let ratio = _mm512_sub_ps(_mm512_mul_ps(qn, inv2), _mm512_mul_ps(n, radial));
        *sum = _mm512_add_ps(*sum, _mm512_maskz_mul_ps(keep, scale, ratio));
    }
}

/// The eight slots of `v`.
#[inline]
#[target_feature(enable = "avx512f")]
fn slots(v: __m512d) -> [f64; 8] {
    let quarters = [_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v)]
        .map(|h| [_mm256_castpd256_pd128(h), _mm256_extractf128_pd::<1>(h)]);
    std::array::from_fn(|i| {
        let q = quarters[i / 4][i / 2 % 2];
        _mm_cvtsd_f64(if i % 2 == 0 { q } else { _mm_unpackhi_pd(q, q) })
    })
}

/// One body's partial sums in `f64` (lanes 0–7 and 8–15), into which each
/// block's `f32` sums are carried, as the plain kernel's `lane_sums`.
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
        lanes_total(self.0.map(|[low, high]| {
            let (low, high) = (slots(low), slots(high));
            std::array::from_fn(|l| if l < 8 { low[l] } else { high[l - 8] })
        }))
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
    let softening2 = _mm512_set1_ps(softening2 as f32);
    let (mut near, mut far) = ([DVec3::ZERO; BATCH], [DVec3::ZERO; BATCH]);
    for batch in members.chunks(BATCH) {
        let mut at = [DVec3::ZERO; BATCH];
        for (at, s) in at.iter_mut().zip(batch) {
            *at = s.position;
        }
        let at = &at[..batch.len()];
        near_sums(lists, at, &mut near, softening2);
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
