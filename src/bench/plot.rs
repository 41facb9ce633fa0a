//! The benchmark plot: update time against body count, log–log, one color
//! per execution setting (sequential, parallel on T threads with its split
//! policy), a thick line for the whole update and a thin dashed line for
//! each stage of the stage list, each measured point marked (the whole
//! update by a large dot, each stage by a shape of its own, so a setting
//! measured at one count still shows), ticks labelled at the decades only
//! (so no two labels run into each other), a vertical mark where parallel
//! with split `Always` starts to beat sequential (the crossover), and a
//! footer naming the machine and the commit. Drawn with plotters as SVG
//! and as PNG; the labels use the Ubuntu
//! font that `epaint_default_fonts` bundles (the crate egui takes its fonts
//! from), so the PNG reads the same on every machine, with or without
//! system fonts.

use std::collections::BTreeMap;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::crossover::Crossover;
use super::measured_run::RunResult;
use crate::execution::{ExecutionMode, SplitPolicy, WorkerPool};
use crate::output::{FONT, Figure, Labels, PLOT_SIZE, PlotError, figure_png, figure_svg, grouped, page};
use crate::systems::STAGES;

/// Width of the legend at the right.
const LEGEND_WIDTH: u32 = 290;
/// Colors of the execution settings, in turn.
const SETTING_COLORS: [RGBColor; 6] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

/// The plot as an SVG document.
pub fn svg(results: &[RunResult], crossovers: &[Crossover], labels: Labels<'_>) -> Result<String, PlotError> {
    figure_svg(&RunsPlot {
        results,
        crossovers,
        labels,
    })
}

/// The plot as a PNG image.
pub fn png(results: &[RunResult], crossovers: &[Crossover], labels: Labels<'_>) -> Result<Vec<u8>, PlotError> {
    figure_png(&RunsPlot {
        results,
        crossovers,
        labels,
    })
}

/// The runs' plot: what [`svg`] and [`png`] draw.
struct RunsPlot<'a> {
    results: &'a [RunResult],
    crossovers: &'a [Crossover],
    labels: Labels<'a>,
}

impl Figure for RunsPlot<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        draw_on(root, self.results, self.crossovers, self.labels)
    }
}

/// Dash length and gap of the `k`-th stage's line, pixels.
fn dash(k: usize) -> (u32, u32) {
    let k = k as u32;
    (2 + 4 * k, 3 + k)
}

/// Runs `$draw` on the `$k`-th stage's marker at `$at` in `$color`: a
/// filled and a hollow circle, a triangle, a hollow square, a cross, a
/// filled square (six shapes for the six stages, then again).
macro_rules! stage_marker {
    ($k:expr, $at:expr, $color:expr, |$e:ident| $draw:expr) => {
        match $k % 6 {
            0 => {
                let $e = Circle::new($at, 4, $color.filled());
                $draw
            }
            1 => {
                let $e = Circle::new($at, 4, $color.stroke_width(1));
                $draw
            }
            2 => {
                let $e = TriangleMarker::new($at, 5, $color.filled());
                $draw
            }
            3 => {
                let $e = EmptyElement::at($at) + Rectangle::new([(-3, -3), (3, 3)], $color.stroke_width(1));
                $draw
            }
            4 => {
                let $e = Cross::new($at, 4, $color.stroke_width(2));
                $draw
            }
            _ => {
                let $e = EmptyElement::at($at) + Rectangle::new([(-3, -3), (3, 3)], $color.filled());
                $draw
            }
        }
    };
}

/// Whether `v` is a power of ten (to a rounding), the only ticks labelled.
#[expect(clippy::disallowed_methods, reason = "a plot's axis, not the state")]
fn is_decade(v: f64) -> bool {
    v > 0.0 && (v.log10() - v.log10().round()).abs() < 1e-9
}

/// A tick's label: a decade written out in groups of three digits
/// (`100 000`), or below one as a decimal; nothing between decades.
fn decade_label(v: f64) -> String {
    if !is_decade(v) {
        String::new()
    } else if v >= 1.0 {
        grouped(v as u64)
    } else {
        format!("{v}")
    }
}

/// The decades `10^lo..10^hi` that hold every positive value (1..10 if
/// there is none).
#[expect(clippy::disallowed_methods, reason = "a plot's axis, not the state")]
fn decades(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| *v > 0.0) {
        lo = lo.min(v.log10().floor());
        hi = hi.max(v.log10().ceil());
    }
    if !lo.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    10f64.powf(lo)..10f64.powf(hi.max(lo + 1.0))
}

/// An execution setting: mode, threads, and split policy (`None` in
/// sequential mode, where it does not apply).
type Setting = (ExecutionMode, usize, Option<String>);

fn setting_of(r: &RunResult) -> Setting {
    let split = (r.mode == ExecutionMode::Parallel).then(|| match r.pool {
        WorkerPool::Kessler => r.split.to_string(),
        WorkerPool::Bevy => format!("{}, Bevy's pool", r.split),
    });
    (r.mode, r.threads, split)
}

/// What a setting is called in the legend.
fn setting_name((mode, threads, split): &Setting) -> String {
    match split {
        None => mode.to_string(),
        Some(split) => {
            let split = if split.parse::<u64>().is_ok() {
                format!("from {split}")
            } else {
                split.clone()
            };
            format!(
                "{mode}, {threads} thread{}, split {split}",
                if *threads == 1 { "" } else { "s" }
            )
        }
    }
}

fn draw_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    results: &[RunResult],
    crossovers: &[Crossover],
    labels: Labels<'_>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let ms = |ns: f64| ns / 1e6;
    // Runs by execution setting, sequential first.
    let mut settings: BTreeMap<Setting, Vec<&RunResult>> = BTreeMap::new();
    for r in results.iter().filter(|r| r.bodies_start > 0) {
        settings.entry(setting_of(r)).or_default().push(r);
    }
    let all = || settings.values().flatten();
    let x_range = decades(all().map(|r| r.bodies_start as f64));
    let y_range = decades(
        all()
            .flat_map(|r| std::iter::once(r.update_ns).chain(r.stage_ns))
            .map(ms),
    );

    let root = page(root, labels.footer)?;
    let (plot_area, legend_area) = root.split_horizontally(PLOT_SIZE.0 - LEGEND_WIDTH);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(labels.title, (FONT, 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x_range.log_scale(), y_range.clone().log_scale())?;
    chart
        .configure_mesh()
        .x_desc("bodies")
        .y_desc("time per update, ms")
        .label_style((FONT, 13))
        .x_label_formatter(&|v| decade_label(*v))
        .y_label_formatter(&|v| decade_label(*v))
        .draw()?;
    for (i, runs) in settings.values_mut().enumerate() {
        runs.sort_by_key(|r| r.bodies_start);
        let color = SETTING_COLORS[i % SETTING_COLORS.len()];
        let update: Vec<(f64, f64)> = runs.iter().map(|r| (r.bodies_start as f64, ms(r.update_ns))).collect();
        chart.draw_series(LineSeries::new(update.iter().copied(), color.stroke_width(3)))?;
        chart.draw_series(update.iter().map(|&p| Circle::new(p, 5, color.filled())))?;
        for (k, stage) in STAGES.iter().enumerate() {
            let line: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| r.stage(stage.stage) > 0.0)
                .map(|r| (r.bodies_start as f64, ms(r.stage(stage.stage))))
                .collect();
            let (length, gap) = dash(k);
            chart.draw_series(DashedLineSeries::new(
                line.iter().copied(),
                length,
                gap,
                color.stroke_width(1),
            ))?;
            for &p in &line {
                stage_marker!(k, p, color, |e| chart.draw_series(std::iter::once(e))?);
            }
        }
    }
    // The crossover of the whole update: a vertical line in the color of
    // the `Always` setting it belongs to.
    let always = SplitPolicy::Always.to_string();
    for c in crossovers.iter().filter(|c| c.stage == "update") {
        let (Some(n), Some(i)) = (
            c.from_bodies.filter(|&n| n > 0),
            settings.keys().position(|(mode, threads, split)| {
                *mode == ExecutionMode::Parallel && *threads == c.threads && split.as_ref() == Some(&always)
            }),
        ) else {
            continue;
        };
        let color = SETTING_COLORS[i % SETTING_COLORS.len()];
        let x = n as f64;
        chart.draw_series(DashedLineSeries::new(
            [(x, y_range.start), (x, y_range.end)],
            8,
            4,
            color.stroke_width(2),
        ))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("crossover: {n}"),
            (x * 1.08, y_range.end / 2.0),
            (FONT, 13).into_font().color(&color),
        )))?;
    }
    draw_legend(&legend_area, settings.keys())
}

/// The legend: a color swatch per setting, then the line style of the whole
/// update and of each stage.
fn draw_legend<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    settings: impl Iterator<Item = &'a Setting>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let text = (FONT, 13).into_font().color(&BLACK);
    let mut y = 60;
    for (i, setting) in settings.enumerate() {
        let color = SETTING_COLORS[i % SETTING_COLORS.len()];
        area.draw(&Rectangle::new([(10, y - 7), (24, y + 7)], color.filled()))?;
        area.draw(&Text::new(setting_name(setting), (32, y - 7), text.clone()))?;
        y += 22;
    }
    y += 12;
    area.draw(&PathElement::new(vec![(10, y), (40, y)], BLACK.stroke_width(3)))?;
    area.draw(&Circle::new((25, y), 5, BLACK.filled()))?;
    area.draw(&Text::new("whole update", (48, y - 7), text.clone()))?;
    for (k, stage) in STAGES.iter().enumerate() {
        y += 20;
        let (length, gap) = dash(k);
        area.draw(&DashedPathElement::new(
            vec![(10, y), (40, y)],
            length,
            gap,
            BLACK.stroke_width(1),
        ))?;
        stage_marker!(k, (25, y), BLACK, |e| area.draw(&e)?);
        area.draw(&Text::new(stage.label, (48, y - 7), text.clone()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::measured_run::test_result;
    use crate::systems::{STAGE_COUNT, SimulationSystems};

    fn result(bodies: usize, mode: ExecutionMode, threads: usize, ns: f64) -> RunResult {
        let mut result = test_result(bodies as u64, mode, threads, SplitPolicy::Always, ns);
        result.stage_ns = [ns / 8.0; STAGE_COUNT];
        result.stage_ns[SimulationSystems::Response as usize] = 0.0;
        result
    }

    fn results() -> Vec<RunResult> {
        vec![
            result(0, ExecutionMode::Sequential, 1, 1e3),
            result(1000, ExecutionMode::Sequential, 1, 1e5),
            result(100_000, ExecutionMode::Sequential, 1, 1e7),
            result(1000, ExecutionMode::Parallel, 2, 1e5),
            result(100_000, ExecutionMode::Parallel, 2, 5e6),
            result(10_000, ExecutionMode::Parallel, 3, 4e5),
        ]
    }

    fn labels(title: &str) -> Labels<'_> {
        Labels {
            title,
            footer: "Some CPU, 2 hardware threads · Kessler 0.1.0, commit abc123",
        }
    }

    #[test]
    fn svg_has_the_title_the_legend_and_a_line_per_setting() {
        let crossover = Crossover {
            stage: "update",
            threads: 2,
            from_bodies: Some(1000),
            counts: 2,
            auto_worst: None,
        };
        let svg = svg(&results(), &[crossover], labels("a < b")).unwrap();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        // Each text element's content stands on a line of its own.
        let has_text = |text: &str| svg.lines().any(|l| l.trim() == text);
        assert!(has_text("a &lt; b"), "the title, escaped");
        for text in [
            "sequential",
            "parallel, 2 threads, split always",
            "parallel, 3 threads, split always",
            "whole update",
            "bodies",
            "crossover: 1000",
            "Some CPU, 2 hardware threads · Kessler 0.1.0, commit abc123",
        ] {
            assert!(has_text(text), "missing {text}");
        }
        // The x axis is labelled at the decades only, so no two labels meet.
        for text in ["1 000", "10 000", "100 000"] {
            assert!(has_text(text), "no tick {text}");
        }
        assert!(
            !has_text("20000") && !has_text("90000") && !has_text("20 000"),
            "a tick between decades"
        );
        // Every measured point of the whole update is marked, the third
        // setting's single one included (a line through one point shows
        // nothing).
        let dots = |color: &str| {
            svg.lines()
                .filter(|l| l.contains("<circle") && l.contains("r=\"5\"") && l.contains(color))
                .count()
        };
        assert_eq!(
            (dots("#D62728"), dots("#1F77B4"), dots("#2CA02C")),
            (2, 2, 1),
            "{svg:.3000}"
        );
        for stage in &STAGES {
            assert!(has_text(stage.label), "legend lacks {}", stage.label);
        }
        // The whole update: one thick line in each setting's color, through
        // its two points (zero bodies cannot sit on a log axis).
        let thick: Vec<&str> = svg
            .lines()
            .filter(|l| l.contains("<polyline") && l.contains("stroke-width=\"3\"") && !l.contains("#000000"))
            .collect();
        let thick: Vec<&str> = thick.into_iter().filter(|l| !l.contains("#2CA02C")).collect();
        assert_eq!(thick.len(), 2, "{thick:?}");
        assert!(
            thick[0].contains("#D62728") && thick[1].contains("#1F77B4"),
            "{thick:?}"
        );
        let points = |line: &str| {
            let list = line.split("points=\"").nth(1).unwrap();
            list.split('"').next().unwrap().split_whitespace().count()
        };
        assert!(thick.iter().all(|l| points(l) == 2), "{thick:?}");
    }

    #[test]
    fn png_shows_lines_and_text_on_white() {
        let png = png(&results(), &[], labels("t")).unwrap();
        let decoder = ::png::Decoder::new(std::io::Cursor::new(png));
        let mut reader = decoder.read_info().unwrap();
        let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut rgb).unwrap();
        assert_eq!((info.width, info.height), PLOT_SIZE);
        let width = info.width as usize;
        let pixels: Vec<(usize, &[u8])> = rgb.chunks(3).enumerate().map(|(i, p)| (i % width, p)).collect();
        let count = |f: &dyn Fn(usize, &[u8]) -> bool| pixels.iter().filter(|(x, p)| f(*x, p)).count();
        let white = count(&|_, p| p == [255, 255, 255]);
        // The first setting's color (#d62728) is drawn.
        let red = count(&|_, p| p[0] > 180 && p[1] < 80 && p[2] < 80);
        // The legend's text: dark gray pixels right of the plot, far more
        // than its line samples alone make.
        let legend_x = (PLOT_SIZE.0 - LEGEND_WIDTH) as usize;
        let text = count(&|x, p| {
            let (lo, hi) = (p.iter().min().unwrap(), p.iter().max().unwrap());
            x >= legend_x && *hi < 128 && hi - lo < 12
        });
        assert!(white > pixels.len() / 2, "background is not white");
        assert!(red > 200, "only {red} pixels of the line color");
        assert!(text > 600, "only {text} dark pixels in the legend: is the text drawn?");
    }
}
