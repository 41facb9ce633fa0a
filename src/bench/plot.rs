//! The benchmark plot: update time against body count, log–log, one colour
//! per execution setting (sequential, parallel on T threads), a thick line
//! for the whole update and thin dashed lines for each stage. Written as SVG
//! by hand (no fonts or raster libraries needed).

use std::collections::BTreeMap;
use std::fmt::Write;

use super::run::RunResult;

const WIDTH: f64 = 960.0;
const HEIGHT: f64 = 600.0;
const LEFT: f64 = 110.0;
const RIGHT: f64 = 250.0;
const TOP: f64 = 50.0;
const BOTTOM: f64 = 60.0;
const COLOURS: [&str; 6] = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

/// Stage name, value of a result, dash pattern.
type Series = (&'static str, fn(&RunResult) -> f64, &'static str);
const SERIES: [Series; 5] = [
    ("update", |r| r.update_ns, ""),
    ("gravity", |r| r.gravity_ns, "2,3"),
    ("integrate", |r| r.integrate_ns, "8,3,2,3"),
    ("broad phase", |r| r.broad_phase_ns, "6,4"),
    ("response", |r| r.response_ns, "12,4"),
];

/// Log-scale axis from 10^lo to 10^hi over pixels `from..to`.
struct Axis {
    lo: f64,
    hi: f64,
    from: f64,
    to: f64,
}

impl Axis {
    fn fit(values: impl Iterator<Item = f64>, from: f64, to: f64) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| *v > 0.0) {
            lo = lo.min(v.log10().floor());
            hi = hi.max(v.log10().ceil());
        }
        if !lo.is_finite() {
            (lo, hi) = (0.0, 1.0);
        }
        Self {
            lo,
            hi: hi.max(lo + 1.0),
            from,
            to,
        }
    }

    fn pixel(&self, v: f64) -> f64 {
        self.from + (v.log10() - self.lo) / (self.hi - self.lo) * (self.to - self.from)
    }
}

fn label(exponent: f64, unit: &str) -> String {
    let v = 10f64.powf(exponent);
    if v >= 1.0 {
        format!("{v:.0}{unit}")
    } else {
        format!("{v}{unit}")
    }
}

/// The plot as an SVG document.
pub fn svg(results: &[RunResult], title: &str) -> String {
    let ms = |ns: f64| ns / 1e6;
    let points: Vec<&RunResult> = results.iter().filter(|r| r.bodies_start > 0).collect();
    let x = Axis::fit(points.iter().map(|r| r.bodies_start as f64), LEFT, WIDTH - RIGHT);
    let y = Axis::fit(
        points
            .iter()
            .flat_map(|r| SERIES.iter().map(|(_, value, _)| ms(value(r)))),
        HEIGHT - BOTTOM,
        TOP,
    );
    let mut groups: BTreeMap<(String, usize), Vec<&RunResult>> = BTreeMap::new();
    for r in &points {
        groups.entry((r.mode.to_string(), r.threads)).or_default().push(r);
    }

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="28" font-size="17" text-anchor="middle">{}</text>"#,
        (LEFT + WIDTH - RIGHT) / 2.0,
        escape(title)
    );
    // Grid and tick labels at every decade.
    for e in (x.lo as i32)..=(x.hi as i32) {
        let px = x.pixel(10f64.powi(e));
        let _ = writeln!(
            s,
            r##"<line x1="{px:.1}" y1="{TOP}" x2="{px:.1}" y2="{:.1}" stroke="#ddd"/>"##,
            HEIGHT - BOTTOM
        );
        let _ = writeln!(
            s,
            r#"<text x="{px:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            HEIGHT - BOTTOM + 18.0,
            label(f64::from(e), "")
        );
    }
    for e in (y.lo as i32)..=(y.hi as i32) {
        let py = y.pixel(10f64.powi(e));
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{py:.1}" x2="{:.1}" y2="{py:.1}" stroke="#ddd"/>"##,
            WIDTH - RIGHT
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"#,
            LEFT - 6.0,
            py + 4.0,
            label(f64::from(e), " ms")
        );
    }
    let _ = writeln!(
        s,
        r#"<rect x="{LEFT}" y="{TOP}" width="{:.1}" height="{:.1}" fill="none" stroke="black"/>"#,
        WIDTH - RIGHT - LEFT,
        HEIGHT - BOTTOM - TOP
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">bodies</text>"#,
        (LEFT + WIDTH - RIGHT) / 2.0,
        HEIGHT - 15.0
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(20 {:.1}) rotate(-90)" text-anchor="middle">time per update</text>"#,
        (TOP + HEIGHT - BOTTOM) / 2.0
    );

    // One colour per execution setting; the stages as dashed lines.
    let mut legend_y = TOP + 10.0;
    let legend_x = WIDTH - RIGHT + 20.0;
    for (i, ((mode, threads), runs)) in groups.iter_mut().enumerate() {
        runs.sort_by_key(|r| r.bodies_start);
        let colour = COLOURS[i % COLOURS.len()];
        for (name, value, dash) in SERIES {
            let line: Vec<String> = runs
                .iter()
                .filter(|r| value(r) > 0.0)
                .map(|r| format!("{:.1},{:.1}", x.pixel(r.bodies_start as f64), y.pixel(ms(value(r)))))
                .collect();
            if line.is_empty() {
                continue;
            }
            let width = if name == "update" { 2.5 } else { 1.2 };
            let _ = writeln!(
                s,
                r#"<polyline class="{}" points="{}" fill="none" stroke="{colour}" stroke-width="{width}" stroke-dasharray="{dash}"/>"#,
                name.replace(' ', "_"),
                line.join(" ")
            );
        }
        let setting = if mode == "sequential" {
            mode.clone()
        } else {
            format!("{mode}, {threads} thread{}", if *threads == 1 { "" } else { "s" })
        };
        let _ = writeln!(
            s,
            r#"<rect x="{legend_x:.1}" y="{:.1}" width="14" height="14" fill="{colour}"/>"#,
            legend_y - 11.0
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{legend_y:.1}">{setting}</text>"#,
            legend_x + 20.0
        );
        legend_y += 22.0;
    }
    legend_y += 10.0;
    for (name, _, dash) in SERIES {
        let width = if name == "update" { 2.5 } else { 1.2 };
        let _ = writeln!(
            s,
            r#"<line x1="{legend_x:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="black" stroke-width="{width}" stroke-dasharray="{dash}"/>"#,
            legend_y - 4.0,
            legend_x + 30.0,
            legend_y - 4.0
        );
        let label = if name == "update" { "whole update" } else { name };
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{legend_y:.1}">{label}</text>"#,
            legend_x + 38.0
        );
        legend_y += 20.0;
    }
    s.push_str("</svg>\n");
    s
}

/// Renders an SVG document (the plot) to PNG. Text is drawn with the
/// system's fonts (DejaVu Sans where present); without any font the lines
/// are still drawn.
pub fn png(svg: &str) -> Result<Vec<u8>, String> {
    use resvg::{tiny_skia, usvg};
    let mut options = usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    let family = fonts
        .faces()
        .flat_map(|face| face.families.iter().map(|(name, _)| name.clone()))
        .find(|name| name == "DejaVu Sans")
        .or_else(|| {
            fonts
                .faces()
                .next()
                .and_then(|face| face.families.first().map(|(name, _)| name.clone()))
        });
    if let Some(family) = family {
        fonts.set_sans_serif_family(family);
    }
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| format!("plot: {e}"))?;
    let size = tree.size().to_int_size();
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or("plot: empty picture")?;
    resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| format!("plot: {e}"))
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resources::ExecutionMode;

    fn result(bodies: usize, mode: ExecutionMode, threads: usize, ns: f64) -> RunResult {
        RunResult {
            run: 1,
            bodies_start: bodies,
            bodies_end: bodies,
            updates: 1,
            mode,
            threads,
            update_ns: ns,
            gravity_ns: ns / 2.0,
            integrate_ns: ns / 4.0,
            broad_phase_ns: ns / 8.0,
            response_ns: 0.0,
        }
    }

    #[test]
    fn one_line_per_setting_and_stage_on_log_axes() {
        let results = [
            result(0, ExecutionMode::Sequential, 1, 1e3),
            result(1000, ExecutionMode::Sequential, 1, 1e5),
            result(100_000, ExecutionMode::Sequential, 1, 1e7),
            result(1000, ExecutionMode::Parallel, 2, 1e5),
            result(100_000, ExecutionMode::Parallel, 2, 5e6),
        ];
        let svg = svg(&results, "a < b");
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt; b"));
        // Two settings × four stages with data (response is all zero).
        assert_eq!(svg.matches("<polyline").count(), 8);
        assert_eq!(svg.matches(r#"class="update""#).count(), 2);
        // Zero bodies cannot sit on a log axis: two points per line.
        let update_line = svg.lines().find(|l| l.contains(r#"class="update""#)).unwrap();
        assert_eq!(
            update_line
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .split(' ')
                .count(),
            2
        );
        // Decades 10^3…10^5 bodies and 10^-1…10^1 ms are labelled.
        for tick in [">1000<", ">100000<", ">0.1 ms<", ">10 ms<"] {
            assert!(svg.contains(tick), "missing tick {tick}");
        }
    }

    #[test]
    fn png_shows_the_lines_on_white() {
        let results = [
            result(1000, ExecutionMode::Sequential, 1, 1e5),
            result(100_000, ExecutionMode::Sequential, 1, 1e7),
        ];
        let png = png(&svg(&results, "t")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let pixmap = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
        assert_eq!((pixmap.width(), pixmap.height()), (WIDTH as u32, HEIGHT as u32));
        let pixels = pixmap.pixels();
        let white = pixels
            .iter()
            .filter(|p| (p.red(), p.green(), p.blue()) == (255, 255, 255))
            .count();
        // The first series' colour (#d62728) is drawn somewhere.
        let red = pixels
            .iter()
            .filter(|p| p.red() > 180 && p.green() < 80 && p.blue() < 80)
            .count();
        assert!(white > pixels.len() / 2, "background is not white");
        assert!(red > 200, "only {red} pixels of the line colour");
    }
}
