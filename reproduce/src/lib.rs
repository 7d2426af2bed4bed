//! # reproduce: the experiments of `docs/reproduction.md`, run and nothing written
//!
//! The layer between the simulator (`swarm-sim`) and the pages (`pages`): every experiment
//! of the reproduction, from its set-up to its result type, and nothing that writes a file.
//!
//! - [`units`](mod@units): the units of work, one per stage, in the fixed order of [`UNITS`];
//! - [`stages`]: the seed stages, one named block of offsets per experiment;
//! - [`compute`](fn@compute): one unit's runs, from the [`Options`] alone, with its log lines
//!   and progress bar;
//! - [`results`]: what a unit measured ([`UnitResult`]) and the set of them ([`Results`]) the
//!   page is written from (`pages::reproduction::write`); a [`UnitResult`] goes through JSON
//!   bit for bit, so shards computed elsewhere merge into the same page;
//! - the experiments that are more than one call to the simulator, each in its own file:
//!   [`settle`] (the rows the comparison cannot settle by itself), [`caption_cloud`],
//!   [`sensitivity`], [`beyond`] (beyond the paper) and [`shapes`] (section 5).

use swarm_sim::experiment::RadialPoint;
use swarm_sim::scenario::{Placement, Scenario};

pub mod beyond;
pub mod caption_cloud;
pub mod compute;
pub mod error;
pub mod indecision;
pub mod results;
pub mod sensitivity;
pub mod settle;
pub mod shapes;
pub mod stage;
pub mod stages;
pub mod units;

pub use compute::compute;
pub use error::Error;
pub use results::{Results, UnitResult};
pub use units::{Field, Scene, Side, UNITS, Unit, placement, units};

/// What the runs of `swarm reproduce` depend on.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Base seed; every stage derives its own ([`stages`]).
    pub seed: u64,
    /// No progress bars.
    pub quiet: bool,
    /// The placement of every experiment of the page; the sweeps are also run with the other
    /// placement, as a check of robustness.
    pub placement: Placement,
}

/// Runs tried for each run figure (the first successful one is shown).
pub const RUN_TRIES: u64 = 20;

/// Cycle lengths of the cycle-length experiment, seconds.
pub const CYCLES: [u64; 7] = [100, 200, 300, 500, 1000, 2000, 5000];
/// Initial positions of the cycle-length experiment.
pub const CYCLE_XS: [f64; 2] = [-2.0, -1.0];
/// Runs per point of the cycle-length experiment.
pub const CYCLE_RUNS: u32 = 50;

/// Runs per distance of the cloud's radial profile.
pub const PROFILE_RUNS: u32 = 40;
/// Runs per point of the other placement's sweeps (the robustness check; the main placement
/// runs the scenario's 50, as the paper did).
pub const OTHER_RUNS: u32 = 20;
/// Runs per scenario and placement of the averaged courses (Figs. 5b, 8b) and the plateaus.
pub const COURSE_RUNS: u32 = 50;
/// The averaged courses' plateau counts the runs that arrived at least this many periods
/// before the end.
pub const PLATEAU_MIN_AFTER: u32 = 10;
/// Placements measured for [`results::PlacementStats`].
pub const PLACEMENTS: u64 = 200;

/// Where the cloud profiles are refined to 0.25 R: around the claimed edges d = 4 (heading
/// out inside) and d = 7, 7.5 (random beyond).
pub const CLOUD_REFINED: [f64; 9] = [3.25, 3.75, 4.25, 4.75, 6.25, 6.75, 7.25, 7.75, 8.25];

/// The built-in scenario `name`.
///
/// # Errors
/// If there is none of that name.
pub fn builtin(name: &str) -> Result<Scenario, Error> {
    Scenario::builtin(name).ok_or_else(|| Error::NoScenario(name.to_owned()))
}

/// A built-in scenario with its agents placed by `placement`.
///
/// # Errors
/// If there is none of that name, or its agents cannot be placed.
pub fn builtin_placed(name: &str, placement: Placement) -> Result<Scenario, Error> {
    Ok(builtin(name)?.placed(placement)?)
}

/// Scenario `scn` (placed by the page's placement `main`) as `side` runs it: itself, or the
/// built-in scenario of its name placed by the other placement.
///
/// # Errors
/// If the other placement cannot be had (see [`builtin_placed`]).
pub fn on_side(
    scn: &Scenario,
    main: Placement,
    side: Side,
) -> Result<std::borrow::Cow<'_, Scenario>, Error> {
    Ok(match side {
        Side::Main => std::borrow::Cow::Borrowed(scn),
        Side::Other => std::borrow::Cow::Owned(builtin_placed(&scn.name, main.other())?),
    })
}

/// `grid` with the points `refined` added where they are new, by increasing value: a grid
/// refined where the paper claims an edge. The grid's own points keep their indices first, so
/// their seeds do not change.
pub fn refined(grid: Vec<f64>, refined: &[f64]) -> Vec<f64> {
    let mut all = grid;
    for &r in refined {
        if all.iter().all(|g| (g - r).abs() > 1e-9) {
            all.push(r);
        }
    }
    all
}

/// `profile` by increasing distance.
pub fn by_distance(mut profile: Vec<RadialPoint>) -> Vec<RadialPoint> {
    profile.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    profile
}
