//! "Settling the open rows" (run by [`reproduce::settle`]): the tables, figures and CSV files of
//! the experiments behind the rows the comparison cannot settle by
//! itself (issue 22, item 4), each a table and a figure with its CSV file:
//!
//! - the sharp plateau against the cycle, the placement and the way diversity is taken
//!   ([`plateau`]);
//! - where the gradient's runs spend their periods before arriving ([`arrival`]);
//! - the starting diversity against the agents across x = 0 ([`start`]);
//! - the walk after arrival on both fields ([`wander`]);
//! - steeper gradients ([`steep`]);
//! - the caption's cloud, toward its border ([`caption`]);
//! - the refractory time, off and on ([`refractory`]);
//! - the sensor model the paper leaves open, both ways ([`sensor`]);
//! - indecision points against the swarm's size ([`indecision`]).

mod arrival;
pub(super) mod caption;
mod indecision;
mod plateau;
mod refractory;
pub(super) mod sensor;
mod start;
pub(super) mod steep;
pub(super) mod wander;

use std::path::Path;

use serde::Serialize;

use super::WriteError;
use super::caption_cloud::CaptionCloud;
use report::csv_files::fixed;
use reproduce::results::CourseDigest;
use reproduce::results::Results;
use reproduce::units::{Field, Side, Unit};
use swarm_sim::experiment::Error;
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::timecourse::TimeCourse;

/// The section as its template (`reproduction/settle.md.j2`) sees it.
#[derive(Serialize)]
pub(super) struct SettleSection {
    plateau: plateau::PlateauPart,
    arrival: arrival::ArrivalPart,
    start: start::StartPart,
    wander: wander::WanderPart,
    steep: steep::SteepPart,
    caption: caption::CaptionPart,
    refractory: refractory::RefractoryPart,
    sensor: sensor::SensorPart,
    indecision: indecision::IndecisionPart,
}

/// The section's facts the comparison's rows read.
pub(super) struct Settled {
    /// What the page shows.
    pub(super) section: SettleSection,
    /// The sharp plateau against the cycle and the placement.
    pub(super) plateau: plateau::PlateauFacts,
    /// The gradient's way to its line.
    pub(super) arrival: arrival::ArrivalFacts,
    /// The starting diversity against the agents across.
    pub(super) start: start::StartFacts,
    /// The refractory time, off and on.
    pub(super) refractory: refractory::Flooding,
    /// The levels under the other sensor model.
    pub(super) sensor: sensor::SensorFacts,
    /// The walk along the sharp border and the gradient's walk in two dimensions, per
    /// placement (main, other).
    pub(super) wander: [wander::Walks; 2],
    /// Steeper gradients, faster arrival.
    pub(super) steep: [steep::Steepness; 2],
    /// The caption's cloud toward its border, per placement (main, other).
    pub(super) caption: [caption::TowardBorder; 2],
    /// Indecision points against the swarm's size.
    pub(super) indecision: indecision::Indecision,
}

/// The section from its units' results and the averaged courses (`courses`, per field: main
/// placement, other) and the caption's cloud; writes its figures and CSV files. The tapped
/// runs must give the courses' plateaus again (they are the same runs).
///
/// # Errors
/// If a unit has no result, the tapped runs are not the courses' runs, or a file cannot be
/// written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    results: &Results,
    courses: &[[TimeCourse; 2]],
    caption_cloud: &CaptionCloud,
) -> Result<Settled, Error> {
    let tapped = |side| -> Result<[&CourseDigest; 2], Error> {
        Ok([
            results.tapped(Field::Sharp, side)?,
            results.tapped(Field::Gradient, side)?,
        ])
    };
    let (digests, others) = (tapped(Side::Main)?, tapped(Side::Other)?);
    for (j, ds) in [digests, others].iter().enumerate() {
        for (k, (scn, d)) in scns.iter().zip(ds).enumerate() {
            let course = courses.get(k).map_or(f64::NAN, |c| c[j].plateau);
            if (d.plateaus.agents.mean - course).abs() > 1e-9 {
                return Err(WriteError::NotTheCourses {
                    scenario: scn.name.clone(),
                    tapped: d.plateaus.agents.mean,
                    course,
                }
                .into());
            }
        }
    }
    let held = [
        *results.sensor(Unit::Sensor(Field::Sharp))?,
        *results.sensor(Unit::Sensor(Field::Gradient))?,
    ];
    let (sensor_part, sensor_facts) = sensor::write(figs, scns, digests.map(|d| &d.levels), held)?;
    let (plateau, plateau_facts) = plateau::write(figs, main, scns, results, digests)?;
    let headings = [
        results.heading(Unit::Heading(Field::Sharp))?,
        results.heading(Unit::Heading(Field::Gradient))?,
    ];
    let ways = digests.map(|d| &d.way);
    let (arrival, arrival_facts) = arrival::write(figs, scns, headings, ways)?;
    let (start, start_facts) = start::write(figs, main, scns, results)?;
    let (wander_part, walks) = wander::write(figs, [&digests[0].msd, &digests[1].msd])?;
    let other_walks = wander::walks([&others[0].msd, &others[1].msd]);
    let (steep_part, steepness) = steep::write(figs, scns, results)?;
    let (caption_part, toward) = caption::write(figs, caption_cloud)?;
    let (refractory, flooding) = refractory::write(figs, results.refractory(Unit::Refractory)?)?;
    let (indecision_part, indecision) = indecision::write(figs, main, results)?;
    Ok(Settled {
        section: SettleSection {
            plateau,
            arrival,
            start,
            wander: wander_part,
            steep: steep_part,
            caption: caption_part,
            refractory,
            sensor: sensor_part,
            indecision: indecision_part,
        },
        plateau: plateau_facts,
        arrival: arrival_facts,
        start: start_facts,
        refractory: flooding,
        sensor: sensor_facts,
        wander: [walks, other_walks],
        steep: steepness,
        caption: toward,
        indecision,
    })
}

/// `mean ± se` with `digits` decimals.
fn pm(mean: f64, se: f64, digits: usize) -> String {
    format!("{} ± {}", fixed(mean, digits), fixed(se, digits))
}

/// Writes a CSV file of `header` and `rows` into the figures folder `figs`.
fn write_csv(figs: &Path, name: &str, header: &[&str], rows: &[Vec<String>]) -> Result<(), Error> {
    let mut w = csv::Writer::from_path(figs.join(name))?;
    w.write_record(header)?;
    for r in rows {
        w.write_record(r)?;
    }
    w.flush()?;
    Ok(())
}
