//! `cimax swarm reproduce`: every experiment of the paper's section 3, its figures and CSV
//! files, and `docs/reproduction.md` (rendered from `templates/reproduction.md.j2`) with the
//! paper's numbers beside ours.

use std::path::{Path, PathBuf};
use std::time::Instant as Clock;

use nalgebra::Point2;
use protocol::Duration;
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::Serialize;

use crate::pages::csv::write_course_csv;
use crate::pages::csv::{
    CycleRow, write_cycle_csv, write_field_csv, write_radial_csv, write_run_csv, write_sweep_csv,
};
use crate::pages::figures::{self, time_course_figure};
use crate::pages::marks;
use crate::progress::Progress;
use crate::report::csv_files::{fixed, opt};
use crate::report::plot::{self, Line};
use crate::seeds::derive;
use crate::swarm::experiment::{
    self, Arrow, Error, RadialPoint, RunOutput, SweepPoint, direction_map, radial_profile, sweep,
    waves_heard,
};
use crate::swarm::geometry::{Swarm, lattice};
use crate::swarm::scenario::{DEFAULT_PLACEMENT, LATTICE_SPACING, Placement, Scenario};
use crate::swarm::sensitivity::{Knob, diversity_at, heading_against_x, success_against};
use crate::swarm::timecourse::{TimeCourse, time_course};

mod beyond;
mod caption_cloud;
mod page;
mod sensitivity;
mod settle;
mod verdicts;

use page::{Report, markdown};
use sensitivity::{SensitivitySection, sensitivity};

/// What `swarm reproduce` needs.
#[derive(Clone, Debug)]
pub struct Options {
    /// Base seed; every stage derives its own.
    pub seed: u64,
    /// The `docs` directory: `reproduction.md` goes there, figures and CSV into `figures/`.
    pub docs: PathBuf,
    /// No progress bars.
    pub quiet: bool,
    /// The placement of every experiment of the page ([`DEFAULT_PLACEMENT`] for the committed
    /// page); the sweeps are also run with the other placement, as a check of robustness.
    pub placement: Placement,
}

/// Runs tried for each run figure (the first successful one is shown).
pub const RUN_TRIES: u64 = 20;

/// Cycle lengths of the cycle-length experiment, seconds.
pub const CYCLES: [u64; 7] = [100, 200, 300, 500, 1000, 2000, 5000];
/// Initial positions of the cycle-length experiment.
pub const CYCLE_XS: [f64; 2] = [-2.0, -1.0];

fn builtin(name: &str) -> Result<Scenario, Error> {
    Scenario::builtin(name).ok_or_else(|| format!("built-in scenario {name} is missing").into())
}

/// A built-in scenario with its agents placed by `placement`.
fn builtin_placed(name: &str, placement: Placement) -> Result<Scenario, Error> {
    Ok(builtin(name)?.placed(placement)?)
}

/// The stages of `swarm reproduce`: their log lines, progress bars, seeds and output folder.
struct Stage<'a> {
    log: &'a mut dyn FnMut(&str),
    quiet: bool,
    t: Clock,
    /// The base seed.
    base: u64,
    /// `docs/figures`.
    figs: PathBuf,
}

impl Stage<'_> {
    /// The seed of stage `stage`.
    fn seed(&self, stage: u64) -> u64 {
        derive(self.base, &[stage])
    }

    fn start(&mut self, what: &str, runs: u64) -> Progress {
        self.t = Clock::now();
        (self.log)(&format!("{what} ({runs} runs)..."));
        Progress::new(runs, what, self.quiet)
    }

    fn done(&mut self, p: &Progress) {
        p.finish();
        (self.log)(&format!(
            "  done in {:.1} s",
            self.t.elapsed().as_secs_f64()
        ));
    }
}

fn mean_time_at(points: &[SweepPoint], x: f64) -> Option<f64> {
    points
        .iter()
        .find(|p| (p.x_init - x).abs() < 1e-9)
        .and_then(|p| p.mean_success_periods)
}

fn rate_at(points: &[SweepPoint], x: f64) -> Option<f64> {
    points
        .iter()
        .find(|p| (p.x_init - x).abs() < 1e-9)
        .map(SweepPoint::success_rate)
}

fn rate_range(points: &[SweepPoint], keep: impl Fn(f64) -> bool) -> (f64, f64) {
    points
        .iter()
        .filter(|p| keep(p.x_init))
        .map(SweepPoint::success_rate)
        .fold((f64::MAX, f64::MIN), |(lo, hi), r| (lo.min(r), hi.max(r)))
}

fn pct(v: f64) -> String {
    format!("{:.0} %", 100.0 * v)
}

fn rate_span((lo, hi): (f64, f64)) -> String {
    if (hi - lo).abs() < 1e-9 {
        format!("{:.2}", lo)
    } else {
        format!("{lo:.2}–{hi:.2}")
    }
}

/// Fraction of arrows in `keep` whose direction has a component toward the line x = 0.
fn toward_border(arrows: &[Arrow], keep: impl Fn(f64) -> bool) -> (usize, usize) {
    let sel: Vec<&Arrow> = arrows.iter().filter(|a| keep(a.at.x)).collect();
    let ok = sel
        .iter()
        .filter(|a| a.direction.is_some_and(|d| d.cos() * a.at.x < 0.0))
        .count();
    (ok, sel.len())
}

/// Fraction of arrows in `keep` pointing toward +x.
fn toward_plus_x(arrows: &[Arrow], keep: impl Fn(f64) -> bool) -> (usize, usize) {
    let sel: Vec<&Arrow> = arrows.iter().filter(|a| keep(a.at.x)).collect();
    let ok = sel
        .iter()
        .filter(|a| a.direction.is_some_and(|d| d.cos() > 0.0))
        .count();
    (ok, sel.len())
}

/// A cloud's radial profile as `(d, inward, s.e.)` points.
fn inward_points(profile: &[RadialPoint]) -> Vec<(f64, f64, f64)> {
    profile
        .iter()
        .map(|p| (p.distance, p.inward, p.inward_se))
        .collect()
}

/// Distance beyond which a swarm no longer heads for the cloud: where the mean inward
/// alignment last falls through `threshold`, interpolated, with its standard error.
fn perception_limit(profile: &[RadialPoint], threshold: f64) -> Option<(f64, f64)> {
    crate::stats::crossing(&inward_points(profile), threshold, false)
}

/// Distance up to which a swarm inside the cloud heads out toward its border: where the mean
/// inward alignment first turns from negative to positive going out, interpolated, with its
/// standard error.
fn outward_limit(profile: &[RadialPoint]) -> Option<(f64, f64)> {
    crate::stats::crossing(&inward_points(profile), 0.0, true)
}

/// `grid` with the points `refined` added where they are new, by increasing value: a grid
/// refined where the paper claims an edge. The grid's own points keep their indices first, so
/// their seeds do not change.
fn refined(grid: Vec<f64>, refined: &[f64]) -> Vec<f64> {
    let mut all = grid;
    for &r in refined {
        if all.iter().all(|g| (g - r).abs() > 1e-9) {
            all.push(r);
        }
    }
    all
}

/// `profile` by increasing distance.
fn by_distance(mut profile: Vec<RadialPoint>) -> Vec<RadialPoint> {
    profile.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    profile
}

/// Where the cloud profiles are refined to 0.25 R: around the claimed edges d = 4 (heading
/// out inside) and d = 7, 7.5 (random beyond).
const CLOUD_REFINED: [f64; 9] = [3.25, 3.75, 4.25, 4.75, 6.25, 6.75, 7.25, 7.75, 8.25];

/// Swarm sizes of the speed figures.
const BENCH_AGENTS: [usize; 3] = [61, 1000, 10_000];

/// Results of `swarm reproduce` that the command prints.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Where the report went.
    pub report: PathBuf,
    /// Wall time, seconds.
    pub wall_s: f64,
    /// The placement of every experiment ([`Options::placement`]).
    pub placement: Placement,
    /// Sharp-border sweep, main placement.
    pub sharp: Vec<SweepPoint>,
    /// Gradient sweep, main placement.
    pub gradient: Vec<SweepPoint>,
    /// Sharp-border sweep, the other placement.
    pub sharp_other: Vec<SweepPoint>,
    /// Gradient sweep, the other placement.
    pub gradient_other: Vec<SweepPoint>,
}

/// Runs every experiment, writes the figures and CSV files into `docs/figures/` and
/// regenerates `docs/reproduction.md`. `log` receives one line per stage.
///
/// # Errors
/// If a run fails or a file cannot be written.
pub fn reproduce(opts: &Options, log: &mut dyn FnMut(&str)) -> Result<Summary, Error> {
    let t0 = Clock::now();
    let figs = opts.docs.join("figures");
    std::fs::create_dir_all(&figs)?;
    let main = opts.placement;
    let sharp = builtin_placed("sharp", main)?;
    let gradient = builtin_placed("gradient", main)?;
    let cloud = builtin_placed("cloud", main)?;
    let mut st = Stage {
        log,
        quiet: opts.quiet,
        t: Clock::now(),
        base: opts.seed,
        figs,
    };
    let runs = run_figures(&mut st, [&sharp, &gradient])?;
    let (sweeps, other_sweeps) = sweeps(&mut st, main, [&sharp, &gradient])?;
    sweep_figures(&st.figs, main, [&sharp, &gradient], &sweeps, &other_sweeps)?;
    let maps = direction_maps(&mut st, [&sharp, &gradient, &cloud])?;
    let profile = cloud_profile(&mut st, &cloud)?;
    let caption = caption_cloud::run(&mut st, main)?;
    let courses = time_courses(&mut st, main, [&sharp, &gradient])?;
    let plateaus: Vec<(f64, f64, usize)> = courses
        .iter()
        .map(|[c, _]| (c.plateau, c.plateau_se, c.plateau_runs))
        .collect();
    let settled = settle::run(&mut st, main, [&sharp, &gradient], &courses, &caption)?;
    let cycle_rows = cycle_effect(&mut st, &sharp)?;
    let sensitivity = sensitivity(&mut st, main, &sharp, &gradient)?;
    let shapes = shapes_stage(&mut st, &sharp)?;
    let beyond = beyond::run(&mut st, [&sharp, &gradient])?;
    let waves = wave_stage(&mut st)?;
    let speed = speed(&st, &sharp)?;

    let wall_s = t0.elapsed().as_secs_f64();
    let md = markdown(&Report {
        placement: placement_stats(&builtin_placed("sharp", Placement::Random)?, st.seed(80))?,
        speed: &speed,
        seed: opts.seed,
        wall_s,
        threads: rayon::current_num_threads(),
        sharp: &sharp,
        gradient: &gradient,
        cloud: &cloud,
        runs: &runs,
        sweeps: &sweeps,
        main,
        other_sweeps: &other_sweeps,
        maps: &maps,
        profile: &profile,
        profile_runs: PROFILE_RUNS,
        caption_cloud: &caption,
        plateaus: &plateaus,
        plateau_runs: COURSE_RUNS,
        courses: &courses,
        sensitivity: &sensitivity,
        shapes: &shapes,
        beyond: &beyond,
        settled: &settled,
        cycle_rows: &cycle_rows,
        cycle_runs: CYCLE_RUNS,
        waves,
    })?;
    let report = opts.docs.join("reproduction.md");
    std::fs::write(&report, md)?;
    Ok(Summary {
        report,
        wall_s,
        placement: main,
        sharp: sweeps[0].clone(),
        gradient: sweeps[1].clone(),
        sharp_other: other_sweeps[0].clone(),
        gradient_other: other_sweeps[1].clone(),
    })
}

/// The discussion's shapes on a random field (line, cross, …), both opposite-bearing rules.
fn shapes_stage(
    st: &mut Stage<'_>,
    sharp: &Scenario,
) -> Result<crate::pages::shapes::ShapesSection, Error> {
    let runs_n = (4 + u64::from(crate::pages::shapes::KEEP_FORMATIONS))
        * u64::from(crate::pages::shapes::RUNS);
    let p = st.start("shapes on a random field", runs_n);
    let shapes = crate::pages::shapes::reproduce(&st.figs, sharp.run, st.seed(200), &p)?;
    st.done(&p);
    Ok(shapes)
}

/// One wave through the swarm of Fig. 2.
fn wave_stage(st: &mut Stage<'_>) -> Result<crate::pages::waves::WavesSection, Error> {
    let p = st.start("one wave (Fig. 2)", 1);
    let waves = crate::pages::waves::reproduce(&st.figs, st.seed(95))?;
    st.done(&p);
    Ok(waves)
}

/// Speed: one negotiation period per size of [`BENCH_AGENTS`] on one thread (`swarm bench`).
fn speed(st: &Stage<'_>, sharp: &Scenario) -> Result<Vec<experiment::BenchResult>, Error> {
    BENCH_AGENTS
        .iter()
        .map(|&n| experiment::bench(sharp, n, st.seed(70 + n as u64)))
        .collect()
}

/// Runs per distance of the cloud's radial profile.
const PROFILE_RUNS: u32 = 40;
/// Runs per point of the other placement's sweeps (the robustness check; the main placement
/// runs the scenario's 50, as the paper did).
pub const OTHER_RUNS: u32 = 20;
/// Runs per scenario and placement of the averaged courses (Figs. 4b, 7b) and the plateaus.
pub const COURSE_RUNS: u32 = 50;
/// The averaged courses' plateau counts the runs that arrived at least this many periods
/// before the end.
pub(super) const PLATEAU_MIN_AFTER: u32 = 10;
/// First seed stage of the averaged courses: `COURSE_STAGE + 2 · field + placement`.
pub(super) const COURSE_STAGE: u64 = 40;
/// Runs per point of the cycle-length experiment.
const CYCLE_RUNS: u32 = 50;

/// Figs. 4 and 7: one run each, with its CSV and figure. The figure shows the first of up to
/// [`RUN_TRIES`] runs that succeeds (the sweeps give the rates); the report says which.
fn run_figures(st: &mut Stage<'_>, scns: [&Scenario; 2]) -> Result<Vec<(u64, RunOutput)>, Error> {
    let mut runs = Vec::new();
    for (k, scn) in scns.into_iter().enumerate() {
        let p = st.start(&format!("{} run", scn.name), RUN_TRIES);
        let mut chosen = None;
        for tries in 0..RUN_TRIES {
            let s = derive(st.seed(k as u64), &[tries]);
            let out = experiment::run(scn, scn.run, scn.start, scn.periods, s, false)?;
            let ok = out.success_at.is_some();
            if chosen.is_none() || ok {
                chosen = Some((tries, out));
            }
            if ok {
                break;
            }
        }
        let (tries, out) = chosen.ok_or("no run")?;
        let figs = &st.figs;
        write_run_csv(&figs.join(format!("{}-run.csv", scn.name)), &out, &scn.run)?;
        figures::run_figure(&figs.join(format!("{}-run.svg", scn.name)), scn, &out)?;
        st.done(&p);
        runs.push((tries, out));
    }
    Ok(runs)
}

/// Sweeps of one placement, one per scenario.
type Sweeps = Vec<Vec<SweepPoint>>;

/// Figs. 5 and 8: sweeps with the `main` placement (`SCENARIO-sweep.csv`) and with the other
/// (`SCENARIO-sweep-OTHER.csv`), and their CSV files. `scns` are placed by `main`. Each placement keeps the seeds it had as the main or the second one
/// (random 10, 11; lattice 12, 13).
fn sweeps(
    st: &mut Stage<'_>,
    main: Placement,
    scns: [&Scenario; 2],
) -> Result<(Sweeps, Sweeps), Error> {
    let mut sweeps = Vec::new();
    let mut other_sweeps = Vec::new();
    let other = main.other();
    let stage_of = |p: Placement| match p {
        Placement::Random => 10,
        Placement::Lattice => 12,
    };
    let other_suffix = format!("-{other}");
    for (k, scn) in scns.into_iter().enumerate() {
        let spec = scn
            .sweep
            .as_ref()
            .ok_or("built-in scenario without sweep")?;
        let placed_other = builtin_placed(&scn.name, other)?;
        for (out, scn, stage, suffix, runs) in [
            (&mut sweeps, scn, stage_of(main), "", spec.runs),
            (
                &mut other_sweeps,
                &placed_other,
                stage_of(other),
                other_suffix.as_str(),
                spec.runs.min(OTHER_RUNS),
            ),
        ] {
            let p = st.start(
                &format!("{} sweep{suffix}", scn.name),
                spec.xs.len() as u64 * u64::from(runs),
            );
            let pts = sweep(scn, scn.run, &spec.xs, runs, st.seed(stage + k as u64), &p)?;
            st.done(&p);
            let csv = st.figs.join(format!("{}-sweep{suffix}.csv", scn.name));
            write_sweep_csv(&csv, &pts)?;
            out.push(pts);
        }
    }
    Ok((sweeps, other_sweeps))
}

/// The sweep figures: both placements and the paper's rates.
fn sweep_figures(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    sweeps: &[Vec<SweepPoint>],
    other_sweeps: &[Vec<SweepPoint>],
) -> Result<(), Error> {
    let [sharp, gradient] = scns;
    for (k, (scn, crit, paper)) in [
        (sharp, "|x| < 0.33 R", marks::sweep_for("sharp")),
        (gradient, "x ≥ 2.33", marks::sweep_for("gradient")),
    ]
    .into_iter()
    .enumerate()
    {
        figures::sweep_figure(
            &figs.join(format!("{}-sweep.svg", scn.name)),
            &format!(
                "{}: success ({crit} within {} periods), runs per point: {main} {}, {} {}",
                scn.name,
                scn.periods,
                sweeps[k].first().map_or(0, |p| p.runs),
                main.other(),
                other_sweeps[k].first().map_or(0, |p| p.runs),
            ),
            &[
                (format!("{main} placement").as_str(), &sweeps[k]),
                (
                    format!("{} placement", main.other()).as_str(),
                    &other_sweeps[k],
                ),
            ],
            &paper,
        )?;
    }
    Ok(())
}

/// Figs. 6, 9, 10: direction maps, with their CSV files and figures.
fn direction_maps(st: &mut Stage<'_>, scns: [&Scenario; 3]) -> Result<Vec<Vec<Arrow>>, Error> {
    let mut maps = Vec::new();
    for (k, scn) in scns.into_iter().enumerate() {
        let grid = scn.grid.as_ref().ok_or("built-in scenario without grid")?;
        let p = st.start(
            &format!("{} field", scn.name),
            (grid.xs.len() * grid.ys.len()) as u64,
        );
        let arrows = direction_map(scn, grid, st.seed(20 + k as u64), &p)?;
        st.done(&p);
        let figs = &st.figs;
        write_field_csv(&figs.join(format!("{}-field.csv", scn.name)), &arrows)?;
        figures::direction_figure(
            &figs.join(format!("{}-field.svg", scn.name)),
            scn,
            grid,
            &arrows,
            &marks::map(&scn.name),
        )?;
        maps.push(arrows);
    }
    Ok(maps)
}

/// Cloud: how far the swarm perceives it, with its CSV file and figure.
fn cloud_profile(st: &mut Stage<'_>, cloud: &Scenario) -> Result<Vec<RadialPoint>, Error> {
    let distances = refined(
        (0..=24).map(|k| 0.5 * f64::from(k)).collect(),
        &CLOUD_REFINED,
    );
    let profile_runs = PROFILE_RUNS;
    let p = st.start(
        "cloud radial profile",
        distances.len() as u64 * u64::from(profile_runs),
    );
    let profile = radial_profile(
        cloud,
        cloud.run,
        Point2::origin(),
        &distances,
        profile_runs,
        st.seed(30),
        &p,
    )?;
    let profile = by_distance(profile);
    st.done(&p);
    write_radial_csv(&st.figs.join("cloud-profile.csv"), &profile)?;
    figures::radial_figure(
        &st.figs.join("cloud-profile.svg"),
        &format!(
            "cloud: heading of a swarm against its distance from the cloud's centre, {profile_runs} runs per point"
        ),
        &profile,
        &marks::profile_lines(cloud),
    )?;
    Ok(profile)
}

/// Figs. 4b and 7b averaged: [`COURSE_RUNS`] full runs from the start per scenario and
/// placement (`[main, other]` per scenario), their CSV files and figures. The main placement's
/// runs give the diversity plateaus.
fn time_courses(
    st: &mut Stage<'_>,
    main: Placement,
    scns: [&Scenario; 2],
) -> Result<Vec<[TimeCourse; 2]>, Error> {
    let mut courses = Vec::new();
    for (k, scn) in scns.into_iter().enumerate() {
        let other = builtin_placed(&scn.name, main.other())?;
        let mut pair = Vec::new();
        for (j, (placed, placement)) in [(scn, main), (&other, main.other())]
            .into_iter()
            .enumerate()
        {
            let p = st.start(
                &format!("{} course, {placement} placement", scn.name),
                u64::from(COURSE_RUNS),
            );
            pair.push(time_course(
                placed,
                COURSE_RUNS,
                PLATEAU_MIN_AFTER,
                st.seed(COURSE_STAGE + 2 * k as u64 + j as u64),
                &p,
            )?);
            st.done(&p);
        }
        let [m, o]: [TimeCourse; 2] = pair.try_into().map_err(|_| "two courses")?;
        let (main_name, other_name) = (main.to_string(), main.other().to_string());
        let named = [(main_name.as_str(), &m), (other_name.as_str(), &o)];
        write_course_csv(&st.figs.join(format!("{}-course.csv", scn.name)), &named)?;
        time_course_figure(
            &st.figs.join(format!("{}-course.svg", scn.name)),
            &format!(
                "{}: {} runs from x = {} per placement, averaged",
                scn.name, COURSE_RUNS, scn.start.x
            ),
            &named,
            &marks::course(&scn.name),
        )?;
        courses.push([m, o]);
    }
    Ok(courses)
}

/// The paper's Figs. 4b and 7b: the diversity at the start and the plateau(s).
struct PaperCourse {
    start: f64,
    plateaus: Vec<(f64, &'static str)>,
}

/// The paper's course of the sharp border (k = 0) or the gradient, from the claims.
fn paper_course(k: usize) -> PaperCourse {
    use crate::pages::claims::{Id, claim};
    let (start, plateau) = [
        (Id::SharpStart, Id::SharpPlateau),
        (Id::GradientStart, Id::GradientPlateau),
    ][k];
    PaperCourse {
        start: claim(start).values().first().map_or(f64::NAN, |v| v.0),
        plateaus: claim(plateau).values(),
    }
}

/// The cycle length: success and waves heard per cycle length, with the CSV file and figure.
fn cycle_effect(st: &mut Stage<'_>, sharp: &Scenario) -> Result<Vec<CycleRow>, Error> {
    let cycle_runs = CYCLE_RUNS;
    let mut cycle_rows = Vec::new();
    let p = st.start(
        "cycle length (sharp)",
        (CYCLES.len() * CYCLE_XS.len()) as u64 * u64::from(cycle_runs),
    );
    for (k, &c) in CYCLES.iter().enumerate() {
        let mut cfg = sharp.run;
        cfg.params.wave.cycle = Duration::from_secs(c);
        let points = sweep(
            sharp,
            cfg,
            &CYCLE_XS,
            cycle_runs,
            st.seed(50 + k as u64),
            &p,
        )?;
        let heard = waves_heard(sharp, cfg, 10, st.seed(60 + k as u64))?;
        cycle_rows.push(CycleRow {
            cycle_s: c,
            waves_heard: heard,
            points,
        });
    }
    st.done(&p);
    write_cycle_csv(&st.figs.join("cycle-effect.csv"), &cycle_rows)?;
    cycle_figure(&st.figs.join("cycle-effect.svg"), sharp, &cycle_rows)?;
    Ok(cycle_rows)
}

/// The cycle-length figure: success from each start and waves heard, against the cycle.
fn cycle_figure(path: &Path, sharp: &Scenario, cycle_rows: &[CycleRow]) -> Result<(), Error> {
    let lines: Vec<Line> = CYCLE_XS
        .iter()
        .enumerate()
        .map(|(i, &x)| Line {
            label: format!("success rate from x = {x}"),
            points: cycle_rows
                .iter()
                .map(|r| (r.cycle_s as f64, r.points[i].success_rate(), 0.0))
                .collect(),
        })
        .chain(std::iter::once(Line {
            label: format!("waves heard per agent per cycle / {}", sharp.agents),
            points: cycle_rows
                .iter()
                .map(|r| (r.cycle_s as f64, r.waves_heard / sharp.agents as f64, 0.0))
                .collect(),
        }))
        .collect();
    plot::xy_figure(
        path,
        &format!("sharp border: effect of the cycle length t_p^max ({CYCLE_RUNS} runs per point)"),
        "cycle length t_p^max / s",
        "fraction",
        &lines,
        (0.0, 1.05),
        &[],
        true,
    )?;
    Ok(())
}

/// Neighbour counts of random placements of the sharp scenario's swarm.
struct PlacementStats {
    /// Mean degree with the redraw-until-connected rule ([`Swarm::place`]).
    redrawn_degree: f64,
    /// Mean degree of plain uniform scattering.
    plain_degree: f64,
    /// Fraction of plain scatterings that are disconnected.
    plain_disconnected: f64,
}

/// Placements measured for [`PlacementStats`].
const PLACEMENTS: u64 = 200;

fn placement_stats(scn: &Scenario, seed: u64) -> Result<PlacementStats, Error> {
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
