//! `cimax arena` on a line: the paper's suite or one pattern, many seeds, judged by the LEDs;
//! a table or JSON on stdout, the failing runs with their replay commands on stderr, and the
//! first run's trace, replay page and timeline if asked.

use std::process::ExitCode;

use firmware::Config;
use hal_emu::judge::{
    LabExperiment, LabRun, judge, leds_str, paper_suite, parse_pattern, pattern_str,
};
use hal_emu::world::hil::HilRobot;
use hal_emu::{ArenaConfig, ArenaError, MediumParams};
use protocol::{Duration, Instant, Params};

use lab::line::{Experiment, replay_lights};

use super::ArenaArgs;
use super::options::{
    check_kills, hil_robots, medium, robot_params, run_length, scaled, secs, time_scale,
};
use super::print::{
    Crashed, JsonSummary, earlier_pattern_failed, print_failures, print_hil, print_json,
    print_table,
};
use super::replay::replay_options;
use crate::cli::files::{self, Staged};
use crate::cli::out::{Exit, outln};
use clap::ArgMatches;

/// The number of robots in the line (`--robots`, the pattern's length, or 4), 2 to 64.
fn line_robots(args: &ArenaArgs, lights: Option<&[bool]>) -> Result<usize, String> {
    let robots = args
        .robots
        .map(usize::from)
        .or(lights.map(<[bool]>::len))
        .unwrap_or(4);
    if !(2..=64).contains(&robots) {
        return Err(format!("a line needs 2 to 64 robots, not {robots}"));
    }
    Ok(robots)
}

/// The experiments the options ask for: the paper's suite, or one pattern (with its change if
/// `--switch-at --then`), each over `--runs` seeds.
pub(super) fn build(args: &ArenaArgs) -> Result<Vec<Experiment>, String> {
    let params = robot_params(args)?;
    let medium = medium(args)?;
    let run = run_length(args, &params)?;
    let lights = args.lights.as_deref().map(parse_pattern).transpose();
    let lights = lights.map_err(|e| e.to_string())?;
    let robots = line_robots(args, lights.as_deref())?;
    let then = args.then.as_deref().map(parse_pattern).transpose();
    let then = then.map_err(|e| e.to_string())?;
    let setup = LineSetup {
        args,
        params,
        medium,
        hil: hil_robots(args, robots, 2)?,
        sample: scaled(Config::robots().sample_period, time_scale(args)?),
    };
    check_kills(&args.kill, &args.restart)?;
    for &(r, _) in args.kill.iter().chain(&args.restart) {
        if r >= robots {
            return Err(format!(
                "there is no robot {r} to kill or restart (robots are 0..{})",
                robots - 1
            ));
        }
    }
    suite(lights, robots)?
        .iter()
        .map(|e| experiment(&setup, e, then.as_deref(), robots, run))
        .collect()
}

/// The patterns to run: `--lights`, else the paper's suite (for four robots only).
fn suite(lights: Option<Vec<bool>>, robots: usize) -> Result<Vec<LabExperiment>, String> {
    match lights {
        Some(p) => Ok(vec![LabExperiment {
            first: p,
            then: None,
        }]),
        None if robots == 4 => Ok(paper_suite()),
        None => Err(format!(
            "--robots {robots} needs --lights (the paper's patterns are for 4)"
        )),
    }
}

/// `Ok` if pattern `p` (`what`) has one light per robot.
fn check_length(p: &[bool], robots: usize, what: &str) -> Result<(), String> {
    if p.len() == robots {
        Ok(())
    } else {
        Err(format!(
            "{what} {} has {} robots but there are {robots}",
            pattern_str(p),
            p.len()
        ))
    }
}

/// The options' robots, medium, faults and sensors, put on each run of a line.
struct LineSetup<'a> {
    args: &'a ArenaArgs,
    params: Params,
    medium: MediumParams,
    hil: Vec<HilRobot>,
    sample: Duration,
}

impl LineSetup<'_> {
    /// `c`, a run of the experiment, with the options' robots, medium, faults and sensors.
    fn apply(&self, mut c: ArenaConfig) -> ArenaConfig {
        let args = self.args;
        c.robot.params = self.params;
        c.robot.key = args.key;
        c.medium = self.medium;
        c.kills = args
            .kill
            .iter()
            .map(|&(r, t)| (Instant::from_secs(t), r))
            .collect();
        c.restarts = args
            .restart
            .iter()
            .map(|&(r, t)| (Instant::from_secs(t), r))
            .collect();
        c.env.readings = args.readings();
        c.robot.sample_period = self.sample;
        c.hil = self.hil.clone();
        c
    }
}

/// Experiment `e` of the suite over the options' seeds, each run `run` long; `--switch-at
/// --then` changes a single pattern (the suite's alternating experiments have their own change).
fn experiment(
    setup: &LineSetup<'_>,
    e: &LabExperiment,
    then: Option<&[bool]>,
    robots: usize,
    run: Duration,
) -> Result<Experiment, String> {
    let args = setup.args;
    check_length(&e.first, robots, "pattern")?;
    let switch = match (args.switch_at, then, &e.then) {
        (Some(at), Some(t), None) => {
            check_length(t, robots, "--then pattern")?;
            Some((Instant::ZERO + secs(at, "switch-at")?, t))
        }
        _ => None,
    };
    let configs = (0..args.runs)
        .map(|k| args.seed.wrapping_add(k))
        .map(|s| {
            let mut c = setup.apply(e.config(args.spacing, run, s));
            if let Some((at, t)) = switch {
                c.env.schedule.push((at, t.to_vec()));
                c.duration = c.duration.max(at.saturating_since(Instant::ZERO) + run);
            }
            c
        })
        .collect();
    let label = match switch {
        Some((_, t)) => format!("{}>{}", e.label(), pattern_str(t)),
        None => e.label(),
    };
    Ok(Experiment { label, configs })
}

/// `cimax arena` on a line; the exit code is non-zero if any run with a verdict failed or an
/// option was bad.
pub(super) fn main(args: &ArenaArgs, matches: &ArgMatches) -> Exit {
    let experiments = build(args)?;
    check_artifacts(args)?;
    let first = experiments.first().and_then(|e| e.configs.first()).cloned();
    let ((runs, crashed), wall_s) = match run_all(&experiments) {
        Ok(r) => r,
        Err(ArenaError::Interrupted) => {
            eprintln!("cimax arena: interrupted; robots in the loop stopped");
            return Ok(ExitCode::from(130));
        }
        Err(e) => return Err(e.to_string().into()),
    };
    if let Some(cfg) = &first {
        write_artifacts(args, cfg)?;
    }

    let emulated_s: f64 = runs
        .iter()
        .map(|(_, r)| r.report.emulated.as_secs_f64())
        .sum();
    let failures: Vec<(&LabRun, String, Option<String>)> = runs
        .iter()
        .filter(|(_, r)| !r.success)
        .map(|(i, r)| {
            let cfg = experiments[*i].configs.iter().find(|c| c.seed == r.seed);
            let earlier = cfg.and_then(|c| earlier_pattern_failed(c, r));
            (r, cfg.map(replay_lights).unwrap_or_default(), earlier)
        })
        .collect();
    let total = runs.len() + crashed.len();
    // A pattern without a verdict is not judged: neither a success nor a failure.
    let not_judged = runs.iter().filter(|(_, r)| r.expected.is_none()).count();
    let successes = runs
        .iter()
        .filter(|(_, r)| r.success && r.expected.is_some())
        .count();
    if args.json {
        let summary = JsonSummary {
            runs: total,
            successes,
            not_judged,
            emulated_s,
            wall_s,
        };
        print_json(&experiments, &runs, &crashed, summary)?;
    } else {
        print_table(args, &experiments, &runs, &crashed)?;
        print_hil(&runs)?;
        let unjudged = match not_judged {
            0 => String::new(),
            n => format!(", {n} not judged (no verdict for the pattern)"),
        };
        outln!(
            "{} runs, {} successful{unjudged}; {:.0} s of robot time in {:.3} s wall ({:.0}x real time)",
            total,
            successes,
            emulated_s,
            wall_s,
            emulated_s / wall_s.max(1e-9)
        )?;
    }
    print_failures(&replay_options(matches), &failures, &crashed);
    Ok(if failures.is_empty() && crashed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// Judged runs and crashed runs, each with its experiment's index.
pub(super) type Runs = (Vec<(usize, LabRun)>, Vec<(usize, Crashed)>);

/// [`lab::line::run_all`], each crashed run with what the table, JSON and failure lines print
/// of it ([`Crashed`]).
pub(super) fn run_all(experiments: &[Experiment]) -> Result<(Runs, f64), ArenaError> {
    let (runs, wall_s) = lab::line::run_all(experiments)?;
    let crashed = runs
        .crashed
        .into_iter()
        .map(|(i, k, f)| (i, Crashed::new(&experiments[i].configs[k], f)))
        .collect();
    Ok(((runs.judged, crashed), wall_s))
}

/// `--trace`, `--svg` and `--html`, checked before any work: files (their folders are
/// created), each its own.
pub(super) fn check_artifacts(args: &ArenaArgs) -> Result<(), String> {
    let all: Vec<(&str, &std::path::Path)> = [
        ("--trace", &args.trace),
        ("--svg", &args.svg),
        ("--html", &args.html),
    ]
    .into_iter()
    .filter_map(|(o, p)| Some((o, p.as_deref()?)))
    .collect();
    for (option, p) in &all {
        files::check_file(option, p)?;
    }
    files::check_distinct(&all)
}

/// `--trace`, `--html` and `--svg` for the first run (run again with tracing on), moved in
/// together once all are written.
fn write_artifacts(args: &ArenaArgs, cfg: &ArenaConfig) -> Result<(), String> {
    if args.trace.is_none() && args.svg.is_none() && args.html.is_none() {
        return Ok(());
    }
    let mut cfg = cfg.clone();
    cfg.trace = true;
    let run = judge(&cfg).map_err(|e| e.to_string())?;
    let mut staged = Staged::new();
    if args.trace.is_some() || args.html.is_some() {
        let header = lab_header(&cfg, &run, args);
        if let Some(path) = &args.trace {
            staged.write_with(path, |p| {
                viewer::write_trace(p, header.clone(), &run.report.trace)
            })?;
        }
        if let Some(path) = &args.html {
            staged.write_with(path, |p| viewer::write_page(p, header, &run.report.trace))?;
        }
    }
    if let Some(path) = &args.svg {
        staged.write(path, timeline_svg(&cfg, &run))?;
    }
    staged.commit()
}

/// The viewer's header of a lab run: the set-up, a title and the verdict.
fn lab_header(cfg: &ArenaConfig, run: &LabRun, args: &ArenaArgs) -> viewer::Header {
    let mut h = viewer::header_of(cfg, &run.report.trace);
    h.title = format!(
        "cimax arena: {} robots, lights {}, seed {}, {:?} rule",
        cfg.positions.len(),
        replay_lights(cfg).trim_start_matches("--lights "),
        cfg.seed,
        args.decide
    );
    let leds = leds_str(&run.leds);
    let expected = run.expected.as_deref().map(leds_str);
    let text = match (&expected, run.success) {
        (None, _) => format!("no verdict for this pattern; LEDs at the end {leds}"),
        (Some(x), true) => format!(
            "passed: LEDs {leds} as expected ({x}){}",
            run.consensus_s
                .map_or(String::new(), |s| format!(", settled after {s:.0} s"))
        ),
        (Some(x), false) => match run.flicker {
            Some((t, r)) => format!(
                "FAILED: robot {r} changed its LEDs at {t:.0} s after it showed its side; at the end {leds}, expected {x}"
            ),
            None => format!("FAILED: LEDs at the end {leds}, expected {x}"),
        },
    };
    h.verdict = Some(viewer::Verdict {
        success: run.success,
        leds,
        expected,
        text,
    });
    h
}

/// The timeline of `run` as SVG ([`pages::figures::draw_timeline`]); an error is reported on
/// stderr and leaves what was drawn.
fn timeline_svg(cfg: &ArenaConfig, run: &LabRun) -> String {
    let mut svg = String::new();
    if let Err(e) = pages::figures::draw_timeline(cfg, run, &mut svg) {
        eprintln!("cimax arena: timeline: {e}");
    }
    svg
}
