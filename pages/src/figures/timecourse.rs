//! The averaged Figs. 5b and 8b: diversity and consensus against time, both placements, with
//! the paper's starting values and plateaus marked.

use std::path::Path;

use plotters::prelude::*;

use report::csv_files::fixed;
use report::plot::PlotError;
use swarm_sim::timecourse::{Spread, TimeCourse};

/// The runs' spread as the page gives it: "10–90 %", the quantiles of
/// [`swarm_sim::timecourse::BAND`] in per cent.
pub fn band_words() -> String {
    let [lo, hi] = swarm_sim::timecourse::BAND;
    format!("{}–{} %", fixed(100.0 * lo, 0), fixed(100.0 * hi, 0))
}

const FONT: &str = "sans-serif";
const COLOURS: [RGBColor; 2] = [RGBColor(70, 110, 180), RGBColor(200, 90, 40)];
const PAPER: RGBColor = RGBColor(60, 60, 60);

/// One paper value to mark: a horizontal dashed line (a plateau) or a point at `t = 0` (a
/// starting value).
pub struct PaperMark {
    /// The value.
    pub value: f64,
    /// Legend text, e.g. "paper: plateau ≈ 4.5".
    pub label: String,
    /// A point at t = 0 instead of a line.
    pub at_start: bool,
}

/// Draws one panel: the mean of `pick` per course, its 10–90 % band, and the marks; the legend
/// goes into `side`.
#[allow(clippy::too_many_arguments)]
fn panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    side: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    caption: &str,
    y_desc: &str,
    courses: &[(&str, &TimeCourse)],
    pick: fn(&swarm_sim::timecourse::TimePoint) -> Spread,
    y_max: f64,
    marks: &[PaperMark],
) -> Result<(), PlotError> {
    let t_max = courses
        .iter()
        .flat_map(|(_, c)| c.points.iter().map(|p| f64::from(p.t)))
        .fold(1.0, f64::max);
    let mut legend = Vec::new();
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .caption(caption, (FONT, 15))
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(-0.5..t_max + 0.5, 0f64..y_max)?;
    chart
        .configure_mesh()
        .x_desc("t / negotiation periods since the start")
        .y_desc(y_desc)
        .max_light_lines(2)
        .draw()?;
    for (k, (label, c)) in courses.iter().enumerate() {
        let col = COLOURS[k % COLOURS.len()];
        let band: Vec<(f64, f64)> = c
            .points
            .iter()
            .map(|p| (f64::from(p.t), pick(p).q90))
            .chain(c.points.iter().rev().map(|p| (f64::from(p.t), pick(p).q10)))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(band, col.mix(0.18).filled())))?;
        chart.draw_series(LineSeries::new(
            c.points.iter().map(|p| (f64::from(p.t), pick(p).mean)),
            col.stroke_width(2),
        ))?;
        legend.push((
            format!("{label}: mean of {} runs, band {}", c.runs, band_words()),
            Glyph::Line(col),
        ));
    }
    for m in marks {
        if m.at_start {
            chart.draw_series(std::iter::once(TriangleMarker::new(
                (0.0, m.value),
                7,
                PAPER.filled(),
            )))?;
            legend.push((m.label.clone(), Glyph::Triangle));
        } else {
            chart.draw_series(DashedLineSeries::new(
                vec![(-0.5, m.value), (t_max + 0.5, m.value)],
                6,
                4,
                PAPER.stroke_width(1),
            ))?;
            legend.push((m.label.clone(), Glyph::Dashed));
        }
    }
    draw_legend(side, &legend)
}

/// What a legend entry shows beside its text.
enum Glyph {
    Line(RGBColor),
    Dashed,
    Triangle,
}

/// The legend, in its own area beside the chart: it never covers data.
fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    entries: &[(String, Glyph)],
) -> Result<(), PlotError> {
    for (k, (text, glyph)) in entries.iter().enumerate() {
        let y = 40 + 22 * k as i32;
        match glyph {
            Glyph::Line(c) => {
                area.draw(&PathElement::new(vec![(5, y), (25, y)], c.stroke_width(2)))?;
            }
            Glyph::Dashed => {
                area.draw(&PathElement::new(
                    vec![(5, y), (11, y)],
                    PAPER.stroke_width(1),
                ))?;
                area.draw(&PathElement::new(
                    vec![(16, y), (22, y)],
                    PAPER.stroke_width(1),
                ))?;
            }
            Glyph::Triangle => {
                area.draw(&TriangleMarker::new((15, y), 6, PAPER.filled()))?;
            }
        }
        area.draw(&Text::new(
            text.clone(),
            (32, y - 7),
            (FONT, 12).into_font(),
        ))?;
    }
    Ok(())
}

/// The figure: diversity on top, consensus below, one line per course (placement).
///
/// # Errors
/// If the file cannot be written.
pub fn time_course_figure(
    path: &Path,
    title: &str,
    courses: &[(&str, &TimeCourse)],
    marks: &[PaperMark],
) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, (1060, 720)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 17))?;
    let (top, bottom) = root.split_vertically(400);
    let (top, top_side) = top.split_horizontally(700);
    let (bottom, bottom_side) = bottom.split_horizontally(700);
    let div_max = courses
        .iter()
        .flat_map(|(_, c)| c.points.iter().map(|p| p.diversity.q90))
        .chain(marks.iter().map(|m| m.value))
        .filter(|v| v.is_finite())
        .fold(0.5, f64::max)
        * 1.1;
    panel(
        &top,
        &top_side,
        "(b) the agents' average diversity, mean V_k",
        "mean V_k",
        courses,
        |p| p.diversity,
        div_max,
        marks,
    )?;
    panel(
        &bottom,
        &bottom_side,
        "consensus: mean resultant length of the decided bearings",
        "consensus",
        courses,
        |p| p.consensus,
        1.05,
        &[],
    )?;
    root.present()?;
    Ok(())
}
