//! `cimax arena sweep`: success rate and mean moves to success against the initial position,
//! the robot program on a plane ([`lab::plane::sweep_run`]) beside the 2D
//! simulator ([`swarm_sim::experiment::sweep_run`]) and the paper; and its shards.
//!
//! The job ([`SweepJob`]) is numbered in units: first every robots' run, position by position
//! (`p * runs + k`: run `k` from `xs[p]`), then every run of the 2D simulator the same way. The
//! unsharded command computes them all and writes with [`SweepJob::write`]; `--shard I/N`
//! computes its share into a part; `cimax merge` hands the parts' results to the same
//! [`SweepJob::write`].

use std::path::{Path, PathBuf};

use hal_emu::world::hil::HilSpec;
use hal_emu::{MediumParams, Readings};
use host_sim::shard::{self, Job, ShardSpec, merge::Merged};
use lab::InTheLoop;
use lab::plane::{self, Layout, PlaneError, PlaneSpec, SweepRun};
use protocol::Params;
use serde::{Deserialize, Serialize};
use swarm_sim::experiment::{self, SweepPoint};
use swarm_sim::geometry::Shape;
use swarm_sim::progress::Progress;
use swarm_sim::scenario::{MAX_EXTENT, Placement, Scenario, check_runs};

use super::options::in_the_loop;
use super::plane::shape_parser;
use crate::cli::job::ScenarioSource;
use crate::cli::out::{Exit, Fail, StdoutError, outln};

/// The job's command in a part's header.
pub const COMMAND: &str = "arena sweep";

/// Options of `cimax arena sweep`.
#[derive(clap::Args, Debug, Clone)]
#[command(allow_negative_numbers = true)]
pub struct SweepArgs {
    /// The field: a `cimax swarm` scenario (sharp, gradient) or its TOML file.
    #[arg(long, default_value = "sharp")]
    pub field: String,
    /// How the robots are placed.
    #[arg(long, value_parser = shape_parser(), default_value = "lattice")]
    pub shape: Layout,
    /// Number of robots.
    #[arg(long, default_value_t = 61, value_parser = crate::cli::values::whole::<u16>(2, 1000))]
    pub robots: u16,
    /// Receive sectors per robot.
    #[arg(long, default_value_t = 6, value_parser = crate::cli::values::whole::<u8>(2, 8))]
    pub sectors: u8,
    /// First initial x, in R.
    #[arg(long, default_value_t = -4.0, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
    pub from: f64,
    /// Last initial x, in R.
    #[arg(long, default_value_t = 4.0, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
    pub to: f64,
    /// Step between initial positions, in R.
    #[arg(long, default_value_t = 1.0, value_parser = crate::cli::values::positive(2.0 * MAX_EXTENT, "a step in R"))]
    pub step: f64,
    /// Runs per position (run k uses seed BASE + k).
    #[arg(long, default_value_t = 10, value_parser = crate::cli::values::whole::<u64>(1, 10_000))]
    pub runs: u64,
    /// Base seed.
    #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
    pub seed: u64,
    /// Moves per run.
    #[arg(long, default_value_t = 50, value_parser = crate::cli::values::whole::<u32>(1, 1000))]
    pub moves: u32,
    /// Probability that a frame is lost at a receiver.
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::number(0.0, 1.0, "a probability"))]
    pub loss: f64,
    /// What the light sensors report (`full`, `binary`, `levels:N`, `gain:G,offset:B`; see
    /// `cimax arena --help`).
    #[arg(long, value_name = "KIND", default_value_t = Readings::Levels)]
    pub readings: Readings,
    /// Runs of the 2D simulator (`cimax swarm`, three-phase variant, same placement) per
    /// position, for the curve beside, 0 to 100,000; 0 leaves it out.
    #[arg(long, default_value_t = 20, value_parser = crate::cli::values::whole::<u32>(0, u64::from(swarm_sim::scenario::MAX_RUNS_PER_POINT)))]
    pub swarm_runs: u32,
    /// Where to write the CSV and the SVG (`arena-<field>-sweep.csv|svg`); with --shard, the
    /// part.
    #[arg(long, default_value = "target/arena-sweep")]
    pub out: PathBuf,
    /// Run only shard I of N (1 <= I <= N) of the sweep's runs and write them to
    /// OUT/part-I-of-N.jsonl, nothing else; `cimax merge` makes the outputs of all N parts.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<ShardSpec>,
    /// Robots in the loop in every run of the robots, on the arena's clock (docs/hil.md):
    /// `qemu:N` (N QEMU robots running the Cortex-M HIL image, `hil6` with 6 sectors, `hil`
    /// with 2) or `loopback:N` (its host build in this process), spread evenly over the
    /// robots' places (0, R/N, 2R/N, ... of R robots). Not in the 2D simulator's runs.
    #[arg(long, value_name = "qemu:N|loopback:N")]
    pub hil: Option<HilSpec>,
    /// The image --hil qemu:N boots (default: the one `cargo hil-image` builds).
    #[arg(long, value_name = "ELF", requires = "hil")]
    pub hil_image: Option<PathBuf>,
}

/// Everything that makes a sweep's results, resolved: the job in a part's header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepJob {
    /// The field.
    field: ScenarioSource,
    /// `line`, `lattice` or `disk`.
    shape: String,
    robots: u16,
    sectors: u8,
    /// The initial positions, in R.
    xs: Vec<f64>,
    runs: u64,
    seed: u64,
    moves: u32,
    loss: f64,
    /// As `--readings` spells it.
    readings: String,
    swarm_runs: u32,
    /// Robots in the loop in every run of the robots; absent in parts of sweeps without.
    #[serde(default)]
    hil: Option<InTheLoop>,
}

/// A unit's result: one run of the robots or one of the 2D simulator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
enum Unit {
    /// A run of the robots.
    Arena(SweepRun),
    /// A run of the 2D simulator: the periods until success, if it succeeded.
    Swarm {
        /// The periods until success.
        success_at: Option<u32>,
    },
}

/// What a job runs on, made once from it.
struct Ready {
    scenario: Scenario,
    layout: Layout,
    /// The robots' experiment (its `x_init` replaced per position).
    base: PlaneSpec,
    /// The 2D simulator's scenario, with the robots' placement and number.
    swarm: Scenario,
}

/// `cimax arena sweep`: the unsharded sweep, or one shard of it.
pub fn sweep_main(a: &SweepArgs) -> Exit {
    sweep(a)?;
    Ok(std::process::ExitCode::SUCCESS)
}

fn sweep(a: &SweepArgs) -> Result<(), Fail> {
    crate::cli::files::check_dir("--out", &a.out)?;
    let job = SweepJob::of(a)?;
    let ready = job.ready()?;
    let total = job.units();
    let unit = |k| job.unit(&ready, k);
    if let Some(shard) = a.shard {
        let config = Job::new(COMMAND, &job).map_err(|e| e.to_string())?;
        let path = shard::run_shard(config, total, shard, &a.out, false, unit)
            .map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
        return Ok(());
    }
    let all: Vec<u64> = (0..total).collect();
    let units = shard::compute(&all, &Progress::new(total, "arena sweep", false), unit)?;
    job.write(&ready, &units, &a.out)
}

/// `cimax merge` of an arena sweep's parts: the outputs into `out`, as the unsharded sweep
/// with `--out OUT` writes them.
///
/// # Errors
/// If the parts are not a sweep this cimax can write, or the outputs cannot be written.
pub fn merge(m: &Merged, out: &Path) -> Exit {
    let (job, units): (SweepJob, Vec<Unit>) = m.decode().map_err(|e| e.to_string())?;
    let ready = job.ready().map_err(|e| m.bad_config(e).to_string())?;
    if units.len() as u64 != job.units() {
        let e = format!("{} units, but the sweep has {}", units.len(), job.units());
        return Err(m.bad_config(e).to_string().into());
    }
    job.write(&ready, &units, out)?;
    Ok(std::process::ExitCode::SUCCESS)
}

/// `--shape` as a job spells it.
fn layout_name(l: Layout) -> &'static str {
    match l {
        Layout::Line => "line",
        Layout::Placed(Placement::Lattice) => "lattice",
        Layout::Placed(Placement::Random) => "disk",
        Layout::File => "file",
    }
}

impl SweepJob {
    /// The job the options ask for, checked.
    fn of(a: &SweepArgs) -> Result<SweepJob, String> {
        if a.shape == Layout::File {
            return Err(
                "sweep places robots on a line, the lattice or a disk, not from a file".into(),
            );
        }
        Ok(SweepJob {
            field: ScenarioSource::of(&a.field)?,
            shape: layout_name(a.shape).into(),
            robots: a.robots,
            sectors: a.sectors,
            xs: positions(a)?,
            runs: a.runs,
            seed: a.seed,
            moves: a.moves,
            loss: a.loss,
            readings: a.readings.to_string(),
            swarm_runs: a.swarm_runs,
            hil: in_the_loop(
                a.hil.as_ref(),
                a.hil_image.as_ref(),
                a.sectors,
                usize::from(a.robots),
            )?,
        })
    }

    /// What the runs need: the scenario (with a success criterion), the robots' experiment and
    /// the 2D simulator's scenario.
    fn ready(&self) -> Result<Ready, String> {
        let scenario = self.field.load()?;
        if scenario.success.is_none() {
            return Err(PlaneError::NoCriterion(scenario.name).to_string());
        }
        let layout = [
            Layout::Line,
            Layout::Placed(Placement::Lattice),
            Layout::Placed(Placement::Random),
        ]
        .into_iter()
        .find(|&l| layout_name(l) == self.shape)
        .ok_or_else(|| format!("no shape {:?}", self.shape))?;
        let medium = MediumParams {
            loss: self.loss,
            ..MediumParams::default()
        };
        medium.validate().map_err(|e| e.to_string())?;
        check_runs(&[(self.xs.len() as u64, "positions"), (self.runs, "runs")])
            .map_err(|e| format!("--runs {}: {e}", self.runs))?;
        check_runs(&[
            (self.xs.len() as u64, "positions"),
            (u64::from(self.swarm_runs), "runs"),
        ])
        .map_err(|e| format!("--swarm-runs {}: {e}", self.swarm_runs))?;
        let base = PlaneSpec {
            scenario: scenario.clone(),
            placement: layout,
            robots: usize::from(self.robots),
            sectors: self.sectors,
            x_init: 0.0,
            moves: self.moves,
            medium,
            params: Params::robots(),
            file_positions: Vec::new(),
            readings: self
                .readings
                .parse()
                .map_err(|e| format!("--readings: {e}"))?,
            hil: self.hil.as_ref().map_or_else(Vec::new, |h| {
                let n = usize::from(self.robots);
                let places: Vec<usize> = (0..h.robots).map(|k| k * n / h.robots).collect();
                h.at(&places)
            }),
            sample_period: None,
        };
        let mut swarm = scenario.clone();
        if layout == Layout::Placed(Placement::Lattice) {
            swarm.shape = Shape::Lattice {
                spacing: plane::SPACING,
            };
        }
        swarm.agents = usize::from(self.robots);
        Ok(Ready {
            scenario,
            layout,
            base,
            swarm,
        })
    }

    /// Runs of the robots (the first units).
    fn arena_units(&self) -> u64 {
        self.xs.len() as u64 * self.runs
    }

    /// Units of the job: the robots' runs, then the 2D simulator's.
    fn units(&self) -> u64 {
        self.arena_units() + self.xs.len() as u64 * u64::from(self.swarm_runs)
    }

    /// Unit `k`.
    fn unit(&self, r: &Ready, k: u64) -> Result<Unit, String> {
        let arena = self.arena_units();
        if k < arena {
            plane::sweep_run(&r.base, &self.xs, self.runs, self.seed, k)
                .map(Unit::Arena)
                .map_err(|e| e.to_string())
        } else {
            experiment::sweep_run(
                &r.swarm,
                r.swarm.run,
                &self.xs,
                self.swarm_runs,
                self.seed,
                k - arena,
            )
            .map(|success_at| Unit::Swarm { success_at })
            .map_err(|e| e.to_string())
        }
    }

    /// The points of both sweeps from every unit's result, in unit order.
    fn points(&self, units: &[Unit]) -> Result<(Vec<SweepPoint>, Vec<SweepPoint>), String> {
        let split = usize::try_from(self.arena_units()).unwrap_or(usize::MAX);
        let mut arena = Vec::new();
        let mut swarm = Vec::new();
        for (k, u) in units.iter().enumerate() {
            match (u, k < split) {
                (Unit::Arena(r), true) => arena.push(*r),
                (Unit::Swarm { success_at }, false) => swarm.push(*success_at),
                _ => return Err(format!("unit {k}: a run of the other simulator")),
            }
        }
        Ok((
            plane::sweep_points(&self.xs, self.runs, &arena),
            experiment::sweep_points(&self.xs, self.swarm_runs, &swarm),
        ))
    }

    /// Writes the sweep's CSV files and figure into `out` and prints its table: what the
    /// unsharded sweep and the merge of its parts both do with the units' results.
    fn write(&self, r: &Ready, units: &[Unit], out: &Path) -> Result<(), Fail> {
        let (arena, swarm) = self.points(units)?;
        let swarm = (self.swarm_runs > 0).then_some(swarm);
        let name = &r.scenario.name;
        let csv = out.join(format!("arena-{name}-sweep.csv"));
        let mut staged = crate::cli::files::Staged::new();
        staged.write_with(&csv, |p| pages::csv::write_sweep_csv(p, &arena))?;
        if let Some(pts) = &swarm {
            let csv = out.join(format!("swarm-{name}-sweep.csv"));
            staged.write_with(&csv, |p| pages::csv::write_sweep_csv(p, pts))?;
        }
        let svg = self.figure(r, &arena, swarm.as_deref(), out, &mut staged)?;
        staged.commit()?;
        print_sweep(&arena, swarm.as_deref())?;
        outln!("wrote {} and {}", csv.display(), svg.display())?;
        Ok(())
    }

    /// The sweep's figure: the robots beside the swarm simulator and the paper.
    fn figure(
        &self,
        r: &Ready,
        arena: &[SweepPoint],
        swarm: Option<&[SweepPoint]>,
        out: &Path,
        staged: &mut crate::cli::files::Staged,
    ) -> Result<PathBuf, String> {
        let arena_label = format!("robot program (arena), K = {}", self.sectors);
        let mut series: Vec<(&str, &[SweepPoint])> = vec![(&arena_label, arena)];
        if let Some(s) = swarm {
            series.push(("three-phase (cimax swarm)", s));
        }
        // The same paper marks as docs/reproduction.md's sweeps (the gradient's 85–100 % band
        // and its 25 % at −4), for the built-in scenarios.
        let paper = pages::marks::sweep_for(&r.scenario.name);
        let svg = out.join(format!("arena-{}-sweep.svg", r.scenario.name));
        let title = format!(
            "{}: {} robots ({}), success within {} moves, {} runs per point",
            r.scenario.name,
            self.robots,
            r.layout.label(),
            self.moves,
            self.runs
        );
        staged.write_with(&svg, |p| {
            pages::figures::sweep_figure(p, &title, &series, &paper)
        })?;
        Ok(svg)
    }
}

/// The initial positions `--from`, `--to` and `--step` ask for, at most 10,001.
fn positions(a: &SweepArgs) -> Result<Vec<f64>, String> {
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
    let count = (span + 1e-9).floor() as usize + 1;
    Ok((0..count).map(|i| a.from + a.step * i as f64).collect())
}

/// The sweep as a table on stdout.
fn print_sweep(arena: &[SweepPoint], swarm: Option<&[SweepPoint]>) -> Result<(), StdoutError> {
    outln!("x_init  arena success  moves   swarm success  moves")?;
    for (i, p) in arena.iter().enumerate() {
        let s = swarm.and_then(|s| s.get(i));
        outln!(
            "{:>6.2}  {:>13.2}  {:>5}   {:>13}  {:>5}",
            p.x_init,
            p.success_rate(),
            p.mean_success_periods
                .map_or("-".into(), |m| format!("{m:.1}")),
            s.map_or("-".into(), |s| format!("{:.2}", s.success_rate())),
            s.and_then(|s| s.mean_success_periods)
                .map_or("-".into(), |m| format!("{m:.1}")),
        )?;
    }
    Ok(())
}
