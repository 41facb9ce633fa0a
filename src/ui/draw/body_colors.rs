//! Colors of the body cubes, and which bodies are drawn as spheres instead.

use bevy::prelude::*;

use crate::components::{BodyId, GravityRole};
use crate::systems::OverlappingPairs;

/// What a cube's color shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyLook {
    /// Speed divided by the field's mean speed.
    pub relative_speed: f32,
    /// Born from a shatter (not in the scenario).
    pub fragment: bool,
    /// In an overlapping pair in the last update.
    pub colliding: bool,
}

/// Gray of every cube when visual effects are off.
pub const PLAIN: [u8; 4] = [200, 200, 205, 255];
/// Colliding cubes flash white-hot.
pub const COLLIDING: [u8; 4] = [255, 255, 230, 255];

/// sRGB color of a cube: plain gray without effects; else white when
/// colliding, and otherwise a ramp from cool blue (slow) through cyan to
/// warm red (twice the mean speed and faster), pushed towards orange for
/// fragments.
pub fn body_color(look: BodyLook, effects: bool) -> [u8; 4] {
    if !effects {
        return PLAIN;
    }
    if look.colliding {
        return COLLIDING;
    }
    let t = (look.relative_speed / 2.0).clamp(0.0, 1.0);
    let ramp = |a: f32, b: f32| a + (b - a) * t;
    let (r, g, b) = if look.fragment {
        (ramp(0.95, 1.0), ramp(0.75, 0.35), ramp(0.25, 0.1))
    } else {
        (ramp(0.25, 0.95), ramp(0.55, 0.35), ramp(1.0, 0.3))
    };
    let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    [byte(r), byte(g), byte(b), 255]
}

/// What every drawing method needs to color the cubes of one frame: which
/// bodies collide now, and the mean cube speed of the previous frame (the
/// color ramp's scale).
#[derive(Debug, Default)]
pub struct LookTracker {
    /// Indexed by entity index: in an overlapping pair this update.
    colliding: Vec<bool>,
    mean_speed: f32,
    speed_sum: f64,
    counted: u64,
}

impl LookTracker {
    /// Starts a frame: marks the bodies of this update's overlapping pairs.
    pub fn start(&mut self, pairs: &OverlappingPairs) {
        self.colliding.clear();
        for pair in &pairs.0 {
            for entity in [pair.entity_a, pair.entity_b] {
                let i = entity.index_u32() as usize;
                if self.colliding.len() <= i {
                    self.colliding.resize(i + 1, false);
                }
                self.colliding[i] = true;
            }
        }
        (self.speed_sum, self.counted) = (0.0, 0);
    }

    /// The look of one cube (counted towards this frame's mean speed).
    pub fn look(&mut self, entity: Entity, id: BodyId, velocity: Vec3, first_fragment_id: u64) -> BodyLook {
        let speed = velocity.length();
        self.speed_sum += f64::from(speed);
        self.counted += 1;
        BodyLook {
            relative_speed: speed / self.mean_speed.max(1e-6),
            fragment: id.0 >= first_fragment_id,
            colliding: self
                .colliding
                .get(entity.index_u32() as usize)
                .copied()
                .unwrap_or(false),
        }
    }

    /// Ends a frame: its mean speed scales the next frame's ramp.
    pub fn finish(&mut self) {
        if self.counted > 0 {
            self.mean_speed = (self.speed_sum / self.counted as f64) as f32;
        }
    }
}

/// Bodies drawn as spheres rather than cubes: sources that do not collide
/// (the planet, moons: [`NonInteracting`](crate::components::NonInteracting)).
pub fn is_celestial(role: GravityRole, non_interacting: bool) -> bool {
    role.is_source() && non_interacting
}

#[cfg(test)]
mod tests {
    use super::*;

    fn look(relative_speed: f32, fragment: bool, colliding: bool) -> BodyLook {
        BodyLook {
            relative_speed,
            fragment,
            colliding,
        }
    }

    #[test]
    fn without_effects_every_cube_is_plain() {
        for l in [look(0.0, false, false), look(5.0, true, true)] {
            assert_eq!(body_color(l, false), PLAIN);
        }
    }

    #[test]
    fn colliding_wins_over_speed_and_fragment() {
        assert_eq!(body_color(look(0.3, true, true), true), COLLIDING);
    }

    #[test]
    fn faster_cubes_are_warmer() {
        let slow = body_color(look(0.2, false, false), true);
        let fast = body_color(look(1.8, false, false), true);
        assert!(fast[0] > slow[0] && fast[2] < slow[2], "{slow:?} {fast:?}");
        // Beyond twice the mean, the ramp saturates.
        assert_eq!(
            body_color(look(2.0, false, false), true),
            body_color(look(9.0, false, false), true)
        );
    }

    #[test]
    fn fragments_differ_from_originals_at_the_same_speed() {
        let original = body_color(look(1.0, false, false), true);
        let fragment = body_color(look(1.0, true, false), true);
        assert_ne!(original, fragment);
        assert!(fragment[0] > original[0], "fragments lean orange");
    }

    #[test]
    fn only_non_interacting_sources_are_celestial() {
        assert!(is_celestial(GravityRole::Source, true));
        assert!(is_celestial(GravityRole::SourceAndAdopter, true));
        assert!(!is_celestial(GravityRole::SourceAndAdopter, false));
        assert!(!is_celestial(GravityRole::Adopter, true));
    }
}
