//! "The artificial swarms using this algorithm perform better the steeper a gradient in
//! measured quantity is" (§4, from the sharp border's shorter times): success and time from the
//! page's start for ramps of several slopes and the sharp border, timed two ways: to the
//! scenario's criterion, and to the same line for all (within 0.33 R of x = 0, the border or
//! the ramp's start), since the gradient's criterion (x ≥ 2.33) lies 2.33 R farther.

use std::path::Path;

use nalgebra::Point2;
use serde::Serialize;

use super::{pm, write_csv};
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::results::{Results, Times};
use reproduce::settle::steep::{NEAR, RUNS, SLOPES, label, slope_of};
use reproduce::units::{Side, Unit};
use swarm_sim::experiment::Error;
use swarm_sim::scenario::Scenario;
use swarm_sim::stats;

/// Which of a run's [`Times`].
type Pick = fn(&Times) -> Option<u32>;

/// One field's runs from the start.
struct Case {
    label: String,
    /// The slope (the sharp border: none).
    slope: Option<f64>,
    /// Per run: periods to the criterion, and to the common line (`None`: not met).
    runs: Vec<Times>,
}

/// Steeper, faster: as the comparison judges it.
pub(in super::super) struct Steepness {
    /// The slope of the mean time to the common line against log2 of the slope (periods per
    /// doubling), with its 95 % half-width, over the ramps.
    pub(in super::super) per_doubling: (f64, f64),
    /// The sharp border's mean time to the line, and the steepest ramp's.
    pub(in super::super) sharp_time: f64,
    pub(in super::super) steepest_time: f64,
    /// The shallowest and the steepest slope, and per measure their values there: success,
    /// mean time to the common line, mean time to the criterion.
    pub(in super::super) slopes: (f64, f64),
    pub(in super::super) success: (f64, f64),
    pub(in super::super) to_line: (f64, f64),
    pub(in super::super) to_criterion: (f64, f64),
    /// The common line (within this of x = 0, [`NEAR`]) and the ramp's success line
    /// (`x ≥ line_x`), R.
    pub(in super::super) near: f64,
    pub(in super::super) line_x: f64,
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct SteepPart {
    runs: u32,
    x: String,
    near: String,
    /// How far apart the two fields' success criteria lie: the gradient's line against the
    /// sharp border's band, R.
    criteria_apart: String,
    /// Per case: field, slope, success, mean time to the criterion, to the common line.
    rows: Vec<Vec<String>>,
    per_doubling: String,
    sharp_time: String,
    steepest_time: String,
    /// The page's own slope, and its mean time to the common line.
    page_slope: String,
    page_slope_time: String,
    /// Shallowest and steepest: slope, success, time to the line, time to the criterion.
    slopes: [String; 2],
    success: [String; 2],
    to_line: [String; 2],
    to_criterion: [String; 2],
}

/// The part from the units [`Unit::Steep`]; writes `settle-steep.{csv,svg}`.
///
/// # Errors
/// If a unit has no result or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    scns: [&Scenario; 2],
    results: &Results,
) -> Result<(SteepPart, [Steepness; 2]), Error> {
    let [sharp, gradient] = scns;
    let page_slope =
        gradient.field.mean(Point2::new(1.0, 0.0)) - gradient.field.mean(Point2::origin());
    let cases_of = |side| -> Result<Vec<Case>, Error> {
        (0..=SLOPES.len())
            .map(|k| {
                let slope = slope_of(k)?;
                Ok(Case {
                    label: label(sharp, slope),
                    slope,
                    runs: results.steep(Unit::Steep(k as u8, side))?.clone(),
                })
            })
            .collect()
    };
    let line_x = reproduce::sensitivity::line_x(gradient);
    let cases = cases_of(Side::Main)?;
    let steep = steepness(&cases, line_x);
    let other = steepness(&cases_of(Side::Other)?, line_x);
    figure(figs, &cases, line_x, gradient.start.x)?;
    let rows: Vec<Vec<String>> = cases.iter().map(cells).collect();
    write_csv(
        figs,
        "settle-steep.csv",
        &[
            "case",
            "slope",
            "success",
            "time_to_criterion",
            "time_to_x0",
        ],
        &rows,
    )?;
    let part = SteepPart {
        runs: RUNS,
        x: gradient.start.x.to_string(),
        near: NEAR.to_string(),
        criteria_apart: line_x.to_string(),
        rows,
        per_doubling: pm(steep.per_doubling.0, steep.per_doubling.1, 2),
        sharp_time: fixed(steep.sharp_time, 1),
        steepest_time: fixed(steep.steepest_time, 1),
        page_slope: page_slope.to_string(),
        page_slope_time: cases
            .iter()
            .find(|c| c.slope == Some(page_slope))
            .map_or("—".into(), |c| fixed(mean_time(c, |r| r.1).0, 1)),
        slopes: [steep.slopes.0.to_string(), steep.slopes.1.to_string()],
        success: [fixed(steep.success.0, 2), fixed(steep.success.1, 2)],
        to_line: [fixed(steep.to_line.0, 1), fixed(steep.to_line.1, 1)],
        to_criterion: [
            fixed(steep.to_criterion.0, 1),
            fixed(steep.to_criterion.1, 1),
        ],
    };
    Ok((part, [steep, other]))
}

/// Mean periods of the runs that met a time (`pick`), and how many.
fn mean_time(c: &Case, pick: Pick) -> (f64, usize) {
    let v: Vec<f64> = c.runs.iter().filter_map(pick).map(f64::from).collect();
    (stats::mean(&v).unwrap_or(f64::NAN), v.len())
}

fn cells(c: &Case) -> Vec<String> {
    let (crit, met) = mean_time(c, |r| r.0);
    let (near, _) = mean_time(c, |r| r.1);
    vec![
        c.label.clone(),
        c.slope.map_or("∞".into(), |s| s.to_string()),
        fixed(met as f64 / c.runs.len().max(1) as f64, 2),
        fixed(crit, 1),
        fixed(near, 1),
    ]
}

/// Steeper, faster, from the cases' runs (`line_x`: the ramp's success line).
fn steepness(cases: &[Case], line_x: f64) -> Steepness {
    let pts: Vec<(f64, f64)> = cases
        .iter()
        .filter_map(|c| Some((c.slope?.log2(), mean_time(c, |r| r.1).0)))
        .collect();
    let fit = stats::line_fit(&pts);
    let ramps: Vec<&Case> = cases.iter().filter(|c| c.slope.is_some()).collect();
    let ends = |f: &dyn Fn(&Case) -> f64| {
        (
            ramps.first().map_or(f64::NAN, |c| f(c)),
            ramps.last().map_or(f64::NAN, |c| f(c)),
        )
    };
    let success = |c: &Case| {
        c.runs.iter().filter(|r| r.0.is_some()).count() as f64 / c.runs.len().max(1) as f64
    };
    Steepness {
        slopes: ends(&|c| c.slope.unwrap_or(f64::NAN)),
        success: ends(&success),
        to_line: ends(&|c| mean_time(c, |r| r.1).0),
        to_criterion: ends(&|c| mean_time(c, |r| r.0).0),
        per_doubling: fit.map_or((f64::NAN, f64::NAN), |f| (f.slope, f.slope_ci)),
        sharp_time: cases
            .iter()
            .find(|c| c.slope.is_none())
            .map_or(f64::NAN, |c| mean_time(c, |r| r.1).0),
        steepest_time: cases
            .iter()
            .rfind(|c| c.slope.is_some())
            .map_or(f64::NAN, |c| mean_time(c, |r| r.1).0),
        near: NEAR,
        line_x,
    }
}

/// Mean times against the slope (log axis), both ways; the sharp border as a level
/// (`line_x`: the ramp's success line; `start_x`: where the runs start).
fn figure(figs: &Path, cases: &[Case], line_x: f64, start_x: f64) -> Result<(), Error> {
    let ramps: Vec<&Case> = cases.iter().filter(|c| c.slope.is_some()).collect();
    let line = |label: &str, pick: Pick| Line {
        label: label.into(),
        points: ramps
            .iter()
            .filter_map(|c| Some((c.slope?, mean_time(c, pick).0, 0.0)))
            .collect(),
    };
    let sharp = cases
        .iter()
        .find(|c| c.slope.is_none())
        .map_or(f64::NAN, |c| mean_time(c, |r| r.1).0);
    let lines = [
        line(
            &format!("ramp: mean periods to the criterion x ≥ {line_x}"),
            |r| r.0,
        ),
        line(
            &format!("ramp: mean periods to within {NEAR} R of x = 0"),
            |r| r.1,
        ),
        Line {
            label: format!(
                "sharp border: mean periods to within {NEAR} R of x = 0 (its criterion)"
            ),
            points: SLOPES.iter().map(|&s| (s, sharp, 0.0)).collect(),
        },
    ];
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(1.0, f64::max);
    plot::xy_figure(
        &figs.join("settle-steep.svg"),
        &format!(
            "steeper ramps: time from x = {} ({RUNS} runs per slope)",
            start_x.to_string().replace('-', "−")
        ),
        "slope of the ramp / per R",
        "mean periods (runs that got there)",
        &lines,
        (0.0, (top * 1.1).ceil()),
        &[],
        true,
    )?;
    Ok(())
}
