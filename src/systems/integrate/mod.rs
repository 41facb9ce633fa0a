//! The integrate stage: the drift (docs/design.md, "Integration").
//!
//! Adopters have already taken their kick `v += a·dt` in the gravity stage
//! (so no acceleration is stored); here every body moves with its new
//! velocity: a whole step `p += v·dt` with semi-implicit Euler, keeping the
//! position before the move for the collision response, or, with the
//! leapfrog, the second half `p += v·dt/2` after the gravity stage's first
//! (which kept the previous position).

mod drift;

use std::sync::atomic::{AtomicBool, Ordering};

use bevy::prelude::*;

pub use drift::{Drift, integrate_kernel};

use crate::components::{BodyId, Position, PreviousPosition, Velocity};
use crate::execution::WorkerPool;
use crate::resources::SimulationSettings;
use crate::systems::{SimulationFault, SimulationSystems, SimulationUpdate, StageClocks, first_non_finite};

/// Moves every body in [`SimulationSystems::Integrate`].
pub struct IntegratePlugin;

impl Plugin for IntegratePlugin {
    fn build(&self, app: &mut App) {
        app.add_systems(SimulationUpdate, integrate.in_set(SimulationSystems::Integrate));
    }
}

fn integrate(
    settings: Res<SimulationSettings>,
    mut clocks: StageClocks,
    mut bodies: Query<(&BodyId, &Velocity, &mut Position, &mut PreviousPosition)>,
    mut fault: ResMut<SimulationFault>,
) {
    let clock = clocks.start(SimulationSystems::Integrate);
    let (dt, drift) = (settings.time_step, Drift::of(&settings));
    let execution = clock.execution(bodies.iter().len());
    let finite = if execution.splits() && execution.pool() == WorkerPool::Bevy {
        // Bevy's own way for a stage that is per body: `par_iter_mut` on
        // its ComputeTaskPool, in its batches; the kernel on each body
        // alone (any cut gives the same bits), the check an exact "and".
        let all_finite = AtomicBool::new(true);
        bodies
            .par_iter_mut()
            .for_each(|(_, velocity, mut position, mut previous)| {
                let one = (
                    std::slice::from_ref(velocity),
                    std::slice::from_mut(position.bypass_change_detection()),
                    std::slice::from_mut(previous.bypass_change_detection()),
                );
                if !integrate_kernel(one, dt, drift) {
                    all_finite.store(false, Ordering::Relaxed);
                }
            });
        all_finite.into_inner()
    } else {
        let tables = bodies.contiguous_iter_mut().expect("body components are table-stored");
        let mut finite = true;
        for (_, velocities, mut positions, mut previous) in tables {
            let columns = (
                velocities,
                positions.bypass_change_detection(),
                previous.bypass_change_detection(),
            );
            finite &= execution
                .map_chunks(columns, |columns| integrate_kernel(columns, dt, drift))
                .into_iter()
                .all(|chunk| chunk);
        }
        finite
    };
    if !finite {
        // Rare: find which body, by the lowest id.
        let found = first_non_finite(bodies.iter().map(|(id, v, p, _)| (id, p, v)));
        fault.stop(found.expect("a non-finite value was seen"));
    }
    clock.finish();
}
