//! The sensor model the paper leaves open: one sample per activation (ours) or one per agent
//! and negotiation period ([`Sensor::PerPeriod`]), the averaged courses run again with the
//! same seeds.

use crate::Error;
use crate::results::Levels;
use crate::stage::Stage;
use swarm_sim::probe::{Tapped, plateaus, tapped_runs};
use swarm_sim::scenario::Scenario;
use swarm_sim::sim::Sensor;
use swarm_sim::stats;

/// The levels of a set of runs.
pub fn levels(runs: &[Tapped]) -> Levels {
    let start: Vec<f64> = runs
        .iter()
        .filter_map(|t| t.out.periods.first().map(|p| p.diversity))
        .collect();
    let arrival: Vec<f64> = runs
        .iter()
        .filter_map(|t| t.out.success_at.map(f64::from))
        .collect();
    let p = plateaus(runs, crate::PLATEAU_MIN_AFTER).agents;
    let spread = |v: &[f64]| {
        (
            stats::mean(v).unwrap_or(f64::NAN),
            stats::standard_error(v).unwrap_or(f64::NAN),
        )
    };
    Levels {
        start: spread(&start),
        arrival: spread(&arrival),
        plateau: (p.mean, p.se),
        arrived: arrival.len(),
        runs: runs.len(),
    }
}

/// Runs `scn`'s averaged course again with one sample per period (its seed `seed`, the
/// course's); their levels.
///
/// # Errors
/// If a run fails.
pub fn per_period(st: &mut Stage<'_>, scn: &Scenario, seed: u64) -> Result<Levels, Error> {
    let runs = crate::COURSE_RUNS;
    let p = st.start(
        &format!("{}: the courses, one reading per period", scn.name),
        u64::from(runs),
    );
    let cfg = swarm_sim::sim::RunConfig {
        sensor: Sensor::PerPeriod,
        ..scn.run
    };
    let held = tapped_runs(scn, cfg, scn.start.x, scn.periods, runs, seed, &p)?;
    st.done(&p);
    Ok(levels(&held))
}
