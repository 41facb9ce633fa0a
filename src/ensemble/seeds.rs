//! Members' seeds (docs/guide.md, "Ensembles"): mixed from the ensemble's
//! seed and the member's place in its combination, never `seed + index`,
//! so that ensembles with neighbouring seeds share no member and a
//! member's seed depends on nothing but those two numbers — not on how
//! many members run at once, nor where.
//!
//! With `f` SplitMix64's finaliser (a bijection of 64-bit words) and
//! `γ = 0x9E3779B97F4A7C15` its increment, member `m` of the ensemble
//! seeded `s` gets `f(f(s + γ) + (m + 1)·γ)`: output `m` of the SplitMix64
//! stream that starts from the ensemble seed's own mix. Within an ensemble
//! no two members share a seed (`γ` is odd, so the states differ, and `f`
//! keeps them apart); two ensembles share one only where their mixed
//! starting points lie within a million steps of `γ` of each other, about
//! one chance in 2⁴³ per pair of ensembles.
//!
//! The same place in every combination gets the same seed (common random
//! numbers): combinations then differ by their settings, not by their
//! draws.

use crate::maths::Rng;

/// The seed of member `member` (its place within its combination) of the
/// ensemble seeded `ensemble_seed`.
pub fn member_seed(ensemble_seed: u64, member: u64) -> u64 {
    const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;
    let start = Rng::new(ensemble_seed).next_u64();
    Rng::new(start.wrapping_add(member.wrapping_mul(GAMMA))).next_u64()
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use super::*;

    #[test]
    fn seeds_are_the_stream_of_the_mixed_ensemble_seed() {
        // Output m of SplitMix64 started from the ensemble seed's mix.
        let mut stream = Rng::new(Rng::new(7).next_u64());
        for m in 0..5 {
            assert_eq!(member_seed(7, m), stream.next_u64());
        }
        assert_ne!(member_seed(7, 0), 7);
        assert_ne!(member_seed(7, 1), member_seed(8, 0));
    }

    #[test]
    fn ensembles_with_neighbouring_seeds_share_no_member_seed() {
        const MEMBERS: u64 = 20_000;
        let mut seen = HashSet::new();
        for ensemble in [0, 1, 2, 3, 4, 5, 1000, 1001, u64::MAX - 1, u64::MAX] {
            for m in 0..MEMBERS {
                assert!(
                    seen.insert(member_seed(ensemble, m)),
                    "ensemble {ensemble}, member {m}: a seed already given"
                );
            }
        }
    }
}
