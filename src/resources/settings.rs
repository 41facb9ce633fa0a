//! The physics settings: [`SimulationSettings`], a plain struct with each
//! setting's meaning and default beside its field, and [`rules`], one
//! [`Rule`] per setting (its name in files, the values it allows, when the
//! window applies it). [`SimulationSettings::visit`] walks the settings in
//! file order with their rules: scenario files, `Set` events, a benchmark
//! run's overrides, an ensemble's varied settings and the window's saved
//! settings are all read, checked and written through it
//! ([`by_name`](super::settings_by_name)). Adding a setting is a field
//! here, its rule, a line in `visit`, and the code that uses it.

use bevy::prelude::*;
use serde::{Deserialize, Serialize};

use super::setting_value::SettingValue;
use super::{CollisionDetection, FragmentSizes, GravityMethod, Integrator};

/// Most bodies one run may hold: about 200 bytes each in memory, so this
/// bounds a run to a few GiB.
pub const MAX_BODIES: u64 = 20_000_000;
/// Most fragments one shatter may create.
pub const MAX_FRAGMENTS: u32 = 1000;
/// Largest fragment spread, as a share of the impact speed.
pub const MAX_FRAGMENT_SPREAD: f32 = 10.0;
/// Largest gravitational constant.
pub const MAX_GRAVITATIONAL_CONSTANT: f32 = 1e6;
/// Largest time step.
pub const MAX_TIME_STEP: f32 = 1e3;
/// Largest softening length (and generator coordinate, speed or size).
pub const MAX_LENGTH: f32 = 1e9;

/// The physics of one simulation and its stage switches: set from the
/// scenario, some changeable live (docs/design.md, "Physics settings").
/// Every field but the stage switches has a [`Rule`] in [`rules`].
#[derive(Resource, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimulationSettings {
    /// `G`, the gravitational constant (the thesis: 6.674). Default 6.674.
    pub gravitational_constant: f32,
    /// Simulated time per update, `dt`. Default 1.
    pub time_step: f32,
    /// How an update moves the bodies: `Leapfrog` (drift–kick–drift,
    /// second order; the default) or `SemiImplicitEuler` (the thesis: kick,
    /// then drift).
    pub integrator: Integrator,
    /// Softening length `ε`: gravity uses `(r² + ε²)^{3/2}`; 0 (the
    /// default) means none.
    pub softening: f32,
    /// How gravity is summed: `Auto` (the default: direct below 512
    /// sources, else the tree), `Direct`, or `Tree(theta: θ)`
    /// (Barnes–Hut). Named `gravity` in scenario files.
    pub gravity_method: GravityMethod,
    /// How collisions are found: `Swept` (the default: along each body's
    /// path over the update, at the time the pair first touches) or
    /// `Discrete` (the thesis: where the update ends).
    pub collision_detection: CollisionDetection,
    /// Impact speed (the size of `v1 − v2`) from which two interacting
    /// bodies shatter. Default 3.
    pub shatter_threshold: f32,
    /// Fragments one shatter makes (with `PowerLaw` sizes, the most it
    /// makes). Default 5.
    pub shatter_fragments: u32,
    /// How a shatter sizes its fragments: `Equal` cubes (the default, as
    /// the thesis), or `PowerLaw(exponent: α)`, edges from the NASA
    /// standard breakup model's `N(>L) ∝ L^−α`.
    pub fragment_sizes: FragmentSizes,
    /// Fragments' speed away from their center of mass, as a share of the
    /// impact speed (the thesis's "Streuung"). Default 0.2.
    pub fragment_spread: f32,
    /// Edge length below which a collision bounces instead of making
    /// fragments; 0: no floor (the thesis). Default 1.
    pub min_fragment_size: f32,
    /// Most bodies there may be: a shatter that would exceed it bounces
    /// instead. Default 1 000 000.
    pub max_bodies: u64,
    /// Seed of every random choice: the generators and the fragments'
    /// spread. Default 1.
    pub seed: u64,
    /// Which stages run (all, by default).
    pub stages: Stages,
}

/// Stage switches: which stages of an update run. The window's panel sets
/// them live; a benchmark run may turn stages off to time the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Stages {
    /// Gravity stage on/off. Off: adopters keep their velocity.
    pub gravity: bool,
    /// Broad phase on/off. Off: no pairs, so no responses.
    pub collisions: bool,
    /// Bounce and shatter on/off. Off: pairs are found but not acted on.
    /// (`response` in older benchmark configs, `collision_effects` in
    /// older window settings: the thesis's name.)
    #[serde(alias = "response", alias = "collision_effects")]
    pub collision_response: bool,
}

impl Stages {
    /// Every stage on.
    pub const ALL: Self = Self {
        gravity: true,
        collisions: true,
        collision_response: true,
    };
}

impl Default for Stages {
    fn default() -> Self {
        Self::ALL
    }
}

impl SimulationSettings {
    /// Every setting at its default and every stage on: the defaults of
    /// scenario files and of the window's settings.
    pub const DEFAULT: Self = Self {
        gravitational_constant: 6.674,
        time_step: 1.0,
        integrator: Integrator::Leapfrog,
        softening: 0.0,
        gravity_method: GravityMethod::Auto,
        collision_detection: CollisionDetection::Swept,
        shatter_threshold: 3.0,
        shatter_fragments: 5,
        fragment_sizes: FragmentSizes::Equal,
        fragment_spread: 0.2,
        min_fragment_size: 1.0,
        max_bodies: 1_000_000,
        seed: 1,
        stages: Stages::ALL,
    };

    /// Calls `visitor` with every physics setting, in file order: its
    /// rule, its value here and its value in `other` (pass `self`'s clone
    /// where only one side matters). The one list of the settings.
    pub fn visit(&mut self, other: &Self, visitor: &mut impl Visit) {
        use rules::*;
        visitor.setting(
            &GRAVITATIONAL_CONSTANT,
            &mut self.gravitational_constant,
            &other.gravitational_constant,
        );
        visitor.setting(&TIME_STEP, &mut self.time_step, &other.time_step);
        visitor.setting(&INTEGRATOR, &mut self.integrator, &other.integrator);
        visitor.setting(&SOFTENING, &mut self.softening, &other.softening);
        visitor.setting(&GRAVITY_METHOD, &mut self.gravity_method, &other.gravity_method);
        visitor.setting(
            &COLLISION_DETECTION,
            &mut self.collision_detection,
            &other.collision_detection,
        );
        visitor.setting(
            &SHATTER_THRESHOLD,
            &mut self.shatter_threshold,
            &other.shatter_threshold,
        );
        visitor.setting(
            &SHATTER_FRAGMENTS,
            &mut self.shatter_fragments,
            &other.shatter_fragments,
        );
        visitor.setting(&FRAGMENT_SIZES, &mut self.fragment_sizes, &other.fragment_sizes);
        visitor.setting(&FRAGMENT_SPREAD, &mut self.fragment_spread, &other.fragment_spread);
        visitor.setting(
            &MIN_FRAGMENT_SIZE,
            &mut self.min_fragment_size,
            &other.min_fragment_size,
        );
        visitor.setting(&MAX_BODIES, &mut self.max_bodies, &other.max_bodies);
        visitor.setting(&SEED, &mut self.seed, &other.seed);
    }
}

impl Default for SimulationSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What walks the settings with [`SimulationSettings::visit`].
pub trait Visit {
    /// One setting: its rule, its value in the settings visited, and in
    /// the other settings.
    fn setting<T: SettingValue>(&mut self, rule: &Rule<T>, value: &mut T, other: &T);
}

/// When the window applies a setting changed in its panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Applies {
    /// At once, to the running simulation.
    Live,
    /// When the scene is rebuilt (a restart or another scenario).
    OnRestart,
}

impl Applies {
    /// As the settings table writes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Live => "live",
            Self::OnRestart => "on restart",
        }
    }
}

/// A setting's rule: its name in files, the values it allows, and when
/// the window applies a change.
#[derive(Debug)]
pub struct Rule<T> {
    /// The name in scenario files, `Set` events and messages.
    pub key: &'static str,
    /// The field of [`SimulationSettings`].
    pub field: &'static str,
    /// What it means, in one line (docs/design.md's table).
    pub doc: &'static str,
    /// The values allowed, as messages say it (`must be …`).
    pub rule: &'static str,
    /// Whether a value is allowed (a number is finite besides:
    /// [`SettingValue::sound`]).
    pub ok: fn(T) -> bool,
    /// When the window applies a change.
    pub applies: Applies,
}

/// Every setting's [`Rule`], named after its field.
pub mod rules {
    use super::Applies::{Live, OnRestart};
    use super::*;

    /// `gravitational_constant`.
    pub const GRAVITATIONAL_CONSTANT: Rule<f32> = Rule {
        key: "gravitational_constant",
        field: "gravitational_constant",
        doc: "`G`, the gravitational constant (the thesis: 6.674).",
        rule: "finite, from 0 to 1e6",
        ok: |v| (0.0..=MAX_GRAVITATIONAL_CONSTANT).contains(&v),
        applies: OnRestart,
    };
    /// `time_step`.
    pub const TIME_STEP: Rule<f32> = Rule {
        key: "time_step",
        field: "time_step",
        doc: "Simulated time per update, `dt`.",
        rule: "finite, > 0 and at most 1e3",
        ok: |v| v > 0.0 && v <= MAX_TIME_STEP,
        applies: OnRestart,
    };
    /// `integrator`.
    pub const INTEGRATOR: Rule<Integrator> = Rule {
        key: "integrator",
        field: "integrator",
        doc: "How an update moves the bodies: `Leapfrog` (drift–kick–drift, second order) or \
              `SemiImplicitEuler` (the thesis: kick, then drift).",
        rule: "Leapfrog or SemiImplicitEuler",
        ok: |_| true,
        applies: Live,
    };
    /// `softening`.
    pub const SOFTENING: Rule<f32> = Rule {
        key: "softening",
        field: "softening",
        doc: "Softening length `ε`: gravity uses `(r² + ε²)^{3/2}`; 0 means none.",
        rule: "finite, from 0 to 1e9",
        ok: |v| (0.0..=MAX_LENGTH).contains(&v),
        applies: OnRestart,
    };
    /// `gravity` (the field `gravity_method`).
    pub const GRAVITY_METHOD: Rule<GravityMethod> = Rule {
        key: "gravity",
        field: "gravity_method",
        doc: "How gravity is summed: `Auto` (direct below 512 sources, else the tree), `Direct`, or \
              `Tree(theta: θ)` (Barnes–Hut).",
        rule: "Auto, Direct, or Tree(theta: θ) with θ finite from 0 to 2",
        ok: |v| v.check().is_ok(),
        applies: Live,
    };
    /// `collision_detection`.
    pub const COLLISION_DETECTION: Rule<CollisionDetection> = Rule {
        key: "collision_detection",
        field: "collision_detection",
        doc: "How collisions are found: `Swept` (along each body's path over the update, at the time the pair \
              first touches) or `Discrete` (the thesis: where the update ends).",
        rule: "Swept or Discrete",
        ok: |_| true,
        applies: Live,
    };
    /// `shatter_threshold`.
    pub const SHATTER_THRESHOLD: Rule<f32> = Rule {
        key: "shatter_threshold",
        field: "shatter_threshold",
        doc: "Impact speed (the size of `v1 − v2`) from which two interacting bodies shatter.",
        rule: "finite and >= 0",
        ok: |v| v >= 0.0,
        applies: Live,
    };
    /// `shatter_fragments`.
    pub const SHATTER_FRAGMENTS: Rule<u32> = Rule {
        key: "shatter_fragments",
        field: "shatter_fragments",
        doc: "Fragments one shatter makes (with `PowerLaw` sizes, the most it makes).",
        rule: "between 2 and 1000",
        ok: |v| (2..=MAX_FRAGMENTS).contains(&v),
        applies: Live,
    };
    /// `fragment_sizes`.
    pub const FRAGMENT_SIZES: Rule<FragmentSizes> = Rule {
        key: "fragment_sizes",
        field: "fragment_sizes",
        doc: "How a shatter sizes its fragments: `Equal` cubes (the thesis), or `PowerLaw(exponent: α)`, edges \
              from the NASA standard breakup model's `N(>L) ∝ L^−α` (1.71 for collisions, 1.6 for explosions).",
        rule: "Equal, or PowerLaw(exponent: α) with α finite, > 0 and at most 10",
        ok: |v| v.is_valid(),
        applies: Live,
    };
    /// `fragment_spread`.
    pub const FRAGMENT_SPREAD: Rule<f32> = Rule {
        key: "fragment_spread",
        field: "fragment_spread",
        doc: "Fragments' speed away from their center of mass, as a share of the impact speed (the thesis's \
              \"Streuung\").",
        rule: "finite and between 0 and 10",
        ok: |v| (0.0..=MAX_FRAGMENT_SPREAD).contains(&v),
        applies: Live,
    };
    /// `min_fragment_size`.
    pub const MIN_FRAGMENT_SIZE: Rule<f32> = Rule {
        key: "min_fragment_size",
        field: "min_fragment_size",
        doc: "Edge length below which a collision bounces instead of making fragments; 0: no floor (the thesis).",
        rule: "finite and >= 0",
        ok: |v| v >= 0.0,
        applies: Live,
    };
    /// `max_bodies`.
    pub const MAX_BODIES: Rule<u64> = Rule {
        key: "max_bodies",
        field: "max_bodies",
        doc: "Most bodies there may be: a shatter that would exceed it bounces instead.",
        rule: "between 1 and 20000000",
        ok: |v| (1..=super::MAX_BODIES).contains(&v),
        applies: Live,
    };
    /// `seed`.
    pub const SEED: Rule<u64> = Rule {
        key: "seed",
        field: "seed",
        doc: "Seed of every random choice: the generators and the fragments' spread.",
        rule: "between 0 and 18446744073709551615",
        ok: |_| true,
        applies: OnRestart,
    };
}
