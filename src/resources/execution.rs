//! Sequential or parallel execution of the simulation kernels, chosen at run
//! time — the one place that decides how a kernel is driven.
//!
//! Every stage writes its logic once as a kernel over slices. [`Execution`]
//! either calls that kernel on the whole data (sequential) or splits the data
//! into contiguous chunks and calls the same kernel on each chunk from a rayon
//! pool of exactly `threads` threads (parallel). Results of chunked maps are
//! returned in input order, so reductions and collects see the same sequence
//! in both modes and the state stays bit-identical.

use std::fmt;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use super::KeepWarm;

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

/// How the simulation stages run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
pub enum ExecutionMode {
    /// Every stage on the calling thread.
    Sequential,
    /// Stages split into chunks on a pool of worker threads (falling back to
    /// sequential where the work is too small to pay for the dispatch).
    #[default]
    Parallel,
}

impl ExecutionMode {
    /// Lower-case name as used on the command line and in CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Sequential => "sequential",
            Self::Parallel => "parallel",
        }
    }
}

impl fmt::Display for ExecutionMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Most worker threads a pool may have.
pub const MAX_THREADS: usize = 256;

/// The execution mode, thread count and worker pool of the simulation.
#[derive(Resource, Clone)]
pub struct Execution {
    mode: ExecutionMode,
    pool: Arc<rayon::ThreadPool>,
    /// Ignore the callers' grains and split all work as finely as possible.
    fine_grained: bool,
    /// Set whenever work was split since the last [`install`](Self::install).
    split_recently: Arc<AtomicBool>,
    /// Keeps the pool's other workers awake between the steps of an update.
    warm: Arc<KeepWarm>,
}

impl fmt::Debug for Execution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Execution")
            .field("mode", &self.mode)
            .field("threads", &self.threads())
            .finish()
    }
}

/// The worker pool could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ExecutionError {
    #[error("thread count must be between 1 and {MAX_THREADS}, got {0}")]
    BadThreadCount(usize),
    #[error("could not start {threads} worker threads: {source}")]
    Pool {
        threads: usize,
        source: rayon::ThreadPoolBuildError,
    },
}

impl Execution {
    /// A pool of `threads` workers used in `mode`.
    pub fn new(mode: ExecutionMode, threads: usize) -> Result<Self, ExecutionError> {
        Ok(Self {
            mode,
            pool: Arc::new(build_pool(threads)?),
            fine_grained: false,
            split_recently: Arc::new(AtomicBool::new(true)),
            warm: Arc::default(),
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

    pub fn mode(&self) -> ExecutionMode {
        self.mode
    }

    pub fn set_mode(&mut self, mode: ExecutionMode) {
        self.mode = mode;
    }

    /// Worker threads used in parallel mode.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Replaces the worker pool; a no-op if the count is unchanged.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), ExecutionError> {
        if threads != self.threads() {
            self.pool = Arc::new(build_pool(threads)?);
            self.warm = Arc::default();
        }
        Ok(())
    }

    /// Runs `f` on a worker of the pool in parallel mode when work was split
    /// since the last call (the caller waits), else inline. A whole update
    /// runs this way: when its stages split work, their serial parts then
    /// run on a worker too, so the idle workers, which spin a while before
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
        // A few chunks per thread, claimed in turn, even out uneven chunks.
        let chunk = grain.max(len.div_ceil(self.threads() * CHUNKS_PER_THREAD));
        let claims = Claims::new(data, chunk);
        self.pool.install(|| claims.run(&kernel));
        self.warm.after_step(&self.pool);
        claims.into_results()
    }
}

/// Chunks per worker thread of a parallel step.
const CHUNKS_PER_THREAD: usize = 4;

/// The chunks of one parallel step: each is claimed by the next free thread
/// and its result stored in its slot, so the results keep input order
/// whichever thread ran which chunk.
struct Claims<S, R> {
    /// Each chunk's data until claimed, then its result.
    slots: Vec<Mutex<(Option<S>, Option<R>)>>,
    /// The next chunk to claim.
    next: AtomicUsize,
    /// Chunks finished (or panicked).
    finished: AtomicUsize,
}

impl<S: Split, R: Send> Claims<S, R> {
    /// `data` cut into contiguous chunks of `chunk` items (the last may be
    /// shorter).
    fn new(mut data: S, chunk: usize) -> Self {
        let mut slots = Vec::with_capacity(data.len().div_ceil(chunk));
        while data.len() > chunk {
            let (head, tail) = data.split_at(chunk);
            slots.push(Mutex::new((Some(head), None)));
            data = tail;
        }
        slots.push(Mutex::new((Some(data), None)));
        Self {
            slots,
            next: AtomicUsize::new(0),
            finished: AtomicUsize::new(0),
        }
    }

    /// Runs every chunk on this worker and as many other workers as there
    /// are chunks to share, and returns once all chunks are done. The
    /// calling thread waits for the last chunks of the others spinning, not
    /// asleep: on a virtual machine, waking a sleeping thread costs tens of
    /// microseconds, more than the wait it ends.
    fn run<K: Fn(S) -> R + Sync>(&self, kernel: &K) {
        let helpers = rayon::current_num_threads().min(self.slots.len()) - 1;
        rayon::scope(|scope| {
            for _ in 0..helpers {
                scope.spawn(|_| self.claim_all(kernel));
            }
            self.claim_all(kernel);
            let mut spins = 0u32;
            while self.finished.load(Ordering::Acquire) < self.slots.len() {
                spins += 1;
                if spins < SPINS_BEFORE_YIELD {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
        });
    }

    /// Claims and runs chunks until none is left.
    fn claim_all<K: Fn(S) -> R + Sync>(&self, kernel: &K) {
        loop {
            let index = self.next.fetch_add(1, Ordering::Relaxed);
            let Some(slot) = self.slots.get(index) else {
                return;
            };
            // Counts the chunk as finished even if the kernel panics, so the
            // waiting thread stops waiting and the scope passes the panic on.
            let _finish = Finish(&self.finished);
            let data = lock(slot).0.take().expect("each chunk is claimed once");
            let result = kernel(data);
            lock(slot).1 = Some(result);
        }
    }

    fn into_results(self) -> Vec<R> {
        self.slots
            .into_iter()
            .map(|slot| {
                let (_, result) = slot.into_inner().unwrap_or_else(PoisonError::into_inner);
                result.expect("every chunk ran")
            })
            .collect()
    }
}

/// Spins of a thread waiting for other threads' chunks before it starts
/// yielding its core (each spin is a few nanoseconds).
const SPINS_BEFORE_YIELD: u32 = 100_000;

/// Adds one to the finished count when dropped.
struct Finish<'a>(&'a AtomicUsize);

impl Drop for Finish<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
    }
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
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

/// Hardware threads of this machine (1 if unknown).
pub fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Data that can be cut into two contiguous parts: slices, index ranges and
/// tuples of equally long ones (the columns of one ECS table).
pub trait Split: Sized + Send {
    /// Number of items.
    fn len(&self) -> usize;
    /// True when there are no items.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The first `mid` items and the rest.
    fn split_at(self, mid: usize) -> (Self, Self);
}

impl<T: Sync> Split for &[T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        <[T]>::split_at(self, mid)
    }
}

impl<T: Send> Split for &mut [T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

impl Split for Range<usize> {
    fn len(&self) -> usize {
        self.end.saturating_sub(self.start)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let cut = self.start + mid;
        (self.start..cut, cut..self.end)
    }
}

macro_rules! impl_split_for_tuple {
    ($($column:ident . $index:tt),+) => {
        impl<$($column: Split),+> Split for ($($column,)+) {
            fn len(&self) -> usize {
                let len = self.0.len();
                $(debug_assert_eq!(self.$index.len(), len, "split columns differ in length");)+
                len
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                let halves = ($(self.$index.split_at(mid),)+);
                (($(halves.$index.0,)+), ($(halves.$index.1,)+))
            }
        }
    };
}

impl_split_for_tuple!(A.0, B.1);
impl_split_for_tuple!(A.0, B.1, C.2);
impl_split_for_tuple!(A.0, B.1, C.2, D.3);
impl_split_for_tuple!(A.0, B.1, C.2, D.3, E.4);
impl_split_for_tuple!(A.0, B.1, C.2, D.3, E.4, F.5);

#[cfg(test)]
mod tests {
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
    fn thread_count_is_checked() {
        assert!(Execution::new(ExecutionMode::Parallel, 0).is_err());
        assert!(Execution::new(ExecutionMode::Parallel, MAX_THREADS + 1).is_err());
        let mut exec = Execution::new(ExecutionMode::Parallel, 1).unwrap();
        exec.set_threads(3).unwrap();
        assert_eq!(exec.threads(), 3);
    }
}
