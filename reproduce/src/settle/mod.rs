//! The runs behind "Settling the open rows" (the rows the comparison cannot settle by itself,
//! issue 22 item 4), one file per experiment; `pages::reproduction` writes their tables,
//! figures and CSV files.

pub mod arrival;
pub mod plateau;
pub mod refractory;
pub mod sensor;
pub mod start;
pub mod steep;
pub mod wander;

use crate::Error;
use crate::results::{CourseDigest, Levels, RefractoryRuns, Times};
use crate::stage::Stage;
use crate::stages::COURSES;
use crate::units::{Field, Side, placement};
use crate::{COURSE_RUNS, PLATEAU_MIN_AFTER};
use swarm_sim::experiment::RunOutput;
use swarm_sim::probe::{Plateaus, StartRun, plateaus, tapped_runs};
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::timecourse::{TimeCourse, summarise};

/// The seed of the averaged course of field `f`, main placement.
pub fn course_seed(st: &Stage<'_>, f: Field) -> u64 {
    st.seed(COURSES.at2(f.index(), Side::Main.index()))
}

/// Figs. 5b and 8b averaged with `side`'s placement (`scn` is placed by `main`):
/// [`COURSE_RUNS`] full runs from the start of field `f`, tapped as they run (the tap changes
/// nothing in a run): the course, and what the section reads off the same runs. The start is
/// on the x axis.
///
/// # Errors
/// If a run fails.
pub fn course(
    st: &mut Stage<'_>,
    main: Placement,
    f: Field,
    side: Side,
    scn: &Scenario,
) -> Result<(TimeCourse, CourseDigest), Error> {
    let scn = &*crate::on_side(scn, main, side)?;
    let p = st.start(
        &format!("{} course, {} placement", scn.name, placement(main, side)),
        u64::from(COURSE_RUNS),
    );
    let seed = st.seed(COURSES.at2(f.index(), side.index()));
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
    let course = summarise(&outs, PLATEAU_MIN_AFTER);
    let digest = CourseDigest {
        plateaus: plateaus(&t, PLATEAU_MIN_AFTER),
        levels: sensor::levels(&t),
        way: arrival::way(scn, &outs),
        msd: wander::msd(&outs),
    };
    Ok((course, digest))
}

/// Field `f`'s averaged course again with one sensor reading per period.
///
/// # Errors
/// If a run fails.
pub fn sensor(st: &mut Stage<'_>, f: Field, scn: &Scenario) -> Result<Levels, Error> {
    let seed = course_seed(st, f);
    sensor::per_period(st, scn, seed)
}

/// The sharp plateau at cycle `k` with placement `side` (`None`: the courses' own).
///
/// # Errors
/// If `k` is no cycle or a run fails.
pub fn plateau(
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
pub fn heading(
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
pub fn start(
    st: &mut Stage<'_>,
    main: Placement,
    f: Field,
    side: Side,
    scn: &Scenario,
) -> Result<Vec<StartRun>, Error> {
    start::runs(st, placement(main, side), f.index(), side.index(), scn)
}

/// Steeper ramps: case `k` (0 the sharp border, then the slopes) with `side`'s placement.
///
/// # Errors
/// If `k` is no case or a run fails.
pub fn steep(
    st: &mut Stage<'_>,
    k: u8,
    main: Placement,
    side: Side,
    scns: [&Scenario; 2],
) -> Result<Vec<Times>, Error> {
    steep::case(st, usize::from(k), main, side, scns)
}

/// The refractory time, off and on.
///
/// # Errors
/// If a wave cannot be run or the model differs from the protocol.
pub fn refractory(st: &mut Stage<'_>) -> Result<RefractoryRuns, Error> {
    refractory::runs(st)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::UNITS;
    use crate::units::Unit;

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
            let cases: Vec<usize> = UNITS
                .iter()
                .filter_map(|u| match u {
                    Unit::Steep(k, s) if *s == side => Some(usize::from(*k)),
                    _ => None,
                })
                .collect();
            assert_eq!(cases, (0..=steep::SLOPES.len()).collect::<Vec<_>>());
        }
    }
}
