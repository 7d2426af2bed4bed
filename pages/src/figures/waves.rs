//! The paper's Fig. 2 drawn from a [`Wave`]: five snapshots of the agents' states and the paths
//! of a few messages, and the CSV file with the same data.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use protocol::WaveState;

use report::csv_files::fixed;
use report::plot::PlotError;
use swarm_sim::waves::{PATH_SECTORS, Wave};

const FONT: &str = "sans-serif";
/// The paper's colours: inactive black, active red, refractory blue.
const INACTIVE: RGBColor = RGBColor(25, 25, 25);
const ACTIVE: RGBColor = RGBColor(225, 30, 30);
const REFRACTORY: RGBColor = RGBColor(45, 95, 225);
const LINK: RGBColor = RGBColor(215, 215, 215);
const FADED: RGBColor = RGBColor(150, 150, 150);

fn colour(s: WaveState) -> RGBColor {
    match s {
        WaveState::Inactive => INACTIVE,
        WaveState::Active => ACTIVE,
        WaveState::Refractory => REFRACTORY,
    }
}

/// The state's name in the CSV file.
fn name(s: WaveState) -> &'static str {
    match s {
        WaveState::Inactive => "inactive",
        WaveState::Active => "active",
        WaveState::Refractory => "refractory",
    }
}

type Panel<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A square panel over the swarm's disk with a caption.
fn panel<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: &str,
    lim: f64,
) -> Result<Panel<'a, 'b>, PlotError> {
    let mut chart = ChartBuilder::on(area)
        .margin(6)
        .caption(caption, (FONT, 15))
        .x_label_area_size(22)
        .y_label_area_size(28)
        .build_cartesian_2d(-lim..lim, -lim..lim)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(5)
        .y_labels(5)
        .label_style((FONT, 11))
        .draw()?;
    Ok(chart)
}

fn xy(w: &Wave, i: usize) -> (f64, f64) {
    let p = w.position(i);
    (p.x, p.y)
}

/// Fig. 2: panels (a)–(e) the agents coloured by state at each of `times` (seconds after the
/// initiation, as [`Wave::shown`]), (f) the paths of the messages that reached the last agent
/// of each sector ([`Wave::path_ends`]) over the neighbour links; a legend below the panels.
/// The initiator is ringed in every panel; (a) has a bar one perception range long.
///
/// # Errors
/// If the file cannot be written.
pub fn waves_figure(path: &Path, w: &Wave, times: &[u64]) -> Result<(), PlotError> {
    let root = SVGBackend::new(path, (1080, 815)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "One wave through N = {} agents (swarm of {} R, R = 1): t_ref = {} s, relay delay {} s; x, y in R",
            w.len(),
            w.spec.diameter,
            w.spec.refractory_s,
            w.spec.config().params.wave.relay_delay.as_millis() as f64 / 1000.0
        ),
        (FONT, 18),
    )?;
    let height = root.dim_in_pixel().1;
    let (grid, legend) = root.split_vertically(height.saturating_sub(40));
    let panels = grid.split_evenly((2, 3));
    let lim = (0..w.len())
        .map(|i| w.swarm.offsets()[i].abs().max())
        .fold(0.5 * w.spec.diameter, f64::max)
        + 0.35;
    let letter = |k: usize| char::from(b'a' + k as u8);
    let ring = |i: usize| Circle::new(xy(w, i), 7, BLACK.stroke_width(1));
    for (k, (area, &t)) in panels.iter().zip(times).enumerate() {
        let mut chart = panel(area, &format!("({}) t = {t} s", letter(k)), lim)?;
        chart.draw_series(
            (0..w.len()).map(|i| Circle::new(xy(w, i), 4, colour(w.shown(i, t)).filled())),
        )?;
        chart.draw_series(std::iter::once(ring(w.initiator)))?;
        if k == 0 {
            let y = -lim + 0.25;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(lim - 1.25, y), (lim - 0.25, y)],
                BLACK.stroke_width(2),
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                "R",
                (lim - 0.8, y + 0.35),
                (FONT, 13),
            )))?;
        }
    }
    if let Some(area) = panels.get(times.len()) {
        let ends = w.path_ends(PATH_SECTORS);
        let mut chart = panel(
            area,
            &format!(
                "({}) paths of {} messages (red)",
                letter(times.len()),
                ends.len()
            ),
            lim,
        )?;
        let links = (0..w.len()).flat_map(|i| {
            w.swarm
                .neighbours(i)
                .iter()
                .filter(move |l| l.agent as usize > i)
                .map(move |l| (i, l.agent as usize))
        });
        chart.draw_series(
            links.map(|(i, j)| PathElement::new(vec![xy(w, i), xy(w, j)], LINK.stroke_width(1))),
        )?;
        chart.draw_series((0..w.len()).map(|i| Circle::new(xy(w, i), 3, FADED.filled())))?;
        for &e in &ends {
            let p: Vec<(f64, f64)> = w.path(e).into_iter().map(|i| xy(w, i)).collect();
            chart.draw_series(p.iter().map(|&q| Circle::new(q, 3, ACTIVE.filled())))?;
            chart.draw_series(std::iter::once(PathElement::new(p, ACTIVE.stroke_width(2))))?;
            chart.draw_series(std::iter::once(Circle::new(xy(w, e), 5, ACTIVE.filled())))?;
        }
        chart.draw_series(std::iter::once(ring(w.initiator)))?;
    }
    draw_legend(&legend)?;
    root.present()?;
    Ok(())
}

/// The legend, in its own strip below the panels.
fn draw_legend(area: &DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), PlotError> {
    let y = 18;
    let text = |s: &str, x: i32| Text::new(s.to_owned(), (x, y - 8), (FONT, 14));
    let mut x = 40;
    for (c, label, width) in [
        (INACTIVE, "inactive", 95),
        (ACTIVE, "active (transmits this second)", 235),
        (REFRACTORY, "refractory", 110),
    ] {
        area.draw(&Circle::new((x, y), 5, c.filled()))?;
        area.draw(&text(label, x + 10))?;
        x += width;
    }
    area.draw(&Circle::new((x, y), 7, BLACK.stroke_width(1)))?;
    area.draw(&text("initiator", x + 12))?;
    x += 100;
    area.draw(&PathElement::new(
        vec![(x - 8, y), (x + 14, y)],
        ACTIVE.stroke_width(2),
    ))?;
    area.draw(&text("(f) message path", x + 20))?;
    x += 160;
    area.draw(&PathElement::new(
        vec![(x - 8, y), (x + 14, y)],
        LINK.stroke_width(2),
    ))?;
    area.draw(&text("(f) neighbours within R", x + 20))?;
    Ok(())
}

/// `agent,x,y,sent_at_s,parent,state_t{T}...`: per agent its position, the second of the wave
/// at which it transmitted (empty if never), the agent whose message activated it (empty for
/// the initiator) and its state at each of `times`, as [`Wave::shown`] (the paper's colours).
///
/// # Errors
/// If the file cannot be written.
pub fn write_waves_csv(path: &Path, w: &Wave, times: &[u64]) -> std::io::Result<()> {
    let mut out = csv::Writer::from_path(path)?;
    let mut header: Vec<String> = ["agent", "x", "y", "sent_at_s", "parent"]
        .map(str::to_owned)
        .to_vec();
    header.extend(times.iter().map(|t| format!("state_t{t}")));
    out.write_record(&header)?;
    for i in 0..w.len() {
        let (x, y) = xy(w, i);
        let mut row = vec![
            i.to_string(),
            fixed(x, 4),
            fixed(y, 4),
            w.sent_at[i].map_or(String::new(), |t| t.to_string()),
            w.parent[i].map_or(String::new(), |p| p.to_string()),
        ];
        row.extend(times.iter().map(|&t| name(w.shown(i, t)).to_owned()));
        out.write_record(&row)?;
    }
    out.flush()
}
