//! The window as a user sees it: `kessler run --frames N --screenshot` under
//! Xvfb with Mesa's software Vulkan (`.ci/run` installs both), and the
//! pictures checked for the planet and the bodies.
//!
//! Without `xvfb-run`, `xauth` or a Vulkan driver, the tests that open a
//! window print one line saying they were skipped and why, and pass — unless
//! `KESSLER_REQUIRE_WINDOW_TESTS=1` (as in CI), where a missing tool fails
//! them.

#![cfg(feature = "gui")]

mod common {
    pub mod binary;
    pub mod skip;
}

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::binary::{KESSLER, isolated, kessler};
use common::skip::Needs;

/// Why the window cannot be opened here, if it cannot.
fn missing_window_tools() -> Option<String> {
    let on_path = |tool: &str| {
        std::env::var_os("PATH").is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(tool).is_file()))
    };
    for tool in ["xvfb-run", "xauth"] {
        if !on_path(tool) {
            return Some(format!("`{tool}` is not installed"));
        }
    }
    missing_vulkan()
}

/// Why nothing can be drawn here, even offscreen, if it cannot: no Vulkan
/// driver.
fn missing_vulkan() -> Option<String> {
    let icd_dirs = [
        "/usr/share/vulkan/icd.d",
        "/etc/vulkan/icd.d",
        "/usr/local/share/vulkan/icd.d",
    ];
    let has_driver = icd_dirs.iter().any(|dir| {
        std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .any(|entry| entry.path().extension().is_some_and(|e| e == "json"))
    });
    if !has_driver {
        return Some(format!("no Vulkan driver (no ICD file in {})", icd_dirs.join(", ")));
    }
    None
}

/// What the window tests need.
const WINDOW: Needs = Needs {
    test: "window test",
    tests: "window tests",
    require: "KESSLER_REQUIRE_WINDOW_TESTS",
    install: "apt install xvfb xauth mesa-vulkan-drivers",
};

/// Whether `test` can open a window. If not, says so on the terminal (past
/// the test harness's capture of `eprintln!`) or, when the window tests are
/// required, fails.
fn window_available(test: &str) -> bool {
    WINDOW.available(test, missing_window_tools())
}

/// Whether `test` can draw offscreen (a Vulkan driver, no X server); as
/// [`window_available`] if not.
fn vulkan_available(test: &str) -> bool {
    WINDOW.available(test, missing_vulkan())
}

/// `kessler` under a virtual X server (a 1280×800 screen), drawing with
/// Vulkan, blind to the user's own files; its arguments are to follow.
/// [`run_window`] runs the window with it; other runs under a display use
/// it directly.
fn under_xvfb() -> std::process::Command {
    let mut command = isolated("xvfb-run");
    command
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(KESSLER)
        .env("WGPU_BACKEND", "vulkan");
    command
}

/// Runs the window app under a virtual X server; returns the screenshot,
/// stdout and stderr.
fn run_window(dir: &Path, name: &str, settings: &str, extra: &[&str]) -> (PathBuf, String, String) {
    let (shot, stdout, stderr, _) = run_window_frames(dir, name, settings, 20, extra);
    (shot, stdout, stderr)
}

/// [`run_window`] for `frames` frames; also returns how long the run took.
fn run_window_frames(
    dir: &Path,
    name: &str,
    settings: &str,
    frames: u64,
    extra: &[&str],
) -> (PathBuf, String, String, Duration) {
    let shot = dir.join(format!("{name}.png"));
    let settings_path = dir.join(format!("{name}-settings.ron"));
    std::fs::write(&settings_path, settings).unwrap();
    let started = Instant::now();
    let out = under_xvfb()
        .args(["run", "--frames", &frames.to_string(), "--screenshot"])
        .arg(&shot)
        .arg("--settings")
        .arg(&settings_path)
        .args(extra)
        .output()
        .expect("xvfb-run runs");
    let took = started.elapsed();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "{name}: exit {:?}\n{stdout}\n{stderr}",
        out.status
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(shot.exists(), "{name}: no screenshot\n{stderr}");
    (shot, stdout, stderr, took)
}

struct Picture {
    width: usize,
    height: usize,
    rgb: Vec<u8>,
}

impl Picture {
    fn load(path: &Path) -> Self {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb, "screenshots are saved as RGB");
        buf.truncate(info.buffer_size());
        Self {
            width: info.width as usize,
            height: info.height as usize,
            rgb: buf,
        }
    }

    fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        let i = (y * self.width + x) * 3;
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// The egui overlays drawn over the view (the panel on the left, the
    /// HUD on the right), found by egui's window fill: in each half of the
    /// picture, the rows holding a run of at least [`OVERLAY_RUN`] fill
    /// pixels, and the columns those runs span, widened by the frame.
    /// Their size follows their text (the HUD grows a line when updates
    /// are dropped), so no test may assume where they end.
    fn overlays(&self) -> Vec<Rect> {
        let halves = [0..self.width / 2, self.width / 2..self.width];
        halves
            .into_iter()
            .filter_map(|columns| {
                let mut found: Option<Rect> = None;
                for y in 0..self.height {
                    let mut run_start = columns.start;
                    for x in columns.clone() {
                        if self.pixel(x, y) != EGUI_FILL {
                            run_start = x + 1;
                        } else if x + 1 - run_start >= OVERLAY_RUN {
                            let rect = found.get_or_insert(Rect {
                                x0: run_start,
                                y0: y,
                                x1: x,
                                y1: y,
                            });
                            (rect.x0, rect.x1) = (rect.x0.min(run_start), rect.x1.max(x));
                            (rect.y0, rect.y1) = (rect.y0.min(y), rect.y1.max(y));
                        }
                    }
                }
                found
            })
            .map(|r| Rect {
                x0: r.x0.saturating_sub(OVERLAY_FRAME),
                y0: r.y0.saturating_sub(OVERLAY_FRAME),
                x1: r.x1 + OVERLAY_FRAME,
                y1: r.y1 + OVERLAY_FRAME,
            })
            .collect()
    }
}

/// egui's window and panel fill in its dark theme.
const EGUI_FILL: [u8; 3] = [27, 27, 27];

/// Fill pixels in a row that make it part of an overlay (no body or star
/// draws a run of one exact gray this long).
const OVERLAY_RUN: usize = 24;

/// Pixels around an overlay's fill: its frame and shadow.
const OVERLAY_FRAME: usize = 6;

/// A rectangle of pixels, bounds included.
#[derive(Clone, Copy, Debug)]
struct Rect {
    x0: usize,
    y0: usize,
    x1: usize,
    y1: usize,
}

impl Rect {
    fn contains(&self, (x, y): (usize, usize)) -> bool {
        (self.x0..=self.x1).contains(&x) && (self.y0..=self.y1).contains(&y)
    }
}

/// Pixels of the 3D view, the lower half of the middle, that no overlay of
/// any of `pictures` covers: what the pictures' scenes can be compared on.
fn scene_pixels(pictures: &[&Picture]) -> Vec<(usize, usize)> {
    let (width, height) = (pictures[0].width, pictures[0].height);
    let overlays: Vec<Rect> = pictures.iter().flat_map(|p| p.overlays()).collect();
    (height / 2..height)
        .flat_map(|y| (300..width - 300).map(move |x| (x, y)))
        .filter(|&at| !overlays.iter().any(|o| o.contains(at)))
        .collect()
}

fn differs(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(b).any(|(x, y)| x.abs_diff(y) > 24)
}

#[test]
fn window_shows_the_planet_and_the_bodies() {
    if !window_available("window_shows_the_planet_and_the_bodies") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (with_bodies, report, _) = run_window(dir.path(), "bodies", "()", &[]);
    let (without, ..) = run_window(dir.path(), "empty", "(render_bodies: false)", &[]);
    let (meshes, mesh_report, _) = run_window(dir.path(), "meshes", "()", &["--render", "meshes", "--bodies", "5000"]);
    let (own, own_report, _) = run_window(
        dir.path(),
        "own",
        "()",
        &["--render", "mesh-per-body", "--bodies", "5000", "--vsync", "off"],
    );
    assert!(report.contains("render instanced"), "{report}");
    assert!(mesh_report.contains("render shared-mesh"), "{mesh_report}");
    assert!(own_report.contains("render mesh-per-body"), "{own_report}");

    let with_bodies = Picture::load(&with_bodies);
    let without = Picture::load(&without);
    let meshes = Picture::load(&meshes);
    let own = Picture::load(&own);
    assert_eq!((with_bodies.width, with_bodies.height), (1280, 800));

    // Not blank: many distinct colors.
    let mut colors: Vec<[u8; 3]> = with_bodies.rgb.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    colors.sort_unstable();
    colors.dedup();
    assert!(colors.len() > 200, "only {} colors", colors.len());

    // The Earth fills the middle of the view: within 80 pixels of the
    // center, lit ocean, continents (green or brown) and white (ice,
    // clouds), each a good share.
    let (cx, cy) = (with_bodies.width as i64 / 2, with_bodies.height as i64 / 2);
    let disc: Vec<[u8; 3]> = (-80..=80i64)
        .flat_map(|dy| (-80..=80i64).map(move |dx| (dx, dy)))
        .filter(|(dx, dy)| dx * dx + dy * dy <= 80 * 80)
        .map(|(dx, dy)| without.pixel((cx + dx) as usize, (cy + dy) as usize))
        .collect();
    let share =
        |f: &dyn Fn([u16; 3]) -> bool| disc.iter().filter(|p| f(p.map(u16::from))).count() as f64 / disc.len() as f64;
    let ocean = share(&|[r, g, b]| b > 60 && b > r + 30 && b > g);
    let land = share(&|[r, g, b]| g.max(r) > b + 10 && r.max(g).max(b) > 40 && r.min(g).min(b) < 170);
    let white = share(&|[r, g, b]| r.min(g).min(b) > 170);
    assert!(
        ocean > 0.2 && land > 0.05 && white > 0.01,
        "not the Earth around the center: ocean {ocean:.2}, land {land:.2}, white {white:.2}"
    );

    // The bodies: the debris field changes thousands of pixels of the view
    // against the same scene drawn without bodies, in all three methods.
    // Against the black sky, they are colored by state (speed) in the
    // instanced and the mesh-per-body method, and plain gray with the one
    // shared mesh: compare the mean saturation of those pixels.
    let saturation = |[r, g, b]: [u8; 3]| {
        let (hi, lo) = (r.max(g).max(b), r.min(g).min(b));
        f64::from(hi - lo) / f64::from(hi.max(1))
    };
    let mut mean_saturation = Vec::new();
    let view = scene_pixels(&[&with_bodies, &without, &meshes, &own]);
    for (name, picture) in [
        ("instanced", &with_bodies),
        ("shared mesh", &meshes),
        ("mesh per body", &own),
    ] {
        let changed = view
            .iter()
            .filter(|&&(x, y)| differs(picture.pixel(x, y), without.pixel(x, y)))
            .count();
        assert!(changed > 1000, "{name}: only {changed} pixels show bodies");
        let on_sky: Vec<f64> = view
            .iter()
            .filter(|&&(x, y)| without.pixel(x, y).iter().all(|&c| c < 30))
            .map(|&(x, y)| picture.pixel(x, y))
            .filter(|p| p.iter().any(|&c| c > 60))
            .map(saturation)
            .collect();
        assert!(
            on_sky.len() > 200,
            "{name}: only {} body pixels on the sky",
            on_sky.len()
        );
        mean_saturation.push(on_sky.iter().sum::<f64>() / on_sky.len() as f64);
    }
    let [instanced, shared, own] = mean_saturation[..] else {
        unreachable!()
    };
    assert!(
        own > 1.4 * shared && instanced > 1.4 * shared,
        "mean saturation of body pixels on the sky: instanced {instanced:.3}, shared mesh {shared:.3}, mesh per body {own:.3}"
    );
}

/// The thesis scene, 10 000 unit cubes about 2 500 units from the camera,
/// reads as a cloud: each body keeps a least size on screen, so a tenth of
/// the view outside the panel and the HUD is lit by bodies (sub-pixel dots
/// lit under half a percent), while the stars alone, smaller and dimmer
/// than any body, light under one percent and never brightly.
#[test]
fn the_thesis_cloud_reads_as_a_cloud_and_the_stars_stay_dim() {
    if !window_available("the_thesis_cloud_reads_as_a_cloud_and_the_stars_stay_dim") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    let (cloud, ..) = run_window(dir.path(), "cloud", "()", &[scene]);
    let (sky, ..) = run_window(dir.path(), "sky", "(render_bodies: false)", &[scene]);
    let (cloud, sky) = (Picture::load(&cloud), Picture::load(&sky));
    for picture in [&cloud, &sky] {
        assert_eq!(
            picture.overlays().len(),
            2,
            "the panel and the HUD: {:?}",
            picture.overlays()
        );
    }
    let (cx, cy) = (cloud.width as i64 / 2, cloud.height as i64 / 2);
    // The view outside the panel and the HUD, away from the planet.
    let around: Vec<(usize, usize)> = scene_pixels(&[&cloud, &sky])
        .into_iter()
        .filter(|&(x, y)| (x as i64 - cx).pow(2) + (y as i64 - cy).pow(2) > 120 * 120)
        .collect();
    let lit = |picture: &Picture| {
        around
            .iter()
            .filter(|&&(x, y)| picture.pixel(x, y).iter().any(|&c| c > 60))
            .count() as f64
            / around.len() as f64
    };
    let (bodies, stars) = (lit(&cloud), lit(&sky));
    assert!(bodies > 0.03, "only {:.2} % of the view shows bodies", bodies * 100.0);
    assert!(stars < 0.01, "the stars alone light {:.2} % of the view", stars * 100.0);
    let brightest_star = around
        .iter()
        .map(|&(x, y)| *sky.pixel(x, y).iter().max().unwrap())
        .max()
        .unwrap();
    assert!(brightest_star < 140, "a star as bright as {brightest_star}");
}

#[test]
fn a_benchmark_render_run_reports_frames_memory_and_gpu_memory() {
    if !window_available("a_benchmark_render_run_reports_frames_memory_and_gpu_memory") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("render.ron");
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/thesis_cloud.ron");
    std::fs::write(
        &config,
        format!(
            r#"Bench(scenario: "{scenario}", runs: [
                Render(bodies: 300, frames: 15, method: MeshPerBody),
                Render(bodies: 300, frames: 15, method: Instanced, simulate: true, ups: 30),
            ])"#
        ),
    )
    .unwrap();
    let out = dir.path().join("render-results.csv");
    let result = under_xvfb()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("xvfb-run runs");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "{stderr}");
    let csv = std::fs::read_to_string(dir.path().join("render-results-render.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(
        lines[0].starts_with("run,bodies,method,simulate,mode,vsync,frames,mean_fps"),
        "{csv}"
    );
    for (line, method, simulate) in [(lines[1], "mesh-per-body", "false"), (lines[2], "instanced", "true")] {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!((f[2], f[3], f[5]), (method, simulate, "off"), "{line}");
        // The scene's 300 cubes and its planet.
        assert_eq!(f[1], "301", "{line}");
        let number = |k: usize| f[k].parse::<f64>().unwrap();
        assert!(number(6) >= 15.0, "frames timed after the warm-up: {line}");
        assert!(
            number(7) > 0.0 && number(8) > 0.0 && number(9) >= number(8) * 0.5,
            "{line}"
        );
        assert!(number(11) > 1e6, "peak RAM of a window is more than a megabyte: {line}");
        assert!(
            number(12) > 0.0 && !f[13].is_empty() && !f[14].is_empty(),
            "GPU memory and its source: {line}"
        );
    }
    // The simulated run updated; the paused one did not.
    let ups = |line: &str| line.split(',').nth(10).unwrap().parse::<f64>().unwrap();
    assert_eq!(ups(lines[1]), 0.0, "{csv}");
    assert!(ups(lines[2]) > 0.0, "{csv}");
    // No headless runs: no results CSV, but the machine report.
    assert!(!out.exists());
    assert!(dir.path().join("render-results-machine.txt").exists());
}

#[test]
fn broken_settings_warn_and_survive_a_run() {
    if !window_available("broken_settings_warn_and_survive_a_run") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let broken = "(threads: \"many\"";
    let (.., stderr) = run_window(dir.path(), "broken", broken, &["--paused", "--bodies", "100"]);
    assert!(
        stderr.contains("warning") && stderr.contains("broken-settings.ron"),
        "no warning naming the file: {stderr}"
    );
    let kept = std::fs::read_to_string(dir.path().join("broken-settings.ron")).unwrap();
    assert_eq!(kept, broken, "an unchanged session must not rewrite the file");
}

/// The `kessler: warning: ` lines of a run's stderr that name `file`.
fn warnings_about<'a>(stderr: &'a str, file: &str) -> Vec<&'a str> {
    stderr
        .lines()
        .filter(|line| line.starts_with("kessler: warning: ") && line.contains(file))
        .collect()
}

#[test]
fn out_of_range_settings_warn_once_and_survive_a_run_byte_for_byte() {
    if !window_available("out_of_range_settings_warn_once_and_survive_a_run_byte_for_byte") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Out of range: more threads than the window offers on this machine
    // (twice its hardware threads), more fragments than a shatter may make,
    // a negative threshold. The command line adds one-run choices.
    let text = "(\n    threads: 256,\n    shatter_fragments: 5000,\n    shatter_threshold: -1.0,\n)\n";
    let scenario = concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/cascade.ron");
    let (.., stderr) = run_window(
        dir.path(),
        "out-of-range",
        text,
        &[scenario, "--bodies", "200", "--paused", "--render", "shared-mesh"],
    );
    let warnings = warnings_about(&stderr, "out-of-range-settings.ron");
    assert_eq!(warnings.len(), 1, "one warning line about the file:\n{stderr}");
    let hardware = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut said = vec!["shatter_fragments 5000", "shatter_threshold -1.0", "using"];
    if hardware * 2 < 256 {
        said.push("threads 256");
    }
    for said in said {
        assert!(warnings[0].contains(said), "{said:?} not in {}", warnings[0]);
    }
    let kept = std::fs::read_to_string(dir.path().join("out-of-range-settings.ron")).unwrap();
    assert_eq!(kept, text, "an unchanged session must not rewrite the file");
}

#[test]
fn settings_beyond_the_panels_sliders_and_one_run_choices_are_not_saved() {
    if !window_available("settings_beyond_the_panels_sliders_and_one_run_choices_are_not_saved") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // Allowed values past the ends of the panel's sliders: the panel used
    // to clamp them, which counted as a change and saved the session's
    // settings, `--bodies` included.
    let text = "(shatter_fragments: 50, shatter_threshold: 100.0, gravity_method: Tree(theta: 1.9))";
    let (.., stderr) = run_window(dir.path(), "beyond", text, &["--bodies", "200", "--paused"]);
    assert!(
        warnings_about(&stderr, "beyond-settings.ron").is_empty(),
        "allowed values need no warning:\n{stderr}"
    );
    let kept = std::fs::read_to_string(dir.path().join("beyond-settings.ron")).unwrap();
    assert_eq!(kept, text, "no body_count, nothing clamped: the file is not rewritten");
}

#[test]
fn a_scripted_run_of_a_scene_without_cubes_does_not_wait_for_them() {
    if !window_available("a_scripted_run_of_a_scene_without_cubes_does_not_wait_for_them") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("empty.ron");
    std::fs::write(&scenario, "Scenario()").unwrap();
    let (.., took) = run_window_frames(dir.path(), "no-cubes", "()", 5, &[scenario.to_str().unwrap()]);
    // A bound on a hang (each of a scripted run's waits, for the scene to
    // be drawn and for the pipelines to settle, gives up after 120 s), not
    // a speed test.
    assert!(took < Duration::from_secs(60), "took {took:?}");
}

#[test]
fn screenshot_never_overwrites() {
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("exists.png");
    std::fs::write(&shot, "precious").unwrap();
    let out = kessler()
        .args(["run", "--frames", "1", "--screenshot"])
        .arg(&shot)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        stderr.contains("exists.png") && stderr.contains("exists already"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&shot).unwrap(), "precious");
}

#[test]
fn without_a_display_the_window_says_so() {
    let out = kessler()
        .args(["run", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("DISPLAY") && stderr.contains("headless"), "{stderr}");
}

#[test]
fn a_benchmark_with_render_runs_needs_a_display_and_writes_nothing_without() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("render.ron");
    std::fs::write(
        &config,
        "Bench(runs: [Run(bodies: 10, updates: 2), Render(bodies: 10, frames: 5, method: Instanced)])",
    )
    .unwrap();
    let out = kessler()
        .arg("bench")
        .arg(&config)
        .arg("--out")
        .arg(dir.path().join("results.csv"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("render.ron") && stderr.contains("runs[1]") && stderr.contains("DISPLAY"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "only the config is there"
    );
}

/// A settings file that is a FIFO, and a saved scenario that names one,
/// are refused at once with a warning: the window opens on defaults and
/// the built-in scene instead of waiting for a writer.
#[cfg(unix)]
#[test]
fn fifos_as_settings_or_saved_scenario_warn_instead_of_hanging() {
    if !window_available("fifos_as_settings_or_saved_scenario_warn_instead_of_hanging") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo.ron");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    // The saved scenario is the FIFO.
    let settings = format!("(scenario: Some({:?}))", fifo.display().to_string());
    let (.., stderr, took) = run_window_frames(dir.path(), "fifo-scenario", &settings, 3, &["--paused"]);
    assert!(
        stderr.contains("saved scenario") && stderr.contains("is a FIFO (named pipe)"),
        "{stderr}"
    );
    assert!(took < Duration::from_secs(100), "took {took:?}");
    // The settings file is the FIFO.
    let shot = dir.path().join("fifo-settings.png");
    let out = under_xvfb()
        .args(["run", "--frames", "3", "--paused", "--bodies", "100", "--screenshot"])
        .arg(&shot)
        .arg("--settings")
        .arg(&fifo)
        .output()
        .expect("xvfb-run runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("is a FIFO (named pipe)"), "{stderr}");
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(),
        "the FIFO was replaced"
    );
}

/// The sandbox's tools through the message the panel's buttons send
/// (`--actions`): a launched ring, a fired impactor, a breakup, a removal,
/// a saved session; the state the window had at its close (`--dump`) is
/// the one `kessler headless SESSION --steps U` reaches, and the tools'
/// effects show in the pictures.
#[test]
fn a_session_of_tool_actions_replays_headless_to_the_windows_state() {
    if !window_available("a_session_of_tool_actions_replays_headless_to_the_windows_state") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("ring.ron");
    std::fs::write(
        &scenario,
        "Scenario(name: \"ring\", bodies: [
            Body(position: (0, 0, 0), shape: Sphere(radius: 430), mass: 4000, role: Source, interacts: false, absorbs: true),
        ], generators: [Shell(count: 300, around: 0, inner_radius: 700, outer_radius: 800, inclination: 0)])",
    )
    .unwrap();
    let session = dir.path().join("session.ron");
    let actions = dir.path().join("actions.ron");
    std::fs::write(
        &actions,
        format!(
            "[
                (frame: 3, action: Launch(altitude: 150, inclination: 60, count: 24, half_size: 2, mass: 3)),
                (frame: 5, action: Select(3)),
                (frame: 5, action: Fire(speed: 6, distance: 30, from_camera: true)),
                (frame: 7, action: Select(5)),
                (frame: 7, action: Breakup(fragments: 6, speed: 1.5)),
                (frame: 9, action: Select(7)),
                (frame: 9, action: Remove),
                (frame: 12, action: SaveSession({:?})),
            ]",
            session.display().to_string()
        ),
    )
    .unwrap();
    let dump = dir.path().join("window.csv");
    let (shot, stdout, _, _) = run_window_frames(
        dir.path(),
        "tools",
        "(updates_per_second: 60)",
        30,
        &[
            "--actions",
            actions.to_str().unwrap(),
            "--dump",
            dump.to_str().unwrap(),
            scenario.to_str().unwrap(),
        ],
    );
    let updates: u64 = stdout
        .split("closed after ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no update count at the close: {stdout}"));
    let text = std::fs::read_to_string(&session).expect("the session was saved");
    for kind in ["Spawn(", "Fire(", "Breakup(", "Remove("] {
        assert!(text.contains(kind), "{kind} not recorded:\n{text}");
    }
    let replay = dir.path().join("replay.csv");
    let out = kessler()
        .args(["headless", "--steps", &updates.to_string(), "--dump"])
        .arg(&replay)
        .arg(&session)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let window_state = std::fs::read_to_string(&dump).unwrap();
    // Each action left its mark: the planet is 0 and the ring 1–300, the
    // launch made 301–324, the shot 325 and the breakup of 5 its fragments
    // from 326; 7 was removed. (How many survive depends on how many
    // updates the run took, which depends on the machine; fragments and a
    // missing 5 could also come from a collision, so the session's text is
    // checked for each kind of event above.)
    let ids: Vec<u64> = window_state
        .lines()
        .skip(1)
        .filter_map(|line| line.split(',').next()?.parse().ok())
        .collect();
    let launched = ids.iter().filter(|id| (301..=324).contains(*id)).count();
    let fragments = ids.iter().filter(|&&id| id >= 326).count();
    assert!(
        launched > 0 && fragments > 0,
        "{updates} updates: {launched} launched, {fragments} fragments"
    );
    assert!(
        !ids.contains(&5) && !ids.contains(&7),
        "5 broken up and 7 removed: {ids:?}"
    );
    assert_eq!(
        std::fs::read_to_string(&replay).unwrap(),
        window_state,
        "the replay of {} after {updates} updates",
        session.display()
    );
    assert!(shot.exists());
}

/// Every way a body enters the world passes the same checks: tool actions
/// that a scenario file could not hold (a launch of bodies without mass or
/// size, a shot backwards, a breakup into one fragment, a planet's
/// breakup, a launch past the body budget) are refused and not recorded,
/// so the session saved after them is one `validate` accepts and holds
/// only the launch that was allowed.
#[test]
fn tool_actions_are_held_to_the_files_rules_and_refusals_are_not_recorded() {
    if !window_available("tool_actions_are_held_to_the_files_rules_and_refusals_are_not_recorded") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let scenario = dir.path().join("planet.ron");
    std::fs::write(
        &scenario,
        "Scenario(bodies: [
            Body(position: (0, 0, 0), shape: Sphere(radius: 430), mass: 4000, role: Source, interacts: false),
            Body(position: (700, 0, 0), velocity: (0, 0, 2)),
        ])",
    )
    .unwrap();
    let (session, actions) = (dir.path().join("session.ron"), dir.path().join("actions.ron"));
    std::fs::write(
        &actions,
        format!(
            "[
                (frame: 3, action: Launch(altitude: 150, inclination: 0, count: 4, half_size: 2, mass: 0)),
                (frame: 3, action: Launch(altitude: 150, inclination: 0, count: 4, half_size: 0, mass: 1)),
                (frame: 3, action: Launch(altitude: 150, inclination: 0, count: 4294967295, half_size: 1, mass: 1)),
                (frame: 3, action: Launch(altitude: 1e38, inclination: 0, count: 2, half_size: 1, mass: 1)),
                (frame: 4, action: Select(1)),
                (frame: 4, action: Fire(speed: -5, distance: 30, from_camera: false)),
                (frame: 4, action: Fire(speed: 5, distance: 0, from_camera: false)),
                (frame: 4, action: Breakup(fragments: 1, speed: 1)),
                (frame: 4, action: Breakup(fragments: 5000, speed: 1)),
                (frame: 5, action: Select(0)),
                (frame: 5, action: Breakup(fragments: 5, speed: 1)),
                (frame: 6, action: Launch(altitude: 150, inclination: 0, count: 3, half_size: 1, mass: 1)),
                (frame: 8, action: SaveSession({:?})),
            ]",
            session.display().to_string()
        ),
    )
    .unwrap();
    let (_, _, stderr) = run_window(
        dir.path(),
        "refused",
        "(updates_per_second: 60)",
        &["--actions", actions.to_str().unwrap(), scenario.to_str().unwrap()],
    );
    for problem in [
        "`bodies[0].mass`",
        "`bodies[0].half_extents`",
        "`max_bodies`",
        "`speed`",
        "`distance`",
        "`fragments`",
        "does not interact",
    ] {
        assert!(stderr.contains(problem), "{problem} not said:\n{stderr}");
    }
    let text = std::fs::read_to_string(&session).expect("the session was saved");
    assert_eq!(text.matches("Spawn(").count(), 1, "{text}");
    assert!(!text.contains("Fire(") && !text.contains("Breakup("), "{text}");
    let validated = kessler().arg("validate").arg(&session).output().unwrap();
    assert!(
        validated.status.success(),
        "{}",
        String::from_utf8_lossy(&validated.stderr)
    );
}

/// A tool's effect shows in the next drawn frame, even while paused: a
/// ring launched in the frame before the screenshot changes the picture
/// of the same paused scene without it.
#[test]
fn a_launched_ring_shows_in_the_next_frame_while_paused() {
    if !window_available("a_launched_ring_shows_in_the_next_frame_while_paused") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let actions = dir.path().join("launch.ron");
    std::fs::write(
        &actions,
        "[(frame: 11, action: Launch(altitude: 900, inclination: 70, count: 300, half_size: 4, mass: 1))]",
    )
    .unwrap();
    let (plain, ..) = run_window_frames(dir.path(), "plain", "()", 12, &["--paused"]);
    let (launched, stdout, ..) = run_window_frames(
        dir.path(),
        "launched",
        "()",
        12,
        &["--paused", "--actions", actions.to_str().unwrap()],
    );
    assert!(stdout.contains("0 updates"), "paused: {stdout}");
    let (plain, launched) = (Picture::load(&plain), Picture::load(&launched));
    let changed = scene_pixels(&[&plain, &launched])
        .into_iter()
        .filter(|&(x, y)| differs(plain.pixel(x, y), launched.pixel(x, y)))
        .count();
    assert!(changed > 300, "only {changed} pixels changed");
}

/// `--offscreen` draws into an image without an X server (DISPLAY unset):
/// the same screenshot — the Earth in the middle — and a film of numbered
/// pictures every `--every` updates, in which the bodies move.
#[test]
fn offscreen_runs_draw_without_an_x_server_and_film_the_run() {
    if !vulkan_available("offscreen_runs_draw_without_an_x_server_and_film_the_run") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // The film's folder does not exist yet: it is made.
    let (shot, film, settings) = (
        dir.path().join("shot.png"),
        dir.path().join("films/first"),
        dir.path().join("s.ron"),
    );
    std::fs::write(&settings, "(updates_per_second: 60)").unwrap();
    let out = kessler()
        .args(["run", "--offscreen", "--frames", "30", "--every", "10", "--screenshot"])
        .arg(&shot)
        .arg("--frames-out")
        .arg(&film)
        .arg("--settings")
        .arg(&settings)
        .env_remove("DISPLAY")
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let picture = Picture::load(&shot);
    assert_eq!((picture.width, picture.height), (1280, 800));
    // The ocean's blue in the middle of a picture: (its pixels, of all).
    let ocean = |picture: &Picture| {
        let (cx, cy) = (640, 400);
        let disc: Vec<[u8; 3]> = (-60..=60i64)
            .flat_map(|dy| (-60..=60i64).map(move |dx| (dx, dy)))
            .map(|(dx, dy)| picture.pixel((cx + dx) as usize, (cy + dy) as usize))
            .collect();
        let blue = disc
            .iter()
            .filter(|[r, g, b]| *b > 60 && *b > r.saturating_add(30) && b > g)
            .count();
        (blue, disc.len())
    };
    let (blue, all) = ocean(&picture);
    assert!(blue * 5 > all, "no Earth in the middle: {blue} of {all}");
    let mut frames: Vec<PathBuf> = std::fs::read_dir(&film).unwrap().map(|e| e.unwrap().path()).collect();
    frames.sort();
    assert!(frames.len() >= 2, "{frames:?}");
    assert!(frames[0].ends_with("frame-000001.png"), "{frames:?}");
    let (first, last) = (Picture::load(&frames[0]), Picture::load(frames.last().unwrap()));
    // The film starts once the scene is drawn in full, not while shaders
    // compile (on a fast GPU, its first picture used to be black).
    let (blue, all) = ocean(&first);
    assert!(blue * 5 > all, "the film's first picture has no Earth: {blue} of {all}");
    let moved = scene_pixels(&[&first, &last])
        .into_iter()
        .filter(|&(x, y)| differs(first.pixel(x, y), last.pixel(x, y)))
        .count();
    assert!(moved > 100, "the film's pictures are all alike: {moved} pixels changed");
    // A second film into the same folder would overwrite the first.
    let again = kessler()
        .args(["run", "--offscreen", "--frames", "5", "--frames-out"])
        .arg(&film)
        .arg("--settings")
        .arg(&settings)
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert_eq!(
        again.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(String::from_utf8_lossy(&again.stderr).contains("--frames-out"));
    // So would one into a folder holding any picture of a film, not only
    // the first.
    let other = dir.path().join("other");
    std::fs::create_dir(&other).unwrap();
    std::fs::write(other.join("frame-000002.png"), "precious").unwrap();
    let refused = kessler()
        .args(["run", "--offscreen", "--frames", "5", "--frames-out"])
        .arg(&other)
        .arg("--settings")
        .arg(&settings)
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("frame-000002.png exists already"), "{stderr}");
    assert_eq!(std::fs::read_dir(&other).unwrap().count(), 1);
}

/// A film whose pictures cannot all be saved (something took their names
/// during the run) leaves what it found alone and ends with exit status 1,
/// as every command does when an output fails.
#[test]
fn a_film_that_loses_pictures_fails_and_replaces_nothing() {
    if !vulkan_available("a_film_that_loses_pictures_fails_and_replaces_nothing") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (film, settings) = (dir.path().join("film"), dir.path().join("s.ron"));
    std::fs::write(&settings, "(updates_per_second: 60)").unwrap();
    let child = isolated(KESSLER)
        .args(["run", "--offscreen", "--frames", "150", "--every", "1", "--frames-out"])
        .arg(&film)
        .arg("--settings")
        .arg(&settings)
        .env_remove("DISPLAY")
        .env("WGPU_BACKEND", "vulkan")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while !film.join("frame-000001.png").exists() {
        assert!(started.elapsed().as_secs() < 120, "no picture after two minutes");
        std::thread::sleep(Duration::from_millis(20));
    }
    let taken: Vec<PathBuf> = (40..600).map(|k| film.join(format!("frame-{k:06}.png"))).collect();
    for path in &taken {
        std::fs::write(path, "taken").unwrap();
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("cannot save a film's picture"), "{stderr}");
    assert!(stderr.contains("could not be written"), "{stderr}");
    for path in &taken {
        assert_eq!(std::fs::read_to_string(path).unwrap(), "taken", "{}", path.display());
    }
}

/// A window run ends as a headless run of its scene does: stopped by a
/// fault (an adopter 1e-10 from a heavy source overflows at update 4), it
/// writes no state at the close (that state is half an update) and exits
/// 3, saying why; a scripted save that fails (onto a file that exists,
/// `/dev/full`, a folder, into a missing folder) says so on stderr, each,
/// and the run exits 1. Offscreen and in a window alike.
#[test]
fn a_window_run_that_stops_or_loses_an_output_ends_as_a_headless_run_does() {
    if !vulkan_available("a_window_run_that_stops_or_loses_an_output_ends_as_a_headless_run_does")
        || !window_available("a_window_run_that_stops_or_loses_an_output_ends_as_a_headless_run_does")
    {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let settings = dir.path().join("s.ron");
    std::fs::write(&settings, "(updates_per_second: 60)").unwrap();
    let overflow = dir.path().join("overflow.ron");
    std::fs::write(
        &overflow,
        "Scenario(gravitational_constant: 1e6, bodies: [\
         Body(position: (0, 0, 0), mass: 1e12, role: Source, interacts: false),\
         Body(position: (1e-10, 0, 0), interacts: false)])",
    )
    .unwrap();
    let (existing, folder) = (dir.path().join("existing.ron"), dir.path().join("folder"));
    std::fs::write(&existing, "precious").unwrap();
    std::fs::create_dir(&folder).unwrap();
    let missing = dir.path().join("missing").join("s.ron");
    let actions = dir.path().join("saves.ron");
    std::fs::write(
        &actions,
        format!(
            "[(frame: 1, action: SaveSession({existing:?})), (frame: 1, action: SaveSession(\"/dev/full\")), \
             (frame: 2, action: SaveSession({folder:?})), (frame: 3, action: SaveSession({missing:?}))]"
        ),
    )
    .unwrap();
    let dump = dir.path().join("window.csv");
    for offscreen in [true, false] {
        let run = |args: &[&std::ffi::OsStr]| {
            let mut command = if offscreen {
                let mut command = isolated(KESSLER);
                command
                    .env_remove("DISPLAY")
                    .env("WGPU_BACKEND", "vulkan")
                    .args(["run", "--offscreen"]);
                command
            } else {
                let mut command = under_xvfb();
                command.arg("run");
                command
            };
            command.arg("--settings").arg(&settings).args(args).output().unwrap()
        };
        std::fs::write(&dump, "precious").unwrap();
        let out = run(&[
            "--frames".as_ref(),
            "20".as_ref(),
            "--dump".as_ref(),
            dump.as_os_str(),
            overflow.as_os_str(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "offscreen {offscreen}: {stderr}");
        let said: Vec<&str> = stderr.lines().filter(|l| l.starts_with("kessler: error:")).collect();
        assert_eq!(said.len(), 1, "{stderr}");
        for needle in [
            "overflow.ron: update 4: body 1 has a non-finite position",
            "the simulation stopped; the state at the close, half an update, was not written",
        ] {
            assert!(said[0].contains(needle), "{needle} not in {stderr}");
        }
        assert_eq!(std::fs::read_to_string(&dump).unwrap(), "precious");
        assert!(!String::from_utf8_lossy(&out.stdout).contains("closed after"));

        let out = run(&[
            "--frames".as_ref(),
            "6".as_ref(),
            "--actions".as_ref(),
            actions.as_os_str(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "offscreen {offscreen}: {stderr}");
        let said: Vec<&str> = stderr
            .lines()
            .filter(|l| l.contains("cannot save the session"))
            .collect();
        assert_eq!(said.len(), 4, "offscreen {offscreen}: {stderr}");
        for (line, path) in said.iter().zip([
            existing.display().to_string(),
            "/dev/full".to_owned(),
            folder.display().to_string(),
            missing.display().to_string(),
        ]) {
            assert!(line.contains(&path), "{path} not in {line}");
        }
        assert!(
            stderr.contains("4 output(s) of the run could not be written"),
            "{stderr}"
        );
        assert_eq!(std::fs::read_to_string(&existing).unwrap(), "precious");
        assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0);
    }
}

/// A benchmark's `Render` run with `offscreen: true` measures frames
/// without a display.
#[test]
fn an_offscreen_render_run_needs_no_display() {
    if !vulkan_available("an_offscreen_render_run_needs_no_display") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("offscreen.ron");
    std::fs::write(
        &config,
        "Bench(runs: [Render(bodies: 2000, frames: 10, method: Instanced, offscreen: true)])",
    )
    .unwrap();
    let out = kessler()
        .args(["bench"])
        .arg(&config)
        .arg("--out")
        .arg(dir.path().join("offscreen.csv"))
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = std::fs::read_to_string(dir.path().join("offscreen-render.csv")).unwrap();
    assert_eq!(rows.lines().count(), 2, "{rows}");
    assert!(rows.contains(",instanced,"), "{rows}");
}

/// A bad action script is one line of error naming the field, exit 2,
/// before anything of the window starts (no renderer's log around it).
#[test]
fn a_bad_action_script_is_refused_before_the_window_starts() {
    if !window_available("a_bad_action_script_is_refused_before_the_window_starts") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let actions = dir.path().join("actions.ron");
    std::fs::write(
        &actions,
        "[(frame: 1, action: Launch(altitude: 1, inclination: 0, count: -1, half_size: 1, mass: 1))]",
    )
    .unwrap();
    let out = under_xvfb()
        .args(["run", "--frames", "5", "--actions"])
        .arg(&actions)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "not one line: {stderr}");
    assert!(stderr.contains("actions.ron"), "{stderr}");
    assert!(stderr.contains("field `count`"), "which field: {stderr}");
}
