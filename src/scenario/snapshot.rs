//! Snapshots: the running state written as a scenario file that every
//! command loads (`kessler headless --save-scenario`). Every body is
//! explicit, with its id; `next_id` keeps the ids fresh bodies will get, so
//! a run continued from the file is the run it was saved from, bit for bit
//! (docs/design.md, "Scenario files").

use std::io::{self, Write};

use super::contents::Scenario;
use super::events::Event;
use super::field_checks::MAX_STATE;
use super::format::Body;
use super::initial_state::check_start;
use crate::components::BodyState;
use crate::record::StateHash;
use crate::resources::SimulationSettings;

/// What a snapshot holds.
#[derive(Clone, Copy, Debug)]
pub struct Snapshot<'a> {
    /// The scenario's name.
    pub name: &'a str,
    /// Updates run so far (said in the file's first line).
    pub updates: u64,
    /// The physics in force.
    pub settings: &'a SimulationSettings,
    /// Every body, sorted by id.
    pub bodies: &'a [BodyState],
    /// The id the next fresh body gets.
    pub next_id: u64,
    /// The events still to come, counted from now (update 0: the events of
    /// the snapshot's own update are done).
    pub events: &'a [Event],
    /// The events to come that the run will skip for certain, left out of
    /// `events`, each with why (said in a comment line).
    pub left_out: &'a [String],
}

impl Snapshot<'_> {
    /// The state as a scenario: every body explicit with its id, no
    /// generators, `next_id` set. No previous position: every update's
    /// drift sets it before anything reads it, so the state between two
    /// updates does not hold it (docs/design.md, "Snapshots").
    pub fn to_scenario(&self) -> Scenario {
        let bodies = self.bodies.iter().map(Body::from_state).collect();
        Scenario {
            name: self.name.to_owned(),
            physics: self.settings.clone(),
            next_id: Some(self.next_id),
            bodies,
            events: self.events.to_vec(),
            ..Scenario::default()
        }
    }
}

/// What keeps `bodies` under `settings` from being a scenario that loads
/// back, else `None`: a coordinate or a speed beyond ±1e30 (the file
/// would not parse), or a state that loading refuses because it would
/// stop at once (bodies piled on one another, a first update that
/// overflows: [`check_start`]).
pub fn not_a_scenario(bodies: &[BodyState], settings: &SimulationSettings) -> Option<String> {
    let beyond = |v: bevy::math::Vec3| v.abs().max_element() > MAX_STATE;
    if let Some(b) = bodies.iter().find(|b| beyond(b.position) || beyond(b.velocity)) {
        return Some(format!(
            "body {} is beyond ±1e30 (position {}, velocity {}), which a scenario cannot hold",
            b.id.0, b.position, b.velocity
        ));
    }
    check_start(bodies, settings).err().map(|problem| {
        format!(
            "the state would not load back as a scenario: loading refuses a start that would stop at once ({})",
            problem.trim_start_matches("at the start, ")
        )
    })
}

/// Writes `snapshot` as a scenario file: a comment line, one with the
/// state's hash, then the scenario as RON, a field a line and a body a
/// line.
pub fn write_snapshot(snapshot: &Snapshot<'_>, mut out: impl Write) -> io::Result<()> {
    BodyState::check_all_finite(snapshot.bodies)?;
    // What a scenario file may hold, so that the snapshot loads back.
    if let Some(problem) = not_a_scenario(snapshot.bodies, snapshot.settings) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("{problem}; nothing was written"),
        ));
    }
    let name = ron::to_string(snapshot.name).map_err(io::Error::other)?;
    writeln!(
        out,
        "// A snapshot of {name} after {} updates, written by Kessler: every body with its id.",
        snapshot.updates
    )?;
    writeln!(
        out,
        "// State hash {} (docs/design.md, \"State hash\").",
        StateHash::of_slice(snapshot.bodies, snapshot.next_id)
    )?;
    if let Some(first) = snapshot.left_out.first() {
        let line = format!(
            "// {} event(s) to come left out, which the run skips for certain; the first: {first}",
            snapshot.left_out.len()
        );
        writeln!(out, "{}", crate::output::printable(&line))?;
    }
    writeln!(out, "{}", scenario_text(&snapshot.to_scenario())?)?;
    out.flush()
}

/// `scenario` as a file writes it: RON, a field a line and a body or an
/// event a line.
pub fn scenario_text(scenario: &Scenario) -> io::Result<String> {
    ron::ser::to_string_pretty(scenario, super::ron_form::layout().depth_limit(2)).map_err(io::Error::other)
}

/// Writes a session: the scenario a run started from with every event of
/// the run, the scenario's and those recorded (`session`), after a
/// comment line saying how far the run had gone. Replayed, it reaches the
/// run's states (docs/design.md, "Events").
pub fn write_session(session: &Scenario, updates: u64, mut out: impl Write) -> io::Result<()> {
    let name = ron::to_string(&session.name).map_err(io::Error::other)?;
    writeln!(
        out,
        "// A session of {name}, written by Kessler after {updates} updates: the scenario it started from with \
         every event, its own and those recorded."
    )?;
    writeln!(out, "{}", scenario_text(session)?)?;
    out.flush()
}

#[cfg(test)]
mod tests {
    use bevy::math::Vec3;

    use super::*;
    use crate::components::{BodyId, GravityRole};
    use crate::resources::GravityMethod;

    #[test]
    fn a_snapshot_reads_back_bit_for_bit() {
        let bodies = [
            BodyState {
                id: BodyId(4),
                position: Vec3::new(0.1, -2.0e-30, 9.87654e29),
                velocity: Vec3::new(0.81694555, -0.0, f32::MIN_POSITIVE),
                mass: 4000.0,
                half_extents: Vec3::new(430.0, 1e-3, 7.25),
                role: GravityRole::SourceAndAdopter,
                interacts: false,
                previous: Vec3::new(0.2, -1.0e-30, -9.87654e29),
                spherical: false,
                absorbs: false,
            },
            BodyState {
                id: BodyId(9),
                position: Vec3::new(1.0 / 3.0, 2.0, 3.0),
                velocity: Vec3::ZERO,
                mass: 0.1,
                half_extents: Vec3::ONE,
                role: GravityRole::Adopter,
                interacts: true,
                previous: Vec3::new(1.0 / 3.0, 2.0, 3.0),
                spherical: false,
                absorbs: false,
            },
            BodyState {
                id: BodyId(11),
                position: Vec3::new(-5.0, 0.5, 0.0),
                velocity: Vec3::new(0.0, 0.0, -2.983),
                mass: 50.0,
                half_extents: Vec3::splat(60.0),
                role: GravityRole::SourceAndAdopter,
                interacts: false,
                previous: Vec3::new(-5.0, 0.5, 2.983),
                spherical: true,
                absorbs: true,
            },
        ];
        let settings = SimulationSettings {
            softening: 0.3,
            fragment_spread: 0.7,
            seed: u64::MAX,
            ..SimulationSettings::default()
        };
        let snapshot = Snapshot {
            name: "a \"quoted\" name",
            updates: 12,
            settings: &settings,
            bodies: &bodies,
            next_id: 15,
            events: &[],
            left_out: &[],
        };
        let mut text = Vec::new();
        write_snapshot(&snapshot, &mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        assert!(!text.contains("previous_position"), "{text}");
        let scenario = Scenario::parse(&text, "snapshot").unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(scenario.name, "a \"quoted\" name");
        assert_eq!(scenario.settings(), settings);
        assert_eq!(scenario.next_id(), 15);
        let read = scenario.bodies().unwrap();
        let bits = |b: &BodyState| {
            (
                b.id,
                [b.position, b.velocity, b.half_extents].map(|v| v.to_array().map(f32::to_bits)),
                b.mass.to_bits(),
                b.role,
                b.interacts,
                b.absorbs,
            )
        };
        assert_eq!(
            read.iter().map(bits).collect::<Vec<_>>(),
            bodies.iter().map(bits).collect::<Vec<_>>()
        );
    }

    #[test]
    fn every_setting_round_trips_through_a_snapshot() {
        // Every setting away from its default (a new setting must be given
        // a value here: the loop below names the one that is not).
        let settings = SimulationSettings {
            gravitational_constant: 0.25,
            time_step: 0.125,
            integrator: crate::resources::Integrator::SemiImplicitEuler,
            collision_detection: crate::resources::CollisionDetection::Discrete,
            softening: 3.5,
            gravity_method: GravityMethod::Tree { theta: 0.75 },
            shatter_threshold: 0.0,
            shatter_fragments: 1000,
            fragment_sizes: crate::resources::FragmentSizes::PowerLaw { exponent: 1.6 },
            fragment_spread: 10.0,
            min_fragment_size: 0.0,
            max_bodies: crate::resources::MAX_BODIES,
            seed: 0,
            ..SimulationSettings::default()
        };
        assert_eq!(settings.problems(), []);
        let defaults = SimulationSettings::DEFAULT;
        for s in crate::resources::settings() {
            assert_ne!(
                settings.shown(s.key),
                defaults.shown(s.key),
                "{} is at its default",
                s.key
            );
        }
        let snapshot = Snapshot {
            name: "settings",
            updates: 0,
            settings: &settings,
            bodies: &[],
            next_id: 0,
            events: &[],
            left_out: &[],
        };
        let mut text = Vec::new();
        write_snapshot(&snapshot, &mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        let scenario = Scenario::parse(&text, "snapshot").unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(scenario.settings(), settings, "{text}");
        // And back again: the scenario written from the file is the file.
        let again = Snapshot {
            settings: &scenario.settings(),
            ..snapshot
        };
        let mut second = Vec::new();
        write_snapshot(&again, &mut second).unwrap();
        assert_eq!(String::from_utf8(second).unwrap(), text);
    }

    #[test]
    fn explicit_ids_are_all_or_none_unique_and_below_next_id() {
        let errors = [
            (
                "Scenario(bodies: [Body(id: 1, position: (0, 0, 0)), Body(position: (5, 0, 0))])",
                "bodies[1].id",
            ),
            (
                "Scenario(bodies: [Body(id: 1, position: (0, 0, 0)), Body(id: 1, position: (5, 0, 0))])",
                "already",
            ),
            (
                "Scenario(next_id: 1, bodies: [Body(id: 3, position: (0, 0, 0))])",
                "next_id",
            ),
        ];
        for (text, needle) in errors {
            let e = Scenario::parse(text, "ids.ron").unwrap_err().to_string();
            assert!(e.contains(needle) && e.contains("ids.ron"), "{e}");
        }
        // Generated bodies follow the highest explicit id.
        let s = Scenario::parse(
            "Scenario(bodies: [Body(id: 7, position: (0, 0, 0), mass: 5, role: Source, interacts: false)], \
             generators: [Shell(count: 3, around: 0, inner_radius: 50, outer_radius: 60)])",
            "t",
        )
        .unwrap();
        let ids: Vec<u64> = s.bodies().unwrap().iter().map(|b| b.id.0).collect();
        assert_eq!(ids, [7, 8, 9, 10]);
        assert_eq!(s.next_id(), 11);
    }
}
