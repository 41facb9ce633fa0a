//! [`MemoryBudget`]: how many bodies the memory this run may use holds
//! ([`crate::memory_limit`]), read once when the simulation is made.

use bevy::prelude::*;

use crate::memory::{BYTES_PER_BODY, MemoryLimit};

/// The memory limit a run is held to: the response makes no fragments that
/// would outgrow it, and the shatter stage then stops the run.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    /// The limit that binds, if any is known.
    pub limit: Option<MemoryLimit>,
}

impl Default for MemoryBudget {
    /// This process's limit, now.
    fn default() -> Self {
        Self {
            limit: MemoryLimit::of_this_process(),
        }
    }
}

impl MemoryBudget {
    /// No limit but `max_bodies`.
    pub const UNLIMITED: Self = Self { limit: None };

    /// The most bodies the run may hold.
    pub fn max_bodies(&self) -> u64 {
        self.limit.map_or(u64::MAX, |l| l.bodies())
    }

    /// A warning where `max_bodies` bodies would not fit: the estimate, the
    /// limit and what the run will do.
    pub fn warning(&self, max_bodies: u64) -> Option<String> {
        let limit = self.limit?;
        (max_bodies > limit.bodies()).then(|| {
            format!(
                "max_bodies {max_bodies} would take about {} at {BYTES_PER_BODY} bytes a body, more than the {} \
                 left under {} ({}): the run stops with an error if its bodies would pass {}",
                gigabytes(max_bodies.saturating_mul(BYTES_PER_BODY)),
                gigabytes(limit.free_bytes),
                limit.kind,
                gigabytes(limit.limit_bytes),
                limit.bodies()
            )
        })
    }
}

/// Bytes as gigabytes, one decimal.
pub fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::memory::LimitKind;

    #[test]
    fn a_budget_beyond_the_limit_is_said_with_the_estimate() {
        let budget = MemoryBudget {
            limit: Some(MemoryLimit {
                free_bytes: 2_900_000_000,
                limit_bytes: 3_000_000_000,
                kind: LimitKind::AddressSpace,
            }),
        };
        assert_eq!(budget.max_bodies(), 5_800_000);
        assert_eq!(budget.warning(5_800_000), None);
        let warning = budget.warning(20_000_000).unwrap();
        assert_eq!(
            warning,
            "max_bodies 20000000 would take about 10.0 GB at 500 bytes a body, more than the 2.9 GB left under \
             the address-space limit (ulimit -v) (3.0 GB): the run stops with an error if its bodies would pass 5800000"
        );
        assert_eq!(MemoryBudget::UNLIMITED.max_bodies(), u64::MAX);
        assert_eq!(MemoryBudget::UNLIMITED.warning(u64::MAX), None);
    }
}
