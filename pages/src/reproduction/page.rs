//! The page of `swarm reproduce`: every result of the run ([`Report`]) becomes the view model
//! the templates render (`templates/reproduction.md.j2` and its partials), every number formatted
//! here.

use super::*;
use reproduce::PLACEMENTS;
use reproduce::results::PlacementStats;

pub(super) struct Report<'a> {
    pub(super) placement: PlacementStats,
    pub(super) speed: &'a [experiment::BenchResult],
    /// This run's wall seconds per run of the NumPy peer's work.
    pub(super) peer_work_s: f64,
    pub(super) seed: u64,
    pub(super) wall_s: f64,
    pub(super) threads: usize,
    pub(super) sharp: &'a Scenario,
    pub(super) gradient: &'a Scenario,
    pub(super) cloud: &'a Scenario,
    pub(super) runs: &'a [(u64, RunOutput)],
    pub(super) sweeps: &'a [Vec<SweepPoint>],
    /// The placement of every experiment.
    pub(super) main: Placement,
    /// Sweeps with the other placement.
    pub(super) other_sweeps: &'a [Vec<SweepPoint>],
    pub(super) maps: &'a [Vec<Arrow>],
    /// The direction maps with the other placement.
    pub(super) other_maps: &'a [Vec<Arrow>],
    pub(super) profile: &'a [RadialPoint],
    /// The text's cloud's profile with the other placement.
    pub(super) other_profile: &'a [RadialPoint],
    pub(super) profile_runs: u32,
    /// The cloud of Fig. 11's caption.
    pub(super) caption_cloud: &'a caption_cloud::CaptionCloud,
    pub(super) plateaus: &'a [(f64, f64, usize)],
    pub(super) plateau_runs: u32,
    /// Per scenario, the averaged course of the main placement and of the other.
    pub(super) courses: &'a [[TimeCourse; 2]],
    pub(super) sensitivity: &'a SensitivitySection,
    /// The discussion's line and cross on a random field.
    pub(super) shapes: &'a reproduce::shapes::ShapesSection,
    /// Entropy instead of variance (beyond the paper).
    pub(super) beyond: &'a beyond::BeyondSection,
    /// The experiments that settle the open rows.
    pub(super) settled: &'a settle::Settled,
    pub(super) cycle_rows: &'a [CycleRow],
    pub(super) cycle_runs: u32,
    pub(super) waves: crate::waves::WavesSection,
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
    shapes: &'a reproduce::shapes::ShapesSection,
    beyond: &'a beyond::BeyondSection,
    settle: &'a settle::SettleSection,
    speed: SpeedSection,
    waves: crate::waves::WavesSection,
    names: [String; 3],
    placement: PlacementNote,
    settings: super::settings::Settings,
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
    /// Waves an agent takes part in per cycle at the page's cycle (the cycle-length
    /// experiment), and the share of its cycle it is then busy (active or refractory: the relay
    /// delay and the refractory time per wave), which is the share of its initiations that
    /// fall while it is busy and are skipped.
    heard: String,
    busy_pct: String,
    /// The share of agent-cycles without an initiation, measured at the page's cycle.
    skipped_pct: String,
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
    /// The paper's runs per point of its sweeps.
    paper_runs: u32,
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
pub(super) fn reach(scn: &Scenario) -> [String; 3] {
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
    /// The NumPy peer's work: runs, our milliseconds per run, the peer's, and the ratio.
    peer_runs: u32,
    peer_ours_ms: String,
    peer_ms: String,
    peer_ratio: String,
    /// When and where the peer's time was measured.
    peer_measured: &'static str,
}

/// The NumPy peer's time per run of its work (`scripts/numpy_peer.py --runs 100`, one thread),
/// milliseconds: measured, not computed, so it is stated with [`PEER_MEASURED`]. The page sets
/// this run's time of the same work beside it (`reproduce`'s peer-work unit).
const PEER_MS: f64 = 38.9;

/// Where [`PEER_MS`] was measured.
const PEER_MEASURED: &str =
    "numpy 2.4.6, Python 3.11.7, one thread, on a 2-core Xeon VM, 2026-11-28";

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

/// Success rates in the sharp border's band |x| ≤ [`SHARP_NEAR`](super::settings::SHARP_NEAR).
fn sharp_near(points: &[SweepPoint]) -> (f64, f64) {
    rate_range(points, |x| x.abs() <= super::settings::SHARP_NEAR + 1e-9)
}

/// Success rates in the gradient's band of its claim `GradientMid` (−2 ≤ x < 2.33).
fn gradient_mid(points: &[SweepPoint]) -> [String; 2] {
    let c = crate::claims::claim(crate::claims::Id::GradientMid);
    let (lo, hi) = rate_range(points, |x| c.covers(x));
    [pct(lo), pct(hi)]
}

/// Success rate at the x of the claim `GradientFar` (−4), `–` if not swept.
fn at_m4(points: &[SweepPoint]) -> String {
    let x = crate::claims::claim(crate::claims::Id::GradientFar)
        .over
        .map_or(f64::NAN, |o| o.0);
    rate_at(points, x).map_or("–".into(), pct)
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
    let (cycle_s, relay_s, refractory_s) = (
        p.wave.cycle.as_millis() / 1000,
        p.wave.relay_delay.as_millis() / 1000,
        p.wave.refractory.as_millis() / 1000,
    );
    let row = r.cycle_rows.iter().find(|row| row.cycle_s == cycle_s);
    let heard = row.map_or(f64::NAN, |row| row.waves_heard);
    let skipped = row.map_or(f64::NAN, |row| 1.0 - row.initiating_share());
    let busy = heard * (relay_s + refractory_s) as f64 / cycle_s.max(1) as f64;
    Setup {
        heard: fixed(heard, 0),
        busy_pct: pct(busy),
        skipped_pct: pct(skipped),
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
        cycle_s,
        relay_s,
        refractory_s,
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
        paper_runs: crate::verdict::PAPER_RUNS,
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
            Some(swarm_sim::scenario::Success::BeyondX { x }) => x.to_string(),
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
            let mut cells = vec![
                row.cycle_s.to_string(),
                fixed(row.waves_heard, 1),
                pct(row.initiating_share()),
            ];
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
        peer_runs: reproduce::compute::PEER_RUNS,
        peer_ours_ms: fixed(1e3 * r.peer_work_s, 2),
        peer_ms: fixed(PEER_MS, 1),
        peer_ratio: fixed(PEER_MS / (1e3 * r.peer_work_s), 0),
        peer_measured: PEER_MEASURED,
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
    /// The paper's periods until its single run arrives, and whether ours (main placement)
    /// take longer on average.
    paper_arrival: String,
    slower: bool,
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
    /// The plateau counts runs that arrived at least this many periods before the end.
    min_after: u32,
    periods: u32,
    scenarios: Vec<CourseScenario>,
    /// The time of a course's first value: the swarm at its start.
    t0: u32,
    /// The sharp plateau against the cycle length, main placement (the settling section):
    /// its lowest and highest, with their cycles.
    plateau_by_cycle: [String; 2],
}

/// The mean of `f` over a course's last [`TAIL`](super::settings::TAIL) periods.
fn tail_of(c: &TimeCourse, f: fn(&swarm_sim::timecourse::TimePoint) -> f64) -> f64 {
    let k = c.points.len().saturating_sub(super::settings::TAIL);
    let v: Vec<f64> = c.points[k..].iter().map(f).collect();
    swarm_sim::stats::mean(&v).unwrap_or(f64::NAN)
}

/// One placement's row of a scenario's averaged course.
fn course_row(c: &TimeCourse, placement: Placement, paper: &PaperCourse) -> CourseRow {
    let tail = |c: &TimeCourse, f| fixed(tail_of(c, f), 2);
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
        consensus_start: first.map_or(String::new(), |p| fixed(p.consensus.mean, 2)),
        consensus_end: tail(c, |p| p.consensus.mean),
        arrived: c.points.last().map_or(0, |p| p.arrived),
        above_paper: first.is_some_and(|p| p.diversity.mean > paper.start),
        mean_arrival: fixed(c.mean_arrival, 1),
        y_at_arrival: fixed(c.y_at_arrival, 1),
        straightness: fixed(100.0 * c.straightness, 0),
        consensus_falls: first.is_some_and(|p| tail_of(c, |p| p.consensus.mean) < p.consensus.mean),
    }
}

/// One scenario's averaged courses (`k`: 0 sharp, 1 gradient), both placements.
fn course_scenario(
    r: &Report<'_>,
    k: usize,
    scn: &Scenario,
    pair: &[TimeCourse; 2],
) -> CourseScenario {
    let paper = paper_course(k);
    let floor = scn.run.noise * scn.run.noise / 12.0;
    let rows = pair
        .iter()
        .zip([r.main, r.main.other()])
        .map(|(c, placement)| course_row(c, placement, &paper))
        .collect();
    let main = &pair[0];
    let p = main.across_at_start;
    let paper_arrival = {
        use crate::claims::{Id, Value, claim};
        match claim([Id::SharpArrival, Id::GradientArrival][k.min(1)]).value {
            Value::At(v) => v,
            _ => f64::NAN,
        }
    };
    CourseScenario {
        paper_arrival: paper_arrival.to_string(),
        slower: main.mean_arrival > paper_arrival,
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
            let step =
                scn.field.mean(Point2::new(10.0, 0.0)) - scn.field.mean(Point2::new(-10.0, 0.0));
            fixed(p * (1.0 - p) * step * step + floor, 2)
        }),
    }
}

fn course_section(r: &Report<'_>) -> CourseSection {
    let scenarios = [r.sharp, r.gradient]
        .iter()
        .zip(r.courses)
        .enumerate()
        .map(|(k, (scn, pair))| course_scenario(r, k, scn, pair))
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
    let main_cycles: Vec<(u64, f64)> = r
        .settled
        .plateau
        .by_cycle
        .iter()
        .filter(|c| c.1 == r.main)
        .map(|c| (c.0, c.2))
        .collect();
    let at = |c: Option<&(u64, f64)>| {
        c.map_or("n/a".into(), |c| format!("{} at {} s", fixed(c.1, 2), c.0))
    };
    CourseSection {
        plateau_by_cycle: [at(main_cycles.first()), at(main_cycles.last())],
        gradient_run_y: [fixed(lo, 1), fixed(hi, 1)],
        runs: COURSE_RUNS,
        min_after: reproduce::PLATEAU_MIN_AFTER,
        periods: r.sharp.periods,
        t0: r.courses[0][0].points.first().map_or(0, |p| p.t),
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
        settle: &r.settled.section,
        speed: speed_section(r),
        waves: r.waves.clone(),
        names: [r.sharp, r.gradient, r.cloud].map(|s| s.name.clone()),
        placement: placement_note(r),
        settings: super::settings::settings([r.sharp, r.gradient, r.cloud], r.main)?,
    })
}

/// `docs/reproduction.md`, rendered from `templates/reproduction.md.j2`.
/// The page, and its view model as JSON with what varies from run to run (wall time, threads,
/// the speed section) blanked: the data `templates_fill_every_number_from_data` renders.
pub(super) fn markdown(r: &Report<'_>) -> Result<(String, serde_json::Value), Error> {
    let p = page(r)?;
    let md = crate::page::render("reproduction.md.j2", &p)?;
    let mut model = serde_json::to_value(&p)?;
    blank_timing(&mut model);
    Ok((md, model))
}

/// The view model's fields that vary from run to run, blanked (strings "…", numbers 0).
fn blank_timing(model: &mut serde_json::Value) {
    fn blank(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::String(s) => *s = "…".into(),
            serde_json::Value::Number(_) => *v = 0.into(),
            serde_json::Value::Array(xs) => xs.iter_mut().for_each(blank),
            serde_json::Value::Object(m) => m.values_mut().for_each(blank),
            _ => {}
        }
    }
    for key in ["wall_s", "threads", "speed"] {
        if let Some(v) = model.get_mut(key) {
            blank(v);
        }
    }
}
