//! Where the gradient's runs spend their periods before arriving: the first move's heading
//! from every step of the way, and the way of the averaged courses' runs.

use crate::Error;
use crate::results::Way;
use crate::stage::Stage;
use crate::stages::HEADING;
use swarm_sim::experiment::RunOutput;
use swarm_sim::probe::periods_per_bin;
use swarm_sim::scenario::{Scenario, Success};
use swarm_sim::sensitivity::heading_against_x;

/// Step of the heading profile and of the bins, R.
pub const STEP: f64 = 0.25;
/// One-period runs per point of the heading profile.
pub const RUNS: u32 = 30;
/// The starts from `scn`'s start to its line, every [`STEP`].
pub fn way_xs(scn: &Scenario) -> Vec<f64> {
    let end = scn
        .success
        .as_ref()
        .map_or(0.0, |s| success_x(s, scn.start.x));
    steps(scn.start.x, end)
}

/// Where the runs `outs` of `scn` spent their periods, per step of [`way_xs`], and when they
/// arrived.
pub fn way(scn: &Scenario, outs: &[RunOutput]) -> Way {
    let n = way_xs(scn).len();
    let lo = scn.start.x - 0.5 * STEP;
    Way {
        spent: periods_per_bin(outs, lo, lo + STEP * n as f64, STEP),
        arrivals: outs
            .iter()
            .filter_map(|o| o.success_at.map(f64::from))
            .collect(),
    }
}

/// The first move's heading from every step of the way of field `k` (`scn`).
///
/// # Errors
/// If a run fails.
pub fn heading(
    st: &mut Stage<'_>,
    k: usize,
    scn: &Scenario,
) -> Result<Vec<(f64, f64, f64)>, Error> {
    let xs = way_xs(scn);
    let p = st.start(
        &format!("{}: heading along the way", scn.name),
        xs.len() as u64 * u64::from(RUNS),
    );
    let heading = heading_against_x(scn, &xs, RUNS, st.seed(HEADING.at(k)), &p)?;
    st.done(&p);
    Ok(heading)
}

/// The x at which a swarm coming from `from` (left of the line) meets the criterion.
pub fn success_x(s: &Success, from: f64) -> f64 {
    match *s {
        Success::NearX { x, within } if from < x => x - within,
        Success::NearX { x, within } => x + within,
        Success::BeyondX { x } => x,
    }
}

/// `from`, `from + STEP`, … up to below `to`.
pub fn steps(from: f64, to: f64) -> Vec<f64> {
    let n = ((to - from) / STEP).ceil().max(1.0) as usize;
    (0..n).map(|k| from + STEP * k as f64).collect()
}
