//! The fault campaign (`cimax arena campaign`): the lab experiment under faults, over many
//! seeds, against bars.
//!
//! Every [`SCENARIOS`] entry is run once per seed ([`SEEDS`] by default) in the emulated arena
//! (`hal-emu`), each run judged exactly as `cimax arena` judges one
//! ([`hal_emu::judge::judge`]: the top-cap LEDs at the end against the expected verdict). Seed
//! `s` uses the paper's pattern `PAPER_PATTERNS[s mod 6]`, so every six consecutive seeds
//! cover the six patterns, and the run's seed is `s` itself: one seed replays one run
//! (`cimax arena campaign --scenario NAME --seed S --seeds 1`). Runs are spread over threads
//! with rayon; each is independent and seeded, so the report does not depend on the number
//! of threads.
//!
//! [`run`] returns a [`Report`]; the page made of it (`pages::reliability`) gives per scenario
//! the success rate, time to consensus (median and 95th percentile), frames per run dropped by
//! reason, the bar with PASS or FAIL, and the failing seeds with the command that replays each,
//! and `pages::figures` draws the success rates against the bars as SVG. The scenarios and how
//! each injects its fault are `scenarios.rs`; this file runs them.

mod error;
mod scenarios;
mod stats_serde;
mod suite_file;

use std::fmt::Write as _;

use hal_emu::judge::{judge, leds_str, pattern_str};
use hal_emu::world::arena::RobotFailure;
use hal_emu::{ArenaConfig, ArenaError, MediumStats, Readings};
use protocol::params::DecisionRule;
use protocol::wave::WaveStats;
use protocol::{Duration, Instant, Params};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use swarm_sim::progress::Progress;

pub use super::InTheLoop;
pub use error::CampaignError;

pub use scenarios::{
    ADVERSARY_AT, Fault, REBOOT_DOWN, SCENARIOS, Scenario, config, hil_places, pattern_for,
};
pub use suite_file::{ExperimentCount, SuiteCounts, SuiteFile};

/// `--decide`: the protocol's [`DecisionRule`] on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Decide {
    /// At the end of every negotiation period (the paper's robots).
    #[default]
    Fixed,
    /// When the evidence settles; the negotiation period is the cap.
    Adaptive,
}

impl Decide {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Decide::Fixed => "fixed",
            Decide::Adaptive => "adaptive",
        }
    }
}

impl From<Decide> for DecisionRule {
    fn from(d: Decide) -> Self {
        match d {
            Decide::Fixed => DecisionRule::Fixed,
            Decide::Adaptive => DecisionRule::Adaptive,
        }
    }
}

/// One run of a scenario, judged. Serialised whole (a part file of `cimax arena campaign
/// --shard`), floats bit for bit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Outcome {
    /// The seed that replays it.
    pub seed: u64,
    /// The light pattern.
    pub pattern: String,
    /// The LEDs expected at the end (`-` for a robot that is dead).
    pub expected: String,
    /// The LEDs at the end.
    pub leds: String,
    /// Whether every verdict of the run held.
    pub success: bool,
    /// Why not, if it failed.
    pub why: Option<String>,
    /// A robot stopped on its own (its task panicked, or it could not boot): the run failed
    /// with no LEDs to judge (`leds` is all `?`, the counters are zero). A bug, never a
    /// statistic: the campaign exits 1 whatever its bars.
    pub crashed: bool,
    /// Seconds from the start until the LEDs reached the state they kept to the end.
    pub consensus_s: Option<f64>,
    /// Reboot only: seconds from the reboot until consensus was back for good.
    pub restore_s: Option<f64>,
    /// The medium's counters.
    #[serde(with = "stats_serde::MediumStatsDef")]
    pub medium: MediumStats,
    /// Frames the robots' deframers rejected (CRC, stuffing, length), all robots.
    pub frame_errors: u64,
    /// Each robot's wave counters at the end (of its last life; empty if the run crashed).
    #[serde(with = "stats_serde::waves")]
    pub waves: Vec<WaveStats>,
    /// Each robot's protocol counters at the end (of its last life; empty if the run crashed):
    /// negotiation periods, and those with fewer initiations than cycles.
    #[serde(with = "stats_serde::nodes")]
    pub nodes: Vec<protocol::fused::NodeStats>,
    /// The run's emulated length, s.
    pub duration_s: f64,
}

/// What a campaign covers.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Indices into [`SCENARIOS`].
    pub scenarios: Vec<usize>,
    /// First seed.
    pub seed: u64,
    /// Seeds per scenario.
    pub seeds: u64,
    /// Frame loss replacing every scenario's own.
    pub loss: Option<f64>,
    /// The robots' decision rule.
    pub decide: Decide,
    /// Robots in the loop in every run (the Cortex-M build on the arena's clock), if any.
    pub hil: Option<InTheLoop>,
}

/// One scenario's runs and what they add up to.
#[derive(Clone, Debug)]
pub struct ScenarioResult {
    /// The scenario.
    pub scenario: Scenario,
    /// Its runs, in seed order.
    pub runs: Vec<Outcome>,
}

impl ScenarioResult {
    /// Successful runs.
    pub fn successes(&self) -> usize {
        self.runs.iter().filter(|r| r.success).count()
    }

    /// The success rate, 0 to 1.
    pub fn rate(&self) -> f64 {
        self.successes() as f64 / self.runs.len().max(1) as f64
    }

    /// `Some(true)` if the bar is met, `Some(false)` if missed, `None` without a bar.
    pub fn passed(&self) -> Option<bool> {
        self.scenario.bar.map(|b| self.rate() >= b)
    }

    /// The failed runs.
    pub fn failures(&self) -> impl Iterator<Item = &Outcome> {
        self.runs.iter().filter(|r| !r.success)
    }
}

/// A whole campaign.
#[derive(Clone, Debug)]
pub struct Report {
    /// What was run.
    pub plan: Plan,
    /// Per scenario, in plan order.
    pub results: Vec<ScenarioResult>,
    /// Wall time, seconds.
    pub wall_s: f64,
    /// Worker threads.
    pub threads: usize,
}

impl Report {
    /// The scenarios whose bar was missed.
    pub fn missed(&self) -> Vec<&ScenarioResult> {
        self.results
            .iter()
            .filter(|r| r.passed() == Some(false))
            .collect()
    }
}

/// The failed outcome of a run of `cfg` in which a robot stopped on its own.
pub fn crashed(cfg: &ArenaConfig, failure: &RobotFailure) -> Outcome {
    let (lights, expected) = hal_emu::judge::crash_verdict(cfg);
    Outcome {
        seed: cfg.seed,
        pattern: pattern_str(&lights),
        expected: expected.as_deref().map(leds_str).unwrap_or_default(),
        leds: "?".repeat(lights.len()),
        success: false,
        why: Some(failure.what()),
        crashed: true,
        consensus_s: None,
        restore_s: None,
        medium: MediumStats::default(),
        frame_errors: 0,
        waves: Vec::new(),
        nodes: Vec::new(),
        duration_s: cfg.duration.as_secs_f64(),
    }
}

/// Judges a run of `scenario` (with `cimax arena`'s [`judge`]) and, for a reboot, also checks
/// that consensus held just before it and was back within two nominal negotiation periods. A
/// run in which a robot panicked is a failed outcome ([`Outcome::crashed`]).
fn outcome(cfg: &ArenaConfig, reboot: Option<Instant>) -> Result<Outcome, CampaignError> {
    let run = match judge(cfg) {
        Ok(run) => run,
        Err(ArenaError::Robot(f)) => return Ok(crashed(cfg, &f)),
        Err(e) => return Err(e.into()),
    };
    let expected = run.expected.clone();
    let mut success = run.success;
    let mut why = (!success).then(|| match run.flicker {
        Some((t, r)) => format!("robot {r}'s LEDs changed at {t:.0} s, after it showed its side"),
        None => "wrong LEDs at the end".to_string(),
    });
    let mut restore_s = None;
    if let (Some(t), Some(e)) = (reboot, &expected) {
        let before = run.report.leds_at(t - Duration::from_millis(1));
        let limit = cfg.robot.params.nominal_period().saturating_mul(2);
        restore_s = run
            .consensus_s
            .map(|c| c - t.saturating_since(Instant::ZERO).as_secs_f64());
        if before != *e {
            success = false;
            why = Some(format!(
                "no consensus before the reboot at {} s (LEDs {})",
                t.as_millis() / 1000,
                leds_str(&before)
            ));
        } else if success && restore_s.is_none_or(|r| r > limit.as_secs_f64()) {
            success = false;
            why = Some(format!(
                "consensus back only {:.0} s after the reboot (limit {} s)",
                restore_s.unwrap_or(f64::NAN),
                limit.as_millis() / 1000
            ));
        }
    }
    let o = Outcome {
        seed: cfg.seed,
        pattern: pattern_str(&run.lights),
        expected: expected.as_deref().map(leds_str).unwrap_or_default(),
        leds: leds_str(&run.leds),
        success,
        why,
        crashed: false,
        consensus_s: run.consensus_s,
        restore_s,
        medium: run.report.medium,
        frame_errors: run
            .report
            .robots
            .iter()
            .map(|s| u64::from(s.frame_errors))
            .sum(),
        waves: run.report.waves.clone(),
        nodes: run.report.nodes.clone(),
        duration_s: cfg.duration.as_secs_f64(),
    };
    Ok(o)
}

/// Runs one seed of one scenario.
///
/// # Errors
/// Why the run cannot start.
pub fn run_one(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
    decide: Decide,
) -> Result<Outcome, CampaignError> {
    run_in_loop(scenario, seed, loss, decide, None)
}

/// [`run_one`] with `hil` robots in the loop.
///
/// # Errors
/// Why the run cannot start.
pub fn run_in_loop(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
    decide: Decide,
    hil: Option<&InTheLoop>,
) -> Result<Outcome, CampaignError> {
    let (cfg, reboot) = run_config(scenario, seed, loss, decide, hil)?;
    outcome(&cfg, reboot)
}

/// The run of `scenario` for `seed` under `decide`, with `hil` robots in the loop, and its
/// reboot time if it has one ([`config`]).
///
/// # Errors
/// Why the run cannot be set up.
pub fn run_config(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
    decide: Decide,
    hil: Option<&InTheLoop>,
) -> Result<(ArenaConfig, Option<Instant>), CampaignError> {
    let (mut cfg, reboot) = config(scenario, seed, loss)?;
    cfg.robot.params.decide = decide.into();
    if let Some(h) = hil {
        cfg.hil = h.at(&hil_places(&cfg, h.robots)?);
    }
    Ok((cfg, reboot))
}

/// Runs the plan, in parallel; the result does not depend on the number of threads. Its runs
/// are [`jobs`], each [`run_one`], put together by [`report`].
///
/// # Errors
/// An option is unusable ([`check`]) or a run cannot start.
pub fn run(plan: &Plan, progress: &Progress) -> Result<Report, CampaignError> {
    check(plan)?;
    let wall = std::time::Instant::now();
    let jobs = jobs(plan);
    let outcomes: Vec<Outcome> = jobs
        .par_iter()
        .map(|&(s, seed)| {
            let o = run_in_loop(
                &SCENARIOS[s],
                seed,
                plan.loss,
                plan.decide,
                plan.hil.as_ref(),
            );
            progress.inc();
            o
        })
        .collect::<Result<_, CampaignError>>()?;
    progress.finish();
    Ok(report(
        plan,
        outcomes,
        wall.elapsed().as_secs_f64(),
        rayon::current_num_threads(),
    ))
}

/// That the plan can run: at least one seed, a loss that is a probability, scenarios that
/// exist.
///
/// # Errors
/// The first unusable option.
pub fn check(plan: &Plan) -> Result<(), CampaignError> {
    if plan.seeds == 0 {
        return Err(CampaignError::NoSeeds);
    }
    if let Some(p) = plan.loss
        && !(0.0..=1.0).contains(&p)
    {
        return Err(CampaignError::Loss(p));
    }
    if let Some(&i) = plan.scenarios.iter().find(|&&i| i >= SCENARIOS.len()) {
        return Err(CampaignError::NoScenario(i));
    }
    Ok(())
}

/// The plan's runs in order, scenario by scenario (in plan order), seeds in order: (index into
/// [`SCENARIOS`], seed).
pub fn jobs(plan: &Plan) -> Vec<(usize, u64)> {
    plan.scenarios
        .iter()
        .flat_map(|&s| (0..plan.seeds).map(move |k| (s, plan.seed.wrapping_add(k))))
        .collect()
}

/// The report of `plan` from the outcomes of its [`jobs`], in order, which took `wall_s` on
/// `threads` threads.
pub fn report(plan: &Plan, outcomes: Vec<Outcome>, wall_s: f64, threads: usize) -> Report {
    let mut results: Vec<ScenarioResult> = plan
        .scenarios
        .iter()
        .map(|&s| ScenarioResult {
            scenario: SCENARIOS[s],
            runs: Vec::new(),
        })
        .collect();
    for ((s, _), o) in jobs(plan).iter().zip(outcomes) {
        let i = plan.scenarios.iter().position(|x| x == s).unwrap_or(0);
        results[i].runs.push(o);
    }
    Report {
        plan: plan.clone(),
        results,
        wall_s,
        threads,
    }
}

/// The command that replays one run of `plan`.
pub fn replay_command(scenario: &str, seed: u64, plan: &Plan) -> String {
    let mut c = format!("cimax arena campaign --scenario {scenario} --seed {seed} --seeds 1");
    if let Some(p) = plan.loss {
        let _ = write!(c, " --loss {p}");
    }
    let _ = write!(c, " --decide {}", plan.decide.name());
    if let Some(h) = &plan.hil {
        let _ = write!(c, " --hil {}", h.spec());
        if let Some(image) = &h.image {
            let _ = write!(c, " --hil-image {}", image.display());
        }
    }
    c
}

/// One experiment of the lab suite (`cimax arena` with no options) under one rule: success
/// and the time to consensus of each run (from the start, or from the mirroring).
#[derive(Clone, Debug)]
pub struct SuiteResult {
    /// The experiment: a pattern, or e.g. `1000>0001` for an alternating one.
    pub label: String,
    /// Per run: success and time to consensus.
    pub runs: Vec<(bool, Option<f64>)>,
}

/// The share of the lab suite's runs that must succeed, per rule and readings: the paper's
/// 5 of 5 for every pattern allows no failure in five runs; over 200 seeds, one in a hundred.
pub const SUITE_BAR: f64 = 0.99;

/// Seeds per scenario of the documented campaign (`docs/reliability.md`), from seed 1: the
/// default of `cimax arena campaign --seeds`, and what its page's command line leaves out.
pub const SEEDS: u64 = 200;

/// The readings the campaign runs the lab suite with: the emulator's levels and the paper's
/// binary readings (Fig. 12(d), g ∈ {0, 1}).
pub const SUITE_READINGS: [Readings; 2] = [Readings::Levels, Readings::Binary];

/// The lab suite under `decide` ([`hal_emu::judge::paper_suite`]): the paper's six patterns and
/// the alternating experiment from each (mirrored once the run's duration has passed), seeds
/// `seed..seed + seeds`, no fault, the sensors reporting `readings`, as
/// `cimax arena --runs SEEDS --decide RULE --readings KIND` runs it. Each run is a
/// [`suite_run`], put together by [`suite_results`].
///
/// # Errors
/// Why a run cannot start.
pub fn lab_suite(
    decide: Decide,
    readings: Readings,
    seed: u64,
    seeds: u64,
) -> Result<Vec<SuiteResult>, CampaignError> {
    let experiments = hal_emu::judge::paper_suite().len();
    let runs = (0..experiments)
        .map(|e| {
            (0..seeds)
                .into_par_iter()
                .map(|k| suite_run(decide, readings, e, seed.wrapping_add(k)))
                .collect::<Result<Vec<_>, CampaignError>>()
        })
        .collect::<Result<Vec<_>, CampaignError>>()?;
    Ok(suite_results(runs.concat(), seeds))
}

/// One run of the lab suite: experiment `experiment` of [`hal_emu::judge::paper_suite`] with
/// seed `seed`; whether it succeeded, and its time to consensus.
///
/// # Errors
/// Why the run cannot start, or there is no such experiment.
pub fn suite_run(
    decide: Decide,
    readings: Readings,
    experiment: usize,
    seed: u64,
) -> Result<(bool, Option<f64>), CampaignError> {
    let mut params = Params::robots();
    params.decide = decide.into();
    let suite = hal_emu::judge::paper_suite();
    let e = suite
        .get(experiment)
        .ok_or(CampaignError::NoExperiment(experiment))?;
    let mut cfg = e.config(1.0, params.lab_run(), seed);
    cfg.robot.params = params;
    cfg.env.readings = readings;
    judge(&cfg)
        .map(|r| (r.success, r.consensus_s))
        .map_err(CampaignError::from)
}

/// The lab suite's results from its runs ([`suite_run`]), experiment by experiment, `seeds`
/// each, in order.
pub fn suite_results(runs: Vec<(bool, Option<f64>)>, seeds: u64) -> Vec<SuiteResult> {
    let mut runs = runs.into_iter();
    hal_emu::judge::paper_suite()
        .iter()
        .map(|e| SuiteResult {
            label: e.label(),
            runs: runs.by_ref().take(seeds as usize).collect(),
        })
        .collect()
}
