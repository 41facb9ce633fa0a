//! A parallel step on Bevy's `ComputeTaskPool`: the same contiguous chunks
//! as Kessler's own pool cuts, each spawned as a task of one `scope`, each
//! result stored in its chunk's slot, so the results keep input order
//! whichever thread ran which chunk.

use std::sync::{Mutex, PoisonError};

use bevy::tasks::{ComputeTaskPool, TaskPool, TaskPoolBuilder};

use super::Split;

/// Bevy's compute pool, made with `threads − 1` workers if it does not
/// exist yet (the thread that starts a step works on it too, as with
/// Kessler's pool); if the app made it already, it keeps its own count.
pub fn compute_pool(threads: usize) -> &'static TaskPool {
    ComputeTaskPool::get_or_init(|| {
        TaskPoolBuilder::new()
            .num_threads(threads.saturating_sub(1))
            .thread_name("kessler-bevy".to_owned())
            .build()
    })
}

/// Threads a step on Bevy's compute pool runs on: its workers and the
/// starting thread.
pub fn compute_threads(threads: usize) -> usize {
    compute_pool(threads).thread_num() + 1
}

/// Runs `kernel` on `data` cut into contiguous chunks of `chunk` items on
/// Bevy's compute pool; the results in input order.
pub fn map_on_bevy<S, R, K>(mut data: S, chunk: usize, threads: usize, kernel: &K) -> Vec<R>
where
    S: Split,
    R: Send,
    K: Fn(S) -> R + Sync,
{
    let mut chunks = Vec::with_capacity(data.len().div_ceil(chunk.max(1)));
    while data.len() > chunk {
        let (head, tail) = data.split_at(chunk);
        chunks.push(head);
        data = tail;
    }
    chunks.push(data);
    let slots: Vec<Mutex<Option<R>>> = chunks.iter().map(|_| Mutex::new(None)).collect();
    compute_pool(threads).scope(|scope| {
        for (part, slot) in chunks.into_iter().zip(&slots) {
            scope.spawn(async move {
                let result = kernel(part);
                *slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(result);
            });
        }
    });
    slots
        .into_iter()
        .map(|slot| {
            slot.into_inner()
                .unwrap_or_else(PoisonError::into_inner)
                .expect("every chunk ran (a panicking one panics the scope)")
        })
        .collect()
}
