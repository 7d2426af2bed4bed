//! The discussion's shapes (paper section 5) drawn from [`ShapeHistograms`]: per formation its
//! agents, and histograms over the circle of the swarm's decided direction and of the agents'
//! bearings; and the CSV file with the same counts.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use report::csv_files::fixed;
use report::plot::PlotError;
use reproduce::shapes::{CSV, FIGURE, RUNS, ShapesResult};
use swarm_sim::experiment::Error;
use swarm_sim::shapes::ShapeHistograms;

const FONT: &str = "sans-serif";
/// Decisions with the paper's diffusion: filled bars.
const DECIDED: RGBColor = RGBColor(70, 110, 180);
/// Preferences before diffusion: an outline.
const PREFERRED: RGBColor = RGBColor(215, 95, 20);
const UNIFORM: RGBColor = RGBColor(120, 120, 120);
const AGENT: RGBColor = RGBColor(25, 25, 25);

/// The figure: a strip with each formation's agents (each to its own scale, its extent
/// written), then one column per formation, the swarm's direction on top and the agents'
/// bearings below, as the fraction of runs (agents) per bin. Bars: at the end of the period,
/// with the diffusion of `diffusion_pct` %; outline: the agents' preferences at the end of the
/// gathering phase, before diffusion (top: their circular mean). A dashed line marks a uniform
/// distribution; the legend sits in its own strip below.
///
/// # Errors
/// If the file cannot be written.
pub fn shapes_figure(
    path: &Path,
    shapes: &[ShapeHistograms],
    runs: u32,
    diffusion_pct: &str,
) -> Result<(), PlotError> {
    let cols = shapes.len().max(1);
    let root = SVGBackend::new(path, (330 * cols as u32, 790)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "Decided directions on a field of independent random values (X = 0 plus noise), \
             one negotiation period, {runs} runs per formation"
        ),
        (FONT, 18),
    )?;
    let (w, h) = root.dim_in_pixel();
    let (top, rest) = root.split_vertically(125);
    let (grid, legend) = rest.split_vertically(h.saturating_sub(125 + 40));
    let strips = top.split_evenly((1, cols));
    for (area, s) in strips.iter().zip(shapes) {
        draw_agents(area, s)?;
    }
    let panels = grid.split_evenly((2, cols));
    let letter = |k: usize| char::from(b'a' + k as u8);
    for (c, s) in shapes.iter().enumerate() {
        for (row, (bars, outline, what)) in [
            (&s.swarm, &s.swarm_preferred, "swarm's direction"),
            (&s.agents, &s.agents_preferred, "agents' bearings"),
        ]
        .into_iter()
        .enumerate()
        {
            let k = row * cols + c;
            let caption = format!("({}) {}: {what}", letter(k), s.name);
            let unit = ["of the runs", "of the agents"][row];
            let width = 360 / bars.len().max(1);
            let desc = (c == 0).then(|| format!("{unit} per {width}° bin"));
            histogram_panel(
                &panels[k],
                &caption,
                bars,
                outline,
                row == 1,
                desc.as_deref(),
            )?;
        }
    }
    draw_legend(&legend, w, diffusion_pct)?;
    root.present()?;
    Ok(())
}

/// The fraction of the total in each bin.
fn fractions(counts: &[usize]) -> Vec<f64> {
    let n = counts.iter().sum::<usize>().max(1) as f64;
    counts.iter().map(|&c| c as f64 / n).collect()
}

/// One histogram over 0°–360°, bin `k` centred on `k × 360° / bins`, with `y_desc` along its
/// y axis if given.
fn histogram_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    caption: &str,
    bars: &[usize],
    outline: &[usize],
    bottom: bool,
    y_desc: Option<&str>,
) -> Result<(), PlotError> {
    let bins = bars.len().max(1);
    let w = 360.0 / bins as f64;
    let (fb, fo) = (fractions(bars), fractions(outline));
    let top = fb
        .iter()
        .chain(&fo)
        .fold(1.0 / bins as f64, |a, &b| a.max(b))
        * 1.12;
    let mut chart = ChartBuilder::on(area)
        .margin(6)
        .margin_right(12)
        .caption(caption, (FONT, 14))
        .x_label_area_size(if bottom { 36 } else { 22 })
        .y_label_area_size(if y_desc.is_some() { 58 } else { 44 })
        .build_cartesian_2d(-0.5 * w..360.0 - 0.5 * w, 0.0..top)?;
    let mut mesh = chart.configure_mesh();
    mesh.disable_mesh()
        .x_labels(40)
        .x_label_formatter(&|x| {
            // Ticks every 10°, labels on the axes only.
            if (x.rem_euclid(90.0)).min(90.0 - x.rem_euclid(90.0)) < 1e-6 {
                format!("{x:.0}°")
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|y| format!("{:.0} %", 100.0 * y))
        .y_labels(5)
        .label_style((FONT, 11));
    if bottom {
        mesh.x_desc("direction (0° = +x, counter-clockwise)");
    }
    if let Some(d) = y_desc {
        mesh.y_desc(d);
    }
    mesh.axis_desc_style((FONT, 12)).draw()?;
    let x0 = |k: usize| k as f64 * w - 0.5 * w;
    chart.draw_series(
        fb.iter()
            .enumerate()
            .filter(|(_, f)| **f > 0.0)
            .map(|(k, &f)| {
                Rectangle::new([(x0(k), 0.0), (x0(k) + w, f)], DECIDED.mix(0.85).filled())
            }),
    )?;
    let mut step = Vec::with_capacity(2 * bins + 2);
    step.push((x0(0), 0.0));
    for (k, &f) in fo.iter().enumerate() {
        step.push((x0(k), f));
        step.push((x0(k) + w, f));
    }
    step.push((x0(bins), 0.0));
    chart.draw_series(std::iter::once(PathElement::new(
        step,
        PREFERRED.stroke_width(2),
    )))?;
    let u = 1.0 / bins as f64;
    chart.draw_series(DashedLineSeries::new(
        vec![(x0(0), u), (x0(bins), u)],
        5,
        4,
        UNIFORM.stroke_width(1),
    ))?;
    Ok(())
}

/// A formation's agents, to the strip's own scale (equal in x and y), with its name, size and
/// extent.
fn draw_agents(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    s: &ShapeHistograms,
) -> Result<(), PlotError> {
    let (w, h) = area.dim_in_pixel();
    let label = format!("{}: {} agents, {} R across", s.name, s.size, s.extent);
    area.draw(&Text::new(label, (50, 4), (FONT, 13)))?;
    let (bx, by, bw, bh) = (20.0, 24.0, f64::from(w) - 40.0, f64::from(h) - 30.0);
    let (lo, hi) = s.offsets.iter().fold(
        ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN)),
        |(lo, hi), &(x, y)| ((lo.0.min(x), lo.1.min(y)), (hi.0.max(x), hi.1.max(y))),
    );
    if lo.0 > hi.0 {
        return Ok(());
    }
    let span = ((hi.0 - lo.0) / bw).max((hi.1 - lo.1) / bh).max(1e-9);
    let (cx, cy) = (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1));
    let r = if span > 0.2 { 1 } else { 2 };
    for &(x, y) in &s.offsets {
        let px = bx + 0.5 * bw + (x - cx) / span;
        let py = by + 0.5 * bh - (y - cy) / span;
        area.draw(&Circle::new((px as i32, py as i32), r, AGENT.filled()))?;
    }
    Ok(())
}

/// The legend, in its own strip below the panels.
fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    width: u32,
    diffusion_pct: &str,
) -> Result<(), PlotError> {
    let y = 18;
    let text = |s: String, x: i32| Text::new(s, (x, y - 8), (FONT, 14));
    let mut x = (width as i32 / 2 - 480).max(10);
    area.draw(&Rectangle::new(
        [(x, y - 6), (x + 22, y + 6)],
        DECIDED.mix(0.85).filled(),
    ))?;
    area.draw(&text(
        format!("decided at the end of the period ({diffusion_pct} % diffusion)"),
        x + 30,
    ))?;
    x += 400;
    area.draw(&PathElement::new(
        vec![(x, y), (x + 22, y)],
        PREFERRED.stroke_width(2),
    ))?;
    area.draw(&text(
        "preferred after gathering, before diffusion".to_owned(),
        x + 30,
    ))?;
    x += 360;
    area.draw(&PathElement::new(
        vec![(x, y), (x + 8, y)],
        UNIFORM.stroke_width(1),
    ))?;
    area.draw(&PathElement::new(
        vec![(x + 13, y), (x + 22, y)],
        UNIFORM.stroke_width(1),
    ))?;
    area.draw(&text("uniform".to_owned(), x + 30))?;
    Ok(())
}

/// `shape,quantity,bin_from_deg,bin_to_deg,count,fraction`: per formation and quantity
/// (`swarm_decided`, `swarm_preferred_mean`, `agents_decided`, `agents_preferred`), the counts
/// in each bin (bin `k` centred on `k × 360° / bins`; the first starts below 0°).
///
/// # Errors
/// If the file cannot be written.
pub fn write_shapes_csv(path: &Path, shapes: &[ShapeHistograms]) -> std::io::Result<()> {
    let mut out = csv::Writer::from_path(path)?;
    out.write_record([
        "shape",
        "quantity",
        "bin_from_deg",
        "bin_to_deg",
        "count",
        "fraction",
    ])?;
    for s in shapes {
        for (q, h) in [
            ("swarm_decided", &s.swarm),
            ("swarm_preferred_mean", &s.swarm_preferred),
            ("agents_decided", &s.agents),
            ("agents_preferred", &s.agents_preferred),
        ] {
            let w = 360.0 / h.len().max(1) as f64;
            for (k, (&c, f)) in h.iter().zip(fractions(h)).enumerate() {
                let from = k as f64 * w - 0.5 * w;
                out.write_record([
                    s.name.to_owned(),
                    q.to_owned(),
                    fixed(from, 1),
                    fixed(from + w, 1),
                    c.to_string(),
                    fixed(f, 4),
                ])?;
            }
        }
    }
    out.flush()
}

/// Writes `figs/shapes-directions.svg` and `.csv` from the shapes' runs `r`.
///
/// # Errors
/// If a file cannot be written.
pub fn write_shapes(figs: &Path, r: &ShapesResult) -> Result<(), Error> {
    write_shapes_csv(&figs.join(CSV), &r.hists)?;
    shapes_figure(&figs.join(FIGURE), &r.hists, RUNS, &r.diffusion)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use reproduce::shapes::{BINS, compute};
    use swarm_sim::progress::Progress;
    use swarm_sim::scenario::Scenario;

    #[test]
    fn the_shapes_files_and_section_are_written_from_the_runs() {
        let cfg = Scenario::builtin("sharp").unwrap().run;
        let r = compute(cfg, 3, &Progress::hidden()).unwrap();
        let dir = std::env::temp_dir().join(format!("cimax-shapes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        write_shapes(&dir, &r).unwrap();
        let csv = std::fs::read_to_string(dir.join(CSV)).unwrap();
        assert_eq!(csv.lines().count(), 1 + 4 * 4 * BINS);
        assert!(dir.join(FIGURE).exists());
        let md = crate::page::render(
            "reproduction/shapes.md.j2",
            serde_json::json!({
                "shapes": r.section,
                "settings": { "bin_deg": 360 / BINS },
            }),
        )
        .unwrap();
        assert!(md.contains("| line | 61 | 45 |"), "{md}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
