//! `cimax arena campaign`: the lab experiment under faults, over many seeds, against bars.
//!
//! Every [`SCENARIOS`] entry is run once per seed (200 by default) in the emulated arena
//! (`hal-emu`), each run judged exactly as `cimax arena` judges one
//! ([`hal_emu::judge::judge`]: the top-cap LEDs at the end against the expected verdict). Seed
//! `s` uses the paper's pattern `PAPER_PATTERNS[s mod 6]`, so every six consecutive seeds
//! cover the six patterns, and the run's seed is `s` itself: one seed replays one run
//! (`cimax arena campaign --scenario NAME --seed S --seeds 1`). Runs are spread over threads
//! with rayon; each is independent and seeded, so the report does not depend on the number
//! of threads.
//!
//! The report ([`markdown`]) gives per scenario the success rate, time to consensus (median
//! and 95th percentile), frames per run dropped by reason, the bar with PASS or FAIL, and the
//! failing seeds with the command that replays each; [`chart`] draws the success rates
//! against the bars as SVG.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::builder::PossibleValuesParser;
use clap::{Args, Subcommand};
use hal_emu::judge::{PAPER_PATTERNS, judge, leds_str, parse_pattern, pattern_str};
use hal_emu::world::arena::RobotFailure;
use hal_emu::{Adversary, ArenaConfig, ArenaError, MediumStats, Point2, Readings};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use protocol::{Duration, Instant, Params};
use rayon::prelude::*;
use serde::Serialize;

use crate::progress::Progress;
use crate::seeds;
use protocol::params::DecisionRule;
use protocol::wave::WaveStats;

/// Subcommands of `cimax arena`.
#[derive(Subcommand, Debug, Clone)]
pub enum ArenaCommand {
    /// Fault-injection campaign: every scenario over many seeds, with bars to meet; writes
    /// docs/reliability.md and exits 1 if a bar is missed.
    Campaign(CampaignArgs),
    /// Robots on a plane over a field: success rate and moves to success against the initial
    /// position, beside the 2D simulator's and the paper's (Figs. 5 and 8).
    Sweep(crate::arena::plane::SweepArgs),
    /// Speed of the robot program over the emulated medium: robot-seconds per wall second for
    /// 4, 64 and 1000 robots on a plane, one negotiation period, one core.
    Bench(crate::arena::plane::BenchArgs),
}

/// Options of `cimax arena campaign`.
#[derive(Args, Debug, Clone)]
pub struct CampaignArgs {
    /// Seeds per scenario: run k of every scenario uses seed BASE + k.
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub seeds: u64,
    /// Base seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Run only this scenario (repeatable); default: all.
    #[arg(long, value_parser = PossibleValuesParser::new(SCENARIOS.iter().map(|s| s.name)))]
    pub scenario: Vec<String>,
    /// Frame loss at every receiver in every scenario, replacing the scenario's own.
    #[arg(long)]
    pub loss: Option<f64>,
    /// Run only this decision rule (docs/protocol.md §5.4); default: both, side by side (the
    /// documented campaign).
    #[arg(long, value_enum)]
    pub decide: Option<Decide>,
    /// The Markdown report (default: docs/reliability.md for the documented campaign only,
    /// every scenario over 200 seeds from seed 1 at the scenarios' own loss; any other campaign
    /// writes nothing unless --out is given).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The SVG chart (default: figures/reliability.svg beside the report).
    #[arg(long)]
    pub figure: Option<PathBuf>,
    /// Write the trace of the first run as JSON lines (to look into a replayed seed).
    #[arg(long)]
    pub trace: Option<PathBuf>,
}

/// `--decide`: the protocol's [`DecisionRule`] on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
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

/// The fault a scenario injects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// Each frame is lost at each receiver with this probability.
    Loss(f64),
    /// Each received byte is corrupted with this probability (collisions on).
    ByteErrors(f64),
    /// Cycles drawn uniformly from `cycle ± spread` seconds, every cycle.
    CycleSpread {
        /// Mean cycle, s.
        cycle: u64,
        /// Spread, s.
        spread: u64,
    },
    /// One robot at an end of the line is dead from the start.
    DeadEnd,
    /// One robot reboots (killed, restarted 5 s later) at a random time after consensus.
    Reboot,
    /// A rogue transmitter in range of every robot sends random bytes.
    Rogue,
    /// A replayer in range of every robot sends captured frames again later.
    Replayer,
}

/// One scenario of the campaign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scenario {
    /// Its name on the command line.
    pub name: &'static str,
    /// What it does, for the report.
    pub what: &'static str,
    /// The fault.
    pub fault: Fault,
    /// Least success rate (0 to 1) to pass; `None`: reported only.
    pub bar: Option<f64>,
}

/// The campaign's scenarios and their bars.
pub const SCENARIOS: &[Scenario] = &[
    Scenario {
        name: "loss-10",
        what: "10 % of frames lost at each receiver",
        fault: Fault::Loss(0.1),
        bar: Some(0.99),
    },
    Scenario {
        name: "loss-20",
        what: "20 % of frames lost at each receiver",
        fault: Fault::Loss(0.2),
        bar: Some(0.95),
    },
    Scenario {
        name: "loss-30",
        what: "30 % of frames lost at each receiver",
        fault: Fault::Loss(0.3),
        bar: None,
    },
    Scenario {
        name: "byte-errors",
        what: "byte error rate 1e-3 (collisions on, as in every scenario)",
        fault: Fault::ByteErrors(1e-3),
        bar: Some(0.99),
    },
    Scenario {
        name: "cycle-spread",
        what: "cycles drawn from 40-70 s every cycle (the robots' measured spread; also the robot program's default, so this is the fault-free baseline every other scenario adds its fault to)",
        fault: Fault::CycleSpread {
            cycle: 55,
            spread: 15,
        },
        bar: Some(0.99),
    },
    Scenario {
        name: "dead-end",
        what: "a robot at one end dead from the start; the three others judged as a line of three",
        fault: Fault::DeadEnd,
        bar: Some(0.99),
    },
    Scenario {
        name: "reboot",
        what: "a robot reboots after consensus; consensus back within two negotiation periods",
        fault: Fault::Reboot,
        bar: Some(0.99),
    },
    Scenario {
        name: "rogue",
        what: "a rogue transmitter in range of all four sends random bytes",
        fault: Fault::Rogue,
        bar: Some(0.99),
    },
    Scenario {
        name: "replayer",
        what: "a replayer in range of all four sends captured frames again 10-60 s later",
        fault: Fault::Replayer,
        bar: Some(0.99),
    },
];

/// Where the adversaries stand: between robots 1 and 2 of the line of four (1 m apart), 1.5 m
/// from the end robots, so every robot hears them (range 1.5 m), the end robots on the same
/// receiver as their only neighbour.
pub const ADVERSARY_AT: (f64, f64) = (1.5, 0.0);

/// Delay between a reboot's kill and its restart.
pub const REBOOT_DOWN: Duration = Duration::from_secs(5);

/// One run of a scenario, judged.
#[derive(Clone, Debug)]
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
    pub medium: MediumStats,
    /// Frames the robots' deframers rejected (CRC, stuffing, length), all robots.
    pub frame_errors: u64,
    /// Each robot's wave counters at the end (of its last life; empty if the run crashed).
    pub waves: Vec<WaveStats>,
    /// Each robot's protocol counters at the end (of its last life; empty if the run crashed):
    /// negotiation periods, and those with fewer initiations than cycles.
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

/// The pattern seed `seed` uses: the paper's six in turn.
pub fn pattern_for(seed: u64) -> &'static str {
    PAPER_PATTERNS[(seed % PAPER_PATTERNS.len() as u64) as usize]
}

/// The run of `scenario` for `seed`, and the reboot time if it has one.
///
/// # Errors
/// A message if the pattern does not parse (cannot happen for the paper's patterns).
pub fn config(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
) -> Result<(ArenaConfig, Option<Instant>), String> {
    let pattern = parse_pattern(pattern_for(seed))?;
    let n = pattern.len();
    let params = Params::robots();
    let mut cfg = ArenaConfig::line(pattern.clone(), 1.0, params.lab_run(), seed);
    // Scenario-specific draws (which robot, when) from their own seed, so they do not disturb
    // the run's other random numbers.
    let draw = |what: u64| seeds::derive(seed, &[what]);
    let at = Point2::new(ADVERSARY_AT.0, ADVERSARY_AT.1);
    let mut reboot = None;
    match scenario.fault {
        Fault::Loss(p) => cfg.medium.loss = p,
        Fault::ByteErrors(p) => {
            cfg.medium.byte_error_rate = p;
            cfg.medium.collisions = true;
        }
        Fault::CycleSpread { cycle, spread } => {
            cfg.robot.params.wave.cycle = Duration::from_secs(cycle);
            cfg.robot.params.wave.cycle_spread = Duration::from_secs(spread);
            cfg.duration = cfg.robot.params.lab_run();
        }
        Fault::DeadEnd => {
            // The end drawn for this seed, or the other one if without it the three others
            // would see no border (1000 without robot 0 is 000: no verdict).
            let (mut end, other) = if draw(1) % 2 == 0 {
                (0, n - 1)
            } else {
                (n - 1, 0)
            };
            let rest = |e: usize| {
                let mut p = pattern.clone();
                p.remove(e);
                hal_emu::judge::expected(&p)
            };
            if rest(end).is_none() {
                end = other;
            }
            cfg.dead_at_start = vec![end];
        }
        Fault::Reboot => {
            // After the first decision (at most 10 cycles of 70 s = 700 s): 800 to 1400 s.
            let t = Instant::from_secs(800 + draw(2) % 601);
            let robot = (draw(3) % n as u64) as usize;
            cfg.kills.push((t, robot));
            cfg.restarts.push((t + REBOOT_DOWN, robot));
            cfg.duration = t.saturating_since(Instant::ZERO) + params.lab_run();
            reboot = Some(t);
        }
        Fault::Rogue => cfg.adversaries.push(Adversary::rogue(at)),
        Fault::Replayer => cfg.adversaries.push(Adversary::replayer(at)),
    }
    if let Some(p) = loss {
        cfg.medium.loss = p;
    }
    Ok((cfg, reboot))
}

/// The failed outcome of a run of `cfg` in which a robot stopped on its own.
fn crashed(cfg: &ArenaConfig, failure: &RobotFailure) -> Outcome {
    let end = Instant::ZERO + cfg.duration;
    let lights = cfg
        .env
        .pattern_at(end)
        .map(<[bool]>::to_vec)
        .unwrap_or_default();
    let expected = hal_emu::judge::expected_without(&lights, &hal_emu::judge::absent(cfg));
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
fn outcome(cfg: &ArenaConfig, reboot: Option<Instant>) -> Result<Outcome, String> {
    let run = match judge(cfg) {
        Ok(run) => run,
        Err(ArenaError::Robot(f)) => return Ok(crashed(cfg, &f)),
        Err(e) => return Err(e.to_string()),
    };
    let expected = run.expected.clone();
    let mut success = run.success;
    let mut why = (!success).then(|| match run.flicker {
        Some((t, r)) => format!("robot {r}'s LEDs changed at {t:.0} s, after consensus"),
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
/// A message if the run cannot start.
pub fn run_one(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
    decide: Decide,
) -> Result<Outcome, String> {
    let (mut cfg, reboot) = config(scenario, seed, loss)?;
    cfg.robot.params.decide = decide.into();
    outcome(&cfg, reboot)
}

/// Runs the plan, in parallel; the result does not depend on the number of threads.
///
/// # Errors
/// A message if an option is unusable or a run cannot start.
pub fn run(plan: &Plan, progress: &Progress) -> Result<Report, String> {
    if plan.seeds == 0 {
        return Err("a campaign needs at least one seed".into());
    }
    if let Some(p) = plan.loss
        && !(0.0..=1.0).contains(&p)
    {
        return Err(format!("--loss must be a probability in [0, 1], not {p}"));
    }
    if let Some(&i) = plan.scenarios.iter().find(|&&i| i >= SCENARIOS.len()) {
        return Err(format!("there is no scenario number {i}"));
    }
    let wall = std::time::Instant::now();
    let jobs: Vec<(usize, u64)> = plan
        .scenarios
        .iter()
        .flat_map(|&s| (0..plan.seeds).map(move |k| (s, plan.seed.wrapping_add(k))))
        .collect();
    let outcomes: Vec<Result<Outcome, String>> = jobs
        .par_iter()
        .map(|&(s, seed)| {
            let o = run_one(&SCENARIOS[s], seed, plan.loss, plan.decide);
            progress.inc();
            o
        })
        .collect();
    progress.finish();
    let mut results: Vec<ScenarioResult> = plan
        .scenarios
        .iter()
        .map(|&s| ScenarioResult {
            scenario: SCENARIOS[s],
            runs: Vec::new(),
        })
        .collect();
    for ((s, _), o) in jobs.iter().zip(outcomes) {
        let i = plan.scenarios.iter().position(|x| x == s).unwrap_or(0);
        results[i].runs.push(o?);
    }
    Ok(Report {
        plan: plan.clone(),
        results,
        wall_s: wall.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    })
}

pub use crate::stats::quantile;

/// The command that replays one run.
pub fn replay_command(scenario: &str, seed: u64, loss: Option<f64>, decide: Decide) -> String {
    let mut c = format!("cimax arena campaign --scenario {scenario} --seed {seed} --seeds 1");
    if let Some(p) = loss {
        let _ = write!(c, " --loss {p}");
    }
    let _ = write!(c, " --decide {}", decide.name());
    c
}

/// The command that produced a report.
fn command(plan: &Plan) -> String {
    let mut c = "cargo run --release -p host-sim -- arena campaign".to_string();
    if plan.seeds != 200 {
        let _ = write!(c, " --seeds {}", plan.seeds);
    }
    if plan.seed != 1 {
        let _ = write!(c, " --seed {}", plan.seed);
    }
    if plan.scenarios.len() != SCENARIOS.len() {
        for &s in &plan.scenarios {
            let _ = write!(c, " --scenario {}", SCENARIOS[s].name);
        }
    }
    if let Some(p) = plan.loss {
        let _ = write!(c, " --loss {p}");
    }
    c
}

fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn secs(x: Option<f64>) -> String {
    x.map_or("-".into(), |s| format!("{s:.0}"))
}

fn verdict(r: &ScenarioResult) -> &'static str {
    match r.passed() {
        Some(true) => "PASS",
        Some(false) => "FAIL",
        None => "reported",
    }
}

/// A bar of `width` characters filled to `x` (0 to 1), with `|` inserted at the bar `b`, if
/// any.
fn text_bar(x: f64, b: Option<f64>, width: usize) -> String {
    let filled = ((x * width as f64).round() as usize).min(width);
    let mut bar = "#".repeat(filled) + &".".repeat(width - filled);
    if let Some(b) = b {
        bar.insert(((b * width as f64).round() as usize).min(width), '|');
    }
    bar
}

/// The bar as a percentage, `-` if none.
fn bar_str(r: &ScenarioResult) -> String {
    r.scenario
        .bar
        .map_or("-".into(), |b| format!("{:.0} %", b * 100.0))
}

/// Consensus time (median, 95th percentile) and restoration time (the same), seconds.
fn times(r: &ScenarioResult) -> [String; 4] {
    let c: Vec<f64> = r.runs.iter().filter_map(|o| o.consensus_s).collect();
    let rs: Vec<f64> = r.runs.iter().filter_map(|o| o.restore_s).collect();
    [
        secs(quantile(&c, 0.5)),
        secs(quantile(&c, 0.95)),
        secs(quantile(&rs, 0.5)),
        secs(quantile(&rs, 0.95)),
    ]
}

/// Per scenario: success, bar, verdict, consensus times (one line each, as printed).
pub fn table(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<13} {:>5} {:>8} {:>6}  {:<8} {:>11} {:>6} {:>11} {:>6}",
        "scenario", "runs", "success", "bar", "verdict", "consensus s", "p95", "restore s", "p95"
    );
    for r in &report.results {
        let [c50, c95, r50, r95] = times(r);
        let _ = writeln!(
            s,
            "{:<13} {:>5} {:>8} {:>6}  {:<8} {c50:>11} {c95:>6} {r50:>11} {r95:>6}",
            r.scenario.name,
            r.runs.len(),
            pct(r.rate()),
            bar_str(r),
            verdict(r),
        );
    }
    s
}

/// The time a run is judged by in the comparison of the rules: consensus from the start, or
/// for a reboot the time from the reboot until consensus was back.
fn decision_time(o: &Outcome) -> Option<f64> {
    o.restore_s.or(o.consensus_s)
}

/// Median and 95th percentile of [`decision_time`] over a scenario's runs.
fn decision_times(r: &ScenarioResult) -> (Option<f64>, Option<f64>) {
    let t: Vec<f64> = r.runs.iter().filter_map(decision_time).collect();
    (quantile(&t, 0.5), quantile(&t, 0.95))
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

/// The readings the campaign runs the lab suite with: the emulator's levels and the paper's
/// binary readings (Fig. 5(d), g ∈ {0, 1}).
pub const SUITE_READINGS: [Readings; 2] = [Readings::Levels, Readings::Binary];

/// The lab suite under `decide` ([`hal_emu::judge::paper_suite`]): the paper's six patterns and
/// the alternating experiment from each (mirrored once the run's duration has passed), seeds
/// `seed..seed + seeds`, no fault, the sensors reporting `readings`, as
/// `cimax arena --runs SEEDS --decide RULE --readings KIND` runs it.
///
/// # Errors
/// A message if a run cannot start.
pub fn lab_suite(
    decide: Decide,
    readings: Readings,
    seed: u64,
    seeds: u64,
) -> Result<Vec<SuiteResult>, String> {
    let mut params = Params::robots();
    params.decide = decide.into();
    let run = params.lab_run();
    hal_emu::judge::paper_suite()
        .iter()
        .map(|e| {
            let runs = (0..seeds)
                .into_par_iter()
                .map(|k| {
                    let mut cfg = e.config(1.0, run, seed.wrapping_add(k));
                    cfg.robot.params = params;
                    cfg.env.readings = readings;
                    judge(&cfg)
                        .map(|r| (r.success, r.consensus_s))
                        .map_err(|e| e.to_string())
                })
                .collect::<Result<Vec<_>, String>>()?;
            Ok(SuiteResult {
                label: e.label(),
                runs,
            })
        })
        .collect()
}

/// The lab suite of both rules, as the page's section shows it (`suite` in
/// `templates/reliability/suite.md.j2`).
#[derive(Serialize)]
pub struct SuiteSection {
    /// The readings, as `--readings` spells them (`full`, `binary`).
    pub readings: String,
    /// What they are, in words.
    pub readings_text: String,
    /// The bar, formatted (`99 %`).
    pub bar: String,
    /// Seeds per experiment.
    pub seeds: u64,
    /// The rules whose success over the whole suite is below [`SUITE_BAR`], one line each.
    pub missed: Vec<String>,
    /// Per experiment, and `all` last: its label and its cells (success of each rule, median
    /// and p95 time of each rule).
    pub rows: Vec<LabelledRow>,
}

/// A table row: a label and its formatted cells.
#[derive(Serialize)]
pub struct LabelledRow {
    /// The first cell, as shown (with its backquotes if any).
    pub label: String,
    /// The other cells, formatted.
    pub cells: Vec<String>,
}

/// The lab suite of both rules with `readings` as the page's section (success, median and p95
/// time, the bar).
pub fn suite_section(
    fixed: &[SuiteResult],
    adaptive: &[SuiteResult],
    readings: Readings,
    seeds: u64,
) -> SuiteSection {
    let stats = |r: &SuiteResult| {
        let ok = r.runs.iter().filter(|x| x.0).count();
        let t: Vec<f64> = r.runs.iter().filter_map(|x| x.1).collect();
        (
            format!("{ok}/{}", r.runs.len()),
            quantile(&t, 0.5),
            quantile(&t, 0.95),
        )
    };
    let mut all = [Vec::new(), Vec::new()];
    let mut rows = Vec::new();
    for (f, a) in fixed.iter().zip(adaptive) {
        let (fs, fm, fp) = stats(f);
        let (as_, am, ap) = stats(a);
        all[0].extend(f.runs.iter().filter_map(|x| x.1));
        all[1].extend(a.runs.iter().filter_map(|x| x.1));
        rows.push(LabelledRow {
            label: format!("`{}`", f.label),
            cells: vec![fs, as_, secs(fm), secs(am), secs(fp), secs(ap)],
        });
    }
    let ok = |r: &[SuiteResult]| r.iter().flat_map(|x| &x.runs).filter(|x| x.0).count();
    let n = |r: &[SuiteResult]| r.iter().map(|x| x.runs.len()).sum::<usize>();
    rows.push(LabelledRow {
        label: "all".into(),
        cells: vec![
            format!("{}/{}", ok(fixed), n(fixed)),
            format!("{}/{}", ok(adaptive), n(adaptive)),
            secs(quantile(&all[0], 0.5)),
            secs(quantile(&all[1], 0.5)),
            secs(quantile(&all[0], 0.95)),
            secs(quantile(&all[1], 0.95)),
        ],
    });
    let mut missed = Vec::new();
    for (name, r) in [("fixed", fixed), ("adaptive", adaptive)] {
        let share = ok(r) as f64 / n(r).max(1) as f64;
        if share < SUITE_BAR {
            missed.push(format!(
                "bar missed: the lab suite with {readings} readings succeeded in {} of runs under \
                 the {name} rule, below its bar of {}",
                pct(share),
                pct(SUITE_BAR)
            ));
        }
    }
    SuiteSection {
        readings: readings.to_string(),
        readings_text: match readings {
            Readings::Levels => "levels (lit 200, dark 30, noise ±10)".into(),
            Readings::Binary => "the paper's binary readings (g = 1 lit, 0 dark, no noise)".into(),
            r => format!("readings {r}"),
        },
        bar: pct(SUITE_BAR),
        seeds,
        rows,
        missed,
    }
}

/// The adaptive rule's campaign beside the fixed rule's, as the page's section shows it
/// (`rules` in `templates/reliability/rules.md.j2`).
#[derive(Serialize)]
pub struct RulesSection {
    /// Per scenario.
    pub rows: Vec<RulesRow>,
    /// The figure, relative to the page.
    pub figure: Option<String>,
    /// The adaptive rule's failed runs.
    pub failing: Vec<FailingGroup>,
    /// The adaptive rule's missed bars, one line each.
    pub missed: Vec<String>,
}

/// One scenario under both rules.
#[derive(Serialize)]
pub struct RulesRow {
    /// Scenario name.
    pub name: &'static str,
    /// Its bar, `99 %` or `-`.
    pub bar: String,
    /// Success rate under the fixed rule.
    pub fixed_success: String,
    /// PASS, FAIL or reported, under the fixed rule.
    pub fixed_verdict: &'static str,
    /// Success rate under the adaptive rule.
    pub adaptive_success: String,
    /// PASS, FAIL or reported, under the adaptive rule.
    pub adaptive_verdict: &'static str,
    /// Median time fixed, adaptive; p95 time fixed, adaptive (s).
    pub times: [String; 4],
}

/// The section of `docs/reliability.md` that sets the adaptive rule's campaign beside the fixed
/// rule's: success, median and p95 time per scenario, the adaptive runs' failing seeds and its
/// verdict, and the figure (`figure`, relative to the page).
pub fn rules_section(fixed: &Report, adaptive: &Report, figure: Option<&str>) -> RulesSection {
    let rows = fixed
        .results
        .iter()
        .zip(&adaptive.results)
        .map(|(f, a)| {
            let (fm, fp) = decision_times(f);
            let (am, ap) = decision_times(a);
            RulesRow {
                name: f.scenario.name,
                bar: bar_str(f),
                fixed_success: pct(f.rate()),
                fixed_verdict: verdict(f),
                adaptive_success: pct(a.rate()),
                adaptive_verdict: verdict(a),
                times: [secs(fm), secs(am), secs(fp), secs(ap)],
            }
        })
        .collect();
    RulesSection {
        rows,
        figure: figure.map(str::to_string),
        failing: failing_seeds(adaptive),
        missed: adaptive.missed().into_iter().map(missed_line).collect(),
    }
}

/// The figure of [`rules_section`]: per scenario, the median time (bar) and the 95th
/// percentile (whisker) of each rule, on a common axis of seconds.
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
        .x_desc("seconds (one cycle: 55 s)")
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

/// One rule's campaign as the page shows it (`campaign` in
/// `templates/reliability/campaign.md.j2`).
#[derive(Serialize)]
pub struct CampaignSection {
    /// The command that regenerates the page.
    pub command: String,
    /// Wall time of the campaign, s.
    pub wall_s: String,
    /// Threads it ran on.
    pub threads: usize,
    /// Seeds per scenario, the first and the last.
    pub seeds: u64,
    /// The first seed.
    pub first_seed: u64,
    /// The last seed.
    pub last_seed: u64,
    /// Length of a run, whole seconds.
    pub run_s: u64,
    /// The set-up facts the page states, read from the configuration of a run (so that CI's
    /// staleness diff catches a change of the emulator's defaults).
    pub setup: Setup,
    /// The paper's patterns, in the order seeds rotate through them.
    pub patterns: &'static [&'static str],
    /// How long a rebooting robot stays down, whole seconds.
    pub reboot_down_s: u64,
    /// The longest restoration that passes, whole seconds.
    pub restore_limit_s: u64,
    /// Where the adversaries stand, m.
    pub adversary_x: String,
    /// Where the adversaries stand, m.
    pub adversary_y: String,
    /// Per scenario.
    pub scenarios: Vec<ScenarioRow>,
    /// The success-rate figure, relative to the page.
    pub figure: Option<String>,
    /// The failed runs.
    pub failing: Vec<FailingGroup>,
    /// The missed bars, one line each.
    pub missed: Vec<String>,
}

/// What the campaign's runs are, as configured (robots, spacing, light link, cycles).
#[derive(Serialize)]
pub struct Setup {
    /// Robots in the line.
    pub robots: usize,
    /// Distance between neighbours, m.
    pub spacing_m: String,
    /// Light range, m.
    pub range_m: String,
    /// Bits per second on air.
    pub bitrate: u32,
    /// Bits per byte on air.
    pub bits_per_byte: u32,
    /// Mean cycle, s.
    pub cycle_s: String,
    /// Cycle spread, ± s.
    pub spread_s: String,
    /// Cycles per negotiation period.
    pub negotiation_cycles: u16,
}

impl Setup {
    /// The facts of `cfg`, a run of the campaign.
    pub fn of(cfg: &ArenaConfig) -> Setup {
        let spacing = match cfg.positions.as_slice() {
            [a, b, ..] => (b - a).norm(),
            _ => 0.0,
        };
        let p = &cfg.robot.params;
        Setup {
            robots: cfg.positions.len(),
            spacing_m: format!("{spacing}"),
            range_m: format!("{}", cfg.medium.range),
            bitrate: cfg.medium.bitrate,
            bits_per_byte: cfg.medium.bits_per_byte,
            cycle_s: format!("{}", p.wave.cycle.as_secs_f64()),
            spread_s: format!("{}", p.wave.cycle_spread.as_secs_f64()),
            negotiation_cycles: p.negotiation_cycles,
        }
    }
}

/// One scenario's results, formatted.
#[derive(Serialize)]
pub struct ScenarioRow {
    /// Scenario name.
    pub name: &'static str,
    /// Its fault, in words.
    pub fault: &'static str,
    /// Its bar as required (`≥ 99 %` or `reported only`).
    pub required: String,
    /// Runs.
    pub runs: usize,
    /// Success rate.
    pub success: String,
    /// Successful runs.
    pub successes: usize,
    /// Its bar, `99 %` or `-`.
    pub bar: String,
    /// PASS, FAIL or reported.
    pub verdict: &'static str,
    /// Consensus median and p95, restoration median and p95 (s).
    pub times: [String; 4],
    /// Successful runs of runs per pattern (`33/33`).
    pub per_pattern: Vec<String>,
    /// The line of the text chart.
    pub text_bar: String,
    /// Frames per run: mean sent, delivered, lost, rx busy, rx dead, garbled, corrupt bytes,
    /// rejected, adversary sent, captured.
    pub frames: Vec<String>,
}

/// One scenario's failed runs, each with its replay command.
#[derive(Serialize)]
pub struct FailingGroup {
    /// Scenario name.
    pub scenario: &'static str,
    /// Failed runs.
    pub failed: usize,
    /// Runs.
    pub runs: usize,
    /// One line per failed run.
    pub lines: Vec<String>,
}

/// The page `docs/reliability.md`: one rule's campaign and, with both rules, the sections
/// comparing them (`templates/reliability.md.j2`).
#[derive(Serialize)]
pub struct Page {
    /// The first rule's campaign.
    pub campaign: CampaignSection,
    /// Both rules side by side.
    pub rules: Option<RulesSection>,
    /// The lab suite under both rules, once per [`SUITE_READINGS`].
    pub suites: Vec<SuiteSection>,
    /// Initiations per negotiation period.
    pub initiations: Option<crate::arena::stress::InitiationsSection>,
    /// The loss sweep.
    pub loss: Option<crate::arena::stress::LossSection>,
}

impl Page {
    /// Renders the page.
    ///
    /// # Errors
    /// The template engine's message (a bug: the templates are built in).
    pub fn render(&self) -> Result<String, String> {
        crate::report::page::render("reliability.md.j2", self)
    }
}

/// One scenario's row of every table of the campaign section.
fn scenario_row(r: &ScenarioResult) -> ScenarioRow {
    let n = r.runs.len().max(1) as f64;
    let mean = |f: &dyn Fn(&Outcome) -> u64| {
        format!("{:.1}", r.runs.iter().map(f).sum::<u64>() as f64 / n)
    };
    let frames = vec![
        mean(&|o| o.medium.sent),
        mean(&|o| o.medium.delivered),
        mean(&|o| o.medium.lost),
        mean(&|o| o.medium.receiver_transmitting),
        mean(&|o| o.medium.receiver_dead),
        mean(&|o| o.medium.garbled),
        mean(&|o| o.medium.corrupted_bytes),
        mean(&|o| o.frame_errors),
        mean(&|o| o.medium.rogue_bursts + o.medium.replayed),
        mean(&|o| o.medium.captured),
    ];
    let per_pattern = PAPER_PATTERNS
        .iter()
        .map(|p| {
            let runs = r.runs.iter().filter(|o| o.pattern == *p);
            let ok = runs.clone().filter(|o| o.success).count();
            format!("{ok}/{}", runs.count())
        })
        .collect();
    ScenarioRow {
        name: r.scenario.name,
        fault: r.scenario.what,
        required: r
            .scenario
            .bar
            .map_or("reported only".into(), |b| format!("≥ {:.0} %", b * 100.0)),
        runs: r.runs.len(),
        success: pct(r.rate()),
        successes: r.successes(),
        bar: bar_str(r),
        verdict: verdict(r),
        times: times(r),
        per_pattern,
        text_bar: format!(
            "{:<13} {} {:>7}  {}",
            r.scenario.name,
            text_bar(r.rate(), r.scenario.bar, 50),
            pct(r.rate()),
            verdict(r)
        ),
        frames,
    }
}

/// The set-up of the baseline scenario's first run (every scenario shares it but its fault).
fn baseline_setup(seed: u64) -> Setup {
    let baseline = SCENARIOS
        .iter()
        .find(|s| matches!(s.fault, Fault::CycleSpread { .. }))
        .unwrap_or(&SCENARIOS[0]);
    match config(baseline, seed, None) {
        Ok((cfg, _)) => Setup::of(&cfg),
        Err(_) => Setup::of(&ArenaConfig::line(Vec::new(), 1.0, Duration::ZERO, seed)),
    }
}

/// One rule's campaign as the page's first section; `figure` relative to the page.
pub fn campaign_section(report: &Report, figure: Option<&str>) -> CampaignSection {
    let plan = &report.plan;
    let p = Params::robots();
    CampaignSection {
        command: command(plan),
        wall_s: format!("{:.0}", report.wall_s),
        threads: report.threads,
        seeds: plan.seeds,
        first_seed: plan.seed,
        last_seed: plan.seed.wrapping_add(plan.seeds - 1),
        run_s: p.lab_run().as_millis() / 1000,
        setup: baseline_setup(plan.seed),
        patterns: &PAPER_PATTERNS,
        reboot_down_s: REBOOT_DOWN.as_millis() / 1000,
        restore_limit_s: p.nominal_period().saturating_mul(2).as_millis() / 1000,
        adversary_x: ADVERSARY_AT.0.to_string(),
        adversary_y: ADVERSARY_AT.1.to_string(),
        scenarios: report.results.iter().map(scenario_row).collect(),
        figure: figure.map(str::to_string),
        failing: failing_seeds(report),
        missed: report.missed().into_iter().map(missed_line).collect(),
    }
}

/// The report as Markdown: the page `docs/reliability.md` with one rule's campaign only.
///
/// # Panics
/// If the built-in template does not render (a bug).
pub fn markdown(report: &Report, figure: Option<&str>) -> String {
    let page = Page {
        campaign: campaign_section(report, figure),
        rules: None,
        suites: Vec::new(),
        initiations: None,
        loss: None,
    };
    page.render().unwrap_or_else(|e| panic!("{e}"))
}

/// Every failed run of `report`, per scenario, with its replay command.
fn failing_seeds(report: &Report) -> Vec<FailingGroup> {
    report
        .results
        .iter()
        .filter_map(|r| {
            let lines: Vec<String> = r
                .failures()
                .map(|o| failure_line(r.scenario.name, o, report.plan.loss, report.plan.decide))
                .collect();
            (!lines.is_empty()).then_some(FailingGroup {
                scenario: r.scenario.name,
                failed: lines.len(),
                runs: r.runs.len(),
                lines,
            })
        })
        .collect()
}

fn failure_line(scenario: &str, o: &Outcome, loss: Option<f64>, decide: Decide) -> String {
    format!(
        "seed {}: pattern {}, LEDs {}, expected {} ({}); replay: `{}`",
        o.seed,
        o.pattern,
        o.leds,
        o.expected,
        o.why.as_deref().unwrap_or("failed"),
        replay_command(scenario, o.seed, loss, decide)
    )
}

fn missed_line(r: &ScenarioResult) -> String {
    format!(
        "bar missed: `{}` succeeded in {} of runs, below its bar of {:.0} %",
        r.scenario.name,
        pct(r.rate()),
        r.scenario.bar.unwrap_or(0.0) * 100.0
    )
}

/// Draws the success rate of every scenario as a horizontal bar, with its bar as a red mark.
///
/// # Errors
/// Any failure to draw or write the file.
pub fn chart(report: &Report, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
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

fn write_trace(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
    decide: Decide,
    path: &Path,
) -> Result<(), String> {
    let (mut cfg, _) = config(scenario, seed, loss)?;
    cfg.robot.params.decide = decide.into();
    cfg.trace = true;
    let run = judge(&cfg).map_err(|e| e.to_string())?;
    let mut out = String::new();
    for e in &run.report.trace {
        out += &serde_json::to_string(e).map_err(|e| e.to_string())?;
        out.push('\n');
    }
    std::fs::write(path, out).map_err(|e| format!("{}: {e}", path.display()))
}

fn ensure_parent(p: &Path) -> std::io::Result<()> {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => std::fs::create_dir_all(d),
        _ => Ok(()),
    }
}

/// The figure's path relative to the report's directory, for the Markdown link.
fn relative(figure: &Path, out: &Path) -> String {
    let dir = out.parent().unwrap_or(Path::new(""));
    figure
        .strip_prefix(dir)
        .unwrap_or(figure)
        .to_string_lossy()
        .replace('\\', "/")
}

/// Runs `cimax arena campaign`: 0 if every bar is met, 1 if one is missed or a robot crashed
/// in a run ([`Outcome::crashed`]), 2 for bad options.
pub fn main(args: &CampaignArgs) -> ExitCode {
    let scenarios: Vec<usize> = if args.scenario.is_empty() {
        (0..SCENARIOS.len()).collect()
    } else {
        let mut v: Vec<usize> = args
            .scenario
            .iter()
            .filter_map(|n| SCENARIOS.iter().position(|s| s.name == n))
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let rules = args
        .decide
        .map_or(vec![Decide::Fixed, Decide::Adaptive], |d| vec![d]);
    let mut reports = Vec::new();
    for &decide in &rules {
        let plan = Plan {
            scenarios: scenarios.clone(),
            seed: args.seed,
            seeds: args.seeds,
            loss: args.loss,
            decide,
        };
        match run_rule(&plan, args) {
            Ok(r) => reports.push(r),
            Err(code) => return code,
        }
    }
    let documented = args.scenario.is_empty()
        && args.seeds == 200
        && args.seed == 1
        && args.loss.is_none()
        && args.decide.is_none();
    let out = args
        .out
        .clone()
        .or_else(|| documented.then(|| crate::report::default_docs_dir().join("reliability.md")));
    let mut failed = false;
    if let Some(out) = out {
        match write_page(&reports, &out, args.figure.clone()) {
            Ok(missed) => {
                for m in missed {
                    eprintln!("{m}");
                    failed = true;
                }
            }
            Err(e) => {
                eprintln!("cimax arena campaign: {}: {e}", out.display());
                return ExitCode::from(2);
            }
        }
    }
    for report in &reports {
        let plan = &report.plan;
        for r in &report.results {
            for o in r.failures() {
                failed |= o.crashed;
                eprintln!(
                    "FAILED {} {}",
                    r.scenario.name,
                    failure_line(r.scenario.name, o, plan.loss, plan.decide).replace('`', "")
                );
            }
        }
        for r in report.missed() {
            failed = true;
            eprintln!(
                "{} rule: {}",
                plan.decide.name(),
                missed_line(r).replace('`', "")
            );
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// Runs one rule's campaign and prints its table (and each run, for a single seed); writes the
/// trace if asked. `Err` holds the exit code of a bad option.
fn run_rule(plan: &Plan, args: &CampaignArgs) -> Result<Report, ExitCode> {
    let total = plan.scenarios.len() as u64 * plan.seeds;
    let progress = if total > 1 {
        Progress::new(total, "campaign", false)
    } else {
        Progress::hidden()
    };
    let report = run(plan, &progress).map_err(|e| {
        eprintln!("cimax arena campaign: {e}");
        ExitCode::from(2)
    })?;
    if let (Some(path), Some(&s)) = (&args.trace, plan.scenarios.first())
        && let Err(e) = write_trace(&SCENARIOS[s], plan.seed, plan.loss, plan.decide, path)
    {
        eprintln!("cimax arena campaign: {e}");
        return Err(ExitCode::from(2));
    }
    println!(
        "CIMAX fault campaign, {} rule: {} scenarios x {} seeds in the emulated arena ({:.1} s wall, {} threads)",
        plan.decide.name(),
        plan.scenarios.len(),
        plan.seeds,
        report.wall_s,
        report.threads
    );
    print!("{}", table(&report));
    if plan.seeds == 1 {
        for r in &report.results {
            for o in &r.runs {
                println!(
                    "{} seed {}: pattern {}, expected {}, LEDs {}, {}, consensus {} s{}",
                    r.scenario.name,
                    o.seed,
                    o.pattern,
                    o.expected,
                    o.leds,
                    if o.success { "success" } else { "FAILED" },
                    secs(o.consensus_s),
                    o.restore_s.map_or(String::new(), |x| format!(
                        ", restored {x:.0} s after the reboot"
                    ))
                );
            }
        }
    }
    Ok(report)
}

/// Writes the page `out` with its figures beside it (`figures/reliability.svg`, or `figure`,
/// and `reliability-rules.svg` next to it): the first report's page and, with two rules, the
/// section setting them side by side.
///
/// Returns the lab suite's missed bars, one line each.
fn write_page(
    reports: &[Report],
    out: &Path,
    figure: Option<PathBuf>,
) -> Result<Vec<String>, String> {
    let mut missed = Vec::new();
    let Some(first) = reports.first() else {
        return Ok(missed);
    };
    let figure = figure.unwrap_or_else(|| {
        out.parent()
            .unwrap_or(Path::new("."))
            .join("figures")
            .join("reliability.svg")
    });
    let rules_figure = figure.with_file_name("reliability-rules.svg");
    ensure_parent(out)
        .and_then(|()| ensure_parent(&figure))
        .map_err(|e| e.to_string())?;
    chart(first, &figure).map_err(|e| e.to_string())?;
    let mut page = Page {
        campaign: campaign_section(first, Some(&relative(&figure, out))),
        rules: None,
        suites: Vec::new(),
        initiations: None,
        loss: None,
    };
    if let [fixed, adaptive] = reports {
        rules_chart(fixed, adaptive, &rules_figure).map_err(|e| e.to_string())?;
        page.rules = Some(rules_section(
            fixed,
            adaptive,
            Some(&relative(&rules_figure, out)),
        ));
        let (seed, seeds) = (fixed.plan.seed, fixed.plan.seeds);
        for readings in SUITE_READINGS {
            let f = lab_suite(Decide::Fixed, readings, seed, seeds)?;
            let a = lab_suite(Decide::Adaptive, readings, seed, seeds)?;
            let section = suite_section(&f, &a, readings, seeds);
            missed.extend(section.missed.iter().map(|m| m.replace('`', "")));
            page.suites.push(section);
        }
        page.initiations = Some(crate::arena::stress::initiations_section(fixed, adaptive));
        let sweep_seeds = seeds.min(crate::arena::stress::SWEEP_SEEDS);
        let f = crate::arena::stress::loss_sweep(Decide::Fixed, seed, sweep_seeds)?;
        let a = crate::arena::stress::loss_sweep(Decide::Adaptive, seed, sweep_seeds)?;
        page.loss = Some(crate::arena::stress::loss_section(&f, &a, sweep_seeds));
        println!(
            "wrote {}, {} and {}",
            out.display(),
            figure.display(),
            rules_figure.display()
        );
    } else {
        println!("wrote {} and {}", out.display(), figure.display());
    }
    let page = page.render()?;
    std::fs::write(out, page).map_err(|e| e.to_string())?;
    Ok(missed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_by_nearest_rank() {
        let xs: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&xs, 0.5), Some(50.0));
        assert_eq!(quantile(&xs, 0.95), Some(95.0));
        assert_eq!(quantile(&[3.0], 0.95), Some(3.0));
        assert_eq!(quantile(&[], 0.5), None);
    }

    #[test]
    fn seeds_rotate_the_six_patterns_and_scenarios_draw_their_own_choices() {
        let six: Vec<&str> = (6..12).map(pattern_for).collect();
        assert_eq!(six, PAPER_PATTERNS);
        let dead = SCENARIOS.iter().find(|s| s.name == "dead-end").unwrap();
        for seed in 0..60 {
            let (cfg, _) = config(dead, seed, None).unwrap();
            let &[end] = cfg.dead_at_start.as_slice() else {
                panic!("one dead robot")
            };
            assert!(end == 0 || end == 3);
            let r = hal_emu::judge::absent(&cfg);
            let p = parse_pattern(pattern_for(seed)).unwrap();
            assert!(
                hal_emu::judge::expected_without(&p, &r).is_some(),
                "seed {seed}"
            );
        }
        let reboot = SCENARIOS.iter().find(|s| s.name == "reboot").unwrap();
        let (cfg, t) = config(reboot, 3, None).unwrap();
        let t = t.unwrap();
        assert!((800..=1400).contains(&(t.as_millis() / 1000)));
        assert_eq!(cfg.restarts, vec![(t + REBOOT_DOWN, cfg.kills[0].1)]);
    }

    #[test]
    fn a_run_in_which_a_robot_panicked_fails_and_is_listed_with_its_replay() {
        let scenario = SCENARIOS.iter().find(|s| s.name == "loss-10").unwrap();
        let (cfg, _) = config(scenario, 7, None).unwrap();
        // What `hal_emu::run` returns when robot 2's task panics (hal-emu's arena tests
        // inject one); `outcome` turns it into this.
        let f = RobotFailure {
            robot: 2,
            seed: 7,
            panicked: true,
            message: "index out of bounds".into(),
        };
        let o = crashed(&cfg, &f);
        assert!(!o.success && o.crashed);
        assert_eq!((o.seed, o.pattern.as_str()), (7, pattern_for(7)));
        assert_eq!(o.leds, "????");
        assert_eq!(o.expected, "LLLL", "pattern 0111");
        let line = failure_line(scenario.name, &o, None, Decide::Fixed);
        assert_eq!(
            line,
            "seed 7: pattern 0111, LEDs ????, expected LLLL (robot 2 panicked: index out of \
             bounds); replay: `cimax arena campaign --scenario loss-10 --seed 7 --seeds 1 \
             --decide fixed`"
        );
        // Listed among the failing seeds, and it counts against the bar.
        let report = Report {
            plan: Plan {
                scenarios: vec![0],
                seed: 7,
                seeds: 1,
                loss: None,
                decide: Decide::Fixed,
            },
            results: vec![ScenarioResult {
                scenario: *scenario,
                runs: vec![o],
            }],
            wall_s: 0.0,
            threads: 1,
        };
        let failing = failing_seeds(&report);
        assert_eq!(failing.len(), 1);
        assert_eq!((failing[0].scenario, failing[0].failed), ("loss-10", 1));
        assert_eq!(failing[0].lines, [line]);
        assert!(markdown(&report, None).contains("## Failing seeds\n\n**`loss-10`** (1 of 1):"));
        assert_eq!(report.results[0].rate(), 0.0);
    }

    #[test]
    fn text_bars_mark_the_bar() {
        assert_eq!(text_bar(1.0, Some(0.5), 10), "#####|#####");
        assert_eq!(text_bar(0.2, Some(0.99), 10), "##........|");
        assert_eq!(text_bar(0.2, None, 10), "##........");
    }
}
