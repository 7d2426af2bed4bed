//! The starting diversity (ours 0.52 on the sharp border and 0.09 on the gradient, the paper's
//! 0.2 and 0.3) per run, against the agents that stand across x = 0 at the start.

use std::path::Path;

use serde::Serialize;

use super::write_csv;
use crate::claims::{Id, claim};
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::results::Results;
use reproduce::settle::start::{RUNS, XS};
use reproduce::units::{Field, Side, Unit, placement};
use swarm_sim::experiment::Error;
use swarm_sim::probe::StartRun;
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::stats;

/// One column: a field and a placement, and its runs.
struct Column {
    label: String,
    runs: Vec<StartRun>,
}

/// The starting diversity against the agents across, main placement, as the comparison reads
/// it: per field, `(agents across, mean, runs)`.
pub(in super::super) struct StartFacts {
    pub(in super::super) sharp: Vec<(usize, f64, usize)>,
    pub(in super::super) gradient: Vec<(usize, f64, usize)>,
    /// Agents across at the page's start, per field.
    pub(in super::super) at_start: [usize; 2],
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct StartPart {
    runs: u32,
    xs: String,
    columns: Vec<String>,
    /// Per count of agents across: the count, then per column "mean (runs)".
    rows: Vec<Vec<String>>,
    /// Sharp (main placement): mean with no agent across, and the fewest agents across whose
    /// mean exceeds the paper's value.
    sharp_none: String,
    sharp_paper: String,
    /// The starts from which the main placement has one agent across (the lattice's are
    /// fixed).
    sharp_one_starts: String,
    /// How much farther out than the page's start the nearest of those starts lies, R.
    sharp_one_gap: Option<String>,
    /// Gradient (main placement): the same.
    gradient_none: String,
    gradient_paper: String,
    gradient_max: String,
    gradient_exceeds_at: Option<usize>,
    /// Agents across at the page's start (x = −2.5), main placement.
    across_at_start: usize,
    /// Sharp (main placement): the mean with one agent across, and with the start's count.
    sharp_one: String,
    sharp_at_start: String,
    /// Gradient (main placement): the most agents across of any run, and their mean.
    gradient_most: usize,
    gradient_most_mean: String,
}

/// The part from the units [`Unit::Start`], both fields and placements; writes
/// `settle-start.{csv,svg}`.
///
/// # Errors
/// If a unit has no result or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    results: &Results,
) -> Result<(StartPart, StartFacts), Error> {
    let mut cols = Vec::new();
    for (f, scn) in Field::BOTH.into_iter().zip(scns) {
        for side in Side::BOTH {
            cols.push(Column {
                label: format!("{}, {}", scn.name, placement(main, side)),
                runs: results.start(Unit::Start(f, side))?.clone(),
            });
        }
    }
    let most = cols
        .iter()
        .flat_map(|c| c.runs.iter().map(|r| r.across))
        .max()
        .unwrap_or(0);
    let rows = (0..=most)
        .filter(|&n| cols.iter().any(|c| c.runs.iter().any(|r| r.across == n)))
        .map(|n| {
            std::iter::once(n.to_string())
                .chain(cols.iter().map(|c| match mean_at(c, n) {
                    Some((m, k)) => format!("{} ({k})", fixed(m, 2)),
                    None => String::new(),
                }))
                .collect()
        })
        .collect();
    write_files(figs, &cols)?;
    figure(figs, &cols, most)?;
    let by_count = |c: &Column| -> Vec<(usize, f64, usize)> {
        (0..=most)
            .filter_map(|n| mean_at(c, n).map(|(m, k)| (n, m, k)))
            .collect()
    };
    let at = |c: &Column, scn: &Scenario| {
        c.runs
            .iter()
            .find(|r| (r.x - scn.start.x).abs() < 1e-9)
            .map_or(0, |r| r.across)
    };
    let facts = StartFacts {
        sharp: by_count(&cols[0]),
        gradient: by_count(&cols[2]),
        at_start: [at(&cols[0], scns[0]), at(&cols[2], scns[1])],
    };
    Ok((summary(&cols, rows, scns), facts))
}

/// The diversities of a column's runs with `n` agents across.
fn diversities_at(c: &Column, n: usize) -> Vec<f64> {
    c.runs
        .iter()
        .filter(|r| r.across == n)
        .map(|r| r.diversity)
        .collect()
}

/// The mean diversity of a column's runs with `n` agents across, and how many runs.
fn mean_at(c: &Column, n: usize) -> Option<(f64, usize)> {
    let v = diversities_at(c, n);
    Some((stats::mean(&v)?, v.len()))
}

/// The starts of a column from which some run had exactly one agent across.
fn one_starts(c: &Column) -> String {
    XS.iter()
        .filter(|&&x| c.runs.iter().any(|r| r.x == x && r.across == 1))
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The most agents across of any run of a column, and their mean diversity.
fn gradient_most(c: &Column) -> (usize, f64) {
    let n = c.runs.iter().map(|r| r.across).max().unwrap_or(0);
    (n, mean_at(c, n).map_or(f64::NAN, |m| m.0))
}

/// The fewest agents across whose mean diversity is above `level`.
fn exceeds(c: &Column, level: f64, most: usize) -> Option<usize> {
    (0..=most).find(|&n| mean_at(c, n).is_some_and(|(m, _)| m > level))
}

fn summary(cols: &[Column], rows: Vec<Vec<String>>, scns: [&Scenario; 2]) -> StartPart {
    let value = |id| claim(id).values().first().map_or(f64::NAN, |v| v.0);
    let (sharp_paper, gradient_paper) = (value(Id::SharpStart), value(Id::GradientStart));
    let most = cols
        .iter()
        .flat_map(|c| c.runs.iter().map(|r| r.across))
        .max()
        .unwrap_or(0);
    let none = |c: &Column| mean_at(c, 0).map_or("—".into(), |(m, _)| fixed(m, 2));
    let gradient_max = cols[2]
        .runs
        .iter()
        .map(|r| r.diversity)
        .fold(f64::MIN, f64::max);
    let at_start = cols[0]
        .runs
        .iter()
        .find(|r| (r.x - scns[0].start.x).abs() < 1e-9)
        .map_or(0, |r| r.across);
    StartPart {
        runs: RUNS,
        xs: XS.map(|x| x.to_string()).join(", "),
        columns: cols.iter().map(|c| c.label.clone()).collect(),
        rows,
        sharp_none: none(&cols[0]),
        sharp_paper: fixed(sharp_paper, 1),
        sharp_one_starts: one_starts(&cols[0]),
        sharp_one_gap: XS
            .iter()
            .filter(|&&x| cols[0].runs.iter().any(|r| r.x == x && r.across == 1))
            .map(|x| scns[0].start.x - x)
            .filter(|g| *g > 0.0)
            .reduce(f64::min)
            .map(|g| fixed(g, 2)),
        gradient_none: none(&cols[2]),
        gradient_paper: fixed(gradient_paper, 1),
        gradient_max: fixed(gradient_max, 2),
        gradient_exceeds_at: exceeds(&cols[2], gradient_paper, most),
        across_at_start: at_start,
        sharp_one: mean_at(&cols[0], 1).map_or("—".into(), |m| fixed(m.0, 2)),
        sharp_at_start: mean_at(&cols[0], at_start).map_or("—".into(), |m| fixed(m.0, 2)),
        gradient_most: gradient_most(&cols[2]).0,
        gradient_most_mean: fixed(gradient_most(&cols[2]).1, 2),
    }
}

fn write_files(figs: &Path, cols: &[Column]) -> Result<(), Error> {
    let rows: Vec<Vec<String>> = cols
        .iter()
        .flat_map(|c| {
            c.runs.iter().map(|r| {
                vec![
                    c.label.clone(),
                    r.x.to_string(),
                    r.across.to_string(),
                    fixed(r.diversity, 4),
                ]
            })
        })
        .collect();
    write_csv(
        figs,
        "settle-start.csv",
        &["field_placement", "x_init", "agents_across", "diversity"],
        &rows,
    )
}

/// Mean starting diversity against the agents across, one line per field and placement.
fn figure(figs: &Path, cols: &[Column], most: usize) -> Result<(), Error> {
    let lines: Vec<Line> = cols
        .iter()
        .map(|c| Line {
            label: c.label.clone(),
            points: (0..=most)
                .filter_map(|n| {
                    let v = diversities_at(c, n);
                    let m = stats::mean(&v)?;
                    Some((n as f64, m, stats::standard_error(&v).unwrap_or(0.0)))
                })
                .collect(),
        })
        .collect();
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1 + p.2))
        .fold(0.5, f64::max);
    plot::xy_figure(
        &figs.join("settle-start.svg"),
        &format!(
            "the first period's diversity against the agents across x = 0 ({RUNS} runs per start)"
        ),
        "agents at x ≥ 0 at the start",
        "mean over agents of V_k, first period",
        &lines,
        (0.0, (top * 1.1 * 10.0).ceil() / 10.0),
        &[],
        false,
    )?;
    Ok(())
}
