//! After arrival: the mean squared displacement of the swarm's centre along x and y against
//! the lag, from the position at arrival on.

use swarm_sim::experiment::RunOutput;
use swarm_sim::probe::{Msd, msd_after_arrival};

/// The longest lag, periods.
pub const MAX_LAG: u32 = 20;
/// The walk after arrival of the runs `outs`: the mean squared displacements up to
/// [`MAX_LAG`].
pub fn msd(outs: &[RunOutput]) -> Vec<Msd> {
    msd_after_arrival(outs, MAX_LAG)
}
