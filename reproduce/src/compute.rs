//! The compute phase of `swarm reproduce`: one [`Unit`] at a time, from the options alone
//! (its seeds derive from the base seed and the unit, never from another unit's result), with
//! its log lines and progress bar. Nothing here writes a file.

use std::time::Instant as Clock;

use nalgebra::Point2;
use protocol::Duration;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;

use crate::Error;
use crate::on_side;
use crate::results::{CycleRun, Outcome, PlacementStats, RunFigure, UnitResult};
use crate::stage::{Scenes, Stage};
use crate::stages::{
    CLOUD_PROFILE, CYCLE_SWEEPS, CYCLE_WAVES, MAPS, MAPS_OTHER, PEER, PLACEMENT_STATS,
    PROFILES_OTHER, RUN_FIGURES, SHAPES, SPEED, SWEEPS_LATTICE, SWEEPS_RANDOM, WAVE,
};
use crate::units::{Field, Scene, Side, Unit, placement};
use crate::{
    CLOUD_REFINED, CYCLE_RUNS, CYCLE_XS, CYCLES, OTHER_RUNS, Options, PLACEMENTS, PROFILE_RUNS,
    RUN_TRIES, beyond, builtin_placed, by_distance, caption_cloud, refined, sensitivity, settle,
};
use swarm_sim::experiment::{
    self, Arrow, BenchResult, RadialPoint, SweepPoint, cycle_load, direction_map, radial_profile,
    sweep,
};
use swarm_sim::geometry::Swarm;
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::seeds::derive;

/// Swarm sizes of the speed figures.
const BENCH_AGENTS: [usize; 3] = [61, 1000, 10_000];

/// Computes one unit of `swarm reproduce` with `opts` (its seed and placement; `docs` is not
/// read). `log` receives the unit's log lines.
///
/// # Errors
/// If a run fails, or the unit's index is out of its list.
pub fn compute(unit: Unit, opts: &Options, log: &mut dyn FnMut(&str)) -> Result<UnitResult, Error> {
    let t0 = Clock::now();
    let mut st = Stage::new(log, opts.quiet, opts.seed);
    let scns = Scenes::new(opts.placement)?;
    let outcome = outcome(unit, &mut st, opts.placement, &scns)?;
    Ok(UnitResult::new(
        unit,
        t0.elapsed().as_secs_f64(),
        rayon::current_num_threads(),
        outcome,
    ))
}

/// What `unit` measures.
fn outcome(unit: Unit, st: &mut Stage<'_>, main: Placement, s: &Scenes) -> Result<Outcome, Error> {
    use Outcome as O;
    Ok(match unit {
        Unit::Run(f) => O::Run(run_figure(st, f, s.field(f))?),
        Unit::Sweep(f, side) => O::Sweep(sweep_of(st, main, f, side, s.field(f))?),
        Unit::Map(m, side) => O::Map(map_of(st, main, m, side, s.scene(m))?),
        Unit::CloudProfile(side) => O::Profile(cloud_profile(st, main, side, &s.cloud)?),
        Unit::CaptionMap => O::Map(caption_cloud::map(st, main)?),
        Unit::CaptionProfile(side) => O::Profile(caption_cloud::profile(st, main, side)?),
        Unit::Course(f, side) => {
            let (c, d) = settle::course(st, main, f, side, s.field(f))?;
            O::Course(c, Box::new(d))
        }
        Unit::Sensor(f) => O::Sensor(settle::sensor(st, f, s.field(f))?),
        Unit::Plateau(side, k) => O::Plateau(settle::plateau(st, main, side, k, &s.sharp)?),
        Unit::Heading(f) => O::Heading(settle::heading(st, f, s.field(f))?),
        Unit::Start(f, side) => O::Start(settle::start(st, main, f, side, s.field(f))?),
        Unit::Steep(k, side) => O::Steep(settle::steep(st, k, main, side, s.fields())?),
        Unit::Refractory => O::Refractory(settle::refractory(st)?),
        Unit::Cycle => O::Cycle(cycle_effect(st, &s.sharp)?),
        Unit::Knob(k) => O::Knob(sensitivity::knob(st, main, k, &s.sharp, &s.gradient)?),
        Unit::Slope => O::Slope(sensitivity::slope(st, &s.gradient)?),
        Unit::Extent(side) => O::Extent(sensitivity::extent(st, main, side, s.fields())?),
        Unit::Shapes => O::Shapes(Box::new(shapes(st, &s.sharp)?)),
        Unit::BeyondSuccess => O::BeyondSuccess(beyond::success(st, s.fields())?),
        Unit::BeyondAlong => O::BeyondAlong(beyond::along(st, &s.gradient)?),
        Unit::BeyondTwo => O::BeyondTwo(beyond::two(st, &s.sharp)?),
        Unit::Waves => O::Waves(wave(st)?),
        Unit::Speed => O::Speed(speed(st, &s.sharp)?),
        Unit::PeerWork => O::PeerWork(peer_work(st, &s.sharp)?),
        Unit::Placements => O::Placements(placement_stats(st)?),
        Unit::Indecision(side) => O::Indecision(crate::indecision::runs(st, main, side)?),
    })
}

/// Figs. 5 and 8: the first of up to [`RUN_TRIES`] runs that succeeds.
fn run_figure(st: &mut Stage<'_>, f: Field, scn: &Scenario) -> Result<RunFigure, Error> {
    let p = st.start(&format!("{} run", scn.name), RUN_TRIES);
    let mut chosen = None;
    for tries in 0..RUN_TRIES {
        let s = derive(st.seed(RUN_FIGURES.at(f.index())), &[tries]);
        let out = experiment::run(scn, scn.run, scn.start, scn.periods, s, false)?;
        let ok = out.success_at.is_some();
        if chosen.is_none() || ok {
            chosen = Some(RunFigure { tries, out });
        }
        if ok {
            break;
        }
    }
    st.done(&p);
    chosen.ok_or(Error::NoRun)
}

/// Figs. 6 and 9: the sweep of field `f` with placement `side`. `scn` is placed by `main`.
/// Each placement keeps the seeds it had as the main or the second one (random 10, 11;
/// lattice 12, 13); the other placement runs at most [`OTHER_RUNS`] per point.
fn sweep_of(
    st: &mut Stage<'_>,
    main: Placement,
    f: Field,
    side: Side,
    scn: &Scenario,
) -> Result<Vec<SweepPoint>, Error> {
    let spec = scn.sweep.as_ref().ok_or(Error::ScenarioWithout("sweep"))?;
    let placement = placement(main, side);
    let block = match placement {
        Placement::Random => SWEEPS_RANDOM,
        Placement::Lattice => SWEEPS_LATTICE,
    };
    let (placed, suffix, runs) = match side {
        Side::Main => (scn.clone(), String::new(), spec.runs),
        Side::Other => (
            builtin_placed(&scn.name, placement)?,
            format!("-{placement}"),
            spec.runs.min(OTHER_RUNS),
        ),
    };
    let p = st.start(
        &format!("{} sweep{suffix}", placed.name),
        spec.xs.len() as u64 * u64::from(runs),
    );
    let seed = st.seed(block.at(f.index()));
    let pts = sweep(&placed, placed.run, &spec.xs, runs, seed, &p)?;
    st.done(&p);
    Ok(pts)
}

/// Figs. 7, 10, 11: a direction map.
fn map_of(
    st: &mut Stage<'_>,
    main: Placement,
    m: Scene,
    side: Side,
    scn: &Scenario,
) -> Result<Vec<Arrow>, Error> {
    let scn = &*on_side(scn, main, side)?;
    let seed = match side {
        Side::Main => MAPS.at(m.index()),
        Side::Other => MAPS_OTHER.at(m.index()),
    };
    let grid = scn.grid.as_ref().ok_or(Error::ScenarioWithout("grid"))?;
    let p = st.start(
        &format!("{} field, {} placement", scn.name, placement(main, side)),
        (grid.xs.len() * grid.ys.len()) as u64,
    );
    let arrows = direction_map(scn, grid, st.seed(seed), &p)?;
    st.done(&p);
    Ok(arrows)
}

/// Cloud: how far the swarm perceives it, by increasing distance, with `side`'s placement.
fn cloud_profile(
    st: &mut Stage<'_>,
    main: Placement,
    side: Side,
    cloud: &Scenario,
) -> Result<Vec<RadialPoint>, Error> {
    let cloud = &*on_side(cloud, main, side)?;
    let seed = match side {
        Side::Main => CLOUD_PROFILE.at(0),
        Side::Other => PROFILES_OTHER.at(0),
    };
    let distances = refined(
        (0..=24).map(|k| 0.5 * f64::from(k)).collect(),
        &CLOUD_REFINED,
    );
    let p = st.start(
        &format!("cloud radial profile, {} placement", placement(main, side)),
        distances.len() as u64 * u64::from(PROFILE_RUNS),
    );
    let profile = radial_profile(
        cloud,
        cloud.run,
        Point2::origin(),
        &distances,
        PROFILE_RUNS,
        st.seed(seed),
        &p,
    )?;
    let profile = by_distance(profile);
    st.done(&p);
    Ok(profile)
}

/// The cycle length: success and waves heard per cycle length of [`CYCLES`].
fn cycle_effect(st: &mut Stage<'_>, sharp: &Scenario) -> Result<Vec<CycleRun>, Error> {
    let mut rows = Vec::new();
    let p = st.start(
        "cycle length (sharp)",
        (CYCLES.len() * CYCLE_XS.len()) as u64 * u64::from(CYCLE_RUNS),
    );
    for (k, &c) in CYCLES.iter().enumerate() {
        let mut cfg = sharp.run;
        cfg.params.wave.cycle = Duration::from_secs(c);
        let seed = st.seed(CYCLE_SWEEPS.at(k));
        let points = sweep(sharp, cfg, &CYCLE_XS, CYCLE_RUNS, seed, &p)?;
        let load = cycle_load(sharp, cfg, 10, st.seed(CYCLE_WAVES.at(k)))?;
        rows.push(CycleRun {
            cycle_s: c,
            waves_heard: load.heard,
            initiating: load.initiating,
            agent_cycles: load.agents,
            points,
        });
    }
    st.done(&p);
    Ok(rows)
}

/// The discussion's shapes on a random field (line, cross, …), both opposite-bearing rules.
fn shapes(st: &mut Stage<'_>, sharp: &Scenario) -> Result<crate::shapes::ShapesResult, Error> {
    use crate::shapes::{KEEP_FORMATIONS, RUNS, compute};
    let runs_n = (4 + u64::from(KEEP_FORMATIONS)) * u64::from(RUNS);
    let p = st.start("shapes on a random field", runs_n);
    let shapes = compute(sharp.run, st.seed(SHAPES.at(0)), &p)?;
    st.done(&p);
    Ok(shapes)
}

/// One wave through the swarm of Fig. 2.
fn wave(st: &mut Stage<'_>) -> Result<swarm_sim::waves::Wave, Error> {
    use swarm_sim::waves::{WaveSpec, one_wave};
    let p = st.start("one wave (Fig. 2)", 1);
    let w = one_wave(&WaveSpec::paper(), st.seed(WAVE.at(0)))?;
    st.done(&p);
    Ok(w)
}

/// Runs of the NumPy peer's work (`scripts/numpy_peer.py`): [`PEER_RUNS`] runs of one
/// negotiation period of the sharp scenario from its start, one after another on this thread,
/// the observer's pooled diversity included (the peer computes it too). Wall seconds per run.
fn peer_work(st: &Stage<'_>, sharp: &Scenario) -> Result<f64, Error> {
    let seed = st.seed(PEER.at(0));
    let t0 = Clock::now();
    for r in 0..PEER_RUNS {
        let s = derive(seed, &[u64::from(r)]);
        experiment::run(sharp, sharp.run, sharp.start, 1, s, false)?;
    }
    Ok(t0.elapsed().as_secs_f64() / f64::from(PEER_RUNS))
}

/// Runs of the NumPy peer's work (unit `peer-work`), as the peer's header measures it.
pub const PEER_RUNS: u32 = 100;

/// Speed: one negotiation period per size of [`BENCH_AGENTS`] on one thread (`swarm bench`).
fn speed(st: &Stage<'_>, sharp: &Scenario) -> Result<Vec<BenchResult>, Error> {
    BENCH_AGENTS
        .iter()
        .enumerate()
        .map(|(k, &n)| Ok(experiment::bench(sharp, n, st.seed(SPEED.at(k)))?))
        .collect()
}

/// Neighbour counts of [`PLACEMENTS`] random placements of the sharp scenario's swarm.
fn placement_stats(st: &Stage<'_>) -> Result<PlacementStats, Error> {
    let scn = builtin_placed("sharp", Placement::Random)?;
    let seed = st.seed(PLACEMENT_STATS.at(0));
    let (mut redrawn, mut plain, mut disconnected) = (0.0, 0.0, 0u64);
    for k in 0..PLACEMENTS {
        let mut rng = Pcg64Mcg::seed_from_u64(derive(seed, &[k]));
        redrawn += Swarm::place(scn.agents, scn.shape, 1.0, &mut rng)?.mean_degree();
        let offsets = (0..scn.agents)
            .map(|_| scn.shape.sample(&mut rng).unwrap_or_default())
            .collect();
        let s = Swarm::from_offsets(offsets, 1.0);
        plain += s.mean_degree();
        disconnected += u64::from(!s.is_connected());
    }
    let n = PLACEMENTS as f64;
    Ok(PlacementStats {
        redrawn_degree: redrawn / n,
        plain_degree: plain / n,
        plain_disconnected: disconnected as f64 / n,
    })
}
