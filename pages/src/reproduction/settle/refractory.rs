//! The refractory state, off and on (§2: it "assures that a signal will neither 'flood' a
//! swarm … nor periodically propagate through the swarm"). The protocol refuses a refractory
//! time not above the relay delay (`ParamError::RefractoryNotAboveRelayDelay`), so below it
//! the wave is run by [`swarm_sim::probe::flood`], the simulator's delivery rule as a model;
//! where the protocol takes the time, the model's wave is checked to be the protocol's.

use std::path::Path;

use serde::Serialize;

use super::write_csv;
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::results::RefractoryRuns;
use reproduce::settle::refractory::HORIZON;
use swarm_sim::experiment::Error;

/// Seconds drawn in the figure.
const SHOWN: u64 = 40;

/// The refractory time off and on, as the comparison reads it.
pub(in super::super) struct Flooding {
    /// Without refractory time (the model, t_ref = 0): still transmitting at the horizon, and
    /// transmissions per agent until then.
    pub(in super::super) floods_without: bool,
    pub(in super::super) sends_without: f64,
    /// The smallest refractory time the protocol takes, and whether every agent then sent
    /// exactly once.
    pub(in super::super) smallest: Option<u64>,
    pub(in super::super) once_with: bool,
    /// The horizon, seconds.
    pub(in super::super) horizon: u64,
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct RefractoryPart {
    agents: usize,
    relay_s: u64,
    horizon: u64,
    /// Per refractory time: t_ref, the protocol's answer, transmissions per agent in the
    /// horizon, the last second with a transmission.
    rows: Vec<Vec<String>>,
    /// The smallest refractory time the protocol takes.
    smallest: Option<u64>,
}

/// The part from the runs; writes `settle-refractory.{csv,svg}`.
///
/// # Errors
/// If a file cannot be written.
pub(super) fn write(figs: &Path, r: &RefractoryRuns) -> Result<(RefractoryPart, Flooding), Error> {
    let (mut rows, mut lines, mut smallest) = (Vec::new(), Vec::new(), None);
    let mut flooding = Flooding {
        floods_without: false,
        sends_without: f64::NAN,
        smallest: None,
        once_with: false,
        horizon: HORIZON,
    };
    for run in &r.runs {
        let (refractory_s, sends) = (run.refractory_s, &run.sends);
        if let (None, Some(once)) = (smallest, run.once) {
            smallest = Some(refractory_s);
            flooding.smallest = Some(refractory_s);
            flooding.once_with = once;
        }
        let total: u32 = sends.iter().sum();
        let last = sends.iter().rposition(|&k| k > 0).unwrap_or(0);
        if refractory_s == 0 {
            flooding.floods_without = last as u64 == HORIZON;
            flooding.sends_without = f64::from(total) / r.agents as f64;
        }
        rows.push(vec![
            refractory_s.to_string(),
            run.answer.clone(),
            fixed(f64::from(total) / r.agents as f64, 2),
            if last as u64 == HORIZON {
                format!("{HORIZON} (still going)")
            } else {
                last.to_string()
            },
        ]);
        if [0, 1, 2, 10].contains(&refractory_s) {
            lines.push(Line {
                label: format!("t_ref = {refractory_s} s"),
                points: (0..=SHOWN)
                    .map(|t| (t as f64, f64::from(sends[t as usize]), 0.0))
                    .collect(),
            });
        }
    }
    write_files(figs, &rows, &lines, r.agents)?;
    let part = RefractoryPart {
        agents: r.agents,
        relay_s: r.relay_s,
        horizon: HORIZON,
        rows,
        smallest,
    };
    Ok((part, flooding))
}

/// Writes the table as CSV and the lines as the figure.
fn write_files(
    figs: &Path,
    rows: &[Vec<String>],
    lines: &[Line],
    agents: usize,
) -> Result<(), Error> {
    write_csv(
        figs,
        "settle-refractory.csv",
        &["refractory_s", "protocol", "sends_per_agent", "last_send_s"],
        rows,
    )?;
    plot::xy_figure(
        &figs.join("settle-refractory.svg"),
        &format!(
            "one initiation in the {agents} agents of {}: transmissions per second",
            crate::paper::Fig::Waves
        ),
        "t / s since the initiation",
        "agents transmitting",
        lines,
        (0.0, 1.1 * lines_top(lines)),
        &[],
        false,
    )?;
    Ok(())
}

fn lines_top(lines: &[Line]) -> f64 {
    lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .fold(1.0, f64::max)
}
