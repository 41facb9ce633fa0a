//! The lists the walks' sums run down, as columns (docs/design.md,
//! "Gravity"), and what every kernel over them shares: a region or a group
//! gathers the sources it sums one by one and the nodes it takes whole into
//! [`GroupLists`] once, and each of its bodies then runs down them in
//! [`LANES`] independent partial sums, the slots of a SIMD register, each
//! carried over into `f64` every [`BLOCK`] terms and the lanes added in one
//! fixed order at the end ([`lanes_total`]). The lists hold `f32` positions
//! relative to a center near their bodies (the region's or the group's), so
//! no precision is lost to the distance from the origin; they are padded to
//! a multiple of [`PAD_TO`] entries.
//!
//! The kernels that run down the lists (`kernel.rs`, and the SIMD ones it
//! dispatches to, `avx.rs` and `avx512.rs`) import this file; it imports
//! none of them.

use bevy::math::DVec3;

use super::source::GravitySource;

/// Partial sums per component: the `f32` slots of a 512-bit register (two
/// 256-bit ones). Every kernel sums entry `i` in lane `i % LANES`, so this
/// number is part of what decides the bits of a pull.
pub const LANES: usize = 16;

/// Terms per lane summed in `f32` before the lane's partial sum is carried
/// over into `f64`.
pub const BLOCK: usize = 16;

/// The lists are padded to a multiple of this many entries, whole chunks
/// of [`LANES`] (the padding adds exactly nothing).
pub const PAD_TO: usize = LANES;

/// Padding: a massless entry this far away adds exactly nothing (an
/// infinite squared distance in `f32`, a finite distance from any position
/// a body may have, ±10³⁰, so no NaN).
pub(super) const FAR_AWAY: f32 = f32::MAX / 4.0;

/// The tree's sources in leaf order as columns, as the near lists copy
/// them: position (`f64`) and `G·m` (`f32`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LeafSources {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    gm: Vec<f32>,
}

impl LeafSources {
    /// The columns of `sources`, reusing this one's memory.
    pub fn fill(&mut self, sources: &[GravitySource]) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
        self.gm.clear();
        self.x.extend(sources.iter().map(|s| s.position.x));
        self.y.extend(sources.iter().map(|s| s.position.y));
        self.z.extend(sources.iter().map(|s| s.position.z));
        self.gm.extend(sources.iter().map(|s| s.gm as f32));
    }
}

/// What a group or a region of bodies sums, as columns relative to a
/// center near them, each padded with massless entries to a multiple of [`PAD_TO`]:
/// the sources it sums one by one (position, `G·m`) and the nodes it takes
/// whole (center of mass, `G·m`, quadrupole).
#[derive(Clone, Debug, Default)]
pub struct GroupLists {
    pub(super) center: DVec3,
    pub(super) near: [Vec<f32>; 4],
    pub(super) far: [Vec<f32>; 10],
}

impl GroupLists {
    /// Empty lists with room for `near` sources and `far` nodes, so that
    /// a chunk of groups does not grow them step by step.
    pub fn with_capacity(near: usize, far: usize) -> Self {
        Self {
            center: DVec3::ZERO,
            near: std::array::from_fn(|_| Vec::with_capacity(near)),
            far: std::array::from_fn(|_| Vec::with_capacity(far)),
        }
    }

    /// Empties the lists, keeping their memory; positions are taken
    /// relative to `center` from now on.
    pub fn clear(&mut self, center: DVec3) {
        self.center = center;
        self.near.iter_mut().chain(&mut self.far).for_each(Vec::clear);
    }

    /// Where `p` is from the center, in `f32`.
    #[inline]
    pub(super) fn relative(&self, p: DVec3) -> [f32; 3] {
        (p - self.center).as_vec3().to_array()
    }

    /// Appends the sources `range` of `sources` to sum one by one.
    pub fn push_near(&mut self, sources: &LeafSources, range: std::ops::Range<usize>) {
        let c = self.center;
        let [x, y, z, gm] = &mut self.near;
        x.extend(sources.x[range.clone()].iter().map(|v| (v - c.x) as f32));
        y.extend(sources.y[range.clone()].iter().map(|v| (v - c.y) as f32));
        z.extend(sources.z[range.clone()].iter().map(|v| (v - c.z) as f32));
        gm.extend_from_slice(&sources.gm[range]);
    }

    /// Appends a node to take whole: its center of mass, `G·m` and
    /// quadrupole per unit of `G·m` (see `far_term` in `kernel.rs`).
    pub fn push_far(&mut self, com: DVec3, gm: f32, quad: [f32; 6]) {
        self.extend_far([(com, gm, quad)].iter().copied());
    }

    /// Appends nodes to take whole, as [`push_far`](Self::push_far) does,
    /// column by column (no growth check per value).
    pub fn extend_far<I>(&mut self, nodes: I)
    where
        I: Iterator<Item = (DVec3, f32, [f32; 6])> + Clone,
    {
        let c = self.center;
        let [x, y, z, gm, quad @ ..] = &mut self.far;
        x.extend(nodes.clone().map(|(p, ..)| (p.x - c.x) as f32));
        y.extend(nodes.clone().map(|(p, ..)| (p.y - c.y) as f32));
        z.extend(nodes.clone().map(|(p, ..)| (p.z - c.z) as f32));
        gm.extend(nodes.clone().map(|(_, gm, _)| gm));
        for (k, column) in quad.iter_mut().enumerate() {
            column.extend(nodes.clone().map(|(.., q)| q[k]));
        }
    }

    /// Pads both lists to a multiple of [`PAD_TO`] with massless entries
    /// far away (each list's first three columns are the position).
    pub fn pad(&mut self) {
        for columns in [&mut self.near[..], &mut self.far[..]] {
            while !columns[0].len().is_multiple_of(PAD_TO) {
                for (k, column) in columns.iter_mut().enumerate() {
                    column.push(if k < 3 { FAR_AWAY } else { 0.0 });
                }
            }
        }
    }

    /// The number of whole lanes in the near and far lists.
    pub(super) fn chunks(&self) -> (usize, usize) {
        (self.near[3].len() / LANES, self.far[3].len() / LANES)
    }
}

/// The sum of `LANES` lanes, pairwise in a fixed order: `((l0 + l1) +
/// (l2 + l3)) + ((l4 + l5) + (l6 + l7))` for each half, then the halves.
#[inline]
pub(super) fn lane_total(l: [f64; LANES]) -> f64 {
    let half = |l: &[f64]| ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]));
    half(&l[..8]) + half(&l[8..])
}

const _: () = assert!(LANES == 16, "lane_total adds two halves of eight");

/// The sum of the lanes of each component, pairwise in a fixed order.
#[inline]
pub(super) fn lanes_total(a: [[f64; LANES]; 3]) -> DVec3 {
    DVec3::new(lane_total(a[0]), lane_total(a[1]), lane_total(a[2]))
}
