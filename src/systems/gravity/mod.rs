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
//! - `mod.rs`: the plugin and its system;
//! - `kick.rs`: the sources, the pull (`Auto` decided), the kick;
//! - `walk.rs`: the region walks and the group walks of the tree;
//! - `tree.rs`: the Barnes–Hut octree: the build, regions and groups, the
//!   single-point walk;
//! - `local_expansion.rs`: a region's local expansion of distant sources;
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
mod kick;
mod local_expansion;
mod source;
mod tree;
mod walk;

pub use kernel::Kernel;
pub use kick::{Pull, PullScratch, Roles, collect_sources, gravity_kernel, prepare_pull};
pub use source::GravitySource;
pub use tree::Octree;

use bevy::prelude::*;

use crate::components::{BodyId, GravityRole, Mass, Position, PreviousPosition, Velocity};
use crate::resources::{GravityMethod, SimulationSettings};
use crate::systems::{SimulationSystems, SimulationUpdate, StageClocks};

/// Accelerates adopters towards the sources in [`SimulationSystems::Gravity`].
pub struct GravityPlugin;

impl Plugin for GravityPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<GravityInUse>().add_systems(
            SimulationUpdate,
            apply_gravity
                .in_set(SimulationSystems::Gravity)
                .run_if(|s: Res<SimulationSettings>| s.stages.gravity),
        );
    }
}

/// How the last gravity stage summed, for the HUD; before the first, no
/// sources summed directly.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct GravityInUse {
    /// The method used: `Direct` or `Tree`, never `Auto`.
    pub method: GravityMethod,
    /// Whether `Auto` chose it.
    pub auto: bool,
    /// Sources summed.
    pub sources: usize,
}

impl Default for GravityInUse {
    fn default() -> Self {
        Self {
            method: GravityMethod::Direct,
            auto: false,
            sources: 0,
        }
    }
}

/// What the gravity stage keeps between updates: the sources and what its
/// pull is made in.
#[derive(Default)]
struct GravityScratch {
    sources: Vec<GravitySource>,
    pull: PullScratch,
}

/// What the gravity stage reads and writes of every body: its role only
/// where it stores one (an adopter does not).
type GravityQuery<'w, 's> = Query<
    'w,
    's,
    (
        &'static BodyId,
        Option<&'static GravityRole>,
        &'static Mass,
        &'static mut Position,
        &'static mut PreviousPosition,
        &'static mut Velocity,
    ),
>;

fn apply_gravity(
    settings: Res<SimulationSettings>,
    mut clocks: StageClocks,
    mut in_use: ResMut<GravityInUse>,
    mut scratch: Local<GravityScratch>,
    mut bodies: GravityQuery,
) {
    let clock = clocks.start(SimulationSystems::Gravity);
    let (integrator, dt) = (settings.integrator, settings.time_step);
    let tables = bodies.contiguous_iter().expect("body components are table-stored");
    let GravityScratch { sources, pull } = &mut *scratch;
    let all = tables.map(|(ids, roles, masses, positions, _, velocities)| (ids, positions, velocities, masses, roles));
    collect_sources(all, f64::from(settings.gravitational_constant), integrator, dt, sources);
    let softening = f64::from(settings.softening);
    let softening2 = softening * softening;
    let (pull, stage) = prepare_pull(
        settings.gravity_method,
        sources,
        bodies.iter().len(),
        softening2,
        clock.executor(),
        pull,
    );
    in_use.set_if_neq(GravityInUse {
        method: pull.method(),
        auto: settings.gravity_method == GravityMethod::Auto,
        sources: sources.len(),
    });
    let tables = bodies.contiguous_iter_mut().expect("body components are table-stored");
    for (ids, roles, _, mut positions, mut previous, mut velocities) in tables {
        let columns = (
            ids,
            Roles::of_table(roles, ids.len()),
            positions.bypass_change_detection(),
            previous.bypass_change_detection(),
            velocities.bypass_change_detection(),
        );
        stage.for_chunks(columns, |columns| {
            gravity_kernel(columns, pull, softening2, dt, integrator);
        });
    }
    clock.finish();
}
