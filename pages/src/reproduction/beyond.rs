//! "Beyond the paper": the binned entropy ([`protocol::diversity::Entropy`]) as the diversity
//! measure instead of the variance, the alternative the paper's discussion names. Success from
//! [`SENS_X`] on both fields with each measure, and the agents' mean diversity along the
//! gradient with each (where the entropy's plateau lies against its ceiling).

use std::path::Path;

use nalgebra::Point2;
use serde::Serialize;

use super::Stage;
use super::results::{Along, Results};
use super::sensitivity::{SENS_RUNS, SENS_X, cell};
use super::stages::{BEYOND_PROFILE, BEYOND_SLOPES, BEYOND_SUCCESS, BEYOND_TWO};
use super::units::Unit;
use report::csv_files::fixed;
use report::plot::{self, Line};
use swarm_sim::experiment::{Error, SweepPoint, sweep};
use swarm_sim::measure::Measure;
use swarm_sim::scenario::{Scenario, Success};
use swarm_sim::sensitivity::{Knob, diversity_at};

/// The entropy's bin widths tried for success; [`MAIN_BIN`] is the one of the profile.
const BINS: [f32; 3] = [0.25, 0.5, 1.0];
/// The bin width of the diversity profile: half the noise's width, so that the noise alone
/// spreads a uniform field's readings over two or three bins.
const MAIN_BIN: f32 = 0.5;
/// Swarm centres (x, on y = 0) of the diversity profile along the gradient.
const PROFILE_XS: [f64; 8] = [-3.0, -2.0, -1.0, 0.0, 1.0, 2.33, 3.5, 5.0];
/// Slopes of the gradient at which both measures are taken at the success line (the
/// scenario's 2.5 per R between them).
const SLOPES: [f64; 3] = [1.0, 2.5, 4.0];

/// The section as its template (`reproduction/beyond.md.j2`) sees it.
#[derive(Default, Serialize)]
pub(super) struct BeyondSection {
    runs: u32,
    x: String,
    main_bin: String,
    /// Field names across.
    fields: Vec<String>,
    /// Per measure: its name, then success from `x` (rate and mean time) per field.
    rows: Vec<Vec<String>>,
    /// Per field: the entropy (main bin) is within 0.15 of the variance's success rate.
    same_success: Vec<bool>,
    /// Per field: the lowest entropy success rate over the bins, and the variance's.
    worst_entropy: Vec<String>,
    variance_rate: Vec<String>,
    /// Gradient profile: x, mean variance, mean entropy.
    profile_rows: Vec<[String; 3]>,
    /// The success line of the gradient.
    line_x: String,
    /// The entropy and the variance with the swarm at the success line, and at the last
    /// profile point (the swarm wholly on the ramp).
    entropy_line: String,
    entropy_far: String,
    variance_line: String,
    variance_far: String,
    /// log2 of a message's most readings with the scorer's own (33): the entropy's ceiling.
    ceiling: String,
    /// The entropy at the last point is within 10 % of its value at the success line.
    entropy_flat: bool,
    /// The variance at the last point exceeds its value at the success line by more than 10 %.
    variance_grows: bool,
    /// The entropy ratio far / at the line, the variance's.
    entropy_ratio: String,
    variance_ratio: String,
    /// The variance at the last point is within 10 % of its value at the success line.
    variance_flat: bool,
    /// Per slope of [`SLOPES`]: slope, variance and entropy at the success line.
    slope_rows: Vec<[String; 3]>,
    /// From the smallest slope to the largest: the variance's ratio and the entropy's
    /// difference in bits, and the slopes' ratio (its log2 alongside).
    slope_variance_ratio: String,
    slope_entropy_bits: String,
    slope_ratio: String,
    slope_log2: String,
    /// The entropy grew by at most log2 of the slopes' ratio (+ 0.25 bits) while the variance
    /// grew by more than the slopes' ratio.
    entropy_logarithmic: bool,
    /// Two quantities (light uniform, oxygen the sharp border): per measure, its name and
    /// success from `x` (rate and mean time).
    two_rows: Vec<[String; 2]>,
    /// Per measure: two quantities succeed within 0.15 of the sharp field alone.
    two_same: Vec<bool>,
}

/// `scn` with the agents using `m`.
fn with(scn: &Scenario, m: Measure) -> Scenario {
    let mut s = scn.clone();
    s.run.diversity = m;
    s
}

/// The measures compared: the variance, then the entropy at each of [`BINS`]; and the index
/// of the entropy at [`MAIN_BIN`].
fn measures() -> Result<(Vec<Measure>, usize), Error> {
    let mut measures = vec![Measure::Variance];
    for b in BINS {
        measures.push(Measure::entropy(b).ok_or("bad bin width")?);
    }
    let main_m = 1 + BINS.iter().position(|&b| b == MAIN_BIN).unwrap_or(0);
    Ok((measures, main_m))
}

/// The two measures of the profile and of two quantities: the variance and the entropy at
/// [`MAIN_BIN`].
fn both() -> Result<[Measure; 2], Error> {
    let (measures, main_m) = measures()?;
    Ok([Measure::Variance, measures[main_m]])
}

/// The section from the units [`Unit::BeyondSuccess`], [`Unit::BeyondAlong`] and
/// [`Unit::BeyondTwo`]; writes `beyond-diversity.svg`.
///
/// # Errors
/// If a unit has no result or the figure cannot be written.
pub(super) fn write(
    figs: &Path,
    fields: [&Scenario; 2],
    all: &Results,
) -> Result<BeyondSection, Error> {
    let (measures, main_m) = measures()?;
    let both = both()?;
    let results = all.beyond_success(Unit::BeyondSuccess)?;
    let along = all.beyond_along(Unit::BeyondAlong)?;
    along.figure(figs, fields[1], both)?;
    let mut section = success_section(fields, &measures, results, main_m);
    let (two_rows, two_same) = two_section(both, all.beyond_two(Unit::BeyondTwo)?, results, main_m);
    section.two_rows = two_rows;
    section.two_same = two_same;
    along.fill(&mut section);
    Ok(section)
}

/// Success from [`SENS_X`] per field and measure: `results[field][measure]`.
///
/// # Errors
/// If a run fails.
pub(super) fn success(
    st: &mut Stage<'_>,
    fields: [&Scenario; 2],
) -> Result<Vec<Vec<SweepPoint>>, Error> {
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

/// The section's success part (the rest filled in by the other steps).
fn success_section(
    fields: [&Scenario; 2],
    measures: &[Measure],
    results: &[Vec<SweepPoint>],
    main_m: usize,
) -> BeyondSection {
    let rows = measures
        .iter()
        .enumerate()
        .map(|(m, measure)| {
            std::iter::once(measure.to_string())
                .chain(results.iter().map(|per| cell(&per[m])))
                .collect()
        })
        .collect();
    BeyondSection {
        runs: SENS_RUNS,
        x: SENS_X.to_string(),
        main_bin: MAIN_BIN.to_string(),
        fields: fields.iter().map(|s| s.name.clone()).collect(),
        rows,
        same_success: results
            .iter()
            .map(|per| (per[main_m].success_rate() - per[0].success_rate()).abs() <= 0.15)
            .collect(),
        worst_entropy: results
            .iter()
            .map(|per| {
                let w = per[1..]
                    .iter()
                    .map(SweepPoint::success_rate)
                    .fold(f64::MAX, f64::min);
                fixed(w, 2)
            })
            .collect(),
        variance_rate: results
            .iter()
            .map(|per| fixed(per[0].success_rate(), 2))
            .collect(),
        ..BeyondSection::default()
    }
}

/// Runs both measures ([`both`]) along the gradient and against the slope.
///
/// # Errors
/// If a run fails.
pub(super) fn along(st: &mut Stage<'_>, gradient: &Scenario) -> Result<Along, Error> {
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
    let line_x = match &gradient.success {
        Some(Success::BeyondX { x }) => *x,
        _ => 2.33,
    };
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

/// log2 of a message's most readings with the scorer's own (33): the entropy's ceiling.
fn ceiling() -> f64 {
    33f64.log2()
}

impl Along {
    /// The mean of measure `m` at profile point `x`.
    fn at(&self, m: usize, x: f64) -> f64 {
        self.prof[m]
            .iter()
            .find(|q| (q.0 - x).abs() < 1e-9)
            .map_or(f64::NAN, |q| q.1)
    }

    /// `beyond-diversity.svg`.
    fn figure(
        &self,
        figs: &Path,
        gradient: &Scenario,
        measures: [Measure; 2],
    ) -> Result<(), Error> {
        let y_max = self
            .prof
            .iter()
            .flatten()
            .map(|q| q.1 + q.2)
            .fold(ceiling(), f64::max);
        plot::xy_figure(
            &figs.join("beyond-diversity.svg"),
            &format!(
                "{}: the agents' mean diversity against the swarm's x, {SENS_RUNS} runs per point",
                gradient.name
            ),
            "x of the swarm's centre / R",
            "mean V_k (variance) or bits (entropy)",
            &measures
                .iter()
                .zip(&self.prof)
                .map(|(m, pts)| Line {
                    label: m.to_string(),
                    points: pts.clone(),
                })
                .collect::<Vec<_>>(),
            (0.0, 1.05 * y_max),
            &[(self.line_x, " success line")],
            false,
        )?;
        Ok(())
    }

    /// Fills the section's profile and slope parts.
    fn fill(&self, s: &mut BeyondSection) {
        let (lo, hi) = (self.by_slope[0], self.by_slope[SLOPES.len() - 1]);
        let slope_ratio = SLOPES[SLOPES.len() - 1] / SLOPES[0];
        let far_x = PROFILE_XS[PROFILE_XS.len() - 1];
        let (v_line, v_far) = (self.at(0, self.line_x), self.at(0, far_x));
        let (e_line, e_far) = (self.at(1, self.line_x), self.at(1, far_x));
        let prof = &self.prof;
        s.profile_rows = PROFILE_XS
            .iter()
            .enumerate()
            .map(|(k, x)| {
                [
                    x.to_string(),
                    format!("{} ± {}", fixed(prof[0][k].1, 2), fixed(prof[0][k].2, 2)),
                    format!("{} ± {}", fixed(prof[1][k].1, 2), fixed(prof[1][k].2, 2)),
                ]
            })
            .collect();
        s.line_x = self.line_x.to_string();
        s.entropy_line = fixed(e_line, 2);
        s.entropy_far = fixed(e_far, 2);
        s.variance_line = fixed(v_line, 1);
        s.variance_far = fixed(v_far, 1);
        s.ceiling = fixed(ceiling(), 2);
        s.entropy_flat = (e_far / e_line - 1.0).abs() <= 0.1;
        s.variance_grows = v_far > 1.1 * v_line;
        s.entropy_ratio = fixed(e_far / e_line, 2);
        s.variance_ratio = fixed(v_far / v_line, 2);
        s.variance_flat = (v_far / v_line - 1.0).abs() <= 0.1;
        s.slope_rows = SLOPES
            .iter()
            .zip(&self.by_slope)
            .map(|(k, v)| [k.to_string(), fixed(v[0], 2), fixed(v[1], 2)])
            .collect();
        s.slope_variance_ratio = fixed(hi[0] / lo[0], 1);
        s.slope_entropy_bits = fixed(hi[1] - lo[1], 2);
        s.slope_ratio = fixed(slope_ratio, 1);
        s.slope_log2 = fixed(slope_ratio.log2(), 2);
        s.entropy_logarithmic =
            hi[1] - lo[1] <= slope_ratio.log2() + 0.25 && hi[0] / lo[0] > slope_ratio;
    }
}

/// Two quantities, light uniform (no information) and oxygen the sharp border: success from
/// [`SENS_X`] per measure of [`both`].
///
/// # Errors
/// If a run fails.
pub(super) fn two(st: &mut Stage<'_>, sharp: &Scenario) -> Result<Vec<SweepPoint>, Error> {
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

/// Two quantities' rows, and per measure whether it is within 0.15 of the sharp field alone
/// (`results`, the success per field and measure).
fn two_section(
    measures: [Measure; 2],
    pts: &[SweepPoint],
    results: &[Vec<SweepPoint>],
    main_m: usize,
) -> (Vec<[String; 2]>, Vec<bool>) {
    let mut two_rows = Vec::new();
    let mut two_same = Vec::new();
    for (m, (measure, pt)) in measures.iter().zip(pts).enumerate() {
        let alone = &results[0][if m == 0 { 0 } else { main_m }];
        two_same.push((pt.success_rate() - alone.success_rate()).abs() <= 0.15);
        two_rows.push([measure.to_string(), cell(pt)]);
    }
    (two_rows, two_same)
}
