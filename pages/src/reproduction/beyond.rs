//! "Beyond the paper": the binned entropy ([`protocol::diversity::Entropy`]) as the diversity
//! measure instead of the variance, the alternative the paper's discussion names (run by
//! [`reproduce::beyond`]). Success from [`SENS_X`] on both fields with each measure, and the agents' mean diversity along the
//! gradient with each (where the entropy's plateau lies against its ceiling).

use std::path::Path;

use serde::Serialize;

use super::sensitivity::cell;
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::beyond::{MAIN_BIN, PROFILE_XS, SLOPES, both, measures};
use reproduce::results::{Along, Results};
use reproduce::sensitivity::{SENS_RUNS, SENS_X};
use reproduce::units::Unit;
use swarm_sim::experiment::{Error, SweepPoint};
use swarm_sim::measure::Measure;
use swarm_sim::scenario::Scenario;
use swarm_sim::sim::MESSAGE_READINGS;

/// The section as its template (`reproduction/beyond.md.j2`) sees it.
#[derive(Default, Serialize)]
pub(super) struct BeyondSection {
    /// [`SAME_WITHIN`].
    same_within: String,
    runs: u32,
    x: String,
    main_bin: String,
    /// Field names across.
    fields: Vec<String>,
    /// Per measure: its name, then success from `x` (rate and mean time) per field.
    rows: Vec<Vec<String>>,
    /// Per field: the entropy (main bin) is within [`SAME_WITHIN`] of the variance's success rate.
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
    /// A message's most readings ([`MESSAGE_READINGS`]).
    message_readings: usize,
    /// log2 of a message's most readings with the scorer's own: the entropy's ceiling.
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
    /// Per measure: two quantities succeed within [`SAME_WITHIN`] of the sharp field alone.
    two_same: Vec<bool>,
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
    along_figure(along, figs, fields[1], both)?;
    let mut section = success_section(fields, &measures, results, main_m);
    let (two_rows, two_same) = two_section(both, all.beyond_two(Unit::BeyondTwo)?, results, main_m);
    section.two_rows = two_rows;
    section.two_same = two_same;
    along_fill(along, &mut section);
    Ok(section)
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
        same_within: SAME_WITHIN.to_string(),
        runs: SENS_RUNS,
        x: SENS_X.to_string(),
        main_bin: MAIN_BIN.to_string(),
        fields: fields.iter().map(|s| s.name.clone()).collect(),
        rows,
        same_success: results
            .iter()
            .map(|per| (per[main_m].success_rate() - per[0].success_rate()).abs() <= SAME_WITHIN)
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

/// Two success rates closer than this are the same, within what the runs can tell.
const SAME_WITHIN: f64 = 0.15;

/// log2 of a message's most readings with the scorer's own: the entropy's ceiling.
fn ceiling() -> f64 {
    ((MESSAGE_READINGS + 1) as f64).log2()
}

/// `beyond-diversity.svg`.
fn along_figure(
    this: &Along,
    figs: &Path,
    gradient: &Scenario,
    measures: [Measure; 2],
) -> Result<(), Error> {
    let y_max = this
        .prof
        .iter()
        .flatten()
        .map(|q| q.1 + q.2)
        .fold(ceiling(), f64::max);
    let lines: Vec<Line> = measures
        .iter()
        .zip(&this.prof)
        .map(|(m, pts)| Line {
            label: m.to_string(),
            points: pts.clone(),
        })
        .collect();
    let (x, y) = (
        "x of the swarm's centre / R",
        "mean V_k (variance) or bits (entropy)",
    );
    crate::csv::write_lines_csv(&figs.join("beyond-diversity.csv"), x, y, &lines)?;
    plot::xy_figure(
        &figs.join("beyond-diversity.svg"),
        &format!(
            "{}: the agents' mean diversity against the swarm's x, {SENS_RUNS} runs per point",
            gradient.name
        ),
        x,
        y,
        &lines,
        (0.0, 1.05 * y_max),
        &[(this.line_x, " success line")],
        false,
    )?;
    Ok(())
}

/// Fills the section's profile and slope parts.
fn along_fill(this: &Along, s: &mut BeyondSection) {
    let (lo, hi) = (this.by_slope[0], this.by_slope[SLOPES.len() - 1]);
    let slope_ratio = SLOPES[SLOPES.len() - 1] / SLOPES[0];
    let far_x = PROFILE_XS[PROFILE_XS.len() - 1];
    let (v_line, v_far) = (this.at(0, this.line_x), this.at(0, far_x));
    let (e_line, e_far) = (this.at(1, this.line_x), this.at(1, far_x));
    let prof = &this.prof;
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
    s.line_x = this.line_x.to_string();
    s.entropy_line = fixed(e_line, 2);
    s.entropy_far = fixed(e_far, 2);
    s.variance_line = fixed(v_line, 1);
    s.variance_far = fixed(v_far, 1);
    s.message_readings = MESSAGE_READINGS;
    s.ceiling = fixed(ceiling(), 2);
    s.entropy_flat = (e_far / e_line - 1.0).abs() <= 0.1;
    s.variance_grows = v_far > 1.1 * v_line;
    s.entropy_ratio = fixed(e_far / e_line, 2);
    s.variance_ratio = fixed(v_far / v_line, 2);
    s.variance_flat = (v_far / v_line - 1.0).abs() <= 0.1;
    s.slope_rows = SLOPES
        .iter()
        .zip(&this.by_slope)
        .map(|(k, v)| [k.to_string(), fixed(v[0], 2), fixed(v[1], 2)])
        .collect();
    s.slope_variance_ratio = fixed(hi[0] / lo[0], 1);
    s.slope_entropy_bits = fixed(hi[1] - lo[1], 2);
    s.slope_ratio = fixed(slope_ratio, 1);
    s.slope_log2 = fixed(slope_ratio.log2(), 2);
    s.entropy_logarithmic =
        hi[1] - lo[1] <= slope_ratio.log2() + 0.25 && hi[0] / lo[0] > slope_ratio;
}

/// Two quantities' rows, and per measure whether it is within [`SAME_WITHIN`] of the sharp field alone
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
        two_same.push((pt.success_rate() - alone.success_rate()).abs() <= SAME_WITHIN);
        two_rows.push([measure.to_string(), cell(pt)]);
    }
    (two_rows, two_same)
}
