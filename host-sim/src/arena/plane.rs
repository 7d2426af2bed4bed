//! The robot program on a plane: `cimax arena --field ...` and `cimax arena sweep`.
//!
//! Robots on a line, the paper's hexagonal lattice or a random disk, each with K receivers,
//! run the unchanged robot program (`firmware::Robot`) over the emulated light medium
//! (`hal-emu`). What they sense is one of the 2D simulator's fields ([`crate::swarm::field`], the
//! scenarios of `cimax swarm`), read where each robot is; every negotiation period the swarm
//! moves rigidly by the scenario's step (0.33 R) along the circular mean of the sectors its
//! LEDs show ([`hal_emu::world::arena::swarm_heading`]). A run succeeds by the scenario's criterion
//! (sharp: the centre of mass within 0.33 R of the border; gradient: at x >= 2.33) within the
//! given number of moves, as in the paper's Figs. 5 and 8.

use hal_emu::world::arena::{Motion, Move};
use hal_emu::{ArenaConfig, Environment, MediumParams, Point2};
use nalgebra::Vector2;
use protocol::{MAX_TAGS, Params};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::Serialize;

use crate::swarm::geometry::{PlacementError, Shape, Swarm};
use crate::swarm::scenario::{Scenario, Success, check_runs};

/// How the robots are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Placement {
    /// In a line along x, 0.75 R apart.
    Line,
    /// The nodes of a triangular lattice of spacing 0.75 R nearest the centre (61: the paper's
    /// disk of 6 R).
    Lattice,
    /// Uniformly at random in a disk with the density of the paper's (61 robots in 6 R), redrawn
    /// until connected.
    Disk,
    /// Where a file says (`--positions FILE`, [`read_positions`]).
    File,
}

/// Spacing of the line and the lattice, in R: 61 lattice robots fill the paper's 6 R disk.
pub const SPACING: f64 = 0.75;

/// One plane experiment.
#[derive(Clone, Debug)]
pub struct PlaneSpec {
    /// The field, the success criterion and the step, from a `cimax swarm` scenario.
    pub scenario: Scenario,
    /// How the robots are placed.
    pub placement: Placement,
    /// Number of robots.
    pub robots: usize,
    /// Receive sectors per robot (2 to 8).
    pub sectors: u8,
    /// Where the centre of mass starts, in R along x.
    pub x_init: f64,
    /// Negotiation periods (moves) per run.
    pub moves: u32,
    /// The light medium (its `range` is R in metres).
    pub medium: MediumParams,
    /// Protocol parameters (`sectors` is set from `sectors`).
    pub params: Params,
    /// Positions relative to the swarm, in R, for [`Placement::File`] (recentred on their
    /// centre of mass).
    pub file_positions: Vec<Vector2<f64>>,
    /// What the light sensors report (`--readings`).
    pub readings: hal_emu::Readings,
    /// Robots in the loop (`--hil`): places taken by robots running the real image elsewhere.
    pub hil: Vec<hal_emu::world::hil::HilRobot>,
    /// How often the robots read their sensors, if not the robot program's default (`--cycle`
    /// scales it).
    pub sample_period: Option<protocol::Duration>,
}

impl PlaneSpec {
    /// The experiment in a few words: robots, placement, sectors, field, start and moves.
    pub fn summary(&self) -> String {
        format!(
            "{} robots ({:?}, K = {}) on field {} from x = {}, {} moves",
            self.robots, self.placement, self.sectors, self.scenario.name, self.x_init, self.moves
        )
    }
}

/// Reads robot positions, in R: one robot per line, `x y` or `x,y`; empty lines and lines
/// starting with `#` are skipped. The positions are recentred on their centre of mass.
///
/// # Errors
/// A message naming the line and what is wrong with it, or that there are fewer than two
/// robots or more than 1000.
pub fn read_positions(text: &str, source: &str) -> Result<Vec<Vector2<f64>>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let [x, y] = fields.as_slice() else {
            return Err(format!(
                "{source}:{}: expected two numbers `x y` (in R), got {line:?}",
                i + 1
            ));
        };
        let num = |f: &str| {
            f.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("{source}:{}: {f:?} is not a finite number", i + 1))
        };
        out.push(Vector2::new(num(x)?, num(y)?));
    }
    if !(2..=1000).contains(&out.len()) {
        return Err(format!(
            "{source}: {} robots; 2 to 1000 are needed",
            out.len()
        ));
    }
    let centre = out.iter().fold(Vector2::zeros(), |s, p| s + p) / out.len() as f64;
    Ok(out.into_iter().map(|p| p - centre).collect())
}

/// What one run did.
#[derive(Clone, Debug, Serialize)]
pub struct PlaneRun {
    /// The run's seed.
    pub seed: u64,
    /// True if the criterion was met within the moves.
    pub success: bool,
    /// The first move after which the criterion held, if any.
    pub moves_to_success: Option<u32>,
    /// Per negotiation period: the fraction of robots whose LEDs show the sector nearest the
    /// swarm's decision.
    pub consensus: Vec<f64>,
    /// The centre of mass at the end, in R.
    pub final_position: [f64; 2],
    /// The LEDs at the end: `R` (sector 0, +x) and `L` with two sectors, else the sector's
    /// digit; `-` off.
    pub leds: String,
    /// Emulated seconds.
    pub emulated_s: f64,
    /// Wall seconds.
    pub wall_s: f64,
    /// Each robot in the loop's link (`--hil`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub hil: Vec<hal_emu::world::hil::HilReport>,
}

/// Why a plane experiment could not be set up.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneError {
    /// No connected placement.
    Placement(PlacementError),
    /// The emulator refused the configuration.
    Arena(String),
    /// A sweep over a scenario without a success criterion.
    NoCriterion(String),
}

impl std::fmt::Display for PlaneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlaneError::Placement(e) => write!(f, "placing the robots: {e}"),
            PlaneError::Arena(e) => write!(f, "emulator: {e}"),
            PlaneError::NoCriterion(s) => write!(f, "scenario {s} has no success criterion"),
        }
    }
}

impl std::error::Error for PlaneError {}

/// The robots' positions relative to the centre of mass, in R.
///
/// # Errors
/// [`PlacementError`] if a random disk cannot be made connected.
pub fn positions(spec: &PlaneSpec, seed: u64) -> Result<Vec<Vector2<f64>>, PlacementError> {
    let n = spec.robots;
    let shape = match spec.placement {
        Placement::Line => {
            let mid = (n as f64 - 1.0) / 2.0;
            return Ok((0..n)
                .map(|i| Vector2::new((i as f64 - mid) * SPACING, 0.0))
                .collect());
        }
        Placement::File => return Ok(spec.file_positions.clone()),
        Placement::Lattice => Shape::Lattice { spacing: SPACING },
        // The paper's density: 61 robots in a disk of diameter 6 R.
        Placement::Disk => Shape::Disk { diameter: 6.0 }.scaled_for(61, n),
    };
    let mut rng = Pcg64Mcg::seed_from_u64(crate::seeds::derive(seed, &[7]));
    Ok(Swarm::place(n, shape, 1.0, &mut rng)?.offsets().to_vec())
}

/// Robot ids whose tags (`id mod 16`) differ between robots close to each other: each robot in
/// turn takes the tag whose nearest holder is farthest away (greedy), so that robots sharing a
/// tag are as far apart as the swarm allows (on the lattice at least 3 spacings). Robots
/// within a message's reach should not share a tag (`docs/protocol.md` §5.1).
pub fn spread_ids(positions: &[Vector2<f64>]) -> Vec<u16> {
    let mut tags: Vec<u16> = Vec::with_capacity(positions.len());
    for p in positions {
        let nearest = |t: u16| {
            tags.iter()
                .zip(positions)
                .filter(|(tag, _)| **tag == t)
                .map(|(_, q)| (p - q).norm())
                .fold(f64::INFINITY, f64::min)
        };
        // The first tag whose nearest holder is farthest (an unused tag first).
        let tag = (0..MAX_TAGS as u16)
            .map(|t| (t, nearest(t)))
            .fold(
                (0, f64::NEG_INFINITY),
                |best, c| if c.1 > best.1 { c } else { best },
            )
            .0;
        tags.push(tag);
    }
    // Distinct ids with these tags: the k-th robot with tag t gets 16 k + t.
    let mut count = [0u16; MAX_TAGS];
    tags.iter()
        .map(|&t| {
            let k = &mut count[usize::from(t)];
            *k += 1;
            (*k - 1) * MAX_TAGS as u16 + t
        })
        .collect()
}

/// The arena configuration of one run with `seed`.
///
/// # Errors
/// [`PlaneError::Placement`] if the robots cannot be placed.
pub fn config(spec: &PlaneSpec, seed: u64) -> Result<ArenaConfig, PlaneError> {
    let rel = positions(spec, seed).map_err(PlaneError::Placement)?;
    let range = spec.medium.range;
    let metres = rel.iter().map(|v| Point2::from(v * range)).collect();
    let mut params = spec.params;
    params.sectors = spec.sectors;
    let period = params.nominal_period();
    let mut c = ArenaConfig::line(
        Vec::new(),
        1.0,
        period.saturating_mul(u64::from(spec.moves)),
        seed,
    );
    c.positions = metres;
    c.ids = Some(spread_ids(&rel));
    c.robot.params = params;
    c.medium = spec.medium;
    c.env = Environment::plane(
        spec.scenario.field.clone(),
        rel.iter().map(|v| Point2::from(*v)).collect(),
        Vector2::new(spec.x_init, 0.0),
    );
    let (base, gain, noise) = sensor_scale(&spec.scenario);
    if let Some(f) = c.env.field.as_mut() {
        f.base = base;
        f.gain = gain;
    }
    c.env.noise = noise;
    c.env.readings = spec.readings;
    c.motion = Some(Motion {
        period,
        step: spec.scenario.run.step,
    });
    c.hil = spec.hil.clone();
    if let Some(p) = spec.sample_period {
        c.robot.sample_period = p;
    }
    Ok(c)
}

/// How the sensor reads the scenario's field: `(base, gain, noise)`, the level of X being
/// `base + gain · X` and the noise ± `noise` levels. The field's range where a swarm can go
/// (|x|, |y| ≤ 10 R) maps into 30..=255 with at most 34 levels per unit of X (the sharp border's
/// 0 and 5 read 30 and 200, the lab's dark and lit); the paper's noise of width `noise` in X
/// becomes ± `gain · noise / 2` levels. A steeper gain would saturate the gradient's ramp
/// (2.5 per R) 2.6 R into it, where the swarm must go, and stall it there.
pub fn sensor_scale(scenario: &Scenario) -> (f64, f64, u8) {
    let (lo, hi) = scenario.field.range_over((-10.0, 10.0), (-10.0, 10.0));
    let gain = if hi > lo {
        (225.0 / (hi - lo)).min(34.0)
    } else {
        34.0
    };
    let noise = (gain * scenario.run.noise / 2.0).round().clamp(0.0, 255.0) as u8;
    (30.0 - gain * lo, gain, noise)
}

/// The centre after each move, and the first move after which `success` held.
fn judge(moves: &[Move], step: f64, success: &Success) -> (Option<u32>, Point2<f64>) {
    let mut first = None;
    let mut last = moves.first().map_or(Point2::origin(), |m| m.centre);
    for (k, m) in moves.iter().enumerate() {
        let after = match m.heading {
            Some(h) => m.centre + Vector2::new(h.cos(), h.sin()) * step,
            None => m.centre,
        };
        if first.is_none() && success.met(after) {
            first = Some(k as u32 + 1);
        }
        last = after;
    }
    (first, last)
}

/// Runs one experiment with `seed`.
///
/// # Errors
/// A [`PlaneError`] if it cannot be set up.
pub fn run(spec: &PlaneSpec, seed: u64) -> Result<PlaneRun, PlaneError> {
    Ok(run_traced(spec, seed, false)?.0)
}

/// Runs one experiment with `seed`, with its configuration and, if `trace`, its trace.
///
/// # Errors
/// A [`PlaneError`] if it cannot be set up.
pub fn run_traced(
    spec: &PlaneSpec,
    seed: u64,
    trace: bool,
) -> Result<(PlaneRun, ArenaConfig, Vec<hal_emu::TraceEvent>), PlaneError> {
    let mut cfg = config(spec, seed)?;
    cfg.trace = trace;
    let mut report = hal_emu::run(&cfg).map_err(|e| PlaneError::Arena(e.to_string()))?;
    let events = std::mem::take(&mut report.trace);
    // A field without a criterion (the cloud) is reported, never a success.
    let never = Success::BeyondX { x: f64::INFINITY };
    let success = spec.scenario.success.unwrap_or(never);
    let (first, end) = judge(&report.moves, spec.scenario.run.step, &success);
    let leds = hal_emu::judge::leds_str(&report.leds_at(protocol::Instant::MAX));
    let run = PlaneRun {
        seed,
        success: first.is_some(),
        moves_to_success: first,
        consensus: report.moves.iter().map(|m| m.consensus).collect(),
        final_position: [end.x, end.y],
        leds,
        emulated_s: report.emulated.as_secs_f64(),
        wall_s: report.wall.as_secs_f64(),
        hil: report.hil,
    };
    Ok((run, cfg, events))
}

/// The viewer's header of a plane run: the set-up, the goal and the verdict.
pub fn viewer_header(
    spec: &PlaneSpec,
    cfg: &ArenaConfig,
    run: &PlaneRun,
    trace: &[hal_emu::TraceEvent],
) -> crate::viewer::Header {
    let mut h = crate::viewer::header_of(cfg, trace);
    h.title = format!("cimax arena: {}, seed {}", spec.summary(), run.seed);
    if let Some(f) = h.field.as_mut() {
        f.label = format!("field {} (X)", spec.scenario.name);
    }
    h.goal = crate::viewer::goal_of(spec.scenario.success);
    h.verdict = Some(crate::viewer::move_verdict(
        h.goal.as_ref(),
        run.moves_to_success,
        spec.moves,
        "moves",
        run.final_position,
        run.leds.clone(),
    ));
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_files_are_read_and_their_errors_name_the_line() {
        let p = read_positions("# a triangle\n0 0\n\n1.5,0\n0.75 1.3\n", "t.txt").unwrap();
        assert_eq!(p.len(), 3);
        assert!((p.iter().fold(Vector2::zeros(), |s, q| s + q)).norm() < 1e-12);
        let e = read_positions("0 0\n1 x\n", "t.txt").unwrap_err();
        assert!(e.starts_with("t.txt:2:") && e.contains("\"x\""), "{e}");
        let e = read_positions("0 0\n1 2 3\n", "t.txt").unwrap_err();
        assert!(e.starts_with("t.txt:2:"), "{e}");
        let e = read_positions("0 inf\n1 2\n", "t.txt").unwrap_err();
        assert!(e.starts_with("t.txt:1:"), "{e}");
        assert!(
            read_positions("0 0\n", "t.txt")
                .unwrap_err()
                .contains("1 robots")
        );
    }

    #[test]
    fn the_sharp_border_reads_as_the_lab_and_the_gradient_does_not_saturate() {
        let sharp = Scenario::load("sharp").unwrap();
        assert_eq!(sensor_scale(&sharp), (30.0, 34.0, 17));
        let gradient = Scenario::load("gradient").unwrap();
        let (base, gain, noise) = sensor_scale(&gradient);
        // X reaches 25 at x = 10 R: 30 + 9 × 25 = 255.
        assert_eq!((base, gain, noise), (30.0, 9.0, 5));
    }

    #[test]
    fn spread_ids_keep_equal_tags_apart_on_the_lattice() {
        let p = crate::swarm::geometry::lattice(61, SPACING);
        let ids = spread_ids(&p);
        let mut closest = f64::INFINITY;
        for i in 0..p.len() {
            for j in 0..i {
                if ids[i] % 16 == ids[j] % 16 {
                    closest = closest.min((p[i] - p[j]).norm() / SPACING);
                }
            }
        }
        assert!(closest >= 3.0, "{closest}");
        // Ids stay distinct.
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), ids.len());
    }

    #[test]
    fn the_centre_moves_by_a_step_along_each_heading() {
        let m = |x: f64, h: Option<f64>| Move {
            t: protocol::Instant::ZERO,
            centre: Point2::new(x, 0.0),
            heading: h,
            consensus: 1.0,
        };
        let near = Success::NearX {
            x: 0.0,
            within: 0.33,
        };
        // From -0.9: -0.57 after the first move, -0.24 after the second (success), then no
        // decision, no move.
        let moves = [m(-0.9, Some(0.0)), m(-0.57, Some(0.0)), m(-0.24, None)];
        let (first, end) = judge(&moves, 0.33, &near);
        assert_eq!(first, Some(2));
        assert!((end.x + 0.24).abs() < 1e-12, "{end}");
        let (first, _) = judge(&moves[..1], 0.33, &near);
        assert_eq!(first, None);
    }
}

/// Prints the runs of one plane experiment (a table, or JSON with `json`); exit code 0.
pub fn print_runs(
    spec: &PlaneSpec,
    runs: &[PlaneRun],
    wall_s: f64,
    json: bool,
) -> std::process::ExitCode {
    let ok = runs.iter().filter(|r| r.success).count();
    let emulated: f64 = runs.iter().map(|r| r.emulated_s).sum();
    let mean_moves = mean(
        runs.iter()
            .filter_map(|r| r.moves_to_success.map(f64::from)),
    );
    if json {
        #[derive(Serialize)]
        struct Summary {
            runs: usize,
            successes: usize,
            mean_moves_to_success: Option<f64>,
            emulated_s: f64,
            wall_s: f64,
            robot_s_per_wall_s: f64,
        }
        #[derive(Serialize)]
        struct Report<'a> {
            runs: &'a [PlaneRun],
            summary: Summary,
        }
        let report = Report {
            runs,
            summary: Summary {
                runs: runs.len(),
                successes: ok,
                mean_moves_to_success: mean_moves,
                emulated_s: emulated,
                wall_s,
                robot_s_per_wall_s: emulated * spec.robots as f64 / wall_s.max(1e-9),
            },
        };
        match serde_json::to_string_pretty(&report) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("cimax arena: {e}");
                return std::process::ExitCode::from(2);
            }
        }
        return std::process::ExitCode::SUCCESS;
    }
    println!(
        "CIMAX arena on a plane, the robot program on {} of {} R",
        spec.summary(),
        spec.scenario.run.step
    );
    println!("seed      success  moves  final x  final y  mean consensus");
    for r in runs {
        println!(
            "{:<9} {:<8} {:>5}  {:>7.2}  {:>7.2}  {:>14.2}",
            r.seed,
            if r.success { "yes" } else { "no" },
            r.moves_to_success.map_or("-".into(), |m| m.to_string()),
            r.final_position[0],
            r.final_position[1],
            mean(r.consensus.iter().copied()).unwrap_or(0.0)
        );
        for h in &r.hil {
            println!(
                "  robot {} in the loop over {}: {} link frames sent to it, {} received ({} light frames), {} link errors",
                h.robot, h.transport, h.frames_sent, h.frames_received, h.tx, h.link_errors
            );
        }
    }
    println!(
        "{} runs, {} successful ({}); mean moves to success {}; {:.0} robot-s in {:.1} s wall",
        runs.len(),
        ok,
        spec.scenario
            .success
            .map_or("no criterion".into(), |s| s.to_string()),
        mean_moves.map_or("-".into(), |m| format!("{m:.1}")),
        emulated * spec.robots as f64,
        wall_s
    );
    std::process::ExitCode::SUCCESS
}

fn mean(xs: impl Iterator<Item = f64>) -> Option<f64> {
    crate::stats::mean(&xs.collect::<Vec<_>>())
}

/// Options of `cimax arena sweep`.
#[derive(clap::Args, Debug, Clone)]
pub struct SweepArgs {
    /// The field: a `cimax swarm` scenario (sharp, gradient) or its TOML file.
    #[arg(long, default_value = "sharp")]
    pub field: String,
    /// How the robots are placed.
    #[arg(long, value_enum, default_value_t = Placement::Lattice)]
    pub shape: Placement,
    /// Number of robots.
    #[arg(long, default_value_t = 61, value_parser = clap::value_parser!(u16).range(2..=1000))]
    pub robots: u16,
    /// Receive sectors per robot.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(2..=8))]
    pub sectors: u8,
    /// First initial x, in R.
    #[arg(long, default_value_t = -4.0, allow_hyphen_values = true)]
    pub from: f64,
    /// Last initial x, in R.
    #[arg(long, default_value_t = 4.0, allow_hyphen_values = true)]
    pub to: f64,
    /// Step between initial positions, in R.
    #[arg(long, default_value_t = 1.0)]
    pub step: f64,
    /// Runs per position (run k uses seed BASE + k).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub runs: u64,
    /// Base seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Moves per run.
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub moves: u32,
    /// Probability that a frame is lost at a receiver.
    #[arg(long, default_value_t = 0.0)]
    pub loss: f64,
    /// What the light sensors report (`full`, `binary`, `levels:N`, `gain:G,offset:B`; see
    /// `cimax arena --help`).
    #[arg(long, value_name = "KIND", default_value_t = hal_emu::Readings::Levels)]
    pub readings: hal_emu::Readings,
    /// Runs of the 2D simulator (`cimax swarm`, three-phase variant, same placement) per
    /// position, for the curve beside, 0 to 100,000; 0 leaves it out.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(0..=i64::from(crate::swarm::scenario::MAX_RUNS_PER_POINT)))]
    pub swarm_runs: u32,
    /// Where to write the CSV and the SVG (`arena-<field>-sweep.csv|svg`).
    #[arg(long, default_value = "target/arena-sweep")]
    pub out: std::path::PathBuf,
}

/// `cimax arena sweep`: success rate and mean moves to success against the initial position,
/// the robot program beside the 2D simulator and the paper.
pub fn sweep_main(a: &SweepArgs) -> std::process::ExitCode {
    match sweep(a) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("cimax arena sweep: {e}");
            std::process::ExitCode::from(2)
        }
    }
}

fn sweep(a: &SweepArgs) -> Result<(), String> {
    let scenario = Scenario::load(&a.field).map_err(|e| e.to_string())?;
    if scenario.success.is_none() {
        return Err(PlaneError::NoCriterion(scenario.name).to_string());
    }
    let (xs, medium) = sweep_positions(a)?;
    let arena = arena_points(a, &scenario, &xs, medium)?;
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let csv = a.out.join(format!("arena-{}-sweep.csv", scenario.name));
    crate::report::write_sweep_csv(&csv, &arena).map_err(|e| format!("{}: {e}", csv.display()))?;
    let swarm = swarm_points(a, &scenario, &xs)?;
    let svg = sweep_svg(a, &scenario, &arena, swarm.as_deref())?;
    print_sweep(&arena, swarm.as_deref());
    println!("wrote {} and {}", csv.display(), svg.display());
    Ok(())
}

/// The initial positions of `cimax arena sweep` and its medium, after checking the options.
fn sweep_positions(a: &SweepArgs) -> Result<(Vec<f64>, MediumParams), String> {
    if a.shape == Placement::File {
        return Err("sweep places robots on a line, the lattice or a disk, not from a file".into());
    }
    if !(a.step > 0.0 && a.from.is_finite() && a.to.is_finite() && a.from <= a.to) {
        return Err(format!(
            "--from {} --to {} --step {}: need from <= to and a positive step",
            a.from, a.to, a.step
        ));
    }
    // At most 10,001 positions, as `cimax swarm sweep`: a tiny step would ask for billions.
    let span = (a.to - a.from) / a.step;
    if span > 10_000.0 {
        return Err(format!(
            "--from {} --to {} --step {}: {} positions; at most 10001",
            a.from,
            a.to,
            a.step,
            (span + 1e-9).floor() + 1.0
        ));
    }
    let medium = MediumParams {
        loss: a.loss,
        ..MediumParams::default()
    };
    medium.validate()?;
    let count = (span + 1e-9).floor() as usize + 1;
    check_runs(&[(count as u64, "positions"), (a.runs, "runs")])
        .map_err(|e| format!("--runs {}: {e}", a.runs))?;
    check_runs(&[
        (count as u64, "positions"),
        (u64::from(a.swarm_runs), "runs"),
    ])
    .map_err(|e| format!("--swarm-runs {}: {e}", a.swarm_runs))?;
    let xs: Vec<f64> = (0..count).map(|i| a.from + a.step * i as f64).collect();
    Ok((xs, medium))
}

/// The robots' sweep: every position `a.runs` times, in parallel.
fn arena_points(
    a: &SweepArgs,
    scenario: &Scenario,
    xs: &[f64],
    medium: MediumParams,
) -> Result<Vec<crate::swarm::experiment::SweepPoint>, String> {
    use rayon::prelude::*;
    let spec = |x: f64| PlaneSpec {
        scenario: scenario.clone(),
        placement: a.shape,
        robots: usize::from(a.robots),
        sectors: a.sectors,
        x_init: x,
        moves: a.moves,
        medium,
        params: Params::robots(),
        file_positions: Vec::new(),
        readings: a.readings,
        hil: Vec::new(),
        sample_period: None,
    };
    let jobs: Vec<(usize, u64)> = (0..xs.len())
        .flat_map(|p| (0..a.runs).map(move |k| (p, a.seed.wrapping_add(k))))
        .collect();
    let bar = crate::progress::Progress::new(jobs.len() as u64, "arena sweep", false);
    let runs: Vec<(usize, PlaneRun)> = jobs
        .par_iter()
        .map(|&(p, s)| {
            let r = run(&spec(xs[p]), s);
            bar.inc();
            r.map(|r| (p, r))
        })
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    bar.finish();
    let arena = xs
        .iter()
        .enumerate()
        .map(|(p, &x)| {
            let mine: Vec<&PlaneRun> = runs
                .iter()
                .filter(|(q, _)| *q == p)
                .map(|(_, r)| r)
                .collect();
            crate::swarm::experiment::SweepPoint {
                x_init: x,
                runs: mine.len() as u32,
                successes: mine.iter().filter(|r| r.success).count() as u32,
                mean_success_periods: mean(
                    mine.iter()
                        .filter_map(|r| r.moves_to_success.map(f64::from)),
                ),
            }
        })
        .collect();
    Ok(arena)
}

/// The swarm simulator's sweep over the same positions (none with `--swarm-runs 0`), and its
/// CSV file.
fn swarm_points(
    a: &SweepArgs,
    scenario: &Scenario,
    xs: &[f64],
) -> Result<Option<Vec<crate::swarm::experiment::SweepPoint>>, String> {
    let mut swarm_scn = scenario.clone();
    if a.shape == Placement::Lattice {
        swarm_scn.shape = Shape::Lattice { spacing: SPACING };
    }
    swarm_scn.agents = usize::from(a.robots);
    Ok(if a.swarm_runs > 0 {
        let progress = crate::progress::Progress::new(
            (xs.len() * a.swarm_runs as usize) as u64,
            "swarm sweep",
            false,
        );
        let pts = crate::swarm::experiment::sweep(
            &swarm_scn,
            swarm_scn.run,
            xs,
            a.swarm_runs,
            a.seed,
            &progress,
        )
        .map_err(|e| e.to_string())?;
        progress.finish();
        let csv = a.out.join(format!("swarm-{}-sweep.csv", scenario.name));
        crate::report::write_sweep_csv(&csv, &pts)
            .map_err(|e| format!("{}: {e}", csv.display()))?;
        Some(pts)
    } else {
        None
    })
}

/// The sweep's figure: the robots beside the swarm simulator and the paper.
fn sweep_svg(
    a: &SweepArgs,
    scenario: &Scenario,
    arena: &[crate::swarm::experiment::SweepPoint],
    swarm: Option<&[crate::swarm::experiment::SweepPoint]>,
) -> Result<std::path::PathBuf, String> {
    let arena_label = format!("robot program (arena), K = {}", a.sectors);
    let mut series: Vec<(&str, &[crate::swarm::experiment::SweepPoint])> =
        vec![(&arena_label, arena)];
    if let Some(s) = swarm {
        series.push(("three-phase (cimax swarm)", s));
    }
    // The same paper marks as docs/reproduction.md's sweeps (the gradient's 85–100 % band and
    // its 25 % at −4), for the built-in scenarios.
    let paper = crate::pages::marks::sweep_for(&scenario.name);
    let svg = a.out.join(format!("arena-{}-sweep.svg", scenario.name));
    crate::report::plot::sweep_figure(
        &svg,
        &format!(
            "{}: {} robots ({:?}), success within {} moves, {} runs per point",
            scenario.name, a.robots, a.shape, a.moves, a.runs
        ),
        &series,
        &paper,
    )
    .map_err(|e| format!("{}: {e}", svg.display()))?;
    Ok(svg)
}

/// The sweep as a table on stdout.
fn print_sweep(
    arena: &[crate::swarm::experiment::SweepPoint],
    swarm: Option<&[crate::swarm::experiment::SweepPoint]>,
) {
    println!("x_init  arena success  moves   swarm success  moves");
    for (i, p) in arena.iter().enumerate() {
        let s = swarm.and_then(|s| s.get(i));
        println!(
            "{:>6.2}  {:>13.2}  {:>5}   {:>13}  {:>5}",
            p.x_init,
            p.success_rate(),
            p.mean_success_periods
                .map_or("-".into(), |m| format!("{m:.1}")),
            s.map_or("-".into(), |s| format!("{:.2}", s.success_rate())),
            s.and_then(|s| s.mean_success_periods)
                .map_or("-".into(), |m| format!("{m:.1}")),
        );
    }
}

/// Options of `cimax arena bench`.
#[derive(clap::Args, Debug, Clone)]
pub struct BenchArgs {
    /// Swarm sizes to time (robots on the hexagonal lattice), 2 to 1000 each.
    #[arg(long, value_delimiter = ',', default_values_t = [4u16, 64, 1000], value_parser = clap::value_parser!(u16).range(2..=1000))]
    pub robots: Vec<u16>,
    /// Receive sectors per robot.
    #[arg(long, default_value_t = 6, value_parser = clap::value_parser!(u8).range(2..=8))]
    pub sectors: u8,
    /// Seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `cimax arena bench`: robot-seconds per wall second of the robot program over the emulated
/// medium, one negotiation period (550 s) of the sharp field 2 R from the border, on one core
/// (one run at a time on the calling thread).
pub fn bench_main(a: &BenchArgs) -> std::process::ExitCode {
    let scenario = match Scenario::load("sharp") {
        Ok(s) => s,
        Err(e) => {
            eprintln!("cimax arena bench: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    println!("robots  emulated s  wall s  robot-s per wall s  x real time");
    for &n in &a.robots {
        let spec = PlaneSpec {
            scenario: scenario.clone(),
            placement: Placement::Lattice,
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
        match run(&spec, a.seed) {
            Ok(r) => {
                let rate = r.emulated_s * spec.robots as f64 / r.wall_s.max(1e-9);
                println!(
                    "{:>6}  {:>10.0}  {:>6.2}  {:>18.3e}  {:>11.0}",
                    spec.robots,
                    r.emulated_s,
                    r.wall_s,
                    rate,
                    r.emulated_s / r.wall_s.max(1e-9)
                );
            }
            Err(e) => {
                eprintln!("cimax arena bench: {e}");
                return std::process::ExitCode::from(2);
            }
        }
    }
    std::process::ExitCode::SUCCESS
}
