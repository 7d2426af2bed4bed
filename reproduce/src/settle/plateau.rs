//! The sharp plateau against the cycle and the placement.

use crate::Error;
use crate::stage::Stage;
use crate::stages::PLATEAU;
use crate::units::{Side, placement};
use swarm_sim::probe::{Plateaus, plateaus, tapped_runs};
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::sensitivity::Knob;

/// Cycle lengths t_p^max tried, seconds (the page's 1000 among them).
pub const CYCLES: [u64; 4] = [250, 500, 1000, 2000];
/// Runs per cycle and placement other than the courses' own (which has the courses' runs).
pub const RUNS: u32 = 20;

/// The sharp border's cycle, seconds.
pub fn default_cycle(sharp: &Scenario) -> u64 {
    sharp.run.params.wave.cycle.as_millis() / 1000
}

/// Runs the sharp plateau at cycle `k` of [`CYCLES`] with placement `side` (`sharp` is placed
/// by `main`); `None` for the page's own cycle with the main placement: the courses' runs stand
/// for it.
///
/// # Errors
/// If `k` is no cycle or a run fails.
pub fn one(
    st: &mut Stage<'_>,
    main: Placement,
    side: Side,
    k: usize,
    sharp: &Scenario,
) -> Result<Option<Plateaus>, Error> {
    let cycle_s = *CYCLES.get(k).ok_or(Error::NoSuch {
        what: "plateau cycle",
        index: k,
    })?;
    let placement = placement(main, side);
    if placement == main && cycle_s == default_cycle(sharp) {
        return Ok(None);
    }
    let placed = crate::builtin_placed(&sharp.name, placement)?;
    let scn = Knob::Cycle(cycle_s).apply(&placed)?;
    let seed = st.seed(PLATEAU.at2(side.index(), k));
    let pr = st.start(
        &format!("sharp plateau, {placement}, cycle {cycle_s} s"),
        u64::from(RUNS),
    );
    let t = tapped_runs(&scn, scn.run, scn.start.x, scn.periods, RUNS, seed, &pr)?;
    st.done(&pr);
    Ok(Some(plateaus(&t, crate::PLATEAU_MIN_AFTER)))
}
