//! The sharp plateau (ours 5.1, the paper's 4.5) against the cycle length, the placement and
//! the way diversity is taken: the page's mean over agents of `V_k` (the paper's definition),
//! the mean variance per scored message, and the variance of all scored readings pooled.

use std::path::Path;

use serde::Serialize;

use super::{pm, write_csv};
use crate::claims::{Id, claim};
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::results::{CourseDigest, Results};
use reproduce::settle::plateau::{CYCLES, RUNS, default_cycle};
use reproduce::units::{Side, Unit, placement};
use swarm_sim::experiment::Error;
use swarm_sim::probe::Plateaus;
use swarm_sim::scenario::{Placement, Scenario};

/// One row: a field, placement and cycle, and its three plateaus.
struct Row {
    field: String,
    placement: Placement,
    cycle_s: u64,
    p: Plateaus,
}

/// The sharp plateau of the page's measure at every cycle and placement, and the other two
/// measures on the courses' runs, as the comparison reads them.
pub(in super::super) struct PlateauFacts {
    /// `(cycle s, placement, mean, s.e.)` of the mean over agents of `V_k`.
    pub(in super::super) by_cycle: Vec<(u64, Placement, f64, f64)>,
    /// The mean variance per message and the pooled variance on the courses' runs.
    pub(in super::super) message: f64,
    pub(in super::super) pooled: f64,
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct PlateauPart {
    runs: u32,
    course_runs: u32,
    paper: String,
    rows: Vec<Vec<String>>,
    /// The page's measure on the courses' runs (the comparison's value).
    agents_main: String,
    message_main: String,
    pooled_main: String,
    /// The range of the page's measure over every cycle and placement (sharp).
    agents_range: String,
    /// The measure nearest the paper's value on the courses' runs, and its value.
    nearest: &'static str,
    nearest_value: String,
    /// Whether any cycle or placement brings the page's measure within the claim's band.
    agents_reach: bool,
    /// The band the comparison uses.
    band: String,
    /// The cycles and placements that bring the page's measure within it.
    fits: String,
    /// The cycles tried.
    cycles: String,
}

/// The part from the plateau units' results and the courses' tapped runs (`courses`, per
/// field), which stand for the page's own cycle and give the gradient's row; writes
/// `settle-plateau.{csv,svg}`.
///
/// # Errors
/// If a unit has no result or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    results: &Results,
    courses: [&CourseDigest; 2],
) -> Result<(PlateauPart, PlateauFacts), Error> {
    let sharp = scns[0];
    let default_cycle = default_cycle(sharp);
    let mut rows = Vec::new();
    for side in Side::BOTH {
        let placement = placement(main, side);
        for (k, &cycle_s) in CYCLES.iter().enumerate() {
            let p = match results.plateau(Unit::Plateau(side, k as u8))? {
                Some(p) => *p,
                None => courses[0].plateaus,
            };
            rows.push(Row {
                field: sharp.name.clone(),
                placement,
                cycle_s,
                p,
            });
        }
    }
    let gradient = Row {
        field: scns[1].name.clone(),
        placement: main,
        cycle_s: scns[1].run.params.wave.cycle.as_millis() / 1000,
        p: courses[1].plateaus,
    };
    figure(figs, &rows, main)?;
    rows.push(gradient);
    let table: Vec<Vec<String>> = rows.iter().map(cells).collect();
    write_csv(
        figs,
        "settle-plateau.csv",
        &[
            "field",
            "placement",
            "cycle_s",
            "runs",
            "agents_mean",
            "agents_se",
            "message_mean",
            "message_se",
            "pooled_mean",
            "pooled_se",
        ],
        &rows.iter().map(csv_cells).collect::<Vec<_>>(),
    )?;
    let main_row = rows
        .iter()
        .find(|r| r.placement == main && r.cycle_s == default_cycle)
        .ok_or(super::super::WriteError::NoOwnCycle)?;
    let facts = PlateauFacts {
        by_cycle: rows
            .iter()
            .filter(|r| r.field == sharp.name)
            .map(|r| (r.cycle_s, r.placement, r.p.agents.mean, r.p.agents.se))
            .collect(),
        message: main_row.p.message.mean,
        pooled: main_row.p.pooled.mean,
    };
    Ok((summary(&rows, main_row, table), facts))
}

/// The part's facts from its rows.
fn summary(rows: &[Row], main: &Row, table: Vec<Vec<String>>) -> PlateauPart {
    let c = claim(Id::SharpPlateau);
    let paper = c.values().first().map_or(f64::NAN, |v| v.0);
    let (lo, hi) = (paper * (1.0 - c.tolerance()), paper * (1.0 + c.tolerance()));
    let sharp: Vec<&Row> = rows.iter().filter(|r| r.field == main.field).collect();
    let agents = sharp.iter().map(|r| r.p.agents.mean);
    let a_lo = agents.clone().fold(f64::MAX, f64::min);
    let a_hi = agents.clone().fold(f64::MIN, f64::max);
    let m = &main.p;
    let nearest = [
        ("the mean over agents of V_k", m.agents.mean),
        ("the mean variance per message", m.message.mean),
        ("the pooled variance", m.pooled.mean),
    ]
    .into_iter()
    .min_by(|a, b| (a.1 - paper).abs().total_cmp(&(b.1 - paper).abs()))
    .unwrap_or(("", f64::NAN));
    PlateauPart {
        runs: RUNS,
        course_runs: super::super::COURSE_RUNS,
        paper: fixed(paper, 1),
        rows: table,
        agents_main: pm(m.agents.mean, m.agents.se, 2),
        message_main: pm(m.message.mean, m.message.se, 2),
        pooled_main: pm(m.pooled.mean, m.pooled.se, 2),
        agents_range: format!("{}–{}", fixed(a_lo, 2), fixed(a_hi, 2)),
        nearest: nearest.0,
        nearest_value: fixed(nearest.1, 2),
        agents_reach: agents.clone().any(|a| (lo..=hi).contains(&a)),
        band: format!("{}–{}", fixed(lo, 2), fixed(hi, 2)),
        fits: sharp
            .iter()
            .filter(|r| (lo..=hi).contains(&r.p.agents.mean))
            .map(|r| {
                format!(
                    "{} s ({}, {})",
                    r.cycle_s,
                    r.placement,
                    fixed(r.p.agents.mean, 2)
                )
            })
            .collect::<Vec<_>>()
            .join(", "),
        cycles: CYCLES.map(|c| c.to_string()).join(", "),
    }
}

fn cells(r: &Row) -> Vec<String> {
    vec![
        r.field.clone(),
        r.placement.to_string(),
        r.cycle_s.to_string(),
        r.p.runs.to_string(),
        pm(r.p.agents.mean, r.p.agents.se, 2),
        pm(r.p.message.mean, r.p.message.se, 2),
        pm(r.p.pooled.mean, r.p.pooled.se, 2),
    ]
}

fn csv_cells(r: &Row) -> Vec<String> {
    let s = |v: f64| fixed(v, 4);
    vec![
        r.field.clone(),
        r.placement.to_string(),
        r.cycle_s.to_string(),
        r.p.runs.to_string(),
        s(r.p.agents.mean),
        s(r.p.agents.se),
        s(r.p.message.mean),
        s(r.p.message.se),
        s(r.p.pooled.mean),
        s(r.p.pooled.se),
    ]
}

/// The sharp plateau against the cycle: the three measures with the main placement, the page's
/// measure with the other, and the paper's value.
fn figure(figs: &Path, rows: &[Row], main: Placement) -> Result<(), Error> {
    let line = |label: String, placement: Placement, pick: fn(&Plateaus) -> (f64, f64)| Line {
        label,
        points: rows
            .iter()
            .filter(|r| r.placement == placement)
            .map(|r| {
                let (m, se) = pick(&r.p);
                (r.cycle_s as f64, m, se)
            })
            .collect(),
    };
    let paper = claim(Id::SharpPlateau)
        .values()
        .first()
        .map_or(0.0, |v| v.0);
    let other = main.other();
    let lines = [
        line(
            format!("mean over agents of V_k, {main} (the page's)"),
            main,
            |p| (p.agents.mean, p.agents.se),
        ),
        line(format!("mean over agents of V_k, {other}"), other, |p| {
            (p.agents.mean, p.agents.se)
        }),
        line(format!("mean variance per message, {main}"), main, |p| {
            (p.message.mean, p.message.se)
        }),
        line(format!("pooled variance, {main}"), main, |p| {
            (p.pooled.mean, p.pooled.se)
        }),
        Line {
            label: format!(
                "paper: plateau ≈ {paper} ({}b)",
                crate::paper::Fig::SharpRun
            ),
            points: CYCLES.iter().map(|&c| (c as f64, paper, 0.0)).collect(),
        },
    ];
    plot::xy_figure(
        &figs.join("settle-plateau.svg"),
        "sharp border: the diversity plateau, three ways, against the cycle",
        "cycle length t_p^max / s",
        "diversity at the plateau",
        &lines,
        (0.0, 7.0),
        &[],
        true,
    )?;
    Ok(())
}
