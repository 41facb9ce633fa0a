//! ECS resources shared by the stages.

mod body_ids;
mod collision_detection;
mod draw_method;
mod fragment_sizes;
mod gravity_method;
mod integrator;
mod memory_budget;
mod setting_value;
mod settings;
mod settings_by_name;
mod settings_patch;

pub use body_ids::{MAX_ID, NextBodyId};
pub use collision_detection::CollisionDetection;
pub use draw_method::DrawMethod;
pub use fragment_sizes::{FragmentSizes, MAX_EXPONENT};
pub use gravity_method::{AUTO_TREE_FROM, BadGravityMethod, DEFAULT_THETA, GravityMethod, MAX_THETA};
pub use integrator::Integrator;
pub use memory_budget::{MemoryBudget, gigabytes};
pub use setting_value::{SettingValue, problem};
pub use settings::{
    Applies, MAX_BODIES, MAX_FRAGMENT_SPREAD, MAX_FRAGMENTS, MAX_GRAVITATIONAL_CONSTANT, MAX_LENGTH, MAX_TIME_STEP,
    Rule, SimulationSettings, Stages, Visit, rules,
};
pub use settings_by_name::{SettingInfo, as_written, setting, settings, unknown_setting};
pub use settings_patch::SettingsPatch;
