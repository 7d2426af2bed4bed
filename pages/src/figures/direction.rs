//! Figs. 7, 10 and 11: the preferred direction of a swarm centred at each grid point, over the
//! field, with marks.

use std::f64::consts::PI;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::field::draw_field;
use report::plot::{Entry, FONT, Key, PlotError, draw_legend, legend_height};
use swarm_sim::experiment::Arrow;
use swarm_sim::scenario::{GridSpec, Scenario};

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

/// Figs. 7, 10 and 11: the preferred direction of a swarm centred at each grid point, over the
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
    let MapExtent { d, xr, yr } = MapExtent::of(grid);
    let entries = map_legend(d, marks);
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
    draw_marks(&mut chart, marks, xr, yr)?;
    draw_arrows(&mut chart, arrows, d)?;
    root.present()?;
    Ok(())
}

/// The chart of a direction map, in R.
type MapChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Where a direction map draws: the grid's spacing `d` (at most 2 R) and the axes' ranges, the
/// grid with a margin of `d` on every side.
struct MapExtent {
    d: f64,
    xr: (f64, f64),
    yr: (f64, f64),
}

impl MapExtent {
    fn of(grid: &GridSpec) -> MapExtent {
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
        MapExtent {
            d,
            xr: (first(&grid.xs) - d, last(&grid.xs) + d),
            yr: (first(&grid.ys) - d, last(&grid.ys) + d),
        }
    }
}

/// The legend of a direction map with grid spacing `d`: the arrow, the dot, the colour ramp and
/// each mark.
fn map_legend(d: f64, marks: &MapMarks) -> Vec<Entry> {
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
    entries
}

/// Each mark as a dashed shape in its own colour, clipped to the axes `xr` × `yr`.
fn draw_marks(
    chart: &mut MapChart<'_, '_>,
    marks: &MapMarks,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), PlotError> {
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
    Ok(())
}

/// One arrow per grid point, its length growing with the consensus (grid spacing `d`), or a dot
/// where no agent decided.
fn draw_arrows(chart: &mut MapChart<'_, '_>, arrows: &[Arrow], d: f64) -> Result<(), PlotError> {
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
    Ok(())
}
