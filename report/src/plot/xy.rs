//! Plain x–y figures with error bars and marker lines.

use std::path::Path;

use plotters::prelude::*;

use super::legend::{Entry, Key, draw_legend, legend_height};
use super::{FONT, PlotError};

/// One line of a figure: a label and its points (x, y, optional error).
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64, f64)>,
}

/// Colours of the lines of an [`xy_figure`].
const XY_PALETTE: [RGBColor; 5] = [
    RGBColor(70, 110, 180),
    RGBColor(200, 60, 40),
    RGBColor(40, 140, 70),
    RGBColor(140, 80, 160),
    RGBColor(90, 90, 90),
];

/// Colours of the vertical marker lines of an [`xy_figure`], in order.
const MARKER_PALETTE: [RGBColor; 6] = [
    RGBColor(130, 130, 130),
    RGBColor(200, 60, 40),
    RGBColor(0, 150, 170),
    RGBColor(230, 140, 0),
    RGBColor(130, 40, 170),
    RGBColor(0, 130, 60),
];

/// A plain x–y figure with error bars and optional vertical marker lines, each in its own
/// colour and named in the legend, a strip between the title and the axes.
///
/// # Errors
/// If the file cannot be written.
#[allow(clippy::too_many_arguments)]
pub fn xy_figure(
    path: &Path,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    lines: &[Line],
    y_range: (f64, f64),
    markers: &[(f64, &str)],
    log_x: bool,
) -> Result<(), PlotError> {
    let entries: Vec<Entry> = lines
        .iter()
        .enumerate()
        .map(|(k, l)| (Key::Line(XY_PALETTE[k % XY_PALETTE.len()]), l.label.clone()))
        .chain(markers.iter().enumerate().map(|(k, (_, label))| {
            (
                Key::Dashed(MARKER_PALETTE[k % MARKER_PALETTE.len()]),
                label.trim().to_string(),
            )
        }))
        .collect();
    let legend_h = legend_height(800, &entries);
    let root = SVGBackend::new(path, (800, 460 + legend_h)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 17))?;
    let (legend, root) = root.split_vertically(legend_h);
    draw_legend(&legend, &entries)?;
    let xs = lines.iter().flat_map(|l| l.points.iter().map(|p| p.0));
    let x0 = xs.clone().fold(f64::MAX, f64::min);
    let x1 = xs.fold(f64::MIN, f64::max);
    let what = XyBody {
        x_desc,
        y_desc,
        lines,
        y_range,
        markers,
        log_x,
    };
    let mut builder = ChartBuilder::on(&root);
    builder
        .margin(15)
        .x_label_area_size(35)
        .y_label_area_size(50);
    if log_x {
        let range = (x0 * 0.8..x1 * 1.25).log_scale();
        what.draw(&mut builder.build_cartesian_2d(range, y_range.0..y_range.1)?)?;
    } else {
        let pad = 0.03 * (x1 - x0).max(1e-9);
        what.draw(&mut builder.build_cartesian_2d(x0 - pad..x1 + pad, y_range.0..y_range.1)?)?;
    }
    root.present()?;
    Ok(())
}

/// What [`xy_figure`] draws inside its axes, for a linear or a logarithmic x axis alike.
struct XyBody<'a> {
    x_desc: &'a str,
    y_desc: &'a str,
    lines: &'a [Line],
    y_range: (f64, f64),
    markers: &'a [(f64, &'a str)],
    log_x: bool,
}

impl XyBody<'_> {
    /// Mesh, markers, and one line with its points and error bars per [`Line`].
    fn draw<'b, X>(
        &self,
        chart: &mut ChartContext<
            'b,
            SVGBackend<'b>,
            Cartesian2d<X, plotters::coord::types::RangedCoordf64>,
        >,
    ) -> Result<(), PlotError>
    where
        X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    {
        let (y0, y1) = self.y_range;
        chart
            .configure_mesh()
            .x_desc(self.x_desc)
            .y_desc(self.y_desc)
            .x_labels(if self.log_x { 4 } else { 12 })
            .x_label_formatter(&|v: &f64| format!("{v}"))
            .max_light_lines(if self.log_x { 1 } else { 4 })
            .draw()?;
        for (k, &(mx, _)) in self.markers.iter().enumerate() {
            chart.draw_series(DashedLineSeries::new(
                vec![(mx, y0), (mx, y1)],
                5,
                4,
                MARKER_PALETTE[k % MARKER_PALETTE.len()].stroke_width(2),
            ))?;
        }
        for (k, l) in self.lines.iter().enumerate() {
            let c = XY_PALETTE[k % XY_PALETTE.len()];
            chart.draw_series(LineSeries::new(
                l.points.iter().map(|p| (p.0, p.1)),
                c.stroke_width(2),
            ))?;
            chart.draw_series(
                l.points
                    .iter()
                    .map(|p| Circle::new((p.0, p.1), 3, c.filled())),
            )?;
            chart.draw_series(l.points.iter().filter(|p| p.2 > 0.0).map(|p| {
                PathElement::new(vec![(p.0, p.1 - p.2), (p.0, p.1 + p.2)], c.stroke_width(1))
            }))?;
        }
        Ok(())
    }
}
