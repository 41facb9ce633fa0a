//! The stage list: the one place that names the stages of an update, in
//! update order, with what every report shows of them. The schedule's chain,
//! the timings, the headless summary, the HUD's table, colors and plot, the
//! benchmark CSV's columns, its overhead report and its plot all derive
//! from [`STAGES`]; adding a stage is a variant, a row, and its plugin.

use bevy::prelude::*;

/// The stages of one update (docs/design.md, "One update"), each a system
/// set of the [`SimulationUpdate`](super::SimulationUpdate) schedule.
/// Declared in update order; [`STAGES`] describes them.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimulationSystems {
    /// Accelerations of adopters from all sources, applied as the velocity
    /// kick `v += a·dt` of the semi-implicit Euler step.
    Gravity,
    /// The drift `p += v·dt` of the semi-implicit Euler step.
    Integrate,
    /// The broad phase's sort: boxes filed by grid cell, each cell ordered
    /// on x.
    Sort,
    /// The broad phase's sweep: the overlapping pairs.
    Sweep,
    /// Bounce and push-back of colliding pairs.
    Response,
    /// Removal of shattered pairs and spawning of their fragments.
    Shatter,
}

/// What the reports show of one stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StageInfo {
    /// The stage's system set.
    pub stage: SimulationSystems,
    /// Short snake_case name: the headless summary, the HUD, the overhead
    /// report.
    pub name: &'static str,
    /// Name for people: plot legends.
    pub label: &'static str,
    /// sRGB color of the stage in the HUD and the plots.
    pub color: [u8; 3],
    /// The benchmark results' `<column>_ns` columns this stage's time counts
    /// in (a column may sum several stages).
    pub columns: &'static [&'static str],
}

/// Every stage, in update order.
pub const STAGES: [StageInfo; 6] = [
    StageInfo {
        stage: SimulationSystems::Gravity,
        name: "gravity",
        label: "gravity",
        color: [90, 170, 255],
        columns: &["gravity"],
    },
    StageInfo {
        stage: SimulationSystems::Integrate,
        name: "integrate",
        label: "integration",
        color: [120, 220, 120],
        columns: &["integrate"],
    },
    StageInfo {
        stage: SimulationSystems::Sort,
        name: "sort",
        label: "sort",
        color: [255, 160, 40],
        columns: &["broad_phase", "sort"],
    },
    StageInfo {
        stage: SimulationSystems::Sweep,
        name: "sweep",
        label: "sweep",
        color: [250, 220, 100],
        columns: &["broad_phase", "sweep"],
    },
    StageInfo {
        stage: SimulationSystems::Response,
        name: "response",
        label: "response",
        color: [240, 100, 100],
        columns: &["response"],
    },
    StageInfo {
        stage: SimulationSystems::Shatter,
        name: "shatter",
        label: "shatter",
        color: [200, 130, 255],
        columns: &["response"],
    },
];

/// Number of stages.
pub const STAGE_COUNT: usize = STAGES.len();

// `STAGES` lists the variants in declaration order, so a stage indexes
// per-stage arrays by `stage as usize`.
const _: () = {
    let mut i = 0;
    while i < STAGE_COUNT {
        assert!(
            STAGES[i].stage as usize == i,
            "STAGES must list the stages in declaration order"
        );
        i += 1;
    }
};

impl SimulationSystems {
    /// Every stage, in update order.
    pub const ALL: [Self; STAGE_COUNT] = {
        let mut all = [Self::Gravity; STAGE_COUNT];
        let mut i = 0;
        while i < STAGE_COUNT {
            all[i] = STAGES[i].stage;
            i += 1;
        }
        all
    };

    /// This stage's row of [`STAGES`].
    pub fn info(self) -> &'static StageInfo {
        &STAGES[self as usize]
    }

    /// Short snake_case name (summary, HUD, reports).
    pub fn name(self) -> &'static str {
        self.info().name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_colors_are_distinct() {
        for (i, a) in STAGES.iter().enumerate() {
            for b in &STAGES[i + 1..] {
                assert_ne!(a.name, b.name);
                assert_ne!(a.color, b.color, "{} and {} share a color", a.name, b.name);
            }
            assert!(!a.columns.is_empty(), "{} is reported in no column", a.name);
        }
    }
}
