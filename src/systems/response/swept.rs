//! The swept collision test and response: when a pair first touches on the
//! straight lines from its bodies' positions at the update's start to those
//! at its end, and what happens then (docs/design.md, "Response", "Swept
//! contacts"). Everything here is `f64` arithmetic of correctly rounded
//! operations in a fixed order, so every processor gives the same bits.

use bevy::math::DVec3;
use bevy::prelude::*;

use super::contact::{ContactBody, Motion, Outcome, apart_axes, bounce_on_axes, nearest_on_box, respond, shatters};

/// When a pair meets during the update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Meeting {
    /// Overlapping already where the update started (boxes: on every axis;
    /// a box and a ball: touching): today's rule ([`respond`]) acts.
    Already,
    /// First touch at `s`, the share of the update gone by (0 to 1).
    At {
        /// The share of the update at the first touch.
        s: f64,
        /// For two boxes, the axes that closed last (their gap closed at
        /// `s`); for a ball, none.
        axes: [bool; 3],
    },
}

impl Meeting {
    /// The share of the update gone by at the touch: 0 for a pair already
    /// overlapping.
    pub fn time(self) -> f64 {
        match self {
            Self::Already => 0.0,
            Self::At { s, .. } => s,
        }
    }
}

/// Where a body is at share `s` of the update, on the straight line from
/// its previous position to its position.
fn at(body: &ContactBody, s: f64) -> DVec3 {
    let start = body.previous.as_dvec3();
    start + (body.position.as_dvec3() - start) * s
}

/// Kernel: when `a` and `b` first touch during the update, moving on
/// straight lines from their previous positions to their positions
/// (touching counts, as in the broad phase; a box meets a ball where its
/// point nearest the ball's center comes within the radius). `None` where
/// they never touch: their swept boxes may overlap although the bodies
/// pass each other.
pub fn first_contact(a: &ContactBody, b: &ContactBody) -> Option<Meeting> {
    if !a.interacts && !b.interacts {
        return None;
    }
    match (a.spherical, b.spherical) {
        (false, false) => boxes_meet(a, b),
        (false, true) => ball_meets(a, b),
        (true, false) => ball_meets(b, a),
        // Balls never interact: excluded above.
        (true, true) => None,
    }
}

/// Two boxes: the share of the update where their gap closes on every axis
/// at once, the latest of the axes' entry times, if it comes before any
/// axis opens again.
fn boxes_meet(a: &ContactBody, b: &ContactBody) -> Option<Meeting> {
    if !apart_axes(a, b).contains(&true) {
        return Some(Meeting::Already);
    }
    let start = a.previous.as_dvec3() - b.previous.as_dvec3();
    let change = (a.position.as_dvec3() - b.position.as_dvec3()) - start;
    let reach = (a.half_extents + b.half_extents).as_dvec3();
    let (mut enter, mut exit) = ([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]);
    for k in 0..3 {
        if change[k] == 0.0 {
            if start[k].abs() > reach[k] {
                return None;
            }
        } else {
            let (one, other) = ((-reach[k] - start[k]) / change[k], (reach[k] - start[k]) / change[k]);
            (enter[k], exit[k]) = (one.min(other), one.max(other));
        }
    }
    let first = enter[0].max(enter[1]).max(enter[2]);
    let last = exit[0].min(exit[1]).min(exit[2]);
    // Not before the update's start (a pair touching there and parting has
    // its first touch before it), not after its end, and only while no
    // axis has opened again.
    if !((0.0..=1.0).contains(&first) && first <= last) {
        return None;
    }
    Some(Meeting::At {
        s: first,
        axes: enter.map(|e| e == first),
    })
}

/// Iterations of the searches along the update: each halves (bisection)
/// or takes a third off (the minimum) the interval, far below `f64`'s
/// resolution of a share of the update after these many.
const SEARCH_STEPS: u32 = 80;

/// A box and a ball: the first share of the update at which the box's
/// point nearest the ball's center comes within the radius. The distance
/// from the ball's center to the box, both moving on straight lines, is
/// convex in time: its minimum is found by ternary search, the first time
/// within the radius before it by bisection.
fn ball_meets(cube: &ContactBody, ball: &ContactBody) -> Option<Meeting> {
    let radius = f64::from(ball.half_extents.x);
    let distance = |s: f64| nearest_point(cube, ball, s).1;
    if distance(0.0) < radius {
        return Some(Meeting::Already);
    }
    // Seen from the ball's center, the box sweeps the box around its two
    // ends: where that stays a radius away, so does the box (most pairs
    // with a planet are its bounding box's corners).
    let half = cube.half_extents.as_dvec3();
    let (from, to) = (at(cube, 0.0) - at(ball, 0.0), at(cube, 1.0) - at(ball, 1.0));
    let (low, high) = (from.min(to) - half, from.max(to) + half);
    if (DVec3::ZERO.clamp(low, high)).length() >= radius {
        return None;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..SEARCH_STEPS {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if distance(m1) <= distance(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let closest = if distance(1.0) < distance(lo) { 1.0 } else { lo };
    if distance(closest) >= radius {
        return None;
    }
    // distance(outside) ≥ radius > distance(inside), outside < inside.
    let (mut outside, mut inside) = (0.0f64, closest);
    for _ in 0..SEARCH_STEPS {
        let middle = outside + (inside - outside) / 2.0;
        if distance(middle) < radius {
            inside = middle;
        } else {
            outside = middle;
        }
    }
    Some(Meeting::At {
        s: inside,
        axes: [false; 3],
    })
}

/// At share `s` of the update: the box's point nearest the ball's center,
/// its distance from it, and the ball's center.
fn nearest_point(cube: &ContactBody, ball: &ContactBody, s: f64) -> (DVec3, f64, DVec3) {
    let center = at(ball, s);
    let (nearest, distance) = nearest_on_box(at(cube, s), cube.half_extents.as_dvec3(), center);
    (nearest, distance, center)
}

/// Kernel: the response to a pair that met at `meeting` (from
/// [`first_contact`]). `threshold` is the impact speed `|v1 − v2|` from
/// which interacting bodies shatter, `dt` the time step. A pair already
/// overlapping gets today's rule ([`respond`]); otherwise the bounce acts
/// at the touch — on the axes that closed last, the 1-D elastic law (a box
/// against a ball: the reflection about the surface) — and the bodies then
/// move on with their new velocities for the rest of the update, apart.
/// A shatter is placed by [`contact_states`].
pub fn respond_swept(a: &ContactBody, b: &ContactBody, meeting: Meeting, threshold: f32, dt: f32) -> Outcome {
    let (s, axes) = match meeting {
        Meeting::Already => return respond(a, b, threshold, dt),
        Meeting::At { s, axes } => (s, axes),
    };
    let rest = (1.0 - s) * f64::from(dt);
    if b.spherical {
        return bounce_off_ball(a, b, s, rest);
    }
    if a.spherical {
        return bounce_off_ball(b, a, s, rest).swapped();
    }
    let (va, vb) = (a.velocity.as_dvec3(), b.velocity.as_dvec3());
    let offset = a.previous.as_dvec3() - b.previous.as_dvec3();
    let rel = va - vb;
    let closing = [0, 1, 2].map(|k| axes[k] && rel[k] * offset[k] < 0.0);
    // Touching but not approaching (their velocities at the update's end
    // part them): a graze.
    if !closing.contains(&true) {
        return Outcome::Ignore;
    }
    if shatters(a, b, threshold) {
        return Outcome::Shatter;
    }
    let (ua, ub) = bounce_on_axes(a, b, closing);
    let motion = |body: &ContactBody, u: DVec3| Motion {
        position: (at(body, s) + u * rest).as_vec3(),
        velocity: u.as_vec3(),
    };
    Outcome::Bounce(a.interacts.then(|| motion(a, ua)), b.interacts.then(|| motion(b, ub)))
}

/// A box that met a ball at share `s` of the update, `rest` the time left:
/// if it approaches the surface there, its velocity relative to the ball
/// is reflected about the normal and it moves on for the rest of the
/// update from the touch (moved out by what the search left inside).
fn bounce_off_ball(cube: &ContactBody, ball: &ContactBody, s: f64, rest: f64) -> Outcome {
    let (nearest, distance, center) = nearest_point(cube, ball, s);
    let radius = f64::from(ball.half_extents.x);
    let normal = (nearest - center)
        .try_normalize()
        .unwrap_or_else(|| (at(cube, s) - center).try_normalize().unwrap_or(DVec3::Y));
    let (velocity, ball_velocity) = (cube.velocity.as_dvec3(), ball.velocity.as_dvec3());
    let relative = velocity - ball_velocity;
    let approach = relative.dot(normal);
    if approach >= 0.0 {
        return Outcome::Ignore;
    }
    let reflected = ball_velocity + relative - 2.0 * approach * normal;
    let touch = at(cube, s) + normal * (radius - distance).max(0.0);
    Outcome::Bounce(
        Some(Motion {
            position: (touch + reflected * rest).as_vec3(),
            velocity: reflected.as_vec3(),
        }),
        None,
    )
}

/// Where a shattering pair met: each body's position at the touch, and the
/// time left in the update, for which the fragments move on.
pub fn contact_states(a: &ContactBody, b: &ContactBody, meeting: Meeting, dt: f32) -> ([Vec3; 2], f32) {
    match meeting {
        Meeting::Already => ([a.position, b.position], 0.0),
        Meeting::At { s, .. } => (
            [at(a, s).as_vec3(), at(b, s).as_vec3()],
            ((1.0 - s) * f64::from(dt)) as f32,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube moving from `from` to `to` in one update of `dt` = 1,
    /// with that velocity.
    fn moving(from: [f32; 3], to: [f32; 3], mass: f32) -> ContactBody {
        let (from, to) = (Vec3::from_array(from), Vec3::from_array(to));
        ContactBody {
            position: to,
            previous: from,
            velocity: to - from,
            mass,
            half_extents: Vec3::ONE,
            interacts: true,
            spherical: false,
        }
    }

    fn planet(center: [f32; 3], radius: f32) -> ContactBody {
        ContactBody {
            position: Vec3::from_array(center),
            previous: Vec3::from_array(center),
            velocity: Vec3::ZERO,
            mass: 1000.0,
            half_extents: Vec3::splat(radius),
            interacts: false,
            spherical: true,
        }
    }

    /// Head-on at 10 an update each way, 11 apart: they pass through each
    /// other between two updates' ends. Their gap (11 − 2 = 9) closes at
    /// 20 an update: they touch at 9/20 of it, bounce (equal masses swap
    /// velocities) and move apart for the rest, each on its own side.
    #[test]
    fn a_head_on_pair_meets_between_updates_and_bounces_back() {
        let a = moving([-5.5, 0.0, 0.0], [4.5, 0.0, 0.0], 1.0);
        let b = moving([5.5, 0.0, 0.0], [-4.5, 0.0, 0.0], 1.0);
        let meeting = first_contact(&a, &b).unwrap();
        assert_eq!(
            meeting,
            Meeting::At {
                s: 0.45,
                axes: [true, false, false]
            }
        );
        let Outcome::Bounce(Some(ma), Some(mb)) = respond_swept(&a, &b, meeting, f32::INFINITY, 1.0) else {
            panic!("a bounce");
        };
        assert_eq!((ma.velocity.x, mb.velocity.x), (-10.0, 10.0));
        // Touching at x = ∓1 at 0.45, then 0.55 of the update at 10 apart.
        assert!(
            (ma.position.x + 6.5).abs() < 1e-5 && (mb.position.x - 6.5).abs() < 1e-5,
            "{ma:?} {mb:?}"
        );
    }

    /// Swept boxes that overlap (both pass the origin's neighbourhood in
    /// the update) but whose bodies never touch: one passes before the
    /// other arrives.
    #[test]
    fn a_near_miss_whose_swept_boxes_overlap_is_no_contact() {
        // a is within 2 of x = 0 from 0.4 to 0.6 of the update, b within 2
        // of y = 0 only from 0.7 to 0.9.
        let a = moving([-10.0, 0.0, 0.0], [10.0, 0.0, 0.0], 1.0);
        let b = moving([0.0, -16.0, 0.0], [0.0, 4.0, 0.0], 1.0);
        assert!(
            crate::systems::sort::boxes::swept_box(a.previous, a.position, a.half_extents).overlaps(
                &crate::systems::sort::boxes::swept_box(b.previous, b.position, b.half_extents)
            )
        );
        assert_eq!(first_contact(&a, &b), None);
    }

    /// Crossing at right angles: a along x, b along y, meeting at the
    /// origin mid-update. The axis that closed last takes the bounce.
    #[test]
    fn a_right_angle_crossing_bounces_on_the_axis_that_closed_last() {
        let a = moving([-6.0, 0.5, 0.0], [6.0, 0.5, 0.0], 1.0);
        let b = moving([0.0, -6.0, 0.0], [0.0, 6.0, 0.0], 1.0);
        let Some(meeting @ Meeting::At { s, axes }) = first_contact(&a, &b) else {
            panic!("they meet");
        };
        // On x the gap closes at (6 − 2)/12; on y (6.5 − 2)/12, later.
        assert_eq!((s, axes), (4.5 / 12.0, [false, true, false]));
        let Outcome::Bounce(Some(ma), Some(mb)) = respond_swept(&a, &b, meeting, f32::INFINITY, 1.0) else {
            panic!("a bounce");
        };
        // y velocities exchanged, x kept: momentum exactly.
        assert_eq!(ma.velocity, Vec3::new(12.0, 12.0, 0.0));
        assert_eq!(mb.velocity, Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(ma.velocity + mb.velocity, a.velocity + b.velocity);
    }

    /// A cube at 50 an update towards a planet of radius 20 it would pass
    /// through between two updates' ends: it meets the surface and bounces
    /// back, ending the update outside.
    #[test]
    fn a_fast_cube_does_not_tunnel_into_a_ball() {
        let cube = moving([-30.0, 0.0, 0.0], [20.0, 0.0, 0.0], 1.0);
        let ball = planet([0.0, 0.0, 0.0], 20.0);
        let Some(meeting @ Meeting::At { s, .. }) = first_contact(&cube, &ball) else {
            panic!("they meet");
        };
        // The cube's face (x + 1) reaches −20 after 9 of its 50 units.
        assert!((s - 9.0 / 50.0).abs() < 1e-9, "{s}");
        let Outcome::Bounce(Some(m), None) = respond_swept(&cube, &ball, meeting, 3.0, 1.0) else {
            panic!("a bounce");
        };
        assert_eq!(m.velocity, Vec3::new(-50.0, 0.0, 0.0));
        assert!((m.position.x - (-21.0 - 41.0)).abs() < 1e-3, "{m:?}");
        // A cube passing the ball through its box's corner region: its
        // nearest point comes within 15·√2 ≈ 21.2 of the center, no nearer.
        let beside = moving([-30.0, 16.0, 16.0], [30.0, 16.0, 16.0], 1.0);
        let ball_box = crate::systems::sort::boxes::swept_box(ball.previous, ball.position, ball.half_extents);
        assert!(
            crate::systems::sort::boxes::swept_box(beside.previous, beside.position, beside.half_extents)
                .overlaps(&ball_box)
        );
        assert_eq!(first_contact(&beside, &ball), None);
    }
}
