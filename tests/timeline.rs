//! The record of a run (`headless --timeline`), through the real binary:
//! its header and rows, and what the physics keeps — mass through
//! shattering, momentum in a scene without sources.

mod common {
    pub mod binary;
}

use common::binary::kessler;

const HEADER: &str = "update,bodies,pairs,shatters,refused_shatters,mass,kinetic_energy,momentum_x,momentum_y,momentum_z,reentries,absorbed_mass,deferred,state_hash";

/// Runs `headless` with a timeline; returns the rows (as numbers, the state
/// hash left out) and the summary line, whose state hash is the last row's.
fn timeline(scenario: &str, steps: &str, every: Option<&str>) -> (Vec<Vec<f64>>, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("timeline.csv");
    let mut command = kessler();
    command
        .args(["headless", scenario, "--steps", steps, "--timeline"])
        .arg(&path);
    if let Some(every) = every {
        command.args(["--every", every]);
    }
    let out = command.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let mut hashes = Vec::new();
    let rows = lines
        .map(|l| {
            let (numbers, hash) = l.rsplit_once(',').unwrap();
            assert!(
                hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit()),
                "{hash}"
            );
            hashes.push(hash.to_owned());
            numbers
                .split(',')
                .map(|v| v.parse::<f64>().unwrap())
                .collect::<Vec<f64>>()
        })
        .collect();
    let summary = String::from_utf8(out.stdout).unwrap();
    assert!(
        summary
            .trim_end()
            .ends_with(&format!("state hash {}", hashes.last().unwrap())),
        "{summary}"
    );
    assert_ne!(hashes.first(), hashes.last(), "the state moved");
    (rows, summary)
}

/// The number before `word` in the summary line.
fn summary_count(summary: &str, word: &str) -> f64 {
    let before = summary.split(word).next().unwrap();
    before
        .rsplit(' ')
        .next()
        .unwrap()
        .trim_start_matches('(')
        .parse()
        .unwrap()
}

#[test]
fn a_row_every_k_updates_and_mass_kept_through_the_cascade() {
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/cascade.ron");
    let (rows, summary) = timeline(scenario, "95", Some("10"));
    let updates: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let expected: Vec<f64> = (0..10).map(|k| f64::from(k) * 10.0).chain([95.0]).collect();
    assert_eq!(updates, expected, "a row at 0, every 10 updates, and after the last");
    assert!(
        rows.iter().all(|r| r.len() == 13),
        "thirteen numbers and the hash a row"
    );
    // The cascade never reaches the swept contacts' bound, and the summary
    // says nothing of deferred contacts.
    assert!(rows.iter().all(|r| r[12] == 0.0), "no contact deferred");
    assert!(!summary.contains("deferred"), "{summary}");
    let shatters: f64 = rows.iter().map(|r| r[3]).sum();
    assert_eq!(shatters, summary_count(&summary, " shatters"), "{summary}");
    assert!(shatters > 500.0, "shattering happened: {shatters}");
    let last = rows.last().unwrap();
    assert_eq!(last[1], summary_count(&summary, " at the end"), "{summary}");
    assert!(last[1] > rows[0][1] + 1000.0, "the body count grew");
    let mass = rows[0][5];
    for row in &rows {
        assert!(
            (row[5] - mass).abs() <= 1e-6 * mass,
            "mass {} at update {}",
            row[5],
            row[0]
        );
    }
}

#[test]
fn momentum_is_kept_in_a_scene_without_sources() {
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("no_sources.ron");
    std::fs::write(
        &scenario,
        "Scenario(gravitational_constant: 0, shatter_threshold: 1.0, generators: [
            Cloud(count: 2000, center: (0, 0, 0), half_size: (50, 50, 50), max_speed: 2.0),
        ])",
    )
    .unwrap();
    let (rows, _) = timeline(scenario.to_str().unwrap(), "60", None);
    assert_eq!(rows.len(), 61, "every update by default, and the start");
    assert!(rows.iter().map(|r| r[3]).sum::<f64>() > 50.0, "shattering happened");
    let (p0, mass) = ([rows[0][7], rows[0][8], rows[0][9]], rows[0][5]);
    // Each body's velocity is rounded to f32: about 1e-7 of each m·|v|.
    let tolerance = 1e-5 * mass * 2.0;
    for row in &rows {
        for k in 0..3 {
            assert!(
                (row[7 + k] - p0[k]).abs() < tolerance,
                "momentum {:?} at update {} (start {p0:?})",
                &row[7..],
                row[0]
            );
        }
    }
}

/// Cubes at rest around a heavy ball that absorbs them (`absorbs`) or
/// bounces them off: the scene's file.
fn falling_cubes(dir: &std::path::Path, absorbs: bool) -> String {
    let path = dir.join(format!("falling-{absorbs}.ron"));
    std::fs::write(
        &path,
        format!(
            "Scenario(shatter_threshold: 1000, bodies: [
                Body(position: (0, 0, 0), shape: Sphere(radius: 50), mass: 4000, role: Source, interacts: false, absorbs: {absorbs}),
            ], generators: [
                Cloud(count: 400, center: (0, 0, 0), half_size: (150, 150, 150), max_speed: 0.0),
            ])"
        ),
    )
    .unwrap();
    path.display().to_string()
}

#[test]
fn what_falls_on_an_absorbing_ball_is_gone_and_its_mass_counted() {
    let dir = tempfile::tempdir().unwrap();
    let (rows, summary) = timeline(&falling_cubes(dir.path(), true), "200", Some("10"));
    let (bodies, mass, reentries, absorbed) = (1, 5, 10, 11);
    let start = &rows[0];
    assert_eq!((start[bodies], start[reentries], start[absorbed]), (401.0, 0.0, 0.0));
    // Mass is kept, what the ball took counted: at every row.
    for row in &rows {
        let total = row[mass] + row[absorbed];
        assert!((total - start[mass]).abs() <= 1e-9 * start[mass], "{row:?}");
        // Nothing shatters (threshold 1000): each body gone was absorbed.
        let gone: f64 = rows.iter().take_while(|r| r[0] <= row[0]).map(|r| r[reentries]).sum();
        assert_eq!(row[bodies], start[bodies] - gone, "{row:?}");
    }
    let last = rows.last().unwrap();
    assert_eq!(last[bodies], 1.0, "every cube fell in: {last:?}");
    assert_eq!(last[absorbed], 400.0, "400 unit masses");
    assert_eq!(summary_count(&summary, " reentries"), 400.0, "{summary}");

    // The same cubes on a ball that bounces them: all still there.
    let (rows, summary) = timeline(&falling_cubes(dir.path(), false), "200", Some("10"));
    let last = rows.last().unwrap();
    assert_eq!((last[bodies], last[absorbed]), (401.0, 0.0), "{last:?}");
    assert_eq!(rows.iter().map(|r| r[reentries]).sum::<f64>(), 0.0);
    assert_eq!(summary_count(&summary, " reentries"), 0.0, "{summary}");
}
