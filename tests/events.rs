//! Timed events (docs/design.md, "Events"): each kind through the binary,
//! at exactly its update; a skipped event counted and named once; a
//! snapshot with events to come continues exactly; sequential = parallel
//! with every kind; a recorded session replays to the same state.

mod common {
    pub mod binary;
}

use std::path::Path;

use common::binary::kessler;
use kessler::Simulation;
use kessler::components::BodyState;
use kessler::execution::{Execution, ExecutionMode};
use kessler::resources::{FragmentSizes, SimulationSettings};
use kessler::scenario::{Event, Remove, Scenario, Template, write_session};

/// One dumped body: id, position, velocity, mass, half extents.
#[derive(Clone, Debug, PartialEq)]
struct Row {
    id: u64,
    position: [f64; 3],
    velocity: [f64; 3],
    mass: f64,
    half: [f64; 3],
}

/// Runs `kessler headless FILE --steps N --dump` (plus `extra`): the
/// summary line, stderr and the dumped bodies.
fn headless(file: &Path, steps: u64, extra: &[&str]) -> (String, String, Vec<Row>) {
    let dump = file.with_extension(format!("{steps}.csv"));
    let out = kessler()
        .args([
            "headless",
            "--mode",
            "sequential",
            "--steps",
            &steps.to_string(),
            "--dump",
        ])
        .arg(&dump)
        .args(extra)
        .arg(file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{}: {stderr}", file.display());
    let rows = std::fs::read_to_string(&dump)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| !l.starts_with('#'))
        .map(|line| {
            let c: Vec<f64> = line.split(',').take(11).map(|x| x.parse().unwrap()).collect();
            Row {
                id: c[0] as u64,
                position: [c[1], c[2], c[3]],
                velocity: [c[4], c[5], c[6]],
                mass: c[7],
                half: [c[8], c[9], c[10]],
            }
        })
        .collect();
    (String::from_utf8_lossy(&out.stdout).into_owned(), stderr, rows)
}

/// The number before `word` in the summary (`5 shatters`).
fn count(summary: &str, word: &str) -> u64 {
    let at = summary.find(word).unwrap_or_else(|| panic!("no {word:?} in {summary}"));
    summary[..at]
        .trim_end()
        .rsplit([' ', '('])
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Two bodies orbiting a planet (id 0, absorbing), three unit cubes of
/// mass 1 at rest far out (ids 3, 4, 5; no sources reach them much), and
/// `events`.
fn scene(events: &str) -> String {
    format!(
        "Scenario(name: \"events\", bodies: [
            Body(position: (0, 0, 0), shape: Sphere(radius: 100), mass: 4000, role: Source, interacts: false, absorbs: true),
            Body(position: (300, 0, 0), velocity: (0, 0, 9.4318), half_extents: (2, 2, 2), mass: 8),
            Body(position: (-300, 0, 0), velocity: (0, 0, -9.4318)),
            Body(position: (1e6, 0, 0), role: Inert),
            Body(position: (1e6, 100, 0), role: Inert),
            Body(position: (1e6, 200, 0), velocity: (0.5, -0.25, 1), half_extents: (5, 5, 5), mass: 40, role: Inert),
        ], events: [{events}])"
    )
}

#[test]
fn a_spawn_adds_its_bodies_at_its_update() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "spawn.ron",
        &scene(
            "Spawn(update: 4, bodies: [Body(position: (0, 400, 0), velocity: (8.17, 0, 0))],
                   generators: [Shell(count: 50, around: 0, inner_radius: 500, outer_radius: 600)])",
        ),
    );
    let (before, _, rows) = headless(&file, 3, &[]);
    assert_eq!((count(&before, "at the end"), rows.len()), (6, 6), "{before}");
    // A run that stops after update 4 has applied update 4's events.
    let (after, _, rows) = headless(&file, 4, &[]);
    assert_eq!(count(&after, "at the end"), 57, "{after}");
    assert_eq!(count(&after, "events applied"), 1, "{after}");
    // Fresh ids from the next id: the body first, then the shell.
    assert_eq!(
        rows.iter().map(|r| r.id).collect::<Vec<_>>(),
        (0..57).collect::<Vec<_>>()
    );
    // The shell is on circular orbits around the planet: r·v² = G·M.
    for r in rows.iter().filter(|r| r.id >= 7) {
        let radius = r.position.iter().map(|x| x * x).sum::<f64>().sqrt();
        let speed2 = r.velocity.iter().map(|x| x * x).sum::<f64>();
        assert!((500.0..=610.0).contains(&radius), "body {} at {radius}", r.id);
        let gm = 6.674 * 4000.0;
        assert!((radius * speed2 / gm - 1.0).abs() < 0.05, "body {}", r.id);
    }
}

#[test]
fn a_remove_and_a_set_take_effect_at_exactly_their_update() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "remove.ron",
        &scene("Remove(update: 6, body: 4), Set(update: 6, shatter_threshold: 100, shatter_fragments: 9)"),
    );
    let snapshot = dir.path().join("snapshot.ron");
    let path = snapshot.to_str().unwrap();
    let (_, _, rows) = headless(&file, 5, &["--save-scenario", path]);
    assert!(rows.iter().any(|r| r.id == 4), "removed too early");
    let saved = Scenario::load(&snapshot).unwrap();
    assert_eq!(saved.physics.shatter_threshold, 3.0, "set too early");
    assert_eq!(
        saved.events.iter().map(|e| (e.kind(), e.update())).collect::<Vec<_>>(),
        [("Remove", 1), ("Set", 1)],
        "a snapshot keeps the events still to come, counted from its own start"
    );
    std::fs::remove_file(&snapshot).unwrap();
    let (summary, _, rows) = headless(&file, 6, &["--save-scenario", path]);
    assert!(!rows.iter().any(|r| r.id == 4), "not removed");
    assert_eq!(count(&summary, "at the end"), 5, "{summary}");
    let saved = Scenario::load(&snapshot).unwrap();
    assert_eq!(
        (saved.physics.shatter_threshold, saved.physics.shatter_fragments),
        (100.0, 9)
    );
    assert!(saved.events.is_empty());
}

#[test]
fn a_breakup_keeps_mass_volume_and_momentum() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "breakup.ron",
        &scene("Breakup(update: 3, body: 5, fragments: 40, speed: 0.5)"),
    );
    let (_, _, before) = headless(&file, 2, &[]);
    let (summary, _, after) = headless(&file, 3, &[]);
    assert_eq!(after.len(), before.len() - 1 + 40, "{summary}");
    let parent = before.iter().find(|r| r.id == 5).unwrap();
    let fragments: Vec<&Row> = after.iter().filter(|r| r.id >= 6).collect();
    assert_eq!(fragments.len(), 40);
    let mass: f64 = fragments.iter().map(|r| r.mass).sum();
    assert!((mass - 40.0).abs() < 1e-4, "mass {mass}");
    let volume: f64 = fragments.iter().map(|r| r.half.iter().product::<f64>()).sum();
    assert!((volume - 125.0).abs() < 1e-3, "half-volume {volume}");
    for axis in 0..3 {
        let momentum: f64 = fragments.iter().map(|r| r.mass * r.velocity[axis]).sum();
        let expected = parent.mass * parent.velocity[axis];
        assert!(
            (momentum - expected).abs() < 1e-4,
            "axis {axis}: {momentum} vs {expected}"
        );
    }
    // They fly apart at about the speed asked for.
    let mean_speed = fragments
        .iter()
        .map(|r| {
            (0..3)
                .map(|a| (r.velocity[a] - parent.velocity[a]) * (r.velocity[a] - parent.velocity[a]))
                .sum::<f64>()
                .sqrt()
        })
        .sum::<f64>()
        / 40.0;
    assert!((0.35..0.65).contains(&mean_speed), "mean speed {mean_speed}");
}

#[test]
fn a_fired_impactor_shatters_its_target_within_distance_over_speed() {
    let dir = tempfile::tempdir().unwrap();
    // 60 units at 6 a time unit: the hit about 10 updates after update 20.
    for from in ["", ", from: (0, 1, 0)", ", from: (-3, 0, 4)"] {
        let file = write(
            dir.path(),
            "fire.ron",
            &scene(&format!("Fire(update: 20, target: 1, speed: 6, distance: 60{from})")),
        );
        let (summary, _, rows) = headless(&file, 20, &[]);
        assert_eq!(count(&summary, "shatters"), 0, "{summary}");
        assert!(rows.iter().any(|r| r.id == 1));
        let (summary, _, rows) = headless(&file, 20 + 10 + 5, &[]);
        assert_eq!(count(&summary, "shatters"), 1, "{from}: {summary}");
        assert!(
            !rows.iter().any(|r| r.id == 1 || r.id == 6),
            "{from}: target and impactor shattered"
        );
    }
}

#[test]
fn an_event_whose_body_is_gone_is_skipped_counted_and_named_once() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "skipped.ron",
        &scene(
            "Remove(update: 1, body: 3), Remove(update: 2, body: 3), Fire(update: 3, target: 3, speed: 1, distance: 9),
             Remove(update: 4, body: 4)",
        ),
    );
    let (summary, stderr, rows) = headless(&file, 10, &[]);
    assert_eq!(
        (count(&summary, "events applied"), count(&summary, "skipped")),
        (2, 2),
        "{summary}"
    );
    assert_eq!(rows.len(), 4);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("events[1] (Remove at update 2) was skipped: there is no body 3"),
        "{stderr}"
    );
}

/// Every kind of event, some due exactly at the snapshot's update, two
/// seeded (a shell, an impactor's direction), with collisions.
const EVERY_KIND: &str = "
    Spawn(update: 2, generators: [Shell(count: 300, around: 0, inner_radius: 250, outer_radius: 320, inclination: 40)]),
    Fire(update: 5, target: 1, speed: 7, distance: 35),
    Fire(update: 8, target: 2, speed: 9, distance: 40, from: (0, 0, -1), body: (mass: 3, half_extents: (1.5, 1, 1))),
    Breakup(update: 8, body: 5, fragments: 12, speed: 2, sizes: PowerLaw(exponent: 1.6)),
    Set(update: 8, fragment_sizes: PowerLaw(exponent: 1.71), shatter_fragments: 20),
    Remove(update: 12, body: 4),
    Spawn(update: 15, bodies: [Body(position: (0, 0, 260), velocity: (-10.1, 0, 0), mass: 2)]),
";

#[test]
fn a_snapshot_with_events_to_come_continues_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "every.ron", &scene(EVERY_KIND));
    let (straight, _, end) = headless(&file, 40, &[]);
    assert!(count(&straight, "shatters") >= 2, "{straight}");
    for at in [5, 8, 11] {
        let snapshot = dir.path().join(format!("at{at}.ron"));
        headless(&file, at, &["--save-scenario", snapshot.to_str().unwrap()]);
        let (_, _, continued) = headless(&snapshot, 40 - at, &[]);
        assert_eq!(continued, end, "continued from update {at}");
    }
}

fn run(text: &str, mode: ExecutionMode, threads: usize, updates: u64) -> Vec<BodyState> {
    let scenario = Scenario::parse(text, "t").unwrap();
    let execution = Execution::new(mode, threads).unwrap().fine_grained();
    let mut sim = Simulation::from_scenario(&scenario, execution).unwrap();
    sim.step(updates);
    assert_eq!(sim.check_state(), None);
    sim.snapshot()
}

#[test]
fn sequential_equals_parallel_with_every_event_kind() {
    let text = scene(EVERY_KIND);
    let sequential = run(&text, ExecutionMode::Sequential, 1, 40);
    assert!(sequential.len() > 300);
    for threads in [2, 3] {
        assert_eq!(
            run(&text, ExecutionMode::Parallel, threads, 40),
            sequential,
            "{threads} threads"
        );
    }
}

/// Events recorded while a run goes (as the window's tools record them)
/// and written as a session replay to the very state of the run.
#[test]
fn a_recorded_session_replays_exactly() {
    let text = scene("Breakup(update: 3, body: 5, fragments: 6, speed: 1)");
    let scenario = Scenario::parse(&text, "session.ron").unwrap();
    let execution = Execution::new(ExecutionMode::Parallel, 2).unwrap();
    let mut live = Simulation::from_scenario(&scenario, execution).unwrap();
    live.step(4);
    let all: Vec<Event> = Scenario::parse(&scene(EVERY_KIND), "t").unwrap().events;
    // A Remove and a Fire at update 4, then the rest as they come.
    live.record_event(Event::Remove(Remove { update: 4, body: 4 }));
    live.record_event(all[1].at(4));
    live.step(6);
    live.record_event(all[4].at(10));
    live.step(20);
    let session = live.session(&scenario);
    assert_eq!(session.events.len(), 4);
    let mut text = Vec::new();
    write_session(&session, 30, &mut text).unwrap();
    let text = String::from_utf8(text).unwrap();
    assert!(text.contains("Remove(update: 4, body: 4)"), "{text}");
    assert_eq!(run(&text, ExecutionMode::Sequential, 1, 30), live.snapshot());
}

/// `scenarios/asat.ron`: the interceptor shatters satellite 1 within its
/// distance over its speed (5 updates) and 5 more, and its debris is there
/// (with swept detection, meeting other satellites already: shatters
/// beyond the first).
#[test]
fn the_asat_scene_s_interceptor_hits_its_satellite() {
    // A copy: the dumps are written beside it.
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("asat.ron");
    std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/asat.ron"), &copy).unwrap();
    let (summary, _, rows) = headless(&copy, 100, &[]);
    assert_eq!(count(&summary, "shatters"), 0, "{summary}");
    assert!(rows.iter().any(|r| r.id == 1));
    let (summary, _, rows) = headless(&copy, 110, &[]);
    assert!(count(&summary, "shatters") >= 1, "{summary}");
    assert!(!rows.iter().any(|r| r.id == 1), "{summary}");
    assert!(rows.len() > 3001 + 10, "{summary}");
}

/// A `Spawn` is held to what the scenario's own bodies are: a body that
/// would start inside a planet (which a file's `bodies` may not hold) is
/// not made; the event is skipped and named, the run goes on.
#[test]
fn a_spawn_inside_a_planet_is_skipped_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(
        dir.path(),
        "inside.ron",
        &scene("Spawn(update: 4, bodies: [Body(position: (0, 30, 0))])"),
    );
    let (summary, stderr, rows) = headless(&file, 6, &[]);
    assert_eq!(rows.len(), 6, "{summary}");
    assert!(
        stderr.contains("events[0] (Spawn at update 4) was skipped: bodies[0] would start inside body 0"),
        "{stderr}"
    );
}

/// A snapshot is the run it was saved from, its events to come included:
/// a shell to come orbits the same body after the bodies before it are
/// gone (`around` names a place in the file's `bodies`, which the snapshot
/// renumbers), and events the run will skip for certain (their body gone)
/// are left out, so the snapshot loads and its continuation is the
/// straight run's.
#[test]
fn a_snapshot_keeps_its_events_to_come_as_the_run_does() {
    let dir = tempfile::tempdir().unwrap();
    let planets = "bodies: [
        Body(position: (0, 900, 0)),
        Body(position: (0, 0, 0), shape: Sphere(radius: 100), mass: 4000, role: Source, interacts: false),
        Body(position: (3000, 0, 0), shape: Sphere(radius: 50), mass: 400, role: Source, interacts: false),
    ]";
    for (name, events, at, left_out) in [
        (
            "shell",
            "Remove(update: 2, body: 0), Spawn(update: 10, generators: [Shell(count: 20, around: 1, inner_radius: 300, outer_radius: 400)])",
            5,
            false,
        ),
        (
            "fire",
            "Remove(update: 1, body: 0), Fire(update: 5, target: 0, speed: 5, distance: 30)",
            3,
            true,
        ),
        (
            "planet_breakup",
            "Spawn(update: 1, bodies: [Body(position: (0, 600, 0), role: Source, interacts: false)]), Breakup(update: 6, body: 3, fragments: 4, speed: 1)",
            4,
            true,
        ),
    ] {
        let file = write(
            dir.path(),
            &format!("{name}.ron"),
            &format!("Scenario({planets}, events: [{events}])"),
        );
        let (_, _, straight) = headless(&file, 12, &[]);
        let snapshot = dir.path().join(format!("{name}-at-{at}.ron"));
        headless(&file, at, &["--save-scenario", snapshot.to_str().unwrap()]);
        let validated = kessler().arg("validate").arg(&snapshot).output().unwrap();
        assert!(
            validated.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&validated.stderr)
        );
        let text = std::fs::read_to_string(&snapshot).unwrap();
        assert_eq!(text.contains("left out"), left_out, "{name}: {text}");
        let (_, _, continued) = headless(&snapshot, 12 - at, &[]);
        assert_eq!(continued, straight, "{name}: continued from update {at}");
    }
}

/// A session whose tools acted while the window was paused at update U
/// replays with `--steps U` to the window's state, for U = 0 and later: a
/// run that stops after update U has applied U's events (the scenario's
/// and the recorded), as the window has once a tool acts there.
#[test]
fn a_session_of_tools_at_a_paused_update_replays_with_that_many_updates() {
    let dir = tempfile::tempdir().unwrap();
    for at in [0, 5] {
        let text = scene(&format!(
            "Remove(update: {at}, body: 3), Set(update: {at}, shatter_threshold: 50)"
        ));
        let scenario = Scenario::parse(&text, "paused.ron").unwrap();
        let execution = Execution::new(ExecutionMode::Sequential, 1).unwrap();
        let mut live = Simulation::from_scenario(&scenario, execution).unwrap();
        live.step(at);
        live.record_event(Event::Remove(Remove { update: at, body: 4 }));
        let mut text = Vec::new();
        write_session(&live.session(&scenario), 0, &mut text).unwrap();
        let file = write(
            dir.path(),
            &format!("session-{at}.ron"),
            &String::from_utf8(text).unwrap(),
        );
        let (_, _, rows) = headless(&file, at, &[]);
        let replayed: Vec<(u64, [f32; 3])> = rows.iter().map(|r| (r.id, r.position.map(|x| x as f32))).collect();
        let window: Vec<(u64, [f32; 3])> = live
            .snapshot()
            .iter()
            .map(|b| (b.id.0, b.position.to_array()))
            .collect();
        assert_eq!(replayed, window, "paused at update {at}");
        assert_eq!(replayed.iter().map(|r| r.0).collect::<Vec<_>>(), [0, 1, 2, 5]);
        // A snapshot there holds none of them: they have happened.
        let snapshot = dir.path().join(format!("snapshot-{at}.ron"));
        headless(&file, at, &["--save-scenario", snapshot.to_str().unwrap()]);
        let saved = Scenario::load(&snapshot).unwrap();
        assert!(saved.events.is_empty(), "paused at update {at}: {:?}", saved.events);
        assert_eq!(saved.physics.shatter_threshold, 50.0);
    }
}

// The events' format, read from a scenario file and written back.

/// The events of a scenario with two bodies and `events`, or the error.
fn parse_events(events: &str) -> Result<Vec<Event>, String> {
    Scenario::parse(
        &format!("Scenario(bodies: [Body(position: (0, 0, 0)), Body(position: (5, 0, 0))], events: [{events}])"),
        "e.ron",
    )
    .map(|s| s.events)
    .map_err(|e| e.to_string())
}

#[test]
fn every_kind_reads_with_its_defaults() {
    let events = parse_events(
        "Spawn(update: 3, bodies: [Body(position: (9, 9, 9))]),
         Fire(update: 4, target: 1, speed: 5, distance: 50),
         Breakup(update: 5, body: 0, fragments: 8, speed: 0.5, sizes: PowerLaw(exponent: 1.6)),
         Remove(update: 6, body: 1),
         Set(update: 7, shatter_threshold: 10, fragment_sizes: PowerLaw(exponent: 1.71))",
    )
    .unwrap();
    assert_eq!(
        events.iter().map(|e| (e.kind(), e.update())).collect::<Vec<_>>(),
        [("Spawn", 3), ("Fire", 4), ("Breakup", 5), ("Remove", 6), ("Set", 7)]
    );
    let Event::Fire(fire) = &events[1] else { unreachable!() };
    assert_eq!((fire.from, fire.body), (None, Template::default()));
    let Event::Set(set) = &events[4] else { unreachable!() };
    assert_eq!(set.settings.keys, ["shatter_threshold", "fragment_sizes"]);
    let mut settings = SimulationSettings::DEFAULT;
    set.apply(&mut settings);
    assert_eq!(settings.shatter_threshold, 10.0);
    assert_eq!(settings.fragment_sizes, FragmentSizes::PowerLaw { exponent: 1.71 });
    assert_eq!(
        settings.shatter_fragments,
        SimulationSettings::DEFAULT.shatter_fragments
    );
}

#[test]
fn bad_events_name_the_event_and_the_field() {
    for (events, needle) in [
        (
            "Fire(update: 4, target: 1, speed: -5, distance: 50)",
            "field `events[0].speed`",
        ),
        (
            "Remove(update: 1), Fire(update: 4, target: 1, speed: NaN, distance: 50)",
            "events[0]",
        ),
        (
            "Remove(update: 1, body: 0), Fire(update: 4, target: 1, speed: NaN, distance: 50)",
            "field `events[1].speed`",
        ),
        ("Remove(update: 1e13, body: 0)", "events[0].update"),
        ("Remove(update: 1000000000001, body: 0)", "events[0].update"),
        (
            "Breakup(update: 1, body: 0, fragments: 1, speed: 1)",
            "events[0].fragments",
        ),
        ("Explode(update: 1, body: 0)", "events[0]"),
        ("Remove(update: 1, body: 0, when: 3)", "`when`"),
        (
            "Set(update: 1, time_step: 2)",
            "events[0].time_step`: is applied on restart",
        ),
        ("Set(update: 1, shatter_threshold: -1)", "events[0].shatter_threshold"),
        ("Set(update: 1, threshold: 1)", "unknown field `threshold`"),
        ("Set(update: 1)", "at least one live setting"),
    ] {
        let e = parse_events(events).unwrap_err();
        assert!(e.contains(needle) && e.starts_with("e.ron:"), "{events}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn a_set_writes_what_it_reads() {
    let text = "Set(update: 9, shatter_fragments: 12, gravity: Tree(theta: 0.5))";
    let events = parse_events(text).unwrap();
    let written = ron::ser::to_string_pretty(
        &events,
        ron::ser::PrettyConfig::new()
            .struct_names(true)
            .extensions(ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES),
    )
    .unwrap();
    let again: Vec<Event> = ron::from_str(&written).unwrap_or_else(|e| panic!("{e}\n{written}"));
    assert_eq!(again, events, "{written}");
}
