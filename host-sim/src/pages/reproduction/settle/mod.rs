//! "Settling the open rows": the experiments behind the rows the comparison cannot settle by
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
//! - the sensor model the paper leaves open, both ways ([`sensor`]).

mod arrival;
mod caption;
mod plateau;
mod refractory;
pub(super) mod sensor;
mod start;
mod steep;
mod wander;

use serde::Serialize;

use super::Stage;
use super::caption_cloud::CaptionCloud;
use crate::report::csv_files::fixed;
use crate::swarm::experiment::Error;
use crate::swarm::probe::{Tapped, tapped_runs};
use crate::swarm::scenario::{Placement, Scenario};
use crate::swarm::timecourse::TimeCourse;

/// First stage of this section's seeds (clear of the other stages of `reproduce`).
const STAGE: u64 = 600;

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
    /// The walk along the sharp border and the gradient's walk in two dimensions.
    pub(super) wander: wander::Walks,
    /// Steeper gradients, faster arrival.
    pub(super) steep: steep::Steepness,
    /// The caption's cloud toward its border.
    pub(super) caption: caption::TowardBorder,
}

/// The runs of the averaged courses, main placement, again (the same seeds), tapped.
pub(super) struct CourseRuns {
    /// Sharp border.
    pub(super) sharp: Vec<Tapped>,
    /// Gradient.
    pub(super) gradient: Vec<Tapped>,
}

/// Runs every experiment of the section and writes its figures and CSV files. `courses` are
/// the averaged courses (per field: main placement, other); the main placement's runs are run
/// again, tapped, and must give their plateaus again.
///
/// # Errors
/// If a run fails, a file cannot be written, or the tapped runs are not the courses' runs.
pub(super) fn run(
    st: &mut Stage<'_>,
    main: Placement,
    scns: [&Scenario; 2],
    courses: &[[TimeCourse; 2]],
    caption_cloud: &CaptionCloud,
) -> Result<Settled, Error> {
    let seeds = [0, 1].map(|k| st.seed(super::COURSE_STAGE + 2 * k));
    let plateaus = [0, 1].map(|k| courses.get(k).map_or(f64::NAN, |c| c[0].plateau));
    let runs = course_runs(st, scns, seeds, plateaus)?;
    let (sensor_part, sensor_facts) = sensor::run(st, scns, seeds, &runs)?;
    let (plateau, plateau_facts) = plateau::run(st, main, scns, &runs)?;
    let (arrival, arrival_facts) = arrival::run(st, scns, &runs)?;
    let (start, start_facts) = start::run(st, main, scns)?;
    let (wander_part, walks) = wander::run(st, &runs)?;
    let (steep_part, steepness) = steep::run(st, scns)?;
    let (caption_part, toward) = caption::run(st, caption_cloud)?;
    let (refractory, flooding) = refractory::run(st)?;
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
        },
        plateau: plateau_facts,
        arrival: arrival_facts,
        start: start_facts,
        refractory: flooding,
        sensor: sensor_facts,
        wander: walks,
        steep: steepness,
        caption: toward,
    })
}

/// The averaged courses' runs, tapped; checks that their plateaus are the courses'.
fn course_runs(
    st: &mut Stage<'_>,
    scns: [&Scenario; 2],
    seeds: [u64; 2],
    plateaus: [f64; 2],
) -> Result<CourseRuns, Error> {
    let mut out = Vec::new();
    for (k, scn) in scns.into_iter().enumerate() {
        let runs = super::COURSE_RUNS;
        let p = st.start(
            &format!("{}: the courses' runs, tapped", scn.name),
            u64::from(runs),
        );
        let t = tapped_runs(scn, scn.run, scn.start.x, scn.periods, runs, seeds[k], &p)?;
        st.done(&p);
        let again = crate::swarm::probe::plateaus(&t, super::PLATEAU_MIN_AFTER).agents;
        if (again.mean - plateaus[k]).abs() > 1e-9 {
            return Err(format!(
                "{}: the tapped runs' plateau {} is not the course's {}",
                scn.name, again.mean, plateaus[k]
            )
            .into());
        }
        out.push(t);
    }
    let gradient = out.pop().ok_or("two fields")?;
    let sharp = out.pop().ok_or("two fields")?;
    Ok(CourseRuns { sharp, gradient })
}

/// `mean ± se` with `digits` decimals.
fn pm(mean: f64, se: f64, digits: usize) -> String {
    format!("{} ± {}", fixed(mean, digits), fixed(se, digits))
}

/// Writes a CSV file of `header` and `rows` into the figures folder.
fn write_csv(
    st: &Stage<'_>,
    name: &str,
    header: &[&str],
    rows: &[Vec<String>],
) -> Result<(), Error> {
    let mut w = csv::Writer::from_path(st.figs.join(name))?;
    w.write_record(header)?;
    for r in rows {
        w.write_record(r)?;
    }
    w.flush()?;
    Ok(())
}
