//! The sensitivity runs: the knobs the paper leaves open, one at a time (cycle, period,
//! diffusion, noise), the gradient's diversity against its slope, and the swarm's extent
//! against the perception edges.

use nalgebra::Point2;

use crate::Error;
use crate::results::{ExtentRun, SlopeRuns};
use crate::stage::Stage;
use crate::stages::{EXTENT, EXTENT_OTHER, KNOBS, SLOPE_DIVERSITY, SLOPE_SUCCESS};
use crate::units::{Side, placement};
use crate::{builtin_placed, refined};
use swarm_sim::experiment::SweepPoint;
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::sensitivity::{Knob, diversity_at, heading_against_x, success_against};

/// Runs per point of the sensitivity figures.
pub const SENS_RUNS: u32 = 20;
/// Runs per point of the extent's heading profiles.
pub const EXTENT_RUNS: u32 = 30;
/// Where the sensitivity runs start (both fields).
pub const SENS_X: f64 = -2.0;

/// Where the extent's starts are refined to 0.25 R: around the claimed edges 2.5 and 2.2.
pub const EXTENT_REFINED: [f64; 4] = [-3.25, -2.75, -2.25, -1.75];

/// The knobs of the sensitivity tables: key, axis, values, log axis, both placements.
pub fn knob_specs() -> [SensSpec; 4] {
    [
        (
            "cycle",
            "cycle length t_p^max / s",
            [20u64, 50, 100, 200, 500, 1000, 2000]
                .map(|c| (c as f64, Knob::Cycle(c)))
                .to_vec(),
            true,
            true,
        ),
        (
            "period",
            "negotiation period / cycles (half gathering, half deciding)",
            [2u16, 4, 10]
                .map(|c| (f64::from(c), Knob::Period(c)))
                .to_vec(),
            false,
            false,
        ),
        (
            "diffusion",
            "diffusion rate / %",
            [0.05f32, 0.10, 0.20]
                .map(|d| (f64::from(d * 100.0).round(), Knob::Diffusion(d)))
                .to_vec(),
            false,
            false,
        ),
        (
            "noise",
            "noise width (ξ uniform in ±width/2)",
            [0.5, 1.0, 2.0, 4.0].map(|w| (w, Knob::Noise(w))).to_vec(),
            false,
            false,
        ),
    ]
}

/// The cases of a knob's table, by label: each field with the main placement, and with the
/// other too if `both_placements` (the sharp border's other placement after its main one).
pub fn cases(
    main: Placement,
    sharp: &Scenario,
    gradient: &Scenario,
    both_placements: bool,
) -> Result<Vec<(String, Scenario)>, Error> {
    let name = |s: &Scenario, p: Placement| format!("{}, {p}", s.name);
    let mut cases = vec![
        (name(sharp, main), sharp.clone()),
        (name(gradient, main), gradient.clone()),
    ];
    if both_placements {
        let sharp_o = builtin_placed(&sharp.name, main.other())?;
        let gradient_o = builtin_placed(&gradient.name, main.other())?;
        cases.insert(1, (name(&sharp_o, main.other()), sharp_o));
        cases.push((name(&gradient_o, main.other()), gradient_o));
    }
    Ok(cases)
}

/// Knob `k` of [`knob_specs`]: success from [`SENS_X`] per value, per case (field, and
/// placement for the cycle).
///
/// # Errors
/// If `k` is no knob or a run fails.
pub fn knob(
    st: &mut Stage<'_>,
    main: Placement,
    k: u8,
    sharp: &Scenario,
    gradient: &Scenario,
) -> Result<Vec<Vec<SweepPoint>>, Error> {
    let k = usize::from(k);
    let (key, _, values, _, both_placements) =
        knob_specs().into_iter().nth(k).ok_or(Error::NoSuch {
            what: "knob",
            index: k,
        })?;
    let cases = cases(main, sharp, gradient, both_placements)?;
    let knobs: Vec<Knob> = values.iter().map(|v| v.1).collect();
    let p = st.start(
        &format!("sensitivity: {key}"),
        (cases.len() * knobs.len()) as u64 * u64::from(SENS_RUNS),
    );
    let mut results = Vec::new();
    for (j, (_, scn)) in cases.iter().enumerate() {
        let seed = st.seed(KNOBS.at2(k, j));
        results.push(success_against(scn, &knobs, SENS_X, SENS_RUNS, seed, &p)?);
    }
    st.done(&p);
    Ok(results)
}

/// Slopes of the gradient's sensitivity to its slope, per R.
pub const SLOPES: [f64; 6] = [1.0, 1.5, 2.0, 2.5, 3.0, 4.0];

/// The gradient's success line (`x ≥ line_x`; not a number if its criterion is another kind).
pub fn line_x(gradient: &Scenario) -> f64 {
    match &gradient.success {
        Some(swarm_sim::scenario::Success::BeyondX { x }) => *x,
        _ => f64::NAN,
    }
}

/// The gradient's slope: success from [`SENS_X`] and the diversity at the success line, per
/// slope of [`SLOPES`].
///
/// # Errors
/// If a run fails.
pub fn slope(st: &mut Stage<'_>, gradient: &Scenario) -> Result<SlopeRuns, Error> {
    let knobs: Vec<Knob> = SLOPES.iter().map(|&k| Knob::Slope(k)).collect();
    let p = st.start(
        "sensitivity: slope",
        2 * SLOPES.len() as u64 * u64::from(SENS_RUNS),
    );
    let success = success_against(
        gradient,
        &knobs,
        SENS_X,
        SENS_RUNS,
        st.seed(SLOPE_SUCCESS.at(0)),
        &p,
    )?;
    let at = Point2::new(line_x(gradient), 0.0);
    let mut diversity = Vec::new();
    for (k, knob) in knobs.iter().enumerate() {
        let s = knob.apply(gradient)?;
        let (m, se) = diversity_at(&s, at, SENS_RUNS, st.seed(SLOPE_DIVERSITY.at(k)), &p)?;
        diversity.push((SLOPES[k], m, se));
    }
    st.done(&p);
    Ok(SlopeRuns { success, diversity })
}

/// Diameters of the swarm's extent, R: the page's and a smaller one.
pub const DIAMETERS: [f64; 2] = [6.0, 5.0];

/// The swarm's extent: the heading of the first move against the start, per field and
/// diameter of [`DIAMETERS`] (sharp 6 R, sharp 5 R, gradient 6 R, gradient 5 R).
///
/// # Errors
/// If a run fails.
pub fn extent(
    st: &mut Stage<'_>,
    main: Placement,
    side: Side,
    [sharp, gradient]: [&Scenario; 2],
) -> Result<Vec<ExtentRun>, Error> {
    let xs = refined(
        (1..=9).map(|k| -0.5 * f64::from(k)).rev().collect(),
        &EXTENT_REFINED,
    );
    let mut runs = Vec::new();
    // The other placement runs the page's extent only (the perception edges' rows).
    let diameters = match side {
        Side::Main => &DIAMETERS[..],
        Side::Other => &DIAMETERS[..1],
    };
    let p = st.start(
        &format!("sensitivity: extent, {} placement", placement(main, side)),
        2 * (diameters.len() * xs.len()) as u64 * u64::from(EXTENT_RUNS),
    );
    for (k, scn) in [sharp, gradient].into_iter().enumerate() {
        let scn = crate::on_side(scn, main, side)?;
        for (j, &d) in diameters.iter().enumerate() {
            let s = Knob::Extent(d).apply(&scn)?;
            let seed = st.seed(match side {
                Side::Main => EXTENT.at2(k, j),
                Side::Other => EXTENT_OTHER.at(k),
            });
            let mut profile = heading_against_x(&s, &xs, EXTENT_RUNS, seed, &p)?;
            profile.sort_by(|a, b| a.0.total_cmp(&b.0));
            runs.push(ExtentRun {
                agents: s.agents,
                profile,
            });
        }
    }
    st.done(&p);
    Ok(runs)
}

/// One knob's sensitivity run: its key, what the axis shows, (value, knob) pairs, a
/// logarithmic axis, and whether the other placement runs too.
pub type SensSpec = (&'static str, &'static str, Vec<(f64, Knob)>, bool, bool);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::Unit;

    #[test]
    fn there_is_a_unit_per_knob() {
        let knobs: Vec<u8> = crate::UNITS
            .iter()
            .filter_map(|u| match u {
                Unit::Knob(k) => Some(*k),
                _ => None,
            })
            .collect();
        assert_eq!(knobs, (0..knob_specs().len() as u8).collect::<Vec<_>>());
    }
}
