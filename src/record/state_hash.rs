//! The state hash (docs/design.md, "State hash"): 64 bits that say whether
//! two runs reached the same state, bit for bit. It is xxHash64 (seed 0)
//! over little-endian bytes: for every body in id order its id (`u64`),
//! position, velocity, mass and half-extents (`f32` bits, x, y, z), then
//! one byte each for its shape (0 box, 1 ball), gravity role (0 `Source`,
//! 1 `Adopter`, 2 `SourceAndAdopter`, 3 `Inert`) and how it collides (0
//! not at all, 1 interacts, 2 absorbs what touches it); after the bodies, the next id (`u64`). A body's previous position is
//! not part of the state (every drift sets it before anything reads it)
//! and is left out, so a snapshot's hash is the hash of the run that
//! continues from it. Written as sixteen lowercase hexadecimal digits.

use std::borrow::Borrow;
use std::fmt;
use std::hash::Hasher as _;

use twox_hash::XxHash64;

use crate::components::{BodyState, GravityRole};

/// Bytes one body adds to the hash.
const BODY_BYTES: usize = 8 + 4 * 10 + 3;

/// The hash of a state (see the module's documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StateHash(pub u64);

/// Bodies put together before each call to the hasher.
const CHUNK: usize = 4096;

impl StateHash {
    /// The hash of `bodies` in any order (ids unique) and the next id:
    /// each body's bytes put together as it comes, then taken in id order.
    pub fn of<B: Borrow<BodyState>>(bodies: impl IntoIterator<Item = B>, next_id: u64) -> Self {
        let bodies = bodies.into_iter();
        let count = bodies.size_hint().0;
        let (mut ids, mut packed) = (Vec::with_capacity(count), Vec::with_capacity(count));
        for body in bodies {
            let body = body.borrow();
            let mut bytes = [0u8; BODY_BYTES];
            put_body(&mut bytes, body);
            ids.push(body.id.0);
            packed.push(bytes);
        }
        let mut feed = Feed::new();
        for i in id_order(ids.len(), next_id, |i| ids[i]) {
            feed.add(&packed[i as usize]);
        }
        feed.finish(next_id)
    }

    /// The hash of `count` bodies (ids unique) that `id` and `body` give
    /// by index, in any order, reading each body once, in id order: no copy
    /// of the state, only its order (4 bytes a body; none where the ids
    /// already come in order).
    pub fn of_indexed(
        count: usize,
        next_id: u64,
        id: impl Fn(usize) -> u64,
        mut body: impl FnMut(usize) -> BodyState,
    ) -> Self {
        let mut feed = Feed::new();
        let mut put = |i: usize| {
            let mut bytes = [0u8; BODY_BYTES];
            put_body(&mut bytes, &body(i));
            feed.add(&bytes);
        };
        if (1..count).all(|i| id(i - 1) < id(i)) {
            (0..count).for_each(&mut put);
        } else {
            for i in id_order(count, next_id, &id) {
                put(i as usize);
            }
        }
        feed.finish(next_id)
    }

    /// The hash of `bodies` in any order (ids unique) and the next id,
    /// read where they lie (see [`of_indexed`](Self::of_indexed)).
    pub fn of_slice(bodies: &[BodyState], next_id: u64) -> Self {
        Self::of_indexed(bodies.len(), next_id, |i| bodies[i].id.0, |i| bodies[i])
    }
}

/// The indices of `count` bodies in id order, given each one's `id`:
/// without sorting where the ids are dense (below four times the count,
/// as fresh ids keep them), else through a sorted list of ids.
fn id_order(count: usize, next_id: u64, id: impl Fn(usize) -> u64) -> Vec<u32> {
    let dense = count.saturating_mul(4).max(64) as u64;
    if next_id <= dense && (0..count).all(|i| id(i) < next_id) {
        let mut at = vec![u32::MAX; next_id as usize];
        for i in 0..count {
            at[id(i) as usize] = i as u32;
        }
        at.into_iter().filter(|&i| i != u32::MAX).collect()
    } else {
        let mut by_id: Vec<(u64, u32)> = (0..count).map(|i| (id(i), i as u32)).collect();
        by_id.sort_unstable();
        by_id.into_iter().map(|(_, i)| i).collect()
    }
}

/// The bodies' bytes on their way to xxHash64, [`CHUNK`] bodies a call.
struct Feed {
    hasher: XxHash64,
    buffer: Vec<u8>,
}

impl Feed {
    fn new() -> Self {
        Self {
            hasher: XxHash64::with_seed(0),
            buffer: Vec::with_capacity(BODY_BYTES * CHUNK),
        }
    }

    /// One body's bytes, in id order.
    fn add(&mut self, bytes: &[u8; BODY_BYTES]) {
        self.buffer.extend_from_slice(bytes);
        if self.buffer.len() == BODY_BYTES * CHUNK {
            self.hasher.write(&self.buffer);
            self.buffer.clear();
        }
    }

    /// The hash, after the last body and then the next id.
    fn finish(mut self, next_id: u64) -> StateHash {
        self.hasher.write(&self.buffer);
        self.hasher.write(&next_id.to_le_bytes());
        StateHash(self.hasher.finish())
    }
}

/// Puts `body`'s bytes into `out`.
#[inline]
fn put_body(out: &mut [u8; BODY_BYTES], body: &BodyState) {
    out[..8].copy_from_slice(&body.id.0.to_le_bytes());
    let [px, py, pz] = body.position.to_array();
    let [vx, vy, vz] = body.velocity.to_array();
    let [hx, hy, hz] = body.half_extents.to_array();
    let floats = [px, py, pz, vx, vy, vz, body.mass, hx, hy, hz];
    for (k, f) in floats.into_iter().enumerate() {
        out[8 + 4 * k..12 + 4 * k].copy_from_slice(&f.to_bits().to_le_bytes());
    }
    let role = match body.role {
        GravityRole::Source => 0,
        GravityRole::Adopter => 1,
        GravityRole::SourceAndAdopter => 2,
        GravityRole::Inert => 3,
    };
    out[48] = u8::from(body.spherical);
    out[49] = role;
    // An absorber never interacts: 2 stands for it, so that every state
    // without one hashes as it did before absorbers existed.
    out[50] = if body.absorbs { 2 } else { u8::from(body.interacts) };
}

impl fmt::Display for StateHash {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:016x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::BodyId;

    fn body(id: u64) -> BodyState {
        BodyState {
            id: BodyId(id),
            position: Vec3::new(1.0, -2.0, 3.5),
            velocity: Vec3::new(0.25, 0.0, -0.0),
            mass: 2.0,
            half_extents: Vec3::ONE,
            role: GravityRole::Adopter,
            interacts: true,
            previous: Vec3::ZERO,
            spherical: false,
            absorbs: false,
        }
    }

    /// The published xxHash64 of the empty input and of "abc" (seed 0),
    /// so that the function is the documented one, not the crate's choice.
    #[test]
    fn the_hash_function_is_xxhash64() {
        let hash = |bytes: &[u8]| {
            let mut h = XxHash64::with_seed(0);
            h.write(bytes);
            h.finish()
        };
        assert_eq!(hash(b""), 0xef46_db37_51d8_e999);
        assert_eq!(hash(b"abc"), 0x44bc_2cf5_ad77_0999);
    }

    /// The hash is the xxHash64 of the documented bytes, written out here
    /// field by field.
    #[test]
    fn the_hash_covers_the_documented_bytes_in_order() {
        let bodies = [
            body(1),
            BodyState {
                spherical: true,
                absorbs: false,
                role: GravityRole::Inert,
                ..body(4)
            },
        ];
        let mut bytes = Vec::new();
        for b in &bodies {
            bytes.extend(b.id.0.to_le_bytes());
            for f in [1.0f32, -2.0, 3.5, 0.25, 0.0, -0.0, 2.0, 1.0, 1.0, 1.0] {
                bytes.extend(f.to_bits().to_le_bytes());
            }
            bytes.extend([u8::from(b.spherical), if b.spherical { 3 } else { 1 }, 1]);
        }
        bytes.extend(9u64.to_le_bytes());
        let mut h = XxHash64::with_seed(0);
        h.write(&bytes);
        assert_eq!(StateHash::of(bodies, 9).0, h.finish());
        assert_eq!(StateHash(0xab).to_string(), "00000000000000ab");
    }

    /// More bodies than one chunk, sorted, shuffled with dense ids and
    /// with sparse ids: every way in hashes the documented bytes, written
    /// at once in id order.
    #[test]
    fn every_way_in_hashes_the_bodies_in_id_order() {
        let mut rng = crate::maths::Rng::new(4);
        for spread in [1u64, 1_000] {
            let mut bodies: Vec<BodyState> = (0..2 * CHUNK as u64 + 77)
                .map(|k| BodyState {
                    position: Vec3::new(rng.range(-9.0, 9.0) as f32, k as f32, 0.5),
                    ..body(k * spread + 3)
                })
                .collect();
            let next_id = bodies.len() as u64 * spread + 3;
            let mut bytes = Vec::new();
            for b in &bodies {
                let mut one = [0u8; BODY_BYTES];
                put_body(&mut one, b);
                bytes.extend(one);
            }
            bytes.extend(next_id.to_le_bytes());
            let mut h = XxHash64::with_seed(0);
            h.write(&bytes);
            let expected = StateHash(h.finish());
            assert_eq!(
                StateHash::of_slice(&bodies, next_id),
                expected,
                "sorted, spread {spread}"
            );
            for k in (1..bodies.len()).rev() {
                bodies.swap(k, (rng.next_u64() % (k as u64 + 1)) as usize);
            }
            assert_eq!(StateHash::of(&bodies, next_id), expected, "shuffled, spread {spread}");
            assert_eq!(
                StateHash::of_slice(&bodies, next_id),
                expected,
                "shuffled, spread {spread}"
            );
        }
    }

    /// Every field, every body and the next id change the hash; the
    /// previous position does not.
    #[test]
    fn every_part_of_the_state_changes_the_hash() {
        let base = vec![body(1), body(2)];
        let hash = StateHash::of(&base, 3);
        let changed: [fn(&mut BodyState); 10] = [
            |b| b.id = BodyId(7),
            |b| b.position.z = f32::from_bits(b.position.z.to_bits() + 1),
            |b| b.velocity.z = 0.0,
            |b| b.mass = 2.5,
            |b| b.half_extents.y = 0.5,
            |b| b.role = GravityRole::Source,
            |b| b.interacts = false,
            |b| b.spherical = true,
            |b| b.velocity.x = -b.velocity.x,
            |b| {
                b.interacts = false;
                b.absorbs = true;
            },
        ];
        for (i, change) in changed.iter().enumerate() {
            let mut bodies = base.clone();
            change(&mut bodies[1]);
            assert_ne!(StateHash::of(&bodies, 3), hash, "change {i}");
        }
        assert_ne!(StateHash::of(&base, 4), hash);
        let reversed: Vec<BodyState> = base.iter().rev().copied().collect();
        assert_eq!(StateHash::of(reversed, 3), hash, "dense ids");
        let (far, sparse) = ([body(1), body(2_000_000)], [body(2_000_000), body(1)]);
        assert_eq!(StateHash::of(sparse, 2_000_001), StateHash::of(far, 2_000_001));
        assert_ne!(StateHash::of(&base[..1], 3), hash);
        let mut moved = base.clone();
        moved[0].previous = Vec3::splat(9.0);
        assert_eq!(StateHash::of(&moved, 3), hash);
    }
}
