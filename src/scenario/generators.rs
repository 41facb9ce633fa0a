//! Seeded random bodies: the thesis cloud and a debris shell in orbit.

use bevy::math::{DVec3, Vec3};

use super::format::{Body, Cloud, Shape, Shell, Template};
use crate::components::{BodyId, BodyState};
use crate::maths;
use crate::maths::Rng;

/// Draws tried per body before a cloud gives up on finding free space.
const PLACEMENT_TRIES: u32 = 1000;

fn body_state(id: u64, position: DVec3, velocity: DVec3, t: &Template) -> BodyState {
    BodyState::new_box(
        BodyId(id),
        position.as_vec3(),
        velocity.as_vec3(),
        t.mass,
        Vec3::from_array(t.half_extents),
        t.role,
        t.interacts,
    )
}

/// How far a box of `half` at `p` is from the explicit body `b` (its box,
/// or its ball): below 0 they overlap, 0 they touch.
fn gap(p: DVec3, half: DVec3, b: &Body) -> f64 {
    let center = DVec3::from_array(b.position.map(f64::from));
    match b.shape {
        Shape::Box => {
            let reach = DVec3::from_array(b.box_half_extents().map(f64::from)) + half;
            ((p - center).abs() - reach).max_element()
        }
        Shape::Sphere { radius } => {
            let closest = p + (center - p).clamp(-half, half);
            closest.distance(center) - f64::from(radius)
        }
    }
}

/// True when a box of `half` at `p` touches or overlaps an explicit
/// non-interacting body (its box, or its ball).
fn inside_obstacle(p: DVec3, half: DVec3, obstacles: &[Body]) -> bool {
    obstacles
        .iter()
        .filter(|b| !b.interacts)
        .any(|b| gap(p, half, b) <= 0.0)
}

/// A scenario's explicit non-interacting bodies (planets, moons, walls),
/// sorted along x, to find the one a box overlaps among many.
pub struct Obstacles<'a> {
    /// Each body's center along x, its index among the explicit bodies,
    /// and the body; by center.
    sorted: Vec<(f64, usize, &'a Body)>,
    /// The largest half width along x of any of them.
    widest: f64,
}

impl<'a> Obstacles<'a> {
    /// The non-interacting ones of `bodies`.
    pub fn new(bodies: &'a [Body]) -> Self {
        let mut sorted: Vec<(f64, usize, &Body)> = bodies
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.interacts)
            .map(|(i, b)| (f64::from(b.position[0]), i, b))
            .collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let widest = sorted
            .iter()
            .map(|(_, _, b)| f64::from(b.box_half_extents()[0]))
            .fold(0.0, f64::max);
        Self { sorted, widest }
    }

    /// The index (among the explicit bodies) of a non-interacting body that
    /// a box of `half` at `p` overlaps (touching is not overlapping).
    pub fn overlapped(&self, p: DVec3, half: DVec3) -> Option<usize> {
        let reach = half.x + self.widest;
        let first = self.sorted.partition_point(|(x, _, _)| *x < p.x - reach);
        self.sorted[first..]
            .iter()
            .take_while(|(x, _, _)| *x <= p.x + reach)
            .find(|(_, _, b)| gap(p, half, b) < 0.0)
            .map(|(_, i, _)| *i)
    }
}

/// A shell's body would start inside a non-interacting body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StartsInside {
    /// Index of the body within its generator.
    pub body: u64,
    /// Index of the non-interacting body among the explicit ones.
    pub obstacle: usize,
}

/// A cloud's body could not be placed outside the non-interacting bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no free space for body {body}: {PLACEMENT_TRIES} random positions all fell inside non-interacting bodies")]
pub struct NoFreeSpace {
    /// Index of the body within its generator.
    pub body: u64,
}

/// Appends `cloud.count` bodies with ids from `first_id`. Errors when a body
/// cannot be placed outside the non-interacting bodies.
pub fn cloud(
    cloud: &Cloud,
    rng: &mut Rng,
    first_id: u64,
    obstacles: &[Body],
    out: &mut Vec<BodyState>,
) -> Result<(), NoFreeSpace> {
    let center = DVec3::from_array(cloud.center.map(f64::from));
    let half_size = DVec3::from_array(cloud.half_size.map(f64::from));
    let half = DVec3::from_array(cloud.body.half_extents.map(f64::from));
    let speed = f64::from(cloud.max_speed);
    for i in 0..cloud.count {
        let mut tries = 0;
        let position = loop {
            let p = center + DVec3::new(rng.symmetric(1.0), rng.symmetric(1.0), rng.symmetric(1.0)) * half_size;
            if !inside_obstacle(p, half, obstacles) {
                break p;
            }
            tries += 1;
            if tries == PLACEMENT_TRIES {
                return Err(NoFreeSpace { body: i });
            }
        };
        let velocity = DVec3::new(rng.symmetric(speed), rng.symmetric(speed), rng.symmetric(speed));
        out.push(body_state(first_id + i, position, velocity, &cloud.body));
    }
    Ok(())
}

/// Appends `shell.count` bodies on near-circular orbits around `source`
/// (circular speed from its mass alone), with ids from `first_id`. Errors
/// when a body would start inside one of the `obstacles` (its `source`
/// among them: the scenario's check refuses radii that reach into it).
pub fn shell(
    shell: &Shell,
    rng: &mut Rng,
    first_id: u64,
    source: &Body,
    obstacles: &Obstacles<'_>,
    gravitational_constant: f32,
    out: &mut Vec<BodyState>,
) -> Result<(), StartsInside> {
    let half = DVec3::from_array(shell.body.half_extents.map(f64::from));
    let center = DVec3::from_array(source.position.map(f64::from));
    let center_velocity = DVec3::from_array(source.velocity.map(f64::from));
    let gm = f64::from(gravitational_constant) * f64::from(source.mass);
    let (r_in, r_out) = (f64::from(shell.inner_radius), f64::from(shell.outer_radius));
    let max_tilt = f64::from(shell.inclination).to_radians();
    for i in 0..shell.count {
        let r = rng.range(r_in, r_out);
        // Orbit plane: the equator (x–z) tilted about a random line of nodes.
        let node = rng.range(0.0, std::f64::consts::TAU);
        let tilt = rng.range(-max_tilt, max_tilt);
        let plane = maths::rotation_y(node) * maths::rotation_x(tilt);
        let (sin, cos) = maths::sin_cos(rng.range(0.0, std::f64::consts::TAU));
        let radial = plane * DVec3::new(cos, 0.0, sin);
        let normal = plane * DVec3::Y;
        let mut speed = (gm / r).sqrt() * (1.0 + rng.symmetric(f64::from(shell.speed_jitter)));
        if rng.unit() < f64::from(shell.retrograde_fraction) {
            speed = -speed;
        }
        let velocity = center_velocity + normal.cross(radial) * speed;
        let position = center + radial * r;
        if let Some(obstacle) = obstacles.overlapped(position, half) {
            return Err(StartsInside { body: i, obstacle });
        }
        out.push(body_state(first_id + i, position, velocity, &shell.body));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::GravityRole;

    fn planet() -> Body {
        Body {
            id: None,
            position: [0.0; 3],
            previous_position: None,
            velocity: [0.0; 3],
            half_extents: Some([10.0; 3]),
            shape: Shape::Box,
            mass: 100.0,
            role: GravityRole::Source,
            interacts: false,
            absorbs: false,
        }
    }

    #[test]
    fn cloud_stays_in_its_box_and_out_of_obstacles() {
        let c = Cloud {
            count: 2000,
            center: [0.0; 3],
            half_size: [12.0; 3],
            max_speed: 5.0,
            body: Template::default(),
        };
        let mut out = Vec::new();
        cloud(&c, &mut Rng::new(3), 1, &[planet()], &mut out).unwrap();
        assert_eq!(out.len(), 2000);
        assert_eq!((out[0].id, out[1999].id), (BodyId(1), BodyId(2000)));
        for b in &out {
            assert!(b.position.abs().max_element() <= 12.0);
            assert!(
                b.position.abs().max_element() > 11.0,
                "inside the planet: {}",
                b.position
            );
            assert!(b.velocity.abs().max_element() <= 5.0);
        }
    }

    #[test]
    fn a_cloud_fills_a_balls_corners_but_not_the_ball() {
        let ball = Body {
            shape: Shape::Sphere { radius: 10.0 },
            half_extents: None,
            ..planet()
        };
        let c = Cloud {
            count: 2000,
            center: [0.0; 3],
            half_size: [12.0; 3],
            max_speed: 0.0,
            body: Template {
                half_extents: [0.5; 3],
                ..Template::default()
            },
        };
        let mut out = Vec::new();
        cloud(&c, &mut Rng::new(5), 1, &[ball], &mut out).unwrap();
        let nearest = |p: Vec3| (p.abs() - Vec3::splat(0.5)).max(Vec3::ZERO).length();
        assert!(out.iter().all(|b| nearest(b.position) > 10.0), "a cube inside the ball");
        assert!(
            out.iter().any(|b| b.position.abs().max_element() < 10.0),
            "none in the corners of the ball's box, which are free space"
        );
    }

    #[test]
    fn cloud_inside_a_wall_is_an_error() {
        let c = Cloud {
            count: 1,
            center: [0.0; 3],
            half_size: [5.0; 3],
            max_speed: 0.0,
            body: Template::default(),
        };
        assert!(cloud(&c, &mut Rng::new(3), 0, &[planet()], &mut Vec::new()).is_err());
    }

    #[test]
    fn shell_orbits_are_circular_and_within_radius_and_tilt() {
        let s = Shell {
            count: 500,
            around: 0,
            inner_radius: 50.0,
            outer_radius: 80.0,
            inclination: 10.0,
            speed_jitter: 0.0,
            retrograde_fraction: 0.0,
            body: Template::default(),
        };
        let mut out = Vec::new();
        let bodies = [planet()];
        shell(
            &s,
            &mut Rng::new(9),
            1,
            &planet(),
            &Obstacles::new(&bodies),
            2.0,
            &mut out,
        )
        .unwrap();
        for b in &out {
            let (p, v) = (b.position, b.velocity);
            let r = p.length();
            assert!((50.0..=80.0).contains(&r), "radius {r}");
            // Circular: speed² = G·M / r, velocity ⟂ radius.
            assert!((v.length_squared() - 200.0 / r).abs() < 1e-4 * 200.0 / r);
            assert!(p.dot(v).abs() < 1e-3 * r * v.length());
            // Prograde about +y, tilted at most 10°.
            let n = p.cross(v).normalize();
            assert!(
                f64::from(n.y) >= maths::sin_cos(10f64.to_radians()).1 - 1e-5,
                "normal {n}"
            );
        }
    }
}
