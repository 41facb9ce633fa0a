//! The walks' kernel (`kernel.rs`) with AVX: the [`LANES`] lanes in the
//! `f32` slots of two 256-bit registers (lanes 0–7 and 8–15), every
//! operation the one the plain kernel does in that lane, in the same order
//! (no fused multiply-add, which AVX alone does not have), so both give
//! the same bits; a test in `kernel.rs` holds them to it. The two halves
//! give the processor independent work between divisions.

use std::arch::x86_64::*;

use bevy::math::DVec3;

use super::columns::{BLOCK, GroupLists, LANES, lanes_total};
use super::source::GravitySource;

const _: () = assert!(LANES == 16, "the lanes two registers of eight f32 slots");

/// Eight values of `a` from `from` on in one register.
#[inline]
#[target_feature(enable = "avx")]
fn load(a: &[f32; LANES], from: usize) -> __m256 {
    let a = &a[from..from + 8];
    _mm256_set_ps(a[7], a[6], a[5], a[4], a[3], a[2], a[1], a[0])
}

/// The `k`-th chunk of each of `columns`: lanes 0–7, then 8–15.
#[inline]
#[target_feature(enable = "avx")]
fn load_all<const N: usize>(columns: &[&[[f32; LANES]]; N], k: usize) -> [[__m256; N]; 2] {
    let mut out = [[_mm256_setzero_ps(); N]; 2];
    for (half, from) in out.iter_mut().zip([0, 8]) {
        for (v, column) in half.iter_mut().zip(columns) {
            *v = load(&column[k], from);
        }
    }
    out
}

/// The four slots of `v`.
#[inline]
#[target_feature(enable = "avx")]
fn slots(v: __m256d) -> [f64; 4] {
    let (low, high) = (_mm256_castpd256_pd128(v), _mm256_extractf128_pd::<1>(v));
    [
        _mm_cvtsd_f64(low),
        _mm_cvtsd_f64(_mm_unpackhi_pd(low, low)),
        _mm_cvtsd_f64(high),
        _mm_cvtsd_f64(_mm_unpackhi_pd(high, high)),
    ]
}

/// `a·x + b·y + c·z`, summed left to right.
#[inline]
#[target_feature(enable = "avx")]
fn dot(a: [__m256; 3], x: [__m256; 3]) -> __m256 {
    _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(a[0], x[0]), _mm256_mul_ps(a[1], x[1])),
        _mm256_mul_ps(a[2], x[2]),
    )
}

/// `kernel::near_term` in each slot.
#[inline]
#[target_feature(enable = "avx")]
fn near_term(gm: __m256, d: [__m256; 3], softening2: __m256) -> [__m256; 3] {
    let r2 = dot(d, d);
    let inv2 = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_add_ps(r2, softening2));
    let f = _mm256_mul_ps(gm, _mm256_mul_ps(inv2, _mm256_sqrt_ps(inv2)));
    // Zero where r2 > 0 fails (the body itself), as the plain branch.
    let f = _mm256_and_ps(f, _mm256_cmp_ps::<_CMP_GT_OQ>(r2, _mm256_setzero_ps()));
    [_mm256_mul_ps(d[0], f), _mm256_mul_ps(d[1], f), _mm256_mul_ps(d[2], f)]
}

/// `kernel::far_term` in each slot.
#[inline]
#[target_feature(enable = "avx")]
fn far_term(gm: __m256, q: [__m256; 6], r: [__m256; 3], softening2: __m256) -> [__m256; 3] {
    let [xx, yy, zz, xy, xz, yz] = q;
    let inv2 = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_add_ps(dot(r, r), softening2));
    let inv1 = _mm256_sqrt_ps(inv2);
    let n = [
        _mm256_mul_ps(r[0], inv1),
        _mm256_mul_ps(r[1], inv1),
        _mm256_mul_ps(r[2], inv1),
    ];
    let qn = [dot([xx, xy, xz], n), dot([xy, yy, yz], n), dot([xz, yz, zz], n)];
    let radial = _mm256_add_ps(
        _mm256_set1_ps(1.0),
        _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(2.5), dot(n, qn)), inv2),
    );
    let scale = _mm256_mul_ps(gm, inv2);
    // Zero where r² overflowed (1/r² = 0), as the plain branch.
    let keep = _mm256_cmp_ps::<_CMP_GT_OQ>(inv2, _mm256_setzero_ps());
    let component = |c: usize| {
        let term = _mm256_mul_ps(
            scale,
            _mm256_sub_ps(_mm256_mul_ps(qn[c], inv2), _mm256_mul_ps(n[c], radial)),
        );
        _mm256_and_ps(term, keep)
    };
    [component(0), component(1), component(2)]
}

/// One body's partial sums in `f64` (lanes 0–3, 4–7, 8–11 and 12–15),
/// into which each block's `f32` sums (lanes 0–7, 8–15) are carried, as
/// the plain kernel's `lane_sums`.
#[derive(Clone, Copy)]
struct Sums([[__m256d; 4]; 3]);

impl Sums {
    #[inline]
    #[target_feature(enable = "avx")]
    fn new() -> Self {
        Self([[_mm256_setzero_pd(); 4]; 3])
    }

    #[inline]
    #[target_feature(enable = "avx")]
    fn carry(&mut self, block: [[__m256; 3]; 2]) {
        for (sum, c) in self.0.iter_mut().zip(0..3) {
            for (quarters, half) in sum.chunks_exact_mut(2).zip(block) {
                let half = half[c];
                quarters[0] = _mm256_add_pd(quarters[0], _mm256_cvtps_pd(_mm256_castps256_ps128(half)));
                quarters[1] = _mm256_add_pd(quarters[1], _mm256_cvtps_pd(_mm256_extractf128_ps::<1>(half)));
            }
        }
    }

    #[inline]
    #[target_feature(enable = "avx")]
    fn total(&self) -> DVec3 {
        lanes_total(self.0.map(|quarters| {
            let quarters = quarters.map(|q| slots(q));
            std::array::from_fn(|l| quarters[l / 4][l % 4])
        }))
    }
}

/// The sums of `term` over the `chunks` chunks of `columns` for a body at
/// `p`: blocks of [`BLOCK`] chunks summed in registers in `f32`, each
/// block then carried into the `f64` sums.
#[inline]
#[target_feature(enable = "avx")]
fn block_sums<const N: usize>(
    columns: &[&[[f32; LANES]]; N],
    chunks: usize,
    p: [__m256; 3],
    term: impl Fn([__m256; N], [__m256; 3]) -> [__m256; 3],
) -> Sums {
    let mut sums = Sums::new();
    let mut start = 0;
    while start < chunks {
        let end = (start + BLOCK).min(chunks);
        let mut block = [[_mm256_setzero_ps(); 3]; 2];
        for k in start..end {
            for (block, values) in block.iter_mut().zip(load_all(columns, k)) {
                let t = term(values, p);
                for (b, t) in block.iter_mut().zip(t) {
                    *b = _mm256_add_ps(*b, t);
                }
            }
        }
        sums.carry(block);
        start = end;
    }
    sums
}

/// `kernel::pull_on` for a body at `at`.
#[inline]
#[target_feature(enable = "avx")]
fn pull(lists: &GroupLists, at: DVec3, softening2: f32) -> DVec3 {
    let (near_chunks, far_chunks) = lists.chunks();
    let p = lists.relative(at).map(|c| _mm256_set1_ps(c));
    let softening2 = _mm256_set1_ps(softening2);
    let near = lists
        .near
        .each_ref()
        .map(|column| &column.as_chunks::<LANES>().0[..near_chunks]);
    let near_sums = block_sums(&near, near_chunks, p, |[x, y, z, gm], [px, py, pz]| {
        let d = [_mm256_sub_ps(x, px), _mm256_sub_ps(y, py), _mm256_sub_ps(z, pz)];
        near_term(gm, d, softening2)
    });
    let far = lists
        .far
        .each_ref()
        .map(|column| &column.as_chunks::<LANES>().0[..far_chunks]);
    let far_sums = block_sums(&far, far_chunks, p, |[x, y, z, gm, q @ ..], [px, py, pz]| {
        let r = [_mm256_sub_ps(px, x), _mm256_sub_ps(py, y), _mm256_sub_ps(pz, z)];
        far_term(gm, q, r, softening2)
    });
    near_sums.total() + far_sums.total()
}

/// `kernel::group_pulls` with AVX.
#[target_feature(enable = "avx")]
pub fn group_pulls(lists: &GroupLists, members: &[GravitySource], softening2: f64, out: &mut Vec<DVec3>) {
    let softening2 = softening2 as f32;
    out.extend(members.iter().map(|s| pull(lists, s.position, softening2)));
}
