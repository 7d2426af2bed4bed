//! Indecision points against the swarm's size (run by [`reproduce::indecision`]): the share of
//! one-period runs, started centred on the sharp border, whose agents split evenly between left
//! and right, per swarm size and placement.

use std::path::Path;

use serde::Serialize;

use super::write_csv;
use crate::verdict;
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::indecision::{RUNS, SIZES};
use reproduce::results::Results;
use reproduce::units::{Side, Unit, placement};
use swarm_sim::experiment::Error;
use swarm_sim::probe::Split;
use swarm_sim::scenario::Placement;

/// Per placement (main, other), per size of [`SIZES`]: `(agents, tied runs, runs)`.
pub(in super::super) struct Indecision {
    pub(in super::super) by_side: [Vec<(usize, u32, u32)>; 2],
    /// The placements, main first.
    pub(in super::super) placements: [Placement; 2],
}

impl Indecision {
    /// The share of tied runs and its binomial standard error, per size of one placement.
    pub(in super::super) fn shares(&self, side: usize) -> Vec<(f64, f64, f64)> {
        self.by_side[side]
            .iter()
            .map(|&(n, tied, runs)| {
                let p = f64::from(tied) / f64::from(runs.max(1));
                (n as f64, p, verdict::rate_se(p, runs))
            })
            .collect()
    }
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct IndecisionPart {
    runs: u32,
    main: String,
    other: String,
    /// Per size: agents, the main placement's tied runs (share), the other's.
    rows: Vec<[String; 3]>,
}

/// The part from the runs; writes `settle-indecision.{csv,svg}`.
///
/// # Errors
/// If a unit has no result or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    results: &Results,
) -> Result<(IndecisionPart, Indecision), Error> {
    let count = |runs: &[Split]| -> Vec<(usize, u32, u32)> {
        SIZES
            .iter()
            .map(|&n| {
                let of: Vec<&Split> = runs.iter().filter(|s| s.agents == n).collect();
                let tied = of.iter().filter(|s| s.tied()).count() as u32;
                (n, tied, of.len() as u32)
            })
            .collect()
    };
    let facts = Indecision {
        by_side: [
            count(results.indecision(Unit::Indecision(Side::Main))?),
            count(results.indecision(Unit::Indecision(Side::Other))?),
        ],
        placements: Side::BOTH.map(|s| placement(main, s)),
    };
    let cell = |&(_, tied, runs): &(usize, u32, u32)| {
        format!(
            "{tied}/{runs} ({})",
            fixed(f64::from(tied) / f64::from(runs.max(1)), 3)
        )
    };
    let rows: Vec<[String; 3]> = facts.by_side[0]
        .iter()
        .zip(&facts.by_side[1])
        .map(|(a, b)| [a.0.to_string(), cell(a), cell(b)])
        .collect();
    let csv_rows: Vec<Vec<String>> = (0..2)
        .flat_map(|k| {
            let name = facts.placements[k].name();
            facts.by_side[k].iter().map(move |&(n, tied, runs)| {
                vec![
                    name.to_string(),
                    n.to_string(),
                    tied.to_string(),
                    runs.to_string(),
                ]
            })
        })
        .collect();
    write_csv(
        figs,
        "settle-indecision.csv",
        &["placement", "agents", "tied_runs", "runs"],
        &csv_rows,
    )?;
    let lines: Vec<Line> = (0..2)
        .map(|k| Line {
            label: format!("{} placement", facts.placements[k]),
            points: facts.shares(k),
        })
        .collect();
    plot::xy_figure(
        &figs.join("settle-indecision.svg"),
        &format!(
            "sharp border, centred on it: runs whose agents split evenly left and right ({RUNS} one-period runs per point)"
        ),
        "agents in the swarm",
        "share of runs tied",
        &lines,
        (0.0, 1.0),
        &[],
        true,
    )?;
    let part = IndecisionPart {
        runs: RUNS,
        main: facts.placements[0].to_string(),
        other: facts.placements[1].to_string(),
        rows,
    };
    Ok((part, facts))
}
