//! `cimax swarm run|sweep|field|reproduce|bench`: the options of the 2D simulator's commands
//! and what each does with the library (run the experiment, write its CSV and SVG, print).
//! `sweep` and `reproduce`, which shard (`--shard I/N`), are [`sweep`] and [`reproduce`].

mod reproduce;
mod sweep;

pub(crate) use reproduce::{COMMAND as REPRODUCE_COMMAND, merge as merge_reproduce};
pub(crate) use sweep::{COMMAND as SWEEP_COMMAND, merge as merge_sweep};

use std::path::{Path, PathBuf};
use std::time::Instant as Clock;

use clap::{Args, Subcommand};
use nalgebra::Point2;
use pages::csv::{write_field_csv, write_run_csv};
use pages::figures;
use protocol::Duration;
use swarm_sim::experiment;
use swarm_sim::progress::Progress;
use swarm_sim::scenario::{
    DEFAULT_PLACEMENT, MAX_AGENTS, MAX_EXTENT, MAX_PERIODS, MAX_RUNS_PER_POINT, Placement, Scenario,
};
use swarm_sim::seeds;
use swarm_sim::sim::MAX_PERIOD_SECS;

use crate::cli::files::{self, Staged};
use crate::cli::out::{StdoutError, outln};

#[derive(Args, Debug, Clone)]
pub struct Common {
    /// A built-in scenario (sharp, gradient, cloud, cloud-caption) or the path of a scenario TOML file.
    #[arg(long, default_value = "sharp")]
    scenario: String,
    /// Base seed: every run's seed is derived from it and the run's coordinates.
    #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
    seed: u64,
    /// Override the cycle length t_p^max, seconds; a negotiation period of (gather + decide)
    /// cycles must stay within 1,000,000 s.
    #[arg(long, value_parser = crate::cli::values::whole::<u64>(1, MAX_PERIOD_SECS))]
    cycle: Option<u64>,
    /// Where the agents start: `lattice`, the nodes of a triangular lattice of spacing 0.75 R
    /// nearest the centre (61 agents: a hexagon filling a 6 R disk, 5.1 neighbours each on
    /// average, the paper's "about five"), or `random`, uniformly in the scenario's disk or
    /// rectangle, redrawn until connected (6.1 neighbours for 61 agents in a 6 R disk).
    /// Outputs of `random` are named SCENARIO-random-COMMAND [default: lattice].
    #[arg(long, value_name = "random|lattice", value_parser = parse_placement)]
    placement: Option<Placement>,
    /// The same as `--placement lattice` (the default since the lattice matched the paper).
    #[arg(long, conflicts_with = "placement")]
    lattice: bool,
    /// CSV output (default: OUT_DIR/SCENARIO-COMMAND.csv). Missing folders of every output
    /// are created; the files are moved in only when all are written.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// SVG plot output (default: OUT_DIR/SCENARIO-COMMAND.svg).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Directory for default outputs (and for `sweep --shard`, the part).
    #[arg(long, visible_alias = "out", default_value = "target/swarm")]
    out_dir: PathBuf,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Subcommand, Debug)]
pub enum SwarmCommand {
    /// One run: trajectory of the centre of mass and average diversity over time (Figs. 5, 8).
    #[command(allow_negative_numbers = true)]
    Run {
        #[command(flatten)]
        common: Common,
        /// Initial x of the centre of mass (default: the scenario's start).
        #[arg(long, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
        x: Option<f64>,
        /// Initial y of the centre of mass (default: the scenario's start).
        #[arg(long, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
        y: Option<f64>,
        /// Negotiation periods, 1 to 100,000 (default: the scenario's).
        #[arg(long, value_parser = crate::cli::values::whole::<u32>(1, u64::from(MAX_PERIODS)))]
        periods: Option<u32>,
        /// Also write the run as one self-contained HTML page that replays it (waves,
        /// messages, decisions, the swarm's path; docs/viewer.md).
        #[arg(long, value_name = "FILE")]
        html: Option<PathBuf>,
    },
    /// Success rate and mean success time against the initial position (Figs. 6, 9).
    #[command(allow_negative_numbers = true)]
    Sweep {
        #[command(flatten)]
        common: Common,
        /// First initial x (default: the scenario's sweep).
        #[arg(long, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
        from: Option<f64>,
        /// Last initial x.
        #[arg(long, value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
        to: Option<f64>,
        /// Spacing of initial positions.
        #[arg(long, value_parser = crate::cli::values::positive(2.0 * MAX_EXTENT, "a step in R"))]
        step: Option<f64>,
        /// Runs per initial position, 1 to 100,000, and at most 1,000,000 runs in all
        /// (default: the scenario's, 50).
        #[arg(long, value_parser = crate::cli::values::whole::<u32>(1, u64::from(MAX_RUNS_PER_POINT)))]
        runs: Option<u32>,
        /// Run only shard I of N (1 <= I <= N) of the sweep's runs and write them to
        /// OUT_DIR/part-I-of-N.jsonl, nothing else; `cimax merge` makes the CSV and SVG of
        /// all N parts.
        #[arg(long, value_name = "I/N", conflicts_with_all = ["csv", "plot"])]
        shard: Option<host_sim::shard::ShardSpec>,
    },
    /// The preferred direction of a swarm centred at each point of a grid (Figs. 7, 10, 11).
    #[command(allow_negative_numbers = true)]
    Field {
        #[command(flatten)]
        common: Common,
    },
    /// Runs everything above for the paper's scenarios and regenerates docs/reproduction.md.
    #[command(allow_negative_numbers = true)]
    Reproduce {
        /// Base seed.
        #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
        seed: u64,
        /// The docs directory (default: the docs/ of the checkout cimax was built from, and only
        /// when run inside that checkout; elsewhere give --docs); with --shard, the directory
        /// of the part.
        #[arg(long)]
        docs: Option<PathBuf>,
        /// No progress bars.
        #[arg(long)]
        quiet: bool,
        /// The placement of every experiment, random or lattice; the sweeps also run the
        /// other one [default: lattice, as on the committed page].
        #[arg(long, value_name = "random|lattice", value_parser = parse_placement)]
        placement: Option<Placement>,
        /// Run only shard I of N (1 <= I <= N) of the page's units of work (its stages, in a
        /// fixed order; unit k is shard k % N + 1's) and write their results to
        /// DOCS/part-I-of-N.jsonl, nothing else; `cimax merge PARTS --out DIR` then writes
        /// DIR/reproduction.md and DIR/figures/ as `swarm reproduce --docs DIR` does.
        #[arg(long, value_name = "I/N", requires = "docs")]
        shard: Option<host_sim::shard::ShardSpec>,
    },
    /// Agent-steps per second for swarms of several sizes (one negotiation period each).
    #[command(allow_negative_numbers = true)]
    Bench {
        /// Swarm sizes, 2 to 1,000,000 each (the disk grows to keep the density).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "61,1000,10000",
            value_parser = crate::cli::values::whole::<usize>(2, MAX_AGENTS as u64)
        )]
        agents: Vec<usize>,
        /// Seed.
        #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
        seed: u64,
        /// A built-in scenario or scenario file.
        #[arg(long, default_value = "sharp")]
        scenario: String,
    },
}

fn parse_placement(s: &str) -> Result<Placement, String> {
    s.parse()
        .map_err(|e: swarm_sim::scenario::PlacementError| e.to_string())
}

pub type Res = Result<(), Box<dyn std::error::Error + Send + Sync>>;

impl Common {
    /// `--placement`, or the lattice with `--lattice`.
    fn placement(&self) -> Placement {
        if self.lattice {
            Placement::Lattice
        } else {
            self.placement.unwrap_or(DEFAULT_PLACEMENT)
        }
    }

    fn scenario(&self) -> Result<Scenario, Box<dyn std::error::Error + Send + Sync>> {
        placed(
            Scenario::load(&self.scenario)?,
            self.placement(),
            self.cycle,
        )
    }

    fn outputs(&self, scn: &Scenario, what: &str) -> (PathBuf, PathBuf) {
        let name = |ext: &str| self.out_dir.join(format!("{}-{what}.{ext}", scn.name));
        (
            self.csv.clone().unwrap_or_else(|| name("csv")),
            self.plot.clone().unwrap_or_else(|| name("svg")),
        )
    }

    /// The CSV and SVG of command `what` ([`Common::outputs`]), checked before any work
    /// ([`files`]) with the command's `others` (`--html`).
    fn checked_outputs(
        &self,
        scn: &Scenario,
        what: &str,
        others: &[(&str, &Path)],
    ) -> Result<(PathBuf, PathBuf), String> {
        if self.csv.is_none() || self.plot.is_none() {
            files::check_dir("--out-dir", &self.out_dir)?;
        }
        let (csv, svg) = self.outputs(scn, what);
        let mut all = vec![("--csv", csv.as_path()), ("--plot", svg.as_path())];
        all.extend_from_slice(others);
        for (option, p) in &all {
            files::check_file(option, p)?;
        }
        files::check_distinct(&all)?;
        Ok((csv, svg))
    }
}

/// `s` with `placement` (its name marked unless the default) and `--cycle` `cycle`, checked.
fn placed(
    s: Scenario,
    placement: Placement,
    cycle: Option<u64>,
) -> Result<Scenario, Box<dyn std::error::Error + Send + Sync>> {
    let mut s = s
        .placed(placement)
        .map_err(|e| format!("--placement {placement}: {e}"))?;
    if placement != DEFAULT_PLACEMENT {
        s.name = format!("{}-{placement}", s.name);
    }
    s.description = format!("{} ({placement} placement)", s.description);
    if let Some(c) = cycle {
        s.run.params.wave.cycle = Duration::from_secs(c);
        s.run.check().map_err(|e| format!("--cycle {c}: {e}"))?;
        if let Some(g) = &s.grid {
            let mut grid = s.run;
            grid.params.gather_cycles = g.gather_cycles;
            grid.params.decide_cycles = g.decide_cycles;
            grid.check()
                .map_err(|e| format!("--cycle {c} with the scenario's [grid]: {e}"))?;
        }
    }
    Ok(s)
}

fn wrote(csv: &Path, svg: &Path) -> Result<(), StdoutError> {
    outln!("wrote {} and {}", csv.display(), svg.display())
}

fn swarm_run(
    c: &Common,
    x: Option<f64>,
    y: Option<f64>,
    periods: Option<u32>,
    html: Option<&Path>,
) -> Res {
    let scn = c.scenario()?;
    let others: Vec<(&str, &Path)> = html.iter().map(|p| ("--html", *p)).collect();
    let (csv, svg) = c.checked_outputs(&scn, "run", &others)?;
    let start = Point2::new(x.unwrap_or(scn.start.x), y.unwrap_or(scn.start.y));
    let periods = periods.unwrap_or(scn.periods);
    let t = Clock::now();
    let mut staged = Staged::new();
    let out = match html {
        None => experiment::run(&scn, scn.run, start, periods, c.seed, false)?,
        Some(path) => {
            // The same run (recording draws nothing), with its events.
            let (out, trace) = experiment::run_traced(&scn, scn.run, start, periods, c.seed)?;
            let replay = viewer::swarm::replay(&scn, &out, c.seed, &trace);
            staged.write(path, viewer::page(&replay)?)?;
            out
        }
    };
    staged.write_with(&csv, |p| write_run_csv(p, &out, &scn.run))?;
    staged.write_with(&svg, |p| figures::run_figure(p, &scn, &out))?;
    staged.commit()?;
    if let Some(path) = html {
        outln!("wrote {}", path.display())?;
    }
    let last = out.periods.last();
    outln!(
        "{}: {} agents (mean {:.1} neighbours), from ({:.2}, {:.2}), {} periods of {} s in {:.2} s",
        scn.description,
        out.swarm.len(),
        out.swarm.mean_degree(),
        start.x,
        start.y,
        out.periods.len(),
        scn.run.period_secs(),
        t.elapsed().as_secs_f64()
    )?;
    if let Some(p) = last {
        outln!(
            "final centre ({:.2}, {:.2}), mean diversity of the last period {:.2}",
            p.to.x,
            p.to.y,
            p.diversity
        )?;
    }
    match (&scn.success, out.success_at) {
        (Some(s), Some(k)) => outln!("success ({s}) after {k} periods")?,
        (Some(s), None) => outln!("no success ({s}) within {periods} periods")?,
        (None, _) => {}
    }
    wrote(&csv, &svg)?;
    Ok(())
}

fn swarm_field(c: &Common) -> Res {
    let scn = c.scenario()?;
    let grid = scn
        .grid
        .clone()
        .ok_or_else(|| format!("scenario {} has no [grid]", scn.name))?;
    let (csv, svg) = c.checked_outputs(&scn, "field", &[])?;
    let t = Clock::now();
    let progress = Progress::new((grid.xs.len() * grid.ys.len()) as u64, "field", c.quiet);
    let arrows = experiment::direction_map(&scn, &grid, c.seed, &progress)?;
    progress.finish();
    let mut staged = Staged::new();
    staged.write_with(&csv, |p| write_field_csv(p, &arrows))?;
    staged.write_with(&svg, |p| {
        figures::direction_figure(p, &scn, &grid, &arrows, &pages::marks::map_for(&scn))
    })?;
    staged.commit()?;
    outln!(
        "{}: {} grid points in {:.1} s",
        scn.description,
        arrows.len(),
        t.elapsed().as_secs_f64()
    )?;
    wrote(&csv, &svg)?;
    Ok(())
}

fn swarm_bench(agents: &[usize], seed: u64, scenario: &str) -> Res {
    let scn = Scenario::load(scenario)?;
    outln!(
        "one negotiation period ({} s simulated) of {} per size, one thread, density of {} agents in the scenario's shape",
        scn.run.period_secs(),
        scn.description,
        scn.agents
    )?;
    outln!(
        "{:>8} {:>10} {:>10} {:>10} {:>14} {:>16} {:>14}",
        "agents",
        "neighbours",
        "place s",
        "sim s",
        "agent calls",
        "agent-steps/s",
        "calls/s"
    )?;
    for &n in agents {
        let r = experiment::bench(&scn, n, seeds::derive(seed, &[n as u64]))?;
        outln!(
            "{:>8} {:>10.1} {:>10.3} {:>10.3} {:>14} {:>16.3e} {:>14.3e}",
            r.agents,
            r.mean_degree,
            r.place_s,
            r.wall_s,
            r.calls,
            r.agent_steps_per_s(),
            r.calls as f64 / r.wall_s
        )?;
    }
    outln!(
        "agent-steps/s: agents × simulated seconds per wall second (event-driven: idle seconds cost nothing); calls/s: handle_timeout + handle_message calls per second"
    )?;
    Ok(())
}

/// Runs one `cimax swarm` command.
///
/// # Errors
/// Whatever the command failed with (a scenario that does not load, a file not written).
pub fn run(command: SwarmCommand) -> Res {
    match command {
        SwarmCommand::Run {
            common,
            x,
            y,
            periods,
            html,
        } => swarm_run(&common, x, y, periods, html.as_deref()),
        SwarmCommand::Sweep {
            common,
            from,
            to,
            step,
            runs,
            shard,
        } => sweep::sweep(
            &common,
            &sweep::SweepOptions {
                from,
                to,
                step,
                runs,
                shard,
            },
        ),
        SwarmCommand::Field { common } => swarm_field(&common),
        SwarmCommand::Reproduce {
            seed,
            docs,
            quiet,
            placement,
            shard,
        } => reproduce::reproduce(&reproduce::ReproduceOptions {
            seed,
            docs,
            quiet,
            placement,
            shard,
        }),
        SwarmCommand::Bench {
            agents,
            seed,
            scenario,
        } => swarm_bench(&agents, seed, &scenario),
    }
}
