//! The swept collision test and response: when a pair first touches on
//! the straight paths its bodies take through what is left of the update,
//! and what happens then (docs/design.md, "Response", "Swept contacts").
//! A body's path starts where the update starts (or where its last contact
//! in this update left it) and ends where it will be at the update's end;
//! `time_order.rs` takes the contacts one after another in time order.
//! Everything here is `f64` arithmetic of correctly rounded operations in a
//! fixed order, so every processor gives the same bits.

use bevy::math::DVec3;

use super::contact::{
    ContactBody, Motion, Outcome, bounce_velocities, least, nearest_on_box, push_shares, respond_to_ball,
};
use crate::physics::Aabb;

/// A body on its straight path through the rest of the update: at `start`
/// at share `from` of the update, at `end` when it ends, moving at
/// `velocity` (the kick's, which a bounce changes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptBody {
    /// Position at share `from` of the update.
    pub start: DVec3,
    /// Position at the update's end.
    pub end: DVec3,
    /// The share of the update (0 to 1) at which the path starts: 0, or
    /// the time of the body's last contact.
    pub from: f64,
    /// Velocity, length units per time unit.
    pub velocity: DVec3,
    /// Mass, > 0.
    pub mass: f64,
    /// Half the box's edge lengths (a ball: its radius in each).
    pub half_extents: DVec3,
    /// False for a non-interacting body (the planet, a wall).
    pub interacts: bool,
    /// True for a ball of radius `half_extents.x`.
    pub spherical: bool,
}

impl From<&ContactBody> for SweptBody {
    /// The body on the path the update's drift gave it: from its previous
    /// position to its position.
    fn from(b: &ContactBody) -> Self {
        Self {
            start: b.previous.as_dvec3(),
            end: b.position.as_dvec3(),
            from: 0.0,
            velocity: b.velocity.as_dvec3(),
            mass: f64::from(b.mass),
            half_extents: b.half_extents.as_dvec3(),
            interacts: b.interacts,
            spherical: b.spherical,
        }
    }
}

impl SweptBody {
    /// Where the body is at share `s` of the update (`s` ≥ `from`).
    pub fn at(&self, s: f64) -> DVec3 {
        let left = 1.0 - self.from;
        if left <= 0.0 {
            return self.end;
        }
        self.start + (self.end - self.start) * ((s - self.from) / left)
    }

    /// The body leaving `position` at share `s` of an update of `dt` with
    /// `velocity`, for the rest of the update.
    pub fn moved_on(&self, s: f64, position: DVec3, velocity: DVec3, dt: f32) -> Self {
        Self {
            start: position,
            end: position + velocity * ((1.0 - s) * f64::from(dt)),
            from: s,
            velocity,
            ..*self
        }
    }

    /// The box its path sweeps, rounded outwards to `f32`.
    pub fn swept_box(&self) -> Aabb {
        let (lo, hi) = (
            self.start.min(self.end) - self.half_extents,
            self.start.max(self.end) + self.half_extents,
        );
        let margin = |v: DVec3| v.abs() * 1e-6 + DVec3::splat(1e-6);
        Aabb {
            min: (lo - margin(lo)).as_vec3(),
            max: (hi + margin(hi)).as_vec3(),
        }
    }

    /// As the discrete kernels see it: where the path starts (as the
    /// previous position) and ends.
    fn as_contact(&self) -> ContactBody {
        ContactBody {
            position: self.end.as_vec3(),
            previous: self.start.as_vec3(),
            velocity: self.velocity.as_vec3(),
            mass: self.mass as f32,
            half_extents: self.half_extents.as_vec3(),
            interacts: self.interacts,
            spherical: self.spherical,
        }
    }
}

/// When a pair meets during the rest of the update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Meeting {
    /// Overlapping already at share `s`, where the later of their paths
    /// starts (boxes: on every axis; a box and a ball: touching).
    Already {
        /// Where the later of the two paths starts.
        s: f64,
    },
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
    /// The share of the update gone by at the touch.
    pub fn time(self) -> f64 {
        match self {
            Self::Already { s } | Self::At { s, .. } => s,
        }
    }
}

/// Kernel: when `a` and `b` first touch on their paths, from where the
/// later of the two starts (touching counts, as in the broad phase; a box
/// meets a ball where its point nearest the ball's center comes within the
/// radius). `None` where they never touch: their swept boxes may overlap
/// although the bodies pass each other.
pub fn first_contact(a: &SweptBody, b: &SweptBody) -> Option<Meeting> {
    if !a.interacts && !b.interacts {
        return None;
    }
    let from = a.from.max(b.from);
    if from >= 1.0 {
        return None;
    }
    match (a.spherical, b.spherical) {
        (false, false) => boxes_meet(a, b, from),
        (false, true) => ball_meets(a, b, from),
        (true, false) => ball_meets(b, a, from),
        // Balls never interact: excluded above.
        (true, true) => None,
    }
}

/// Share `sigma` of the rest of the update after `from`, as a share of
/// the whole update.
fn share(from: f64, sigma: f64) -> f64 {
    from + sigma * (1.0 - from)
}

/// Two boxes: the share of the update where their gap closes on every axis
/// at once, the latest of the axes' entry times, if it comes before any
/// axis opens again.
fn boxes_meet(a: &SweptBody, b: &SweptBody, from: f64) -> Option<Meeting> {
    let start = a.at(from) - b.at(from);
    let change = (a.end - b.end) - start;
    let reach = a.half_extents + b.half_extents;
    // Touching counts as apart here: a pair that touches and closes meets now.
    if (start.abs() - reach).max_element() < 0.0 {
        return Some(Meeting::Already { s: from });
    }
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
    // Not before the paths' start (a pair touching there and parting has
    // its first touch before it), not after the update's end, and only
    // while no axis has opened again.
    if !((0.0..=1.0).contains(&first) && first <= last) {
        return None;
    }
    Some(Meeting::At {
        s: share(from, first),
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
fn ball_meets(cube: &SweptBody, ball: &SweptBody, from: f64) -> Option<Meeting> {
    let radius = ball.half_extents.x;
    let distance = |sigma: f64| nearest_point(cube, ball, share(from, sigma)).1;
    if distance(0.0) < radius {
        return Some(Meeting::Already { s: from });
    }
    // Seen from the ball's center, the box sweeps the box around its two
    // ends: where that stays a radius away, so does the box (most pairs
    // with a planet are its bounding box's corners).
    let half = cube.half_extents;
    let (first, last) = (cube.at(from) - ball.at(from), cube.end - ball.end);
    let (low, high) = (first.min(last) - half, first.max(last) + half);
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
        s: share(from, inside),
        axes: [false; 3],
    })
}

/// At share `s` of the update: the box's point nearest the ball's center,
/// its distance from it, and the ball's center.
fn nearest_point(cube: &SweptBody, ball: &SweptBody, s: f64) -> (DVec3, f64, DVec3) {
    let center = ball.at(s);
    let (nearest, distance) = nearest_on_box(cube.at(s), cube.half_extents, center);
    (nearest, distance, center)
}

/// What a contact does to a pair, in paths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Contact {
    /// Nothing: touching without approaching (a graze), or a pair that
    /// overlapped already and parts.
    Ignore,
    /// Both interacting, and the impact speed reached the threshold.
    Shatter,
    /// A bounce at the touch: each changed body's new path from there
    /// (`None`: unchanged, a non-interacting body).
    Bounce(Option<SweptBody>, Option<SweptBody>),
    /// Overlapping already and not parting: pushed apart where the update
    /// ends, velocities kept (`None`: unchanged).
    Separate(Option<SweptBody>, Option<SweptBody>),
}

impl Contact {
    /// The same contact with the two bodies' parts swapped.
    fn swapped(self) -> Self {
        match self {
            Self::Bounce(a, b) => Self::Bounce(b, a),
            Self::Separate(a, b) => Self::Separate(b, a),
            other => other,
        }
    }
}

/// Kernel: what the contact `meeting` (from [`first_contact`]) does to
/// `a` and `b`. `threshold` is the impact speed `|v1 − v2|` from which
/// interacting bodies shatter, `dt` the time step. At a touch the bounce
/// acts there — on the axes that closed last, the 1-D elastic law (a box
/// against a ball: the reflection about the surface) — and the bodies then
/// move on with their new velocities for the rest of the update. A pair
/// overlapping already parts freely where it parts; otherwise it gets the
/// discrete rule at the update's end (boxes pushed apart, a box pushed out
/// of a ball).
pub fn respond_swept(a: &SweptBody, b: &SweptBody, meeting: Meeting, threshold: f32, dt: f32) -> Contact {
    match meeting {
        Meeting::Already { s } => overlapping(a, b, s),
        Meeting::At { s, axes } => touching(a, b, s, axes, threshold, dt),
    }
}

/// A pair overlapping at share `s`, where the later of the paths starts.
fn overlapping(a: &SweptBody, b: &SweptBody, s: f64) -> Contact {
    if b.spherical {
        return off_ball(a, b);
    }
    if a.spherical {
        return off_ball(b, a).swapped();
    }
    let reach = a.half_extents + b.half_extents;
    let (now, then) = (a.at(s) - b.at(s), a.end - b.end);
    let overlap = reach - then.abs();
    // Apart where the update ends (touching counts as apart).
    if overlap.min_element() <= 0.0 {
        return Contact::Ignore;
    }
    let k = least(overlap);
    // Parting on the axis they would be pushed apart on: they part freely.
    if then[k].abs() > now[k].abs() {
        return Contact::Ignore;
    }
    let direction = if then[k] >= 0.0 { 1.0 } else { -1.0 };
    let (share_a, share_b) = push_shares(a.interacts, b.interacts);
    let pushed = |body: &SweptBody, amount: f64| {
        let mut moved = *body;
        moved.end[k] += amount;
        moved
    };
    Contact::Separate(
        a.interacts.then(|| pushed(a, direction * share_a * overlap[k])),
        b.interacts.then(|| pushed(b, -direction * share_b * overlap[k])),
    )
}

/// A box overlapping a ball: the discrete rule at the update's end.
fn off_ball(cube: &SweptBody, ball: &SweptBody) -> Contact {
    let with_end = |motion: Option<Motion>| {
        motion.map(|m| SweptBody {
            end: m.position.as_dvec3(),
            velocity: m.velocity.as_dvec3(),
            ..*cube
        })
    };
    match respond_to_ball(&cube.as_contact(), &ball.as_contact()) {
        Outcome::Bounce(m, _) | Outcome::Separate(m, _) => Contact::Separate(with_end(m), None),
        Outcome::Ignore | Outcome::Shatter => Contact::Ignore,
    }
}

/// A pair that touches at share `s`, `axes` the box axes that closed last.
fn touching(a: &SweptBody, b: &SweptBody, s: f64, axes: [bool; 3], threshold: f32, dt: f32) -> Contact {
    if b.spherical {
        return bounce_off_ball(a, b, s, dt);
    }
    if a.spherical {
        return bounce_off_ball(b, a, s, dt).swapped();
    }
    let (pa, pb) = (a.at(s), b.at(s));
    let rel = a.velocity - b.velocity;
    let offset = pa - pb;
    let closing = [0, 1, 2].map(|k| axes[k] && rel[k] * offset[k] < 0.0);
    // Touching but not approaching: a graze.
    if !closing.contains(&true) {
        return Contact::Ignore;
    }
    if a.interacts && b.interacts && rel.length() >= f64::from(threshold) {
        return Contact::Shatter;
    }
    let (ua, ub) = bounce_velocities(
        [(a.velocity, a.mass, a.interacts), (b.velocity, b.mass, b.interacts)],
        closing,
    );
    Contact::Bounce(
        a.interacts.then(|| a.moved_on(s, pa, ua, dt)),
        b.interacts.then(|| b.moved_on(s, pb, ub, dt)),
    )
}

/// A box that meets a ball at share `s`: if it approaches the surface
/// there, its velocity relative to the ball is reflected about the normal
/// and it moves on for the rest of the update from the touch (moved out by
/// what the search left inside).
fn bounce_off_ball(cube: &SweptBody, ball: &SweptBody, s: f64, dt: f32) -> Contact {
    let (nearest, distance, center) = nearest_point(cube, ball, s);
    let radius = ball.half_extents.x;
    let normal = (nearest - center)
        .try_normalize()
        .unwrap_or_else(|| (cube.at(s) - center).try_normalize().unwrap_or(DVec3::Y));
    let relative = cube.velocity - ball.velocity;
    let approach = relative.dot(normal);
    if approach >= 0.0 {
        return Contact::Ignore;
    }
    let reflected = ball.velocity + relative - 2.0 * approach * normal;
    let touch = cube.at(s) + normal * (radius - distance).max(0.0);
    Contact::Bounce(Some(cube.moved_on(s, touch, reflected, dt)), None)
}

#[cfg(test)]
mod tests {
    use bevy::prelude::*;

    use super::*;

    /// A unit cube moving from `from` to `to` in one update of `dt` = 1,
    /// with that velocity.
    fn moving(from: [f32; 3], to: [f32; 3], mass: f32) -> SweptBody {
        let (from, to) = (Vec3::from_array(from), Vec3::from_array(to));
        SweptBody::from(&ContactBody {
            position: to,
            previous: from,
            velocity: to - from,
            mass,
            half_extents: Vec3::ONE,
            interacts: true,
            spherical: false,
        })
    }

    fn planet(center: [f32; 3], radius: f32) -> SweptBody {
        SweptBody::from(&ContactBody {
            position: Vec3::from_array(center),
            previous: Vec3::from_array(center),
            velocity: Vec3::ZERO,
            mass: 1000.0,
            half_extents: Vec3::splat(radius),
            interacts: false,
            spherical: true,
        })
    }

    fn aabb(body: &SweptBody) -> Aabb {
        crate::systems::sort::boxes::swept_box(body.start.as_vec3(), body.end.as_vec3(), body.half_extents.as_vec3())
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
        let Contact::Bounce(Some(ma), Some(mb)) = respond_swept(&a, &b, meeting, f32::INFINITY, 1.0) else {
            panic!("a bounce");
        };
        assert_eq!((ma.velocity.x, mb.velocity.x), (-10.0, 10.0));
        // Touching at x = ∓1 at 0.45, then 0.55 of the update at 10 apart.
        assert!(
            (ma.end.x + 6.5).abs() < 1e-9 && (mb.end.x - 6.5).abs() < 1e-9,
            "{ma:?} {mb:?}"
        );
        assert_eq!((ma.from, ma.start.x), (0.45, -1.0), "the new path starts at the touch");
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
        assert!(aabb(&a).overlaps(&aabb(&b)));
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
        let Contact::Bounce(Some(ma), Some(mb)) = respond_swept(&a, &b, meeting, f32::INFINITY, 1.0) else {
            panic!("a bounce");
        };
        // y velocities exchanged, x kept: momentum exactly.
        assert_eq!(ma.velocity, DVec3::new(12.0, 12.0, 0.0));
        assert_eq!(mb.velocity, DVec3::new(0.0, 0.0, 0.0));
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
        let Contact::Bounce(Some(m), None) = respond_swept(&cube, &ball, meeting, 3.0, 1.0) else {
            panic!("a bounce");
        };
        assert_eq!(m.velocity, DVec3::new(-50.0, 0.0, 0.0));
        assert!((m.end.x - (-21.0 - 41.0)).abs() < 1e-6, "{m:?}");
        // A cube passing the ball through its box's corner region: its
        // nearest point comes within 15·√2 ≈ 21.2 of the center, no nearer.
        let beside = moving([-30.0, 16.0, 16.0], [30.0, 16.0, 16.0], 1.0);
        assert!(aabb(&beside).overlaps(&aabb(&ball)));
        assert_eq!(first_contact(&beside, &ball), None);
    }
}
