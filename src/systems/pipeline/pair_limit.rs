//! The pile-up limit: how many overlapping pairs the sweep may hold
//! before the run stops ([`Fault::PileUp`](super::Fault::PileUp)), and how
//! far swept detection's long boxes may take it past that within the
//! run's memory ([`PAIR_BYTES`]).

/// Pairs a sweep may find per box on average before it stops: bodies
/// overlapping 32 others on average (each pair counts for two) are a
/// pile-up (bodies placed on one point, a collapse crushed flat), not a
/// scene; the densest shipped scene peaks near 0.5 (docs/design.md, "Broad
/// phase"). It bounds the pairs' memory: 16 pairs of 8 bytes a body in the
/// sweep, and as many kept for the response.
pub const PAIRS_PER_BOX: usize = 16;

/// The fewest pairs a sweep may find before it stops, whatever the box
/// count.
pub const MIN_PAIR_LIMIT: usize = 1 << 20;

/// The most pairs a sweep over `boxes` boxes keeps: everything overlapping
/// everything is N² pairs, which would exhaust memory long before the
/// response could use them.
pub fn pair_limit(boxes: usize) -> usize {
    boxes.saturating_mul(PAIRS_PER_BOX).max(MIN_PAIR_LIMIT)
}

/// Bytes one overlapping pair may take across the update: the sweep's
/// index pair (8), the response's pair of ids and entities (32), and the
/// swept contacts' pair, its entry in the set of pairs and its touches
/// (about 60). Swept detection's pairs may grow past [`pair_limit`] while
/// the bodies are not piled (their boxes where the update ends overlap
/// within the limit), to a quarter of the memory the run has left.
pub const PAIR_BYTES: u64 = 100;

/// The most pairs swept detection may hold where long swept boxes, not
/// piled bodies, make them: a quarter of `free_bytes` at [`PAIR_BYTES`] a
/// pair (`None`: no memory limit known, 2²⁶ pairs), never below
/// [`pair_limit`].
pub fn swept_pair_limit(boxes: usize, free_bytes: Option<u64>) -> usize {
    let room = free_bytes.map_or(1 << 26, |free| {
        usize::try_from(free / 4 / PAIR_BYTES).unwrap_or(usize::MAX)
    });
    room.max(pair_limit(boxes))
}

/// What the bodies did in the update the sweep stopped: the longest way
/// one travelled, and that body's largest edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    /// The longest distance a body moved in the update.
    pub distance: f32,
    /// That body's largest edge (twice its largest half extent).
    pub edge: f32,
}

/// A sweep found more pairs than it may hold and stopped.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.message())]
pub struct TooManyPairs {
    /// The limit that was passed.
    pub limit: usize,
    /// The boxes swept.
    pub boxes: usize,
    /// With swept detection, where the bodies' boxes where the update ends
    /// overlap within [`pair_limit`] (they are not piled) but their swept
    /// boxes passed the memory's limit: how far the fastest body moved.
    pub long_sweeps: Option<Travel>,
}

impl TooManyPairs {
    /// A pile-up: `boxes` boxes overlapping in more than `limit` pairs.
    pub fn piled(limit: usize, boxes: usize) -> Self {
        Self {
            limit,
            boxes,
            long_sweeps: None,
        }
    }

    fn message(&self) -> String {
        let Self { limit, boxes, .. } = *self;
        match self.long_sweeps {
            None => format!(
                "the {boxes} bodies overlap in more than {limit} pairs (the limit: {PAIRS_PER_BOX} a body, at \
                 least {MIN_PAIR_LIMIT}): they are piled on one another (bodies placed at one point, or a cloud \
                 too small for its count)"
            ),
            Some(Travel { distance, edge }) => format!(
                "the {boxes} bodies' swept boxes overlap in more than {limit} pairs, as many as a quarter of the \
                 memory left holds at {PAIR_BYTES} bytes a pair (the bodies are not piled: where the update ends \
                 they overlap in fewer than {PAIRS_PER_BOX} pairs a body); the fastest moved {distance} in one \
                 update, {:.0} times its size of {edge}: a smaller time_step shortens the swept boxes, or \
                 collision_detection: Discrete tests only where updates end",
                distance / edge.max(f32::MIN_POSITIVE)
            ),
        }
    }
}
