//! Steeper ramps, faster arrival: the time to the criterion and to a common line per slope.

use nalgebra::Point2;
use rayon::prelude::*;

use crate::Error;
use crate::results::Times;
use crate::stage::Stage;
use crate::stages::{STEEP, STEEP_OTHER};
use crate::units::{Side, placement};
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::seeds::derive;
use swarm_sim::sensitivity::Knob;

/// Slopes of the ramp, per R (the page's 2.5 among them).
pub const SLOPES: [f64; 5] = [1.0, 2.5, 5.0, 10.0, 20.0];
/// Runs per slope.
pub const RUNS: u32 = 50;
/// The common line: within this of x = 0 (the sharp border's criterion).
pub const NEAR: f64 = 0.33;

/// The slope of case `k`: none for the sharp border (0), then [`SLOPES`].
pub fn slope_of(k: usize) -> Result<Option<f64>, Error> {
    match k {
        0 => Ok(None),
        _ => Ok(Some(*SLOPES.get(k - 1).ok_or(Error::NoSuch {
            what: "steepness case",
            index: k,
        })?)),
    }
}

/// The label of the case with `slope` (none: the sharp border).
pub fn label(sharp: &Scenario, slope: Option<f64>) -> String {
    match slope {
        None => format!("{} border", sharp.name),
        Some(s) => format!("ramp of slope {s}"),
    }
}

/// Runs case `k` (0 the sharp border, then each slope of [`SLOPES`]) from the page's start,
/// with `side`'s placement (`scns` are placed by `main`): [`RUNS`] runs, or with the other
/// placement [`OTHER_RUNS`](crate::OTHER_RUNS), as the sweeps.
///
/// # Errors
/// If `k` is no case or a run fails.
pub fn case(
    st: &mut Stage<'_>,
    k: usize,
    main: Placement,
    side: Side,
    scns: [&Scenario; 2],
) -> Result<Vec<Times>, Error> {
    let (sharp, gradient) = (
        crate::on_side(scns[0], main, side)?,
        crate::on_side(scns[1], main, side)?,
    );
    let (sharp, gradient) = (&*sharp, &*gradient);
    let (runs_n, seed) = match side {
        Side::Main => (RUNS, st.seed(STEEP.at(k))),
        Side::Other => (crate::OTHER_RUNS, st.seed(STEEP_OTHER.at(k))),
    };
    let slope = slope_of(k)?;
    let scn = match slope {
        None => sharp.clone(),
        Some(s) => Knob::Slope(s).apply(gradient)?,
    };
    let p = st.start(
        &format!(
            "steepness: {}, {} placement",
            label(sharp, slope),
            placement(main, side)
        ),
        u64::from(runs_n),
    );
    let runs = (0..runs_n)
        .into_par_iter()
        .map(|r| {
            let start = Point2::new(gradient.start.x, 0.0);
            let s = derive(seed, &[u64::from(r)]);
            let out = swarm_sim::experiment::run_moves(&scn, scn.run, start, scn.periods, s, true)?;
            p.inc();
            let near = out.periods.iter().find(|q| q.to.x > -NEAR).map(|q| q.index);
            Ok((out.success_at, near))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    st.done(&p);
    Ok(runs)
}
