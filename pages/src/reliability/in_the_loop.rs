//! The section of `docs/reliability.md` that sets the campaign with robots in the loop (the
//! Cortex-M build in QEMU, `cimax arena campaign --hil qemu:1`, docs/hil.md) beside the host
//! build's campaign over the same seeds (`in_the_loop` in
//! `templates/reliability/in_the_loop.md.j2`).
//!
//! The runs in the loop come from a committed part (`--hil-part`), so the page regenerates
//! without QEMU; the host build's are the page's own runs of those seeds.

use serde::Serialize;

use super::{decision_time, pct, secs};
use lab::campaign::{Outcome, Report};
use swarm_sim::stats::quantile;

/// The campaign in the loop beside the host build's.
#[derive(Debug, Serialize)]
pub struct LoopSection {
    /// The part the runs in the loop come from, as given (or the parts: `DIR/part-I-of-N.jsonl,
    /// I = 1 to N`).
    pub part: String,
    /// How many parts.
    pub parts: usize,
    /// The command that made the part.
    pub made_by: String,
    /// What was in the loop, as `--hil` says it (`qemu:1`).
    pub spec: String,
    /// True for QEMU robots (the Cortex-M build), false for host twins.
    pub qemu: bool,
    /// The seeds, first and last.
    pub first_seed: u64,
    /// The last seed.
    pub last_seed: u64,
    /// Runs in the loop, all rules and scenarios.
    pub runs: usize,
    /// Of which right.
    pub right: usize,
    /// Runs in the loop whose outcome differs from the host build's run of the same seed
    /// (success, or the LEDs at the end).
    pub differ: usize,
    /// Wall time of the part, s.
    pub wall_s: String,
    /// The decision rules, in the order of each row's cells.
    pub rules: Vec<&'static str>,
    /// Per scenario.
    pub rows: Vec<LoopRow>,
}

/// One scenario: per rule, right in the loop and on the host, and the median time.
#[derive(Debug, Serialize)]
pub struct LoopRow {
    /// Scenario name.
    pub name: &'static str,
    /// Per rule (in [`LoopSection::rules`] order): success in the loop, success on the host build, median time
    /// in the loop, median time on the host build (s; from the reboot for `reboot`).
    pub cells: Vec<[String; 4]>,
}

/// The host build's runs of `host` with the seeds of `in_loop`, in the same order.
fn same_seeds<'a>(host: &'a [Outcome], in_loop: &[Outcome]) -> Vec<&'a Outcome> {
    in_loop
        .iter()
        .filter_map(|l| host.iter().find(|h| h.seed == l.seed))
        .collect()
}

/// Success rate and median decision time of `runs`.
fn summary<'a>(runs: impl IntoIterator<Item = &'a Outcome> + Clone) -> (String, String) {
    let n = runs.clone().into_iter().count().max(1);
    let right = runs.clone().into_iter().filter(|o| o.success).count();
    let t: Vec<f64> = runs.into_iter().filter_map(decision_time).collect();
    (pct(right as f64 / n as f64), secs(quantile(&t, 0.5)))
}

/// Checks that `in_loop` and `host` hold the same decision rules, in the same order.
fn same_rules(in_loop: &[Report], host: &[Report]) -> Result<(), LoopError> {
    if in_loop.len() != host.len()
        || in_loop
            .iter()
            .zip(host)
            .any(|(l, h)| l.plan.decide != h.plan.decide)
    {
        return Err(LoopError::Rules);
    }
    Ok(())
}

/// Why the campaign in the loop cannot stand beside the page's ([`loop_section`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum LoopError {
    /// Other decision rules, or in another order.
    #[error("its decision rules are not the page's")]
    Rules,
    /// No report at all.
    #[error("it holds no rule")]
    NoRule,
    /// A campaign without robots in the loop.
    #[error("it is a campaign without robots in the loop (made without --hil)")]
    NoHil,
    /// Another number of scenarios.
    #[error("its scenarios are not the page's")]
    Scenarios,
    /// Another scenario in one place.
    #[error("its scenario {ours} is the page's {page}")]
    Scenario {
        /// The scenario in the loop.
        ours: &'static str,
        /// The page's scenario in its place.
        page: &'static str,
    },
    /// Seeds in the loop that the page's campaign does not run.
    #[error("{scenario} has seeds the page does not run")]
    Seeds {
        /// The scenario.
        scenario: &'static str,
    },
}

/// The section: `in_loop` (one report per rule, from the `parts` parts named `part`, made by `made_by` in
/// `wall_s` seconds) beside `host` (the page's reports, the same rules and scenarios over at
/// least the same seeds).
///
/// # Errors
/// If the two do not cover the same rules and scenarios, or a seed in the loop is not among
/// the host build's.
pub fn loop_section(
    in_loop: &[Report],
    host: &[Report],
    part: &str,
    parts: usize,
    made_by: String,
    wall_s: f64,
) -> Result<LoopSection, LoopError> {
    same_rules(in_loop, host)?;
    let Some(first) = in_loop.first() else {
        return Err(LoopError::NoRule);
    };
    let hil = first.plan.hil.as_ref().ok_or(LoopError::NoHil)?;
    let (spec, qemu) = (hil.spec(), hil.image.is_some());
    let mut rows: Vec<LoopRow> = Vec::new();
    let (mut runs, mut right, mut differ) = (0, 0, 0);
    for (l, h) in in_loop.iter().zip(host) {
        if l.results.len() != h.results.len() {
            return Err(LoopError::Scenarios);
        }
        for (k, (lr, hr)) in l.results.iter().zip(&h.results).enumerate() {
            if lr.scenario.name != hr.scenario.name {
                return Err(LoopError::Scenario {
                    ours: lr.scenario.name,
                    page: hr.scenario.name,
                });
            }
            let host_runs = same_seeds(&hr.runs, &lr.runs);
            if host_runs.len() != lr.runs.len() {
                return Err(LoopError::Seeds {
                    scenario: lr.scenario.name,
                });
            }
            runs += lr.runs.len();
            right += lr.runs.iter().filter(|o| o.success).count();
            differ += lr
                .runs
                .iter()
                .zip(&host_runs)
                .filter(|(a, b)| a.success != b.success || a.leds != b.leds)
                .count();
            let (ls, lt) = summary(&lr.runs);
            let (hs, ht) = summary(host_runs.iter().copied());
            if rows.len() <= k {
                rows.push(LoopRow {
                    name: lr.scenario.name,
                    cells: Vec::new(),
                });
            }
            rows[k].cells.push([ls, hs, lt, ht]);
        }
    }
    let seeds: Vec<u64> = first
        .results
        .iter()
        .flat_map(|r| r.runs.iter().map(|o| o.seed))
        .collect();
    Ok(LoopSection {
        part: part.to_string(),
        parts,
        made_by,
        spec,
        qemu,
        first_seed: seeds.iter().copied().min().unwrap_or(0),
        last_seed: seeds.iter().copied().max().unwrap_or(0),
        runs,
        right,
        differ,
        wall_s: format!("{wall_s:.0}"),
        rules: in_loop.iter().map(|r| r.plan.decide.name()).collect(),
        rows,
    })
}
