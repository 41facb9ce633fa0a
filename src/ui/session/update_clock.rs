//! The update clock: how many simulation updates a frame owes, independent
//! of the frame rate, and what was really achieved.
//!
//! Each frame adds `elapsed × rate` updates to an accumulator. The frame
//! runs the whole updates it owes, but never more than fit in its time
//! budget; what does not fit is dropped rather than carried over, so a slow
//! machine runs the simulation slower instead of spiralling into ever longer
//! frames.

use std::collections::VecDeque;
use std::time::Duration;

use bevy::prelude::*;

/// Longest real time one frame accounts for (a stall, a window drag):
/// beyond this, time is simply lost.
pub const MAX_FRAME_TIME: f64 = 0.25;

/// The accumulator of owed updates and the counters the HUD shows.
#[derive(Resource, Debug, Default)]
pub struct UpdateClock {
    /// Owed updates not yet run (fraction of one, or more while catching up).
    owed: f64,
    /// Updates run, one entry per frame of the last second.
    window: VecDeque<(f64, u32, u32)>,
    /// Updates run since start.
    pub updates_total: u64,
    /// Updates dropped since start because a frame could not fit them.
    pub dropped_total: u64,
}

impl UpdateClock {
    /// Whole updates owed after `elapsed` real seconds at `rate` updates per
    /// second (the fraction is kept for the next frame).
    pub fn owed(&mut self, elapsed: f64, rate: f64) -> u32 {
        let elapsed = elapsed.clamp(0.0, MAX_FRAME_TIME);
        self.owed += elapsed * rate.max(0.0);
        let whole = self.owed.floor();
        self.owed -= whole;
        whole.min(f64::from(u32::MAX)) as u32
    }

    /// Records a frame of `elapsed` seconds that ran `ran` of `owed` updates;
    /// the rest are dropped.
    pub fn record(&mut self, elapsed: f64, owed: u32, ran: u32) {
        let dropped = owed.saturating_sub(ran);
        self.updates_total += u64::from(ran);
        self.dropped_total += u64::from(dropped);
        self.window.push_back((elapsed, ran, dropped));
        let mut span: f64 = self.window.iter().map(|w| w.0).sum();
        while span > 1.0 && self.window.len() > 1 {
            span -= self.window.pop_front().map_or(0.0, |w| w.0);
        }
    }

    /// Achieved updates per second over about the last second.
    pub fn achieved_ups(&self) -> f64 {
        self.per_second(|(_, ran, _)| ran)
    }

    /// Dropped updates per second over about the last second.
    pub fn dropped_per_second(&self) -> f64 {
        self.per_second(|(_, _, dropped)| dropped)
    }

    /// A per-frame count summed over the window, per second.
    fn per_second(&self, count: impl Fn((f64, u32, u32)) -> u32) -> f64 {
        let time: f64 = self.window.iter().map(|w| w.0).sum();
        let total: u64 = self.window.iter().map(|&w| u64::from(count(w))).sum();
        if time > 0.0 { total as f64 / time } else { 0.0 }
    }

    /// Forgets the accumulator (pause, restart), keeping the totals.
    pub fn reset_owed(&mut self) {
        self.owed = 0.0;
    }
}

/// How many of `owed` updates to run when each costs about `update_cost`
/// and the frame may spend `budget` on them: always at least one if any is
/// owed, so the simulation never stalls.
pub fn updates_within_budget(owed: u32, update_cost: Duration, budget: Duration) -> u32 {
    if owed == 0 {
        return 0;
    }
    let cost = update_cost.as_secs_f64().max(1e-9);
    let fit = (budget.as_secs_f64() / cost).floor().max(1.0);
    owed.min(fit.min(f64::from(u32::MAX)) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owed_updates_follow_real_time_not_frames() {
        // 120 updates per second: 2 per frame at 60 fps, 1 per frame at 120.
        let mut clock = UpdateClock::default();
        let at_60: u32 = (0..60).map(|_| clock.owed(1.0 / 60.0, 120.0)).sum();
        let at_144: u32 = (0..144).map(|_| clock.owed(1.0 / 144.0, 120.0)).sum();
        assert!((119..=121).contains(&at_60), "{at_60}");
        assert!((119..=121).contains(&at_144), "{at_144}");
    }

    #[test]
    fn fractions_carry_over_between_frames() {
        // 1 update per second at 8 fps: one update every eighth frame.
        let mut clock = UpdateClock::default();
        let owed: Vec<u32> = (0..16).map(|_| clock.owed(0.125, 1.0)).collect();
        assert_eq!(owed, [[0, 0, 0, 0, 0, 0, 0, 1]; 2].concat());
    }

    #[test]
    fn a_stall_does_not_pile_up_updates() {
        let mut clock = UpdateClock::default();
        // A 10 s stall at 600 UPS owes at most MAX_FRAME_TIME worth.
        let owed = clock.owed(10.0, 600.0);
        assert_eq!(f64::from(owed), (MAX_FRAME_TIME * 600.0).floor());
    }

    #[test]
    fn slow_updates_are_dropped_and_counted() {
        // Updates costing 20 ms with a 50 ms budget: 2 of 10 owed run.
        let ran = updates_within_budget(10, Duration::from_millis(20), Duration::from_millis(50));
        assert_eq!(ran, 2);
        let mut clock = UpdateClock::default();
        for _ in 0..10 {
            clock.record(0.1, 10, ran);
        }
        assert_eq!(clock.updates_total, 20);
        assert_eq!(clock.dropped_total, 80);
        assert!((clock.achieved_ups() - 20.0).abs() < 1e-9);
        assert!((clock.dropped_per_second() - 80.0).abs() < 1e-9);
    }

    #[test]
    fn at_least_one_update_runs_even_when_over_budget() {
        assert_eq!(
            updates_within_budget(3, Duration::from_secs(1), Duration::from_millis(10)),
            1
        );
        assert_eq!(
            updates_within_budget(0, Duration::from_secs(1), Duration::from_millis(10)),
            0
        );
    }
}
