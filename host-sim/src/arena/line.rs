//! `cimax arena`: the paper's lab experiment (section 4) in the emulated arena.
//!
//! Virtual robots run the unchanged robot program (`firmware::Robot::run`) on emulated
//! hardware (`hal-emu`): a modulated-light medium with airtime, collisions, loss and byte
//! errors, and light patterns on their sensors. A run is judged by the LEDs, as a person
//! watching the robots would.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::arena::campaign::{ArenaCommand, Decide};
use crate::arena::plane::{Placement, PlaneSpec};
use crate::progress::Progress;
use clap::Args;
use firmware::Config;
use firmware::LedColor;
use hal_emu::judge::{
    LabExperiment, LabRun, judge, leds_str, paper_suite, parse_pattern, pattern_str,
};
use hal_emu::world::arena::RobotFailure;
use hal_emu::world::hil::{HilReport, HilRobot, HilSpec, Transport};
use hal_emu::{ArenaConfig, ArenaError, MediumParams, Readings, TraceEvent};
use plotters::prelude::*;
use protocol::{Duration, Instant, Params, SwarmKey};
use rayon::prelude::*;
use serde::Serialize;

/// The longest emulated run (or phase) `cimax arena` makes, in seconds: 11.6 days of robot time,
/// where the paper's runs last 2101 s. The LED log, the `--trace` and the wall time grow with it;
/// without a bound a huge `--duration` or `--cycle` would run for ever or exhaust memory.
pub const MAX_RUN_SECS: u64 = 1_000_000;

/// Options of `cimax arena`. With none, the paper's suite ([`paper_suite`]): six patterns and
/// the alternating experiment from each to its mirror image, five runs each.
#[derive(Args, Debug, Clone)]
#[command(args_conflicts_with_subcommands = true)]
pub struct ArenaArgs {
    /// Number of robots: in a line with light patterns 2 to 64 (default: the pattern's length,
    /// else 4); with --field 2 to 1000 (default 61).
    #[arg(long, value_parser = clap::value_parser!(u16).range(2..=1000))]
    pub robots: Option<u16>,
    /// With --field: how the robots are placed (a line, the paper's hexagonal lattice 0.75 R
    /// apart, or a random disk of the paper's density).
    #[arg(long, value_enum, default_value_t = Placement::Lattice, requires = "field")]
    pub shape: Placement,
    /// With --field --shape file: the robots' positions, one `x y` per line, in R.
    #[arg(long, value_name = "FILE", requires = "field")]
    pub positions: Option<PathBuf>,
    /// With --field: receive sectors (receivers) per robot, 2 to 8.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(2..=8), requires = "field")]
    pub sectors: u8,
    /// Robots on a plane over a field instead of light patterns: a `cimax swarm` scenario
    /// (sharp, gradient, cloud) or its TOML file. The swarm moves as it decides.
    #[arg(long)]
    pub field: Option<String>,
    /// With --field: where the centre of mass starts, in R along x.
    #[arg(long, default_value_t = -2.0, allow_hyphen_values = true, requires = "field")]
    pub x_init: f64,
    /// With --field: negotiation periods (moves of 0.33 R) per run.
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1000), requires = "field")]
    pub moves: u32,
    /// Metres between neighbours (the light carries --range metres).
    #[arg(long, default_value_t = 1.0)]
    pub spacing: f64,
    /// Range of the light, metres.
    #[arg(long, default_value_t = 1.5)]
    pub range: f64,
    /// One light pattern instead of the paper's suite, one character per robot, 1 = lit.
    #[arg(long)]
    pub lights: Option<String>,
    /// Change the pattern at this time (seconds, at most 1,000,000)...
    #[arg(long, requires = "then", value_parser = clap::value_parser!(u64).range(0..=MAX_RUN_SECS))]
    pub switch_at: Option<u64>,
    /// ...to this pattern.
    #[arg(long, requires = "switch_at")]
    pub then: Option<String>,
    /// Base seed: run k uses seed + k. Failing runs print their seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Runs per pattern.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub runs: u64,
    /// Emulated seconds per run (per phase in the alternating experiment), 1 to 1,000,000;
    /// default three negotiation periods of the longest cycle.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=MAX_RUN_SECS))]
    pub duration: Option<u64>,
    /// What the light sensors report: `full` (levels of 200 lit and 30 dark with noise ±10,
    /// or the field's level), `binary` (the paper's g in {0, 1}: 1 lit, 0 dark, without noise),
    /// `levels:N` (a coarser sensor of N levels, 2 to 256) or `gain:G,offset:B` (a sensor of
    /// another gain and offset, saturating at 0 and 255). None of these may change a decision.
    #[arg(long, value_name = "KIND", default_value_t = Readings::Levels, conflicts_with = "binary_readings")]
    pub readings: Readings,
    /// The same as `--readings binary`.
    #[arg(long)]
    pub binary_readings: bool,
    /// Probability that a frame is lost at a receiver.
    #[arg(long, default_value_t = 0.0)]
    pub loss: f64,
    /// Probability that a received byte is corrupted.
    #[arg(long, default_value_t = 0.0)]
    pub byte_error_rate: f64,
    /// Turn collisions of overlapping frames off.
    #[arg(long)]
    pub no_collisions: bool,
    /// Bits per second on air (the board's 9600 Bd IrDA SIR link; 10 bits per byte).
    #[arg(long, default_value_t = 9600)]
    pub bitrate: u32,
    /// Mean cycle length, seconds (the paper's 55).
    #[arg(long)]
    pub cycle: Option<f64>,
    /// Cycle spread, seconds (the paper's ±15).
    #[arg(long)]
    pub cycle_spread: Option<f64>,
    /// Refractory time, seconds (the paper's 4).
    #[arg(long)]
    pub refractory: Option<f64>,
    /// Negotiation period, cycles (the paper's 10).
    #[arg(long)]
    pub negotiation: Option<u16>,
    /// When a robot decides: at the end of each negotiation period (the paper's), or as soon as
    /// its evidence settles, at the latest at a period's end (docs/protocol.md §5.4).
    #[arg(long, value_enum, default_value_t = Decide::Fixed)]
    pub decide: Decide,
    /// Kill a robot: ROBOT@SECONDS (robots count from 0); repeatable.
    #[arg(long, value_parser = parse_at)]
    pub kill: Vec<(usize, u64)>,
    /// Restart a killed robot with fresh state: ROBOT@SECONDS; repeatable.
    #[arg(long, value_parser = parse_at)]
    pub restart: Vec<(usize, u64)>,
    /// Print a machine-readable JSON report on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write every frame sent, received or dropped, LED change and event as JSON lines
    /// (the first run only).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Draw a timeline per robot of frames and LED colour as SVG (the first run only).
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write the first run as one self-contained HTML page that replays it: waves, frames,
    /// LEDs, moves, consensus (docs/viewer.md). A failing run opens where it went wrong.
    #[arg(long, value_name = "FILE")]
    pub html: Option<PathBuf>,
    /// Swarm key, 32 hex digits (128 bits): every robot authenticates its frames and drops
    /// those without a valid MAC (docs/protocol.md, "Authenticated frames").
    #[arg(long, value_name = "HEX")]
    pub key: Option<SwarmKey>,
    /// Robots in the loop (docs/hil.md): `qemu:N` (N QEMU processes, each booting the
    /// one-robot HIL image), `serial:PATH[@BAUD]` (a board, 115200 Bd by default),
    /// `tcp:HOST:PORT` (anything speaking the link on a socket) or `loopback:N` (the robot
    /// program in this process, over the link). Repeatable. They take the first places of the
    /// line or plane (--hil-at picks others); the others stay virtual. The run goes in real
    /// time: shrink it with --cycle.
    #[arg(long, value_name = "SPEC")]
    pub hil: Vec<HilSpec>,
    /// The places of the robots in the loop, in the order of --hil: I,J,... (from 0).
    #[arg(long, value_name = "I,J,...", value_delimiter = ',', requires = "hil")]
    pub hil_at: Vec<usize>,
    /// The image --hil qemu:N boots (default: the HIL image `cargo hil-image` builds,
    /// firmware/qemu/target/thumbv7em-none-eabihf/release/hil, or hil6 for 6 sectors).
    #[arg(long, value_name = "ELF", requires = "hil")]
    pub hil_image: Option<PathBuf>,
    /// `campaign`: the fault-injection campaign (`crate::arena::campaign`).
    #[command(subcommand)]
    pub command: Option<Box<ArenaCommand>>,
}

impl ArenaArgs {
    /// What the sensors report: `--readings`, binary with `--binary-readings`.
    pub fn readings(&self) -> Readings {
        if self.binary_readings {
            Readings::Binary
        } else {
            self.readings
        }
    }
}

fn parse_at(s: &str) -> Result<(usize, u64), String> {
    let (r, t) = s
        .split_once('@')
        .ok_or_else(|| format!("{s:?}: expected ROBOT@SECONDS, e.g. 3@600"))?;
    let r = r
        .trim()
        .parse()
        .map_err(|_| format!("{s:?}: {r:?} is not a robot number"))?;
    let t = t
        .trim()
        .parse()
        .map_err(|_| format!("{s:?}: {t:?} is not a whole number of seconds"))?;
    Ok((r, t))
}

/// `--cycle` over the paper's 55 s (1 without `--cycle`).
fn time_scale(args: &ArenaArgs) -> Result<f64, String> {
    let Some(c) = args.cycle else { return Ok(1.0) };
    secs(c, "cycle")?;
    Ok(c / Params::robots().wave.cycle.as_secs_f64())
}

/// `d` times `scale`, to the millisecond, at least 1 ms.
fn scaled(d: Duration, scale: f64) -> Duration {
    Duration::from_millis(((d.as_millis() as f64 * scale).round() as u64).max(1))
}

/// The robots in the loop the options ask for, in a swarm of `robots` with `sectors` each:
/// their places (`--hil-at`, else the first ones) and transports.
fn hil_robots(args: &ArenaArgs, robots: usize, sectors: u8) -> Result<Vec<HilRobot>, String> {
    if args.hil.is_empty() {
        return Ok(Vec::new());
    }
    let image = args.hil_image.clone().unwrap_or_else(|| {
        let name = if sectors == 2 { "hil" } else { "hil6" };
        PathBuf::from("firmware/qemu/target/thumbv7em-none-eabihf/release").join(name)
    });
    let transports: Vec<Transport> = args.hil.iter().flat_map(|h| h.transports(&image)).collect();
    if transports.iter().any(|t| matches!(t, Transport::Qemu(_))) {
        if !image.is_file() {
            return Err(format!(
                "--hil qemu: no image at {} (build it with `cargo hil-image`; docs/hil.md)",
                image.display()
            ));
        }
        if sectors != 2 && sectors != 6 {
            return Err(format!(
                "--hil qemu: the HIL images have 2 (hil) or 6 (hil6) receivers, not {sectors}"
            ));
        }
    }
    let places: Vec<usize> = if args.hil_at.is_empty() {
        (0..transports.len()).collect()
    } else if args.hil_at.len() == transports.len() {
        args.hil_at.clone()
    } else {
        return Err(format!(
            "--hil-at names {} places for {} robots in the loop",
            args.hil_at.len(),
            transports.len()
        ));
    };
    if transports.len() > robots {
        return Err(format!(
            "{} robots in the loop, but only {robots} places",
            transports.len()
        ));
    }
    if let Some(p) = places.iter().find(|&&p| p >= robots) {
        return Err(format!(
            "--hil-at {p}: there is no place {p} (robots are 0..{})",
            robots - 1
        ));
    }
    if args.key.is_some() {
        return Err("--key with --hil: link version 1 carries no swarm key".into());
    }
    Ok(places
        .into_iter()
        .zip(transports)
        .map(|(robot, transport)| HilRobot { robot, transport })
        .collect())
}

fn secs(s: f64, what: &str) -> Result<Duration, String> {
    if s.is_finite() && s >= 0.0 {
        Ok(Duration::from_millis((s * 1000.0).round() as u64))
    } else {
        Err(format!(
            "--{what} must be a non-negative number of seconds, not {s}"
        ))
    }
}

/// The light medium the options describe.
fn medium(args: &ArenaArgs) -> Result<MediumParams, String> {
    let medium = MediumParams {
        bitrate: args.bitrate,
        range: args.range,
        loss: args.loss,
        byte_error_rate: args.byte_error_rate,
        collisions: !args.no_collisions,
        ..MediumParams::default()
    };
    medium.validate()?;
    Ok(medium)
}

/// One experiment: a list of runs sharing a label and an expected outcome.
struct Experiment {
    label: String,
    configs: Vec<ArenaConfig>,
}

/// The robots' protocol parameters: `Params::robots()` with the options' changes, validated.
fn robot_params(args: &ArenaArgs) -> Result<Params, String> {
    let mut params = Params::robots();
    if let Some(c) = args.cycle {
        // The timing the options leave out keeps the paper's proportions to the cycle
        // (15 s spread, 1 s relay delay and 4 s refractory to 55 s), so that `--cycle 2`
        // alone shrinks a whole run (robots in the loop run in real time).
        let scale = time_scale(args)?;
        let w = &mut params.wave;
        w.cycle = secs(c, "cycle")?;
        w.cycle_spread = scaled(w.cycle_spread, scale);
        w.relay_delay = scaled(w.relay_delay, scale);
        w.refractory = scaled(w.refractory, scale);
    }
    if let Some(c) = args.cycle_spread {
        params.wave.cycle_spread = secs(c, "cycle-spread")?;
    }
    if let Some(r) = args.refractory {
        params.wave.refractory = secs(r, "refractory")?;
    }
    if let Some(n) = args.negotiation {
        params.negotiation_cycles = n;
    }
    params.decide = args.decide.into();
    params
        .validate()
        .map_err(|e| format!("protocol parameters: {e}"))?;
    Ok(params)
}

/// The length of a run (`--duration`, or three negotiation periods of the longest cycle),
/// after checking `--spacing`.
fn run_length(args: &ArenaArgs, params: &Params) -> Result<Duration, String> {
    if !(args.spacing.is_finite() && args.spacing > 0.0) {
        return Err(format!(
            "--spacing must be a positive number of metres, not {}",
            args.spacing
        ));
    }
    let run = args.duration.map_or(params.lab_run(), Duration::from_secs);
    if run > Duration::from_secs(MAX_RUN_SECS) {
        return Err(format!(
            "a run of three negotiation periods of the longest cycle (--cycle, --cycle-spread, \
             --negotiation) lasts {} s; at most {MAX_RUN_SECS} s (give a --duration)",
            run.as_millis().div_ceil(1000)
        ));
    }

    Ok(run)
}

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

fn build(args: &ArenaArgs) -> Result<Vec<Experiment>, String> {
    let params = robot_params(args)?;
    let medium = medium(args)?;
    let run = run_length(args, &params)?;
    let lights = args.lights.as_deref().map(parse_pattern).transpose()?;
    let robots = line_robots(args, lights.as_deref())?;
    let check = |p: &[bool], what: &str| {
        if p.len() == robots {
            Ok(())
        } else {
            Err(format!(
                "{what} {} has {} robots but there are {robots}",
                pattern_str(p),
                p.len()
            ))
        }
    };
    let then = args.then.as_deref().map(parse_pattern).transpose()?;
    let hil = hil_robots(args, robots, 2)?;
    let sample = scaled(Config::robots().sample_period, time_scale(args)?);
    for &(r, _) in args.kill.iter().chain(&args.restart) {
        if r >= robots {
            return Err(format!(
                "there is no robot {r} to kill or restart (robots are 0..{})",
                robots - 1
            ));
        }
    }

    // The options' robots, medium, faults and sensors on a line of the experiment.
    let setup = |mut c: ArenaConfig| {
        c.robot.params = params;
        c.robot.key = args.key;
        c.medium = medium;
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
        c.robot.sample_period = sample;
        c.hil = hil.clone();
        c
    };
    let seeds = || (0..args.runs).map(|k| args.seed.wrapping_add(k));

    let suite: Vec<LabExperiment> = match &lights {
        Some(p) => vec![LabExperiment {
            first: p.clone(),
            then: None,
        }],
        None if robots == 4 => paper_suite(),
        None => {
            return Err(format!(
                "--robots {robots} needs --lights (the paper's patterns are for 4)"
            ));
        }
    };
    let mut out = Vec::new();
    for e in &suite {
        check(&e.first, "pattern")?;
        // `--switch-at --then` changes a single pattern (the suite's alternating experiments
        // have their own change).
        let switch = match (args.switch_at, &then, &e.then) {
            (Some(at), Some(t), None) => {
                check(t, "--then pattern")?;
                Some((Instant::from_secs(at), t))
            }
            _ => None,
        };
        let configs = seeds()
            .map(|s| {
                let mut c = setup(e.config(args.spacing, run, s));
                if let Some((at, t)) = switch {
                    c.env.schedule.push((at, t.clone()));
                    c.duration = c.duration.max(at.saturating_since(Instant::ZERO) + run);
                }
                c
            })
            .collect();
        let label = match switch {
            Some((_, t)) => format!("{}>{}", e.label(), pattern_str(t)),
            None => e.label(),
        };
        out.push(Experiment { label, configs });
    }
    Ok(out)
}

/// The options that replay a run of `cfg` alone: its first pattern (`--lights`) and, if the
/// pattern changes, when and to what (`--switch-at`, `--then`).
fn replay_lights(cfg: &ArenaConfig) -> String {
    let mut out = String::new();
    for (i, (t, p)) in cfg.env.schedule.iter().enumerate() {
        if i == 0 {
            out += &format!("--lights {}", pattern_str(p));
        } else {
            let at = t.saturating_since(Instant::ZERO).as_millis() / 1000;
            out += &format!(" --switch-at {at} --then {}", pattern_str(p));
        }
    }
    out
}

/// One run in the `--json` report.
#[derive(Serialize)]
struct JsonRun {
    lights: String,
    expected: Option<String>,
    leds: String,
    success: bool,
    consensus_s: Option<f64>,
    seed: u64,
    emulated_s: f64,
    wall_s: f64,
    /// Why the run has no result (a robot panicked); absent for a judged run.
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
    /// Each robot in the loop's link (`--hil`): transport, frames each way, link errors.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    hil: Vec<HilReport>,
}

/// The `--json` summary.
#[derive(Serialize)]
struct JsonSummary {
    runs: usize,
    successes: usize,
    emulated_s: f64,
    wall_s: f64,
}

#[derive(Serialize)]
struct JsonReport {
    runs: Vec<JsonRun>,
    summary: JsonSummary,
}

/// Runs `cimax arena`; the exit code is non-zero if any run with a verdict failed or an option
/// was bad.
pub fn main(args: &ArenaArgs) -> ExitCode {
    match args.command.as_deref() {
        Some(ArenaCommand::Campaign(c)) => return crate::arena::campaign::main(c),
        Some(ArenaCommand::Sweep(s)) => return crate::arena::plane::sweep_main(s),
        Some(ArenaCommand::Bench(b)) => return crate::arena::plane::bench_main(b),
        None => {}
    }
    if args.field.is_some() {
        return plane_main(args);
    }
    let experiments = match build(args) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("cimax arena: {e}");
            return ExitCode::from(2);
        }
    };
    let first = experiments.first().and_then(|e| e.configs.first()).cloned();
    let ((runs, crashed), wall_s) = match run_all(&experiments) {
        Ok(r) => r,
        Err(ArenaError::Interrupted) => {
            eprintln!("cimax arena: interrupted; robots in the loop stopped");
            return ExitCode::from(130);
        }
        Err(e) => {
            eprintln!("cimax arena: {e}");
            return ExitCode::from(2);
        }
    };
    if let Some(cfg) = &first
        && let Err(e) = write_artifacts(args, cfg)
    {
        eprintln!("cimax arena: {e}");
        return ExitCode::from(2);
    }

    let emulated_s: f64 = runs
        .iter()
        .map(|(_, r)| r.report.emulated.as_secs_f64())
        .sum();
    let failures: Vec<(&LabRun, String)> = runs
        .iter()
        .filter(|(_, r)| !r.success)
        .map(|(i, r)| {
            let cfg = experiments[*i].configs.iter().find(|c| c.seed == r.seed);
            (r, cfg.map(replay_lights).unwrap_or_default())
        })
        .collect();
    let total = runs.len() + crashed.len();
    let successes = runs.len() - failures.len();
    if args.json {
        let summary = JsonSummary {
            runs: total,
            successes,
            emulated_s,
            wall_s,
        };
        if let Err(e) = print_json(&runs, &crashed, summary) {
            eprintln!("cimax arena: {e}");
            return ExitCode::from(2);
        }
    } else {
        print_table(args, &experiments, &runs, &crashed);
        print_hil(&runs);
        println!(
            "{} runs, {} successful; {:.0} s of robot time in {:.3} s wall ({:.0}x real time)",
            total,
            successes,
            emulated_s,
            wall_s,
            emulated_s / wall_s.max(1e-9)
        );
    }
    print_failures(args, &failures, &crashed);
    if failures.is_empty() && crashed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Judged runs and crashed runs, each with its experiment's index.
type Runs = (Vec<(usize, LabRun)>, Vec<(usize, Crashed)>);

/// Runs every configuration of every experiment in parallel: the judged runs, the runs in
/// which a robot crashed, and the wall time.
fn run_all(experiments: &[Experiment]) -> Result<(Runs, f64), ArenaError> {
    let jobs: Vec<(usize, &ArenaConfig)> = experiments
        .iter()
        .enumerate()
        .flat_map(|(i, e)| e.configs.iter().map(move |c| (i, c)))
        .collect();
    let bar = if jobs.len() > 1 {
        Progress::new(jobs.len() as u64, "arena", false)
    } else {
        Progress::hidden()
    };
    let wall = std::time::Instant::now();
    // Each run is independent and seeded: the results do not depend on the thread count.
    let one = |c: &ArenaConfig| {
        let r = judge(c);
        bar.inc();
        r
    };
    // Runs with robots in the loop go in real time, one at a time (the robots are one board,
    // or QEMU processes that need the cores); the others in parallel.
    let results: Vec<Result<LabRun, ArenaError>> = if jobs.iter().any(|(_, c)| c.real_time()) {
        jobs.iter().map(|(_, c)| one(c)).collect()
    } else {
        jobs.par_iter().map(|(_, c)| one(c)).collect()
    };
    bar.finish();
    let wall_s = wall.elapsed().as_secs_f64();
    let (mut runs, mut crashed): Runs = (Vec::new(), Vec::new());
    // Runs in which a robot stopped on its own (a panic): failed, without LEDs to judge.
    for ((i, c), r) in jobs.iter().zip(results) {
        match r {
            Ok(r) => runs.push((*i, r)),
            Err(ArenaError::Robot(f)) => crashed.push((*i, Crashed::new(c, f))),
            Err(e) => return Err(e),
        }
    }
    Ok(((runs, crashed), wall_s))
}

/// Prints the `--json` report.
fn print_json(
    runs: &[(usize, LabRun)],
    crashed: &[(usize, Crashed)],
    summary: JsonSummary,
) -> Result<(), serde_json::Error> {
    let report = JsonReport {
        runs: runs
            .iter()
            .map(|(_, r)| JsonRun {
                lights: pattern_str(&r.lights),
                expected: r.expected.as_deref().map(leds_str),
                leds: leds_str(&r.leds),
                success: r.success,
                consensus_s: r.consensus_s,
                seed: r.seed,
                emulated_s: r.report.emulated.as_secs_f64(),
                wall_s: r.report.wall.as_secs_f64(),
                error: None,
                hil: r.report.hil.clone(),
            })
            .chain(crashed.iter().map(|(_, c)| c.json()))
            .collect(),
        summary,
    };
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}

/// One line per robot in the loop: its link over all runs.
fn print_hil(runs: &[(usize, LabRun)]) {
    let mut places: std::collections::BTreeMap<usize, (String, HilReport, usize)> =
        std::collections::BTreeMap::new();
    for (_, r) in runs {
        for h in &r.report.hil {
            let e = places
                .entry(h.robot)
                .or_insert_with(|| (h.transport.clone(), HilReport::default(), 0));
            e.1.frames_sent += h.frames_sent;
            e.1.frames_received += h.frames_received;
            e.1.link_errors += h.link_errors;
            e.1.tx += h.tx;
            e.1.hello_ms = e.1.hello_ms.max(h.hello_ms);
            e.1.bytes_sent += h.bytes_sent;
            e.1.bytes_received += h.bytes_received;
            // The mean over runs, weighted by round trips.
            let trips = e.1.round_trips + h.round_trips;
            if let Some(mean) = (e.1.rtt_mean_us * e.1.round_trips + h.rtt_mean_us * h.round_trips)
                .checked_div(trips)
            {
                e.1.rtt_mean_us = mean;
            }
            e.1.round_trips = trips;
            e.1.rtt_max_us = e.1.rtt_max_us.max(h.rtt_max_us);
            e.2 += 1;
        }
    }
    for (robot, (transport, h, n)) in places {
        println!(
            "robot {robot} in the loop over {transport}: {n} runs, {} link frames ({} B) sent to it, {} ({} B) received with {} light frames, {} link errors; hello within {} ms, heartbeat round trip {:.2} ms mean, {:.2} ms max",
            h.frames_sent,
            h.bytes_sent,
            h.frames_received,
            h.bytes_received,
            h.tx,
            h.link_errors,
            h.hello_ms,
            h.rtt_mean_us as f64 / 1000.0,
            h.rtt_max_us as f64 / 1000.0
        );
    }
}

/// The options of `args` a replay repeats (after `--runs 1`).
fn replay_extra(args: &ArenaArgs) -> String {
    let mut extra = String::new();
    for h in &args.hil {
        extra += &format!(" --hil {}", hil_spec_str(h));
    }
    if !args.hil_at.is_empty() {
        let at: Vec<String> = args.hil_at.iter().map(usize::to_string).collect();
        extra += &format!(" --hil-at {}", at.join(","));
    }
    if let Some(c) = args.cycle {
        extra += &format!(" --cycle {c}");
    }
    if let Some(d) = args.duration {
        extra += &format!(" --duration {d}");
    }
    if args.decide != Decide::Fixed {
        extra += " --decide adaptive";
    }
    if args.loss > 0.0 {
        extra += &format!(" --loss {}", args.loss);
    }
    match args.readings() {
        Readings::Levels => {}
        Readings::Binary => extra += " --binary-readings",
        r => extra += &format!(" --readings {r}"),
    }
    extra
}

/// `--hil`'s spec as typed.
fn hil_spec_str(h: &HilSpec) -> String {
    match h {
        HilSpec::Qemu(n) => format!("qemu:{n}"),
        HilSpec::Loopback(n) => format!("loopback:{n}"),
        HilSpec::Serial(p, b) => format!("serial:{}@{b}", p.display()),
        HilSpec::Tcp(a) => format!("tcp:{a}"),
    }
}

/// One line on stderr per failed or crashed run (each failed run with the `--lights` options
/// that replay it, [`replay_lights`]), with the command that replays it.
fn print_failures(args: &ArenaArgs, failures: &[(&LabRun, String)], crashed: &[(usize, Crashed)]) {
    let extra = replay_extra(args);
    for (r, lights) in failures {
        let flicker = r
            .flicker
            .map(|(t, robot)| {
                format!("; robot {robot}'s LEDs changed at {t:.0} s, after consensus")
            })
            .unwrap_or_default();
        eprintln!(
            "FAILED {} seed {}: LEDs {}, expected {}{flicker} (replay: cimax arena {lights} --seed {} --runs 1{extra})",
            pattern_str(&r.lights),
            r.seed,
            leds_str(&r.leds),
            r.expected.as_deref().map(leds_str).unwrap_or_default(),
            r.seed
        );
    }
    for (_, c) in crashed {
        eprintln!("{}", c.failed_line(&extra));
    }
}

/// A run in which a robot stopped on its own ([`ArenaError::Robot`]: its task panicked, or it
/// could not boot). It has no LEDs worth judging: it failed.
struct Crashed {
    /// The pattern at the end of the run (what a judged run reports as its lights).
    lights: Vec<bool>,
    /// The LEDs the run should have ended with, if its pattern has a verdict.
    expected: Option<Vec<LedColor>>,
    /// Which robot, why, and the seed.
    failure: RobotFailure,
    /// The options that replay it ([`replay_lights`]).
    replay: String,
}

impl Crashed {
    fn new(cfg: &ArenaConfig, failure: RobotFailure) -> Self {
        let end = Instant::ZERO + cfg.duration;
        let lights = cfg
            .env
            .pattern_at(end)
            .map(<[bool]>::to_vec)
            .unwrap_or_default();
        let expected = hal_emu::judge::expected_without(&lights, &hal_emu::judge::absent(cfg));
        Crashed {
            lights,
            expected,
            failure,
            replay: replay_lights(cfg),
        }
    }

    /// The `FAILED` line on stderr, like a judged run's, with the command that replays it.
    fn failed_line(&self, extra: &str) -> String {
        let (lights, seed) = (pattern_str(&self.lights), self.failure.seed);
        format!(
            "FAILED {lights} seed {seed}: {}, expected {} (replay: cimax arena {} --seed {seed} --runs 1{extra})",
            self.failure.what(),
            self.expected.as_deref().map(leds_str).unwrap_or_default(),
            self.replay,
        )
    }

    /// The run in the `--json` report: no LEDs, not a success, and the error.
    fn json(&self) -> JsonRun {
        JsonRun {
            lights: pattern_str(&self.lights),
            expected: self.expected.as_deref().map(leds_str),
            leds: String::new(),
            success: false,
            consensus_s: None,
            seed: self.failure.seed,
            emulated_s: 0.0,
            wall_s: 0.0,
            error: Some(self.failure.what()),
            hil: Vec::new(),
        }
    }
}

/// What the LEDs of a run of `cfg` should show: the verdict of its pattern, or of each pattern
/// in turn where the pattern changes (`LLLL>RRRR`); `(none)` for a pattern without a verdict.
fn expected_str(cfg: &ArenaConfig) -> String {
    let absent = hal_emu::judge::absent(cfg);
    cfg.env
        .schedule
        .iter()
        .map(|(_, p)| {
            hal_emu::judge::expected_without(p, &absent).map_or("(none)".into(), |e| leds_str(&e))
        })
        .collect::<Vec<_>>()
        .join(">")
}

fn print_table(
    args: &ArenaArgs,
    experiments: &[Experiment],
    runs: &[(usize, LabRun)],
    crashed: &[(usize, Crashed)],
) {
    let cycle_s = args
        .cycle
        .unwrap_or(Params::robots().wave.cycle.as_secs_f64());
    println!(
        "CIMAX lab arena: robots in a line running the robot program over the emulated light medium{}",
        match args.readings() {
            Readings::Binary => "; binary readings (g = 1 lit, 0 dark)".to_string(),
            Readings::Levels => String::new(),
            r => format!("; readings {r}"),
        }
    );
    println!(
        "{:<12} {:<10} {:<36} {:>8} {:>24} {:>9}",
        "pattern", "expected", "LEDs per run", "success", "consensus s (cycles)", "speed"
    );
    for (i, e) in experiments.iter().enumerate() {
        let rs: Vec<&LabRun> = runs
            .iter()
            .filter(|(j, _)| *j == i)
            .map(|(_, r)| r)
            .collect();
        let crashes: Vec<&Crashed> = crashed
            .iter()
            .filter(|(j, _)| *j == i)
            .map(|(_, c)| c)
            .collect();
        let ok = rs.iter().filter(|r| r.success).count();
        let times: Vec<f64> = rs.iter().filter_map(|r| r.consensus_s).collect();
        let mean = crate::stats::mean(&times);
        let speed: f64 = rs
            .iter()
            .map(|r| r.report.emulated.as_secs_f64())
            .sum::<f64>()
            / rs.iter()
                .map(|r| r.report.wall.as_secs_f64())
                .sum::<f64>()
                .max(1e-9);
        let mut leds: Vec<String> = rs.iter().map(|r| leds_str(&r.leds)).collect();
        leds.extend(crashes.iter().map(|_| "crashed".to_string()));
        let exp = e
            .configs
            .first()
            .map_or_else(|| "(none)".into(), expected_str);
        // A crashed run is a failure whatever its pattern.
        let success = if crashes.is_empty() && rs.iter().all(|r| r.expected.is_none()) {
            "n/a".to_string()
        } else {
            let n = rs.len() + crashes.len();
            format!("{:.0}%", 100.0 * ok as f64 / n.max(1) as f64)
        };
        let consensus = mean.map_or("-".into(), |m| format!("{m:.0} ({:.1})", m / cycle_s));
        println!(
            "{:<12} {:<10} {:<36} {:>8} {:>24} {:>8.0}x",
            e.label,
            exp,
            leds.join(" "),
            success,
            consensus,
            speed
        );
    }
}

/// `--trace`, `--html` and `--svg` for the first run (run again with tracing on).
fn write_artifacts(args: &ArenaArgs, cfg: &ArenaConfig) -> Result<(), String> {
    if args.trace.is_none() && args.svg.is_none() && args.html.is_none() {
        return Ok(());
    }
    let mut cfg = cfg.clone();
    cfg.trace = true;
    let run = judge(&cfg).map_err(|e| e.to_string())?;
    if args.trace.is_some() || args.html.is_some() {
        let header = lab_header(&cfg, &run, args);
        if let Some(path) = &args.trace {
            crate::viewer::write_trace(path, header.clone(), &run.report.trace)?;
        }
        if let Some(path) = &args.html {
            crate::viewer::write_page(path, header, &run.report.trace)?;
        }
    }
    if let Some(path) = &args.svg {
        std::fs::write(path, timeline_svg(&cfg, &run))
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// The viewer's header of a lab run: the set-up, a title and the verdict.
fn lab_header(cfg: &ArenaConfig, run: &LabRun, args: &ArenaArgs) -> crate::viewer::Header {
    let mut h = crate::viewer::header_of(cfg, &run.report.trace);
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
                "FAILED: robot {r} changed its LEDs at {t:.0} s after the swarm agreed; at the end {leds}, expected {x}"
            ),
            None => format!("FAILED: LEDs at the end {leds}, expected {x}"),
        },
    };
    h.verdict = Some(crate::viewer::Verdict {
        success: run.success,
        leds,
        expected,
        text,
    });
    h
}

/// A timeline per robot: LED colour as a band, frames sent as ticks above it, frames received
/// as dots below it (red when garbled or dropped).
fn timeline_svg(cfg: &ArenaConfig, run: &LabRun) -> String {
    let mut svg = String::new();
    if let Err(e) = draw_timeline(cfg, run, &mut svg) {
        eprintln!("cimax arena: timeline: {e}");
    }
    svg
}

/// Where the timeline draws: pixel coordinates on a plotters SVG canvas, one lane per robot.
struct Lanes {
    left: f64,
    width: f64,
    lane: f64,
    end_ms: f64,
}

impl Lanes {
    /// The x pixel of time `t_ms`.
    fn x(&self, t_ms: u64) -> i32 {
        (self.left + (self.width - self.left - 10.0) * (t_ms as f64 / self.end_ms)).round() as i32
    }

    /// The top pixel of robot `r`'s lane.
    fn y(&self, r: usize) -> i32 {
        (30.0 + self.lane * r as f64).round() as i32
    }
}

type Canvas<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type Drawn = Result<(), Box<dyn std::error::Error>>;

/// Draws the timeline of `run` into `out` with plotters (as every other figure of `cimax`).
fn draw_timeline(cfg: &ArenaConfig, run: &LabRun, out: &mut String) -> Drawn {
    let n = cfg.positions.len();
    let end_s = cfg.duration.as_secs_f64().max(1.0);
    let lanes = Lanes {
        left: 70.0,
        width: 1200.0,
        lane: 40.0,
        end_ms: end_s * 1000.0,
    };
    let h = (40.0 + lanes.lane * n as f64) as u32;
    {
        let root = SVGBackend::with_string(out, (1200, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let title = format!(
            "pattern {} seed {}: wave state (orange active, red refractory), frames sent (ticks), \
             LED colour (green left, blue right, grey off), frames received (dots; red = garbled \
             or dropped); {end_s:.0} s",
            pattern_str(&run.lights),
            run.seed
        );
        root.draw(&Text::new(title, (70, 4), ("sans-serif", 11)))?;
        led_lanes(&root, &lanes, cfg, run)?;
        wave_bands(&root, &lanes, run, n)?;
        frame_marks(&root, &lanes, run)?;
        root.present()?;
    }
    Ok(())
}

/// The LED colour of each robot over time, one lane per robot, with its label.
fn led_lanes(root: &Canvas<'_>, lanes: &Lanes, cfg: &ArenaConfig, run: &LabRun) -> Drawn {
    for r in 0..cfg.positions.len() {
        let y = lanes.y(r);
        root.draw(&Text::new(
            format!("robot {r}"),
            (4, y + 8),
            ("sans-serif", 11),
        ))?;
        let mut segs: Vec<(u64, LedColor)> = vec![(0, LedColor::Off)];
        segs.extend(
            run.report
                .leds
                .iter()
                .filter(|c| c.robot == r)
                .map(|c| (c.t.as_millis(), c.color)),
        );
        for (i, &(t, c)) in segs.iter().enumerate() {
            let t2 = segs.get(i + 1).map_or(cfg.duration.as_millis(), |s| s.0);
            let fill = match c {
                LedColor::Green => RGBColor(0x2e, 0x9d, 0x4a),
                LedColor::Blue => RGBColor(0x2b, 0x6c, 0xd6),
                LedColor::Off => RGBColor(0xd8, 0xd8, 0xd8),
                LedColor::Sector(_) => RGBColor(0x8a, 0x4f, 0xd6),
            };
            let (x0, x1) = (lanes.x(t), lanes.x(t2).max(lanes.x(t) + 1));
            root.draw(&Rectangle::new([(x0, y + 10), (x1, y + 22)], fill.filled()))?;
        }
    }
    Ok(())
}

/// Wave states as a thin band above the LEDs: orange active, red refractory.
fn wave_bands(root: &Canvas<'_>, lanes: &Lanes, run: &LabRun, n: usize) -> Drawn {
    let mut since: Vec<Option<(u64, &str)>> = vec![None; n];
    for e in &run.report.trace {
        if let TraceEvent::State { t_ms, robot, state } = e
            && let Some(slot) = since.get_mut(*robot)
        {
            if let Some((t0, st)) = slot.take() {
                let fill = if st == "active" {
                    RGBColor(0xf0, 0xa0, 0x30)
                } else {
                    RGBColor(0xe0, 0x60, 0x60)
                };
                let y = lanes.y(*robot);
                let (x0, x1) = (lanes.x(t0), lanes.x(*t_ms).max(lanes.x(t0) + 1));
                root.draw(&Rectangle::new([(x0, y + 3), (x1, y + 8)], fill.filled()))?;
            }
            if *state != "inactive" {
                *slot = Some((*t_ms, state));
            }
        }
    }
    Ok(())
}

/// Frames sent (ticks), received (dots) and dropped (red rings), per robot.
fn frame_marks(root: &Canvas<'_>, lanes: &Lanes, run: &LabRun) -> Drawn {
    let grey = RGBColor(0x55, 0x55, 0x55);
    for e in &run.report.trace {
        match e {
            TraceEvent::Sent { t_ms, robot, .. } => {
                let (x, y) = (lanes.x(*t_ms), lanes.y(*robot));
                root.draw(&PathElement::new(vec![(x, y + 2), (x, y + 9)], BLACK))?;
            }
            TraceEvent::Received {
                t_ms,
                robot,
                garbled,
                corrupted,
                ..
            } => {
                let c = if *garbled || *corrupted > 0 {
                    RED
                } else {
                    grey
                };
                let at = (lanes.x(*t_ms), lanes.y(*robot) + 26);
                root.draw(&Circle::new(at, 1, c.filled()))?;
            }
            TraceEvent::Dropped { t_ms, robot, .. } => {
                let at = (lanes.x(*t_ms), lanes.y(*robot) + 26);
                root.draw(&Circle::new(at, 2, RED))?;
            }
            _ => {}
        }
    }
    Ok(())
}

/// `cimax arena --field ...`: robots on a plane over a field, moving as they decide.
fn plane_main(args: &ArenaArgs) -> ExitCode {
    let spec = match plane_spec(args) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("cimax arena: {e}");
            return ExitCode::from(2);
        }
    };
    let wall = std::time::Instant::now();
    let seeds: Vec<u64> = (0..args.runs).map(|k| args.seed.wrapping_add(k)).collect();
    // With robots in the loop, in real time and one run at a time.
    let results: Result<Vec<_>, _> = if spec.hil.is_empty() {
        seeds
            .par_iter()
            .map(|&s| crate::arena::plane::run(&spec, s))
            .collect()
    } else {
        seeds
            .iter()
            .map(|&s| crate::arena::plane::run(&spec, s))
            .collect()
    };
    let runs = match results {
        Ok(r) => r,
        Err(e) => {
            eprintln!("cimax arena: {e}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = plane_artifacts(args, &spec) {
        eprintln!("cimax arena: {e}");
        return ExitCode::from(2);
    }
    crate::arena::plane::print_runs(&spec, &runs, wall.elapsed().as_secs_f64(), args.json)
}

/// `--trace` and `--html` of a plane's first run (run again with tracing on; `--svg` draws
/// lines only).
fn plane_artifacts(args: &ArenaArgs, spec: &PlaneSpec) -> Result<(), String> {
    if args.trace.is_none() && args.html.is_none() {
        return Ok(());
    }
    let (run, cfg, trace) =
        crate::arena::plane::run_traced(spec, args.seed, true).map_err(|e| e.to_string())?;
    let header = crate::arena::plane::viewer_header(spec, &cfg, &run, &trace);
    if let Some(path) = &args.trace {
        crate::viewer::write_trace(path, header.clone(), &trace)?;
    }
    if let Some(path) = &args.html {
        crate::viewer::write_page(path, header, &trace)?;
    }
    Ok(())
}

/// The plane experiment the options describe.
fn plane_spec(args: &ArenaArgs) -> Result<PlaneSpec, String> {
    let field = args.field.as_deref().unwrap_or("sharp");
    let scenario = crate::swarm::scenario::Scenario::load(field).map_err(|e| e.to_string())?;
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
    // The timing options as on a line (`--cycle` scales what the others leave out).
    let mut params = robot_params(args)?;
    let medium = medium(args)?;
    params.sectors = args.sectors;
    params
        .validate()
        .map_err(|e| format!("protocol parameters: {e}"))?;
    let file_positions = match (&args.positions, args.shape) {
        (Some(path), Placement::File) => {
            let text =
                std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
            crate::arena::plane::read_positions(&text, &path.display().to_string())?
        }
        (None, Placement::File) => return Err("--shape file needs --positions FILE".into()),
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

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser as _;

    /// `cimax arena` as the tool parses it.
    #[derive(clap::Parser)]
    struct Cli {
        #[command(subcommand)]
        command: Cmd,
    }

    #[derive(clap::Subcommand)]
    enum Cmd {
        Arena(ArenaArgs),
    }

    /// The options of `cimax arena ARGS...`.
    fn args(a: &[&str]) -> ArenaArgs {
        let cli = Cli::try_parse_from(["cimax", "arena"].iter().chain(a)).unwrap();
        let Cmd::Arena(args) = cli.command;
        args
    }

    #[test]
    fn the_default_suite_runs_every_pattern_and_its_mirror() {
        let experiments = build(&args(&[])).unwrap();
        let labels: Vec<&str> = experiments.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "1000",
                "0111",
                "0001",
                "1110",
                "1100",
                "0011",
                "1000>0001",
                "0111>1110",
                "0001>1000",
                "1110>0111",
                "1100>0011",
                "0011>1100"
            ]
        );
        let expected: Vec<String> = experiments
            .iter()
            .map(|e| expected_str(&e.configs[0]))
            .collect();
        assert_eq!(
            expected[6..],
            [
                "LLLL>RRRR",
                "LLLL>RRRR",
                "RRRR>LLLL",
                "RRRR>LLLL",
                "RRLL>RRLL",
                "RRLL>RRLL"
            ]
        );
        for e in &experiments {
            assert_eq!(e.configs.len(), 5, "{}", e.label);
            let seeds: Vec<u64> = e.configs.iter().map(|c| c.seed).collect();
            assert_eq!(seeds, [1, 2, 3, 4, 5]);
            for c in &e.configs {
                assert_eq!(c.env.readings, Readings::Levels);
                let phases = if e.label.contains('>') { 2 } else { 1 };
                assert_eq!(c.duration.as_millis(), phases * 2_101_000, "{}", e.label);
            }
        }
        // A failing run of an alternating experiment replays with its change.
        let last = &experiments[11].configs[2];
        assert_eq!(
            replay_lights(last),
            "--lights 0011 --switch-at 2101 --then 1100"
        );
        assert_eq!(replay_lights(&experiments[0].configs[0]), "--lights 1000");
        // One pattern with a change of its own: as before, no suite.
        let one = build(&args(&[
            "--lights",
            "10",
            "--switch-at",
            "60",
            "--then",
            "01",
        ]))
        .unwrap();
        assert_eq!(one.len(), 1);
        assert_eq!(one[0].label, "10>01");
        assert_eq!(
            replay_lights(&one[0].configs[0]),
            "--lights 10 --switch-at 60 --then 01"
        );
    }

    #[test]
    fn binary_readings_reach_every_run_and_its_replay() {
        let a = args(&["--binary-readings", "--runs", "1"]);
        let experiments = build(&a).unwrap();
        assert!(
            experiments
                .iter()
                .flat_map(|e| &e.configs)
                .all(|c| c.env.readings == Readings::Binary)
        );
        assert_eq!(replay_extra(&a), " --binary-readings");
        // The same as `--readings binary`; on a plane too.
        assert_eq!(
            build(&args(&["--readings", "binary", "--runs", "1"])).unwrap()[0].configs[0]
                .env
                .readings,
            Readings::Binary
        );
        assert_eq!(
            plane_spec(&args(&["--field", "sharp", "--binary-readings"]))
                .unwrap()
                .readings,
            Readings::Binary
        );
        let scaled = args(&["--readings", "gain:0.5,offset:100", "--runs", "1"]);
        assert_eq!(replay_extra(&scaled), " --readings gain:0.5,offset:100");
        // The whole suite with binary readings, one run each: every verdict holds.
        let ((runs, crashed), _) = run_all(&experiments).unwrap();
        assert!(crashed.is_empty());
        for (i, r) in &runs {
            assert!(
                r.success,
                "{} seed {}: LEDs {}",
                experiments[*i].label,
                r.seed,
                leds_str(&r.leds)
            );
        }
        let end = |label: &str| {
            let i = experiments.iter().position(|e| e.label == label).unwrap();
            runs.iter()
                .find(|(j, _)| *j == i)
                .map(|(_, r)| leds_str(&r.leds))
                .unwrap()
        };
        assert_eq!(end("1100>0011"), "RRLL");
        assert_eq!(end("0001>1000"), "LLLL");
        assert_eq!(end("0111>1110"), "RRRR");
    }

    #[test]
    fn a_run_in_which_a_robot_panicked_is_reported_failed_with_its_replay() {
        // What `judge` returns when robot 1's task panics (hal-emu's arena tests inject one);
        // `main` keeps it as a crashed run instead of stopping every run.
        let mut cfg = ArenaConfig::line(
            parse_pattern("1100").unwrap(),
            1.0,
            Duration::from_secs(2101),
            42,
        );
        cfg.env
            .schedule
            .push((Instant::from_secs(2101), parse_pattern("0011").unwrap()));
        cfg.duration = Duration::from_secs(4202);
        let c = Crashed::new(
            &cfg,
            RobotFailure {
                robot: 1,
                seed: 42,
                panicked: true,
                message: "attempt to subtract with overflow".into(),
            },
        );
        assert_eq!(
            c.failed_line(" --decide adaptive"),
            "FAILED 0011 seed 42: robot 1 panicked: attempt to subtract with overflow, expected \
             RRLL (replay: cimax arena --lights 1100 --switch-at 2101 --then 0011 --seed 42 --runs 1 \
             --decide adaptive)"
        );
        let json = serde_json::to_value(c.json()).unwrap();
        assert_eq!(json["success"], false);
        assert_eq!(json["seed"], 42);
        assert_eq!(
            json["error"],
            "robot 1 panicked: attempt to subtract with overflow"
        );
        // A judged run's JSON has no `error` key.
        let mut judged = c.json();
        judged.error = None;
        assert!(serde_json::to_value(judged).unwrap().get("error").is_none());
    }
}
