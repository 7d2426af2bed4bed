//! `cimax swarm sweep`: success rate and mean success time against the initial position
//! (Figs. 6, 9), and its shards.
//!
//! The job ([`SwarmSweepJob`]) has one unit per run: unit `p * runs + r` is run `r` from
//! `xs[p]` ([`experiment::sweep_run`]). The unsharded sweep computes them all and writes with
//! [`SwarmSweepJob::write`]; `--shard I/N` computes its share into a part; `cimax merge` hands
//! the parts' results to the same [`SwarmSweepJob::write`].

use crate::cli::out::{Exit, outln};
use std::path::Path;
use std::process::ExitCode;

use host_sim::shard::{self, Job, ShardSpec, Timing, merge::Merged};
use pages::csv::write_sweep_csv;
use pages::figures;
use serde::{Deserialize, Serialize};
use swarm_sim::experiment;
use swarm_sim::progress::Progress;
use swarm_sim::scenario::{Placement, PlacementError, Scenario, check_runs};

use super::{Common, Res, placed, wrote};
use crate::cli::job::ScenarioSource;

/// The job's command in a part's header.
pub const COMMAND: &str = "swarm sweep";

/// Everything that makes a sweep's results, resolved: the job in a part's header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SwarmSweepJob {
    scenario: ScenarioSource,
    /// `random` or `lattice`.
    placement: String,
    /// `--cycle`, s.
    cycle: Option<u64>,
    /// The initial positions.
    xs: Vec<f64>,
    /// Runs per position.
    runs: u32,
    seed: u64,
}

/// A unit's result: the periods until success, if the run succeeded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct Unit {
    success_at: Option<u32>,
}

/// The options of the sweep beside the common ones.
pub struct SweepOptions {
    /// First initial x.
    pub from: Option<f64>,
    /// Last initial x.
    pub to: Option<f64>,
    /// Spacing of initial positions.
    pub step: Option<f64>,
    /// Runs per initial position.
    pub runs: Option<u32>,
    /// Only this shard.
    pub shard: Option<ShardSpec>,
}

/// `cimax swarm sweep`, whole or one shard.
pub fn sweep(c: &Common, o: &SweepOptions) -> Res {
    let (job, scn) = SwarmSweepJob::of(c, o)?;
    let outputs = match o.shard {
        Some(_) => {
            crate::cli::files::check_dir("--out-dir", &c.out_dir)?;
            None
        }
        None => Some(c.checked_outputs(&scn, "sweep", &[])?),
    };
    let total = job.xs.len() as u64 * u64::from(job.runs);
    let unit = |k| {
        experiment::sweep_run(&scn, scn.run, &job.xs, job.runs, job.seed, k)
            .map(|success_at| Unit { success_at })
    };
    if let Some(shard) = o.shard {
        let config = Job::new(COMMAND, &job)?;
        let path = shard::run_shard(config, total, shard, &c.out_dir, c.quiet, unit)
            .map_err(|e| e.to_string())?;
        outln!("wrote {}", path.display())?;
        return Ok(());
    }
    let wall = std::time::Instant::now();
    let all: Vec<u64> = (0..total).collect();
    let units = shard::compute(&all, &Progress::new(total, "sweep", c.quiet), unit)?;
    let timing = Timing {
        wall_s: wall.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    };
    let (csv, svg) = outputs.ok_or("no outputs")?;
    job.write(&scn, &units, (&csv, &svg), timing)
}

/// `cimax merge` of a swarm sweep's parts: its CSV and SVG into `out`, as the unsharded sweep
/// with `--out-dir OUT` writes them; the wall time printed is the shards' added up.
///
/// # Errors
/// If the parts are not a sweep this cimax can write, or the outputs cannot be written.
pub fn merge(m: &Merged, out: &Path) -> Exit {
    let (job, units): (SwarmSweepJob, Vec<Unit>) = m.decode().map_err(|e| e.to_string())?;
    let scn = job.scenario().map_err(|e| m.bad_config(e).to_string())?;
    let total = job.xs.len() as u64 * u64::from(job.runs);
    if units.len() as u64 != total {
        let e = format!("{} units, but the sweep has {total}", units.len());
        return Err(m.bad_config(e).to_string().into());
    }
    let name = |ext: &str| out.join(format!("{}-sweep.{ext}", scn.name));
    let timing = Timing {
        wall_s: m.wall_s,
        threads: m.threads,
    };
    job.write(&scn, &units, (&name("csv"), &name("svg")), timing)?;
    Ok(ExitCode::SUCCESS)
}

impl SwarmSweepJob {
    /// The job the options ask for, checked, and its scenario.
    fn of(c: &Common, o: &SweepOptions) -> Result<(SwarmSweepJob, Scenario), String> {
        let mut job = SwarmSweepJob {
            scenario: ScenarioSource::of(&c.scenario)?,
            placement: c.placement().name().into(),
            cycle: c.cycle,
            xs: Vec::new(),
            runs: 0,
            seed: c.seed,
        };
        let scn = job.scenario()?;
        let (xs, runs) = positions(&scn, o)?;
        job.xs = xs;
        job.runs = runs;
        Ok((job, scn))
    }

    /// The scenario, placed and with its cycle, checked for a success criterion.
    fn scenario(&self) -> Result<Scenario, String> {
        let placement: Placement = self
            .placement
            .parse()
            .map_err(|e: PlacementError| e.to_string())?;
        let scn =
            placed(self.scenario.load()?, placement, self.cycle).map_err(|e| e.to_string())?;
        if scn.success.is_none() {
            return Err(format!(
                "scenario {} has no [success] criterion to sweep",
                scn.name
            ));
        }
        check_runs(&[
            (self.xs.len() as u64, "positions"),
            (u64::from(self.runs), "runs"),
        ])
        .map_err(|e| format!("--runs {}: {e}", self.runs))?;
        Ok(scn)
    }

    /// Writes the sweep's CSV and SVG (`files`) and prints its table, from every unit's result
    /// in unit order: what the unsharded sweep and the merge of its parts both do.
    fn write(&self, scn: &Scenario, units: &[Unit], files: (&Path, &Path), t: Timing) -> Res {
        let (csv, svg) = files;
        let outcomes: Vec<Option<u32>> = units.iter().map(|u| u.success_at).collect();
        let pts = experiment::sweep_points(&self.xs, self.runs, &outcomes);
        let n = self.runs;
        let mut staged = crate::cli::files::Staged::new();
        staged.write_with(csv, |p| write_sweep_csv(p, &pts))?;
        let crit = scn.success.map(|s| s.to_string()).unwrap_or_default();
        // A built-in scenario's sweep carries the paper's marks, as on docs/reproduction.md.
        staged.write_with(svg, |p| {
            figures::sweep_figure(
                p,
                &format!("{}: success ({crit}), {n} runs per point", scn.description),
                &[("this simulator", &pts)],
                &pages::marks::sweep_for(&scn.name),
            )
        })?;
        staged.commit()?;
        outln!(
            "{}: success {crit} within {} periods, {n} runs per point, {:.1} s",
            scn.description,
            scn.periods,
            t.wall_s
        )?;
        outln!(
            "{:>8} {:>6} {:>8} {:>12}",
            "x_init",
            "runs",
            "success",
            "mean periods"
        )?;
        for p in &pts {
            outln!(
                "{:>8.2} {:>6} {:>8.2} {:>12}",
                p.x_init,
                p.runs,
                p.success_rate(),
                p.mean_success_periods
                    .map_or("-".into(), |t| format!("{t:.1}"))
            )?;
        }
        wrote(csv, svg)?;
        Ok(())
    }
}

/// The initial positions and runs per position: the scenario's sweep, or the options'.
fn positions(scn: &Scenario, o: &SweepOptions) -> Result<(Vec<f64>, u32), String> {
    let (mut xs, mut n) = scn
        .sweep
        .as_ref()
        .map_or((vec![-5.0, -4.0, -3.0, -2.0, -1.0, 0.0], 50), |s| {
            (s.xs.clone(), s.runs)
        });
    if o.from.is_some() || o.to.is_some() || o.step.is_some() {
        let a = o.from.unwrap_or(xs.first().copied().unwrap_or(-5.0));
        let b = o.to.unwrap_or(xs.last().copied().unwrap_or(5.0));
        let s = o.step.unwrap_or(0.5);
        if !(s > 0.0 && b >= a && (b - a) / s <= 10_000.0) {
            return Err("--from/--to/--step do not make a range".into());
        }
        xs = (0..=((b - a) / s + 1e-9) as u64)
            .map(|k| a + k as f64 * s)
            .collect();
    }
    if let Some(r) = o.runs {
        n = r;
    }
    check_runs(&[(xs.len() as u64, "positions"), (u64::from(n), "runs")])
        .map_err(|e| format!("--runs {n}: {e}"))?;
    Ok((xs, n))
}
