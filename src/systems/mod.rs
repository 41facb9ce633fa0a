//! The simulation stages, one plugin per stage; the stage list and the
//! schedule that orders them.

mod broad_phase;
mod contact;
mod fault;
mod gravity;
mod integrate;
mod plugins;
mod response;
mod schedule;
mod shatter;
mod stages;
mod timings;
mod totals;

pub use broad_phase::*;
pub use contact::*;
pub use fault::*;
pub use gravity::{
    GROUP_SIZE, GravityColumns, GravityInUse, GravityPlugin, GravitySource, Kernel, LEAF_SIZE, Octree, Pull,
    PullScratch, REGION_SIZE, SourceColumns, acceleration_at, add_pulls, collect_sources, gravity_kernel, prepare_pull,
    pull_factor,
};
pub use integrate::*;
pub use plugins::*;
pub use response::*;
pub use schedule::*;
pub use shatter::*;
pub use stages::*;
pub use timings::*;
pub use totals::*;
