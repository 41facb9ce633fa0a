//! What a run records of its state: the state hash (`state_hash.rs`) and
//! the CSV dump of every body (`dump.rs`).

mod dump;
mod state_hash;

pub use dump::{DumpRow, write_csv};
pub use state_hash::StateHash;
