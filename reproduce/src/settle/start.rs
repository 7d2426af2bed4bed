//! The starting diversity against the agents across x = 0.

use crate::Error;
use crate::stage::Stage;
use crate::stages::START;
use swarm_sim::probe::{StartRun, start_diversity};
use swarm_sim::scenario::{Placement, Scenario};

/// Starts around the page's x = −2.5, so that the agents across vary.
pub const XS: [f64; 7] = [-3.25, -3.0, -2.75, -2.5, -2.25, -2.0, -1.75];
/// One-period runs per start, field and placement.
pub const RUNS: u32 = 20;

/// Runs one period from each start of [`XS`] for field `k` (`scn`) with `placement`, the
/// main one (`j` 0) or the other (1).
///
/// # Errors
/// If a run fails.
pub fn runs(
    st: &mut Stage<'_>,
    placement: Placement,
    k: usize,
    j: usize,
    scn: &Scenario,
) -> Result<Vec<StartRun>, Error> {
    let placed = crate::builtin_placed(&scn.name, placement)?;
    let p = st.start(
        &format!("{}: starting diversity, {placement}", scn.name),
        XS.len() as u64 * u64::from(RUNS),
    );
    let seed = st.seed(START.at2(k, j));
    let runs = start_diversity(&placed, &XS, RUNS, seed, &p)?;
    st.done(&p);
    Ok(runs)
}
