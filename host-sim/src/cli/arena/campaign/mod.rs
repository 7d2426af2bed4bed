//! `cimax arena campaign`: runs the fault campaign ([`lab::campaign`]) under one
//! rule or both, prints its tables, writes `docs/reliability.md`
//! ([`pages::reliability`]) with its figures, and exits 1 if a bar is missed or a robot
//! crashed. With `--shard I/N` it runs only its share of the runs into a part ([`job`]), and
//! `cimax merge` of the parts ([`merge`]) prints, writes and exits as the whole campaign would.

mod job;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use clap::builder::PossibleValuesParser;
use hal_emu::judge::judge;
use hal_emu::world::hil::HilSpec;

use crate::cli::arena::options::in_the_loop;
use host_sim::shard::{self, Job, ShardSpec, Timing, merge::Merged};
use job::{CampaignJob, Results};
use lab::campaign::{Decide, Plan, Report, SCENARIOS, Scenario, run_config};
use pages::figures::{rules_chart, success_chart};
use pages::reliability::{
    Page, campaign_section, failure_line, missed_line, rules_section, secs, suite_section, table,
};
use swarm_sim::progress::Progress;

use crate::cli::files::{self, Staged};
use crate::cli::out::{Exit, StdoutError, outln};

/// The job's command in a part's header.
pub const COMMAND: &str = "arena campaign";

/// Options of `cimax arena campaign`.
#[derive(Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
pub struct CampaignArgs {
    /// Seeds per scenario: run k of every scenario uses seed BASE + k.
    #[arg(long, default_value_t = lab::campaign::SEEDS, value_parser = crate::cli::values::whole::<u64>(1, 100_000))]
    pub seeds: u64,
    /// Base seed.
    #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
    pub seed: u64,
    /// Run only this scenario (repeatable); default: all.
    #[arg(long, value_parser = PossibleValuesParser::new(SCENARIOS.iter().map(|s| s.name)))]
    pub scenario: Vec<String>,
    /// Frame loss at every receiver in every scenario, replacing the scenario's own.
    #[arg(long, value_parser = crate::cli::values::number(0.0, 1.0, "a probability"))]
    pub loss: Option<f64>,
    /// Run only this decision rule (docs/protocol.md §5.4); default: both, side by side (the
    /// documented campaign).
    #[arg(long, value_enum)]
    pub decide: Option<Decide>,
    /// The Markdown report (default: docs/reliability.md of the checkout cimax was built from,
    /// for the documented campaign only, every scenario over 200 seeds from seed 1 at the
    /// scenarios' own loss, and only when run inside that checkout; any other campaign writes
    /// nothing unless --out is given). With both rules, the lab suite's counts go to
    /// data/lab-suite.json beside it (the reproduction page's lab row reads them). With --shard,
    /// the directory of the part. Missing folders are created.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The SVG chart (default: figures/reliability.svg beside the report).
    #[arg(long)]
    pub figure: Option<PathBuf>,
    /// Write the trace of the first run as JSON lines (to look into a replayed seed).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Run only shard I of N (1 <= I <= N) of the campaign's runs (and of its page's lab suite
    /// and loss sweep) and write them to OUT/part-I-of-N.jsonl, nothing else; `cimax merge
    /// PARTS --out DIR` then writes DIR/reliability.md and its figures.
    #[arg(long, value_name = "I/N", requires = "out", conflicts_with_all = ["figure", "trace"])]
    pub shard: Option<ShardSpec>,
    /// Robots in the loop in every run of every scenario, on the arena's clock (docs/hil.md):
    /// `qemu:N` (N QEMU robots running the Cortex-M HIL image, `cargo hil-image`) or
    /// `loopback:N` (its host build in this process). They take the places of the robot the
    /// scenario reboots first, then of the living robots from the left, the robot dead from
    /// the start last. Not in the page's lab suite and loss sweep.
    #[arg(long, value_name = "qemu:N|loopback:N")]
    pub hil: Option<HilSpec>,
    /// The image --hil qemu:N boots (default: the one `cargo hil-image` builds).
    #[arg(long, value_name = "ELF", requires = "hil")]
    pub hil_image: Option<PathBuf>,
    /// The parts (several after one --hil-part, or repeat it; every shard of one job, in any
    /// order: a shell glob will do) of this campaign made with --hil
    /// over some of its seeds: the page gains a section setting those runs in the loop beside
    /// its own host-build runs of the same seeds (docs/reliability.md, "The Cortex-M build in
    /// the loop", from the committed docs/data/campaign-qemu-200/part-I-of-10.jsonl). Read and
    /// checked before any run.
    #[arg(long, value_name = "PART", num_args = 1.., conflicts_with_all = ["shard", "hil"])]
    pub hil_part: Vec<PathBuf>,
    /// With --shard: the campaign's runs only, without the page's lab suite and loss sweep (a
    /// part for --hil-part, a fifth of the size; `cimax merge` refuses it: it has no page).
    #[arg(long, requires = "shard")]
    pub runs_only: bool,
}

/// The runs in the loop of `--hil-part`, as the page sets them beside its own.
struct LoopPart {
    /// The parts, in shard order.
    paths: Vec<PathBuf>,
    /// One report per rule.
    reports: Vec<Report>,
    /// The command that made it.
    made_by: String,
    /// Its wall time, s.
    wall_s: f64,
}

/// `p` with forward slashes (the page's paths read the same on every system).
fn slashed(p: &Path) -> String {
    p.to_string_lossy().replace('\\', "/")
}

/// The folder of the parts `paths` (in shard order) when they are the N > 1 parts of one
/// folder under their own names, `DIR/part-I-of-N.jsonl`.
fn parts_folder(paths: &[PathBuf]) -> Option<&Path> {
    let n = paths.len();
    let dir = paths.first().and_then(|p| p.parent());
    let own_names = n > 1
        && paths.iter().enumerate().all(|(i, p)| {
            p.parent() == dir
                && p.file_name()
                    == Some(std::ffi::OsStr::new(&format!(
                        "part-{}-of-{n}.jsonl",
                        i + 1
                    )))
        });
    dir.filter(|_| own_names)
}

/// The parts `paths` (in shard order) as the page names them: `DIR/part-I-of-N.jsonl, I = 1
/// to N` for the parts of one folder ([`parts_folder`]), else [`shown`].
fn parts_named(paths: &[PathBuf]) -> String {
    let n = paths.len();
    match parts_folder(paths) {
        Some(d) => format!(
            "{}, I = 1 to {n}",
            slashed(&d.join(format!("part-I-of-{n}.jsonl")))
        ),
        None => shown(paths),
    }
}

/// The `--hil-part` options that give `paths` again: one glob for the parts of one folder
/// ([`parts_folder`]), else one option per part.
fn hil_part_options(paths: &[PathBuf]) -> String {
    match parts_folder(paths) {
        Some(d) => format!(
            " --hil-part {}",
            slashed(&d.join(format!("part-*-of-{}.jsonl", paths.len())))
        ),
        None => paths
            .iter()
            .map(|p| format!(" --hil-part {}", slashed(p)))
            .collect(),
    }
}

/// `paths`, [`slashed`], comma-separated.
fn shown(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| slashed(p))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads the `--hil-part`s `paths`: every shard of one campaign made with `--hil`, of the
/// same scenarios, rules and loss as `job`, over seeds `job` runs too.
///
/// # Errors
/// The paths and what is wrong with them.
fn read_loop_part(paths: &[PathBuf], job: &CampaignJob) -> Result<LoopPart, String> {
    let named = |e: &dyn std::fmt::Display| format!("--hil-part {}: {e}", shown(paths));
    let m = shard::merge::merge(paths).map_err(|e| named(&e))?;
    if m.job.command != COMMAND {
        return Err(named(&format!(
            "a part of `cimax {}`, not of `cimax {COMMAND}`",
            m.job.command
        )));
    }
    let (part, units): (CampaignJob, Vec<job::Unit>) = m.decode().map_err(|e| named(&e))?;
    let Some(hil) = &part.hil else {
        return Err(named(
            &"a campaign without robots in the loop (made without --hil)",
        ));
    };
    if part.scenarios != job.scenarios || part.rules != job.rules || part.loss != job.loss {
        return Err(named(
            &"its scenarios, rules or loss are not this campaign's (it must be made with the \
              same options but --hil, --seeds and --seed)",
        ));
    }
    // A part file is input: its seed count may be anything (0 too).
    let Some(more) = part.seeds.checked_sub(1) else {
        return Err(named(&"it holds no seeds"));
    };
    let (first, last) = (part.seed, part.seed.saturating_add(more));
    if first < job.seed || last > job.seed.saturating_add(job.seeds - 1) {
        return Err(named(&format!(
            "its seeds {first} to {last} are not all among this campaign's ({} to {})",
            job.seed,
            job.seed.saturating_add(job.seeds - 1)
        )));
    }
    let plans = part.plans().map_err(|e| named(&e))?;
    let timing = Timing {
        wall_s: m.wall_s,
        threads: m.threads,
    };
    let results = part
        .assemble(&plans, units, timing)
        .map_err(|e| named(&e))?;
    let mut made_by = "cimax arena campaign".to_string();
    if part.scenarios.len() != SCENARIOS.len() {
        for s in &part.scenarios {
            made_by.push_str(&format!(" --scenario {s}"));
        }
    }
    if let [rule] = part.rules.as_slice() {
        made_by.push_str(&format!(" --decide {}", rule.name()));
    }
    if let Some(loss) = part.loss {
        made_by.push_str(&format!(" --loss {loss}"));
    }
    made_by.push_str(&format!(" --hil {} --seeds {}", hil.spec(), part.seeds));
    if part.seed != 1 {
        made_by.push_str(&format!(" --seed {}", part.seed));
    }
    if !part.page {
        made_by.push_str(" --runs-only");
    }
    match m.parts.len() {
        1 => made_by.push_str(" --shard 1/1 --out DIR"),
        n => made_by.push_str(&format!(" --shard I/{n} --out DIR, I = 1 to {n}")),
    }
    Ok(LoopPart {
        paths: m.parts.clone(),
        reports: results.reports,
        made_by,
        wall_s: m.wall_s,
    })
}

/// Runs `cimax arena campaign`: 0 if every bar is met, 1 if one is missed or a robot crashed
/// in a run ([`lab::campaign::Outcome::crashed`]), 2 for bad options. A shard: 0 once its part is
/// written.
pub(super) fn main(args: &CampaignArgs) -> Exit {
    run(args)
}

/// The campaign the options ask for, whole (every unit, then [`finish`]) or one shard.
fn run(args: &CampaignArgs) -> Exit {
    let page = if args.shard.is_some() {
        None
    } else {
        page_path(args)?
    };
    check_paths(args, page.as_deref())?;
    let job = CampaignJob {
        scenarios: selected(args)
            .into_iter()
            .map(|i| SCENARIOS[i].name.to_string())
            .collect(),
        seed: args.seed,
        seeds: args.seeds,
        loss: args.loss,
        rules: args
            .decide
            .map_or(vec![Decide::Fixed, Decide::Adaptive], |d| vec![d]),
        page: (args.shard.is_some() && !args.runs_only) || page.is_some(),
        hil: in_the_loop(
            args.hil.as_ref(),
            args.hil_image.as_ref(),
            2,
            hal_emu::judge::PAPER_PATTERNS[0].len(),
        )?,
    };
    let in_loop = match args.hil_part.as_slice() {
        [] => None,
        _ if page.is_none() => {
            return Err(
                "--hil-part: only with the page (--out, or the documented campaign)".into(),
            );
        }
        parts => Some(read_loop_part(parts, &job)?),
    };
    let plans = job.plans()?;
    let total = job.units();
    let unit = |k| job.unit(&plans, k);
    if let (Some(shard), Some(dir)) = (args.shard, &args.out) {
        let config = Job::new(COMMAND, &job).map_err(|e| e.to_string())?;
        let path =
            shard::run_shard(config, total, shard, dir, false, unit).map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
        return Ok(ExitCode::SUCCESS);
    }
    let wall = std::time::Instant::now();
    let progress = if total > 1 {
        Progress::new(total, "campaign", false)
    } else {
        Progress::hidden()
    };
    let all: Vec<u64> = (0..total).collect();
    let units = shard::compute(&all, &progress, unit)?;
    let timing = Timing {
        wall_s: wall.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    };
    if let Some(path) = &args.trace {
        for plan in &plans {
            if let Some(&s) = plan.scenarios.first() {
                write_trace(&SCENARIOS[s], plan, path)?;
            }
        }
    }
    let results = job.assemble(&plans, units, timing)?;
    finish(
        &results,
        page.map(|out| (out, args.figure.clone())),
        in_loop.as_ref(),
    )
}

/// `cimax merge` of a campaign's parts: prints its tables, writes `OUT/reliability.md` with its
/// figures in `OUT/figures/`, and gives the exit code, as the unsharded campaign with `--out
/// OUT/reliability.md` does. The page's wall time is the shards' added up.
///
/// # Errors
/// If the parts are not a campaign this cimax can write.
pub fn merge(m: &Merged, out: &Path) -> Exit {
    let (job, units): (CampaignJob, Vec<job::Unit>) = m.decode().map_err(|e| e.to_string())?;
    if !job.page {
        return Err(m
            .bad_config("a campaign without its page")
            .to_string()
            .into());
    }
    let plans = job.plans().map_err(|e| m.bad_config(e).to_string())?;
    let timing = Timing {
        wall_s: m.wall_s,
        threads: m.threads,
    };
    let results = job
        .assemble(&plans, units, timing)
        .map_err(|e| m.bad_config(e).to_string())?;
    finish(&results, Some((out.join("reliability.md"), None)), None)
}

/// What the campaign does with its results, whole or merged: prints each rule's table, writes
/// the page (`page`: where, and the figure if not beside it), prints the failures; 0 if every
/// bar is met, 1 if not or a robot crashed, 2 if the page cannot be written.
fn finish(
    results: &Results,
    page: Option<(PathBuf, Option<PathBuf>)>,
    in_loop: Option<&LoopPart>,
) -> Exit {
    for report in &results.reports {
        print_report(report)?;
    }
    let mut failed = false;
    if let Some((out, figure)) = page {
        match write_page(results, &out, figure, in_loop) {
            Ok((missed, wrote)) => {
                outln!("{wrote}")?;
                for m in missed {
                    eprintln!("{m}");
                    failed = true;
                }
            }
            Err(e) => {
                return Err(format!("{}: {e}", out.display()).into());
            }
        }
    }
    failed |= print_failures(&results.reports);
    Ok(if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
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
fn page_path(args: &CampaignArgs) -> Result<Option<PathBuf>, String> {
    let documented = args.scenario.is_empty()
        && args.seeds == lab::campaign::SEEDS
        && args.seed == 1
        && args.loss.is_none()
        && args.decide.is_none();
    if args.out.is_some() || !documented {
        return Ok(args.out.clone());
    }
    Ok(Some(
        files::checkout_docs("--out FILE.md")?.join("reliability.md"),
    ))
}

/// The campaign's output paths, checked before any work: the page and its figures, the
/// trace, or with `--shard` the part's folder.
fn check_paths(args: &CampaignArgs, page: Option<&Path>) -> Result<(), String> {
    if let (Some(_), Some(dir)) = (args.shard, &args.out) {
        return files::check_dir("--out", dir);
    }
    let mut all: Vec<(&str, PathBuf)> = Vec::new();
    if let Some(out) = page {
        let figure = figure_path(out, args.figure.clone());
        all.push(("--out", out.to_path_buf()));
        all.push(("--figure", figure.with_file_name("reliability-rules.svg")));
        all.push(("--figure", figure));
        all.push(("--out", suite_path(out)));
    }
    if let Some(t) = &args.trace {
        all.push(("--trace", t.clone()));
    }
    let all: Vec<(&str, &Path)> = all.iter().map(|(o, p)| (*o, p.as_path())).collect();
    for (option, p) in &all {
        files::check_file(option, p)?;
    }
    files::check_distinct(&all)
}

/// The chart of page `out`: `figure`, or `figures/reliability.svg` beside the page.
fn figure_path(out: &Path, figure: Option<PathBuf>) -> PathBuf {
    figure.unwrap_or_else(|| {
        out.parent()
            .unwrap_or(Path::new("."))
            .join("figures")
            .join("reliability.svg")
    })
}

/// The lab suite's counts of page `out` ([`lab::campaign::SuiteFile`]): `data/lab-suite.json`
/// beside the page, which the reproduction page's lab row reads.
fn suite_path(out: &Path) -> PathBuf {
    out.parent()
        .unwrap_or(Path::new("."))
        .join("data")
        .join("lab-suite.json")
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
                    failure_line(r.scenario.name, o, plan).replace('`', "")
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

/// Prints one rule's table (and each run, for a single seed).
fn print_report(report: &Report) -> Result<(), StdoutError> {
    let plan = &report.plan;
    outln!(
        "CIMAX fault campaign, {} rule: {} scenarios x {} seeds in the emulated arena{} ({:.1} s wall, {} threads)",
        plan.decide.name(),
        plan.scenarios.len(),
        plan.seeds,
        plan.hil
            .as_ref()
            .map_or(String::new(), |h| format!(", {} in the loop", h.spec())),
        report.wall_s,
        report.threads
    )?;
    crate::cli::out::text(&table(report))?;
    if plan.seeds == 1 {
        for r in &report.results {
            for o in &r.runs {
                outln!(
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
                )?;
            }
        }
    }
    Ok(())
}

/// Writes the page `out` with its figures beside it (`figures/reliability.svg`, or `figure`,
/// and `reliability-rules.svg` next to it): the first report's page and, with two rules, the
/// section setting them side by side, the lab suite's sections and the loss sweep's.
///
/// Returns the lab suite's missed bars, one line each, and the line that says what was written.
fn write_page(
    results: &Results,
    out: &Path,
    figure: Option<PathBuf>,
    in_loop: Option<&LoopPart>,
) -> Result<(Vec<String>, String), String> {
    let mut missed = Vec::new();
    let reports = &results.reports;
    let Some(first) = reports.first() else {
        return Ok((missed, String::new()));
    };
    let figure = figure_path(out, figure);
    let rules_figure = figure.with_file_name("reliability-rules.svg");
    let mut staged = Staged::new();
    staged.write_with(&figure, |p| success_chart(first, p))?;
    let mut page = Page {
        campaign: campaign_section(first, Some(&relative(&figure, out))),
        rules: None,
        suites: Vec::new(),
        initiations: None,
        loss: None,
        in_the_loop: None,
    };
    if let Some(l) = in_loop {
        let part = parts_named(&l.paths);
        page.in_the_loop = Some(
            pages::reliability::in_the_loop::loop_section(
                &l.reports,
                reports,
                &part,
                l.paths.len(),
                l.made_by.clone(),
                l.wall_s,
            )
            .map_err(|e| format!("--hil-part {part}: {e}"))?,
        );
        page.campaign.command.push_str(&hil_part_options(&l.paths));
    }
    let wrote = if let [fixed, adaptive] = reports.as_slice() {
        staged.write_with(&rules_figure, |p| rules_chart(fixed, adaptive, p))?;
        page.rules = Some(rules_section(
            fixed,
            adaptive,
            Some(&relative(&rules_figure, out)),
        ));
        let suite = suite_path(out);
        let counts = lab::campaign::SuiteFile::new(fixed.plan.seeds, &results.suites);
        staged.write(&suite, counts.to_json())?;
        for (readings, f, a) in &results.suites {
            let section = suite_section(f, a, *readings, fixed.plan.seeds);
            missed.extend(section.missed.iter().map(|m| m.replace('`', "")));
            page.suites.push(section);
        }
        page.initiations = Some(pages::reliability::stress::initiations_section(
            fixed, adaptive,
        ));
        page.loss = results
            .loss
            .as_ref()
            .map(|(f, a, seeds)| pages::reliability::stress::loss_section(f, a, *seeds));
        format!(
            "wrote {}, {}, {} and {}",
            out.display(),
            figure.display(),
            rules_figure.display(),
            suite.display()
        )
    } else {
        format!("wrote {} and {}", out.display(), figure.display())
    };
    staged.write(out, page.render().map_err(|e| e.to_string())?)?;
    staged.commit()?;
    Ok((missed, wrote))
}

/// Runs the first seed of `plan` for `scenario` again with its trace on, and writes the trace to `path` as
/// JSON lines, the run's set-up first as `cimax arena --trace` writes it (so that `cimax view`
/// opens it).
fn write_trace(scenario: &Scenario, plan: &Plan, path: &Path) -> Result<(), String> {
    let (seed, decide) = (plan.seed, plan.decide);
    let (mut cfg, _) = run_config(scenario, seed, plan.loss, decide, plan.hil.as_ref())
        .map_err(|e| e.to_string())?;
    cfg.trace = true;
    let run = judge(&cfg).map_err(|e| e.to_string())?;
    let mut header = viewer::header_of(&cfg, &run.report.trace);
    header.title = format!(
        "cimax arena campaign: scenario {}, seed {seed}, {} rule",
        scenario.name,
        decide.name()
    );
    let mut staged = Staged::new();
    staged.write_with(path, |p| viewer::write_trace(p, header, &run.report.trace))?;
    staged.commit()
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
