//! `cimax swarm reproduce`: every experiment of the paper's section 3, its figures and CSV
//! files, and `docs/reproduction.md` (rendered from `templates/reproduction.md.j2`) with the
//! paper's numbers beside ours.
//!
//! The second of two phases: the `reproduce` crate runs every unit of the page
//! ([`reproduce::compute()`], writing nothing), and [`write`](fn@write) writes every file from
//! the [`Results`] of all units, running nothing. A unit's result goes through JSON
//! (`serde_json`) and back bit for bit, so results computed elsewhere (shards) write the very
//! same files.

use std::path::{Path, PathBuf};

use nalgebra::Point2;
use serde::Serialize;

use crate::csv::CycleRow;
use crate::marks;
use report::csv_files::{fixed, opt};
use report::plot::{self, Line};
use reproduce::{
    COURSE_RUNS, CYCLE_RUNS, CYCLE_XS, PROFILE_RUNS, RUN_TRIES, Results, builtin_placed, results,
    units,
};
use swarm_sim::experiment::{self, Arrow, Error, RadialPoint, RunOutput, SweepPoint};
use swarm_sim::geometry::{Swarm, lattice};
use swarm_sim::scenario::{DEFAULT_PLACEMENT, LATTICE_SPACING, Placement, Scenario};
use swarm_sim::sensitivity::Knob;
use swarm_sim::timecourse::TimeCourse;

mod beyond;
mod caption_cloud;
mod page;
mod sensitivity;
mod settings;
mod settle;
mod verdicts;
mod write;

use page::{Report, markdown};
use sensitivity::SensitivitySection;

pub use write::write;

/// Where `swarm reproduce` writes, and what its runs were ([`reproduce::Options`]).
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

impl Options {
    /// What the runs depend on: the seed, the placement, and whether to draw progress bars.
    pub fn runs(&self) -> reproduce::Options {
        reproduce::Options {
            seed: self.seed,
            quiet: self.quiet,
            placement: self.placement,
        }
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
    swarm_sim::stats::crossing(&inward_points(profile), threshold, false)
}

/// Distance up to which a swarm inside the cloud heads out toward its border: where the mean
/// inward alignment first turns from negative to positive going out, interpolated, with its
/// standard error.
fn outward_limit(profile: &[RadialPoint]) -> Option<(f64, f64)> {
    swarm_sim::stats::crossing(&inward_points(profile), 0.0, true)
}

/// Why the page cannot be written from its results (besides a run's or a file's own error).
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// Units without a result.
    #[error("{count} units have no result, the first {first}")]
    Missing {
        /// How many.
        count: usize,
        /// The first, in the order of the units.
        first: reproduce::Unit,
    },
    /// The tapped runs are not the averaged course's runs (they must be the same).
    #[error("{scenario}: the tapped runs' plateau {tapped} is not the course's {course}")]
    NotTheCourses {
        /// The scenario.
        scenario: String,
        /// The tapped runs' plateau.
        tapped: f64,
        /// The course's.
        course: f64,
    },
    /// A built-in scenario drawn as a map has no grid.
    #[error("built-in scenario without grid")]
    NoGrid,
    /// The caption's cloud has no edge to mark.
    #[error("the caption's cloud has no edge")]
    NoEdge,
    /// The plateau's rows lack the page's own cycle and placement.
    #[error("the page's own cycle is not among the plateau's")]
    NoOwnCycle,
}

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

/// The paper's Figs. 5b and 8b: the diversity at the start and the plateau(s).
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

#[cfg(test)]
mod tests;
#[cfg(test)]
mod typed_code;
