//! Sequential or parallel execution of the simulation kernels, switchable at
//! run time with bit-identical results — the project's parallel runtime.
//!
//! Every stage writes its logic once, as a *kernel*: a plain function over a
//! [`Split`] input (slices, index ranges, or tuples of a table's columns).
//! [`Execution`] calls that kernel either once on everything or on
//! contiguous chunks from a pool of exactly `threads` worker threads, and
//! hands the chunks' results back in input order. There is no second,
//! parallel copy of any algorithm.
//!
//! Which of the two happens is decided per stage and update by the
//! [`SplitPolicy`] (`policy.rs`): never in sequential mode; in parallel
//! mode at every body count (`Always`, the thesis's behaviour), from a
//! given count (`Above(N)`), or from the count a calibration of this
//! machine found for that stage (`Auto`). A stage asks once,
//! [`Execution::for_stage`], and runs all its steps the way the answer says.
//!
//! # The rules a kernel follows to stay bit-identical
//!
//! 1. **Any cut, same bits.** A kernel may be called on the whole input or
//!    on any contiguous chunks of it, in any order, on any thread. What it
//!    computes for an item depends only on that item and on shared data it
//!    only reads — never on which other items share its chunk.
//! 2. **Reductions go through the ordered results.** A kernel that reduces
//!    (counts, bounds, collected pairs) returns its chunk's part; the caller
//!    combines the parts from [`StageExecution::map_chunks`] in the order given,
//!    which is input order. Floats are never summed across items inside a
//!    chunk and then across chunks: that would round differently for every
//!    cut. Exact reductions (min, max, counts, concatenation) are fine.
//! 3. **No shared mutable state.** Chunks write only what they were handed
//!    (`&mut` slices cut by [`Split`]); no atomics on floats, no locks
//!    around results. (A thread's own copy of shared input,
//!    [`ThreadCopies`], is the same items whichever thread made it.)
//! 4. **Structural changes stay serial.** Spawning, despawning and handing
//!    out ids happen on one thread in a fixed order (e.g. pair order).
//! 5. **Any policy, any chunk size.** Results must not depend on where
//!    the work is cut or whether it is cut: tests run every kernel with
//!    one-item chunks ([`Execution::fine_grained`]) and whole.
//!
//! # How a parallel step runs
//!
//! `claims.rs` cuts the input into about four chunks per thread, in a block
//! per thread that its thread claims first (the same bodies every step, so
//! they stay in that core's caches) before helping with the others' blocks;
//! the thread that started the step waits for the others' last chunks
//! spinning, not asleep, because on the virtual machines this runs on,
//! waking a sleeping thread costs tens of microseconds. After a step, `keep_warm.rs` keeps the idle workers polling
//! for a millisecond, so the next step of the same update finds them awake.
//! Why a pool of our own rather than Bevy's `ComputeTaskPool` or `par_iter`:
//! see ARCHITECTURE.md, "Parallel execution"; `--pool bevy` runs the same
//! chunks on Bevy's pool (`bevy_pool.rs`) to measure the difference.

mod bevy_pool;
mod claims;
mod keep_warm;
mod mode;
mod policy;
mod pool;
mod split;
mod thread_copies;
mod worker_pool;

pub use keep_warm::WARM_FOR;
pub use mode::ExecutionMode;
pub use policy::{AutoSplit, BadSplitPolicy, FALLBACK_SPLIT_FROM, SplitPolicy};
pub use pool::{Execution, ExecutionError, MAX_THREADS, StageExecution, available_threads};
pub use split::Split;
pub use thread_copies::ThreadCopies;
pub use worker_pool::WorkerPool;
