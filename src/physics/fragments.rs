//! Fragments: what two shattering bodies (the response) or one body
//! breaking up (the `Breakup` event) become (docs/design.md, "Shatter").
//!
//! `c` fragments share the pair's mass equally, keep its total box volume
//! (half-extent `l = ∛((h1x·h1y·h1z + h2x·h2y·h2z)/c)`) and its momentum: each
//! starts at the center of mass plus an offset, with the center-of-mass
//! velocity plus an outward spread whose mean is subtracted. Offsets are
//! well-spread directions scaled so that no two fragments touch. The random
//! rotation and speeds come from a stream keyed by the pair's ids, so the
//! result does not depend on how the stage is executed. With
//! `fragment_sizes: PowerLaw`, the edges follow the NASA standard breakup
//! model's power law instead.
//!
//! Over 600 lines with its unit tests, which stay beside the code they
//! test; the code itself is about 400 lines.

use bevy::math::DVec3;
use bevy::prelude::*;

use crate::components::{BodyId, BodyState, GravityRole};
use crate::maths;
use crate::maths::Rng;
use crate::resources::{FragmentSizes, SimulationSettings};

/// Clearance between neighboring fragments, as a share of their edge.
const CLEARANCE: f64 = 0.05;

/// `count` points spread evenly over the unit sphere (a Fibonacci lattice).
fn sphere_points(count: u32) -> Vec<DVec3> {
    let n = f64::from(count);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|i| {
            let y = 1.0 - (f64::from(i) + 0.5) * 2.0 / n;
            let r = (1.0 - y * y).sqrt();
            let (sin, cos) = maths::sin_cos(golden * f64::from(i));
            DVec3::new(r * cos, y, r * sin)
        })
        .collect()
}

/// A box's volume in half-edge units, `hx·hy·hz`.
pub fn box_volume(h: Vec3) -> f64 {
    f64::from(h.x) * f64::from(h.y) * f64::from(h.z)
}

/// Half the edge of each of the `count` fragment cubes of two boxes: the
/// cubes keep the pair's volume, `∛((h1x·h1y·h1z + h2x·h2y·h2z)/count)`.
pub fn fragment_half_extent(a: Vec3, b: Vec3, count: u32) -> f64 {
    maths::cbrt((box_volume(a) + box_volume(b)) / f64::from(count.max(2)))
}

/// The edge the smallest fragments of `volume` (half-edge units) would
/// have, as `sizes` sizes at most `count` of them: the equal cubes', or,
/// for the power law (whose fragments keep to the floor), two halves' —
/// what a shatter and a breakup hold against `min_fragment_size`.
pub fn smallest_fragment_edge(volume: f64, sizes: FragmentSizes, count: u32) -> f64 {
    let pieces = match sizes {
        FragmentSizes::Equal => count,
        FragmentSizes::PowerLaw { .. } => 2,
    };
    2.0 * maths::cbrt(volume / f64::from(pieces.max(2)))
}

/// The least mass and the least half-edge a fragment may have: the
/// smallest normal `f32`. Every fragment a kernel makes has at least these
/// (a shatter or breakup whose fragments could not is refused, see
/// [`fragments_sound`]), so a fragment is always a body a scenario file may
/// hold, and its mass and volume keep their precision.
pub const LEAST_SOUND: f64 = f32::MIN_POSITIVE as f64;

/// Whether the fragments of a parent of `volume` (half-edge units) and
/// `mass`, as `sizes` sizes at most `count` of them, each get a mass and a
/// half-edge of at least [`LEAST_SOUND`]: the equal cubes' share, or, for
/// the power law (whose kernel keeps every fragment above its floor, see
/// [`sound_floor`]), two halves'.
pub fn fragments_sound(volume: f64, mass: f64, sizes: FragmentSizes, count: u32) -> bool {
    let pieces = f64::from(match sizes {
        FragmentSizes::Equal => count.max(2),
        FragmentSizes::PowerLaw { .. } => 2,
    });
    let (half, share) = (maths::cbrt(volume / pieces), mass / pieces);
    // As the fragments will hold them: f32, rounded.
    f64::from(half as f32) >= LEAST_SOUND && f64::from(share as f32) >= LEAST_SOUND
}

/// The least half-edge a power-law fragment of a parent of `volume`
/// (half-edge units) and `mass` may have so that its mass (in proportion
/// to its volume) and its half-edge are at least [`LEAST_SOUND`], with a
/// factor of 2 against rounding.
pub fn sound_floor(volume: f64, mass: f64) -> f64 {
    (2.0 * LEAST_SOUND).max(maths::cbrt(2.0 * LEAST_SOUND * volume / mass))
}

/// Kernel: the fragments of bodies `a` and `b`, with ids from `first_id`.
/// `count` is at least 2 (scenarios reject less, and the response does not
/// shatter with less); a smaller count is taken as 2. `spread` is the
/// fragments' speed away from their center of mass as a share of the impact
/// speed (the thesis's "Streuung"), each fragment's between half of it and
/// all of it.
pub fn fragments(a: &BodyState, b: &BodyState, count: u32, spread: f32, seed: u64, first_id: BodyId) -> Vec<BodyState> {
    let count = count.max(2);
    let half = fragment_half_extent(a.half_extents, b.half_extents, count);
    lay_out(Parent::pair(a, b, spread, seed), first_id, |_| {
        vec![half; count as usize]
    })
}

/// Kernel: the fragments of `a` and `b` as `settings` size them
/// ([`FragmentSizes`]), with ids from `first_id`: `Equal` as
/// [`fragments`], `PowerLaw` as [`power_law_fragments`].
pub fn fragments_for(a: &BodyState, b: &BodyState, settings: &SimulationSettings, first_id: BodyId) -> Vec<BodyState> {
    let (count, spread, seed) = (settings.shatter_fragments, settings.fragment_spread, settings.seed);
    match settings.fragment_sizes {
        FragmentSizes::Equal => fragments(a, b, count, spread, seed, first_id),
        FragmentSizes::PowerLaw { exponent } => {
            let law = PowerLaw {
                count,
                exponent,
                min_size: settings.min_fragment_size,
                spread,
                seed,
            };
            power_law_fragments(a, b, law, first_id)
        }
    }
}

/// The pair's volume in half-edge units (`Σ hx·hy·hz`), and the half-edge
/// of a cube as large as the larger parent.
fn volumes(a: &BodyState, b: &BodyState) -> (f64, f64) {
    let (va, vb) = (box_volume(a.half_extents), box_volume(b.half_extents));
    (va + vb, maths::cbrt(va.max(vb)))
}

/// Half-edges drawn from the truncated power law `N(>L) ∝ L^−exponent`
/// between `smallest` and `largest` until `volume` (in half-edge units) is
/// used, at most `count` of them: a draw that would pass the volume ends
/// the draws, and the last fragment takes the rest (the fragment before it
/// takes the rest instead where the rest is below `smallest`). Each draw
/// inverts the law's distribution, written in ratios so that no power
/// overflows however small `a` is against `b`: `L = a·(1 − u·(1 −
/// (a/b)^α))^(−1/α)` for `u` uniform in [0, 1), at most `b`.
pub fn power_law_halves(
    volume: f64,
    smallest: f64,
    largest: f64,
    count: u32,
    exponent: f32,
    rng: &mut Rng,
) -> Vec<f64> {
    let alpha = f64::from(exponent);
    let kept = 1.0 - maths::pow(smallest / largest, alpha);
    let mut halves: Vec<f64> = Vec::new();
    let mut used = 0.0;
    while halves.len() + 1 < count.max(2) as usize {
        let half = (smallest * maths::pow(1.0 - rng.unit() * kept, -1.0 / alpha)).min(largest);
        let cube = half * half * half;
        if used + cube >= volume {
            break;
        }
        halves.push(half);
        used += cube;
    }
    let rest = volume - used;
    match halves.last_mut() {
        Some(last) if maths::cbrt(rest) < smallest => *last = maths::cbrt(*last * *last * *last + rest),
        _ => halves.push(maths::cbrt(rest)),
    }
    halves
}

/// What a power-law shatter takes from the settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerLaw {
    /// The most fragments (`shatter_fragments`).
    pub count: u32,
    /// The law's exponent α (`fragment_sizes`).
    pub exponent: f32,
    /// The smallest edge (`min_fragment_size`; 0: a hundredth of the
    /// larger parent's).
    pub min_size: f32,
    /// The fragments' spread (`fragment_spread`).
    pub spread: f32,
    /// The seed of their random choices (`seed`).
    pub seed: u64,
}

/// Kernel: the fragments of `a` and `b` with edge lengths from the power
/// law of the NASA standard breakup model ([`power_law_halves`]):
/// between `min_size` (a hundredth of the larger parent's edge where it is
/// 0) and the larger parent's edge, at most `count` of them; each
/// fragment's mass in proportion to its volume; momentum kept; placed as
/// [`fragments`] places them, apart by the largest.
pub fn power_law_fragments(a: &BodyState, b: &BodyState, law: PowerLaw, first_id: BodyId) -> Vec<BodyState> {
    let PowerLaw {
        count,
        exponent,
        min_size,
        spread,
        seed,
    } = law;
    let (volume, largest) = volumes(a, b);
    let floor = if min_size > 0.0 {
        f64::from(min_size) / 2.0
    } else {
        largest / 100.0
    }
    .max(sound_floor(volume, f64::from(a.mass) + f64::from(b.mass)));
    lay_out(Parent::pair(a, b, spread, seed), first_id, |rng| {
        power_law_halves(volume, floor.min(largest), largest, count, exponent, rng)
    })
}

/// What fragments are made from: two shattering bodies, or one body
/// breaking up (docs/design.md, "Events").
struct Parent {
    /// The total mass.
    total: f64,
    /// The center of mass.
    center: DVec3,
    /// The velocity of the center of mass.
    velocity: DVec3,
    /// The speed the spread is a share of (a pair's impact speed).
    impact: f64,
    /// The share.
    spread: f32,
    /// The fragments' gravity role.
    role: GravityRole,
    /// The stream of the fragments' random choices.
    rng: Rng,
}

impl Parent {
    /// Bodies `a` and `b` shattering, their fragments moving apart at
    /// `spread` of the impact speed; the stream keyed by the pair's ids.
    fn pair(a: &BodyState, b: &BodyState, spread: f32, seed: u64) -> Self {
        let (m1, m2) = (f64::from(a.mass), f64::from(b.mass));
        let total = m1 + m2;
        let (low, high) = (a.id.0.min(b.id.0), a.id.0.max(b.id.0));
        Self {
            total,
            center: (a.position.as_dvec3() * m1 + b.position.as_dvec3() * m2) / total,
            velocity: (a.velocity.as_dvec3() * m1 + b.velocity.as_dvec3() * m2) / total,
            impact: (a.velocity - b.velocity).as_dvec3().length(),
            spread,
            role: match (
                a.role.is_source() || b.role.is_source(),
                a.role.is_adopter() || b.role.is_adopter(),
            ) {
                (true, true) => GravityRole::SourceAndAdopter,
                (true, false) => GravityRole::Source,
                (false, true) => GravityRole::Adopter,
                (false, false) => GravityRole::Inert,
            },
            rng: Rng::stream(Rng::stream(seed, low).next_u64(), high),
        }
    }

    /// `body` breaking up, its fragments moving apart at about `speed` (a
    /// share of `speed / 0.75` between a half and all of it, 0.75 on
    /// average); the stream keyed by the body's id.
    fn single(body: &BodyState, speed: f32, seed: u64) -> Self {
        Self {
            total: f64::from(body.mass),
            center: body.position.as_dvec3(),
            velocity: body.velocity.as_dvec3(),
            impact: f64::from(speed) / 0.75,
            spread: 1.0,
            role: body.role,
            rng: Rng::stream(Rng::stream(seed, BREAKUP_STREAM).next_u64(), body.id.0),
        }
    }
}

/// The key of the breakups' streams (beside the pairs', keyed by ids).
const BREAKUP_STREAM: u64 = u64::MAX;

/// Kernel: the fragments of `body` breaking up into at most `count` (2 to
/// [`MAX_FRAGMENTS`](crate::resources::MAX_FRAGMENTS)) with ids from
/// `first_id`: `Equal` cubes that keep its volume, or `PowerLaw` sizes
/// between `min_size` (a hundredth of its edge where 0) and its edge;
/// mass, volume and momentum kept, moving apart at about `speed`, placed
/// as a shatter's fragments are.
pub fn breakup_fragments(
    body: &BodyState,
    count: u32,
    speed: f32,
    sizes: FragmentSizes,
    min_size: f32,
    seed: u64,
    first_id: BodyId,
) -> Vec<BodyState> {
    let count = count.max(2);
    let volume = box_volume(body.half_extents);
    let parent = Parent::single(body, speed, seed);
    match sizes {
        FragmentSizes::Equal => {
            let half = maths::cbrt(volume / f64::from(count));
            lay_out(parent, first_id, |_| vec![half; count as usize])
        }
        FragmentSizes::PowerLaw { exponent } => {
            let largest = maths::cbrt(volume);
            let floor = if min_size > 0.0 {
                f64::from(min_size) / 2.0
            } else {
                largest / 100.0
            }
            .max(sound_floor(volume, f64::from(body.mass)));
            lay_out(parent, first_id, |rng| {
                power_law_halves(volume, floor.min(largest), largest, count, exponent, rng)
            })
        }
    }
}

/// The fragments of `parent` with the half-edges `sizes` gives (drawn
/// from its random stream after the turn, before the speeds): mass in
/// proportion to volume (equal when the halves are), the parent's momentum
/// kept, each at the center of mass plus a direction of a turned Fibonacci
/// lattice scaled so that no two touch, moving apart at its spread of the
/// impact speed.
fn lay_out(parent: Parent, first_id: BodyId, sizes: impl FnOnce(&mut Rng) -> Vec<f64>) -> Vec<BodyState> {
    let Parent {
        total,
        center,
        velocity,
        impact,
        spread,
        role,
        mut rng,
    } = parent;
    let turn = maths::rotation_yxz(
        rng.range(0.0, std::f64::consts::TAU),
        rng.range(0.0, std::f64::consts::TAU),
        rng.range(0.0, std::f64::consts::TAU),
    );
    let halves = sizes(&mut rng);
    let count = halves.len();
    if count == 0 {
        return Vec::new();
    }
    let equal = halves.iter().all(|&h| h == halves[0]);
    let directions: Vec<DVec3> = sphere_points(count as u32).into_iter().map(|d| turn * d).collect();
    // Scale the directions so that every two boxes are apart on some axis.
    let mut closest = f64::INFINITY;
    for (i, p) in directions.iter().enumerate() {
        for q in &directions[i + 1..] {
            closest = closest.min((*p - *q).abs().max_element());
        }
    }
    // Keep the clearance after rounding to f32: a few f32 steps at the center.
    let rounding = 4.0 * f64::from(f32::EPSILON) * center.abs().max_element();
    let widest = halves.iter().copied().fold(0.0, f64::max);
    let radius = (2.0 * widest * (1.0 + CLEARANCE) + rounding) / closest;
    let spreads: Vec<DVec3> = directions
        .iter()
        .map(|d| *d * impact * f64::from(spread) * rng.range(0.5, 1.0))
        .collect();
    // Equal fragments: equal masses, the plain mean (the thesis's
    // arithmetic, kept bit for bit); else by volume, the mass-weighted mean.
    let masses: Vec<f64> = if equal {
        vec![total / count as f64; count]
    } else {
        let volume: f64 = halves.iter().map(|h| h * h * h).sum();
        halves.iter().map(|h| total * h * h * h / volume).collect()
    };
    let mean_spread = if equal {
        spreads.iter().copied().sum::<DVec3>() / count as f64
    } else {
        spreads.iter().zip(&masses).map(|(s, m)| *s * *m).sum::<DVec3>() / total
    };

    directions
        .iter()
        .zip(&spreads)
        .zip(halves.iter().zip(&masses))
        .enumerate()
        .map(|(i, ((d, s), (half, mass)))| {
            BodyState::new_box(
                BodyId(first_id.0 + i as u64),
                (center + *d * radius).as_vec3(),
                (velocity + *s - mean_spread).as_vec3(),
                *mass as f32,
                Vec3::splat(*half as f32),
                role,
                true,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::Aabb;

    fn body(id: u64, position: [f32; 3], velocity: [f32; 3], mass: f32, half: [f32; 3]) -> BodyState {
        BodyState::new_box(
            BodyId(id),
            Vec3::from_array(position),
            Vec3::from_array(velocity),
            mass,
            Vec3::from_array(half),
            GravityRole::Adopter,
            true,
        )
    }

    #[test]
    fn keeps_mass_volume_and_momentum() {
        let a = body(3, [10.0, 0.0, 0.0], [4.0, 1.0, 0.0], 1.0, [1.0, 1.0, 1.0]);
        let b = body(8, [11.5, 0.5, 0.0], [-2.0, 0.0, 0.5], 3.0, [1.0, 0.5, 2.0]);
        for count in [2, 3, 5, 8, 27, 100] {
            let f = fragments(&a, &b, count, 0.2, 1, BodyId(100));
            assert_eq!(f.len(), count as usize);
            let mass: f64 = f.iter().map(|x| f64::from(x.mass)).sum();
            assert!((mass - 4.0).abs() < 1e-5, "mass {mass}");
            let volume: f64 = f
                .iter()
                .map(|x| f64::from(x.half_extents.x) * f64::from(x.half_extents.x) * f64::from(x.half_extents.x))
                .sum();
            assert!((volume - 2.0).abs() < 1e-5, "half-volume {volume}");
            let momentum: DVec3 = f.iter().map(|x| x.velocity.as_dvec3() * f64::from(x.mass)).sum();
            let expected = DVec3::new(4.0 - 6.0, 1.0, 1.5);
            assert!(
                (momentum - expected).length() < 1e-5,
                "{count}: momentum {momentum} vs {expected}"
            );
            assert!(f.iter().enumerate().all(|(i, x)| x.id == BodyId(100 + i as u64)));
        }
    }

    #[test]
    fn fragments_do_not_touch_each_other() {
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        for count in [2, 5, 12, 64, 300] {
            let f = fragments(&a, &b, count, 0.2, 7, BodyId(2));
            let boxes: Vec<Aabb> = f.iter().map(|x| Aabb::new(x.position, x.half_extents)).collect();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    assert!(!boxes[i].overlaps(&boxes[j]), "{count} fragments: {i} and {j} touch");
                }
            }
        }
    }

    #[test]
    fn fragments_far_from_the_origin_do_not_touch_either() {
        let a = body(0, [3.0e6, -2.0e6, 0.0], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [3.0e6 + 1.75, -2.0e6, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        for count in [2, 5, 12] {
            let boxes: Vec<Aabb> = fragments(&a, &b, count, 0.2, 3, BodyId(2))
                .iter()
                .map(|x| Aabb::new(x.position, x.half_extents))
                .collect();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    assert!(!boxes[i].overlaps(&boxes[j]), "{count} fragments: {i} and {j} touch");
                }
            }
        }
    }

    #[test]
    fn spread_is_seeded_and_keyed_by_the_pair() {
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        assert_eq!(
            fragments(&a, &b, 5, 0.2, 1, BodyId(2)),
            fragments(&b, &a, 5, 0.2, 1, BodyId(2))
        );
        assert_ne!(
            fragments(&a, &b, 5, 0.2, 1, BodyId(2)),
            fragments(&a, &b, 5, 0.2, 2, BodyId(2))
        );
    }

    #[test]
    fn the_spread_is_the_fragments_speed_apart_as_a_share_of_the_impact() {
        // Equal masses meeting head-on at 6: the center of mass rests.
        let a = body(0, [0.0; 3], [3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let b = body(1, [1.9, 0.0, 0.0], [-3.0, 0.0, 0.0], 1.0, [1.0; 3]);
        let speeds = |spread: f32| -> Vec<f64> {
            fragments(&a, &b, 8, spread, 1, BodyId(2))
                .iter()
                .map(|f| f.velocity.as_dvec3().length())
                .collect()
        };
        assert!(
            speeds(0.0).iter().all(|&v| v < 1e-6),
            "no spread: the fragments move together"
        );
        let (single, double) = (speeds(0.2), speeds(0.4));
        for (s, d) in single.iter().zip(&double) {
            assert!((d - 2.0 * s).abs() < 1e-5, "twice the spread, twice the speed: {s} {d}");
        }
        // Each fragment moves at up to the spread's share of the impact speed
        // (less the small mean that keeps the momentum).
        let mean = single.iter().sum::<f64>() / single.len() as f64;
        assert!(
            mean > 0.2 * 6.0 * 0.4 && single.iter().all(|&v| v < 0.2 * 6.0 * 1.2),
            "{single:?}"
        );
    }

    /// Two parents of half-edge 10 meeting; fragments of the power law.
    fn law_pair(ids: u64) -> (BodyState, BodyState) {
        let a = body(ids, [0.0; 3], [3.0, 1.0, 0.0], 2.0, [10.0; 3]);
        let b = body(ids + 1, [19.5, 0.0, 0.0], [-4.0, 0.0, 0.5], 3.0, [10.0, 10.0, 10.0]);
        (a, b)
    }

    #[test]
    fn power_law_fragments_keep_mass_volume_and_momentum_apart() {
        let (a, b) = law_pair(3);
        for (count, min_size) in [(2, 1.0), (5, 0.0), (40, 0.5), (300, 0.2)] {
            let f = power_law_fragments(
                &a,
                &b,
                PowerLaw {
                    count,
                    exponent: 1.71,
                    min_size,
                    spread: 0.2,
                    seed: 9,
                },
                BodyId(50),
            );
            assert!(
                (1..=count as usize).contains(&f.len()),
                "{} of at most {count}",
                f.len()
            );
            let mass: f64 = f.iter().map(|x| f64::from(x.mass)).sum();
            assert!((mass - 5.0).abs() < 1e-5, "mass {mass}");
            let cube =
                |x: &BodyState| f64::from(x.half_extents.x) * f64::from(x.half_extents.x) * f64::from(x.half_extents.x);
            let volume: f64 = f.iter().map(cube).sum();
            assert!((volume - 2000.0).abs() < 1e-3, "half-volume {volume}");
            let momentum: DVec3 = f.iter().map(|x| x.velocity.as_dvec3() * f64::from(x.mass)).sum();
            let expected = DVec3::new(6.0 - 12.0, 2.0, 1.5);
            assert!((momentum - expected).length() < 1e-4, "momentum {momentum}");
            // Mass in proportion to volume.
            for x in &f {
                let share = cube(x) / 2000.0;
                assert!((f64::from(x.mass) - 5.0 * share).abs() < 1e-5 * 5.0_f64.max(1.0));
            }
            // Every fragment but the last (the rest) keeps to the floor and the parent's edge.
            let floor = if min_size > 0.0 { f64::from(min_size) } else { 0.2 };
            for x in &f[..f.len() - 1] {
                let edge = 2.0 * f64::from(x.half_extents.x);
                assert!(
                    edge >= floor * (1.0 - 1e-6) && edge <= 20.0 * (1.0 + 1e-6),
                    "edge {edge}"
                );
            }
            let boxes: Vec<Aabb> = f.iter().map(|x| Aabb::new(x.position, x.half_extents)).collect();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    assert!(!boxes[i].overlaps(&boxes[j]), "{count}: fragments {i} and {j} touch");
                }
            }
            assert!(f.iter().enumerate().all(|(i, x)| x.id == BodyId(50 + i as u64)));
        }
        let law = PowerLaw {
            count: 40,
            exponent: 1.71,
            min_size: 0.5,
            spread: 0.2,
            seed: 9,
        };
        assert_eq!(
            power_law_fragments(&a, &b, law, BodyId(50)),
            power_law_fragments(&a, &b, law, BodyId(50)),
            "the same draws every time"
        );
    }

    /// The maximum-likelihood exponent of edges `edges` above `floor`
    /// (a Pareto law's: `n / Σ ln(L/floor)`).
    #[expect(clippy::disallowed_methods, reason = "a test's fit, not the state")]
    fn fitted_exponent(edges: &[f64], floor: f64) -> f64 {
        edges.len() as f64 / edges.iter().map(|e| (e / floor).ln()).sum::<f64>()
    }

    #[test]
    fn the_exponent_comes_back_from_a_fit_on_many_breakups() {
        for exponent in [1.71f32, 1.6] {
            let mut edges = Vec::new();
            for k in 0..100 {
                let (a, b) = law_pair(10 * k);
                let f = power_law_fragments(
                    &a,
                    &b,
                    PowerLaw {
                        count: 300,
                        exponent,
                        min_size: 0.2,
                        spread: 0.2,
                        seed: 4,
                    },
                    BodyId(0),
                );
                // The last fragment is the rest, not a draw.
                edges.extend(f[..f.len() - 1].iter().map(|x| 2.0 * f64::from(x.half_extents.x)));
            }
            assert!(edges.len() > 20_000, "{} draws", edges.len());
            let fitted = fitted_exponent(&edges, 0.2);
            assert!(
                (fitted - f64::from(exponent)).abs() < 0.05,
                "exponent {exponent}: fitted {fitted} from {} edges",
                edges.len()
            );
            // The cumulative law itself: the share above ten times the floor.
            let above = edges.iter().filter(|&&e| e > 2.0).count() as f64 / edges.len() as f64;
            let expected = maths::pow(10.0, -f64::from(exponent));
            assert!(
                (above - expected).abs() < 0.15 * expected,
                "N(>2)/N = {above}, law {expected}"
            );
        }
    }
}
