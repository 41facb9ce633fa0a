//! The bare cost of one parallel step: a near-empty kernel run split into
//! chunks on the worker pool against the same kernel called whole.

use std::hint::black_box;
use std::ops::Range;
use std::time::Instant;

use crate::execution::{Execution, ExecutionError, ExecutionMode, SplitPolicy, WorkerPool};

/// Steps per timed batch.
const BATCH: u32 = 500;
/// Timed batches; the median batch counts.
const BATCHES: usize = 21;

/// The near-empty kernel: the length of its chunk.
fn kernel(range: Range<usize>) -> usize {
    black_box(range.len())
}

/// Median over batches of the mean time of one step of `execution` (which
/// splits as its policy says), in ns. The steps run back to back inside
/// [`Execution::install`], as the steps of an update do: on a worker of the
/// pool, with the other workers awake (warm) between steps.
fn step_ns(execution: &Execution, items: usize) -> f64 {
    let batch = || {
        execution.install(|| {
            let start = Instant::now();
            for _ in 0..BATCH {
                black_box(execution.for_stage("empty_step", items).map_chunks(0..items, kernel));
            }
            start.elapsed().as_nanos() as f64 / f64::from(BATCH)
        })
    };
    // Warm-up; it also lets `install` move the next batches onto the pool.
    batch();
    let mut times: Vec<f64> = (0..BATCHES).map(|_| batch()).collect();
    times.sort_by(f64::total_cmp);
    times[BATCHES / 2]
}

/// `(split, whole)`: the time of one step of the near-empty kernel split
/// into chunks on `pool` with `threads` threads (Bevy's: the threads it
/// has, [`Execution::threads_used`]), and called whole, in ns.
pub fn empty_step_ns(threads: usize, pool: WorkerPool) -> Result<(f64, f64), ExecutionError> {
    let split = Execution::new(ExecutionMode::Parallel, threads)?
        .with_split(SplitPolicy::Always)
        .with_pool(pool);
    let whole = Execution::new(ExecutionMode::Sequential, 1)?;
    // A few chunks per thread, as a stage would be cut.
    let items = 4 * threads;
    Ok((step_ns(&split, items), step_ns(&whole, items)))
}
