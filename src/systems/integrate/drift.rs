//! The integrate stage's kernel: the drift `p += v·dt` (or its second
//! half, with the leapfrog) over the bodies' columns.

use crate::components::{Position, PreviousPosition, Velocity};
use crate::resources::{Integrator, SimulationSettings};

/// The columns the integration kernel reads and writes.
pub type IntegrateColumns<'a> = (&'a [Velocity], &'a mut [Position], &'a mut [PreviousPosition]);

/// How much of an update's drift the integrate stage makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drift {
    /// All of it, `p += v·dt`, keeping the position before as the previous
    /// one: semi-implicit Euler, and either integrator while the gravity
    /// stage is off (with no kick, the leapfrog's two halves are one
    /// straight step).
    Whole,
    /// The second half, `p += v·dt/2`: the leapfrog, whose first half the
    /// gravity stage made (keeping the previous position) before its kick.
    SecondHalf,
}

impl Drift {
    /// The drift the integrate stage makes under `settings`.
    pub fn of(settings: &SimulationSettings) -> Self {
        if settings.stages.gravity && settings.integrator == Integrator::Leapfrog {
            Self::SecondHalf
        } else {
            Self::Whole
        }
    }
}

/// Kernel: the drift for the bodies in the columns, with the velocities the
/// gravity stage's kick left: [`Drift::Whole`] keeps the position as the
/// previous one, then moves it by `v·dt`; [`Drift::SecondHalf`] moves it by
/// `v·dt/2` and leaves the previous one. Returns whether every new position
/// and velocity is finite (the check costs next to nothing in this pass
/// over the same data).
pub fn integrate_kernel((velocities, positions, previous): IntegrateColumns<'_>, dt: f32, drift: Drift) -> bool {
    let mut finite = true;
    let step = match drift {
        Drift::Whole => dt,
        Drift::SecondHalf => dt * 0.5,
    };
    let keep_previous = drift == Drift::Whole;
    for ((v, p), prev) in velocities.iter().zip(positions).zip(previous) {
        if keep_previous {
            prev.0 = p.0;
        }
        p.0 += v.0 * step;
        // With `dt` finite, a non-finite velocity makes the new position
        // non-finite too (∞·dt, NaN·dt; ∞·0 is NaN), so the position alone
        // tells; tested component by component without a branch.
        let q = p.0;
        finite &= q.x.is_finite() & q.y.is_finite() & q.z.is_finite();
    }
    finite
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::math::Vec3;

    #[test]
    fn every_body_drifts_with_its_velocity_and_keeps_its_previous_position() {
        let v = [Velocity(Vec3::new(1.0, -2.0, 0.0)), Velocity(Vec3::ZERO)];
        let mut p = [Position(Vec3::new(10.0, 0.0, 0.0)), Position(Vec3::new(3.0, 4.0, 5.0))];
        let mut prev = [PreviousPosition::default(); 2];
        assert!(integrate_kernel((&v, &mut p, &mut prev), 0.5, Drift::Whole));
        assert_eq!(p[0].0, Vec3::new(10.5, -1.0, 0.0));
        assert_eq!(prev[0].0, Vec3::new(10.0, 0.0, 0.0));
        // A body at rest (a planet) stays put.
        assert_eq!(
            (p[1].0, prev[1].0),
            (Vec3::new(3.0, 4.0, 5.0), Vec3::new(3.0, 4.0, 5.0))
        );
    }

    /// The leapfrog's second half drifts `v·dt/2` and keeps the previous
    /// position the gravity stage's first half set.
    #[test]
    fn the_second_half_drifts_half_a_step_and_keeps_the_previous_position() {
        let v = [Velocity(Vec3::new(1.0, -2.0, 0.0))];
        let mut p = [Position(Vec3::new(10.5, -1.0, 0.0))];
        let mut prev = [PreviousPosition(Vec3::new(10.0, 0.0, 0.0))];
        assert!(integrate_kernel((&v, &mut p, &mut prev), 1.0, Drift::SecondHalf));
        assert_eq!(p[0].0, Vec3::new(11.0, -2.0, 0.0));
        assert_eq!(prev[0].0, Vec3::new(10.0, 0.0, 0.0));
    }

    #[test]
    fn only_the_leapfrog_with_gravity_drifts_in_halves() {
        let drift = |integrator, gravity| {
            Drift::of(&SimulationSettings {
                integrator,
                stages: crate::resources::Stages {
                    gravity,
                    ..crate::resources::Stages::ALL
                },
                ..SimulationSettings::DEFAULT
            })
        };
        assert_eq!(drift(Integrator::Leapfrog, true), Drift::SecondHalf);
        assert_eq!(drift(Integrator::Leapfrog, false), Drift::Whole);
        assert_eq!(drift(Integrator::SemiImplicitEuler, true), Drift::Whole);
    }

    #[test]
    fn an_overflow_is_reported() {
        let v = [Velocity(Vec3::new(3.0e38, 0.0, 0.0)), Velocity(Vec3::ZERO)];
        let mut p = [Position(Vec3::new(1.0e38, 0.0, 0.0)), Position(Vec3::ZERO)];
        let mut prev = [PreviousPosition::default(); 2];
        assert!(
            !integrate_kernel((&v, &mut p, &mut prev), 2.0, Drift::Whole),
            "3e38 · 2 overflows"
        );
        let v = [Velocity(Vec3::new(0.0, f32::NAN, 0.0))];
        let mut p = [Position(Vec3::ZERO)];
        assert!(
            !integrate_kernel((&v, &mut p, &mut prev[..1]), 1.0, Drift::SecondHalf),
            "NaN stays NaN"
        );
    }
}
