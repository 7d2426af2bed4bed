//! Figs. 6 and 9: success rate and mean success time against the initial position, with the
//! paper's values as marks.

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use report::plot::{Entry, FONT, Key, PlotError, draw_legend, legend_height};
use swarm_sim::experiment::SweepPoint;

/// Colours of the series of a sweep figure.
const COLOURS: [RGBColor; 3] = [
    RGBColor(70, 110, 180),
    RGBColor(90, 160, 90),
    RGBColor(150, 100, 170),
];

/// Colour of the paper's values on a sweep figure.
const PAPER: RGBColor = RGBColor(200, 60, 40);

/// The lower panel of [`sweep_figure`]: mean success time against the initial position.
fn times_panel(
    bottom: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    series: &[(&str, &[SweepPoint])],
    (x0, x1): (f64, f64),
) -> Result<(), PlotError> {
    let times: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|(_, pts)| {
            pts.iter()
                .filter_map(|p| p.mean_success_periods.map(|t| (p.x_init, t)))
                .collect()
        })
        .collect();
    let tmax = times.iter().flatten().map(|t| t.1).fold(1.0, f64::max) * 1.1;
    let mut chart = ChartBuilder::on(bottom)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(x0..x1, 0f64..tmax)?;
    chart
        .configure_mesh()
        .x_desc("initial x / R")
        .y_desc("mean success time / periods")
        .draw()?;
    for (s, t) in times.iter().enumerate() {
        let colour = if series.len() == 1 {
            BLACK
        } else {
            COLOURS[s % COLOURS.len()]
        };
        chart.draw_series(LineSeries::new(t.iter().copied(), colour.stroke_width(1)))?;
        chart.draw_series(t.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
    }
    Ok(())
}

/// One of the paper's values on a sweep figure, drawn over the bars in the paper's red.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepMark {
    /// One success rate `y` over `x.0 ≤ x_init < x.1`: a dashed line with ticks at its ends.
    Level {
        /// The initial positions it covers.
        x: (f64, f64),
        /// The rate.
        y: f64,
        /// Legend text.
        label: String,
    },
    /// Rates between `y.0` and `y.1` over `x.0 ≤ x_init < x.1`: a shaded band.
    Band {
        /// The initial positions it covers.
        x: (f64, f64),
        /// The lowest and highest rate.
        y: (f64, f64),
        /// Legend text.
        label: String,
    },
    /// One rate at one initial position: a hollow circle.
    Point {
        /// The initial position.
        x: f64,
        /// The rate.
        y: f64,
        /// Legend text.
        label: String,
    },
}

impl SweepMark {
    /// The mark's legend entry.
    fn entry(&self) -> Entry {
        match self {
            SweepMark::Level { label, .. } => (Key::Dashed(PAPER), label.clone()),
            SweepMark::Band { label, .. } => (Key::Band(PAPER), label.clone()),
            SweepMark::Point { label, .. } => (Key::Marker(PAPER), label.clone()),
        }
    }
}

/// The initial positions of a sweep figure's axis, `(x0, x1)`, and the spacing of its bars.
fn sweep_axis(series: &[(&str, &[SweepPoint])]) -> ((f64, f64), f64) {
    let step = series
        .iter()
        .flat_map(|(_, pts)| pts.windows(2).map(|w| w[1].x_init - w[0].x_init))
        .filter(|d| *d > 0.0)
        .fold(f64::MAX, f64::min)
        .min(1.0);
    let (lo, hi) = series
        .iter()
        .flat_map(|(_, pts)| pts.iter())
        .fold((f64::MAX, f64::MIN), |(lo, hi), p| {
            (lo.min(p.x_init), hi.max(p.x_init))
        });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (-5.0, 5.0) };
    ((lo - step, hi + step), step)
}

/// Figs. 6 and 9: success rate and mean success time against the initial position, one bar
/// per series (label, points) at each initial position, and the paper's values as marks. The
/// legend (series, then each distinct mark label once) is a strip between the title and the
/// plots, where it covers no bar.
///
/// # Errors
/// If the file cannot be written.
pub fn sweep_figure(
    path: &Path,
    title: &str,
    series: &[(&str, &[SweepPoint])],
    marks: &[SweepMark],
) -> Result<(), PlotError> {
    let entries = sweep_legend(series, marks);
    let legend_h = legend_height(800, &entries);
    let root = SVGBackend::new(path, (800, 640 + legend_h)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 18))?;
    let (legend, rest) = root.split_vertically(legend_h);
    draw_legend(&legend, &entries)?;
    let (top, bottom) = rest.split_vertically(300);
    let (xs, step) = sweep_axis(series);
    rates_panel(&top, series, marks, xs, step)?;
    times_panel(&bottom, series, xs)?;
    root.present()?;
    Ok(())
}

/// The legend of a sweep figure: each series, then each distinct mark label once.
fn sweep_legend(series: &[(&str, &[SweepPoint])], marks: &[SweepMark]) -> Vec<Entry> {
    let mut entries: Vec<Entry> = series
        .iter()
        .enumerate()
        .map(|(s, (label, _))| (Key::Bar(COLOURS[s % COLOURS.len()]), (*label).to_string()))
        .collect();
    for m in marks {
        let e = m.entry();
        if !entries.iter().any(|(_, t)| *t == e.1) {
            entries.push(e);
        }
    }
    entries
}

/// The upper panel of [`sweep_figure`]: the success rate of each series as bars side by side at
/// each initial position (`step` apart over `x0..x1`), and the paper's marks over them.
fn rates_panel(
    top: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    series: &[(&str, &[SweepPoint])],
    marks: &[SweepMark],
    (x0, x1): (f64, f64),
    step: f64,
) -> Result<(), PlotError> {
    let mut chart = ChartBuilder::on(top)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(x0..x1, 0f64..1.05)?;
    chart
        .configure_mesh()
        .x_desc("initial x / R")
        .y_desc("success rate")
        .draw()?;
    let k = series.len().max(1) as f64;
    let w = 0.8 * step / k;
    for (s, (_, points)) in series.iter().enumerate() {
        let colour = COLOURS[s % COLOURS.len()];
        let left = -0.4 * step + s as f64 * w;
        chart.draw_series(points.iter().map(|p| {
            Rectangle::new(
                [
                    (p.x_init + left, 0.0),
                    (p.x_init + left + w, p.success_rate()),
                ],
                colour.filled(),
            )
        }))?;
    }
    for m in marks {
        draw_mark(&mut chart, m, step)?;
    }
    Ok(())
}

/// One of the paper's values over the bars (bars `step` apart), in the paper's red.
fn draw_mark(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    mark: &SweepMark,
    step: f64,
) -> Result<(), PlotError> {
    let line = PAPER.stroke_width(2);
    match *mark {
        SweepMark::Level { x, y, .. } => {
            chart.draw_series(DashedLineSeries::new(
                vec![(x.0, y), (x.1, y)],
                6,
                4,
                PAPER.stroke_width(3),
            ))?;
            for end in [x.0, x.1] {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(end, y - 0.04), (end, y + 0.02)],
                    line,
                )))?;
            }
        }
        SweepMark::Band { x, y, .. } => {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x.0, y.0), (x.1, y.1)],
                PAPER.mix(0.2).filled(),
            )))?;
            for level in [y.0, y.1] {
                chart.draw_series(DashedLineSeries::new(
                    vec![(x.0, level), (x.1, level)],
                    6,
                    4,
                    PAPER.stroke_width(1),
                ))?;
            }
        }
        SweepMark::Point { x, y, .. } => {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x - 0.45 * step, y), (x + 0.45 * step, y)],
                line,
            )))?;
            chart.draw_series(std::iter::once(Circle::new((x, y), 6, line)))?;
        }
    }
    Ok(())
}
