//! SVG figures with plotters' SVG backend: pure Rust, no system fonts or libraries (text is
//! written as SVG `<text>` and laid out by the viewer).

use std::f64::consts::PI;
use std::path::Path;

use plotters::prelude::*;

use crate::swarm::experiment::{Arrow, RadialPoint, RunOutput, SweepPoint};
use crate::swarm::field::Field;
use crate::swarm::scenario::{GridSpec, Scenario};

/// Any failure while drawing or writing a figure.
pub type PlotError = Box<dyn std::error::Error + Send + Sync>;

const FONT: &str = "sans-serif";
/// Colours of the series of a sweep figure.
const COLOURS: [RGBColor; 3] = [
    RGBColor(70, 110, 180),
    RGBColor(90, 160, 90),
    RGBColor(150, 100, 170),
];
const LOW: (f64, f64, f64) = (255.0, 243.0, 176.0);
const HIGH: (f64, f64, f64) = (222.0, 45.0, 38.0);

/// Pale yellow (low X) to red (high X), as in the paper's figures.
fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    let t = if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = |a: f64, b: f64| (a + t * (b - a)).round() as u8;
    RGBColor(c(LOW.0, HIGH.0), c(LOW.1, HIGH.1), c(LOW.2, HIGH.2))
}

type Rect = ((f64, f64), (f64, f64), u8);

/// The field as coloured rectangles over `[x0, x1] × [y0, y1]`: a grid of cells in 24 colour
/// levels, merged along rows and then between identical rows, so that a border is a handful of
/// rectangles, not thousands.
fn field_rects(field: &Field, x: (f64, f64), y: (f64, f64), cells: usize) -> (Vec<Rect>, f64, f64) {
    let (lo, hi) = field.range_over(x, y);
    let (dx, dy) = ((x.1 - x.0) / cells as f64, (y.1 - y.0) / cells as f64);
    let level = |v: f64| {
        if hi > lo {
            (((v - lo) / (hi - lo)) * 23.0).round() as u8
        } else {
            0
        }
    };
    let mut out: Vec<Rect> = Vec::new();
    let mut prev_row: Vec<(usize, usize, u8)> = Vec::new();
    let mut prev_start = 0usize;
    let flush = |runs: &[(usize, usize, u8)], r0: usize, r1: usize, out: &mut Vec<Rect>| {
        for &(c0, c1, l) in runs {
            out.push((
                (x.0 + c0 as f64 * dx, y.0 + r0 as f64 * dy),
                (x.0 + c1 as f64 * dx, y.0 + r1 as f64 * dy),
                l,
            ));
        }
    };
    for r in 0..cells {
        let yc = y.0 + (r as f64 + 0.5) * dy;
        let mut row: Vec<(usize, usize, u8)> = Vec::new();
        for c in 0..cells {
            let l = level(field.mean(nalgebra::Point2::new(x.0 + (c as f64 + 0.5) * dx, yc)));
            match row.last_mut() {
                Some(last) if last.2 == l => last.1 = c + 1,
                _ => row.push((c, c + 1, l)),
            }
        }
        if row != prev_row {
            flush(&prev_row, prev_start, r, &mut out);
            prev_row = row;
            prev_start = r;
        }
    }
    flush(&prev_row, prev_start, cells, &mut out);
    (out, lo, hi)
}

fn level_colour(l: u8) -> RGBColor {
    colour(f64::from(l), 0.0, 23.0)
}

fn draw_field<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    field: &Field,
    x: (f64, f64),
    y: (f64, f64),
) -> Result<(f64, f64), PlotError>
where
    DB::ErrorType: 'static,
{
    let (rects, lo, hi) = field_rects(field, x, y, 120);
    chart
        .draw_series(
            rects
                .into_iter()
                .map(|(a, b, l)| Rectangle::new([a, b], level_colour(l).filled())),
        )
        .map_err(|e| e.to_string())?;
    Ok((lo, hi))
}

fn square_range(
    xs: impl Iterator<Item = (f64, f64)> + Clone,
    pad: f64,
) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in xs {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let half = 0.5 * (x1 - x0).max(y1 - y0) + pad;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    ((cx - half, cx + half), (cy - half, cy + half))
}

/// Panel (b) of [`run_figure`]: the agents' average diversity against time.
fn diversity_panel(
    right: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    out: &RunOutput,
) -> Result<(), PlotError> {
    let div: Vec<(f64, f64)> = out
        .periods
        .iter()
        .map(|p| (f64::from(p.index), p.diversity))
        .collect();
    let ymax = div.iter().map(|d| d.1).fold(0.0, f64::max).max(0.5) * 1.1;
    let tmax = div.len().max(1) as f64 + 0.5;
    let mut chart = ChartBuilder::on(right)
        .margin(10)
        .caption("(b) average diversity of the agents", (FONT, 15))
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(0f64..tmax, 0f64..ymax)?;
    chart
        .configure_mesh()
        .x_desc("t / negotiation periods (2 cycles)")
        .y_desc("mean V_k")
        .draw()?;
    chart.draw_series(LineSeries::new(div.iter().copied(), BLACK.stroke_width(2)))?;
    chart.draw_series(div.iter().map(|&p| Circle::new(p, 2, BLACK.filled())))?;
    Ok(())
}

/// Figs. 4 and 7: the trajectory of the centre of mass over the field, with the swarm at its
/// start, and the observer's average diversity against time.
///
/// # Errors
/// If the file cannot be written.
pub fn run_figure(path: &Path, scn: &Scenario, out: &RunOutput) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, (1100, 520)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{}: one run from ({:.1}, {:.1}), {} agents, cycle {} s",
            scn.description,
            out.start.x,
            out.start.y,
            out.swarm.len(),
            scn.run.params.wave.cycle.as_millis() / 1000
        ),
        (FONT, 18),
    )?;
    let (left, right) = root.split_horizontally(520);
    let traj: Vec<(f64, f64)> = std::iter::once((out.start.x, out.start.y))
        .chain(out.periods.iter().map(|p| (p.to.x, p.to.y)))
        .collect();
    let agents: Vec<(f64, f64)> = out
        .swarm
        .offsets()
        .iter()
        .map(|o| (out.start.x + o.x, out.start.y + o.y))
        .collect();
    let end = traj.last().copied().unwrap_or((out.start.x, out.start.y));
    let final_agents: Vec<(f64, f64)> = out
        .swarm
        .offsets()
        .iter()
        .map(|o| (end.0 + o.x, end.1 + o.y))
        .collect();
    let (xr, yr) = square_range(
        traj.iter()
            .chain(agents.iter())
            .chain(final_agents.iter())
            .copied(),
        0.5,
    );
    let mut chart = ChartBuilder::on(&left)
        .margin(10)
        .caption(
            "(a) centre of mass (+); swarm at start (grey) and end (blue)",
            (FONT, 15),
        )
        .x_label_area_size(35)
        .y_label_area_size(40)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x / R")
        .y_desc("y / R")
        .draw()?;
    draw_field(&mut chart, &scn.field, xr, yr)?;
    chart.draw_series(agents.iter().map(|&p| {
        Circle::new(
            p,
            4,
            ShapeStyle::from(&RGBColor(110, 110, 110)).stroke_width(1),
        )
    }))?;
    chart.draw_series(final_agents.iter().map(|&p| {
        Circle::new(
            p,
            4,
            ShapeStyle::from(&RGBColor(60, 90, 200).mix(0.6)).stroke_width(1),
        )
    }))?;
    chart.draw_series(LineSeries::new(traj.iter().copied(), BLACK.stroke_width(1)))?;
    chart.draw_series(
        traj.iter()
            .map(|&p| Cross::new(p, 3, BLACK.stroke_width(1))),
    )?;
    if let Some(&last) = traj.last() {
        chart.draw_series(std::iter::once(Circle::new(last, 5, BLUE.filled())))?;
    }

    diversity_panel(&right, out)?;
    root.present()?;
    Ok(())
}

/// The paper's success rate as dashed segments over `x0..x1` (401 samples; a gap where it
/// gives none).
fn paper_segments(paper: &dyn Fn(f64) -> Option<f64>, x0: f64, x1: f64) -> Vec<Vec<(f64, f64)>> {
    let xs: Vec<f64> = (0..=400)
        .map(|k| x0 + (x1 - x0) * f64::from(k) / 400.0)
        .collect();
    let mut segment: Vec<(f64, f64)> = Vec::new();
    let mut segments = Vec::new();
    for x in xs {
        match paper(x) {
            Some(v) => segment.push((x, v)),
            None if !segment.is_empty() => segments.push(std::mem::take(&mut segment)),
            None => {}
        }
    }
    if !segment.is_empty() {
        segments.push(segment);
    }
    segments
}

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

/// Figs. 5 and 8: success rate and mean success time against the initial position, one bar
/// per series (label, points) at each initial position, and the paper's reported rate.
///
/// # Errors
/// If the file cannot be written.
pub fn sweep_figure(
    path: &Path,
    title: &str,
    series: &[(&str, &[SweepPoint])],
    paper: Option<&dyn Fn(f64) -> Option<f64>>,
) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, (800, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 18))?;
    let (top, bottom) = root.split_vertically(300);
    let all = || series.iter().flat_map(|(_, pts)| pts.iter());
    let step = series
        .iter()
        .flat_map(|(_, pts)| pts.windows(2).map(|w| w[1].x_init - w[0].x_init))
        .filter(|d| *d > 0.0)
        .fold(f64::MAX, f64::min)
        .min(1.0);
    let (lo, hi) = all().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
        (lo.min(p.x_init), hi.max(p.x_init))
    });
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (-5.0, 5.0) };
    let (x0, x1) = (lo - step, hi + step);
    let mut chart = ChartBuilder::on(&top)
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
    for (s, (label, points)) in series.iter().enumerate() {
        let colour = COLOURS[s % COLOURS.len()];
        let left = -0.4 * step + s as f64 * w;
        chart
            .draw_series(points.iter().map(|p| {
                Rectangle::new(
                    [
                        (p.x_init + left, 0.0),
                        (p.x_init + left + w, p.success_rate()),
                    ],
                    colour.filled(),
                )
            }))?
            .label(*label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 15, y + 5)], colour.filled()));
    }
    if let Some(paper) = paper {
        let segments = paper_segments(paper, x0, x1);
        let style = RGBColor(200, 60, 40).stroke_width(2);
        for (k, s) in segments.into_iter().enumerate() {
            let series = chart.draw_series(DashedLineSeries::new(s, 6, 4, style))?;
            if k == 0 {
                series
                    .label("paper (text)")
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 15, y)], style));
            }
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 13))
        .draw()?;

    times_panel(&bottom, series, (x0, x1))?;
    root.present()?;
    Ok(())
}

/// Figs. 6, 9 and 10: the preferred direction of a swarm centred at each grid point, over the
/// field. Arrow length grows with the agreement among the agents (mean resultant length).
///
/// # Errors
/// If the file cannot be written.
pub fn direction_figure(
    path: &Path,
    scn: &Scenario,
    grid: &GridSpec,
    arrows: &[Arrow],
) -> Result<(), PlotError> {
    let spacing = |v: &[f64]| {
        v.windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::MAX, f64::min)
            .min(2.0)
    };
    let d = spacing(&grid.xs).min(spacing(&grid.ys));
    let d = if d.is_finite() && d > 0.0 { d } else { 1.0 };
    let first = |v: &[f64]| v.first().copied().unwrap_or(0.0);
    let last = |v: &[f64]| v.last().copied().unwrap_or(0.0);
    let xr = (first(&grid.xs) - d, last(&grid.xs) + d);
    let yr = (first(&grid.ys) - d, last(&grid.ys) + d);
    let w = 900u32;
    let h = ((f64::from(w - 60) * (yr.1 - yr.0) / (xr.1 - xr.0)) as u32 + 110).clamp(300, 1000);
    let root = SVGBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{}: preferred direction, one run of a {}-cycle period per arrow",
            scn.description,
            grid.gather_cycles + grid.decide_cycles
        ),
        (FONT, 17),
    )?;
    let mut chart = ChartBuilder::on(&root)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(40)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x / R")
        .y_desc("y / R")
        .draw()?;
    draw_field(&mut chart, &scn.field, xr, yr)?;
    let style = BLACK.stroke_width(2);
    for a in arrows {
        let (x, y) = (a.at.x, a.at.y);
        match a.direction {
            Some(th) => {
                let len = 0.85 * d * a.consensus.max(0.25);
                let (c, s) = (th.cos(), th.sin());
                let tail = (x - 0.5 * len * c, y - 0.5 * len * s);
                let tip = (x + 0.5 * len * c, y + 0.5 * len * s);
                let head = 0.3 * d.min(len.max(0.5 * d));
                let wing = |a: f64| (tip.0 - head * (th + a).cos(), tip.1 - head * (th + a).sin());
                chart.draw_series(std::iter::once(PathElement::new(vec![tail, tip], style)))?;
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![wing(PI / 7.0), tip, wing(-PI / 7.0)],
                    style,
                )))?;
            }
            None => {
                chart.draw_series(std::iter::once(Circle::new((x, y), 2, BLACK.filled())))?;
            }
        }
    }
    root.present()?;
    Ok(())
}

/// One line of a figure: a label and its points (x, y, optional error).
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64, f64)>,
}

/// A plain x–y figure with error bars and optional vertical marker lines.
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
    let root = SVGBackend::new(path, (800, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 17))?;
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
    /// Mesh, markers, one line with its points and error bars per [`Line`], and the legend.
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
        let palette = [
            RGBColor(70, 110, 180),
            RGBColor(200, 60, 40),
            RGBColor(40, 140, 70),
            RGBColor(140, 80, 160),
            RGBColor(90, 90, 90),
        ];
        let (y0, y1) = self.y_range;
        chart
            .configure_mesh()
            .x_desc(self.x_desc)
            .y_desc(self.y_desc)
            .x_labels(if self.log_x { 4 } else { 12 })
            .x_label_formatter(&|v: &f64| format!("{v}"))
            .max_light_lines(if self.log_x { 1 } else { 4 })
            .draw()?;
        for &(mx, label) in self.markers {
            chart.draw_series(DashedLineSeries::new(
                vec![(mx, y0), (mx, y1)],
                5,
                4,
                RGBColor(120, 120, 120).stroke_width(1),
            ))?;
            chart.draw_series(std::iter::once(Text::new(
                label.to_string(),
                (mx, y1),
                (FONT, 12).into_font().color(&RGBColor(90, 90, 90)),
            )))?;
        }
        for (k, l) in self.lines.iter().enumerate() {
            let c = palette[k % palette.len()];
            chart
                .draw_series(LineSeries::new(
                    l.points.iter().map(|p| (p.0, p.1)),
                    c.stroke_width(2),
                ))?
                .label(l.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 15, y)], c.stroke_width(2))
                });
            chart.draw_series(
                l.points
                    .iter()
                    .map(|p| Circle::new((p.0, p.1), 3, c.filled())),
            )?;
            chart.draw_series(l.points.iter().filter(|p| p.2 > 0.0).map(|p| {
                PathElement::new(vec![(p.0, p.1 - p.2), (p.0, p.1 + p.2)], c.stroke_width(1))
            }))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 13))
            .draw()?;
        Ok(())
    }
}

/// The radial profile of a cloud: how strongly the swarm heads for the cloud's centre against
/// its distance from it.
///
/// # Errors
/// If the file cannot be written.
pub fn radial_figure(
    path: &Path,
    title: &str,
    points: &[RadialPoint],
    markers: &[(f64, &str)],
) -> Result<(), PlotError> {
    let line = Line {
        label: "mean cos(direction − direction to the centre)".into(),
        points: points
            .iter()
            .map(|p| (p.distance, p.inward, p.inward_se))
            .collect(),
    };
    xy_figure(
        path,
        title,
        "distance of the swarm's centre from the cloud's centre / R",
        "inward alignment",
        &[line],
        (-1.05, 1.05),
        markers,
        false,
    )
}
