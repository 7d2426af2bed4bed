//! Beyond the paper: the entropy of the readings as the diversity measure beside the
//! variance (success per field, both measures along the gradient and against its slope), and
//! two quantities at once.

use nalgebra::Point2;

use crate::Error;
use crate::results::Along;
use crate::sensitivity::{SENS_RUNS, SENS_X};
use crate::stage::Stage;
use crate::stages::{BEYOND_PROFILE, BEYOND_SLOPES, BEYOND_SUCCESS, BEYOND_TWO};
use swarm_sim::experiment::{SweepPoint, sweep};
use swarm_sim::measure::Measure;
use swarm_sim::scenario::Scenario;
use swarm_sim::sensitivity::{Knob, diversity_at};

/// The entropy's bin widths tried for success; [`MAIN_BIN`] is the one of the profile.
pub const BINS: [f32; 3] = [0.25, 0.5, 1.0];
/// The bin width of the diversity profile: half the noise's width, so that the noise alone
/// spreads a uniform field's readings over two or three bins.
pub const MAIN_BIN: f32 = 0.5;
/// Swarm centres (x, on y = 0) of the diversity profile along the gradient.
pub const PROFILE_XS: [f64; 8] = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.33, 3.5, 5.0];
/// Slopes of the gradient at which both measures are taken at the success line (the
/// scenario's 2.5 per R between them).
pub const SLOPES: [f64; 3] = [1.0, 2.5, 4.0];

/// `scn` with the agents using `m`.
pub fn with(scn: &Scenario, m: Measure) -> Scenario {
    let mut s = scn.clone();
    s.run.diversity = m;
    s
}

/// The measures compared: the variance, then the entropy at each of [`BINS`]; and the index
/// of the entropy at [`MAIN_BIN`].
pub fn measures() -> Result<(Vec<Measure>, usize), Error> {
    let mut measures = vec![Measure::Variance];
    for b in BINS {
        measures.push(Measure::entropy(b).ok_or(Error::BadBin)?);
    }
    let main_m = 1 + BINS.iter().position(|&b| b == MAIN_BIN).unwrap_or(0);
    Ok((measures, main_m))
}

/// The two measures of the profile and of two quantities: the variance and the entropy at
/// [`MAIN_BIN`].
pub fn both() -> Result<[Measure; 2], Error> {
    let (measures, main_m) = measures()?;
    Ok([Measure::Variance, measures[main_m]])
}

/// Success from [`SENS_X`] per field and measure: `results[field][measure]`.
///
/// # Errors
/// If a run fails.
pub fn success(st: &mut Stage<'_>, fields: [&Scenario; 2]) -> Result<Vec<Vec<SweepPoint>>, Error> {
    let (measures, _) = measures()?;
    let p = st.start(
        "beyond the paper: entropy, success",
        (fields.len() * measures.len()) as u64 * u64::from(SENS_RUNS),
    );
    let mut results: Vec<Vec<SweepPoint>> = Vec::new();
    for (f, scn) in fields.iter().enumerate() {
        let mut per = Vec::new();
        for (m, &measure) in measures.iter().enumerate() {
            let s = with(scn, measure);
            let seed = st.seed(BEYOND_SUCCESS.at2(f, m));
            per.push(sweep(&s, s.run, &[SENS_X], SENS_RUNS, seed, &p)?[0]);
        }
        results.push(per);
    }
    st.done(&p);
    Ok(results)
}

/// Runs both measures ([`both`]) along the gradient and against the slope.
///
/// # Errors
/// If a run fails.
pub fn along(st: &mut Stage<'_>, gradient: &Scenario) -> Result<Along, Error> {
    let measures = both()?;
    let p = st.start(
        "beyond the paper: entropy, diversity along the gradient",
        (measures.len() * (PROFILE_XS.len() + SLOPES.len())) as u64 * u64::from(SENS_RUNS),
    );
    let mut prof: Vec<Vec<(f64, f64, f64)>> = Vec::new();
    for (m, &measure) in measures.iter().enumerate() {
        let s = with(gradient, measure);
        let mut pts = Vec::new();
        for (k, &x) in PROFILE_XS.iter().enumerate() {
            let seed = st.seed(BEYOND_PROFILE.at2(m, k));
            let (mean, se) = diversity_at(&s, Point2::new(x, 0.0), SENS_RUNS, seed, &p)?;
            pts.push((x, mean, se));
        }
        prof.push(pts);
    }
    let line_x = crate::sensitivity::line_x(gradient);
    let mut by_slope: Vec<[f64; 2]> = Vec::new();
    for (k, &slope) in SLOPES.iter().enumerate() {
        let s = Knob::Slope(slope).apply(gradient)?;
        let mut v = [0.0; 2];
        for (m, &measure) in measures.iter().enumerate() {
            let seed = st.seed(BEYOND_SLOPES.at2(k, m));
            let at = Point2::new(line_x, 0.0);
            v[m] = diversity_at(&with(&s, measure), at, SENS_RUNS, seed, &p)?.0;
        }
        by_slope.push(v);
    }
    st.done(&p);
    Ok(Along {
        prof,
        by_slope,
        line_x,
    })
}

/// Two quantities, light uniform (no information) and oxygen the sharp border: success from
/// [`SENS_X`] per measure of [`both`].
///
/// # Errors
/// If a run fails.
pub fn two(st: &mut Stage<'_>, sharp: &Scenario) -> Result<Vec<SweepPoint>, Error> {
    let measures = both()?;
    let mut two = sharp.clone();
    two.field = hal_emu::world::field::Field::default();
    two.field2 = Some(sharp.field.clone());
    let p = st.start(
        "beyond the paper: two quantities",
        measures.len() as u64 * u64::from(SENS_RUNS),
    );
    let mut pts = Vec::new();
    for (m, &measure) in measures.iter().enumerate() {
        let s = with(&two, measure);
        let seed = st.seed(BEYOND_TWO.at(m));
        pts.push(sweep(&s, s.run, &[SENS_X], SENS_RUNS, seed, &p)?[0]);
    }
    st.done(&p);
    Ok(pts)
}
