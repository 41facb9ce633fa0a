//! One parallel step: contiguous chunks, each pool thread first claiming
//! those of its own block, then helping with the others'; each result
//! stored in its chunk's slot; the starting thread waiting for the last
//! chunks spinning rather than asleep.
//!
//! A thread's own block is the same in every step (block `k` belongs to
//! the pool's worker `k`), so across the steps and stages of an update each
//! thread keeps working on the same bodies, which stay in its core's
//! caches; with chunks handed out first come, first served, the bodies
//! would wander between the cores' caches from step to step. Which thread
//! ran which chunk never changes a result.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use super::Split;

/// Chunks per worker thread of a parallel step: a few per thread even out
/// chunks that take unequal time.
pub const CHUNKS_PER_THREAD: usize = 4;

/// Chunks per worker thread of a step whose items cost unevenly and much
/// each ([`StageExecution::map_uneven_chunks`](super::StageExecution::map_uneven_chunks)).
pub const UNEVEN_CHUNKS_PER_THREAD: usize = 32;

/// Spins of a thread waiting for other threads' chunks before it starts
/// yielding its core (each spin is a few nanoseconds).
const SPINS_BEFORE_YIELD: u32 = 100_000;

/// The chunks of one parallel step, in one block per thread: each chunk is
/// claimed once, by its block's thread or a thread done with its own, and
/// its result stored in its slot, so the results keep input order whichever
/// thread ran which chunk.
pub struct Claims<S, R> {
    /// Each chunk's data until claimed, then its result.
    slots: Vec<Mutex<(Option<S>, Option<R>)>>,
    /// Per block: the next chunk to claim and the block's end.
    blocks: Vec<(AtomicUsize, usize)>,
    /// Chunks finished (or panicked).
    finished: AtomicUsize,
}

impl<S: Split, R: Send> Claims<S, R> {
    /// `data` cut into contiguous chunks of `chunk` items (the last may be
    /// shorter), in `threads` blocks of about as many chunks each.
    pub fn new(mut data: S, chunk: usize, threads: usize) -> Self {
        let mut slots = Vec::with_capacity(data.len().div_ceil(chunk));
        while data.len() > chunk {
            let (head, tail) = data.split_at(chunk);
            slots.push(Mutex::new((Some(head), None)));
            data = tail;
        }
        slots.push(Mutex::new((Some(data), None)));
        let count = slots.len();
        let threads = threads.clamp(1, count);
        let blocks = (0..threads)
            .map(|k| (AtomicUsize::new(k * count / threads), (k + 1) * count / threads))
            .collect();
        Self {
            slots,
            blocks,
            finished: AtomicUsize::new(0),
        }
    }

    /// Runs every chunk on this worker and as many other workers of the
    /// current pool as there are blocks, and returns once all chunks are
    /// done. Call it inside the pool (`ThreadPool::install`).
    pub fn run<K: Fn(S) -> R + Sync>(&self, kernel: &K) {
        let helpers = self.blocks.len() - 1;
        rayon::scope(|scope| {
            for _ in 0..helpers {
                scope.spawn(|_| self.claim_all(kernel));
            }
            self.claim_all(kernel);
            self.wait_for_the_others();
        });
    }

    /// Spins until every chunk is finished: on a virtual machine, waking a
    /// sleeping thread costs tens of microseconds, more than the wait it
    /// ends. After [`SPINS_BEFORE_YIELD`] spins the core is yielded between
    /// checks.
    fn wait_for_the_others(&self) {
        let mut spins = 0u32;
        while self.finished.load(Ordering::Acquire) < self.slots.len() {
            spins = spins.saturating_add(1);
            if spins < SPINS_BEFORE_YIELD {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }

    /// Claims and runs the chunks of this thread's own block (the block of
    /// its index in the pool), then those left in the other blocks.
    fn claim_all<K: Fn(S) -> R + Sync>(&self, kernel: &K) {
        let own = rayon::current_thread_index().unwrap_or(0) % self.blocks.len();
        for k in 0..self.blocks.len() {
            let (next, end) = &self.blocks[(own + k) % self.blocks.len()];
            loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                if index >= *end {
                    break;
                }
                // Counts the chunk as finished even if the kernel panics, so
                // the waiting thread stops waiting and the scope passes the
                // panic on.
                let _finish = Finish(&self.finished);
                let slot = &self.slots[index];
                let data = lock(slot).0.take().expect("each chunk is claimed once");
                let result = kernel(data);
                lock(slot).1 = Some(result);
            }
        }
    }

    /// The results, in chunk order.
    pub fn into_results(self) -> Vec<R> {
        self.slots
            .into_iter()
            .map(|slot| {
                let (_, result) = slot.into_inner().unwrap_or_else(PoisonError::into_inner);
                result.expect("every chunk ran")
            })
            .collect()
    }
}

/// Adds one to the finished count when dropped.
struct Finish<'a>(&'a AtomicUsize);

impl Drop for Finish<'_> {
    fn drop(&mut self) {
        self.0.fetch_add(1, Ordering::Release);
    }
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

#[cfg(test)]
mod tests {
    use std::ops::Range;

    use super::*;

    #[test]
    fn chunks_cover_the_input_in_order() {
        let claims: Claims<Range<usize>, Range<usize>> = Claims::new(0..10, 4, 2);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        pool.install(|| claims.run(&|r| r));
        assert_eq!(claims.into_results(), vec![0..4, 4..8, 8..10]);
    }

    #[test]
    fn blocks_split_the_chunks_evenly_and_each_thread_starts_in_its_own() {
        let claims: Claims<Range<usize>, (usize, Option<usize>)> = Claims::new(0..80, 10, 2);
        let ends: Vec<usize> = claims.blocks.iter().map(|b| b.1).collect();
        assert_eq!(ends, [4, 8]);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        pool.install(|| claims.run(&|r: Range<usize>| (r.start, rayon::current_thread_index())));
        let results = claims.into_results();
        assert_eq!(
            results.iter().map(|r| r.0).collect::<Vec<_>>(),
            (0..80).step_by(10).collect::<Vec<_>>()
        );
        // The block of worker 1 starts at chunk 4: whoever ran chunk 4 is
        // worker 1, unless worker 0 finished its block first and stole it.
        let first_of_block = |k: usize| results[k].1;
        assert!(first_of_block(0).is_some() && first_of_block(4).is_some());
    }
}
