//! [`ThreadCopies`]: each pool thread's own copy of a slice that a
//! parallel step reads at random.
//!
//! A step whose chunks read shared input by index, in an order unrelated
//! to the input's (the sort's repair reads each box in cell order), finds
//! half of it in the other core's cache on two cores, freshly written by
//! the step before, and pays a transfer for every line it touches. A copy
//! read in order first, by the thread that then reads it at random, pays
//! for those lines once, in order, and the random reads hit its own
//! caches. Every copy is the same items, so which thread reads which copy
//! never changes a result.

use std::sync::Mutex;

/// One copy: the generation it was made for and its items.
struct Made<T> {
    generation: u64,
    items: Vec<T>,
}

/// Copies of a slice, one per thread of the pool that runs a step, each
/// made by its thread the first time it asks in a generation
/// ([`renew`](Self::renew)). Made for input of modest size (a copy per
/// thread): the sort uses it only where it repairs, up to 25 000 boxes.
pub struct ThreadCopies<T> {
    /// Slot 0 for a thread outside any rayon pool, slot `k + 1` for the
    /// pool's thread `k`.
    copies: Vec<Mutex<Made<T>>>,
    /// The generation a copy must have to be read.
    generation: u64,
}

impl<T> Default for ThreadCopies<T> {
    fn default() -> Self {
        Self {
            copies: Vec::new(),
            generation: 1,
        }
    }
}

impl<T: Clone + Send> ThreadCopies<T> {
    /// Makes every copy out of date (the slice it copies changed) and
    /// keeps a slot for each of up to `threads` pool threads.
    pub fn renew(&mut self, threads: usize) {
        self.generation += 1;
        if self.copies.len() < threads + 1 {
            self.copies.resize_with(threads + 1, || {
                Mutex::new(Made {
                    generation: 0,
                    items: Vec::new(),
                })
            });
        }
    }

    /// Calls `read` with this thread's copy of `shared`, made now if it is
    /// out of date; with `shared` itself where this thread has no slot or
    /// its slot is busy (another thread of the same index, as on Bevy's
    /// pool, whose threads rayon does not number).
    pub fn read<R>(&self, shared: &[T], read: impl FnOnce(&[T]) -> R) -> R {
        let slot = rayon::current_thread_index().map_or(0, |k| k + 1);
        let Some(mut mine) = self.copies.get(slot).and_then(|m| m.try_lock().ok()) else {
            return read(shared);
        };
        if mine.generation != self.generation {
            mine.items.clear();
            mine.items.extend_from_slice(shared);
            mine.generation = self.generation;
        }
        read(&mine.items)
    }

    /// Frees the copies (they are made again when asked).
    pub fn free(&mut self) {
        self.copies = Vec::new();
    }

    /// Bytes the copies hold (for tests).
    #[cfg(test)]
    pub(crate) fn capacity_bytes(&self) -> usize {
        self.copies
            .iter()
            .map(|m| {
                m.lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .items
                    .capacity()
                    * size_of::<T>()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `items` is `shared` itself rather than a copy.
    fn is_shared<T>(items: &[T], shared: &[T]) -> bool {
        std::ptr::eq(items, shared)
    }

    #[test]
    fn each_thread_reads_its_own_copy_of_the_current_slice() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let mut copies = ThreadCopies::default();
        for round in 0..3u32 {
            let shared: Vec<u32> = (0..1000).map(|i| i * (round + 1)).collect();
            copies.renew(2);
            let seen: Vec<(Vec<u32>, bool, usize)> = pool.install(|| {
                rayon::broadcast(|_| {
                    // Twice on each thread: the second read finds the same copy.
                    let first = copies.read(&shared, |items| items.as_ptr() as usize);
                    copies.read(&shared, |items| (items.to_vec(), is_shared(items, &shared), first))
                })
            });
            for (items, shared_itself, first) in &seen {
                assert_eq!(items, &shared, "round {round}: a copy of the slice as it is now");
                assert!(!shared_itself, "round {round}: a pool thread reads its own copy");
                assert_ne!(*first, shared.as_ptr() as usize);
            }
            assert_ne!(seen[0].2, seen[1].2, "one copy a thread");
        }
        assert!(copies.capacity_bytes() >= 2 * 1000 * size_of::<u32>());
        copies.free();
        assert_eq!(copies.capacity_bytes(), 0);
    }

    #[test]
    fn a_thread_without_a_free_slot_reads_the_slice_itself() {
        let shared = vec![1u8, 2, 3];
        let mut copies = ThreadCopies::default();
        // No slots yet.
        assert!(copies.read(&shared, |items| is_shared(items, &shared)));
        copies.renew(0);
        // This thread's slot (outside a pool: 0), held elsewhere.
        let held = copies.copies[0].lock().unwrap();
        assert!(copies.read(&shared, |items| is_shared(items, &shared)));
        drop(held);
        assert!(copies.read(&shared, |items| items == shared && !is_shared(items, &shared)));
    }
}
