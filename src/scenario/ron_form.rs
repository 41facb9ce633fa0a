//! How a scenario file writes its values in RON, for the readers and the
//! writers alike: the extensions it may use and the writers' layout.

use ron::extensions::Extensions;
use ron::ser::PrettyConfig;

/// The RON extensions a scenario file may use: newtype variants unwrapped
/// (`Spawn(update: 3, …)`), `Some` left out.
pub const EXTENSIONS: Extensions = Extensions::UNWRAP_VARIANT_NEWTYPES.union(Extensions::IMPLICIT_SOME);

/// How a file writes a scenario's values: with their names, a newtype
/// variant unwrapped (`Spawn(update: 3, …)`).
pub fn layout() -> PrettyConfig {
    PrettyConfig::new()
        .struct_names(true)
        .extensions(Extensions::UNWRAP_VARIANT_NEWTYPES)
}
