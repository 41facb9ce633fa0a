//! One parallel step: contiguous chunks claimed in turn by the pool's
//! threads, each result stored in its chunk's slot, and the starting thread
//! waiting for the last chunks spinning rather than asleep.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use super::Split;

/// Chunks per worker thread of a parallel step: a few per thread even out
/// chunks that take unequal time.
pub const CHUNKS_PER_THREAD: usize = 4;

/// Spins of a thread waiting for other threads' chunks before it starts
/// yielding its core (each spin is a few nanoseconds).
const SPINS_BEFORE_YIELD: u32 = 100_000;

/// The chunks of one parallel step: each is claimed by the next free thread
/// and its result stored in its slot, so the results keep input order
/// whichever thread ran which chunk.
pub struct Claims<S, R> {
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
    pub fn new(mut data: S, chunk: usize) -> Self {
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

    /// Runs every chunk on this worker and as many other workers of the
    /// current pool as there are chunks to share, and returns once all
    /// chunks are done. Call it inside the pool (`ThreadPool::install`).
    pub fn run<K: Fn(S) -> R + Sync>(&self, kernel: &K) {
        let helpers = rayon::current_num_threads().min(self.slots.len()) - 1;
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
        let claims: Claims<Range<usize>, Range<usize>> = Claims::new(0..10, 4);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        pool.install(|| claims.run(&|r| r));
        assert_eq!(claims.into_results(), vec![0..4, 4..8, 8..10]);
    }
}
