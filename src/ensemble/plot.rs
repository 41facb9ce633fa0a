//! The ensemble's plot (`DIR/bodies.svg`, `.png`): the body count against
//! the updates, for each combination of settings its median as a line and
//! the band from the 5th to the 95th percentile shaded in its colour, the
//! legend naming the combination and its members, the footer the machine
//! and the commit.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::bench::plot_footer;
use crate::output::{FONT, Figure, PALETTE, PlotError, figure_png, figure_svg, grouped, legend_upper_left, page};

/// One combination's line and band.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// The combination in words.
    pub label: String,
    /// Its finished members.
    pub members: u64,
    /// Updates at each row.
    pub update: Vec<f64>,
    /// The median body count at each row.
    pub median: Vec<f64>,
    /// The 5th percentile at each row.
    pub low: Vec<f64>,
    /// The 95th percentile at each row.
    pub high: Vec<f64>,
}

/// The plot of some bands.
pub struct BodiesPlot<'a> {
    /// The combinations.
    pub bands: &'a [Band],
    /// The title.
    pub title: &'a str,
}

impl BodiesPlot<'_> {
    /// As an SVG document.
    pub fn svg(&self) -> Result<String, PlotError> {
        figure_svg(self)
    }

    /// As a PNG image.
    pub fn png(&self) -> Result<Vec<u8>, PlotError> {
        figure_png(self)
    }
}

impl Figure for BodiesPlot<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let root = page(root, &plot_footer())?;
        let last_update = self
            .bands
            .iter()
            .flat_map(|b| b.update.iter())
            .fold(1.0, |a: f64, &b| a.max(b));
        let (mut lowest, mut highest) = (f64::INFINITY, f64::NEG_INFINITY);
        for band in self.bands {
            for &v in band.low.iter().chain(&band.high).chain(&band.median) {
                lowest = lowest.min(v);
                highest = highest.max(v);
            }
        }
        if !lowest.is_finite() {
            (lowest, highest) = (0.0, 1.0);
        }
        let margin = ((highest - lowest) * 0.08).max(1.0);
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title, (FONT, 18))
            .margin(12)
            // Room for the last tick's label, centred on the right edge.
            .margin_right(36)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(0.0..last_update, (lowest - margin).max(0.0)..highest + margin)?;
        chart
            .configure_mesh()
            .x_desc("updates")
            .y_desc("bodies")
            .label_style((FONT, 13))
            .x_labels(8)
            .y_labels(8)
            .x_label_formatter(&|v| grouped(v.round().max(0.0) as u64))
            .y_label_formatter(&|v| grouped(v.round().max(0.0) as u64))
            .draw()?;
        for (i, band) in self.bands.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let outline: Vec<(f64, f64)> = band
                .update
                .iter()
                .zip(&band.high)
                .map(|(&x, &y)| (x, y))
                .chain(band.update.iter().zip(&band.low).rev().map(|(&x, &y)| (x, y)))
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(outline, color.mix(0.18).filled())))?;
            let median: Vec<(f64, f64)> = band.update.iter().zip(&band.median).map(|(&x, &y)| (x, y)).collect();
            chart
                .draw_series(LineSeries::new(median, color.stroke_width(2)))?
                .label(format!("{} ({} members)", band.label, band.members))
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], color.mix(0.3).filled()));
        }
        legend_upper_left(&mut chart)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_combination_has_a_band_a_line_and_a_legend_entry() {
        let band = |label: &str, shift: f64| Band {
            label: label.to_owned(),
            members: 8,
            update: vec![0.0, 100.0, 200.0],
            median: vec![100.0 + shift, 150.0 + shift, 220.0 + shift],
            low: vec![100.0 + shift, 130.0 + shift, 180.0 + shift],
            high: vec![100.0 + shift, 170.0 + shift, 260.0 + shift],
        };
        let bands = [band("shatter_threshold=2", 0.0), band("shatter_threshold=4", -50.0)];
        let plot = BodiesPlot {
            bands: &bands,
            title: "scene: bodies",
        };
        let svg = plot.svg().unwrap();
        for text in [
            "shatter_threshold=2 (8 members)",
            "shatter_threshold=4 (8 members)",
            "scene: bodies",
            "updates",
        ] {
            assert!(svg.lines().any(|l| l.trim() == text), "missing {text}");
        }
        assert_eq!(svg.matches("<polygon").count(), 2, "a band per combination");
        assert!(svg.matches("<polyline").count() >= 2, "a median line per combination");
        assert!(plot.png().unwrap().starts_with(b"\x89PNG"));
    }
}
