//! [`Execution`]: the execution mode, the worker pool, and the one helper
//! that drives a kernel whole or in chunks.
//!
//! Over 600 lines with its unit tests, which stay beside the code they
//! test; the code itself is about 420 lines.

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use bevy::prelude::*;

use super::bevy_pool::{compute_pool, compute_threads, map_on_bevy};
use super::claims::{CHUNKS_PER_THREAD, Claims, UNEVEN_CHUNKS_PER_THREAD};
use super::keep_warm::KeepWarm;
use super::{AutoSplit, ExecutionMode, Split, SplitPolicy, WorkerPool};

/// Most worker threads a pool may have.
pub const MAX_THREADS: usize = 256;

/// Hardware threads of this machine (1 if unknown), asked once: the
/// answer reads the cgroup's files, tens of microseconds, and the parallel
/// steps ask it every time.
pub fn available_threads() -> usize {
    static THREADS: OnceLock<usize> = OnceLock::new();
    *THREADS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// The execution mode, thread count and worker pool of the simulation.
#[derive(Resource, Clone)]
pub struct Execution {
    mode: ExecutionMode,
    pool: Arc<rayon::ThreadPool>,
    /// Which pool the parallel steps run on.
    worker_pool: WorkerPool,
    /// From which body count a stage splits its work.
    split: SplitPolicy,
    /// The per-stage counts of [`SplitPolicy::Auto`].
    auto: Arc<AutoSplit>,
    /// Split all work, at every body count, into one-item chunks.
    fine_grained: bool,
    /// The machine's hardware threads, as far as the steps are concerned:
    /// a step runs on no more of the pool's threads.
    hardware_threads: usize,
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
            .field("pool", &self.worker_pool)
            .field("threads", &self.threads())
            .field("split", &self.split)
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
            worker_pool: WorkerPool::Kessler,
            split: SplitPolicy::default(),
            auto: Arc::default(),
            fine_grained: false,
            hardware_threads: available_threads(),
            split_recently: Arc::new(AtomicBool::new(true)),
            warm: Some(Arc::default()),
        })
    }

    /// Parallel on every core of this machine.
    pub fn all_cores(mode: ExecutionMode) -> Result<Self, ExecutionError> {
        Self::new(mode, available_threads())
    }

    /// Splits every kernel, however small its input, into one-item chunks
    /// in parallel mode (the split policy becomes `Always`): slow, but it
    /// puts every chunk boundary to the test. For determinism tests.
    pub fn fine_grained(mut self) -> Self {
        self.fine_grained = true;
        self.split = SplitPolicy::Always;
        self
    }

    /// Runs and cuts the steps as if the machine had `threads` hardware
    /// threads (at least one): a step runs on no more of the pool's
    /// threads than the machine has, and is cut for those. For tests that
    /// must cut the work as a machine with more cores would.
    pub fn as_if_hardware_threads(mut self, threads: usize) -> Self {
        self.hardware_threads = threads.max(1);
        self
    }

    /// Leaves `others` of the machine's hardware threads to the host (at
    /// least one is still used): a step runs on no more of the pool's
    /// threads than the rest, and is cut for those. The window leaves one
    /// to its drawing, which runs beside the simulation: a step that counted
    /// on that core waited for a helper that had none (docs/design.md,
    /// "Sequential and parallel").
    pub fn leave_threads(self, others: usize) -> Self {
        let threads = available_threads().saturating_sub(others);
        self.as_if_hardware_threads(threads)
    }

    /// The same execution on `pool`.
    pub fn with_pool(mut self, pool: WorkerPool) -> Self {
        self.set_pool(pool);
        self
    }

    /// Which pool the parallel steps run on.
    pub fn pool(&self) -> WorkerPool {
        self.worker_pool
    }

    /// Switches the pool; takes effect at the next step. Bevy's is made
    /// (with this execution's thread count) if it does not exist yet.
    pub fn set_pool(&mut self, pool: WorkerPool) {
        if pool == WorkerPool::Bevy {
            compute_pool(self.threads());
        }
        self.worker_pool = pool;
    }

    /// The same execution with split policy `split`.
    pub fn with_split(mut self, split: SplitPolicy) -> Self {
        self.set_split(split);
        self
    }

    /// The same execution with `auto`'s counts for [`SplitPolicy::Auto`].
    pub fn with_auto_split(mut self, auto: AutoSplit) -> Self {
        self.auto = Arc::new(auto);
        self
    }

    /// From which body count a stage splits its work.
    pub fn split(&self) -> SplitPolicy {
        self.split
    }

    /// Switches the split policy; takes effect at the next step.
    pub fn set_split(&mut self, split: SplitPolicy) {
        self.split = split;
    }

    /// The per-stage counts that [`SplitPolicy::Auto`] uses.
    pub fn auto_split(&self) -> &AutoSplit {
        &self.auto
    }

    /// Whether `stage` splits its work at `bodies` bodies: never in
    /// sequential mode, else as the split policy says.
    pub fn splits(&self, stage: &str, bodies: usize) -> bool {
        self.mode == ExecutionMode::Parallel && (self.fine_grained || self.split.splits(stage, bodies, &self.auto))
    }

    /// How the stage named `stage` runs its kernels in a world of `bodies`
    /// bodies: split into chunks or whole, as [`splits`](Self::splits)
    /// decides once for all its steps.
    pub fn for_stage(&self, stage: &str, bodies: usize) -> StageExecution<'_> {
        StageExecution {
            execution: self,
            split: self.splits(stage, bodies),
        }
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

    /// Lets the idle workers sleep now instead of polling until
    /// [`WARM_FOR`](super::WARM_FOR) after the last step: for a host whose
    /// own work follows (the window, after a frame's updates, draws).
    pub fn rest(&self) {
        if let Some(warm) = &self.warm {
            warm.rest();
        }
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

    /// Threads a step really runs on: 1 in sequential mode; on Bevy's
    /// pool, the threads it was made with.
    pub fn threads_used(&self) -> usize {
        match (self.mode, self.worker_pool) {
            (ExecutionMode::Sequential, _) => 1,
            (ExecutionMode::Parallel, WorkerPool::Kessler) => self.threads(),
            (ExecutionMode::Parallel, WorkerPool::Bevy) => compute_threads(self.threads()),
        }
    }

    /// Threads a parallel step on Kessler's pool runs on and is cut for:
    /// its threads, no more than the hardware threads left to the steps
    /// ([`leave_threads`](Self::leave_threads)).
    pub fn step_threads(&self) -> usize {
        runners(self.threads(), self.hardware_threads)
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
        let use_pool = self.mode == ExecutionMode::Parallel
            && self.worker_pool == WorkerPool::Kessler
            && self.split_recently.swap(false, Ordering::Relaxed);
        if use_pool { self.pool.install(f) } else { f() }
    }

    /// Runs `kernel` on contiguous chunks of `data` on the pool's threads
    /// (about `chunks_per_thread` per thread, never fewer than `least` items
    /// but in the last; one item each when fine grained) and returns their
    /// results in input order.
    fn map_split<S, R, K>(&self, data: S, chunks_per_thread: usize, least: usize, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        let len = data.len();
        let runners = runners(self.threads(), self.hardware_threads);
        // Fine grained: one-item chunks even where a step asks for more
        // (the filing's), so every boundary is put to the test.
        let chunk = if self.fine_grained {
            1
        } else {
            len.div_ceil(runners * chunks_per_thread).max(least)
        };
        if chunk >= len {
            // One chunk (so also any input of fewer than two items):
            // nothing to hand to another thread.
            return vec![kernel(data)];
        }
        self.split_recently.store(true, Ordering::Relaxed);
        if self.worker_pool == WorkerPool::Bevy {
            // Bevy's pool is made with the threads asked for (if the app
            // did not make it); the chunks are cut for the runners alike.
            return map_on_bevy(data, chunk, self.threads(), &kernel);
        }
        let claims = Claims::new(data, chunk, runners);
        self.pool.install(|| claims.run(&kernel));
        if let Some(warm) = &self.warm {
            warm.after_step(&self.pool, runners);
        }
        claims.into_results()
    }
}

/// One stage's execution at one body count ([`Execution::for_stage`]):
/// every step of the stage runs whole on this thread, or split into
/// contiguous chunks on the worker pool.
#[derive(Clone, Copy, Debug)]
pub struct StageExecution<'a> {
    execution: &'a Execution,
    split: bool,
}

impl StageExecution<'_> {
    /// Whether this stage's steps split their work.
    pub fn splits(&self) -> bool {
        self.split
    }

    /// Which pool the split steps run on.
    pub fn pool(&self) -> WorkerPool {
        self.execution.worker_pool
    }

    /// Threads a split step runs on ([`Execution::step_threads`]).
    pub fn runners(&self) -> usize {
        self.execution.step_threads()
    }

    /// Runs `kernel` over `data`: whole, on this thread, unless the stage
    /// splits; then on contiguous chunks in the worker pool.
    pub fn for_chunks<S, K>(&self, data: S, kernel: K)
    where
        S: Split,
        K: Fn(S) + Sync,
    {
        self.map_chunks(data, kernel);
    }

    /// Like [`for_chunks`](Self::for_chunks), collecting each chunk's result
    /// in input order (one element when run whole).
    pub fn map_chunks<S, R, K>(&self, data: S, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        self.map_in(data, CHUNKS_PER_THREAD, 1, kernel)
    }

    /// Like [`map_chunks`](Self::map_chunks), in chunks of at least `least`
    /// items: for a step whose every chunk pays a cost that grows with the
    /// input (the sort's filing counts into one slot per grid cell), so
    /// that its work does not grow with the number of threads.
    pub fn map_chunks_of_at_least<S, R, K>(&self, data: S, least: usize, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        self.map_in(data, CHUNKS_PER_THREAD, least, kernel)
    }

    /// Like [`map_chunks`](Self::map_chunks), in `UNEVEN_CHUNKS_PER_THREAD`
    /// smaller chunks per thread: for items that cost unevenly and much
    /// each (the gravity tree's regions and groups), so that no thread
    /// waits long for the last chunk.
    pub fn map_uneven_chunks<S, R, K>(&self, data: S, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        self.map_in(data, UNEVEN_CHUNKS_PER_THREAD, 1, kernel)
    }

    /// `kernel` over `data`: whole, on this thread, unless the stage
    /// splits; then in about `chunks_per_thread` chunks per thread of at
    /// least `least` items.
    fn map_in<S, R, K>(&self, data: S, chunks_per_thread: usize, least: usize, kernel: K) -> Vec<R>
    where
        S: Split,
        R: Send,
        K: Fn(S) -> R + Sync,
    {
        if self.split {
            self.execution.map_split(data, chunks_per_thread, least, kernel)
        } else {
            vec![kernel(data)]
        }
    }
}

/// Threads that run a parallel step of a pool of `threads` on a machine
/// with `cores` hardware threads, and so how many chunks it is cut into:
/// more threads than cores would only take turns on them, one waiting for
/// a core in the middle of its chunk while the others spin waiting for
/// that chunk (16 threads on 2 cores made a 10 000-body update 7 times
/// slower than 2), and every chunk more costs its own start. Which thread
/// runs which chunk, and how the work is cut, never changes a result.
fn runners(threads: usize, cores: usize) -> usize {
    threads.min(cores).max(1)
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

    /// `exec` split as `Always` would: every step in chunks.
    fn always(exec: &Execution) -> StageExecution<'_> {
        exec.for_stage("test", 0)
    }

    fn parallel(threads: usize) -> Execution {
        Execution::new(ExecutionMode::Parallel, threads)
            .unwrap()
            .with_split(SplitPolicy::Always)
    }

    #[test]
    fn parallel_map_keeps_input_order_and_covers_every_item() {
        let exec = parallel(3).as_if_hardware_threads(3);
        let chunks = always(&exec).map_chunks(0..10_007, |r: Range<usize>| r);
        assert_eq!(chunks.len(), 3 * CHUNKS_PER_THREAD, "about four chunks per thread");
        let on_two_cores = parallel(3).as_if_hardware_threads(2);
        let chunks = always(&on_two_cores).map_chunks(0..10_007, |r: Range<usize>| r);
        assert_eq!(
            chunks.len(),
            2 * CHUNKS_PER_THREAD,
            "about four chunks per thread that runs"
        );
        let flat: Vec<usize> = chunks.into_iter().flatten().collect();
        assert_eq!(flat, (0..10_007).collect::<Vec<_>>());
    }

    #[test]
    fn a_host_keeps_the_threads_it_leaves_out_of_the_steps() {
        let left = parallel(3).leave_threads(1);
        let runners = 3.min(available_threads().saturating_sub(1)).max(1);
        let chunks = always(&left).map_chunks(0..10_007, |r: Range<usize>| r);
        assert_eq!(chunks.len(), runners * CHUNKS_PER_THREAD);
        let all = parallel(3).leave_threads(1_000);
        assert_eq!(
            always(&all).map_chunks(0..10_007, |r: Range<usize>| r).len(),
            CHUNKS_PER_THREAD,
            "at least one thread runs"
        );
    }

    #[test]
    fn the_policy_decides_per_stage_and_sequential_mode_never_splits() {
        let exec = parallel(2).with_split(SplitPolicy::Above(1000));
        assert_eq!(
            exec.for_stage("s", 999).map_chunks(0..5000, |r: Range<usize>| r),
            vec![0..5000]
        );
        assert!(exec.for_stage("s", 1000).map_chunks(0..5000, |r: Range<usize>| r).len() > 1);
        let auto = AutoSplit::calibrated(vec![("gravity".into(), 10)], "test");
        let exec = parallel(2).with_split(SplitPolicy::Auto).with_auto_split(auto);
        assert!(exec.for_stage("gravity", 10).splits());
        assert!(
            !exec.for_stage("sweep", 10).splits(),
            "uncalibrated stages use the fallback"
        );
        let seq = Execution::new(ExecutionMode::Sequential, 2)
            .unwrap()
            .with_split(SplitPolicy::Always);
        assert_eq!(
            seq.for_stage("s", 1 << 20)
                .map_chunks(0..1_000_000, |r: Range<usize>| r),
            vec![0..1_000_000]
        );
    }

    #[test]
    fn no_more_threads_run_a_step_than_the_machine_has_cores() {
        assert_eq!(runners(2, 2), 2);
        assert_eq!(runners(16, 16), 16);
        assert_eq!(runners(16, 2), 2);
        assert_eq!(runners(1, 16), 1);
        assert_eq!(runners(4, 0), 1);
    }

    #[test]
    fn chunks_of_at_least_a_size_are_fewer_and_cover_every_item() {
        let exec = parallel(2);
        let chunks = always(&exec).map_chunks_of_at_least(0..1000, 300, |r: Range<usize>| r);
        assert_eq!(chunks, vec![0..300, 300..600, 600..900, 900..1000]);
        // Below the usual chunk size the bound changes nothing.
        assert_eq!(
            always(&exec).map_chunks_of_at_least(0..1000, 2, |r: Range<usize>| r),
            always(&exec).map_chunks(0..1000, |r: Range<usize>| r)
        );
    }

    #[test]
    fn always_splits_even_tiny_work_and_one_item_runs_whole() {
        let exec = parallel(2);
        assert_eq!(
            always(&exec).map_chunks(0..3, |r: Range<usize>| r),
            vec![0..1, 1..2, 2..3]
        );
        assert_eq!(always(&exec).map_chunks(0..1, |r: Range<usize>| r), vec![0..1]);
        assert_eq!(always(&exec).map_chunks(0..0, |r: Range<usize>| r), vec![0..0]);
    }

    #[test]
    fn tuples_of_slices_split_in_lockstep() {
        let exec = parallel(2);
        let a: Vec<u32> = (0..5000).collect();
        let mut b = vec![0u32; 5000];
        always(&exec).for_chunks((a.as_slice(), b.as_mut_slice()), |(a, b): (&[u32], &mut [u32])| {
            for (x, y) in a.iter().zip(b) {
                *y = x * 2;
            }
        });
        assert!(b.iter().enumerate().all(|(i, &y)| y == 2 * i as u32));
    }

    #[test]
    fn uneven_chunks_keep_input_order() {
        let exec = parallel(2);
        // Eight chunks of 8 (four per thread); early chunks are slow, so the
        // other thread claims the later ones.
        let chunks = always(&exec).map_chunks(0..64, |r: Range<usize>| {
            std::thread::sleep(std::time::Duration::from_micros(300 * (8 - r.start as u64 / 8)));
            r.start
        });
        assert_eq!(chunks, (0..64).step_by(8).collect::<Vec<_>>());
    }

    #[test]
    fn a_panicking_chunk_panics_the_step_instead_of_hanging_it() {
        let exec = parallel(2);
        for bad in [0, 7] {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                always(&exec).for_chunks(0..800, |r: Range<usize>| assert!(r.start / 100 != bad, "chunk {bad}"))
            }));
            assert!(outcome.is_err(), "chunk {bad}'s panic was lost");
        }
        // The pool still works afterwards.
        assert_eq!(
            always(&exec).map_chunks(0..400, |r: Range<usize>| r.end - r.start),
            vec![50; 8]
        );
    }

    #[test]
    fn without_keep_warm_the_results_are_the_same() {
        let warm = parallel(2);
        let cold = warm.clone().with_keep_warm(false);
        let sums = |e: &Execution| -> Vec<u64> {
            always(e).map_chunks(0..100_000, |r: Range<usize>| r.map(|i| i as u64).sum())
        };
        assert_eq!(sums(&warm), sums(&cold));
    }

    /// Bevy's compute pool gives the very chunks and results Kessler's
    /// gives, in order.
    #[test]
    fn bevy_s_pool_gives_the_same_chunks_in_the_same_order() {
        let ours = parallel(2);
        let bevy = parallel(2).with_pool(WorkerPool::Bevy);
        for len in [0, 1, 3, 10_007] {
            let chunks = |e: &Execution| always(e).map_chunks(0..len, |r: Range<usize>| r);
            assert_eq!(chunks(&bevy), chunks(&ours), "{len} items");
        }
        let uneven = always(&bevy).map_chunks(0..64, |r: Range<usize>| {
            std::thread::sleep(std::time::Duration::from_micros(300 * (8 - r.start as u64 / 8)));
            r.start
        });
        assert_eq!(uneven, (0..64).step_by(8).collect::<Vec<_>>());
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            always(&bevy).for_chunks(0..800, |r: Range<usize>| assert!(r.start != 300, "one chunk"))
        }));
        assert!(outcome.is_err(), "a chunk's panic was lost");
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
