//! The plot of a config's thread sweeps (`<stem>-threads.svg`, `.png`): the
//! whole update's speed-up over sequential against the thread count, a
//! color and a line with a dot per measured point for each body count,
//! the ideal (speed-up = threads) dashed in gray: the thesis's Figures
//! 22–24 for one machine. The footer names the machine and the commit.

use std::collections::BTreeMap;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::threads::ThreadsRow;
use crate::output::{
    FONT, Figure, Labels, PALETTE, PlotError, figure_png, figure_svg, grouped, legend_upper_left, page,
};

/// The plot as an SVG document.
pub fn threads_svg(rows: &[ThreadsRow], labels: Labels<'_>) -> Result<String, PlotError> {
    figure_svg(&ThreadsPlot { rows, labels })
}

/// The plot as a PNG image.
pub fn threads_png(rows: &[ThreadsRow], labels: Labels<'_>) -> Result<Vec<u8>, PlotError> {
    figure_png(&ThreadsPlot { rows, labels })
}

/// What [`threads_svg`] and [`threads_png`] draw.
struct ThreadsPlot<'a> {
    rows: &'a [ThreadsRow],
    labels: Labels<'a>,
}

impl Figure for ThreadsPlot<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        draw_on(root, self.rows, self.labels)
    }
}

fn draw_on<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    rows: &[ThreadsRow],
    labels: Labels<'_>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut by_bodies: BTreeMap<u64, Vec<(f64, f64)>> = BTreeMap::new();
    for row in rows {
        if let Some(speedup) = row.update() {
            by_bodies
                .entry(row.bodies)
                .or_default()
                .push((row.threads as f64, speedup));
        }
    }
    let most_threads = rows.iter().map(|r| r.threads).max().unwrap_or(1).max(2) as f64;
    let most_speedup = by_bodies.values().flatten().map(|p| p.1).fold(most_threads, f64::max);
    let root = page(root, labels.footer)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(labels.title, (FONT, 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(0.5..most_threads + 0.5, 0.0..most_speedup * 1.1)?;
    chart
        .configure_mesh()
        .x_desc("threads")
        .y_desc("speed-up of the update over sequential")
        .label_style((FONT, 13))
        .x_labels(most_threads as usize + 1)
        .x_label_formatter(&|v| {
            if (v - v.round()).abs() < 1e-9 && *v >= 1.0 {
                format!("{v:.0}")
            } else {
                String::new()
            }
        })
        .draw()?;
    let gray = RGBColor(150, 150, 150);
    chart
        .draw_series(DashedLineSeries::new(
            [(1.0, 1.0), (most_threads, most_threads)],
            8,
            5,
            gray.stroke_width(1),
        ))?
        .label("ideal: speed-up = threads")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], gray.stroke_width(1)));
    for (i, (bodies, points)) in by_bodies.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))?
            .label(format!("{} bodies", grouped(*bodies)))
            .legend(move |(x, y)| Circle::new((x + 12, y), 4, color.filled()));
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))?;
    }
    legend_upper_left(&mut chart)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plot_has_a_dot_per_point_the_ideal_and_the_footer() {
        let row = |bodies, threads, s| ThreadsRow {
            bodies,
            threads,
            speedups: vec![Some(s)],
        };
        let rows = [
            row(1000, 1, 0.9),
            row(1000, 2, 1.7),
            row(100_000, 1, 0.95),
            row(100_000, 2, 1.9),
        ];
        let labels = Labels {
            title: "speed-up",
            footer: "Some CPU · commit abc",
        };
        let svg = threads_svg(&rows, labels).unwrap();
        let has_text = |text: &str| svg.lines().any(|l| l.trim() == text);
        for text in [
            "1 000 bodies",
            "100 000 bodies",
            "ideal: speed-up = threads",
            "threads",
            "Some CPU · commit abc",
        ] {
            assert!(has_text(text), "missing {text}");
        }
        let dots = svg
            .lines()
            .filter(|l| l.contains("<circle") && l.contains("r=\"4\""))
            .count();
        assert_eq!(dots, rows.len() + 2, "a dot per point and one per legend entry");
        assert!(threads_png(&rows, labels).unwrap().starts_with(b"\x89PNG"));
    }
}
