//! [`Execution`]: the execution mode, the worker pool, and the one helper
//! that drives a kernel whole or in chunks.

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use bevy::prelude::*;

use super::claims::{CHUNKS_PER_THREAD, Claims};
use super::keep_warm::KeepWarm;
use super::{ExecutionMode, Split};

/// Most worker threads a pool may have.
pub const MAX_THREADS: usize = 256;

/// Hardware threads of this machine (1 if unknown).
pub fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The execution mode, thread count and worker pool of the simulation.
#[derive(Resource, Clone)]
pub struct Execution {
    mode: ExecutionMode,
    pool: Arc<rayon::ThreadPool>,
    /// Ignore the callers' grains and split all work as finely as possible.
    fine_grained: bool,
    /// Set whenever work was split since the last [`install`](Self::install).
    split_recently: Arc<AtomicBool>,
    /// Keeps the pool's other workers awake between the steps of an update;
    /// `None` where polling would steal cores from something else.
    warm: Option<Arc<KeepWarm>>,
}

impl fmt::Debug for Execution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Execution")
            .field("mode", &self.mode)
            .field("threads", &self.threads())
            .field("keep_warm", &self.warm.is_some())
            .finish()
    }
}

/// The worker pool could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ExecutionError {
    /// Fewer than one or more than [`MAX_THREADS`] threads were asked for.
    #[error("thread count must be between 1 and {MAX_THREADS}, got {0}")]
    BadThreadCount(usize),
    /// The operating system would not start the threads.
    #[error("could not start {threads} worker threads: {source}")]
    Pool {
        /// Threads asked for.
        threads: usize,
        /// Why rayon could not build the pool.
        source: rayon::ThreadPoolBuildError,
    },
}

impl Execution {
    /// A pool of `threads` workers used in `mode`, keeping its workers warm
    /// between steps.
    pub fn new(mode: ExecutionMode, threads: usize) -> Result<Self, ExecutionError> {
        Ok(Self {
            mode,
            pool: Arc::new(build_pool(threads)?),
            fine_grained: false,
            split_recently: Arc::new(AtomicBool::new(true)),
            warm: Some(Arc::default()),
        })
    }

    /// Parallel on every core of this machine.
    pub fn all_cores(mode: ExecutionMode) -> Result<Self, ExecutionError> {
        Self::new(mode, available_threads())
    }

    /// Splits every kernel, however small its input, into one-item-minimum
    /// chunks in parallel mode: slow, but it puts every chunk boundary to
    /// the test. For determinism tests.
    pub fn fine_grained(mut self) -> Self {
        self.fine_grained = true;
        self
    }

    /// Whether idle workers keep polling for a moment after each parallel
    /// step ([`WARM_FOR`](super::WARM_FOR)). On by default: it saves the
    /// wake-ups between the steps of an update. Off would suit a host whose
    /// other work needs the cores between updates; the window measured no
    /// cost and keeps it on (`ui/app.rs`).
    pub fn with_keep_warm(mut self, on: bool) -> Self {
        self.warm = on.then(Arc::default);
        self
    }

    /// Sequential or parallel.
    pub fn mode(&self) -> ExecutionMode {
        self.mode
    }

    /// Switches the mode; takes effect at the next step.
    pub fn set_mode(&mut self, mode: ExecutionMode) {
        self.mode = mode;
    }

    /// Worker threads used in parallel mode.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Threads a step really runs on: 1 in sequential mode.
    pub fn threads_used(&self) -> usize {
        match self.mode {
            ExecutionMode::Sequential => 1,
            ExecutionMode::Parallel => self.threads(),
        }
    }

    /// Replaces the worker pool; a no-op if the count is unchanged.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), ExecutionError> {
        if threads != self.threads() {
            self.pool = Arc::new(build_pool(threads)?);
            if self.warm.is_some() {
                self.warm = Some(Arc::default());
            }
        }
        Ok(())
    }

    /// Runs `f` on a worker of the pool in parallel mode when work was split
    /// since the last call (the caller waits), else inline. A whole update
    /// runs this way: when its stages split work, their serial parts then
    /// run on a worker too, so the idle workers, which poll a while before
    /// sleeping, do not compete with the calling thread for the cores, and
    /// every dispatch is a cheap in-pool fork; when nothing splits, waking a
    /// worker for the update would only cost time. Either way the results
    /// are the same.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        let use_pool = self.mode == ExecutionMode::Parallel && self.split_recently.swap(false, Ordering::Relaxed);
        if use_pool { self.pool.install(f) } else { f() }
    }

    /// Runs `kernel` over `data`: whole, on this thread, in sequential mode or
    /// when `data` has fewer than two `grain`s of items; otherwise on
    /// contiguous chunks of at least `grain` items in the worker pool.
    pub fn for_chunks<S, K>(&self, data: S, grain: usize, kernel: K)
    where
        S: Split,
        K: Fn(S) + Sync,
    {
        self.map_chunks(data, grain, kernel);
    }

    /// Like [`for_chunks`](Self::for_chunks), collecting each chunk's result
    /// in input order (one element when run whole).
    pub fn map_chunks<S, R, K>(&self, data: S, grain: usize, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        let len = data.len();
        let grain = if self.fine_grained { 1 } else { grain.max(1) };
        if self.mode == ExecutionMode::Sequential || len < 2 * grain {
            return vec![kernel(data)];
        }
        self.split_recently.store(true, Ordering::Relaxed);
        let chunk = grain.max(len.div_ceil(self.threads() * CHUNKS_PER_THREAD));
        let claims = Claims::new(data, chunk);
        self.pool.install(|| claims.run(&kernel));
        if let Some(warm) = &self.warm {
            warm.after_step(&self.pool);
        }
        claims.into_results()
    }
}

fn build_pool(threads: usize) -> Result<rayon::ThreadPool, ExecutionError> {
    if threads == 0 || threads > MAX_THREADS {
        return Err(ExecutionError::BadThreadCount(threads));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("kessler-sim-{i}"))
        .build()
        .map_err(|source| ExecutionError::Pool { threads, source })
}

#[cfg(test)]
mod tests {
    use std::ops::Range;

    use super::*;

    #[test]
    fn parallel_map_keeps_input_order_and_covers_every_item() {
        let exec = Execution::new(ExecutionMode::Parallel, 3).unwrap();
        let chunks = exec.map_chunks(0..10_007, 100, |r: Range<usize>| r);
        assert!(chunks.len() > 1, "work of 100 grains must be split");
        let flat: Vec<usize> = chunks.into_iter().flatten().collect();
        assert_eq!(flat, (0..10_007).collect::<Vec<_>>());
    }

    #[test]
    fn small_work_and_sequential_mode_run_whole() {
        let par = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        assert_eq!(par.map_chunks(0..199, 100, |r: Range<usize>| r), vec![0..199]);
        let seq = Execution::new(ExecutionMode::Sequential, 2).unwrap();
        assert_eq!(seq.map_chunks(0..1_000_000, 1, |r: Range<usize>| r), vec![0..1_000_000]);
    }

    #[test]
    fn tuples_of_slices_split_in_lockstep() {
        let exec = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        let a: Vec<u32> = (0..5000).collect();
        let mut b = vec![0u32; 5000];
        exec.for_chunks((a.as_slice(), b.as_mut_slice()), 64, |(a, b): (&[u32], &mut [u32])| {
            for (x, y) in a.iter().zip(b) {
                *y = x * 2;
            }
        });
        assert!(b.iter().enumerate().all(|(i, &y)| y == 2 * i as u32));
    }

    #[test]
    fn uneven_chunks_keep_input_order() {
        let exec = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        // Eight chunks of 8 (four per thread); early chunks are slow, so the
        // other thread claims the later ones.
        let chunks = exec.map_chunks(0..64, 8, |r: Range<usize>| {
            std::thread::sleep(std::time::Duration::from_micros(300 * (8 - r.start as u64 / 8)));
            r.start
        });
        assert_eq!(chunks, (0..64).step_by(8).collect::<Vec<_>>());
    }

    #[test]
    fn a_panicking_chunk_panics_the_step_instead_of_hanging_it() {
        let exec = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        for bad in [0, 7] {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                exec.for_chunks(0..800, 100, |r: Range<usize>| {
                    assert!(r.start / 100 != bad, "chunk {bad}")
                })
            }));
            assert!(outcome.is_err(), "chunk {bad}'s panic was lost");
        }
        // The pool still works afterwards.
        assert_eq!(
            exec.map_chunks(0..400, 100, |r: Range<usize>| r.end - r.start),
            vec![100; 4]
        );
    }

    #[test]
    fn without_keep_warm_the_results_are_the_same() {
        let warm = Execution::new(ExecutionMode::Parallel, 2).unwrap();
        let cold = warm.clone().with_keep_warm(false);
        let sums =
            |e: &Execution| -> Vec<u64> { e.map_chunks(0..100_000, 1000, |r: Range<usize>| r.map(|i| i as u64).sum()) };
        assert_eq!(sums(&warm), sums(&cold));
    }

    #[test]
    fn thread_count_is_checked() {
        assert!(Execution::new(ExecutionMode::Parallel, 0).is_err());
        assert!(Execution::new(ExecutionMode::Parallel, MAX_THREADS + 1).is_err());
        let mut exec = Execution::new(ExecutionMode::Parallel, 1).unwrap();
        exec.set_threads(3).unwrap();
        assert_eq!(exec.threads(), 3);
        assert_eq!(exec.threads_used(), 3);
        exec.set_mode(ExecutionMode::Sequential);
        assert_eq!(exec.threads_used(), 1);
    }
}
