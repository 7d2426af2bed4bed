//! The gradient's arrival (ours 23 periods, the paper's one run 15): the spread of the arrival
//! times, and where the time goes: the first move's heading toward +x from every 0.25 R of the
//! way, the periods a drift at that heading would take per 0.25 R, and the periods the runs
//! spent there.

use std::path::Path;

use serde::Serialize;

use super::{pm, write_csv};
use crate::claims::{Id, claim};
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::results::Way;
use reproduce::settle::arrival::{RUNS, STEP, success_x};
use swarm_sim::experiment::Error;
use swarm_sim::scenario::Scenario;
use swarm_sim::stats;

/// Below this mean heading a drift is too slow to predict a time from.
const MIN_HEADING: f64 = 0.05;

/// One field's profile.
struct Profile {
    /// `(x, mean cos, s.e.)` per point.
    heading: Vec<(f64, f64, f64)>,
    /// `(bin's centre, mean periods there)` per point.
    spent: Vec<(f64, f64)>,
    /// Arrival periods of the runs that arrived.
    arrivals: Vec<f64>,
}

/// The gradient's way to its line, as the comparison reads it.
pub(in super::super) struct ArrivalFacts {
    /// Runs that arrived, and those within the paper's periods.
    pub(in super::super) arrived: usize,
    pub(in super::super) within_paper: usize,
    /// The fastest run's periods.
    pub(in super::super) fastest: f64,
    /// Mean periods per run spent before the ramp (x < 0) and on it.
    pub(in super::super) before_ramp: f64,
    pub(in super::super) on_ramp: f64,
    /// Mean periods per run spent in the last R before the line, and the heading half-way
    /// through it.
    pub(in super::super) last_r: f64,
    pub(in super::super) heading_mid_last_r: f64,
}

/// The quantiles of the arrival's spread.
const QUANTILES: [f64; 3] = [0.1, 0.5, 0.9];

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct ArrivalPart {
    /// [`QUANTILES`] in %, "10 / 50 / 90".
    quantiles: String,
    runs: u32,
    course_runs: u32,
    step: String,
    /// Per field: name, arrived, mean ± s.e., 10/50/90 % quantiles, min, max, predicted sum.
    spread: Vec<Vec<String>>,
    /// Gradient: x, heading, predicted periods, spent periods.
    rows: Vec<Vec<String>>,
    paper: String,
    /// Fraction of the gradient's runs that arrived within the paper's periods.
    within_paper: String,
    predicted: String,
    observed: String,
    /// Where the gradient's runs spend most periods, and how many.
    slowest_x: String,
    slowest_periods: String,
    /// The heading there.
    slowest_heading: String,
    /// Periods spent beyond x = 0 (on the ramp) against before it.
    on_ramp: String,
    before_ramp: String,
    /// The sharp border's drift sum and mean arrival.
    sharp_predicted: String,
    sharp_observed: String,
    /// The fastest gradient run, the periods in the last R before the line and the heading
    /// half-way through it, the line, and the paper's run's speed (R per period) against
    /// the step.
    fastest: String,
    last_r: String,
    heading_mid: String,
    line: String,
    paper_speed: String,
    step_r: String,
}

/// The part from both fields' headings and the ways of their courses' runs; writes
/// `settle-arrival.csv` and its two figures.
///
/// # Errors
/// If a file cannot be written.
pub(super) fn write(
    figs: &Path,
    scns: [&Scenario; 2],
    headings: [&Vec<(f64, f64, f64)>; 2],
    ways: [&Way; 2],
) -> Result<(ArrivalPart, ArrivalFacts), Error> {
    let profiles: Vec<Profile> = headings
        .into_iter()
        .zip(ways)
        .map(|(h, w)| Profile {
            heading: h.clone(),
            spent: w.spent.clone(),
            arrivals: w.arrivals.clone(),
        })
        .collect();
    figure(figs, scns, &profiles)?;
    let rows = rows(&profiles[1], scns[1].run.step);
    let mut csv_rows = Vec::new();
    for (scn, p) in scns.iter().zip(&profiles) {
        for r in self::rows(p, scn.run.step) {
            csv_rows.push(std::iter::once(scn.name.clone()).chain(r).collect());
        }
    }
    write_csv(
        figs,
        "settle-arrival.csv",
        &["field", "x", "heading", "drift_periods", "spent_periods"],
        &csv_rows,
    )?;
    let facts = facts(scns[1], &profiles[1]);
    let mut part = summary(scns, &profiles, rows);
    let line = scns[1]
        .success
        .as_ref()
        .map_or(f64::NAN, |s| success_x(s, scns[1].start.x));
    let paper: f64 = part.paper.parse().unwrap_or(f64::NAN);
    let sharp = &profiles[0];
    part.sharp_predicted = fixed(
        sharp
            .heading
            .iter()
            .map(|h| drift(h.1, scns[0].run.step).unwrap_or(f64::INFINITY))
            .sum(),
        1,
    );
    part.sharp_observed = fixed(stats::mean(&sharp.arrivals).unwrap_or(f64::NAN), 1);
    part.fastest = fixed(facts.fastest, 0);
    part.last_r = fixed(facts.last_r, 1);
    part.heading_mid = fixed(facts.heading_mid_last_r, 2);
    part.line = line.to_string();
    part.paper_speed = fixed((line - scns[1].start.x) / paper, 2);
    part.step_r = scns[1].run.step.to_string();
    Ok((part, facts))
}

fn facts(scn: &Scenario, g: &Profile) -> ArrivalFacts {
    let paper = claim(Id::GradientArrival)
        .values()
        .first()
        .map_or(f64::NAN, |v| v.0);
    let line = scn
        .success
        .as_ref()
        .map_or(f64::NAN, |s| success_x(s, scn.start.x));
    let spent = |keep: &dyn Fn(f64) -> bool| -> f64 {
        g.spent.iter().filter(|s| keep(s.0)).map(|s| s.1).sum()
    };
    let mid = line - 0.5;
    ArrivalFacts {
        arrived: g.arrivals.len(),
        within_paper: g.arrivals.iter().filter(|&&a| a <= paper).count(),
        fastest: g.arrivals.iter().copied().fold(f64::INFINITY, f64::min),
        before_ramp: spent(&|x| x < 0.0),
        on_ramp: spent(&|x| x >= 0.0),
        last_r: spent(&|x| x >= line - 1.0),
        heading_mid_last_r: g
            .heading
            .iter()
            .min_by(|a, b| (a.0 - mid).abs().total_cmp(&(b.0 - mid).abs()))
            .map_or(f64::NAN, |h| h.1),
    }
}

/// Periods a drift at mean heading `cos` takes for one step (none if too slow).
fn drift(cos: f64, step: f64) -> Option<f64> {
    (cos > MIN_HEADING).then(|| STEP / (step * cos))
}

/// The table's rows: `step` is the scenario's move per period.
fn rows(p: &Profile, step: f64) -> Vec<Vec<String>> {
    p.heading
        .iter()
        .zip(&p.spent)
        .map(|(&(x, m, se), &(_, spent))| {
            vec![
                fixed(x, 2),
                pm(m, se, 2),
                drift(m, step).map_or("—".into(), |d| fixed(d, 1)),
                fixed(spent, 1),
            ]
        })
        .collect()
}

fn summary(scns: [&Scenario; 2], profiles: &[Profile], rows: Vec<Vec<String>>) -> ArrivalPart {
    let paper = claim(Id::GradientArrival)
        .values()
        .first()
        .map_or(f64::NAN, |v| v.0);
    let spread = scns
        .iter()
        .zip(profiles)
        .map(|(scn, p)| {
            let a = &p.arrivals;
            let q = |f| stats::quantile(a, f).map_or("—".into(), |v| fixed(v, 0));
            let predicted: f64 = p
                .heading
                .iter()
                .map(|h| drift(h.1, scn.run.step).unwrap_or(f64::INFINITY))
                .sum();
            vec![
                scn.name.clone(),
                a.len().to_string(),
                pm(
                    stats::mean(a).unwrap_or(f64::NAN),
                    stats::standard_error(a).unwrap_or(0.0),
                    1,
                ),
                QUANTILES.map(q).join(" / "),
                format!("{} – {}", q(0.0), q(1.0)),
                if predicted.is_finite() {
                    fixed(predicted, 1)
                } else {
                    "— (a point without heading)".into()
                },
            ]
        })
        .collect();
    let g = &profiles[1];
    let within = g.arrivals.iter().filter(|&&a| a <= paper).count();
    let slowest = g
        .spent
        .iter()
        .zip(&g.heading)
        .max_by(|a, b| a.0.1.total_cmp(&b.0.1));
    let on_ramp: f64 = g.spent.iter().filter(|s| s.0 >= 0.0).map(|s| s.1).sum();
    let before: f64 = g.spent.iter().filter(|s| s.0 < 0.0).map(|s| s.1).sum();
    let predicted: f64 = g
        .heading
        .iter()
        .map(|h| drift(h.1, scns[1].run.step).unwrap_or(f64::INFINITY))
        .sum();
    ArrivalPart {
        quantiles: QUANTILES.map(|q| (100.0 * q).to_string()).join(" / "),
        runs: RUNS,
        course_runs: super::super::COURSE_RUNS,
        step: fixed(STEP, 2),
        spread,
        rows,
        paper: fixed(paper, 0),
        within_paper: format!("{} of {}", within, g.arrivals.len()),
        predicted: fixed(predicted, 1),
        observed: fixed(stats::mean(&g.arrivals).unwrap_or(f64::NAN), 1),
        slowest_x: slowest.map_or("—".into(), |s| fixed(s.0.0, 2)),
        slowest_periods: slowest.map_or("—".into(), |s| fixed(s.0.1, 1)),
        slowest_heading: slowest.map_or("—".into(), |s| fixed(s.1.1, 2)),
        on_ramp: fixed(on_ramp, 1),
        before_ramp: fixed(before, 1),
        sharp_predicted: String::new(),
        sharp_observed: String::new(),
        fastest: String::new(),
        last_r: String::new(),
        heading_mid: String::new(),
        line: String::new(),
        paper_speed: String::new(),
        step_r: String::new(),
    }
}

/// Heading and periods against x, both fields.
fn figure(figs: &Path, scns: [&Scenario; 2], profiles: &[Profile]) -> Result<(), Error> {
    let mut heading = Vec::new();
    let mut periods = Vec::new();
    for (scn, p) in scns.iter().zip(profiles) {
        heading.push(Line {
            label: format!("{}: first move's heading toward +x (mean cos)", scn.name),
            points: p.heading.clone(),
        });
        periods.push(Line {
            label: format!(
                "{}: periods spent per {STEP} R before arriving (mean of the runs)",
                scn.name
            ),
            points: p.spent.iter().map(|&(x, s)| (x, s, 0.0)).collect(),
        });
    }
    plot::xy_figure(
        &figs.join("settle-arrival-heading.svg"),
        &format!("the way to the border: heading ({RUNS} one-period runs per point)"),
        "x of the swarm's centre / R",
        "mean cos(decided direction)",
        &heading,
        (-0.2, 1.05),
        &[(0.0, "x = 0: the border, the ramp's start")],
        false,
    )?;
    let top = profiles
        .iter()
        .flat_map(|p| p.spent.iter().map(|s| s.1))
        .fold(1.0, f64::max);
    plot::xy_figure(
        &figs.join("settle-arrival-periods.svg"),
        "the way to the border: where the periods go (the averaged courses' runs)",
        "x of the swarm's centre at the period's start / R",
        &format!("periods per {STEP} R"),
        &periods,
        (0.0, (top * 1.1).ceil()),
        &[(0.0, "x = 0: the border, the ramp's start")],
        false,
    )?;
    Ok(())
}
