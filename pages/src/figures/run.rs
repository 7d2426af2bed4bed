//! Figs. 5 and 8: one run's trajectory over the field and the diversity against time.

use std::path::Path;

use plotters::prelude::*;

use super::field::{draw_field, square_range};
use report::plot::{FONT, PlotError};
use swarm_sim::experiment::RunOutput;
use swarm_sim::scenario::Scenario;

/// Panel (b) of [`run_figure`]: the agents' average diversity against time.
fn diversity_panel(
    right: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    scn: &Scenario,
    out: &RunOutput,
) -> Result<(), PlotError> {
    let p = &scn.run.params;
    let cycles = u32::from(p.gather_cycles) + u32::from(p.decide_cycles);
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
        .x_desc(format!("t / negotiation periods ({cycles} cycles)"))
        .y_desc("mean V_k")
        .draw()?;
    chart.draw_series(LineSeries::new(div.iter().copied(), BLACK.stroke_width(2)))?;
    chart.draw_series(div.iter().map(|&p| Circle::new(p, 2, BLACK.filled())))?;
    Ok(())
}

/// Figs. 5 and 8: the trajectory of the centre of mass over the field, with the swarm at its
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
    trajectory_panel(&left, scn, out)?;
    diversity_panel(&right, scn, out)?;
    root.present()?;
    Ok(())
}

/// Panel (a) of [`run_figure`]: the centre of mass's trajectory over the field, with the swarm
/// at its start and at its end.
fn trajectory_panel(
    left: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    scn: &Scenario,
    out: &RunOutput,
) -> Result<(), PlotError> {
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
    let mut chart = ChartBuilder::on(left)
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
    Ok(())
}
