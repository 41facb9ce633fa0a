//! A figure drawn alike as SVG and as PNG (plotters' two backends), on a
//! white page of [`PLOT_SIZE`] with a footer that names the machine and the
//! commit: what every plot Kessler writes is drawn on (the benchmark's,
//! the thread sweeps', the ensembles'). The labels use the Ubuntu font that
//! `epaint_default_fonts` bundles (the crate egui takes its fonts from), so
//! the PNG reads the same on every machine, with or without system fonts.

use std::sync::Once;

use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;

use super::write_png;

/// Width and height of the plot in pixels.
pub const PLOT_SIZE: (u32, u32) = (1060, 640);
/// Height of the footer at the bottom.
const FOOTER_HEIGHT: u32 = 22;
/// The font family every text is set in (registered as Ubuntu Light).
pub const FONT: &str = "sans-serif";

/// Ten colours that tell apart, for series in turn (the ensembles'
/// combinations, the thread sweeps' body counts).
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The plot could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(String);

/// A figure of [`PLOT_SIZE`], drawn alike as SVG and as PNG.
pub trait Figure {
    /// Draws the figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>)
    -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>;
}

/// `figure` as an SVG document.
pub fn figure_svg(figure: &impl Figure) -> Result<String, PlotError> {
    let mut text = String::new();
    figure
        .draw(SVGBackend::with_string(&mut text, PLOT_SIZE).into_drawing_area())
        .map_err(|e| PlotError(e.to_string()))?;
    Ok(text)
}

/// `figure` as a PNG image.
pub fn figure_png(figure: &impl Figure) -> Result<Vec<u8>, PlotError> {
    let (width, height) = PLOT_SIZE;
    let mut rgb = vec![0u8; (width * height * 3) as usize];
    figure
        .draw(BitMapBackend::with_buffer(&mut rgb, PLOT_SIZE).into_drawing_area())
        .map_err(|e| PlotError(e.to_string()))?;
    let mut png = Vec::new();
    write_png(&mut png, width, height, &rgb).map_err(|e| PlotError(e.to_string()))?;
    Ok(png)
}

/// Readies a figure's page: the bundled font registered as [`FONT`]
/// (once), the page white, `footer` written along the bottom; returns the
/// area above the footer.
pub fn page<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    footer: &str,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    static FONT_REGISTERED: Once = Once::new();
    FONT_REGISTERED.call_once(|| {
        // The bundled font is valid; if it were not, text would be missing.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    });
    root.fill(&WHITE)?;
    let (above, footer_area) = root.split_vertically(PLOT_SIZE.1 - FOOTER_HEIGHT);
    footer_area.draw(&Text::new(
        footer.to_owned(),
        (12, 2),
        (FONT, 12).into_font().color(&RGBColor(90, 90, 90)),
    ))?;
    Ok(above)
}

/// The words around the data: the title at the top, the footer (the
/// machine and the commit) at the bottom.
#[derive(Clone, Copy, Debug)]
pub struct Labels<'a> {
    /// The title.
    pub title: &'a str,
    /// The footer.
    pub footer: &'a str,
}

/// `n` in groups of three digits (`100 000`).
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// Draws `chart`'s legend in its upper left corner, on a light ground.
pub fn legend_upper_left<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 13))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.3))
        .draw()
}
