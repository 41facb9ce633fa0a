//! The gravity stage: gravitational acceleration of every adopter, applied at once
//! as the kick of the integrator's step (docs/design.md, "Gravity" and
//! "Integration").
//!
//! `a_i = Σ_j G·m_j·(p_j − p_i) / (|p_j − p_i|² + ε²)^{3/2}` over all sources
//! `j ≠ i` at non-zero distance, summed in f64 in ascending `BodyId` order.
//! Each body's sum is independent of every other, so any split of the bodies
//! gives the same bits. The stage ends with the kick `v_i += a_i·dt`. With
//! semi-implicit Euler (the thesis) only velocities change, every sum reads
//! positions from before the update, and the integration stage then drifts
//! `p += v·dt`; with the leapfrog every body first drifts half a step, the
//! sums read those midpoints, and the integration stage drifts the second
//! half. The arithmetic is exactly
//! "compute `a`, then `v += a·dt`"; not storing `a` between the stages saves
//! 20 bytes per body (a component and its change ticks).
//!
//! The files form a ladder: each imports only files below it.
//!
//! - `stage.rs`: the plugin and its system, the pull (`Auto` decided), the
//!   kick;
//! - `walk.rs`: the region walks and the group walks of the tree;
//! - `tree.rs`: the Barnes–Hut octree: the build, regions and groups, the
//!   single-point walk;
//! - `local.rs`: a region's local expansion of distant sources;
//! - `kernel.rs`: the near and far terms, the sums lane by lane, and
//!   [`Kernel`], which one this processor runs: `avx512.rs`, `avx.rs` (both
//!   x86-64 only) or lane by lane;
//! - `columns.rs`: a group's lists as `f32` columns and what every kernel
//!   shares (lanes, blocks, padding);
//! - `source.rs`: [`GravitySource`] and the direct sum.

#[cfg(target_arch = "x86_64")]
mod avx;
#[cfg(target_arch = "x86_64")]
mod avx512;
mod columns;
mod kernel;
mod local;
mod source;
mod stage;
mod tree;
mod walk;

pub use kernel::Kernel;
pub use source::{GravitySource, acceleration_at, add_pulls, pull_factor};
pub use stage::{
    GravityColumns, GravityInUse, GravityPlugin, Pull, PullScratch, SourceColumns, collect_sources, gravity_kernel,
    half_drift, prepare_pull,
};
pub use tree::{GROUP_SIZE, LEAF_SIZE, Octree, REGION_SIZE};
