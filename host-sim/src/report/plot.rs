//! SVG figures with plotters' SVG backend: pure Rust, no system fonts or libraries (text is
//! written as SVG `<text>` and laid out by the viewer).

use std::f64::consts::PI;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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

/// The colour of level `l` (0..=23, low to high X): pale yellow to red, or red to pale yellow
/// when `high_is_yellow`.
fn level_colour(l: u8, high_is_yellow: bool) -> RGBColor {
    let l = if high_is_yellow { 23 - l.min(23) } else { l };
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
    high_is_yellow: bool,
) -> Result<(f64, f64), PlotError>
where
    DB::ErrorType: 'static,
{
    let (rects, lo, hi) = field_rects(field, x, y, 120);
    chart
        .draw_series(
            rects
                .into_iter()
                .map(|(a, b, l)| Rectangle::new([a, b], level_colour(l, high_is_yellow).filled())),
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
    draw_field(&mut chart, &scn.field, xr, yr, false)?;
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

/// Colour of the paper's values on a sweep figure.
const PAPER: RGBColor = RGBColor(200, 60, 40);

/// What a legend entry shows beside its text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Key {
    /// A filled box: a bar series.
    Bar(RGBColor),
    /// A pale box with a border: a shaded band.
    Band(RGBColor),
    /// A solid line.
    Line(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A hollow circle: one value at one point.
    Marker(RGBColor),
    /// An arrow: a swarm's preferred direction.
    Arrow,
    /// A dot: no direction.
    Dot,
    /// The field's colour ramp from low X to high X; `true` when high X is pale yellow.
    Ramp(bool),
}

/// A legend entry: its key and its text.
pub type Entry = (Key, String);

/// Height of one row of a legend strip, px.
const LEGEND_ROW: i32 = 20;
/// Width of a legend key, px.
const KEY_W: i32 = 24;
/// Font size of legend text, px.
const LEGEND_FONT: u32 = 13;

/// A generous estimate of the width of `text` in the legend font (SVG text is laid out by the
/// viewer: 0.6 em per character covers sans-serif).
fn text_width(text: &str) -> i32 {
    (text.chars().count() as f64 * 0.6 * f64::from(LEGEND_FONT)).ceil() as i32
}

/// Where each entry of a legend strip `width` px wide goes, (x, row), filling rows left to
/// right; and the number of rows.
fn legend_layout(width: i32, entries: &[Entry]) -> (Vec<(i32, i32)>, i32) {
    let (mut x, mut row) = (10, 0);
    let mut out = Vec::with_capacity(entries.len());
    for (_, text) in entries {
        let w = KEY_W + 6 + text_width(text) + 20;
        if x > 10 && x + w > width - 10 {
            row += 1;
            x = 10;
        }
        out.push((x, row));
        x += w;
    }
    (out, if entries.is_empty() { 0 } else { row + 1 })
}

/// Height of the legend strip of `entries` across `width` px (0 without entries).
fn legend_height(width: u32, entries: &[Entry]) -> u32 {
    let (_, rows) = legend_layout(width as i32, entries);
    if rows == 0 {
        0
    } else {
        (rows * LEGEND_ROW + 8) as u32
    }
}

/// Draws the key of a legend entry with its left end at `x` on the centre line `y` (px).
fn draw_key(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    key: Key,
    x: i32,
    y: i32,
) -> Result<(), PlotError> {
    match key {
        Key::Bar(c) => area.draw(&Rectangle::new(
            [(x, y - 6), (x + KEY_W, y + 6)],
            c.filled(),
        ))?,
        Key::Band(c) => {
            area.draw(&Rectangle::new(
                [(x, y - 6), (x + KEY_W, y + 6)],
                c.mix(0.2).filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x, y - 6), (x + KEY_W, y + 6)],
                c.stroke_width(1),
            ))?;
        }
        Key::Line(c) => area.draw(&PathElement::new(
            vec![(x, y), (x + KEY_W, y)],
            c.stroke_width(2),
        ))?,
        Key::Dashed(c) => {
            for (a, b) in [(0, 7), (11, 18), (22, KEY_W)] {
                area.draw(&PathElement::new(
                    vec![(x + a, y), (x + b, y)],
                    c.stroke_width(2),
                ))?;
            }
        }
        Key::Marker(c) => area.draw(&Circle::new((x + KEY_W / 2, y), 5, c.stroke_width(2)))?,
        Key::Arrow => {
            let style = BLACK.stroke_width(2);
            area.draw(&PathElement::new(vec![(x, y), (x + KEY_W, y)], style))?;
            area.draw(&PathElement::new(
                vec![
                    (x + KEY_W - 6, y - 4),
                    (x + KEY_W, y),
                    (x + KEY_W - 6, y + 4),
                ],
                style,
            ))?;
        }
        Key::Dot => area.draw(&Circle::new((x + KEY_W / 2, y), 2, BLACK.filled()))?,
        Key::Ramp(high_is_yellow) => {
            for i in 0..KEY_W {
                let l = (f64::from(i) * 23.0 / f64::from(KEY_W - 1)).round() as u8;
                area.draw(&Rectangle::new(
                    [(x + i, y - 6), (x + i + 1, y + 6)],
                    level_colour(l, high_is_yellow).filled(),
                ))?;
            }
        }
    }
    Ok(())
}

/// Draws `entries` in rows across `area`, a strip outside every plot, so that no entry can
/// cover data.
fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[Entry],
) -> Result<(), PlotError> {
    let (w, _) = area.dim_in_pixel();
    let (pos, _) = legend_layout(w as i32, entries);
    let font =
        TextStyle::from((FONT, LEGEND_FONT).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for ((key, text), (x, row)) in entries.iter().zip(pos) {
        let y = 4 + row * LEGEND_ROW + LEGEND_ROW / 2;
        draw_key(area, *key, x, y)?;
        area.draw(&Text::new(text.clone(), (x + KEY_W + 6, y), font.clone()))?;
    }
    Ok(())
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

/// Figs. 5 and 8: success rate and mean success time against the initial position, one bar
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
    let legend_h = legend_height(800, &entries);
    let root = SVGBackend::new(path, (800, 640 + legend_h)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (FONT, 18))?;
    let (legend, rest) = root.split_vertically(legend_h);
    draw_legend(&legend, &entries)?;
    let (top, bottom) = rest.split_vertically(300);
    let ((x0, x1), step) = sweep_axis(series);
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
    let line = PAPER.stroke_width(2);
    for m in marks {
        match *m {
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
    }

    times_panel(&bottom, series, (x0, x1))?;
    root.present()?;
    Ok(())
}

/// Colours of the marks of a direction map (neither yellow nor red, so they show on the field).
const MARK_COLOURS: [RGBColor; 4] = [
    RGBColor(20, 70, 200),
    RGBColor(0, 130, 60),
    RGBColor(130, 40, 170),
    RGBColor(0, 150, 170),
];

/// The shape of a mark on a direction map.
#[derive(Clone, Debug, PartialEq)]
pub enum MapShape {
    /// Vertical lines at these x.
    XLines(Vec<f64>),
    /// A circle.
    Circle {
        /// Its centre.
        centre: (f64, f64),
        /// Its radius, R.
        radius: f64,
    },
}

/// A mark on a direction map: a dashed shape in its own colour, with its legend text.
#[derive(Clone, Debug, PartialEq)]
pub struct MapMark {
    /// What is drawn.
    pub shape: MapShape,
    /// Legend text.
    pub label: String,
}

/// Marks on a direction map and the colours of its field.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapMarks {
    /// The marks, in legend order.
    pub marks: Vec<MapMark>,
    /// High X pale yellow and low X red (the paper's cloud figure) instead of the other way
    /// round (its sharp border and gradient figures).
    pub high_is_yellow: bool,
}

/// Figs. 6, 9 and 10: the preferred direction of a swarm centred at each grid point, over the
/// field, with `marks` and their colouring. Arrow length grows with the agreement among the
/// agents (mean resultant length). A legend strip under the title says what an arrow's length,
/// a dot and the colours mean, and names each mark.
///
/// # Errors
/// If the file cannot be written.
pub fn direction_figure(
    path: &Path,
    scn: &Scenario,
    grid: &GridSpec,
    arrows: &[Arrow],
    marks: &MapMarks,
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
    let mut entries: Vec<Entry> = vec![
        (
            Key::Arrow,
            format!(
                "preferred direction; length = consensus, the mean resultant length of the agents' decided bearings ({:.2} R at 1, at least a quarter of that)",
                0.85 * d
            ),
        ),
        (Key::Dot, "no agent decided".into()),
        (
            Key::Ramp(marks.high_is_yellow),
            if marks.high_is_yellow {
                "mean X: red low, pale yellow high (as the paper's cloud)".into()
            } else {
                "mean X: pale yellow low, red high (as the paper)".into()
            },
        ),
    ];
    entries.extend(marks.marks.iter().enumerate().map(|(k, m)| {
        (
            Key::Dashed(MARK_COLOURS[k % MARK_COLOURS.len()]),
            m.label.clone(),
        )
    }));
    let w = 900u32;
    let legend_h = legend_height(w, &entries);
    let h = ((f64::from(w - 60) * (yr.1 - yr.0) / (xr.1 - xr.0)) as u32 + 110).clamp(300, 1000);
    let root = SVGBackend::new(path, (w, h + legend_h)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{}: preferred direction, one run of a {}-cycle period per arrow",
            scn.description,
            grid.gather_cycles + grid.decide_cycles
        ),
        (FONT, 17),
    )?;
    let (legend, plot_area) = root.split_vertically(legend_h);
    draw_legend(&legend, &entries)?;
    let mut chart = ChartBuilder::on(&plot_area)
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
    draw_field(&mut chart, &scn.field, xr, yr, marks.high_is_yellow)?;
    for (k, m) in marks.marks.iter().enumerate() {
        let style = MARK_COLOURS[k % MARK_COLOURS.len()].stroke_width(2);
        let paths: Vec<Vec<(f64, f64)>> = match &m.shape {
            MapShape::XLines(xs) => xs.iter().map(|&x| vec![(x, yr.0), (x, yr.1)]).collect(),
            MapShape::Circle { centre, radius } => vec![
                (0..=240)
                    .map(|i| {
                        let a = 2.0 * PI * f64::from(i) / 240.0;
                        (centre.0 + radius * a.cos(), centre.1 + radius * a.sin())
                    })
                    .filter(|p| (xr.0..=xr.1).contains(&p.0) && (yr.0..=yr.1).contains(&p.1))
                    .collect(),
            ],
        };
        for p in paths {
            chart.draw_series(DashedLineSeries::new(p, 8, 5, style))?;
        }
    }
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

/// The radial profile of a cloud: how strongly the swarm heads for the cloud's centre against
/// its distance from it.
///
/// # Errors
/// If the file cannot be written.
pub fn radial_figure(
    path: &Path,
    title: &str,
    points: &[RadialPoint],
    markers: &[(f64, String)],
) -> Result<(), PlotError> {
    let markers: Vec<(f64, &str)> = markers.iter().map(|(d, l)| (*d, l.as_str())).collect();
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
        &markers,
        false,
    )
}
