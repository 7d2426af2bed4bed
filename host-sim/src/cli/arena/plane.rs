//! `cimax arena --field ...` and `cimax arena bench`: robots on a plane over one of the 2D
//! simulator's fields ([`lab::plane`]), as the options ask, printed. `cimax arena
//! sweep` is [`super::sweep`].

use std::process::ExitCode;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use firmware::Config;
use hal_emu::MediumParams;
use lab::plane::{self, Layout, PlaneRun, PlaneSpec};
use protocol::Params;
use rayon::prelude::*;
use serde::Serialize;
use swarm_sim::scenario::{Placement, Scenario};

use super::ArenaArgs;
use super::options::{hil_robots, medium, robot_params, scaled, time_scale};
use crate::cli::out::{Exit, StdoutError, outln};

/// `--shape`: how the robots are placed on the plane, as typed (`line`, `lattice`, `disk`,
/// `file`), each with its help.
pub(super) fn shape_parser() -> impl TypedValueParser<Value = Layout> {
    PossibleValuesParser::new([
        PossibleValue::new("line").help("In a line along x, 0.75 R apart"),
        PossibleValue::new("lattice").help(
            "The nodes of a triangular lattice of spacing 0.75 R nearest the centre (61: the \
             paper's disk of 6 R)",
        ),
        PossibleValue::new("disk").help(
            "Uniformly at random in a disk with the density of the paper's (61 robots in 6 R), \
             redrawn until connected",
        ),
        PossibleValue::new("file")
            .help("Where a file says (`--positions FILE`, [`read_positions`])"),
    ])
    .map(|s| match s.as_str() {
        "line" => Layout::Line,
        "disk" => Layout::Placed(Placement::Random),
        "file" => Layout::File,
        _ => Layout::Placed(Placement::Lattice),
    })
}

/// `cimax arena --field ...`: robots on a plane over a field, moving as they decide.
pub(super) fn main(args: &ArenaArgs) -> Exit {
    let spec = plane_spec(args)?;
    super::line::check_artifacts(args)?;
    let wall = std::time::Instant::now();
    let seeds: Vec<u64> = (0..args.runs).map(|k| args.seed.wrapping_add(k)).collect();
    // A bar of runs on a terminal (61 robots: about half a second a run).
    let bar = swarm_sim::progress::Progress::new(seeds.len() as u64, "arena plane", false);
    let one = |s: u64| {
        let r = plane::run(&spec, s);
        bar.inc();
        r
    };
    // With robots in the loop, in real time and one run at a time.
    let results: Result<Vec<_>, _> = if spec.hil.is_empty() {
        seeds.par_iter().map(|&s| one(s)).collect()
    } else {
        seeds.iter().map(|&s| one(s)).collect()
    };
    bar.finish();
    let runs = results.map_err(|e| e.to_string())?;
    plane_artifacts(args, &spec)?;
    print_runs(&spec, &runs, wall.elapsed().as_secs_f64(), args.json)
}

/// `--trace` and `--html` of a plane's first run (run again with tracing on; `--svg` draws
/// lines only).
fn plane_artifacts(args: &ArenaArgs, spec: &PlaneSpec) -> Result<(), String> {
    if args.trace.is_none() && args.html.is_none() {
        return Ok(());
    }
    let (run, cfg, trace) = plane::run_traced(spec, args.seed, true).map_err(|e| e.to_string())?;
    let header = plane::viewer_header(spec, &cfg, &run, &trace);
    let mut staged = crate::cli::files::Staged::new();
    if let Some(path) = &args.trace {
        staged.write_with(path, |p| viewer::write_trace(p, header.clone(), &trace))?;
    }
    if let Some(path) = &args.html {
        staged.write_with(path, |p| viewer::write_page(p, header, &trace))?;
    }
    staged.commit()
}

/// The plane experiment the options describe.
pub(super) fn plane_spec(args: &ArenaArgs) -> Result<PlaneSpec, String> {
    let field = args.field.as_deref().unwrap_or("sharp");
    let scenario = Scenario::load(field).map_err(|e| e.to_string())?;
    if !args.x_init.is_finite() {
        return Err(format!(
            "--x-init must be a number of R, not {}",
            args.x_init
        ));
    }
    if args.lights.is_some()
        || args.then.is_some()
        || !args.kill.is_empty()
        || !args.restart.is_empty()
        || args.svg.is_some()
    {
        return Err(
            "--field runs over a field: --lights, --then, --kill, --restart and --svg (a line's \
             timeline; see --html) do not apply"
                .into(),
        );
    }
    // Options of a line that a plane has in other terms, refused rather than ignored.
    let line_only = [
        (
            args.duration.is_some(),
            "--duration (a plane runs --moves negotiation periods)",
        ),
        (
            args.key.is_some(),
            "--key (the robots on a plane run without a swarm key)",
        ),
        (
            args.spacing != 1.0,
            "--spacing (robots on a plane are placed by --shape, in R; --range sets R in metres)",
        ),
    ];
    if let Some((_, what)) = line_only.iter().find(|(given, _)| *given) {
        return Err(format!("--field runs over a field: {what} does not apply"));
    }
    // The timing options as on a line (`--cycle` scales what the others leave out).
    let mut params = robot_params(args)?;
    let medium = medium(args)?;
    params.sectors = args.sectors;
    params
        .validate()
        .map_err(|e| format!("protocol parameters: {e}"))?;
    let file_positions = match (&args.positions, args.shape) {
        (Some(path), Layout::File) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            plane::read_positions(&text, &path.display().to_string()).map_err(|e| e.to_string())?
        }
        (None, Layout::File) => return Err("--shape file needs --positions FILE".into()),
        (Some(_), _) => return Err("--positions needs --shape file".into()),
        (None, _) => Vec::new(),
    };
    let robots = if file_positions.is_empty() {
        args.robots.map_or(61, usize::from)
    } else {
        file_positions.len()
    };
    Ok(PlaneSpec {
        file_positions,
        scenario,
        placement: args.shape,
        robots,
        sectors: args.sectors,
        x_init: args.x_init,
        moves: args.moves,
        medium,
        params,
        readings: args.readings(),
        hil: hil_robots(args, robots, args.sectors)?,
        sample_period: args
            .cycle
            .map(|_| time_scale(args).map(|s| scaled(Config::robots().sample_period, s)))
            .transpose()?,
    })
}

/// Prints the runs of one plane experiment (a table, or JSON with `json`); exit code 0, or 2 if
/// the JSON cannot be written.
fn print_runs(spec: &PlaneSpec, runs: &[PlaneRun], wall_s: f64, json: bool) -> Exit {
    let ok = runs.iter().filter(|r| r.success).count();
    let emulated: f64 = runs.iter().map(|r| r.emulated_s).sum();
    let mean_moves = mean(
        runs.iter()
            .filter_map(|r| r.moves_to_success.map(f64::from)),
    );
    if json {
        let summary = PlaneSummary {
            runs: runs.len(),
            successes: ok,
            mean_moves_to_success: mean_moves,
            emulated_s: emulated,
            wall_s,
            robot_s_per_wall_s: emulated * spec.robots as f64 / wall_s.max(1e-9),
        };
        let text = serde_json::to_string_pretty(&PlaneReport { runs, summary })
            .map_err(|e| e.to_string())?;
        outln!("{text}")?;
        return Ok(ExitCode::SUCCESS);
    }
    print_run_table(spec, runs)?;
    outln!(
        "{} runs, {} successful ({}); mean moves to success {}; {:.0} robot-s in {:.1} s wall",
        runs.len(),
        ok,
        spec.scenario
            .success
            .map_or("no criterion".into(), |s| s.to_string()),
        mean_moves.map_or("-".into(), |m| format!("{m:.1}")),
        emulated * spec.robots as f64,
        wall_s
    )?;
    Ok(ExitCode::SUCCESS)
}

/// The `--json` summary of a plane experiment.
#[derive(Serialize)]
struct PlaneSummary {
    runs: usize,
    successes: usize,
    mean_moves_to_success: Option<f64>,
    emulated_s: f64,
    wall_s: f64,
    robot_s_per_wall_s: f64,
}

/// The `--json` report of a plane experiment: every run and the summary.
#[derive(Serialize)]
struct PlaneReport<'a> {
    runs: &'a [PlaneRun],
    summary: PlaneSummary,
}

/// The table of a plane experiment's runs, one line per run (and per robot in the loop).
fn print_run_table(spec: &PlaneSpec, runs: &[PlaneRun]) -> Result<(), StdoutError> {
    outln!(
        "CIMAX arena on a plane, the robot program on {} of {} R",
        spec.summary(),
        spec.scenario.run.step
    )?;
    outln!("seed      success  moves  final x  final y  mean consensus")?;
    for r in runs {
        outln!(
            "{:<9} {:<8} {:>5}  {:>7.2}  {:>7.2}  {:>14.2}",
            r.seed,
            if r.success { "yes" } else { "no" },
            r.moves_to_success.map_or("-".into(), |m| m.to_string()),
            r.final_position[0],
            r.final_position[1],
            mean(r.consensus.iter().copied()).unwrap_or(0.0)
        )?;
        for h in &r.hil {
            outln!(
                "  robot {} in the loop over {}: {} link frames sent to it, {} received ({} light frames), {} link errors",
                h.robot,
                h.transport,
                h.frames_sent,
                h.frames_received,
                h.tx,
                h.link_errors
            )?;
        }
    }
    Ok(())
}

/// The mean of `xs`, `None` if empty.
fn mean(xs: impl Iterator<Item = f64>) -> Option<f64> {
    swarm_sim::stats::mean(&xs.collect::<Vec<_>>())
}

/// Options of `cimax arena bench`.
#[derive(clap::Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
pub struct BenchArgs {
    /// Swarm sizes to time (robots on the hexagonal lattice), 2 to 10,000 each (docs/plane.md
    /// times 10,000 too).
    #[arg(long, value_delimiter = ',', default_values_t = [4u16, 64, 1000], value_parser = crate::cli::values::whole::<u16>(2, 10_000))]
    pub robots: Vec<u16>,
    /// Receive sectors per robot.
    #[arg(long, default_value_t = 6, value_parser = crate::cli::values::whole::<u8>(2, 8))]
    pub sectors: u8,
    /// Seed.
    #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
    pub seed: u64,
}

/// `cimax arena bench`: robot-seconds per wall second of the robot program over the emulated
/// medium, one negotiation period (550 s) of the sharp field 2 R from the border, on one core
/// (one run at a time on the calling thread).
pub fn bench_main(a: &BenchArgs) -> Exit {
    let scenario = Scenario::load("sharp").map_err(|e| e.to_string())?;
    outln!("robots  emulated s  wall s  robot-s per wall s  x real time")?;
    for &n in &a.robots {
        let spec = PlaneSpec {
            scenario: scenario.clone(),
            placement: Layout::Placed(Placement::Lattice),
            robots: usize::from(n),
            sectors: a.sectors,
            x_init: -2.0,
            moves: 1,
            medium: MediumParams::default(),
            params: Params::robots(),
            file_positions: Vec::new(),
            readings: hal_emu::Readings::Levels,
            hil: Vec::new(),
            sample_period: None,
        };
        let r = plane::run(&spec, a.seed).map_err(|e| e.to_string())?;
        let rate = r.emulated_s * spec.robots as f64 / r.wall_s.max(1e-9);
        outln!(
            "{:>6}  {:>10.0}  {:>6.2}  {:>18.3e}  {:>11.0}",
            spec.robots,
            r.emulated_s,
            r.wall_s,
            rate,
            r.emulated_s / r.wall_s.max(1e-9)
        )?;
    }
    Ok(ExitCode::SUCCESS)
}
