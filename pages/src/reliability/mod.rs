//! The fault campaign ([`lab::campaign`]) as the page `docs/reliability.md` shows it:
//! the view models its templates render (`templates/reliability*.md.j2`), the table printed on
//! stdout, and the lines that name failed runs and missed bars. Its figures are
//! `pages::figures`' [`success_chart`](crate::figures::success_chart) and
//! [`rules_chart`](crate::figures::rules_chart).

pub mod in_the_loop;
pub mod stress;

use std::fmt::Write as _;

use hal_emu::judge::PAPER_PATTERNS;
use hal_emu::{ArenaConfig, Readings};
use protocol::{Duration, Params};
use serde::Serialize;

use lab::campaign::{
    ADVERSARY_AT, Fault, Outcome, Plan, REBOOT_DOWN, Report, SCENARIOS, SUITE_BAR, ScenarioResult,
    SuiteResult, config, replay_command,
};
use swarm_sim::stats::quantile;

/// The command that produced a report.
fn command(plan: &Plan) -> String {
    let mut c = "cargo run --release -p host-sim -- arena campaign".to_string();
    if plan.seeds != lab::campaign::SEEDS {
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
    if let Some(h) = &plan.hil {
        // The rule too: a campaign in the loop is one rule's page.
        let _ = write!(c, " --decide {} --hil {}", plan.decide.name(), h.spec());
    }
    c
}

/// A share (0 to 1) as a percentage with one decimal: `99.5 %`.
pub fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

/// Seconds, whole, or `-` for none.
pub fn secs(x: Option<f64>) -> String {
    x.map_or("-".into(), |s| format!("{s:.0}"))
}

/// PASS, FAIL or `reported` (a scenario without a bar).
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
pub(crate) fn decision_time(o: &Outcome) -> Option<f64> {
    o.restore_s.or(o.consensus_s)
}

/// Median and 95th percentile of `decision_time` (consensus, or restoration after a reboot) over a scenario's runs.
pub fn decision_times(r: &ScenarioResult) -> (Option<f64>, Option<f64>) {
    let t: Vec<f64> = r.runs.iter().filter_map(decision_time).collect();
    (quantile(&t, 0.5), quantile(&t, 0.95))
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
    /// The lab suite under both rules, once per
    /// [`SUITE_READINGS`](lab::campaign::SUITE_READINGS).
    pub suites: Vec<SuiteSection>,
    /// Initiations per negotiation period.
    pub initiations: Option<stress::InitiationsSection>,
    /// The loss sweep.
    pub loss: Option<stress::LossSection>,
    /// The campaign with robots in the loop beside the host build's (`--hil-part`).
    pub in_the_loop: Option<in_the_loop::LoopSection>,
}

impl Page {
    /// Renders the page.
    ///
    /// # Errors
    /// The template engine's error (a bug: the templates are built in).
    pub fn render(&self) -> Result<String, crate::page::RenderError> {
        crate::page::render("reliability.md.j2", self)
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
        in_the_loop: None,
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
                .map(|o| failure_line(r.scenario.name, o, &report.plan))
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

/// One failed run: seed, pattern, LEDs, what was expected and why, and its replay command.
pub fn failure_line(scenario: &str, o: &Outcome, plan: &Plan) -> String {
    format!(
        "seed {}: pattern {}, LEDs {}, expected {} ({}); replay: `{}`",
        o.seed,
        o.pattern,
        o.leds,
        o.expected,
        o.why.as_deref().unwrap_or("failed"),
        replay_command(scenario, o.seed, plan)
    )
}

/// One missed bar: the scenario, its success rate and its bar.
pub fn missed_line(r: &ScenarioResult) -> String {
    format!(
        "bar missed: `{}` succeeded in {} of runs, below its bar of {:.0} %",
        r.scenario.name,
        pct(r.rate()),
        r.scenario.bar.unwrap_or(0.0) * 100.0
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_emu::world::arena::RobotFailure;
    use lab::campaign::{Decide, crashed, pattern_for};

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
        let mut plan = Plan {
            scenarios: vec![0],
            seed: 7,
            seeds: 1,
            loss: None,
            decide: Decide::Fixed,
            hil: Some(lab::campaign::InTheLoop {
                robots: 1,
                image: Some("hil.elf".into()),
            }),
        };
        let in_loop = failure_line(scenario.name, &o, &plan);
        assert!(
            in_loop.ends_with("--decide fixed --hil qemu:1 --hil-image hil.elf`"),
            "{in_loop}"
        );
        plan.hil = None;
        let line = failure_line(scenario.name, &o, &plan);
        assert_eq!(
            line,
            "seed 7: pattern 0111, LEDs ????, expected LLLL (robot 2 panicked: index out of \
             bounds); replay: `cimax arena campaign --scenario loss-10 --seed 7 --seeds 1 \
             --decide fixed`"
        );
        // Listed among the failing seeds, and it counts against the bar.
        let report = Report {
            plan,
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
