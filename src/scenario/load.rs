//! Reading a scenario file and turning it into bodies, with errors that name
//! the file, the line and the field.

use std::path::Path;

use bevy::math::DVec3;

use super::contents::Scenario;
use super::field_checks::{MAX_BODIES, MAX_ID};
use super::format::{Body, Generator, Shape, Shell};
use super::generators::{self, Obstacles};
use super::initial_state::check_start;
use crate::components::BodyState;
use crate::input::{InputError, parse_ron, read_text};
use crate::maths::Rng;
use crate::resources::SimulationSettings;

impl Scenario {
    /// Parses RON text; `origin` names it in errors (usually the path) and
    /// becomes [`Scenario::origin`].
    pub fn parse(text: &str, origin: &str) -> Result<Self, InputError> {
        let mut scenario: Self = parse_ron(text, origin, super::ron_form::EXTENSIONS)?;
        scenario.origin = origin.to_owned();
        scenario.check()?;
        Ok(scenario)
    }

    /// Reads and parses a scenario file.
    pub fn load(path: &Path) -> Result<Self, InputError> {
        Self::parse(&read_text(path)?, &path.display().to_string())
    }

    /// Checks that span several fields (the parser has checked each value).
    fn check(&self) -> Result<(), InputError> {
        for (i, generator) in self.generators.iter().enumerate() {
            if let Generator::Shell(shell) = generator {
                self.check_shell(shell).map_err(|(field, problem)| {
                    InputError::new(&self.origin, format!("field `generators[{i}].{field}`: {problem}"))
                })?;
            }
        }
        self.check_shapes()?;
        self.check_places()?;
        self.check_ids()?;
        self.check_events()?;
        let total = self.body_count();
        if total > MAX_BODIES {
            return Err(InputError::new(
                &self.origin,
                format!("field `generators`: {total} bodies in all would not fit in memory (at most {MAX_BODIES})"),
            ));
        }
        Ok(())
    }

    /// Spheres: only non-interacting bodies, sized by their radius alone;
    /// absorbers: only non-interacting bodies.
    fn check_shapes(&self) -> Result<(), InputError> {
        for (i, body) in self.bodies.iter().enumerate() {
            if let Some((field, problem)) = shape_problem(body) {
                return Err(InputError::new(
                    &self.origin,
                    format!("field `bodies[{i}].{field}`: {problem}"),
                ));
            }
        }
        Ok(())
    }

    /// No interacting explicit body starts overlapping a non-interacting one
    /// (a cube inside a planet would be put out at its surface by the first
    /// update, with whatever speed it had). A saved state (`next_id` set, as
    /// every snapshot has it) is exempt: a body its last update left
    /// overlapping a planet — a fragment made at the surface — is put out by
    /// the next update, as it would have been in the run it was saved from.
    fn check_places(&self) -> Result<(), InputError> {
        if self.next_id.is_some() {
            return Ok(());
        }
        let obstacles = Obstacles::new(&self.bodies);
        for (i, body) in self.bodies.iter().enumerate().filter(|(_, b)| b.interacts) {
            let p = DVec3::from_array(body.position.map(f64::from));
            let half = DVec3::from_array(body.box_half_extents().map(f64::from));
            if let Some(j) = obstacles.overlapped(p, half) {
                let [x, y, z] = body.position;
                return Err(InputError::new(
                    &self.origin,
                    format!(
                        "field `bodies[{i}].position`: must be outside bodies[{j}] ({}), which does not interact: \
                         an interacting body there is put out at its surface by the first update, got ({x}, {y}, {z})",
                        self.bodies[j].described()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Explicit ids: on every body or on none, each used once, and below
    /// `next_id`.
    fn check_ids(&self) -> Result<(), InputError> {
        let error = |message: String| Err(InputError::new(&self.origin, message));
        let given = self.bodies.iter().filter(|b| b.id.is_some()).count();
        if given != 0 && given != self.bodies.len() {
            let missing = self.bodies.iter().position(|b| b.id.is_none()).unwrap_or(0);
            return error(format!(
                "field `bodies[{missing}].id`: missing; give every body an id or none ({given} of {} have one)",
                self.bodies.len()
            ));
        }
        let mut seen = std::collections::HashMap::new();
        for (i, id) in self.bodies.iter().filter_map(|b| b.id).enumerate() {
            if let Some(first) = seen.insert(id, i) {
                return error(format!(
                    "field `bodies[{i}].id`: {id} is the id of bodies[{first}] already"
                ));
            }
        }
        if let Some(next) = self.next_id
            && next < self.first_generated_id()
        {
            return error(format!(
                "field `next_id`: must be above every body's id ({} at least), got {next}",
                self.first_generated_id()
            ));
        }
        if let Some(problem) = self.generated_ids_problem() {
            return error(format!("field `generators`: {problem}"));
        }
        Ok(())
    }

    /// Where generated bodies would be numbered past the bound on ids (the
    /// last of them below [`MAX_ID`], the next id after them at most it):
    /// what is wrong, else `None`.
    pub(super) fn generated_ids_problem(&self) -> Option<String> {
        let first = self.first_generated_id();
        let generated = self.generated_count();
        (first.saturating_add(generated) > MAX_ID).then(|| {
            format!(
                "the {generated} generated bodies would be numbered from {first} to {}, past the largest id, {} \
                 (2^62 - 1)",
                first.saturating_add(generated.saturating_sub(1)),
                MAX_ID - 1
            )
        })
    }

    /// The explicit bodies with their ids: their own, or their place in the
    /// list.
    pub fn explicit_bodies(&self) -> impl Iterator<Item = (u64, &Body)> {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| (b.id.unwrap_or(i as u64), b))
    }

    /// Bodies the generators make.
    pub(super) fn generated_count(&self) -> u64 {
        self.generators
            .iter()
            .map(Generator::count)
            .fold(0, u64::saturating_add)
    }

    /// The id of the first generated body: one past the highest explicit id.
    pub(super) fn first_generated_id(&self) -> u64 {
        self.explicit_bodies().map(|(id, _)| id + 1).max().unwrap_or(0)
    }

    /// The id the first fresh body (a fragment) gets: `next_id`, else one
    /// past every body's id.
    pub fn next_id(&self) -> u64 {
        let past_all = self.first_generated_id() + self.generated_count();
        self.next_id.unwrap_or(past_all).max(past_all)
    }

    /// A shell's radii and source: the field at fault and the problem.
    pub(super) fn check_shell(&self, shell: &Shell) -> Result<(), (&'static str, String)> {
        if shell.inner_radius > shell.outer_radius {
            return Err((
                "outer_radius",
                format!(
                    "must be at least inner_radius ({}), got {}",
                    shell.inner_radius, shell.outer_radius
                ),
            ));
        }
        match self.bodies.get(shell.around) {
            None => Err((
                "around",
                format!(
                    "there is no body {} to orbit (the scenario has {} explicit bodies)",
                    shell.around,
                    self.bodies.len()
                ),
            )),
            Some(b) if !b.role.is_source() => Err((
                "around",
                format!(
                    "body {} has role {:?}, which attracts nothing; orbit a Source or SourceAndAdopter",
                    shell.around, b.role
                ),
            )),
            Some(b) if !b.interacts => {
                let least = shell_clearance(b, shell.body.half_extents);
                if shell.inner_radius < least {
                    Err((
                        "inner_radius",
                        format!(
                            "must be at least {least} so that no body starts inside bodies[{}] ({}, which does \
                             not interact: its size plus a shell body's half diagonal), got {}",
                            shell.around,
                            b.described(),
                            shell.inner_radius
                        ),
                    ))
                } else {
                    Ok(())
                }
            }
            Some(_) => Ok(()),
        }
    }

    /// The simulation settings this scenario asks for (all stages on).
    pub fn settings(&self) -> SimulationSettings {
        self.physics.clone()
    }

    /// Number of bodies [`bodies`](Self::bodies) will create.
    pub fn body_count(&self) -> u64 {
        self.bodies.len() as u64 + self.generated_count()
    }

    /// All bodies: explicit ones with their ids (0, 1, 2… in file order
    /// where none are given), then the generated ones, numbered on from one
    /// past the highest explicit id.
    pub fn bodies(&self) -> Result<Vec<BodyState>, InputError> {
        let mut out = Vec::with_capacity(usize::try_from(self.body_count()).unwrap_or(0));
        out.extend(self.explicit_bodies().map(|(id, b)| b.state(id)));
        let mut first_id = self.first_generated_id();
        let obstacles = Obstacles::new(&self.bodies);
        for (i, generator) in self.generators.iter().enumerate() {
            let mut rng = Rng::stream(self.physics.seed, i as u64);
            match generator {
                Generator::Cloud(c) => generators::cloud(c, &mut rng, first_id, &self.bodies, &mut out)
                    .map_err(|e| InputError::new(&self.origin, format!("generators[{i}] (Cloud): {e}")))?,
                Generator::Shell(s) => {
                    // `check` made sure the source exists.
                    generators::shell(
                        s,
                        &mut rng,
                        first_id,
                        &self.bodies[s.around],
                        &obstacles,
                        self.physics.gravitational_constant,
                        &mut out,
                    )
                    .map_err(|e| {
                        InputError::new(
                            &self.origin,
                            format!(
                                "generators[{i}] (Shell): body {} of the shell would start inside bodies[{}] ({}), \
                                 which does not interact; keep the shell's radii clear of it",
                                e.body,
                                e.obstacle,
                                self.bodies[e.obstacle].described()
                            ),
                        )
                    })?;
                }
            }
            first_id += generator.count();
        }
        check_start(&out, &self.settings()).map_err(|e| InputError::new(&self.origin, e))?;
        Ok(out)
    }
}

/// What is wrong with an explicit body's shape (a sphere that interacts
/// or has half extents) or its absorbing (a body that interacts): the field
/// at fault and the problem.
pub(super) fn shape_problem(body: &Body) -> Option<(&'static str, &'static str)> {
    if body.absorbs && body.interacts {
        return Some((
            "absorbs",
            "only a body that does not interact (`interacts: false`, a planet) absorbs what touches it",
        ));
    }
    if !matches!(body.shape, Shape::Sphere { .. }) {
        return None;
    }
    if body.interacts {
        Some((
            "shape",
            "a Sphere must be a non-interacting body (`interacts: false`): cubes and fragments are boxes",
        ))
    } else if body.half_extents.is_some() {
        Some(("shape", "a Sphere's size is its radius: leave out `half_extents`"))
    } else {
        None
    }
}

/// The smallest orbit radius at which no box of `half` (a shell's body, in
/// any direction) overlaps `around`: a ball's radius plus the box's half
/// diagonal; for a box, the half diagonal of the two boxes' reach. Rounded
/// up to the next `f32`, so that the radius the message says is allowed.
fn shell_clearance(around: &Body, half: [f32; 3]) -> f32 {
    let half = DVec3::from_array(half.map(f64::from));
    let least = match around.shape {
        Shape::Sphere { radius } => f64::from(radius) + half.length(),
        Shape::Box => (DVec3::from_array(around.box_half_extents().map(f64::from)) + half).length(),
    };
    let rounded = least as f32;
    if f64::from(rounded) < least {
        rounded.next_up()
    } else {
        rounded
    }
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::{BodyId, GravityRole};

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
        assert_eq!(
            (
                s.physics.gravitational_constant,
                s.physics.time_step,
                s.physics.softening
            ),
            (6.674, 1.0, 0.0)
        );
        assert_eq!(
            (s.physics.shatter_threshold, s.physics.shatter_fragments, s.physics.seed),
            (3.0, 5, 1)
        );
        assert_eq!(s.physics.fragment_spread, 0.2, "the thesis's spread by default");
        let bodies = s.bodies().unwrap();
        assert_eq!(bodies.len(), 2);
        let b = bodies[1];
        assert_eq!(
            (b.id, b.mass, b.half_extents, b.role, b.interacts),
            (BodyId(1), 1.0, Vec3::ONE, GravityRole::Adopter, true)
        );
    }

    #[test]
    fn spheres_are_sized_by_their_radius_and_only_for_non_interacting_bodies() {
        let s = Scenario::parse(
            "Scenario(bodies: [
                Body(position: (0, 0, 0), shape: Sphere(radius: 430), mass: 4000, role: Source, interacts: false),
                Body(position: (900, 0, 0), previous_position: (899, 0, 0)),
            ])",
            "s.ron",
        )
        .unwrap();
        let bodies = s.bodies().unwrap();
        assert!(bodies[0].spherical && !bodies[1].spherical);
        assert_eq!(bodies[0].half_extents, Vec3::splat(430.0), "the ball's bounding box");
        assert_eq!(bodies[0].previous, bodies[0].position, "default: where it is");
        assert_eq!(
            bodies[1].previous, bodies[1].position,
            "`previous_position` is accepted and ignored: the first drift sets it"
        );
        for (body, problem) in [
            ("Body(position: (0, 0, 0), shape: Sphere(radius: 4))", "non-interacting"),
            (
                "Body(position: (0, 0, 0), half_extents: (4, 4, 4), shape: Sphere(radius: 4), interacts: false)",
                "leave out `half_extents`",
            ),
            (
                "Body(position: (0, 0, 0), shape: Sphere(radius: -4), interacts: false)",
                "`bodies[0].radius`",
            ),
            (
                "Body(position: (0, 0, 0), shape: Sphere(radius: inf), interacts: false)",
                "`bodies[0].radius`",
            ),
            (
                "Body(position: (0, 0, 0), shape: Ball(radius: 4), interacts: false)",
                "Ball",
            ),
        ] {
            let e = Scenario::parse(&format!("Scenario(bodies: [{body}])"), "s.ron").unwrap_err();
            assert!(e.to_string().contains(problem), "{body}: {e}");
            assert_eq!(e.to_string().lines().count(), 1, "{e}");
        }
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
        assert!(e.message.contains("`bodies[0].mass`"), "{e}");
    }

    #[test]
    fn generated_bodies_follow_explicit_ones_and_repeat_per_seed() {
        let text = "Scenario(seed: 4, bodies: [Body(position: (0,0,0), mass: 10, role: Source)], generators: [
            Shell(count: 20, around: 0, inner_radius: 30, outer_radius: 40),
            Cloud(count: 30, center: (0,0,0), half_size: (100,100,100), body: (mass: 2.0)),
        ])";
        let s = Scenario::parse(text, "t").unwrap();
        let a = s.bodies().unwrap();
        assert_eq!(a.len(), 51);
        assert!(a.iter().enumerate().all(|(i, b)| b.id == BodyId(i as u64)));
        assert_eq!(a[50].mass, 2.0);
        assert_eq!(a, s.bodies().unwrap());
        let other = Scenario {
            physics: SimulationSettings {
                seed: 5,
                ..s.physics.clone()
            },
            ..s
        }
        .bodies()
        .unwrap();
        assert_ne!(a[1].position, other[1].position);
    }
}
