//! The command line as a user meets it.

mod common {
    pub mod binary;
}

use common::binary::kessler;

fn scenario(name: &str) -> String {
    format!("{}/scenarios/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn help_lists_the_commands() {
    let out = kessler().arg("--help").output().unwrap();
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    // Every command of `src/cli/args.rs`'s `Command`, each on a line of its
    // own in the list of commands.
    for command in ["run", "headless", "pairs", "bench", "calibrate", "ensemble", "validate"] {
        assert!(help.contains(command), "--help lacks {command}: {help}");
        assert!(
            help.lines().any(|line| line.split_whitespace().next() == Some(command)),
            "--help lists no command {command}: {help}"
        );
    }
}

#[test]
fn shipped_scenarios_validate() {
    for (file, count) in [
        ("two_body.ron", "2 bodies"),
        ("thesis_cloud.ron", "10001 bodies"),
        ("debris_orbit.ron", "20002 bodies"),
        ("cascade.ron", "3001 bodies"),
        ("far_outliers.ron", "100006 bodies"),
        ("debris_ring.ron", "3001 bodies"),
        ("collapse.ron", "300 bodies"),
        ("asat.ron", "3001 bodies, 1 event"),
    ] {
        let out = kessler().args(["validate", &scenario(file)]).output().unwrap();
        assert!(out.status.success(), "{file}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stdout).contains(count), "{file}");
    }
}

#[test]
fn headless_dump_has_the_contract_format() {
    let dir = tempfile::tempdir().unwrap();
    let dump = dir.path().join("two_body.csv");
    let out = kessler()
        .args([
            "headless",
            &scenario("two_body.ron"),
            "--steps",
            "154",
            "--mode",
            "sequential",
            "--dump",
        ])
        .arg(&dump)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary = String::from_utf8(out.stdout).unwrap();
    assert_eq!(summary.lines().count(), 1, "summary: {summary}");
    assert!(summary.contains("154 updates"), "{summary}");

    let csv = std::fs::read_to_string(&dump).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "id,x,y,z,vx,vy,vz,mass,hx,hy,hz,role,interacts");
    assert_eq!(rows[1], "0,0,0,0,0,0,0,2,1,1,1,Source,false");
    let body: Vec<&str> = rows[2].split(',').collect();
    assert_eq!(body.len(), 13);
    assert_eq!((body[0], body[11], body[12]), ("1", "Adopter", "true"));
    let x: f32 = body[1].parse().unwrap();
    assert_eq!(x.round(), 20.0, "one revolution brings the body back to x = 20");
    // Shortest round-trip: printing the parsed value gives the same text.
    assert_eq!(x.to_string(), body[1]);
    // Plain CSV: every line a row of the header (the hash is the summary's).
    assert_eq!(rows.len(), 3, "{csv}");
    assert!(rows.iter().all(|row| row.split(',').count() == 13), "{csv}");
    summary_hash(&summary);
}

/// The state hash a summary line ends with.
fn summary_hash(summary: &str) -> String {
    let (_, hash) = summary.trim_end().rsplit_once("; state hash ").expect("a hash");
    assert!(
        hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit()),
        "{hash}"
    );
    hash.to_owned()
}

/// The summary, the dump and the snapshot give one hash; the snapshot
/// loaded and run for no update gives it again (what a snapshot leaves out,
/// the previous positions, is not part of the state), and 40 updates from
/// it give the hash of the straight 100.
#[test]
fn the_state_hash_is_one_in_every_output_and_continues_with_the_snapshot() {
    let dir = tempfile::tempdir().unwrap();
    let (dump, saved) = (dir.path().join("state.csv"), dir.path().join("saved.ron"));
    let run = |scene: &str, steps: &str, extra: &[&std::path::Path]| {
        let mut command = kessler();
        command.args(["headless", scene, "--steps", steps]);
        for (flag, path) in ["--dump", "--save-scenario"].iter().zip(extra) {
            command.arg(flag).arg(path);
        }
        let out = command.output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        summary_hash(&String::from_utf8(out.stdout).unwrap())
    };
    let collapse = scenario("collapse.ron");
    let at_60 = run(&collapse, "60", &[&dump, &saved]);
    let dumped = std::fs::read_to_string(&dump).unwrap();
    assert!(!dumped.contains('#'), "plain CSV: {dumped:.200}");
    let snapshot = std::fs::read_to_string(&saved).unwrap();
    assert_eq!(
        snapshot.lines().nth(1).unwrap(),
        format!("// State hash {at_60} (docs/design.md, \"State hash\")."),
    );
    let saved = saved.to_str().unwrap();
    assert_eq!(run(saved, "0", &[]), at_60);
    assert_eq!(run(saved, "40", &[]), run(&collapse, "100", &[]));
    assert_ne!(at_60, run(&collapse, "100", &[]));
}

/// Without the `gui` feature, `kessler` simulates headless instead of
/// opening a window (the window itself is tested in `tests/window.rs`).
#[cfg(not(feature = "gui"))]
#[test]
fn run_without_window_simulates_the_default_scene() {
    let out = kessler().output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("Debris in orbit"));
}

#[test]
fn pairs_prints_the_thesis_case_as_csv() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("case2.ron");
    let centers = [
        "(-1.81922, 0.13185, 1.43538)",
        "(0, 2, 0)",
        "(-0.570769, -0.697269, 0.466469)",
        "(-2.56339, 1.2581, 2.37958)",
        "(-1.30461, 2.89979, 1.12968)",
        "(-2.7742, -1.23996, 1.75068)",
        "(-0.848593, -3.80494, 1.73219)",
    ];
    let bodies: Vec<String> = centers.iter().map(|c| format!("Body(position: {c})")).collect();
    std::fs::write(&path, format!("Scenario(bodies: [{}])", bodies.join(", "))).unwrap();
    let out = kessler().arg("pairs").arg(&path).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(
        String::from_utf8(out.stdout).unwrap(),
        "a,b\n0,1\n0,2\n0,3\n0,5\n1,4\n2,3\n3,4\n"
    );
}

#[test]
fn calibrate_stores_what_split_auto_then_uses() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config");
    let headless = |config: &std::path::Path| {
        let out = kessler()
            .args([
                "headless",
                &scenario("two_body.ron"),
                "--steps",
                "3",
                "--mode",
                "parallel",
            ])
            .env("XDG_CONFIG_HOME", config)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        (
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        )
    };
    let (before, _) = headless(&config);
    assert!(before.contains("split auto (no calibration"), "{before}");

    // The calibration file a link into a dotfiles folder, as the
    // settings file may be: written through, the link kept.
    let path = config.join("kessler").join("calibration.ron");
    let dotfiles = dir.path().join("dotfiles");
    std::fs::create_dir_all(&dotfiles).unwrap();
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("../../dotfiles/calibration.ron", &path).unwrap();
    let out = kessler()
        .args(["calibrate", "--threads", "2"])
        .env("XDG_CONFIG_HOME", &config)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    #[cfg(unix)]
    {
        assert!(
            path.symlink_metadata().unwrap().file_type().is_symlink(),
            "the link was replaced"
        );
        assert!(dotfiles.join("calibration.ron").is_file());
    }
    let printed = String::from_utf8(out.stdout).unwrap();
    assert!(printed.contains(&path.display().to_string()), "{printed}");
    let calibration = kessler::calibration::load_calibration(&path).unwrap().unwrap();
    assert_eq!(calibration.threads, 2);
    for stage in kessler::systems::STAGES {
        let from = calibration.split_from[stage.name];
        assert!(
            kessler::calibration::LADDER.contains(&from) || from == kessler::calibration::NOT_FOUND,
            "{}: {from}",
            stage.name
        );
        assert!(
            printed.contains(&format!("{:<10} splits from {from} bodies", stage.name)),
            "{printed}"
        );
    }
    let (after, _) = headless(&config);
    assert!(after.contains("split auto (calibrated on 2 threads"), "{after}");

    // A broken calibration: a warning, the fallback, and the run goes on.
    std::fs::write(&path, "Calibration(").unwrap();
    let (broken, warning) = headless(&config);
    assert!(broken.contains("no calibration"), "{broken}");
    assert!(
        warning.contains("warning") && warning.contains("calibration.ron"),
        "{warning}"
    );
}

/// A default calibration file that cannot be written (a link to a
/// folder) is refused before the measuring, naming the file and the link,
/// not an option the user never gave.
#[cfg(unix)]
#[test]
fn calibrate_names_the_default_file_it_cannot_write() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config");
    let path = config.join("kessler").join("calibration.ron");
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::os::unix::fs::symlink(dir.path(), &path).unwrap();
    let start = std::time::Instant::now();
    let out = kessler()
        .args(["calibrate", "--threads", "2"])
        .env("XDG_CONFIG_HOME", &config)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "the calibration file {}, a link to {}: is a directory",
            path.display(),
            dir.path().display()
        )),
        "{stderr}"
    );
    assert!(!stderr.contains("--out"), "{stderr}");
    assert!(start.elapsed().as_secs() < 20, "measured before refusing");
}

/// What Kessler writes, Kessler reads: near the bound on ids (2^62) too.
/// The highest id a file may give, generated bodies that end just below
/// the bound, a next id with just room for one shatter's fragments, and one
/// without (the shatter bounces instead): each run's snapshot validates,
/// and so does the snapshot of a run continued from it.
#[test]
fn every_snapshot_near_the_bound_on_ids_loads_back() {
    let dir = tempfile::tempdir().unwrap();
    let bound: u64 = 1 << 62;
    let meeting =
        "Body(position: (-1.5, 0, 0), velocity: (2, 0, 0)), Body(position: (1.5, 0, 0), velocity: (-2, 0, 0.1))";
    let cases = [
        (
            format!("Scenario(bodies: [Body(id: {}, position: (0, 0, 0))])", bound - 1),
            "0",
            format!("next_id: {bound}"),
        ),
        (
            format!(
                "Scenario(bodies: [Body(id: {}, position: (0, 0, 0), mass: 10, role: Source, interacts: false)], \
                 generators: [Shell(count: 3, around: 0, inner_radius: 50, outer_radius: 60)])",
                bound - 4
            ),
            "2",
            format!("next_id: {bound}"),
        ),
        (
            format!("Scenario(next_id: {}, bodies: [{meeting}])", bound - 5),
            "3",
            "(5 at the end, 1 shatters, 0 refused, 0 reentries)".to_owned(),
        ),
        (
            format!("Scenario(next_id: {}, bodies: [{meeting}])", bound - 4),
            "3",
            "(2 at the end, 0 shatters, 1 refused, 0 reentries)".to_owned(),
        ),
    ];
    for (i, (text, steps, needle)) in cases.iter().enumerate() {
        let mut from = dir.path().join(format!("{i}.ron"));
        std::fs::write(&from, text).unwrap();
        for generation in 0..2 {
            let snapshot = dir.path().join(format!("{i}-{generation}.snapshot.ron"));
            let out = kessler()
                .args(["headless", "--steps", steps, "--save-scenario"])
                .arg(&snapshot)
                .arg(&from)
                .output()
                .unwrap();
            assert!(out.status.success(), "{text}: {}", String::from_utf8_lossy(&out.stderr));
            let written = std::fs::read_to_string(&snapshot).unwrap();
            let said = format!("{}{written}", String::from_utf8_lossy(&out.stdout));
            assert!(generation == 1 || said.contains(needle.as_str()), "{text}: {said}");
            let out = kessler().arg("validate").arg(&snapshot).output().unwrap();
            assert!(
                out.status.success(),
                "{text}: its snapshot does not load: {}\n{written}",
                String::from_utf8_lossy(&out.stderr)
            );
            from = snapshot;
        }
    }
}

/// More threads than the machine can run are bounded, with a warning:
/// `--threads 256` on two cores took 40 s, and measured only the waiting.
#[test]
fn calibrate_bounds_the_threads_to_what_the_machine_runs() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calibration.ron");
    let start = std::time::Instant::now();
    let out = kessler()
        .args(["calibrate", "--threads", "256", "--out"])
        .arg(&path)
        .timeout(std::time::Duration::from_secs(120))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let most = (2 * std::thread::available_parallelism().map_or(1, |n| n.get())).clamp(2, 256);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if most < 256 {
        assert!(
            stderr.contains("warning: --threads 256: this machine has")
                && stderr.contains(&format!("calibrating on {most}")),
            "{stderr}"
        );
    }
    let calibration = kessler::calibration::load_calibration(&path).unwrap().unwrap();
    assert_eq!(calibration.threads, most);
    eprintln!("calibrate --threads 256 took {:?}", start.elapsed());
}
