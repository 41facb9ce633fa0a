//! The collision response's kernel: what happens to one overlapping pair —
//! a bounce with push-back to first contact, a separation of boxes that
//! overlapped already, a shatter, or nothing (docs/design.md, "Response").
//! A box meeting a ball (a planet) is tested against the ball itself and
//! bounces off its surface ([`respond_to_ball`]).
//!
//! Over 600 lines with its unit tests, which stay beside the code they
//! test; the code itself is about 330 lines.

use bevy::math::DVec3;
use bevy::prelude::*;

use crate::components::BodyState;

/// A body in a contact, as the kernel sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactBody {
    /// Position after this update's drift.
    pub position: Vec3,
    /// Position at the start of this update.
    pub previous: Vec3,
    /// Velocity after this update's kick.
    pub velocity: Vec3,
    /// Mass, > 0.
    pub mass: f32,
    /// Half the box's edge lengths.
    pub half_extents: Vec3,
    /// False for a non-interacting body (the planet).
    pub interacts: bool,
    /// True for a ball of radius `half_extents.x` (only non-interacting
    /// bodies are balls).
    pub spherical: bool,
}

impl From<&BodyState> for ContactBody {
    fn from(b: &BodyState) -> Self {
        Self {
            position: b.position,
            previous: b.previous,
            velocity: b.velocity,
            mass: b.mass,
            half_extents: b.half_extents,
            interacts: b.interacts,
            spherical: b.spherical,
        }
    }
}

/// A body's new position and velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// The new position.
    pub position: Vec3,
    /// The new velocity.
    pub velocity: Vec3,
}

/// What happens to a pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// Both non-interacting, or touching without approaching: nothing.
    Ignore,
    /// Both interacting, they met this update (a collision axis is known),
    /// and the impact speed reached the threshold.
    Shatter,
    /// Elastic bounce on the collision axes, then push-back to first contact.
    /// `None` for a body that does not change (a non-interacting one).
    Bounce(Option<Motion>, Option<Motion>),
    /// Already overlapping a step ago: pushed apart along one axis.
    Separate(Option<Motion>, Option<Motion>),
}

impl Outcome {
    /// The same outcome with the two bodies' parts swapped: the response
    /// of a pair written `(b, a)` as that of `(a, b)`.
    pub fn swapped(self) -> Self {
        match self {
            Self::Bounce(a, b) => Self::Bounce(b, a),
            Self::Separate(a, b) => Self::Separate(b, a),
            other => other,
        }
    }
}

/// Axes on which the boxes were apart at their previous positions
/// (touching counts as apart).
pub fn apart_axes(a: &ContactBody, b: &ContactBody) -> [bool; 3] {
    let gap = (a.previous - b.previous).abs() - (a.half_extents + b.half_extents);
    [gap.x >= 0.0, gap.y >= 0.0, gap.z >= 0.0]
}

/// The collision axes: apart at the previous positions and closing, i.e.
/// the relative velocity points from where `a` was towards where `b` was.
/// (Faces that touched and slide along each other do not collide.)
pub fn collision_axes(a: &ContactBody, b: &ContactBody) -> [bool; 3] {
    let apart = apart_axes(a, b);
    let offset = a.previous - b.previous;
    let rel = a.velocity - b.velocity;
    [0, 1, 2].map(|k| apart[k] && rel[k] * offset[k] < 0.0)
}

/// 1-D elastic collision: the new velocities of masses `m1`, `m2`.
pub fn elastic(m1: f64, v1: f64, m2: f64, v2: f64) -> (f64, f64) {
    let m = m1 + m2;
    (
        ((m1 - m2) * v1 + 2.0 * m2 * v2) / m,
        ((m2 - m1) * v2 + 2.0 * m1 * v1) / m,
    )
}

/// Whether a pair that collides shatters: both interact and the impact
/// speed `|v1 − v2|` reaches `threshold`.
pub fn shatters(a: &ContactBody, b: &ContactBody, threshold: f32) -> bool {
    a.interacts && b.interacts && (a.velocity - b.velocity).length() >= threshold
}

/// The bounce's new velocities: on each of `axes`, the 1-D elastic law
/// between two interacting bodies, or a reflection off the one that does
/// not interact (relative to its own motion, which stays); the other axes
/// keep their velocities.
pub fn bounce_on_axes(a: &ContactBody, b: &ContactBody, axes: [bool; 3]) -> (DVec3, DVec3) {
    bounce_velocities(
        [
            (a.velocity.as_dvec3(), f64::from(a.mass), a.interacts),
            (b.velocity.as_dvec3(), f64::from(b.mass), b.interacts),
        ],
        axes,
    )
}

/// [`bounce_on_axes`] of two bodies given as (velocity, mass, interacts).
pub fn bounce_velocities([(va, ma, ia), (vb, mb, ib)]: [(DVec3, f64, bool); 2], axes: [bool; 3]) -> (DVec3, DVec3) {
    let (mut ua, mut ub) = (va, vb);
    for k in (0..3).filter(|&k| axes[k]) {
        (ua[k], ub[k]) = match (ia, ib) {
            (true, true) => elastic(ma, va[k], mb, vb[k]),
            (true, false) => (2.0 * vb[k] - va[k], vb[k]),
            (false, _) => (va[k], 2.0 * va[k] - vb[k]),
        };
    }
    (ua, ub)
}

/// The point of a box (center `center`, half extents `half`) nearest to
/// `point`, and its distance from it.
pub fn nearest_on_box(center: DVec3, half: DVec3, point: DVec3) -> (DVec3, f64) {
    let nearest = center + (point - center).clamp(-half, half);
    (nearest, nearest.distance(point))
}

/// Kernel: the response to one overlapping pair. `threshold` is the impact
/// speed `|v1 − v2|` from which interacting bodies shatter; `dt` the time step.
pub fn respond(a: &ContactBody, b: &ContactBody, threshold: f32, dt: f32) -> Outcome {
    if !a.interacts && !b.interacts {
        return Outcome::Ignore;
    }
    // A ball never interacts, so its partner is an interacting box.
    if b.spherical {
        return respond_to_ball(a, b);
    }
    if a.spherical {
        return respond_to_ball(b, a).swapped();
    }
    let (pa, pb) = (a.position.as_dvec3(), b.position.as_dvec3());
    let (va, vb) = (a.velocity.as_dvec3(), b.velocity.as_dvec3());
    let reach = (a.half_extents + b.half_extents).as_dvec3();
    // Overlapping already a step ago (e.g. spawned so): no impact
    // happened. A pair that parts on the axis it would be pushed apart on
    // parts freely; one that does not is pushed apart.
    if !apart_axes(a, b).contains(&true) {
        let overlap = reach - (pa - pb).abs();
        let k = least(overlap);
        if (pa[k] - pb[k]).abs() > (f64::from(a.previous[k]) - f64::from(b.previous[k])).abs() {
            return Outcome::Ignore;
        }
        return separate(a, b, overlap);
    }
    let axes = collision_axes(a, b);
    // Apart before, touching now, but not approaching: a graze.
    if !axes.contains(&true) {
        return Outcome::Ignore;
    }
    if shatters(a, b, threshold) {
        return Outcome::Shatter;
    }
    let (ua, ub) = bounce_on_axes(a, b, axes);
    // Time since first contact: the boxes touched once the last collision
    // axis closed. Rewinding by `s` moves the offset `pa − pb` by
    // `−(va − vb)·s`; on axis k it leaves the overlap, on the side the
    // bodies came from, after `s_k = (reach + sign(rel)·offset) / |rel|`.
    let offset = pa - pb;
    let since_contact = (0..3)
        .filter(|&k| axes[k])
        .map(|k| {
            let rel = va[k] - vb[k];
            if rel == 0.0 {
                0.0
            } else {
                (reach[k] + rel.signum() * offset[k]) / rel.abs()
            }
        })
        .fold(f64::INFINITY, f64::min)
        // (Not `clamp`: a time step set to NaN at run time must not panic.)
        .min(f64::from(dt))
        .max(0.0);
    // Rewind along the arrival velocities (relative to a wall, which stays).
    let (back_a, back_b) = match (a.interacts, b.interacts) {
        (true, true) => (va, vb),
        (true, false) => (va - vb, DVec3::ZERO),
        (false, _) => (DVec3::ZERO, vb - va),
    };
    let motion = |p: DVec3, back: DVec3, u: DVec3| Motion {
        position: (p - back * since_contact).as_vec3(),
        velocity: u.as_vec3(),
    };
    Outcome::Bounce(
        a.interacts.then(|| motion(pa, back_a, ua)),
        b.interacts.then(|| motion(pb, back_b, ub)),
    )
}

/// The box's point nearest the ball's center, and its distance from it.
fn nearest_to_center(cube: &ContactBody, ball: &ContactBody) -> (DVec3, f64) {
    nearest_on_box(
        cube.position.as_dvec3(),
        cube.half_extents.as_dvec3(),
        ball.position.as_dvec3(),
    )
}

/// Whether two bodies whose bounding boxes overlap touch: boxes always,
/// a box and a ball where the box's point nearest the ball's center lies
/// within its radius (what [`respond_to_ball`] acts on; the box's corner
/// region does not touch).
pub fn touches(a: &ContactBody, b: &ContactBody) -> bool {
    let within =
        |cube: &ContactBody, ball: &ContactBody| nearest_to_center(cube, ball).1 < f64::from(ball.half_extents.x);
    match (a.spherical, b.spherical) {
        (_, true) => within(a, b),
        (true, false) => within(b, a),
        (false, false) => true,
    }
}

/// A box (`cube`, interacting) against a ball (`ball`, which does not
/// move in a collision). The box touches the ball when its point nearest the
/// ball's center is within the radius (see [`touches`]); a box whose bounding boxes overlap
/// the ball's but which stays outside the ball (its "corner region") is
/// ignored. On contact the box is pushed out along the surface normal until
/// it touches, and, if it was approaching, its velocity relative to the
/// ball is reflected about that normal (a bounce; a separation otherwise).
pub fn respond_to_ball(cube: &ContactBody, ball: &ContactBody) -> Outcome {
    let (p, center) = (cube.position.as_dvec3(), ball.position.as_dvec3());
    let half = cube.half_extents.as_dvec3();
    let radius = f64::from(ball.half_extents.x);
    let (nearest, distance) = nearest_to_center(cube, ball);
    if distance >= radius {
        return Outcome::Ignore;
    }
    // Outward normal and the push that makes the box touch the ball: moving
    // the box by `push` along `normal` moves its nearest point as far.
    let (normal, push) = if distance > 0.0 {
        ((nearest - center) / distance, radius - distance)
    } else {
        // The ball's center inside the box: out along the line of centers
        // until the box's nearest face is a radius away.
        let normal = (p - center).try_normalize().unwrap_or(DVec3::Y);
        let support = (half * normal.abs()).element_sum();
        (normal, radius + support - (p - center).dot(normal))
    };
    let velocity = cube.velocity.as_dvec3();
    let ball_velocity = ball.velocity.as_dvec3();
    let relative = velocity - ball_velocity;
    let approach = relative.dot(normal);
    let position = (p + normal * push).as_vec3();
    if approach < 0.0 {
        let reflected = relative - 2.0 * approach * normal;
        let motion = Motion {
            position,
            velocity: (ball_velocity + reflected).as_vec3(),
        };
        Outcome::Bounce(Some(motion), None)
    } else {
        let motion = Motion {
            position,
            velocity: cube.velocity,
        };
        Outcome::Separate(Some(motion), None)
    }
}

/// The axis of least overlap (ties: the lowest).
pub fn least(overlap: DVec3) -> usize {
    (0..3).fold(0, |best, k| if overlap[k] < overlap[best] { k } else { best })
}

/// How a push apart is shared between two bodies that interact or not:
/// half each when both do, all of it to the one that does otherwise.
pub fn push_shares(a_interacts: bool, b_interacts: bool) -> (f64, f64) {
    match (a_interacts, b_interacts) {
        (true, true) => (0.5, 0.5),
        (true, false) => (1.0, 0.0),
        (false, _) => (0.0, 1.0),
    }
}

/// Pushes the boxes apart along the axis of least overlap (ties: lowest
/// axis), half each when both interact; velocities unchanged.
fn separate(a: &ContactBody, b: &ContactBody, overlap: DVec3) -> Outcome {
    let k = least(overlap);
    let (pa, pb) = (a.position.as_dvec3(), b.position.as_dvec3());
    let direction = if pa[k] >= pb[k] { 1.0 } else { -1.0 };
    let (share_a, share_b) = push_shares(a.interacts, b.interacts);
    let shift = |p: DVec3, amount: f64| {
        let mut p = p;
        p[k] += amount;
        p.as_vec3()
    };
    let motion = |body: &ContactBody, position| Motion {
        position,
        velocity: body.velocity,
    };
    Outcome::Separate(
        a.interacts
            .then(|| motion(a, shift(pa, direction * share_a * overlap[k]))),
        b.interacts
            .then(|| motion(b, shift(pb, -direction * share_b * overlap[k]))),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(x: f32, vx: f32, mass: f32) -> ContactBody {
        ContactBody {
            position: Vec3::new(x, 0.0, 0.0),
            previous: Vec3::new(x - vx, 0.0, 0.0),
            velocity: Vec3::new(vx, 0.0, 0.0),
            mass,
            half_extents: Vec3::ONE,
            interacts: true,
            spherical: false,
        }
    }

    fn bounce(outcome: Outcome) -> (Option<Motion>, Option<Motion>) {
        match outcome {
            Outcome::Bounce(a, b) => (a, b),
            other => panic!("expected a bounce, got {other:?}"),
        }
    }

    fn gap_x(a: Vec3, b: Vec3) -> f32 {
        (a.x - b.x).abs() - 2.0
    }

    #[test]
    fn equal_masses_swap_velocities_head_on() {
        // 0.6 apart on x when they last moved, now overlapping by 0.4.
        let (a, b) = (cube(-0.8, 1.0, 2.0), cube(0.8, -1.0, 2.0));
        let (ma, mb) = bounce(respond(&a, &b, 3.0, 1.0));
        let (ma, mb) = (ma.unwrap(), mb.unwrap());
        assert_eq!(
            (ma.velocity, mb.velocity),
            (Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0))
        );
        // Pushed back to where they first touched: x = ∓1.
        assert!(gap_x(ma.position, mb.position).abs() < 1e-6);
        assert!((ma.position.x + 1.0).abs() < 1e-6 && (mb.position.x - 1.0).abs() < 1e-6);
    }

    #[test]
    fn unequal_masses_follow_the_elastic_formula_and_keep_momentum_and_energy() {
        let (m1, m2, v1, v2) = (3.0f32, 1.0f32, 1.5f32, -0.5f32);
        let (a, b) = (cube(-0.9, v1, m1), cube(0.9, v2, m2));
        let (ma, mb) = bounce(respond(&a, &b, 10.0, 1.0));
        let (u1, u2) = (ma.unwrap().velocity.x, mb.unwrap().velocity.x);
        let expected1 = ((m1 - m2) * v1 + 2.0 * m2 * v2) / (m1 + m2);
        let expected2 = ((m2 - m1) * v2 + 2.0 * m1 * v1) / (m1 + m2);
        assert!(
            (u1 - expected1).abs() < 1e-6 && (u2 - expected2).abs() < 1e-6,
            "{u1} {u2}"
        );
        assert!((m1 * v1 + m2 * v2 - (m1 * u1 + m2 * u2)).abs() < 1e-5, "momentum");
        let energy = |x: f32, y: f32| 0.5 * m1 * x * x + 0.5 * m2 * y * y;
        assert!((energy(v1, v2) - energy(u1, u2)).abs() < 1e-5, "kinetic energy");
    }

    #[test]
    fn bounces_straight_back_off_a_wall() {
        // The wall spans x ∈ [1, 21]; the body reaches 1.5, coming from −0.5.
        let wall = ContactBody {
            position: Vec3::new(11.0, 0.0, 0.0),
            previous: Vec3::new(11.0, 0.0, 0.0),
            velocity: Vec3::ZERO,
            mass: 4000.0,
            half_extents: Vec3::splat(10.0),
            interacts: false,
            spherical: false,
        };
        let mut body = cube(0.5, 2.0, 1.0);
        body.velocity.y = 0.25;
        body.previous.y = -0.25;
        let (m, w) = bounce(respond(&body, &wall, 1.0, 1.0));
        assert_eq!(w, None, "the wall never moves");
        let m = m.unwrap();
        assert_eq!(m.velocity, Vec3::new(-2.0, 0.25, 0.0), "x reversed, y kept");
        // Overlap 0.5 at closing speed 2: contact began 0.25 ago.
        assert!(
            m.position.x.abs() < 1e-6,
            "pushed back to touch the wall: {}",
            m.position
        );
    }

    #[test]
    fn faster_body_moves_back_further_and_still_one_stays() {
        let still = ContactBody {
            previous: Vec3::new(1.0, 0.0, 0.0),
            ..cube(1.0, 0.0, 1.0)
        };
        let mover = cube(-0.5, 2.0, 1.0);
        let (ma, mb) = bounce(respond(&mover, &still, 10.0, 1.0));
        let (ma, mb) = (ma.unwrap(), mb.unwrap());
        assert_eq!(mb.position, still.position, "a stationary body stays put");
        assert!(gap_x(ma.position, mb.position).abs() < 1e-6, "touching after push-back");
    }

    #[test]
    fn pushed_back_boxes_touch_without_overlap_on_random_contacts() {
        let mut rng = crate::maths::Rng::new(11);
        let mut r = |lo: f64, hi: f64| rng.range(lo, hi) as f32;
        for _ in 0..1000 {
            let (ha, hb) = (
                Vec3::new(r(0.5, 2.0), r(0.5, 2.0), r(0.5, 2.0)),
                Vec3::new(r(0.5, 2.0), r(0.5, 2.0), r(0.5, 2.0)),
            );
            let (va, vb) = (
                Vec3::new(r(-3.0, 3.0), r(-3.0, 3.0), r(-3.0, 3.0)),
                Vec3::new(r(-3.0, 3.0), r(-3.0, 3.0), r(-3.0, 3.0)),
            );
            let pa = Vec3::new(r(-1.0, 1.0), r(-1.0, 1.0), r(-1.0, 1.0)) * (ha + hb) * 0.5;
            let a = ContactBody {
                position: pa,
                previous: pa - va,
                velocity: va,
                mass: r(0.5, 4.0),
                half_extents: ha,
                interacts: true,
                spherical: false,
            };
            let b = ContactBody {
                position: Vec3::ZERO,
                previous: -vb,
                velocity: vb,
                mass: r(0.5, 4.0),
                half_extents: hb,
                interacts: true,
                spherical: false,
            };
            if let Outcome::Bounce(Some(ma), Some(mb)) = respond(&a, &b, 100.0, 1.0) {
                let gap = (ma.position - mb.position).abs() - (ha + hb);
                let tolerance = 1e-5 * (1.0 + ma.position.abs().max_element());
                assert!(gap.max_element() >= -tolerance, "still overlapping: gap {gap}");
                assert!(gap.max_element() <= tolerance, "not touching: gap {gap}");
            }
        }
    }

    #[test]
    fn already_overlapping_boxes_separate_along_the_least_overlap() {
        // Closing on y (1.75 apart a step ago, 1.5 now): pushed apart.
        let a = ContactBody {
            previous: Vec3::new(0.0, -0.25, 0.0),
            ..cube(0.0, 0.0, 1.0)
        };
        let b = ContactBody {
            position: Vec3::new(0.5, 1.5, 0.25),
            previous: Vec3::new(0.5, 1.5, 0.25),
            ..cube(0.0, 0.0, 1.0)
        };
        match respond(&a, &b, 3.0, 1.0) {
            Outcome::Separate(Some(ma), Some(mb)) => {
                // Overlaps: x 1.5, y 0.5, z 1.75 → y, 0.25 each.
                assert_eq!(ma.position, Vec3::new(0.0, -0.25, 0.0));
                assert_eq!(mb.position, Vec3::new(0.5, 1.75, 0.25));
            }
            other => panic!("expected a separation, got {other:?}"),
        }
        // Parting on y (0 apart a step ago, 1.5 now): they part freely.
        let parting = ContactBody {
            previous: Vec3::new(0.0, 1.5, 0.0),
            ..a
        };
        assert_eq!(respond(&parting, &b, 3.0, 1.0), Outcome::Ignore);
    }

    #[test]
    fn grazing_faces_neither_bounce_nor_shatter() {
        // Faces touching on x a step ago and now; overlapping on y and z and
        // sliding past each other on z at 1.5 — above the threshold of 1.
        let a = ContactBody {
            position: Vec3::new(0.0, 0.0, 0.25),
            previous: Vec3::new(0.0, 0.0, -0.5),
            velocity: Vec3::new(0.0, 0.0, 0.75),
            ..cube(0.0, 0.0, 1.0)
        };
        let b = ContactBody {
            position: Vec3::new(2.0, 0.0, -0.25),
            previous: Vec3::new(2.0, 0.0, 0.5),
            velocity: Vec3::new(0.0, 0.0, -0.75),
            ..cube(2.0, 0.0, 1.0)
        };
        assert_eq!(apart_axes(&a, &b), [true, false, false]);
        assert_eq!(collision_axes(&a, &b), [false; 3]);
        assert_eq!(respond(&a, &b, 1.0, 1.0), Outcome::Ignore);
    }

    #[test]
    fn a_nan_time_step_does_not_panic() {
        let (a, b) = (cube(-0.9, 1.0, 1.0), cube(0.9, -1.0, 1.0));
        assert!(matches!(respond(&a, &b, 10.0, f32::NAN), Outcome::Bounce(..)));
    }

    #[test]
    fn shatters_from_the_threshold_on_and_not_below() {
        let (a, b) = (cube(-0.9, 1.5, 1.0), cube(0.9, -1.5, 1.0));
        assert_eq!(respond(&a, &b, 3.0, 1.0), Outcome::Shatter);
        assert!(matches!(respond(&a, &b, 3.0001, 1.0), Outcome::Bounce(..)));
        let wall = ContactBody { interacts: false, ..b };
        assert!(
            matches!(respond(&a, &wall, 0.1, 1.0), Outcome::Bounce(..)),
            "walls never shatter"
        );
    }

    fn ball(radius: f32) -> ContactBody {
        ContactBody {
            position: Vec3::ZERO,
            previous: Vec3::ZERO,
            velocity: Vec3::ZERO,
            mass: 4000.0,
            half_extents: Vec3::splat(radius),
            interacts: false,
            spherical: true,
        }
    }

    /// Distance from the ball's center (the origin) to the box's nearest point.
    fn reach(position: Vec3, half: Vec3) -> f32 {
        (position.abs() - half).max(Vec3::ZERO).length()
    }

    #[test]
    fn a_box_in_the_corner_of_a_balls_box_is_left_alone() {
        // Inside the ball's bounding box (|x|, |y|, |z| < 10 + 1) but 5.3
        // from the surface.
        let corner = ContactBody {
            position: Vec3::splat(9.0),
            previous: Vec3::splat(9.5),
            velocity: Vec3::splat(-0.5),
            ..cube(0.0, 0.0, 1.0)
        };
        assert_eq!(respond(&corner, &ball(10.0), 1.0, 1.0), Outcome::Ignore);
        assert_eq!(respond(&ball(10.0), &corner, 1.0, 1.0), Outcome::Ignore);
    }

    #[test]
    fn a_box_hitting_a_ball_touches_it_after_with_its_normal_velocity_reflected() {
        let mut rng = crate::maths::Rng::new(5);
        for _ in 0..1000 {
            let direction = Vec3::new(
                rng.symmetric(1.0) as f32,
                rng.symmetric(1.0) as f32,
                rng.symmetric(1.0) as f32,
            )
            .normalize();
            let half = Vec3::splat(rng.range(0.2, 2.0) as f32);
            let velocity = -direction * 2.0 + Vec3::new(0.3, -0.2, 0.1);
            let mut planet = ball(50.0);
            planet.velocity = Vec3::new(0.0, 0.0, -0.5);
            // The box's center 0.5 inside the distance at which it would touch.
            let center_distance = |d: f32| {
                let p = direction * d;
                reach(p, half) - 50.0
            };
            let (mut lo, mut hi) = (0.0f32, 100.0f32);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if center_distance(mid) < 0.0 { lo = mid } else { hi = mid }
            }
            let body = ContactBody {
                position: direction * (lo - 0.5),
                previous: direction * (lo - 0.5) - velocity,
                velocity,
                half_extents: half,
                ..cube(0.0, 0.0, 1.0)
            };
            let (Some(m), None) = bounce(respond(&body, &planet, 0.0, 1.0)) else {
                panic!("the ball does not move");
            };
            let gap = reach(m.position, half) - 50.0;
            assert!(gap.abs() < 1e-3, "touching after the push: gap {gap}");
            // The normal at the contact: from the center to the nearest point.
            let nearest = m.position + (-m.position).clamp(-half, half);
            let normal = nearest.normalize();
            let (before, after) = (velocity - planet.velocity, m.velocity - planet.velocity);
            assert!(
                (after.dot(normal) + before.dot(normal)).abs() < 1e-4,
                "normal velocity reflected"
            );
            let tangential = |v: Vec3| v - v.dot(normal) * normal;
            assert!(
                (tangential(after) - tangential(before)).length() < 1e-4,
                "tangential kept"
            );
        }
    }

    #[test]
    fn a_box_leaving_a_ball_is_pushed_out_without_a_bounce() {
        let body = ContactBody {
            position: Vec3::new(10.5, 0.0, 0.0),
            previous: Vec3::new(10.0, 0.0, 0.0),
            velocity: Vec3::new(0.5, 0.0, 0.0),
            ..cube(0.0, 0.0, 1.0)
        };
        match respond(&ball(12.0), &body, 0.0, 1.0) {
            Outcome::Separate(None, Some(m)) => {
                assert_eq!(m.velocity, body.velocity);
                assert!((m.position.x - 13.0).abs() < 1e-5, "{}", m.position);
            }
            other => panic!("expected a separation, got {other:?}"),
        }
    }
}
