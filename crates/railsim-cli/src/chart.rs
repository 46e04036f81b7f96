//! Line charts to PNG (plotters' bitmap backend with a built-in font): `replay --plot` and the
//! bifurcation diagram of `critical-speed --png`.

use std::fs::File;
use std::ops::Range;
use std::path::Path;

use anyhow::{Result, anyhow};
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

/// DejaVu Sans (Bitstream Vera licence, see `assets/SOURCE.md`): the plots' only font, so that
/// drawing text needs no system font library.
const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
const FONT_FAMILY: &str = "sans-serif";
/// \[px\] size of the PNG.
const PLOT_SIZE: (u32, u32) = (1280, 720);
/// Line colours, chosen to stay distinct on white and from each other.
const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 0),
];

/// One line of a chart: its legend and its points (non-finite ones are skipped).
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Titles of a chart.
pub struct Labels<'a> {
    pub title: &'a str,
    pub x: &'a str,
    pub y: &'a str,
}

/// Checks that `png` is named `*.png` (in any case): the bitmap backend picks the image format
/// by the extension, and refuses an unknown one only after the whole plot is drawn. `option`
/// names where the file name came from, e.g. `--png`.
pub fn check_png_name(option: &str, png: &Path) -> Result<()> {
    crate::check_extension(option, png, &["png"])
}

/// The x and y ranges of the finite points of `series`, or `None` when there are none.
pub fn bounds(series: &[Series]) -> Option<([f64; 2], [f64; 2])> {
    let (mut x, mut y) = (
        [f64::INFINITY, f64::NEG_INFINITY],
        [f64::INFINITY, f64::NEG_INFINITY],
    );
    for &(a, b) in series.iter().flat_map(|s| &s.points) {
        if a.is_finite() && b.is_finite() {
            x = [x[0].min(a), x[1].max(a)];
            y = [y[0].min(b), y[1].max(b)];
        }
    }
    x[0].is_finite().then_some((x, y))
}

/// Draw `series` as lines in one chart to `png` (the x range exactly that of the points, the y
/// range padded by 5 %). Errors name the file. Nothing is drawn for an empty chart.
pub fn line_chart(png: &Path, labels: &Labels<'_>, series: &[Series]) -> Result<()> {
    let Some((x, y)) = bounds(series) else {
        return Err(anyhow!("{}: nothing to plot", png.display()));
    };
    let (x0, mut x1) = (x[0], x[1]);
    if x1 <= x0 {
        x1 = x0 + 1e-3;
    }
    let pad = if y[1] > y[0] {
        0.05 * (y[1] - y[0])
    } else {
        0.05 * y[0].abs().max(1e-12)
    };
    let (y0, y1) = (y[0] - pad, y[1] + pad);
    register_font(FONT_FAMILY, FontStyle::Normal, FONT)
        .map_err(|_| anyhow!("the built-in font assets/DejaVuSans.ttf does not load"))?;
    check_png_name("--png", png)?;
    // The bitmap backend writes the file only after drawing, and reports a failure to write it as
    // a debug dump of error types this crate cannot name (`ImageError(IoError(Os { .. }))`):
    // create the file first, so that a missing directory or a read-only file is said plainly.
    File::create(png).map_err(|e| anyhow!("{}: creating the PNG: {e}", png.display()))?;
    let drawn = draw(png, labels, series, x0..x1, y0..y1);
    if drawn.is_err() {
        // no empty or partial PNG is left behind
        std::fs::remove_file(png).ok();
    }
    drawn
}

/// Draws the chart of [`line_chart`] with the given axis ranges and writes it to `png`.
fn draw(
    png: &Path,
    labels: &Labels<'_>,
    series: &[Series],
    x: Range<f64>,
    y: Range<f64>,
) -> Result<()> {
    let draw_err =
        |e: &dyn std::fmt::Display| anyhow!("{}: drawing or writing the plot: {e}", png.display());
    let root = BitMapBackend::new(png, PLOT_SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(labels.title, (FONT_FAMILY, 24))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(90)
        .build_cartesian_2d(x, y)
        .map_err(|e| draw_err(&e))?;
    chart
        .configure_mesh()
        .x_desc(labels.x)
        .y_desc(labels.y)
        .label_style((FONT_FAMILY, 15))
        .axis_desc_style((FONT_FAMILY, 18))
        .draw()
        .map_err(|e| draw_err(&e))?;
    for (k, s) in series.iter().enumerate() {
        let c = COLOURS[k % COLOURS.len()];
        if s.points.is_empty() {
            continue;
        }
        let pts = s
            .points
            .iter()
            .copied()
            .filter(|(a, b)| a.is_finite() && b.is_finite());
        chart
            .draw_series(LineSeries::new(pts, c.stroke_width(2)))
            .map_err(|e| draw_err(&e))?
            .label(s.name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .label_font((FONT_FAMILY, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| draw_err(&e))?;
    root.present().map_err(|e| draw_err(&e))?;
    Ok(())
}
