//! The sensor model the paper leaves open: its noise is "time dependent" and it says no more.
//! Ours draws a fresh sample whenever an agent becomes active ([`Sensor::PerActivation`]); the
//! other reading, one sample per agent and negotiation period ([`Sensor::PerPeriod`]), runs the
//! averaged courses again with the same seeds, and the comparison's level rows (starting
//! diversity, arrival, plateau) are judged under both.

use std::path::Path;

use serde::Serialize;

use super::{pm, write_csv};
use reproduce::results::Levels;
use swarm_sim::experiment::Error;
use swarm_sim::scenario::Scenario;

/// Both fields under the other sensor model, as the comparison reads them.
pub(in super::super) struct SensorFacts {
    /// Per field (sharp, gradient), one sample per period.
    pub(in super::super) per_period: [Levels; 2],
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct SensorPart {
    runs: u32,
    /// Per field and quantity: field, quantity, per activation, per period.
    rows: Vec<[String; 4]>,
}

/// The part from both fields' levels per activation (`fresh`, the courses' runs) and per
/// period (`held`); writes `settle-sensor.csv`.
///
/// # Errors
/// If the file cannot be written.
pub(super) fn write(
    figs: &Path,
    scns: [&Scenario; 2],
    fresh: [&Levels; 2],
    held: [Levels; 2],
) -> Result<(SensorPart, SensorFacts), Error> {
    let mut rows = Vec::new();
    for ((scn, a), b) in scns.into_iter().zip(fresh).zip(&held) {
        let row = |what: &str, pick: fn(&Levels) -> (f64, f64), digits| {
            let (x, y) = (pick(a), pick(b));
            [
                scn.name.clone(),
                what.to_string(),
                pm(x.0, x.1, digits),
                pm(y.0, y.1, digits),
            ]
        };
        rows.push(row("diversity at t = 0", |l| l.start, 2));
        rows.push(row("periods until arrival", |l| l.arrival, 1));
        rows.push(row("diversity plateau", |l| l.plateau, 2));
        rows.push([
            scn.name.clone(),
            "runs that arrived".into(),
            format!("{} of {}", a.arrived, a.runs),
            format!("{} of {}", b.arrived, b.runs),
        ]);
    }
    write_csv(
        figs,
        "settle-sensor.csv",
        &["field", "quantity", "per_activation", "per_period"],
        &rows.iter().map(|r| r.to_vec()).collect::<Vec<_>>(),
    )?;
    Ok((
        SensorPart {
            runs: super::super::COURSE_RUNS,
            rows,
        },
        SensorFacts { per_period: held },
    ))
}
