//! The pile-up limit: how many overlapping pairs the sweep may hold
//! before the run stops ([`Fault::PileUp`](super::Fault::PileUp)).

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

/// A sweep found more pairs than [`pair_limit`] allows and stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the {boxes} bodies overlap in more than {limit} pairs (the limit: {PAIRS_PER_BOX} a body, at least \
     {MIN_PAIR_LIMIT}): they are piled on one another (bodies placed at one point, or a cloud too small for its count)"
)]
pub struct TooManyPairs {
    /// The limit that was passed.
    pub limit: usize,
    /// The boxes swept.
    pub boxes: usize,
}
