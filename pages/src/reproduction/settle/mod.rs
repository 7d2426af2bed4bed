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

use std::path::Path;

use serde::Serialize;

use super::Stage;
use super::caption_cloud::CaptionCloud;
use super::results::{CourseDigest, Levels, RefractoryRuns, Results, Times};
use super::stages::COURSES;
use super::units::placement;
use super::units::{Field, Side, Unit};
use super::{COURSE_RUNS, PLATEAU_MIN_AFTER};
use report::csv_files::fixed;
use swarm_sim::experiment::{Error, RunOutput};
use swarm_sim::probe::{Plateaus, StartRun, plateaus, tapped_runs};
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

/// The seed of the averaged course of field `f`, main placement.
fn course_seed(st: &Stage<'_>, f: Field) -> u64 {
    st.seed(COURSES.at2(f.index(), Side::Main.index()))
}

/// The runs of field `f`'s averaged course (main placement; `scn` is so placed) again, tapped.
///
/// # Errors
/// If a run fails.
pub(super) fn tapped(st: &mut Stage<'_>, f: Field, scn: &Scenario) -> Result<CourseDigest, Error> {
    let p = st.start(
        &format!("{}: the courses' runs, tapped", scn.name),
        u64::from(COURSE_RUNS),
    );
    let seed = course_seed(st, f);
    let t = tapped_runs(
        scn,
        scn.run,
        scn.start.x,
        scn.periods,
        COURSE_RUNS,
        seed,
        &p,
    )?;
    st.done(&p);
    let outs: Vec<RunOutput> = t.iter().map(|t| t.out.clone()).collect();
    Ok(CourseDigest {
        plateaus: plateaus(&t, PLATEAU_MIN_AFTER),
        levels: sensor::levels(&t),
        way: arrival::way(scn, &outs),
        msd: wander::msd(&outs),
    })
}

/// Field `f`'s averaged course again with one sensor reading per period.
///
/// # Errors
/// If a run fails.
pub(super) fn sensor(st: &mut Stage<'_>, f: Field, scn: &Scenario) -> Result<Levels, Error> {
    let seed = course_seed(st, f);
    sensor::per_period(st, scn, seed)
}

/// The sharp plateau at cycle `k` with placement `side` (`None`: the courses' own).
///
/// # Errors
/// If `k` is no cycle or a run fails.
pub(super) fn plateau(
    st: &mut Stage<'_>,
    main: Placement,
    side: Side,
    k: u8,
    sharp: &Scenario,
) -> Result<Option<Plateaus>, Error> {
    plateau::one(st, main, side, usize::from(k), sharp)
}

/// The first move's heading along field `f`'s way to its line.
///
/// # Errors
/// If a run fails.
pub(super) fn heading(
    st: &mut Stage<'_>,
    f: Field,
    scn: &Scenario,
) -> Result<Vec<(f64, f64, f64)>, Error> {
    arrival::heading(st, f.index(), scn)
}

/// The starting diversity of field `f` (`scn`, placed by `main`) with placement `side`.
///
/// # Errors
/// If a run fails.
pub(super) fn start(
    st: &mut Stage<'_>,
    main: Placement,
    f: Field,
    side: Side,
    scn: &Scenario,
) -> Result<Vec<StartRun>, Error> {
    start::runs(st, placement(main, side), f.index(), side.index(), scn)
}

/// Steeper ramps: case `k` (0 the sharp border, then the slopes).
///
/// # Errors
/// If `k` is no case or a run fails.
pub(super) fn steep(st: &mut Stage<'_>, k: u8, scns: [&Scenario; 2]) -> Result<Vec<Times>, Error> {
    steep::case(st, usize::from(k), scns)
}

/// The refractory time, off and on.
///
/// # Errors
/// If a wave cannot be run or the model differs from the protocol.
pub(super) fn refractory(st: &mut Stage<'_>) -> Result<RefractoryRuns, Error> {
    refractory::runs(st)
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
    let digests = [
        results.tapped(Unit::Tapped(Field::Sharp))?,
        results.tapped(Unit::Tapped(Field::Gradient))?,
    ];
    for (k, (scn, d)) in scns.iter().zip(digests).enumerate() {
        let course = courses.get(k).map_or(f64::NAN, |c| c[0].plateau);
        if (d.plateaus.agents.mean - course).abs() > 1e-9 {
            return Err(format!(
                "{}: the tapped runs' plateau {} is not the course's {}",
                scn.name, d.plateaus.agents.mean, course
            )
            .into());
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
    let (steep_part, steepness) = steep::write(figs, scns, results)?;
    let (caption_part, toward) = caption::run(figs, caption_cloud)?;
    let (refractory, flooding) = refractory::write(figs, results.refractory(Unit::Refractory)?)?;
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

#[cfg(test)]
mod tests {
    use super::super::UNITS;
    use super::*;

    #[test]
    fn there_is_a_unit_per_plateau_cycle_and_steepness_case() {
        for side in Side::BOTH {
            let ks: Vec<usize> = UNITS
                .iter()
                .filter_map(|u| match u {
                    Unit::Plateau(s, k) if *s == side => Some(usize::from(*k)),
                    _ => None,
                })
                .collect();
            assert_eq!(ks, (0..plateau::CYCLES.len()).collect::<Vec<_>>());
        }
        let cases: Vec<usize> = UNITS
            .iter()
            .filter_map(|u| match u {
                Unit::Steep(k) => Some(usize::from(*k)),
                _ => None,
            })
            .collect();
        assert_eq!(cases, (0..=steep::SLOPES.len()).collect::<Vec<_>>());
    }
}
