//! The campaign as a job of numbered units, for `--shard I/N` and `cimax merge`.
//!
//! Units, in order: every rule's runs (rule by rule, then scenario by scenario, then seed by
//! seed, as [`campaign::jobs`] lists one rule's); then, when the page is written with both
//! rules, the lab suite's runs (readings by readings of [`SUITE_READINGS`], the fixed rule then
//! the adaptive, experiment by experiment, seed by seed) and the loss sweep's (the fixed rule
//! then the adaptive, loss by loss of [`stress::LOSSES`], seed by seed). The unsharded campaign
//! computes them all; either way [`CampaignJob::assemble`] puts them together.

use hal_emu::Readings;
use host_sim::shard::Timing;
use lab::campaign::{
    self, Decide, InTheLoop, Outcome, Plan, Report, SCENARIOS, SUITE_READINGS, SuiteResult,
};
use lab::stress::{self, LossPoint};
use serde::{Deserialize, Serialize};

/// Everything that makes a campaign's results, resolved: the job in a part's header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CampaignJob {
    /// The scenarios' names, in [`SCENARIOS`] order.
    pub scenarios: Vec<String>,
    /// The first seed.
    pub seed: u64,
    /// Seeds per scenario.
    pub seeds: u64,
    /// Frame loss replacing every scenario's own.
    pub loss: Option<f64>,
    /// The decision rules, in order.
    pub rules: Vec<Decide>,
    /// Whether the page is written (with both rules it runs the lab suite and the loss sweep
    /// too).
    pub page: bool,
    /// Robots in the loop in every run of the campaign (not in the page's lab suite and loss
    /// sweep); absent in the parts of a campaign without.
    #[serde(default)]
    pub hil: Option<InTheLoop>,
}

/// A unit's result.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Unit {
    /// A run of a scenario (the campaign's or the loss sweep's).
    Run(Box<Outcome>),
    /// A run of the lab suite.
    Suite {
        /// Every verdict held.
        success: bool,
        /// Time to consensus, s.
        consensus_s: Option<f64>,
    },
}

/// A campaign's results, as the page and the tables use them.
pub struct Results {
    /// One report per rule.
    pub reports: Vec<Report>,
    /// Per readings of [`SUITE_READINGS`], the lab suite under the fixed rule and the
    /// adaptive (with both rules and the page only).
    pub suites: Vec<(Readings, Vec<SuiteResult>, Vec<SuiteResult>)>,
    /// The loss sweep under the fixed rule and the adaptive, and its seeds per loss (with both
    /// rules and the page only).
    pub loss: Option<(Vec<LossPoint>, Vec<LossPoint>, u64)>,
}

impl CampaignJob {
    /// Whether the page's own experiments (lab suite, loss sweep) are run.
    fn extras(&self) -> bool {
        self.page && self.rules == [Decide::Fixed, Decide::Adaptive]
    }

    /// Seeds per loss of the loss sweep.
    fn sweep_seeds(&self) -> u64 {
        self.seeds.min(stress::SWEEP_SEEDS)
    }

    /// Units of each kind: the campaign's runs, the lab suite's, the loss sweep's.
    fn counts(&self) -> (u64, u64, u64) {
        let runs = self.rules.len() as u64 * self.scenarios.len() as u64 * self.seeds;
        if !self.extras() {
            return (runs, 0, 0);
        }
        let experiments = hal_emu::judge::paper_suite().len() as u64;
        let suite = SUITE_READINGS.len() as u64 * 2 * experiments * self.seeds;
        let loss = 2 * stress::LOSSES.len() as u64 * self.sweep_seeds();
        (runs, suite, loss)
    }

    /// Units of the job.
    pub fn units(&self) -> u64 {
        let (a, b, c) = self.counts();
        a + b + c
    }

    /// One plan per rule, checked.
    ///
    /// # Errors
    /// A scenario that does not exist, or an unusable option.
    pub fn plans(&self) -> Result<Vec<Plan>, String> {
        let scenarios = self
            .scenarios
            .iter()
            .map(|n| {
                SCENARIOS
                    .iter()
                    .position(|s| s.name == n)
                    .ok_or_else(|| format!("there is no scenario {n:?}"))
            })
            .collect::<Result<Vec<usize>, String>>()?;
        self.rules
            .iter()
            .map(|&decide| {
                let plan = Plan {
                    scenarios: scenarios.clone(),
                    seed: self.seed,
                    seeds: self.seeds,
                    loss: self.loss,
                    decide,
                    hil: self.hil.clone(),
                };
                campaign::check(&plan)
                    .map(|()| plan)
                    .map_err(|e| e.to_string())
            })
            .collect()
    }

    /// Unit `k`, with `plans` the job's ([`CampaignJob::plans`]).
    ///
    /// # Errors
    /// If the run cannot start.
    pub fn unit(&self, plans: &[Plan], k: u64) -> Result<Unit, String> {
        let (runs, suite, _) = self.counts();
        let seeds = self.seeds.max(1);
        let seed = |i: u64, n: u64| self.seed.wrapping_add(i % n);
        let rule = |i: u64| {
            if i == 0 {
                Decide::Fixed
            } else {
                Decide::Adaptive
            }
        };
        if k < runs {
            let per_rule = (self.scenarios.len() as u64 * seeds).max(1);
            let plan = &plans[(k / per_rule) as usize];
            let s = plan.scenarios[((k % per_rule) / seeds) as usize];
            let hil = plan.hil.as_ref();
            return campaign::run_in_loop(
                &SCENARIOS[s],
                seed(k, seeds),
                plan.loss,
                plan.decide,
                hil,
            )
            .map(|o| Unit::Run(Box::new(o)))
            .map_err(|e| e.to_string());
        }
        if k < runs + suite {
            let k = k - runs;
            let experiments = hal_emu::judge::paper_suite().len() as u64;
            let per_rule = experiments * seeds;
            let readings = SUITE_READINGS[(k / (2 * per_rule)) as usize];
            let (e, s) = ((k / seeds) % experiments, seed(k, seeds));
            return campaign::suite_run(rule((k / per_rule) % 2), readings, e as usize, s)
                .map(|(success, consensus_s)| Unit::Suite {
                    success,
                    consensus_s,
                })
                .map_err(|e| e.to_string());
        }
        let k = k - runs - suite;
        let n = self.sweep_seeds().max(1);
        let per_rule = stress::LOSSES.len() as u64 * n;
        let loss = ((k / n) % stress::LOSSES.len() as u64) as usize;
        stress::loss_run(rule(k / per_rule), loss, seed(k, n))
            .map(|o| Unit::Run(Box::new(o)))
            .map_err(|e| e.to_string())
    }

    /// The results from every unit's, in unit order; `timing` is the reports'.
    ///
    /// # Errors
    /// If the units are not this job's (their number or kinds).
    pub fn assemble(
        &self,
        plans: &[Plan],
        units: Vec<Unit>,
        timing: Timing,
    ) -> Result<Results, String> {
        if units.len() as u64 != self.units() {
            return Err(format!(
                "{} units, but the campaign has {}",
                units.len(),
                self.units()
            ));
        }
        let mut take = Take(units.into_iter().enumerate());
        let per_rule = (self.scenarios.len() as u64 * self.seeds) as usize;
        let reports = plans
            .iter()
            .map(|plan| {
                let runs = take.runs(per_rule)?;
                Ok(campaign::report(plan, runs, timing.wall_s, timing.threads))
            })
            .collect::<Result<Vec<_>, String>>()?;
        let mut results = Results {
            reports,
            suites: Vec::new(),
            loss: None,
        };
        if self.extras() {
            let n = hal_emu::judge::paper_suite().len() * self.seeds as usize;
            for readings in SUITE_READINGS {
                let fixed = campaign::suite_results(take.suite(n)?, self.seeds);
                let adaptive = campaign::suite_results(take.suite(n)?, self.seeds);
                results.suites.push((readings, fixed, adaptive));
            }
            let (ss, n) = (
                self.sweep_seeds(),
                stress::LOSSES.len() * self.sweep_seeds() as usize,
            );
            let fixed = stress::loss_points(take.runs(n)?, ss);
            let adaptive = stress::loss_points(take.runs(n)?, ss);
            results.loss = Some((fixed, adaptive, ss));
        }
        Ok(results)
    }
}

/// Units taken in order, each checked to be of the kind that belongs there.
struct Take(std::iter::Enumerate<std::vec::IntoIter<Unit>>);

impl Take {
    /// The next `n` units, runs of a scenario.
    fn runs(&mut self, n: usize) -> Result<Vec<Outcome>, String> {
        self.0
            .by_ref()
            .take(n)
            .map(|(k, u)| match u {
                Unit::Run(o) => Ok(*o),
                Unit::Suite { .. } => Err(format!("unit {k}: a lab suite run, not a scenario's")),
            })
            .collect()
    }

    /// The next `n` units, runs of the lab suite.
    fn suite(&mut self, n: usize) -> Result<Vec<(bool, Option<f64>)>, String> {
        self.0
            .by_ref()
            .take(n)
            .map(|(k, u)| match u {
                Unit::Suite {
                    success,
                    consensus_s,
                } => Ok((success, consensus_s)),
                Unit::Run(_) => Err(format!("unit {k}: a scenario's run, not the lab suite's")),
            })
            .collect()
    }
}
