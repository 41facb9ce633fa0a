//! Keeps a pool's idle workers awake for a moment after a parallel step.
//!
//! A rayon worker with nothing to do falls asleep within microseconds, and
//! waking it costs a lot on a virtual machine. Measured on the 2-core CI
//! machine type, a `join` of two 100 µs jobs took 118 µs back to back,
//! 166 µs after a 100 µs pause and 271 µs after 1 ms. One update runs
//! several parallel steps with short serial gaps between them (gravity,
//! integration, three steps of the broad phase, the response), so at
//! 100 000 bodies the wake-ups ate about a sixth of a parallel update.
//!
//! After each parallel step, every other worker therefore polls for new
//! work (`ThreadPool::yield_now`) until [`WARM_FOR`] after the latest step,
//! then sleeps as usual. Only the timing changes: the polling workers run
//! the same jobs a woken worker would.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// How long idle workers keep polling after the latest parallel step:
/// longer than the serial gaps inside an update, short enough that a
/// paused or sequential simulation burns no CPU for long.
pub const WARM_FOR: Duration = Duration::from_millis(1);

/// The polling state of one worker pool.
#[derive(Debug)]
pub struct KeepWarm {
    origin: Instant,
    /// Nanoseconds after `origin` when the pollers stop.
    until: AtomicU64,
    /// Pollers spawned and not yet finished.
    polling: AtomicUsize,
    /// Pool index of the worker that runs the steps, which must never poll
    /// (it would delay its own next step); `usize::MAX` if none.
    driver: AtomicUsize,
}

impl Default for KeepWarm {
    fn default() -> Self {
        Self {
            origin: Instant::now(),
            until: AtomicU64::new(0),
            polling: AtomicUsize::new(0),
            driver: AtomicUsize::new(usize::MAX),
        }
    }
}

impl KeepWarm {
    fn now(&self) -> u64 {
        u64::try_from(self.origin.elapsed().as_nanos()).unwrap_or(u64::MAX)
    }

    /// Called by the driving thread when a parallel step of `pool` ends,
    /// one that ran on `runners` of its threads: moves the deadline and
    /// tops the pollers up to one per runner other than the driver (see
    /// [`pollers`]).
    pub fn after_step(self: &Arc<Self>, pool: &Arc<rayon::ThreadPool>, runners: usize) {
        let deadline = self.now().saturating_add(WARM_FOR.as_nanos() as u64);
        self.until.store(deadline, Ordering::Relaxed);
        let driver = pool.current_thread_index().unwrap_or(usize::MAX);
        self.driver.store(driver, Ordering::Relaxed);
        let wanted = pollers(runners, driver != usize::MAX);
        while self
            .polling
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| (n < wanted).then_some(n + 1))
            .is_ok()
        {
            let (warm, worker_pool) = (Arc::clone(self), Arc::clone(pool));
            pool.spawn(move || {
                warm.poll(&worker_pool);
                warm.polling.fetch_sub(1, Ordering::Relaxed);
            });
        }
    }

    /// Ends the polling now: the pollers go back to sleep at their next
    /// look at the deadline (the host needs the cores, as the window's
    /// frame does once its updates are run).
    pub fn rest(&self) {
        self.until.store(0, Ordering::Relaxed);
    }

    /// Runs pending jobs of `pool` until the deadline passes.
    fn poll(&self, pool: &rayon::ThreadPool) {
        loop {
            if pool.current_thread_index() == Some(self.driver.load(Ordering::Relaxed)) {
                return;
            }
            match pool.yield_now() {
                Some(rayon::Yield::Executed) => {}
                Some(rayon::Yield::Idle) if self.now() < self.until.load(Ordering::Relaxed) => {
                    std::hint::spin_loop();
                }
                _ => return,
            }
        }
    }
}

/// How many workers poll after a step that ran on `runners` threads: one
/// per runner, less the driver where it is one of them. A step runs on no
/// more threads than the machine has (the pool's `runners`), so neither do
/// the pollers: a pool with more workers than cores would otherwise keep
/// every core polling, and the driver's serial work between the steps would
/// wait for its turn on a core (16 workers on 2 cores made a 10 000-body
/// update 7 times slower than 2 workers).
fn pollers(runners: usize, driver_is_a_worker: bool) -> usize {
    runners.saturating_sub(usize::from(driver_is_a_worker))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_more_workers_poll_than_a_step_runs_on() {
        assert_eq!(pollers(2, true), 1);
        assert_eq!(pollers(2, false), 2);
        assert_eq!(pollers(16, true), 15);
        assert_eq!(pollers(1, true), 0);
    }

    #[test]
    fn pollers_stop_after_the_deadline_and_never_exceed_the_other_workers() {
        let pool = Arc::new(rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap());
        let warm = Arc::new(KeepWarm::default());
        pool.install(|| {
            warm.after_step(&pool, 3);
            warm.after_step(&pool, 3);
            // The driver is a worker: the two others may poll.
            assert!(warm.polling.load(Ordering::Relaxed) <= 2);
        });
        let start = Instant::now();
        while warm.polling.load(Ordering::Relaxed) > 0 {
            assert!(start.elapsed() < Duration::from_secs(5), "pollers never stopped");
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn resting_stops_the_pollers_before_their_deadline() {
        let pool = Arc::new(rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap());
        let warm = Arc::new(KeepWarm::default());
        // Stepped from outside the pool: every worker polls. A deadline far
        // off: without a rest they would poll for a minute.
        warm.after_step(&pool, 3);
        warm.until.store(warm.now() + 60_000_000_000, Ordering::Relaxed);
        std::thread::sleep(Duration::from_millis(20));
        assert!(warm.polling.load(Ordering::Relaxed) > 0, "nobody polls");
        warm.rest();
        let start = Instant::now();
        while warm.polling.load(Ordering::Relaxed) > 0 {
            assert!(
                start.elapsed() < Duration::from_secs(5),
                "pollers went on after the rest"
            );
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn polling_workers_run_the_next_step() {
        let pool = Arc::new(rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap());
        let warm = Arc::new(KeepWarm::default());
        let sum: u64 = pool.install(|| {
            warm.after_step(&pool, 2);
            let (a, b) = rayon::join(|| (0..1000u64).sum::<u64>(), || (1000..2000u64).sum::<u64>());
            a + b
        });
        assert_eq!(sum, (0..2000u64).sum::<u64>());
    }
}
