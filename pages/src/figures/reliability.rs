//! The fault campaign's figures on `docs/reliability.md`: the success rate of every scenario
//! against its bar, and the time to consensus of both decision rules side by side.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::reliability::{decision_times, pct};
use lab::campaign::Report;

/// The figure of [`crate::reliability::rules_section`]: per scenario, the median time (bar) and the 95th
/// percentile (whisker) of each rule, on a common axis of seconds.
///
/// # Errors
/// Any failure to draw or write the file.
pub fn rules_chart(
    fixed: &Report,
    adaptive: &Report,
    path: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let n = fixed.results.len().max(1);
    let root = SVGBackend::new(path, (760, 110 + 46 * n as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let rows: Vec<[(Option<f64>, Option<f64>); 2]> = fixed
        .results
        .iter()
        .zip(&adaptive.results)
        .map(|(f, a)| [decision_times(f), decision_times(a)])
        .collect();
    let top = rows
        .iter()
        .flat_map(|r| r.iter().filter_map(|t| t.1))
        .fold(100.0f64, f64::max)
        * 1.05;
    let y = |i: usize| (n - 1 - i) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Time to consensus (reboot: to restored consensus), s",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(100)
        .build_cartesian_2d(0.0..top, -0.5..(n as f64 - 0.5))?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_desc(format!(
            "seconds (one cycle: {} s)",
            // The campaign's robots run the lab's parameters (`lab::campaign::config`).
            protocol::Params::robots().wave.cycle.as_millis() / 1000
        ))
        .draw()?;
    let colours = [RGBColor(160, 160, 160), RGBColor(67, 147, 195)];
    for (k, (name, colour)) in ["fixed", "adaptive"].iter().zip(colours).enumerate() {
        let off = if k == 0 { 0.18 } else { -0.18 };
        chart
            .draw_series(rows.iter().enumerate().filter_map(|(i, r)| {
                let m = r[k].0?;
                Some(Rectangle::new(
                    [(0.0, y(i) + off - 0.15), (m, y(i) + off + 0.15)],
                    colour.filled(),
                ))
            }))?
            .label(*name)
            .legend(move |(x, yy)| {
                Rectangle::new([(x, yy - 5), (x + 12, yy + 5)], colour.filled())
            });
        chart.draw_series(rows.iter().enumerate().filter_map(|(i, r)| {
            let (m, p) = (r[k].0?, r[k].1?);
            Some(PathElement::new(
                vec![(m, y(i) + off), (p, y(i) + off)],
                BLACK.stroke_width(1),
            ))
        }))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    let right =
        TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
    for (i, r) in fixed.results.iter().enumerate() {
        let (x0, yc) = chart.backend_coord(&(0.0, y(i)));
        root.draw(&Text::new(r.scenario.name, (x0 - 8, yc), right.clone()))?;
    }
    root.present()?;
    Ok(())
}

/// Draws the success rate of every scenario as a horizontal bar, with its bar as a red mark.
///
/// # Errors
/// Any failure to draw or write the file.
pub fn success_chart(report: &Report, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let n = report.results.len().max(1);
    let root = SVGBackend::new(path, (760, 90 + 34 * n as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    // Row 0 at the top, centred on y = n - 1.
    let y = |i: usize| (n - 1 - i) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Success rate per scenario ({} seeds each); red: the bar",
                report.plan.seeds
            ),
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(100)
        .build_cartesian_2d(0.0..100.0, -0.5..(n as f64 - 0.5))?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_desc("success, %")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .draw()?;
    chart.draw_series(report.results.iter().enumerate().map(|(i, r)| {
        let colour = match r.passed() {
            Some(false) => RGBColor(214, 96, 77),
            Some(true) => RGBColor(67, 147, 195),
            None => RGBColor(160, 160, 160),
        };
        Rectangle::new(
            [(0.0, y(i) - 0.35), (100.0 * r.rate(), y(i) + 0.35)],
            colour.filled(),
        )
    }))?;
    chart.draw_series(report.results.iter().enumerate().filter_map(|(i, r)| {
        let b = 100.0 * r.scenario.bar?;
        Some(PathElement::new(
            vec![(b, y(i) - 0.45), (b, y(i) + 0.45)],
            RED.stroke_width(3),
        ))
    }))?;
    let right =
        TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
    for (i, r) in report.results.iter().enumerate() {
        let (x0, yc) = chart.backend_coord(&(0.0, y(i)));
        root.draw(&Text::new(r.scenario.name, (x0 - 8, yc), right.clone()))?;
        let inside = TextStyle::from(("sans-serif", 12).into_font())
            .pos(Pos::new(HPos::Left, VPos::Center))
            .color(&WHITE);
        root.draw(&Text::new(pct(r.rate()), (x0 + 8, yc), inside))?;
    }
    root.present()?;
    Ok(())
}
