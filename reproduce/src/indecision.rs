//! Indecision points against the swarm's size (the paper's discussion, §5: "the chances of
//! reaching an indecision point, when two aMussels decide to move left and two aMussels decide
//! to move right … decrease with increasing number of members of a swarm"). Swarms of
//! [`SIZES`] agents, placed as the sharp scenario places its swarm at the same density, start
//! centred on the sharp border, as the lab's pattern with the border in the middle; one
//! negotiation period each; a run is an indecision point when as many agents decide left as
//! right ([`swarm_sim::probe::Split::tied`]).

use nalgebra::Point2;

use crate::Error;
use crate::stage::Stage;
use crate::stages::INDECISION;
use crate::units::{Side, placement};
use swarm_sim::probe::{Split, splits};
use swarm_sim::scenario::Placement;

/// Swarm sizes: the lab's four robots, doubled past the paper's 61 agents to 256, as the
/// paper's "sufficiently large swarm" (even sizes, so that a tie is possible).
pub const SIZES: [usize; 7] = [4, 8, 16, 32, 64, 128, 256];
/// One-period runs per size and placement.
pub const RUNS: u32 = 200;

/// The runs of `side`'s placement (the page's is `main`), sizes in order.
///
/// # Errors
/// If a run fails.
pub fn runs(st: &mut Stage<'_>, main: Placement, side: Side) -> Result<Vec<Split>, Error> {
    let placement = placement(main, side);
    let scn = crate::builtin_placed("sharp", placement)?;
    let p = st.start(
        &format!("indecision against the swarm's size, {placement}"),
        SIZES.len() as u64 * u64::from(RUNS),
    );
    let seed = st.seed(INDECISION.at(side.index()));
    let runs = splits(&scn, &SIZES, Point2::origin(), RUNS, seed, &p)?;
    st.done(&p);
    Ok(runs)
}
