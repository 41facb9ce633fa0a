//! The update clock: how many simulation updates a frame owes, independent
//! of the frame rate, and what was really achieved.
//!
//! Bevy's clocks keep the time: a `Time<Virtual>` turns the frame's real
//! time into simulated time (stopped while paused, scaled by the speed, a
//! frame's real time capped at [`MAX_FRAME_TIME`]), and a `Time<Fixed>`
//! whose timestep is one update (1/ups) gathers it: each whole timestep is
//! an update owed, the fraction waits for the next frame. They are this
//! clock's own, not the app's resources (ARCHITECTURE.md, "The window": why
//! the app's clocks and `FixedUpdate` cannot drive the updates).
//!
//! The frame runs the whole updates it owes, but never more than fit in its
//! time budget; what does not fit is dropped rather than carried over, so a
//! slow machine runs the simulation slower instead of spiralling into ever
//! longer frames. Bevy has no such budget (its fixed loop runs every step
//! owed), nor the counters the HUD shows: those are written here.

use std::collections::VecDeque;
use std::time::Duration;

use bevy::prelude::*;
use bevy::time::update_virtual_time;

/// Longest real time one frame accounts for (a stall, a window drag):
/// beyond this, time is simply lost (`Time<Virtual>`'s maximum delta).
pub const MAX_FRAME_TIME: Duration = Duration::from_millis(250);

/// The clocks that say how many updates are owed, and the counters the HUD
/// shows.
#[derive(Resource, Debug)]
pub struct UpdateClock {
    /// Simulated time: paused, sped up, a frame's real time capped.
    virt: Time<Virtual>,
    /// One timestep an update; its overstep holds the owed fraction.
    fixed: Time<Fixed>,
    /// Updates run, one entry per frame of the last second.
    window: VecDeque<(f64, u32, u32)>,
    /// Updates run since start.
    pub updates_total: u64,
    /// Updates dropped since start because a frame could not fit them.
    pub dropped_total: u64,
}

impl Default for UpdateClock {
    fn default() -> Self {
        Self {
            virt: Time::<Virtual>::from_max_delta(MAX_FRAME_TIME),
            fixed: Time::<Fixed>::from_duration(timestep(60)),
            window: VecDeque::new(),
            updates_total: 0,
            dropped_total: 0,
        }
    }
}

/// One update's share of simulated time at `updates_per_second`, rounded
/// down to the nanosecond (the rate is never below the one asked for).
fn timestep(updates_per_second: u32) -> Duration {
    Duration::from_nanos(1_000_000_000 / u64::from(updates_per_second.max(1)))
}

impl UpdateClock {
    /// Sets the rate: `updates_per_second` of simulated time, which runs
    /// `speed` times as fast as real time.
    pub fn set_rate(&mut self, updates_per_second: u32, speed: f32) {
        let step = timestep(updates_per_second);
        if self.fixed.timestep() != step {
            self.fixed.set_timestep(step);
        }
        let speed = f64::from(speed);
        self.virt
            .set_relative_speed_f64(if speed.is_finite() { speed.max(0.0) } else { 1.0 });
    }

    /// Stops or restarts simulated time; pausing forgets the owed fraction
    /// (a resumed run does not start with a part-owed update).
    pub fn set_paused(&mut self, paused: bool) {
        if paused {
            self.virt.pause();
            self.forget_fraction();
        } else {
            self.virt.unpause();
        }
    }

    /// Owes exactly one more update (a step while paused).
    pub fn step(&mut self) {
        let step = self.fixed.timestep();
        self.fixed.accumulate_overstep(step);
    }

    /// Forgets the owed fraction (pause, restart), keeping the totals.
    pub fn forget_fraction(&mut self) {
        let overstep = self.fixed.overstep();
        self.fixed.discard_overstep(overstep);
    }

    /// Whole updates owed after a frame that took `real`'s last delta (the
    /// fraction is kept for the next frame).
    pub fn owed(&mut self, real: &Time<Real>) -> u32 {
        update_virtual_time(&mut Time::default(), &mut self.virt, real);
        self.fixed.accumulate_overstep(self.virt.delta());
        let step = self.fixed.timestep();
        let whole = (self.fixed.overstep().as_nanos() / step.as_nanos()).min(u128::from(u32::MAX)) as u32;
        self.fixed.discard_overstep(step * whole);
        whole
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

    /// A clock at `ups` and `speed`, and the real time its frames take.
    fn clock_at(ups: u32, speed: f32) -> (UpdateClock, Time<Real>) {
        let mut clock = UpdateClock::default();
        clock.set_rate(ups, speed);
        let mut real = Time::<Real>::default();
        // The first update only starts the real clock.
        real.update_with_duration(Duration::ZERO);
        (clock, real)
    }

    /// The updates owed by each of `n` frames of `seconds` real time.
    fn frames(clock: &mut UpdateClock, real: &mut Time<Real>, seconds: f64, n: usize) -> Vec<u32> {
        (0..n)
            .map(|_| {
                real.update_with_duration(Duration::from_secs_f64(seconds));
                clock.owed(real)
            })
            .collect()
    }

    #[test]
    fn owed_updates_follow_real_time_not_frames() {
        // 120 updates per second: 2 per frame at 60 fps, 1 per frame at 120.
        let (mut clock, mut real) = clock_at(120, 1.0);
        let at_60: u32 = frames(&mut clock, &mut real, 1.0 / 60.0, 60).iter().sum();
        let at_144: u32 = frames(&mut clock, &mut real, 1.0 / 144.0, 144).iter().sum();
        assert!((119..=121).contains(&at_60), "{at_60}");
        assert!((119..=121).contains(&at_144), "{at_144}");
    }

    #[test]
    fn the_speed_scales_the_rate() {
        for (speed, expected) in [(2.0, 120), (0.5, 30), (8.0, 480)] {
            let (mut clock, mut real) = clock_at(60, speed);
            let owed: u32 = frames(&mut clock, &mut real, 0.1, 10).iter().sum();
            assert!(owed.abs_diff(expected) <= 1, "speed {speed}: {owed}");
        }
    }

    #[test]
    fn fractions_carry_over_between_frames() {
        // 1 update per second at 8 fps: one update every eighth frame.
        let (mut clock, mut real) = clock_at(1, 1.0);
        let owed = frames(&mut clock, &mut real, 0.125, 16);
        assert_eq!(owed, [[0, 0, 0, 0, 0, 0, 0, 1]; 2].concat());
    }

    #[test]
    fn a_stall_does_not_pile_up_updates() {
        // A 10 s stall at 600 UPS owes at most MAX_FRAME_TIME worth, at
        // any speed.
        let (mut clock, mut real) = clock_at(600, 1.0);
        assert_eq!(frames(&mut clock, &mut real, 10.0, 1), [150]);
        let (mut clock, mut real) = clock_at(600, 2.0);
        assert_eq!(frames(&mut clock, &mut real, 10.0, 1), [300]);
    }

    #[test]
    fn a_paused_clock_owes_nothing_but_its_steps() {
        let (mut clock, mut real) = clock_at(60, 1.0);
        // Half an update owed, then paused: the fraction is forgotten.
        assert_eq!(frames(&mut clock, &mut real, 1.0 / 120.0, 1), [0]);
        clock.set_paused(true);
        assert_eq!(frames(&mut clock, &mut real, 0.1, 20), [0; 20]);
        // A step owes exactly one update.
        clock.step();
        assert_eq!(frames(&mut clock, &mut real, 0.1, 2), [1, 0]);
        // Resumed: the rate from there, no catching up on the pause.
        clock.set_paused(false);
        assert_eq!(frames(&mut clock, &mut real, 1.0 / 120.0, 3), [0, 1, 0]);
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
