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

use crate::pages::marks;
use crate::report::csv_files::write_course_csv;
use crate::report::csv_files::{
    CycleRow, fixed, opt, write_cycle_csv, write_field_csv, write_radial_csv, write_run_csv,
    write_sweep_csv,
};
use crate::report::plot::{self, Line};
use crate::report::timecourse_plot::time_course_figure;
use crate::seeds::derive;
use crate::swarm::experiment::{
    self, Arrow, Error, Progress, RadialPoint, RunOutput, SweepPoint, direction_map,
    radial_profile, sweep, waves_heard,
};
use crate::swarm::geometry::{Swarm, lattice};
use crate::swarm::scenario::{DEFAULT_PLACEMENT, LATTICE_SPACING, Placement, Scenario};
use crate::swarm::sensitivity::{Knob, diversity_at, heading_against_x, success_against};
use crate::swarm::timecourse::{TimeCourse, time_course};

mod beyond;
mod caption_cloud;
mod verdicts;

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
    let cycle_rows = cycle_effect(&mut st, &sharp)?;
    let sensitivity = sensitivity(&mut st, main, &sharp, &gradient)?;
    let runs_n = (4 + u64::from(crate::swarm::shapes::KEEP_FORMATIONS))
        * u64::from(crate::swarm::shapes::RUNS);
    let p = st.start("shapes on a random field", runs_n);
    let shapes = crate::swarm::shapes::reproduce(&st.figs, sharp.run, st.seed(200), &p)?;
    st.done(&p);
    let beyond = beyond::run(&mut st, [&sharp, &gradient])?;
    let p = st.start("one wave (Fig. 2)", 1);
    let waves = crate::swarm::waves::reproduce(&st.figs, st.seed(95))?;
    st.done(&p);

    // Speed: one negotiation period per size on one thread (`swarm bench`).
    let mut speed = Vec::new();
    for n in BENCH_AGENTS {
        speed.push(experiment::bench(&sharp, n, st.seed(70 + n as u64))?);
    }

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

/// Runs per distance of the cloud's radial profile.
const PROFILE_RUNS: u32 = 40;
/// Runs per point of the other placement's sweeps (the robustness check; the main placement
/// runs the scenario's 50, as the paper did).
pub const OTHER_RUNS: u32 = 20;
/// Runs per scenario and placement of the averaged courses (Figs. 4b, 7b) and the plateaus.
pub const COURSE_RUNS: u32 = 50;
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
        plot::run_figure(&figs.join(format!("{}-run.svg", scn.name)), scn, &out)?;
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
        plot::sweep_figure(
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
        plot::direction_figure(
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
    plot::radial_figure(
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
                10,
                st.seed(40 + 2 * k as u64 + j as u64),
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

/// Runs per point of the sensitivity figures.
pub const SENS_RUNS: u32 = 20;
/// Runs per point of the extent's heading profiles.
pub const EXTENT_RUNS: u32 = 30;
/// Where the sensitivity runs start (both fields).
const SENS_X: f64 = -2.0;

/// One sensitivity table: a knob's values down, the cases across.
#[derive(Serialize)]
struct SensTable {
    key: &'static str,
    what: &'static str,
    figure: String,
    cases: Vec<String>,
    /// Per value: the value, then per case "success (mean time)".
    rows: Vec<Vec<String>>,
}

/// The swarm's extent: perception edges per field and extent.
#[derive(Serialize)]
struct ExtentRow {
    field: String,
    diameter: String,
    agents: usize,
    /// The edge, R, two decimals.
    edge: Option<String>,
    /// The edge and its standard error ([`extent_edge`]).
    #[serde(skip)]
    edge_se: Option<(f64, f64)>,
    /// The verdict against the paper's edge on this field.
    verdict: &'static str,
}

/// Where the first move's heading toward the border (`(x, mean cos, s.e.)`, x < 0) last falls
/// through 0.5 going away from the border, interpolated: the farthest start from which the swarm
/// heads for the border, as a distance, with its standard error.
fn extent_edge(profile: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    let mut by_distance: Vec<(f64, f64, f64)> =
        profile.iter().map(|&(x, m, se)| (x.abs(), m, se)).collect();
    by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
    crate::stats::crossing(&by_distance, 0.5, false)
}

/// Where the extent's starts are refined to 0.25 R: around the claimed edges 2.5 and 2.2.
const EXTENT_REFINED: [f64; 4] = [-3.25, -2.75, -2.25, -1.75];

/// The sensitivity section.
#[derive(Serialize)]
struct SensitivitySection {
    runs: u32,
    x: String,
    tables: Vec<SensTable>,
    /// Gradient: per slope, the diversity at the success line.
    slope_rows: Vec<[String; 4]>,
    extent_runs: u32,
    extent: Vec<ExtentRow>,
    /// The 3 R swarm's edges are within 0.5 R (the sampling step) of the paper's 2.5 and 2.2.
    extent_big_matches: bool,
    /// The 2.5 R swarm's edges are shorter than the 3 R swarm's on both fields.
    extent_small_shorter: bool,
}

/// One knob's sensitivity run: its key, what the axis shows, (value, knob) pairs, a
/// logarithmic axis, and whether the other placement runs too.
type SensSpec = (&'static str, &'static str, Vec<(f64, Knob)>, bool, bool);

/// Success and mean time as a table cell.
fn cell(p: &SweepPoint) -> String {
    format!(
        "{} ({})",
        fixed(p.success_rate(), 2),
        opt(p.mean_success_periods, 1)
    )
}

/// The knobs the paper leaves open, one at a time: success from [`SENS_X`] against each, the
/// gradient's diversity against its slope, and the perception edge of a smaller swarm.
fn sensitivity(
    st: &mut Stage<'_>,
    main: Placement,
    sharp: &Scenario,
    gradient: &Scenario,
) -> Result<SensitivitySection, Error> {
    let sharp_o = builtin_placed(&sharp.name, main.other())?;
    let gradient_o = builtin_placed(&gradient.name, main.other())?;
    let name = |s: &Scenario, p: Placement| format!("{}, {p}", s.name);
    let mut tables = Vec::new();
    let specs: [SensSpec; 4] = [
        (
            "cycle",
            "cycle length t_p^max / s",
            [20u64, 50, 100, 200, 500, 1000, 2000]
                .map(|c| (c as f64, Knob::Cycle(c)))
                .to_vec(),
            true,
            true,
        ),
        (
            "period",
            "negotiation period / cycles (half gathering, half deciding)",
            [2u16, 4, 10]
                .map(|c| (f64::from(c), Knob::Period(c)))
                .to_vec(),
            false,
            false,
        ),
        (
            "diffusion",
            "diffusion rate / %",
            [0.05f32, 0.10, 0.20]
                .map(|d| (f64::from(d * 100.0).round(), Knob::Diffusion(d)))
                .to_vec(),
            false,
            false,
        ),
        (
            "noise",
            "noise width (ξ uniform in ±width/2)",
            [0.5, 1.0, 2.0, 4.0].map(|w| (w, Knob::Noise(w))).to_vec(),
            false,
            false,
        ),
    ];
    for (k, (key, what, values, log_x, both_placements)) in specs.into_iter().enumerate() {
        let mut cases: Vec<(String, &Scenario)> =
            vec![(name(sharp, main), sharp), (name(gradient, main), gradient)];
        if both_placements {
            cases.insert(1, (name(&sharp_o, main.other()), &sharp_o));
            cases.push((name(&gradient_o, main.other()), &gradient_o));
        }
        let knobs: Vec<Knob> = values.iter().map(|v| v.1).collect();
        let p = st.start(
            &format!("sensitivity: {key}"),
            (cases.len() * knobs.len()) as u64 * u64::from(SENS_RUNS),
        );
        let mut results = Vec::new();
        for (j, (_, scn)) in cases.iter().enumerate() {
            results.push(success_against(
                scn,
                &knobs,
                SENS_X,
                SENS_RUNS,
                st.seed(500 + 10 * k as u64 + j as u64),
                &p,
            )?);
        }
        st.done(&p);
        let lines: Vec<Line> = cases
            .iter()
            .zip(&results)
            .map(|((label, _), pts)| Line {
                label: label.clone(),
                points: values
                    .iter()
                    .zip(pts)
                    .map(|(v, p)| (v.0, p.success_rate(), 0.0))
                    .collect(),
            })
            .collect();
        let figure = format!("sensitivity-{key}.svg");
        plot::xy_figure(
            &st.figs.join(&figure),
            &format!("success from x = {SENS_X} against the {key}, {SENS_RUNS} runs per point"),
            what,
            "success rate",
            &lines,
            (0.0, 1.05),
            &[],
            log_x,
        )?;
        tables.push(SensTable {
            key,
            what,
            figure,
            cases: cases.iter().map(|c| c.0.clone()).collect(),
            rows: values
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    std::iter::once(v.0.to_string())
                        .chain(results.iter().map(|pts| cell(&pts[i])))
                        .collect()
                })
                .collect(),
        });
    }

    // The gradient's slope: success from SENS_X and the diversity at the success line.
    let slopes = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0];
    let knobs: Vec<Knob> = slopes.iter().map(|&k| Knob::Slope(k)).collect();
    let p = st.start(
        "sensitivity: slope",
        2 * slopes.len() as u64 * u64::from(SENS_RUNS),
    );
    let success = success_against(gradient, &knobs, SENS_X, SENS_RUNS, st.seed(550), &p)?;
    let line_x = match &gradient.success {
        Some(crate::swarm::scenario::Success::BeyondX { x }) => *x,
        _ => 2.33,
    };
    let mut slope_rows = Vec::new();
    let mut div_line = Vec::new();
    for (k, knob) in knobs.iter().enumerate() {
        let s = knob.apply(gradient)?;
        let (m, se) = diversity_at(
            &s,
            Point2::new(line_x, 0.0),
            SENS_RUNS,
            st.seed(560 + k as u64),
            &p,
        )?;
        div_line.push((slopes[k], m, se));
        slope_rows.push([
            slopes[k].to_string(),
            format!("{} ± {}", fixed(m, 1), fixed(se, 1)),
            fixed(success[k].success_rate(), 2),
            opt(success[k].mean_success_periods, 1),
        ]);
    }
    st.done(&p);
    plot::xy_figure(
        &st.figs.join("sensitivity-slope.svg"),
        &format!(
            "gradient: the agents' mean diversity with the swarm at x = {line_x}, {SENS_RUNS} runs per slope"
        ),
        "slope of the ramp / per R",
        "mean V_k",
        &[Line {
            label: format!("{} placement", main),
            points: div_line,
        }],
        (0.0, 30.0),
        &[],
        false,
    )?;

    // The swarm's extent: 3 R against 2.5 R, the heading of the first move against x.
    let xs = refined(
        (1..=9).map(|k| -0.5 * f64::from(k)).rev().collect(),
        &EXTENT_REFINED,
    );
    let mut extent = Vec::new();
    let mut lines = Vec::new();
    let p = st.start(
        "sensitivity: extent",
        4 * xs.len() as u64 * u64::from(EXTENT_RUNS),
    );
    for (k, scn) in [sharp, gradient].into_iter().enumerate() {
        for (j, d) in [6.0, 5.0].into_iter().enumerate() {
            let s = Knob::Extent(d).apply(scn)?;
            let prof = heading_against_x(
                &s,
                &xs,
                EXTENT_RUNS,
                st.seed(570 + 2 * k as u64 + j as u64),
                &p,
            )?;
            let mut prof = prof;
            prof.sort_by(|a, b| a.0.total_cmp(&b.0));
            let edge = extent_edge(&prof);
            extent.push(ExtentRow {
                field: scn.name.clone(),
                diameter: d.to_string(),
                agents: s.agents,
                edge: edge.map(|e| format!("{} ± {}", fixed(e.0, 2), fixed(e.1, 2))),
                edge_se: edge,
                verdict: verdicts::edge_verdict(
                    edge,
                    [
                        crate::pages::claims::Id::SharpEdge,
                        crate::pages::claims::Id::GradientEdge,
                    ][k],
                )
                .words(),
            });
            lines.push(Line {
                label: format!("{}, diameter {d} R ({} agents)", scn.name, s.agents),
                points: prof,
            });
        }
    }
    st.done(&p);
    plot::xy_figure(
        &st.figs.join("sensitivity-extent.svg"),
        &format!(
            "heading of the first move toward +x against the start, {EXTENT_RUNS} runs per point ({main})"
        ),
        "x_init / R",
        "mean cos(direction)",
        &lines,
        (-0.3, 1.05),
        &marks::extent(),
        false,
    )?;
    let edge = |k: usize| extent[k].edge_se.map_or(0.0, |e| e.0);
    let extent_big_matches = {
        use crate::pages::{claims::Id, verdict::Verdict};
        verdicts::edge_verdict(extent[0].edge_se, Id::SharpEdge) == Verdict::Reproduced
            && verdicts::edge_verdict(extent[2].edge_se, Id::GradientEdge) == Verdict::Reproduced
    };
    let extent_small_shorter = edge(1) < edge(0) && edge(3) < edge(2);
    Ok(SensitivitySection {
        extent_big_matches,
        extent_small_shorter,
        runs: SENS_RUNS,
        x: SENS_X.to_string(),
        tables,
        slope_rows,
        extent_runs: EXTENT_RUNS,
        extent,
    })
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

struct Report<'a> {
    placement: PlacementStats,
    speed: &'a [experiment::BenchResult],
    seed: u64,
    wall_s: f64,
    threads: usize,
    sharp: &'a Scenario,
    gradient: &'a Scenario,
    cloud: &'a Scenario,
    runs: &'a [(u64, RunOutput)],
    sweeps: &'a [Vec<SweepPoint>],
    /// The placement of every experiment.
    main: Placement,
    /// Sweeps with the other placement.
    other_sweeps: &'a [Vec<SweepPoint>],
    maps: &'a [Vec<Arrow>],
    profile: &'a [RadialPoint],
    profile_runs: u32,
    /// The cloud of Fig. 10's caption.
    caption_cloud: &'a caption_cloud::CaptionCloud,
    plateaus: &'a [(f64, f64, usize)],
    plateau_runs: u32,
    /// Per scenario, the averaged course of the main placement and of the other.
    courses: &'a [[TimeCourse; 2]],
    sensitivity: &'a SensitivitySection,
    /// The discussion's line and cross on a random field.
    shapes: &'a crate::swarm::shapes::ShapesSection,
    /// Entropy instead of variance (beyond the paper).
    beyond: &'a beyond::BeyondSection,
    cycle_rows: &'a [CycleRow],
    cycle_runs: u32,
    waves: crate::swarm::waves::WavesSection,
}

/// `docs/reproduction.md` as its template sees it (`templates/reproduction.md.j2`).
#[derive(Serialize)]
struct Page<'a> {
    seed: u64,
    wall_s: String,
    threads: usize,
    setup: Setup,
    comparison: Comparison,
    sharp: SharpSection,
    gradient: GradientSection,
    cloud: CloudSection,
    caption_cloud: caption_cloud::CaptionSection,
    cycle: CycleSection,
    course: CourseSection,
    sensitivity: &'a SensitivitySection,
    shapes: &'a crate::swarm::shapes::ShapesSection,
    beyond: &'a beyond::BeyondSection,
    speed: SpeedSection,
    waves: crate::swarm::waves::WavesSection,
    names: [String; 3],
    placement: PlacementNote,
}

/// Which placement ran every experiment, which only the sweeps, and their neighbour counts.
#[derive(Serialize)]
struct PlacementNote {
    main: &'static str,
    other: &'static str,
    /// The main placement is the commands' default ([`DEFAULT_PLACEMENT`]).
    main_is_default: bool,
    /// Mean neighbours of the main placement's 61 agents.
    main_degree: String,
    /// Mean neighbours of the other placement's.
    other_degree: String,
}

/// A value of each placement, by name (the template picks `x[placement.main]`).
#[derive(Serialize)]
struct Pair<T> {
    random: T,
    lattice: T,
}

impl<T> Pair<T> {
    /// The pair whose value for `placement` is `main`, for the other `other`.
    fn of(placement: Placement, main: T, other: T) -> Pair<T> {
        match placement {
            Placement::Random => Pair {
                random: main,
                lattice: other,
            },
            Placement::Lattice => Pair {
                random: other,
                lattice: main,
            },
        }
    }
}

/// `f` of the main sweep (placed by `r.main`) and of the other.
fn pair<T>(
    r: &Report<'_>,
    main: &[SweepPoint],
    other: &[SweepPoint],
    f: impl Fn(&[SweepPoint]) -> T,
) -> Pair<T> {
    Pair::of(r.main, f(main), f(other))
}

/// The set-up section.
#[derive(Serialize)]
struct Setup {
    /// The radius of the main placement's swarm, R.
    radius: String,
    /// Runs per point of the other placement's sweeps.
    other_runs: u32,
    agents: usize,
    degree: String,
    placements: u64,
    lattice_spacing: String,
    lattice_degree: String,
    cycle_s: u64,
    relay_s: u64,
    refractory_s: u64,
    step: String,
    periods: u32,
}

/// Which run a run figure shows.
#[derive(Serialize)]
struct RunNote {
    name: &'static str,
    tries: u64,
    success_at: Option<u32>,
}

/// The table of the paper's numbers beside ours, and the notes below it.
#[derive(Serialize)]
struct Comparison {
    verdicts: Vec<verdicts::Row>,
    /// "N reproduced, M partly, …".
    verdict_counts: String,
    sharp_near: Pair<String>,
    sharp_25: Pair<String>,
    sharp_far: Vec<String>,
    sharp_times: Vec<String>,
    sharp_plateau: String,
    sharp_near_arrows: String,
    sharp_far_arrows: String,
    gradient_mid: Pair<[String; 2]>,
    gradient_m4: Pair<String>,
    gradient_plateau: String,
    gradient_near_arrows: String,
    gradient_far_arrows: String,
    cloud_limit: Option<String>,
    cloud_outward: Option<String>,
    sharp_plateau_runs: usize,
    gradient_plateau_runs: usize,
    plateau_runs: u32,
    runs: Vec<RunNote>,
    run_tries: u64,
}

/// The sharp border's section.
#[derive(Serialize)]
struct SharpSection {
    rows: Vec<[String; 7]>,
    near: Pair<String>,
    degree: String,
    placements: u64,
    plain_degree: String,
    plain_disconnected: String,
    lattice_degree: String,
}

/// The gradient's section.
#[derive(Serialize)]
struct GradientSection {
    /// The field's slope on its ramp, per R.
    slope: String,
    /// The x of the success line.
    line_x: String,
    rows: Vec<[String; 7]>,
    mid: Pair<[String; 2]>,
    m4: Pair<String>,
}

/// The cloud's section.
#[derive(Serialize)]
struct CloudSection {
    runs: u32,
    rows: Vec<[String; 3]>,
    /// The ramp's outer edge, the swarm's radius and their sum (R).
    reach: [String; 3],
}

/// The outer edge of `scn`'s cloud, its swarm's radius and their sum, formatted.
fn reach(scn: &Scenario) -> [String; 3] {
    marks::cloud_reach(scn).map_or(["–".into(), "–".into(), "–".into()], |(e, r)| {
        [e.to_string(), fixed(r, 1), fixed(e + r, 1)]
    })
}

/// The cycle length's section.
#[derive(Serialize)]
struct CycleSection {
    agents: usize,
    runs: u32,
    xs: Vec<String>,
    rows: Vec<Vec<String>>,
    first_cycle_s: u64,
    first_waves: String,
    first_success: String,
    rest_cycle_s: u64,
    rest_range: String,
    /// Every run from every start succeeded with every cycle but the first.
    rest_all_succeed: bool,
    default_cycle_s: u64,
    default_waves: Option<String>,
}

/// One swarm size of the speed line.
#[derive(Serialize)]
struct SpeedSize {
    agents: usize,
    steps_per_s: String,
}

/// The speed section.
#[derive(Serialize)]
struct SpeedSection {
    period_s: u64,
    sizes: Vec<SpeedSize>,
}

/// The rows of a sweep table: the main placement and the other side by side.
fn sweep_rows(main: &[SweepPoint], other: &[SweepPoint]) -> Vec<[String; 7]> {
    main.iter()
        .zip(other)
        .map(|(p, q)| {
            [
                p.x_init.to_string(),
                p.runs.to_string(),
                fixed(p.success_rate(), 2),
                opt(p.mean_success_periods, 1),
                q.runs.to_string(),
                fixed(q.success_rate(), 2),
                opt(q.mean_success_periods, 1),
            ]
        })
        .collect()
}

/// Success rates in the sharp border's band |x| ≤ 2.
fn sharp_near(points: &[SweepPoint]) -> (f64, f64) {
    rate_range(points, |x| x.abs() <= 2.0 + 1e-9)
}

/// Success rates in the gradient's band −2 ≤ x < 2.33.
fn gradient_mid(points: &[SweepPoint]) -> [String; 2] {
    let (lo, hi) = rate_range(points, |x| (-2.0 - 1e-9..2.33).contains(&x));
    [pct(lo), pct(hi)]
}

/// Success rate at x = −4, `–` if not swept.
fn at_m4(points: &[SweepPoint]) -> String {
    rate_at(points, -4.0).map_or("–".into(), pct)
}

/// Mean degree of the lattice placement of the sharp scenario's swarm.
fn lattice_degree(r: &Report<'_>) -> f64 {
    Swarm::from_offsets(lattice(r.sharp.agents, LATTICE_SPACING), 1.0).mean_degree()
}

/// The placements and their measured neighbour counts.
fn placement_note(r: &Report<'_>) -> PlacementNote {
    let degrees = Pair {
        random: fixed(r.placement.redrawn_degree, 1),
        lattice: fixed(lattice_degree(r), 1),
    };
    let degree = |p: Placement| match p {
        Placement::Random => degrees.random.clone(),
        Placement::Lattice => degrees.lattice.clone(),
    };
    PlacementNote {
        main: r.main.name(),
        other: r.main.other().name(),
        main_is_default: r.main == DEFAULT_PLACEMENT,
        main_degree: degree(r.main),
        other_degree: degree(r.main.other()),
    }
}

/// `ok of n`.
fn of((ok, n): (usize, usize)) -> String {
    format!("{ok} of {n}")
}

fn setup(r: &Report<'_>) -> Setup {
    let p = &r.sharp.run.params;
    Setup {
        radius: fixed(marks::swarm_radius(r.sharp), 1),
        other_runs: r
            .other_sweeps
            .first()
            .and_then(|s| s.first())
            .map_or(0, |p| p.runs),
        agents: r.sharp.agents,
        degree: fixed(r.placement.redrawn_degree, 1),
        placements: PLACEMENTS,
        lattice_spacing: LATTICE_SPACING.to_string(),
        lattice_degree: fixed(lattice_degree(r), 1),
        cycle_s: p.wave.cycle.as_millis() / 1000,
        relay_s: p.wave.relay_delay.as_millis() / 1000,
        refractory_s: p.wave.refractory.as_millis() / 1000,
        step: r.sharp.run.step.to_string(),
        periods: r.sharp.periods,
    }
}

fn comparison(r: &Report<'_>) -> Comparison {
    let (sharp, gradient) = (&r.sweeps[0], &r.sweeps[1]);
    let (osharp, ogradient) = (&r.other_sweeps[0], &r.other_sweeps[1]);
    let sharp_25 = |pts: &[SweepPoint]| rate_span(rate_range(pts, |x| x.abs() < 2.5));
    let plateau = |k: usize| format!("{:.1} ± {:.1}", r.plateaus[k].0, r.plateaus[k].1);
    let verdicts = verdicts::verdicts(r);
    let verdict_counts = verdicts::counts(&verdicts);
    Comparison {
        verdicts,
        verdict_counts,
        sharp_near: pair(r, sharp, osharp, |p| rate_span(sharp_near(p))),
        sharp_25: pair(r, sharp, osharp, sharp_25),
        sharp_far: [-3.0, -4.0, -5.0]
            .map(|x| opt(rate_at(sharp, x), 2))
            .to_vec(),
        sharp_times: [-1.0, -2.0, -2.5]
            .map(|x| opt(mean_time_at(sharp, x), 1))
            .to_vec(),
        sharp_plateau: plateau(0),
        sharp_near_arrows: of(toward_border(&r.maps[0], |x| {
            x != 0.0 && x.abs() <= 2.0 + 1e-9
        })),
        sharp_far_arrows: of(toward_border(&r.maps[0], |x| x.abs() >= 3.0 - 1e-9)),
        gradient_mid: pair(r, gradient, ogradient, gradient_mid),
        gradient_m4: pair(r, gradient, ogradient, at_m4),
        gradient_plateau: plateau(1),
        gradient_near_arrows: of(toward_plus_x(&r.maps[1], |x| {
            (-2.0 - 1e-9..=1.5 + 1e-9).contains(&x)
        })),
        gradient_far_arrows: of(toward_plus_x(&r.maps[1], |x| x >= 2.5 - 1e-9)),
        cloud_limit: perception_limit(r.profile, 0.5).map(|d| fixed(d.0, 1)),
        cloud_outward: outward_limit(r.profile).map(|d| fixed(d.0, 1)),
        sharp_plateau_runs: r.plateaus[0].2,
        gradient_plateau_runs: r.plateaus[1].2,
        plateau_runs: r.plateau_runs,
        runs: ["sharp", "gradient"]
            .into_iter()
            .zip(r.runs)
            .map(|(name, (tries, out))| RunNote {
                name,
                tries: *tries,
                success_at: out.success_at,
            })
            .collect(),
        run_tries: RUN_TRIES,
    }
}

fn sharp_section(r: &Report<'_>) -> SharpSection {
    SharpSection {
        rows: sweep_rows(&r.sweeps[0], &r.other_sweeps[0]),
        near: pair(r, &r.sweeps[0], &r.other_sweeps[0], |p| {
            rate_span(sharp_near(p))
        }),
        degree: fixed(r.placement.redrawn_degree, 1),
        placements: PLACEMENTS,
        plain_degree: fixed(r.placement.plain_degree, 1),
        plain_disconnected: fixed(100.0 * r.placement.plain_disconnected, 0),
        lattice_degree: fixed(lattice_degree(r), 1),
    }
}

fn gradient_section(r: &Report<'_>) -> GradientSection {
    let g = r.gradient;
    GradientSection {
        slope: (g.field.mean(Point2::new(1.0, 0.0)) - g.field.mean(Point2::new(0.0, 0.0)))
            .to_string(),
        line_x: match &g.success {
            Some(crate::swarm::scenario::Success::BeyondX { x }) => x.to_string(),
            _ => "–".into(),
        },
        rows: sweep_rows(&r.sweeps[1], &r.other_sweeps[1]),
        mid: pair(r, &r.sweeps[1], &r.other_sweeps[1], gradient_mid),
        m4: pair(r, &r.sweeps[1], &r.other_sweeps[1], at_m4),
    }
}

fn cloud_section(r: &Report<'_>) -> CloudSection {
    CloudSection {
        reach: reach(r.cloud),
        runs: r.profile_runs,
        rows: r
            .profile
            .iter()
            .map(|p| {
                [
                    p.distance.to_string(),
                    fixed(p.inward, 2),
                    fixed(p.inward_se, 2),
                ]
            })
            .collect(),
    }
}

fn cycle_section(r: &Report<'_>) -> CycleSection {
    let default_cycle_s = r.sharp.run.params.wave.cycle.as_millis() / 1000;
    let rows = r
        .cycle_rows
        .iter()
        .map(|row| {
            let mut cells = vec![row.cycle_s.to_string(), fixed(row.waves_heard, 1)];
            for pnt in &row.points {
                cells.push(fixed(pnt.success_rate(), 2));
                cells.push(opt(pnt.mean_success_periods, 1));
            }
            cells
        })
        .collect();
    let first = &r.cycle_rows[0];
    let rest = &r.cycle_rows[1..];
    let rest_range = rest
        .iter()
        .flat_map(|row| row.points.iter().map(SweepPoint::success_rate))
        .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    CycleSection {
        agents: r.sharp.agents,
        runs: r.cycle_runs,
        xs: CYCLE_XS.iter().map(f64::to_string).collect(),
        rows,
        first_cycle_s: first.cycle_s,
        first_waves: fixed(first.waves_heard, 0),
        first_success: fixed(first.points[0].success_rate(), 2),
        rest_cycle_s: rest.first().map_or(0, |row| row.cycle_s),
        rest_range: rate_span(rest_range),
        rest_all_succeed: rest_range.0 >= 1.0,
        default_cycle_s,
        default_waves: r
            .cycle_rows
            .iter()
            .find(|row| row.cycle_s == default_cycle_s)
            .map(|row| fixed(row.waves_heard, 0)),
    }
}

fn speed_section(r: &Report<'_>) -> SpeedSection {
    SpeedSection {
        period_s: r.sharp.run.period_secs(),
        sizes: r
            .speed
            .iter()
            .map(|b| SpeedSize {
                agents: b.agents,
                steps_per_s: format!("{:.2e}", b.agent_steps_per_s()),
            })
            .collect(),
    }
}

/// One placement's row of the averaged course.
#[derive(Serialize)]
struct CourseRow {
    placement: String,
    runs: u32,
    /// Mean diversity at t = 0, and its 10–90 % range.
    start: String,
    start_range: String,
    /// Percentage of agents at x ≥ 0 at the start.
    across: String,
    /// Mean diversity over the last 10 periods.
    end: String,
    /// Mean consensus at t = 0 and over the last 10 periods.
    consensus_start: String,
    consensus_end: String,
    /// Runs that had arrived by the end.
    arrived: u32,
    /// The mean diversity at t = 0 is above the paper's.
    above_paper: bool,
    /// The consensus over the last 10 periods is below that at t = 0.
    consensus_falls: bool,
    /// Runs that arrived: mean periods to arrival, mean |y| at arrival, x gained per R walked
    /// (as a percentage).
    mean_arrival: String,
    y_at_arrival: String,
    straightness: String,
}

/// One scenario of the averaged courses.
#[derive(Serialize)]
struct CourseScenario {
    name: String,
    x_start: String,
    paper_start: String,
    paper_plateaus: String,
    rows: Vec<CourseRow>,
    plateau: String,
    plateau_runs: usize,
    /// Diversity of the noise alone: noise² / 12.
    noise_floor: String,
    /// Mixture estimate of the starting diversity from the fraction across, main placement:
    /// p (1 − p) Δ² + noise floor, Δ the field's step (sharp border only).
    mixture: Option<String>,
}

/// The averaged courses' section.
#[derive(Serialize)]
struct CourseSection {
    /// Smallest and largest y of the gradient run figure's centre.
    gradient_run_y: [String; 2],
    runs: u32,
    periods: u32,
    scenarios: Vec<CourseScenario>,
}

fn course_section(r: &Report<'_>) -> CourseSection {
    let tail_of = |c: &TimeCourse, f: fn(&crate::swarm::timecourse::TimePoint) -> f64| {
        let k = c.points.len().saturating_sub(10);
        let v: Vec<f64> = c.points[k..].iter().map(f).collect();
        crate::stats::mean(&v).unwrap_or(f64::NAN)
    };
    let tail = |c: &TimeCourse, f| fixed(tail_of(c, f), 2);
    let scenarios = [r.sharp, r.gradient]
        .iter()
        .zip(r.courses)
        .zip([paper_course(0), paper_course(1)])
        .enumerate()
        .map(|(k, ((scn, pair), paper))| {
            let noise = scn.run.noise;
            let floor = noise * noise / 12.0;
            let rows = pair
                .iter()
                .zip([r.main, r.main.other()])
                .map(|(c, placement)| {
                    let first = c.points.first();
                    CourseRow {
                        placement: placement.to_string(),
                        runs: c.runs,
                        start: first.map_or(String::new(), |p| fixed(p.diversity.mean, 2)),
                        start_range: first.map_or(String::new(), |p| {
                            format!(
                                "{}–{}",
                                fixed(p.diversity.q10, 2),
                                fixed(p.diversity.q90, 2)
                            )
                        }),
                        across: fixed(100.0 * c.across_at_start, 0),
                        end: tail(c, |p| p.diversity.mean),
                        consensus_start: first
                            .map_or(String::new(), |p| fixed(p.consensus.mean, 2)),
                        consensus_end: tail(c, |p| p.consensus.mean),
                        arrived: c.points.last().map_or(0, |p| p.arrived),
                        above_paper: first.is_some_and(|p| p.diversity.mean > paper.start),
                        mean_arrival: fixed(c.mean_arrival, 1),
                        y_at_arrival: fixed(c.y_at_arrival, 1),
                        straightness: fixed(100.0 * c.straightness, 0),
                        consensus_falls: first
                            .is_some_and(|p| tail_of(c, |p| p.consensus.mean) < p.consensus.mean),
                    }
                })
                .collect();
            let main = &pair[0];
            let p = main.across_at_start;
            CourseScenario {
                name: scn.name.clone(),
                x_start: scn.start.x.to_string(),
                paper_start: paper.start.to_string(),
                paper_plateaus: paper
                    .plateaus
                    .iter()
                    .map(|(v, what)| format!("≈ {v} ({what})"))
                    .collect::<Vec<_>>()
                    .join(", "),
                rows,
                plateau: format!("{:.1} ± {:.1}", main.plateau, main.plateau_se),
                plateau_runs: main.plateau_runs,
                noise_floor: fixed(floor, 2),
                mixture: (k == 0).then(|| {
                    let step = scn.field.mean(Point2::new(10.0, 0.0))
                        - scn.field.mean(Point2::new(-10.0, 0.0));
                    fixed(p * (1.0 - p) * step * step + floor, 2)
                }),
            }
        })
        .collect();
    let ys: Vec<f64> = r.runs[1]
        .1
        .periods
        .iter()
        .map(|p| p.to.y)
        .chain(std::iter::once(r.runs[1].1.start.y))
        .collect();
    let (lo, hi) = ys
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &y| (a.min(y), b.max(y)));
    CourseSection {
        gradient_run_y: [fixed(lo, 1), fixed(hi, 1)],
        runs: COURSE_RUNS,
        periods: r.sharp.periods,
        scenarios,
    }
}

/// The page's data, every number formatted.
fn page<'a>(r: &Report<'a>) -> Result<Page<'a>, Error> {
    Ok(Page {
        seed: r.seed,
        wall_s: fixed(r.wall_s, 0),
        threads: r.threads,
        setup: setup(r),
        comparison: comparison(r),
        sharp: sharp_section(r),
        gradient: gradient_section(r),
        cloud: cloud_section(r),
        caption_cloud: caption_cloud::section(r.caption_cloud, r.profile)?,
        cycle: cycle_section(r),
        course: course_section(r),
        sensitivity: r.sensitivity,
        shapes: r.shapes,
        beyond: r.beyond,
        speed: speed_section(r),
        waves: r.waves.clone(),
        names: [r.sharp, r.gradient, r.cloud].map(|s| s.name.clone()),
        placement: placement_note(r),
    })
}

/// `docs/reproduction.md`, rendered from `templates/reproduction.md.j2`.
fn markdown(r: &Report<'_>) -> Result<String, Error> {
    Ok(crate::report::page::render("reproduction.md.j2", page(r)?)?)
}
