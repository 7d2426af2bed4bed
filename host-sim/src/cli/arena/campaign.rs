//! `cimax arena campaign`: runs the fault campaign ([`host_sim::arena::campaign`]) under one
//! rule or both, prints its tables, writes `docs/reliability.md`
//! ([`host_sim::pages::reliability`]) with its figures, and exits 1 if a bar is missed or a robot
//! crashed.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use clap::builder::PossibleValuesParser;
use hal_emu::judge::judge;
use host_sim::arena::campaign::{
    self, Decide, Plan, Report, SCENARIOS, SUITE_READINGS, Scenario, config, lab_suite,
};
use host_sim::arena::stress;
use host_sim::pages::figures::{rules_chart, success_chart};
use host_sim::pages::reliability::{
    Page, campaign_section, failure_line, missed_line, rules_section, secs, suite_section, table,
};
use host_sim::progress::Progress;

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

/// Runs `cimax arena campaign`: 0 if every bar is met, 1 if one is missed or a robot crashed
/// in a run ([`campaign::Outcome::crashed`]), 2 for bad options.
pub(super) fn main(args: &CampaignArgs) -> ExitCode {
    let scenarios = selected(args);
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
    let mut failed = false;
    if let Some(out) = page_path(args) {
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
    failed |= print_failures(&reports);
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// The scenarios `--scenario` names, in [`SCENARIOS`] order, each once; all without it.
fn selected(args: &CampaignArgs) -> Vec<usize> {
    if args.scenario.is_empty() {
        return (0..SCENARIOS.len()).collect();
    }
    let mut v: Vec<usize> = args
        .scenario
        .iter()
        .filter_map(|n| SCENARIOS.iter().position(|s| s.name == n))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Where the page goes: `--out`, or `docs/reliability.md` for the documented campaign (every
/// scenario, 200 seeds from seed 1, the scenarios' own loss, both rules); else nowhere.
fn page_path(args: &CampaignArgs) -> Option<PathBuf> {
    let documented = args.scenario.is_empty()
        && args.seeds == 200
        && args.seed == 1
        && args.loss.is_none()
        && args.decide.is_none();
    args.out
        .clone()
        .or_else(|| documented.then(|| host_sim::report::default_docs_dir().join("reliability.md")))
}

/// Prints every failed run and missed bar of `reports` on stderr; `true` if one counts against
/// the exit code (a crashed run, a missed bar).
fn print_failures(reports: &[Report]) -> bool {
    let mut failed = false;
    for report in reports {
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
    failed
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
    let report = campaign::run(plan, &progress).map_err(|e| {
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
    success_chart(first, &figure).map_err(|e| e.to_string())?;
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
        page.initiations = Some(host_sim::pages::reliability::stress::initiations_section(
            fixed, adaptive,
        ));
        let sweep_seeds = seeds.min(stress::SWEEP_SEEDS);
        let f = stress::loss_sweep(Decide::Fixed, seed, sweep_seeds)?;
        let a = stress::loss_sweep(Decide::Adaptive, seed, sweep_seeds)?;
        page.loss = Some(host_sim::pages::reliability::stress::loss_section(
            &f,
            &a,
            sweep_seeds,
        ));
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

/// Runs seed `seed` of `scenario` again with its trace on, and writes the trace to `path` as
/// JSON lines.
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

/// Creates the directory `p` goes in, if it has one.
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
