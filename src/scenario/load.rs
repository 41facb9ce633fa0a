//! Reading a scenario file and turning it into bodies, with errors that name
//! the file, the line and the field.

use std::fmt;
use std::path::Path;

use bevy::math::Vec3;
use ron::extensions::Extensions;

use super::checked::MAX_BODIES;
use super::format::{Generator, Scenario};
use super::generators;
use crate::components::{BodyId, BodyState};
use crate::resources::SimulationSettings;
use crate::rng::Rng;

/// Why a scenario could not be used.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenarioError {
    /// The file (or built-in scenario) the error is in.
    pub origin: String,
    /// 1-based line and column, where the parser knows them.
    pub location: Option<(usize, usize)>,
    pub message: String,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.location {
            Some((line, col)) => write!(f, "{}:{line}:{col}: {}", self.origin, self.message),
            None => write!(f, "{}: {}", self.origin, self.message),
        }
    }
}

impl std::error::Error for ScenarioError {}

impl ScenarioError {
    fn new(origin: &str, message: impl Into<String>) -> Self {
        Self {
            origin: origin.to_owned(),
            location: None,
            message: message.into(),
        }
    }
}

impl Scenario {
    /// Parses RON text; `origin` names it in errors (usually the path).
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        let options = ron::Options::default().with_default_extension(Extensions::UNWRAP_VARIANT_NEWTYPES);
        let scenario: Self = options.from_str(text).map_err(|e| ScenarioError {
            origin: origin.to_owned(),
            location: Some((e.span.start.line, e.span.start.col)),
            message: e.code.to_string(),
        })?;
        scenario.check(origin)?;
        Ok(scenario)
    }

    /// Reads and parses a scenario file.
    pub fn load(path: &Path) -> Result<Self, ScenarioError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| ScenarioError::new(&origin, format!("cannot read the file: {e}")))?;
        Self::parse(&text, &origin)
    }

    /// Checks that span several fields (the parser has checked each value).
    fn check(&self, origin: &str) -> Result<(), ScenarioError> {
        for (i, generator) in self.generators.iter().enumerate() {
            let field = |name: &str| format!("generators[{i}].{name}");
            match generator {
                Generator::Cloud(_) => {}
                Generator::Shell(s) => {
                    if s.inner_radius > s.outer_radius {
                        return Err(ScenarioError::new(
                            origin,
                            format!(
                                "field `{}`: must be at least inner_radius ({}), got {}",
                                field("outer_radius"),
                                s.inner_radius,
                                s.outer_radius
                            ),
                        ));
                    }
                    match self.bodies.get(s.around) {
                        None => {
                            return Err(ScenarioError::new(
                                origin,
                                format!(
                                    "field `{}`: there is no body {} to orbit (the scenario has {} explicit bodies)",
                                    field("around"),
                                    s.around,
                                    self.bodies.len()
                                ),
                            ));
                        }
                        Some(b) if !b.role.is_source() => {
                            return Err(ScenarioError::new(
                                origin,
                                format!(
                                    "field `{}`: body {} has role {:?}, which attracts nothing; orbit a Source or SourceAndAdopter",
                                    field("around"),
                                    s.around,
                                    b.role
                                ),
                            ));
                        }
                        Some(_) => {}
                    }
                }
            }
        }
        let total = self.body_count();
        if total > MAX_BODIES {
            return Err(ScenarioError::new(
                origin,
                format!("field `generators`: {total} bodies in all would not fit in memory (at most {MAX_BODIES})"),
            ));
        }
        Ok(())
    }

    /// The simulation settings this scenario asks for (all stages on).
    pub fn settings(&self) -> SimulationSettings {
        SimulationSettings {
            gravitational_constant: self.gravitational_constant,
            time_step: self.time_step,
            softening: self.softening,
            shatter_threshold: self.shatter_threshold,
            shatter_fragments: self.shatter_fragments,
            seed: self.seed,
            ..SimulationSettings::default()
        }
    }

    /// Number of bodies [`bodies`](Self::bodies) will create.
    pub fn body_count(&self) -> u64 {
        let generated: u64 = self.generators.iter().map(Generator::count).sum();
        self.bodies.len() as u64 + generated
    }

    /// All bodies: explicit ones with ids 0, 1, 2… in file order, then the
    /// generated ones. `origin` names the scenario in errors.
    pub fn bodies(&self, origin: &str) -> Result<Vec<BodyState>, ScenarioError> {
        let mut out = Vec::with_capacity(usize::try_from(self.body_count()).unwrap_or(0));
        out.extend(self.bodies.iter().enumerate().map(|(i, b)| BodyState {
            id: BodyId(i as u64),
            position: Vec3::from_array(b.position),
            velocity: Vec3::from_array(b.velocity),
            mass: b.mass,
            half_extents: Vec3::from_array(b.half_extents),
            role: b.role,
            interacts: b.interacts,
        }));
        for (i, generator) in self.generators.iter().enumerate() {
            let mut rng = Rng::stream(self.seed, i as u64);
            let first_id = out.len() as u64;
            match generator {
                Generator::Cloud(c) => generators::cloud(c, &mut rng, first_id, &self.bodies, &mut out)
                    .map_err(|e| ScenarioError::new(origin, format!("generators[{i}] (Cloud): {e}")))?,
                Generator::Shell(s) => {
                    // `check` made sure the source exists.
                    generators::shell(
                        s,
                        &mut rng,
                        first_id,
                        &self.bodies[s.around],
                        self.gravitational_constant,
                        &mut out,
                    );
                }
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::GravityRole;

    #[test]
    fn design_example_parses_with_defaults() {
        let s = Scenario::parse(
            r#"Scenario(
                name: "Two-body orbit",
                bodies: [
                    Body(position: (0.0, 0.0, 0.0), mass: 2.0, role: Source, interacts: false),
                    Body(position: (20.0, 0.0, 0.0), velocity: (0.0, 0.81694555, 0.0)),
                ],
            )"#,
            "example",
        )
        .unwrap();
        assert_eq!((s.gravitational_constant, s.time_step, s.softening), (6.674, 1.0, 0.0));
        assert_eq!((s.shatter_threshold, s.shatter_fragments, s.seed), (3.0, 5, 1));
        let bodies = s.bodies("example").unwrap();
        assert_eq!(bodies.len(), 2);
        let b = bodies[1];
        assert_eq!(
            (b.id, b.mass, b.half_extents, b.role, b.interacts),
            (BodyId(1), 1.0, Vec3::ONE, GravityRole::Adopter, true)
        );
    }

    #[test]
    fn value_errors_carry_line_and_field() {
        let e = Scenario::parse(
            "Scenario(\n  bodies: [\n    Body(position: (0,0,0), mass: -1.0),\n  ],\n)",
            "f.ron",
        )
        .unwrap_err();
        assert_eq!(e.location.map(|l| l.0), Some(3), "{e}");
        assert!(e.to_string().starts_with("f.ron:3:"), "{e}");
        assert!(e.message.contains("`mass`"), "{e}");
    }

    #[test]
    fn generated_bodies_follow_explicit_ones_and_repeat_per_seed() {
        let text = "Scenario(seed: 4, bodies: [Body(position: (0,0,0), mass: 10, role: Source)], generators: [
            Shell(count: 20, around: 0, inner_radius: 30, outer_radius: 40),
            Cloud(count: 30, center: (0,0,0), half_size: (100,100,100), body: (mass: 2.0)),
        ])";
        let s = Scenario::parse(text, "t").unwrap();
        let a = s.bodies("t").unwrap();
        assert_eq!(a.len(), 51);
        assert!(a.iter().enumerate().all(|(i, b)| b.id == BodyId(i as u64)));
        assert_eq!(a[50].mass, 2.0);
        assert_eq!(a, s.bodies("t").unwrap());
        let other = Scenario { seed: 5, ..s }.bodies("t").unwrap();
        assert_ne!(a[1].position, other[1].position);
    }
}
