//! The simulation stages, one plugin per stage; the stage list and the
//! schedule that orders them.

mod broad_phase;
mod contact;
mod fault;
mod gravity;
#[cfg(target_arch = "x86_64")]
mod gravity_avx;
#[cfg(target_arch = "x86_64")]
mod gravity_avx512;
mod gravity_columns;
mod gravity_local;
mod gravity_tree;
mod gravity_walk;
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
pub use gravity::*;
pub use gravity_columns::Kernel;
pub use gravity_tree::*;
pub use integrate::*;
pub use plugins::*;
pub use response::*;
pub use schedule::*;
pub use shatter::*;
pub use stages::*;
pub use timings::*;
pub use totals::*;
