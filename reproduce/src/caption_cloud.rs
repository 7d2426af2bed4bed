//! The cloud of Fig. 11's caption (`cloud-caption`: radius 5, X rising linearly from 0 at the
//! centre to 5 at the edge, noise in [0, 1)): its direction map and radial profile, run with
//! the page's placement.

use nalgebra::Point2;

use crate::Error;
use crate::stage::Stage;
use crate::stages::{CAPTION_MAP, CAPTION_PROFILE, PROFILES_OTHER};
use crate::units::{Side, placement};
use crate::{CLOUD_REFINED, PROFILE_RUNS, builtin_placed, by_distance, refined};
use swarm_sim::experiment::{Arrow, RadialPoint, direction_map, radial_profile};
use swarm_sim::scenario::Placement;

/// The distances of the radial profile, as for the text's cloud: 0 to 12 R in steps of 0.5,
/// refined to 0.25 around the claimed edges.
pub fn distances() -> Vec<f64> {
    refined(
        (0..=24).map(|k| 0.5 * f64::from(k)).collect(),
        &CLOUD_REFINED,
    )
}

/// The caption's cloud's direction map with the `main` placement.
///
/// # Errors
/// If a run fails.
pub fn map(st: &mut Stage<'_>, main: Placement) -> Result<Vec<Arrow>, Error> {
    let scn = builtin_placed("cloud-caption", main)?;
    let grid = scn.grid.as_ref().ok_or(Error::ScenarioWithout("grid"))?;
    let p = st.start(
        &format!("{} field", scn.name),
        (grid.xs.len() * grid.ys.len()) as u64,
    );
    let arrows = direction_map(&scn, grid, st.seed(CAPTION_MAP.at(0)), &p)?;
    st.done(&p);
    Ok(arrows)
}

/// The caption's cloud's radial profile with `side`'s placement (the page's is `main`), by
/// increasing distance.
///
/// # Errors
/// If a run fails.
pub fn profile(st: &mut Stage<'_>, main: Placement, side: Side) -> Result<Vec<RadialPoint>, Error> {
    let scn = builtin_placed("cloud-caption", placement(main, side))?;
    let seed = match side {
        Side::Main => CAPTION_PROFILE.at(0),
        Side::Other => PROFILES_OTHER.at(1),
    };
    let distances = distances();
    let p = st.start(
        &format!(
            "cloud-caption radial profile, {} placement",
            placement(main, side)
        ),
        distances.len() as u64 * u64::from(PROFILE_RUNS),
    );
    let profile = radial_profile(
        &scn,
        scn.run,
        Point2::origin(),
        &distances,
        PROFILE_RUNS,
        st.seed(seed),
        &p,
    )?;
    let profile = by_distance(profile);
    st.done(&p);
    Ok(profile)
}
