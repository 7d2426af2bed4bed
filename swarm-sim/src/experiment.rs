//! Experiments over [`Sim`]: one run, sweeps over initial positions, preferred-direction maps,
//! radial profiles. Runs are independent and each has its own seed
//! ([`crate::seeds::derive`]`(seed, [point, run])`), so they are spread over all cores with rayon
//! and the results do not depend on the number of threads.

use crate::stats;
use nalgebra::Point2;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::geometry::Swarm;
use crate::lean::LeanSim;
use crate::progress::Progress;
use crate::scenario::{GridSpec, Scenario, Success};
use crate::seeds::derive;
use crate::sim::{Period, RunConfig, Sim, SimError};
use crate::tap::Tap;

/// Any failure of an experiment (parameters that do not validate, a swarm that cannot be placed).
pub type Error = Box<dyn std::error::Error + Send + Sync>;

/// One run: the placement, every period, and when it first met the success criterion.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunOutput {
    /// The swarm's geometry.
    pub swarm: Swarm,
    /// The initial centre of mass.
    #[serde(with = "crate::json")]
    pub start: Point2<f64>,
    /// Every period run.
    pub periods: Vec<Period>,
    /// Periods after which the run first met the criterion (0: at the start).
    pub success_at: Option<u32>,
}

/// Places a swarm for run `seed`.
pub(crate) fn place(scn: &Scenario, agents: usize, seed: u64) -> Result<Swarm, Error> {
    let mut rng = Pcg64Mcg::seed_from_u64(derive(seed, &[3]));
    let shape = scn.shape.scaled_for(scn.agents, agents);
    Ok(Swarm::place(agents, shape, 1.0, &mut rng)?)
}

/// Runs `scn` from `start` for up to `periods` negotiation periods. With `stop_on_success`, the
/// run ends as soon as the scenario's criterion is met (at the start or after a move).
///
/// # Errors
/// If the parameters do not validate or no connected placement exists.
pub fn run(
    scn: &Scenario,
    cfg: RunConfig,
    start: Point2<f64>,
    periods: u32,
    seed: u64,
    stop_on_success: bool,
) -> Result<RunOutput, Error> {
    Ok(run_inner(
        scn,
        cfg,
        start,
        periods,
        seed,
        stop_on_success,
        Observe::default(),
    )?
    .0)
}

/// [`run`] (to the last period) with the observer's [`Tap`] of every period: the messages
/// scored in that period's gathering phase. The run itself is the same as [`run`]'s.
///
/// # Errors
/// As [`run`].
pub fn run_tapped(
    scn: &Scenario,
    cfg: RunConfig,
    start: Point2<f64>,
    periods: u32,
    seed: u64,
) -> Result<(RunOutput, Vec<Tap>), Error> {
    let observe = Observe {
        tap: true,
        ..Observe::default()
    };
    let (out, _, taps) = run_inner(scn, cfg, start, periods, seed, false, observe)?;
    Ok((out, taps))
}

/// [`run`] without the observer's diversity (every [`Period::diversity`] is 0; the run is
/// otherwise the same, draw for draw): for runs read only for where the swarm went.
///
/// # Errors
/// As [`run`].
pub fn run_moves(
    scn: &Scenario,
    cfg: RunConfig,
    start: Point2<f64>,
    periods: u32,
    seed: u64,
    stop_on_success: bool,
) -> Result<RunOutput, Error> {
    let observe = Observe {
        no_diversity: true,
        ..Observe::default()
    };
    Ok(run_inner(scn, cfg, start, periods, seed, stop_on_success, observe)?.0)
}

/// What a run records besides its periods.
#[derive(Clone, Copy, Debug, Default)]
struct Observe {
    /// The events, for the replay viewer ([`Sim::record`]).
    trace: bool,
    /// Each period's [`Tap`].
    tap: bool,
    /// No observer's diversity ([`Sim::without_diversity`]): every period's is 0.
    no_diversity: bool,
    /// Stops as soon as the criterion is out of reach (the swarm cannot get there in the
    /// periods left, a step each): the periods are then cut short, [`RunOutput::success_at`]
    /// is the same.
    give_up: bool,
}

/// Slack on how far a swarm can move, for the rounding of its moves (each a `step` long up to
/// a few ulps): far more than rounding, far less than any criterion's scale.
const REACH_SLACK: f64 = 1e-6;

/// [`run`] (to the last period) with its events recorded for the replay viewer
/// ([`Sim::record`]).
///
/// # Errors
/// As [`run`].
pub fn run_traced(
    scn: &Scenario,
    cfg: RunConfig,
    start: Point2<f64>,
    periods: u32,
    seed: u64,
) -> Result<(RunOutput, Vec<hal_emu::TraceEvent>), Error> {
    let observe = Observe {
        trace: true,
        ..Observe::default()
    };
    let (out, events, _) = run_inner(scn, cfg, start, periods, seed, false, observe)?;
    Ok((out, events))
}

/// A run's output, its events (if `observe.trace`) and its taps, one per period (if
/// `observe.tap`).
type Observed = (RunOutput, Vec<hal_emu::TraceEvent>, Vec<Tap>);

/// [`run`], recording what `observe` asks for.
fn run_inner(
    scn: &Scenario,
    cfg: RunConfig,
    start: Point2<f64>,
    periods: u32,
    seed: u64,
    stop_on_success: bool,
    observe: Observe,
) -> Result<Observed, Error> {
    let swarm = place(scn, scn.agents, seed)?;
    let mut out = RunOutput {
        swarm,
        start,
        periods: Vec::new(),
        success_at: None,
    };
    let met = |c: Point2<f64>| scn.success.as_ref().is_some_and(|s: &Success| s.met(c));
    if met(start) {
        out.success_at = Some(0);
        if stop_on_success {
            return Ok((out, Vec::new(), Vec::new()));
        }
    }
    let mut periods_out = Vec::with_capacity(periods as usize);
    let mut taps = Vec::new();
    let events;
    {
        // A plain run (nothing recorded or tapped) on the lean engine if it covers it: the
        // same run bit for bit ([`crate::lean`]).
        let lean = match (&scn.field2, observe.trace || observe.tap) {
            (None, false) => LeanSim::new(&out.swarm, &scn.field, cfg, start, seed)?,
            _ => None,
        };
        let mut sim = match lean {
            Some(l) => Engine::Lean(Box::new(l)),
            None => Engine::Agents(Box::new(AnySim::new(&out.swarm, scn, cfg, start, seed)?)),
        };
        if let Some(s) = sim.agents() {
            if observe.trace {
                s.record();
            }
            if observe.tap {
                s.tap();
            }
        }
        if observe.no_diversity {
            sim.without_diversity();
        }
        for _ in 0..periods {
            let p = sim.run_period()?;
            periods_out.push(p);
            if let (true, Some(s)) = (observe.tap, sim.agents()) {
                taps.push(s.take_tap());
            }
            if out.success_at.is_none() && met(p.to) {
                out.success_at = Some(p.index);
                if stop_on_success {
                    break;
                }
            }
            if observe.give_up && out.success_at.is_none() {
                let left = f64::from(periods - p.index.min(periods));
                let reach = cfg.step.abs() * left + REACH_SLACK;
                if scn
                    .success
                    .as_ref()
                    .is_some_and(|s| !s.reachable(p.to, reach))
                {
                    break;
                }
            }
        }
        events = sim.agents().map(AnySim::take_trace).unwrap_or_default();
    }
    out.periods = periods_out;
    Ok((out, events, taps))
}

/// The engine of a run: the agents', or the lean one for a plain run.
enum Engine<'a> {
    /// Both boxed (one allocation per run): they differ in size.
    Agents(Box<AnySim<'a>>),
    Lean(Box<LeanSim<'a>>),
}

impl<'a> Engine<'a> {
    fn run_period(&mut self) -> Result<Period, SimError> {
        match self {
            Engine::Agents(s) => s.run_period(),
            Engine::Lean(s) => s.run_period(),
        }
    }

    fn without_diversity(&mut self) {
        match self {
            Engine::Agents(s) => s.without_diversity(),
            Engine::Lean(s) => s.without_diversity(),
        }
    }

    /// The agents' engine, which records and taps (the lean one is never asked to).
    fn agents(&mut self) -> Option<&mut AnySim<'a>> {
        match self {
            Engine::Agents(s) => Some(&mut **s),
            Engine::Lean(_) => None,
        }
    }
}

/// The simulation of a scenario: one quantity (the paper), or two when it has a `[[field2]]`.
enum AnySim<'a> {
    One(Sim<'a, f32>),
    Two(Sim<'a, [f32; 2]>),
}

impl<'a> AnySim<'a> {
    fn new(
        swarm: &'a Swarm,
        scn: &'a Scenario,
        cfg: RunConfig,
        start: Point2<f64>,
        seed: u64,
    ) -> Result<Self, SimError> {
        Ok(match &scn.field2 {
            None => AnySim::One(Sim::new(swarm, &scn.field, cfg, start, seed)?),
            Some(f2) => AnySim::Two(Sim::with_fields(
                swarm,
                vec![&scn.field, f2],
                cfg,
                start,
                seed,
            )?),
        })
    }

    fn run_period(&mut self) -> Result<Period, SimError> {
        match self {
            AnySim::One(s) => s.run_period(),
            AnySim::Two(s) => s.run_period(),
        }
    }

    fn record(&mut self) {
        match self {
            AnySim::One(s) => s.record(),
            AnySim::Two(s) => s.record(),
        }
    }

    fn without_diversity(&mut self) {
        match self {
            AnySim::One(s) => s.without_diversity(),
            AnySim::Two(s) => s.without_diversity(),
        }
    }

    fn tap(&mut self) {
        match self {
            AnySim::One(s) => s.tap(),
            AnySim::Two(s) => s.tap(),
        }
    }

    fn take_tap(&mut self) -> Tap {
        match self {
            AnySim::One(s) => s.take_tap(),
            AnySim::Two(s) => s.take_tap(),
        }
    }

    fn take_trace(&mut self) -> Vec<hal_emu::TraceEvent> {
        match self {
            AnySim::One(s) => s.take_trace(),
            AnySim::Two(s) => s.take_trace(),
        }
    }

    fn run_until(&mut self, t: u64) -> u64 {
        match self {
            AnySim::One(s) => s.run_until(t),
            AnySim::Two(s) => s.run_until(t),
        }
    }

    fn calls(&self) -> u64 {
        match self {
            AnySim::One(s) => s.calls(),
            AnySim::Two(s) => s.calls(),
        }
    }

    /// Agents that initiated at least one wave so far.
    fn initiating(&self) -> u64 {
        match self {
            AnySim::One(s) => s
                .agents()
                .iter()
                .filter(|a| a.wave_stats().initiated > 0)
                .count() as u64,
            AnySim::Two(s) => s
                .agents()
                .iter()
                .filter(|a| a.wave_stats().initiated > 0)
                .count() as u64,
        }
    }

    /// Messages the agents accepted (scored or diffused), summed.
    fn accepted(&self) -> u64 {
        match self {
            AnySim::One(s) => s
                .agents()
                .iter()
                .map(|a| u64::from(a.stats().accepted))
                .sum(),
            AnySim::Two(s) => s
                .agents()
                .iter()
                .map(|a| u64::from(a.stats().accepted))
                .sum(),
        }
    }
}

/// Success statistics at one initial position.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Initial x of the centre of mass (y = 0).
    #[serde(with = "crate::json")]
    pub x_init: f64,
    /// Runs made.
    pub runs: u32,
    /// Runs that met the criterion.
    pub successes: u32,
    /// Mean number of negotiation periods (moves) until success, over successful runs.
    #[serde(with = "crate::json")]
    pub mean_success_periods: Option<f64>,
}

impl SweepPoint {
    /// Fraction of successful runs.
    pub fn success_rate(&self) -> f64 {
        f64::from(self.successes) / f64::from(self.runs.max(1))
    }
}

/// `runs` runs from each `(x, 0)` in `xs`, each stopped at success or after the scenario's
/// periods. Run `r` at point `p` uses seed `derive(seed, [p, r])`: unit `p * runs + r` of
/// [`sweep_run`], put together by [`sweep_points`].
///
/// # Errors
/// The first run's error, if any run fails.
pub fn sweep(
    scn: &Scenario,
    cfg: RunConfig,
    xs: &[f64],
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<SweepPoint>, Error> {
    let n = (xs.len() * runs as usize) as u64;
    let outcomes: Vec<Option<u32>> = (0..n)
        .into_par_iter()
        .map(|k| {
            let out = sweep_run(scn, cfg, xs, runs, seed, k);
            progress.inc();
            out
        })
        .collect::<Result<_, _>>()?;
    Ok(sweep_points(xs, runs, &outcomes))
}

/// Unit `k` of [`sweep`]: run `k % runs` from `(xs[k / runs], 0)`, with seed
/// `derive(seed, [k / runs, k % runs])`; the periods until success, if it succeeded.
///
/// # Errors
/// The run's error, or that `k` is beyond the sweep.
pub fn sweep_run(
    scn: &Scenario,
    cfg: RunConfig,
    xs: &[f64],
    runs: u32,
    seed: u64,
    k: u64,
) -> Result<Option<u32>, Error> {
    let runs = u64::from(runs.max(1));
    let (p, r) = (k / runs, k % runs);
    let x = usize::try_from(p)
        .ok()
        .and_then(|p| xs.get(p))
        .ok_or_else(|| format!("sweep unit {k} is beyond the sweep"))?;
    let s = derive(seed, &[p, r]);
    // Only the success counts: the observer's diversity is not accumulated, and a run
    // whose success is out of reach stops.
    let observe = Observe {
        no_diversity: true,
        give_up: true,
        ..Observe::default()
    };
    let start = Point2::new(*x, 0.0);
    run_inner(scn, cfg, start, scn.periods, s, true, observe).map(|o| o.0.success_at)
}

/// The points of a sweep from its units' outcomes ([`sweep_run`], in unit order).
pub fn sweep_points(xs: &[f64], runs: u32, outcomes: &[Option<u32>]) -> Vec<SweepPoint> {
    xs.iter()
        .enumerate()
        .map(|(p, &x)| {
            let mine = outcomes
                .get(p * runs as usize..(p + 1) * runs as usize)
                .unwrap_or_default();
            let ok: Vec<f64> = mine.iter().flatten().map(|&t| f64::from(t)).collect();
            SweepPoint {
                x_init: x,
                runs,
                successes: ok.len() as u32,
                mean_success_periods: stats::mean(&ok),
            }
        })
        .collect()
}

/// The swarm's preferred direction with its centre at one point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Arrow {
    /// The swarm's centre.
    #[serde(with = "crate::json")]
    pub at: Point2<f64>,
    /// Circular mean of the decided bearings (radians), if any agent decided.
    #[serde(with = "crate::json")]
    pub direction: Option<f64>,
    /// Length of the mean resultant (0..1).
    #[serde(with = "crate::json")]
    pub consensus: f64,
    /// Agents with a decision.
    pub decided: u32,
}

/// One run of one negotiation period (of the grid's length) at each grid point, row by row
/// (`y` outer, `x` inner). Point `k` uses seed `derive(seed, [k])`.
///
/// # Errors
/// The first run's error, if any run fails.
pub fn direction_map(
    scn: &Scenario,
    grid: &GridSpec,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<Arrow>, Error> {
    let mut cfg = scn.run;
    cfg.params.gather_cycles = grid.gather_cycles;
    cfg.params.decide_cycles = grid.decide_cycles;
    let points: Vec<Point2<f64>> = grid
        .ys
        .iter()
        .flat_map(|&y| grid.xs.iter().map(move |&x| Point2::new(x, y)))
        .collect();
    points
        .par_iter()
        .enumerate()
        .map(|(k, &at)| {
            let out = run_moves(scn, cfg, at, 1, derive(seed, &[k as u64]), false)?;
            progress.inc();
            let p = out.periods[0];
            Ok(Arrow {
                at,
                direction: p.direction,
                consensus: p.consensus,
                decided: p.decided,
            })
        })
        .collect()
}

/// How strongly a swarm at distance `d` from a centre heads toward it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RadialPoint {
    /// Distance of the swarm's centre from the profile's centre.
    #[serde(with = "crate::json")]
    pub distance: f64,
    /// Runs made.
    pub runs: u32,
    /// Mean of cos(angle between the decided direction and the direction to the centre); 0 for
    /// a run without a direction. +1: straight in, −1: straight out, about 0: no preference.
    #[serde(with = "crate::json")]
    pub inward: f64,
    /// Standard error of `inward`.
    #[serde(with = "crate::json")]
    pub inward_se: f64,
}

/// `runs` one-period runs at each distance in `distances` from `centre`, at random angles.
/// Run `r` at distance index `p` uses seed `derive(seed, [p, r])`.
///
/// # Errors
/// The first run's error, if any run fails.
pub fn radial_profile(
    scn: &Scenario,
    cfg: RunConfig,
    centre: Point2<f64>,
    distances: &[f64],
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<RadialPoint>, Error> {
    let n = distances.len() * runs as usize;
    let cosines: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|k| {
            let (p, r) = (k / runs as usize, k % runs as usize);
            let s = derive(seed, &[p as u64, r as u64]);
            let phi =
                std::f64::consts::TAU * Pcg64Mcg::seed_from_u64(derive(s, &[4])).random::<f64>();
            let d = distances[p];
            let at = centre + nalgebra::Vector2::new(d * phi.cos(), d * phi.sin());
            let out = run_moves(scn, cfg, at, 1, s, false)?;
            progress.inc();
            // Direction to the centre is phi + π.
            Ok(out.periods[0]
                .direction
                .map_or(0.0, |dir| (dir - phi - std::f64::consts::PI).cos()))
        })
        .collect::<Result<_, Error>>()?;
    Ok(distances
        .iter()
        .enumerate()
        .map(|(p, &d)| {
            let c = &cosines[p * runs as usize..(p + 1) * runs as usize];
            RadialPoint {
                distance: d,
                runs,
                inward: stats::mean(c).unwrap_or(f64::NAN),
                inward_se: stats::standard_error(c).unwrap_or(f64::NAN),
            }
        })
        .collect())
}

/// Mean number of waves an agent takes part in during one gathering cycle (the messages that
/// activated it), over `runs` runs at the scenario's start: with `N` agents each initiating once,
/// `N` means that every wave flooded the whole swarm; fewer, that waves collided.
///
/// # Errors
/// The first run's error, if any run fails.
pub fn waves_heard(scn: &Scenario, cfg: RunConfig, runs: u32, seed: u64) -> Result<f64, Error> {
    Ok(cycle_load(scn, cfg, runs, seed)?.heard)
}

/// What one cycle asks of an agent ([`cycle_load`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CycleLoad {
    /// Waves heard (messages accepted) per agent in the cycle, the mean over runs.
    #[serde(with = "crate::json")]
    pub heard: f64,
    /// Agents that initiated a wave in the cycle, over all runs.
    pub initiating: u64,
    /// Agents over all runs (agent-cycles).
    pub agents: u64,
}

/// The first cycle of `runs` runs from the scenario's start (seeds derived from `seed`): the
/// waves an agent hears, and how many agents initiate (the rest had their initiation fall while
/// they were busy, [`protocol::wave::WaveStats::skipped_initiations`]).
///
/// # Errors
/// If a run cannot be set up.
pub fn cycle_load(
    scn: &Scenario,
    cfg: RunConfig,
    runs: u32,
    seed: u64,
) -> Result<CycleLoad, Error> {
    let per_run: Vec<(f64, u64, u64)> = (0..runs)
        .into_par_iter()
        .map(|r| {
            let s = derive(seed, &[u64::from(r)]);
            let swarm = place(scn, scn.agents, s)?;
            let mut sim = AnySim::new(&swarm, scn, cfg, scn.start, s)?;
            // Only the counters are read.
            sim.without_diversity();
            let cycle = cfg.params.wave.cycle.as_millis() / 1000;
            sim.run_until(cycle);
            let n = swarm.len() as u64;
            Ok((sim.accepted() as f64 / n.max(1) as f64, sim.initiating(), n))
        })
        .collect::<Result<_, Error>>()?;
    let heard: Vec<f64> = per_run.iter().map(|r| r.0).collect();
    Ok(CycleLoad {
        heard: stats::mean(&heard).unwrap_or(0.0),
        initiating: per_run.iter().map(|r| r.1).sum(),
        agents: per_run.iter().map(|r| r.2).sum(),
    })
}

/// Agent-steps per second at one swarm size.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BenchResult {
    /// Agents.
    pub agents: usize,
    /// Mean neighbours per agent.
    #[serde(with = "crate::json")]
    pub mean_degree: f64,
    /// Wall time to place the swarm and build its neighbour lists, seconds.
    #[serde(with = "crate::json")]
    pub place_s: f64,
    /// Simulated seconds.
    pub sim_secs: u64,
    /// Wall time of the simulation, seconds.
    #[serde(with = "crate::json")]
    pub wall_s: f64,
    /// Calls into the agents (`handle_timeout` + `handle_message`).
    pub calls: u64,
}

impl BenchResult {
    /// Agents × simulated seconds per wall-clock second.
    pub fn agent_steps_per_s(&self) -> f64 {
        self.agents as f64 * self.sim_secs as f64 / self.wall_s
    }
}

/// Places `agents` agents (the scenario's shape scaled to keep its density) and runs one
/// negotiation period of the scenario at its start, on one thread.
///
/// # Errors
/// If the parameters do not validate or no connected placement exists.
pub fn bench(scn: &Scenario, agents: usize, seed: u64) -> Result<BenchResult, Error> {
    let t0 = std::time::Instant::now();
    let swarm = place(scn, agents, seed)?;
    let place_s = t0.elapsed().as_secs_f64();
    let t1 = std::time::Instant::now();
    let mut sim = AnySim::new(&swarm, scn, scn.run, scn.start, seed)?;
    sim.run_period()?;
    Ok(BenchResult {
        agents,
        mean_degree: swarm.mean_degree(),
        place_s,
        sim_secs: scn.run.period_secs(),
        wall_s: t1.elapsed().as_secs_f64(),
        calls: sim.calls(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn success_out_of_reach_is_told_conservatively() {
        let near = Success::NearX {
            x: 0.0,
            within: 0.33,
        };
        let at = |x| Point2::new(x, 1.0);
        assert!(near.reachable(at(-1.0), 0.68));
        assert!(!near.reachable(at(-1.0), 0.66));
        assert!(!near.reachable(at(1.0), 0.66));
        assert!(near.reachable(at(f64::NAN), 0.0));
        let beyond = Success::BeyondX { x: 2.33 };
        assert!(beyond.reachable(at(3.0), 0.0));
        assert!(beyond.reachable(at(2.0), 0.34));
        assert!(!beyond.reachable(at(2.0), 0.32));
    }

    #[test]
    fn a_sweep_run_that_gives_up_has_the_success_of_the_whole_run() {
        // Twelve periods of 0.33 R: from |x| = 5 the line is out of reach from the first move
        // on, from |x| = 3.5 only after a few moves away from it, from 2.5 rarely.
        let mut scn = Scenario::builtin("sharp").unwrap();
        scn.periods = 12;
        let xs = [-5.0, -3.5, -2.5, 3.5, 5.0];
        let runs = 2;
        for k in 0..(xs.len() * runs) as u64 {
            let gave_up = sweep_run(&scn, scn.run, &xs, runs as u32, 7, k).unwrap();
            let (p, r) = (k / runs as u64, k % runs as u64);
            let s = derive(7, &[p, r]);
            let start = Point2::new(xs[p as usize], 0.0);
            let whole = run(&scn, scn.run, start, scn.periods, s, true).unwrap();
            assert_eq!(gave_up, whole.success_at, "unit {k}");
        }
    }
}
