//! `cimax swarm reproduce`: every experiment of the paper's section 3, its figures and CSV
//! files, and `docs/reproduction.md` (rendered from `templates/reproduction.md.j2`) with the
//! paper's numbers beside ours.
//!
//! In two phases, so that the work can be shared out and merged: [`compute`] runs one [`Unit`]
//! (a stage: its runs, with seeds derived from the base seed and the unit alone) and returns
//! its [`UnitResult`], writing nothing; [`write`](fn@write) writes every file from the [`Results`] of all
//! units, running nothing. [`reproduce`] does both, unit by unit in the order of [`units`]. A
//! [`UnitResult`] goes through JSON (`serde_json`) and back bit for bit, so results computed
//! elsewhere write the very same files.

use std::path::{Path, PathBuf};
use std::time::Instant as Clock;

use nalgebra::Point2;
use serde::Serialize;

use crate::csv::CycleRow;
use crate::marks;
use report::csv_files::{fixed, opt};
use report::plot::{self, Line};
use swarm_sim::experiment::{self, Arrow, Error, RadialPoint, RunOutput, SweepPoint};
use swarm_sim::geometry::{Swarm, lattice};
use swarm_sim::scenario::{DEFAULT_PLACEMENT, LATTICE_SPACING, Placement, Scenario};
use swarm_sim::sensitivity::{Knob, diversity_at, heading_against_x, success_against};
use swarm_sim::timecourse::TimeCourse;

mod beyond;
mod caption_cloud;
mod compute;
mod page;
mod results;
mod sensitivity;
mod settle;
mod stages;
mod units;
mod verdicts;
mod write;

use compute::Stage;
use page::{Report, markdown};
use sensitivity::SensitivitySection;

pub use compute::compute;
pub use results::{Results, UnitResult};
pub use units::{Field, Scene, Side, UNITS, Unit, units};
pub use write::write;

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
    swarm_sim::stats::crossing(&inward_points(profile), threshold, false)
}

/// Distance up to which a swarm inside the cloud heads out toward its border: where the mean
/// inward alignment first turns from negative to positive going out, interpolated, with its
/// standard error.
fn outward_limit(profile: &[RadialPoint]) -> Option<(f64, f64)> {
    swarm_sim::stats::crossing(&inward_points(profile), 0.0, true)
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

/// Runs every experiment ([`compute`], unit by unit in the order of [`units`]), then writes
/// the figures and CSV files into `docs/figures/` and regenerates `docs/reproduction.md`
/// ([`write`](fn@write)). `log` receives one line per stage.
///
/// # Errors
/// If a run fails or a file cannot be written.
pub fn reproduce(opts: &Options, log: &mut dyn FnMut(&str)) -> Result<Summary, Error> {
    let t0 = Clock::now();
    let mut results = Results::default();
    for &unit in units() {
        results.insert(compute(unit, opts, log)?)?;
    }
    let summary = write(&results, opts)?;
    Ok(Summary {
        wall_s: t0.elapsed().as_secs_f64(),
        ..summary
    })
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
/// Runs per point of the cycle-length experiment.
const CYCLE_RUNS: u32 = 50;

/// The paper's Figs. 4b and 7b: the diversity at the start and the plateau(s).
struct PaperCourse {
    start: f64,
    plateaus: Vec<(f64, &'static str)>,
}

/// The paper's course of the sharp border (k = 0) or the gradient, from the claims.
fn paper_course(k: usize) -> PaperCourse {
    use crate::claims::{Id, claim};
    let (start, plateau) = [
        (Id::SharpStart, Id::SharpPlateau),
        (Id::GradientStart, Id::GradientPlateau),
    ][k];
    PaperCourse {
        start: claim(start).values().first().map_or(f64::NAN, |v| v.0),
        plateaus: claim(plateau).values(),
    }
}

/// Placements measured for [`PlacementStats`].
const PLACEMENTS: u64 = 200;

#[cfg(test)]
mod tests;
