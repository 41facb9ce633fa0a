//! Memory: how much this process may use ([`MemoryLimit`], `allowance.rs`)
//! and how glibc's allocator is told to treat the big blocks a million
//! bodies need (`heap.rs`).

mod allowance;
mod heap;

pub use allowance::{BYTES_PER_BODY, LimitKind, MemoryLimit};
pub use heap::{BIG_BLOCK, HEAPS, KEPT_FREE, hand_back_big_blocks, release_free_memory};
