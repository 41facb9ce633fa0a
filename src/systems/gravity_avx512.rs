//! The group walk's kernel (`gravity_columns`) with AVX-512: sixteen
//! `f32` lanes in one 512-bit register, and `1/r` from the processor's
//! approximate reciprocal square root (`vrsqrt14ps`, 14 bits) refined by
//! one Newton step, instead of a division and a square root: those run on
//! one unit of the core and bound the 256-bit kernel, while the estimate
//! and the Newton step take a cycle or two. The step brings `1/r` to about
//! `f32`'s precision; the pull differs from the plain kernel's in the last
//! bits. Every run on one processor takes the same kernel, so sequential
//! and parallel still give the same bits. Each body's sum depends on its
//! group's lists alone, summed in a fixed order: blocks of [`BLOCK`] chunks
//! in `f32`, carried into `f64`, the lanes added at the end.

use std::arch::x86_64::*;

use bevy::math::{DVec3, Vec3};

use super::gravity::GravitySource;
use super::gravity_columns::{BLOCK, FAR_AWAY, GroupLists, LANES};

/// Entries in a register.
const WIDE: usize = 16;

const _: () = assert!(
    WIDE.is_multiple_of(LANES),
    "lists padded to LANES fill registers but for one half"
);

/// Sixteen values in one register.
#[inline]
#[target_feature(enable = "avx512f")]
fn load(a: &[f32; WIDE]) -> __m512 {
    _mm512_set_ps(
        a[15], a[14], a[13], a[12], a[11], a[10], a[9], a[8], a[7], a[6], a[5], a[4], a[3], a[2], a[1], a[0],
    )
}

/// The values of `column` from `start` on, `fill` past its end.
#[inline]
#[target_feature(enable = "avx512f")]
fn load_tail(column: &[f32], start: usize, fill: f32) -> __m512 {
    load(&std::array::from_fn(|l| column.get(start + l).copied().unwrap_or(fill)))
}

/// `1/√s` in each slot: the 14-bit estimate and one Newton step,
/// `y·(3/2 − s·y²/2)`.
#[inline]
#[target_feature(enable = "avx512f")]
fn inverse_sqrt(s: __m512) -> __m512 {
    let y = _mm512_rsqrt14_ps(s);
    let half_s_y = _mm512_mul_ps(_mm512_mul_ps(s, _mm512_set1_ps(0.5)), y);
    _mm512_mul_ps(y, _mm512_fnmadd_ps(half_s_y, y, _mm512_set1_ps(1.5)))
}

/// The slots where `s`, a squared distance, is finite (not the padding far
/// away, nor a source beyond `f32`'s range, whose pull is below it).
#[inline]
#[target_feature(enable = "avx512f")]
fn finite(s: __m512) -> __mmask16 {
    _mm512_cmp_ps_mask::<_CMP_LT_OQ>(s, _mm512_set1_ps(f32::INFINITY))
}

/// `|d|²`.
#[inline]
#[target_feature(enable = "avx512f")]
fn length2(d: [__m512; 3]) -> __m512 {
    _mm512_fmadd_ps(d[2], d[2], _mm512_fmadd_ps(d[1], d[1], _mm512_mul_ps(d[0], d[0])))
}

/// `gravity_columns::near_term` in each slot.
#[inline]
#[target_feature(enable = "avx512f")]
fn near_term(gm: __m512, d: [__m512; 3], softening2: __m512) -> [__m512; 3] {
    let r2 = length2(d);
    let s = _mm512_add_ps(r2, softening2);
    let inv1 = inverse_sqrt(s);
    let f = _mm512_mul_ps(_mm512_mul_ps(gm, inv1), _mm512_mul_ps(inv1, inv1));
    // Nothing from the body itself (r² = 0) nor from beyond f32's range.
    let keep = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(r2, _mm512_setzero_ps()) & finite(s);
    let f = _mm512_maskz_mov_ps(keep, f);
    d.map(|d| _mm512_mul_ps(d, f))
}

/// `gravity_columns::far_term` in each slot.
#[inline]
#[target_feature(enable = "avx512f")]
fn far_term(gm: __m512, q: [__m512; 6], r: [__m512; 3], softening2: __m512) -> [__m512; 3] {
    let [xx, yy, zz, xy, xz, yz] = q;
    let s = _mm512_add_ps(length2(r), softening2);
    // 0 beyond f32's range (the padding among them), so that every term
    // there is 0, not NaN.
    let inv1 = _mm512_maskz_mov_ps(finite(s), inverse_sqrt(s));
    let inv2 = _mm512_mul_ps(inv1, inv1);
    let n = r.map(|r| _mm512_mul_ps(r, inv1));
    let dot = |a: [__m512; 3]| _mm512_fmadd_ps(a[2], n[2], _mm512_fmadd_ps(a[1], n[1], _mm512_mul_ps(a[0], n[0])));
    let qn = [dot([xx, xy, xz]), dot([xy, yy, yz]), dot([xz, yz, zz])];
    let radial = _mm512_fmadd_ps(_mm512_mul_ps(_mm512_set1_ps(2.5), dot(qn)), inv2, _mm512_set1_ps(1.0));
    let scale = _mm512_mul_ps(gm, inv2);
    let component = |c: usize| _mm512_mul_ps(scale, _mm512_fmsub_ps(qn[c], inv2, _mm512_mul_ps(n[c], radial)));
    [component(0), component(1), component(2)]
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

/// The sums of `term` over `len` entries of `columns` (past the end,
/// `fill`) for each of `B` bodies at `p`: blocks of [`BLOCK`] registers
/// summed in `f32`, each block then carried into the `f64` sums.
#[inline]
#[target_feature(enable = "avx512f")]
fn block_sums<const B: usize, const N: usize>(
    columns: [&[f32]; N],
    fill: [f32; N],
    p: [[__m512; 3]; B],
    term: impl Fn([__m512; N], [__m512; 3]) -> [__m512; 3],
) -> [Sums; B] {
    let whole = columns.map(|c| c.as_chunks::<WIDE>().0);
    let chunks = columns[0].len().div_ceil(WIDE);
    let mut sums = [Sums::new(); B];
    let mut start = 0;
    while start < chunks {
        let end = (start + BLOCK).min(chunks);
        let mut block = [[_mm512_setzero_ps(); 3]; B];
        for k in start..end {
            // Whole registers, then the last half of one (the lists are
            // padded to 8).
            let values: [__m512; N] = std::array::from_fn(|c| match whole[c].get(k) {
                Some(chunk) => load(chunk),
                None => load_tail(columns[c], k * WIDE, fill[c]),
            });
            for (block, p) in block.iter_mut().zip(p) {
                for (b, t) in block.iter_mut().zip(term(values, p)) {
                    *b = _mm512_add_ps(*b, t);
                }
            }
        }
        for (sums, block) in sums.iter_mut().zip(block) {
            sums.carry(block);
        }
        start = end;
    }
    sums
}

/// The pull of the lists on each of `B` bodies at `p`: the near sum, then
/// the far sum, added in `f64`.
#[inline]
#[target_feature(enable = "avx512f")]
fn pulls<const B: usize>(lists: &GroupLists, at: [DVec3; B], softening2: f32) -> [DVec3; B] {
    let p = at.map(|p| lists.relative(p).map(|c| _mm512_set1_ps(c)));
    let softening2 = _mm512_set1_ps(softening2);
    let [x, y, z, gm] = &lists.near;
    let columns = [&x[..], &y[..], &z[..], &gm[..]];
    let fill = [FAR_AWAY, FAR_AWAY, FAR_AWAY, 0.0];
    let near = block_sums(columns, fill, p, |[x, y, z, gm], [px, py, pz]| {
        let d = [_mm512_sub_ps(x, px), _mm512_sub_ps(y, py), _mm512_sub_ps(z, pz)];
        near_term(gm, d, softening2)
    });
    let columns: [&[f32]; 10] = std::array::from_fn(|c| &lists.far[c][..]);
    let fill = std::array::from_fn(|c| if c < 3 { FAR_AWAY } else { 0.0 });
    let far = block_sums(columns, fill, p, |[x, y, z, gm, q @ ..], [px, py, pz]| {
        let r = [_mm512_sub_ps(px, x), _mm512_sub_ps(py, y), _mm512_sub_ps(pz, z)];
        far_term(gm, q, r, softening2)
    });
    std::array::from_fn(|b| lists.total(near[b].total() + far[b].total(), at[b]))
}

/// `gravity_columns::group_pulls` with AVX-512.
#[target_feature(enable = "avx512f")]
pub fn group_pulls(lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<Vec3>) {
    let softening2 = softening2 as f32;
    // Four bodies at a time share the loads (32 registers hold their sums).
    let mut fours = members.chunks_exact(4);
    for four in &mut fours {
        let at: [DVec3; 4] = std::array::from_fn(|b| four[b].position);
        out.extend(pulls(lists, at, softening2).map(DVec3::as_vec3));
    }
    for s in fours.remainder() {
        out.extend(pulls(lists, [s.position], softening2).map(DVec3::as_vec3));
    }
}
