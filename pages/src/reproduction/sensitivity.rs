//! The sensitivity section of `swarm reproduce` (run by [`reproduce::sensitivity`]): the knobs the paper leaves open, one at a time
//! (cycle, period, diffusion, noise), the gradient's diversity against its slope, and the
//! swarm's extent against the perception edges.

use super::*;
use reproduce::results::{ExtentRun, SlopeRuns};
use reproduce::sensitivity::{
    DIAMETERS, EXTENT_RUNS, SENS_RUNS, SENS_X, cases, knob_specs, line_x,
};
use reproduce::units::{Side, Unit};

/// One sensitivity table: a knob's values down, the cases across.
#[derive(Serialize)]
pub(super) struct SensTable {
    pub(super) key: &'static str,
    pub(super) what: &'static str,
    pub(super) figure: String,
    pub(super) cases: Vec<String>,
    /// Per value: the value, then per case "success (mean time)".
    pub(super) rows: Vec<Vec<String>>,
}

/// The swarm's extent: perception edges per field and extent.
#[derive(Serialize)]
pub(super) struct ExtentRow {
    pub(super) field: String,
    /// The placement (the page's: rows 0–3, per field both diameters; the other: rows 4 and
    /// 5, per field the page's diameter).
    pub(super) placement: String,
    pub(super) diameter: String,
    pub(super) agents: usize,
    /// The edge, R, two decimals.
    pub(super) edge: Option<String>,
    /// The edge and its standard error ([`extent_edge`]).
    #[serde(skip)]
    pub(super) edge_se: Option<(f64, f64)>,
    /// The verdict against the paper's edge on this field.
    pub(super) verdict: &'static str,
}

/// The mean heading the perception edge is where the first move's heading falls through.
pub(super) const EDGE_LEVEL: f64 = 0.5;

/// Where the first move's heading toward the border (`(x, mean cos, s.e.)`, x < 0) last falls
/// through 0.5 going away from the border, interpolated: the farthest start from which the swarm
/// heads for the border, as a distance, with its standard error.
pub(super) fn extent_edge(profile: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    let mut by_distance: Vec<(f64, f64, f64)> =
        profile.iter().map(|&(x, m, se)| (x.abs(), m, se)).collect();
    by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
    swarm_sim::stats::crossing(&by_distance, EDGE_LEVEL, false)
}

/// The sensitivity section.
#[derive(Serialize)]
pub(super) struct SensitivitySection {
    pub(super) runs: u32,
    pub(super) x: String,
    pub(super) tables: Vec<SensTable>,
    /// Gradient: per slope, the diversity at the success line.
    pub(super) slope_rows: Vec<[String; 4]>,
    pub(super) extent_runs: u32,
    pub(super) extent: Vec<ExtentRow>,
    /// The 3 R swarm's edges are within 0.5 R (the sampling step) of the paper's 2.5 and 2.2.
    pub(super) extent_big_matches: bool,
    /// The 2.5 R swarm's edges are shorter than the 3 R swarm's on both fields.
    pub(super) extent_small_shorter: bool,
    /// The cycle knob's runs from x = [`SENS_X`]: per case (its label, "field, placement"),
    /// per cycle length (seconds) the point. The rate rows' escape through the cycle reads it.
    #[serde(skip)]
    pub(super) by_cycle: Vec<(String, Vec<(f64, SweepPoint)>)>,
    /// Runs per point of the sharp border's sweeps, and the largest binomial standard error of
    /// a rate from [`SENS_RUNS`] runs (at 0.5), one decimal.
    pub(super) sweep_runs: u32,
    pub(super) rate_se: String,
    /// The step of the extent's grid where it is refined (around the paper's edges), R.
    pub(super) refined: String,
}

/// Success and mean time as a table cell.
pub(super) fn cell(p: &SweepPoint) -> String {
    format!(
        "{} ({})",
        fixed(p.success_rate(), 2),
        opt(p.mean_success_periods, 1)
    )
}

/// The sensitivity section from the units [`Unit::Knob`], [`Unit::Slope`] and
/// [`Unit::Extent`]: success against each knob the paper leaves open (cycle, period,
/// diffusion, noise), the gradient's diversity against its slope, and the perception edge of a
/// smaller swarm; writes the `sensitivity-*.svg` figures.
///
/// # Errors
/// If a unit has no result or a figure cannot be written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    sharp: &Scenario,
    gradient: &Scenario,
    results: &Results,
) -> Result<SensitivitySection, Error> {
    let tables = knob_tables(figs, main, sharp, gradient, results)?;
    let slope_rows = slope_rows(figs, main, gradient, results.slope(Unit::Slope)?)?;
    let extent = extent_rows(
        figs,
        main,
        [sharp, gradient],
        results.extent(Unit::Extent(Side::Main))?,
        results.extent(Unit::Extent(Side::Other))?,
    )?;
    let edge = |k: usize| extent[k].edge_se.map_or(0.0, |e| e.0);
    let extent_big_matches = {
        use crate::{claims::Id, verdict::Verdict};
        verdicts::edge_verdict(extent[0].edge_se, Id::SharpEdge) == Verdict::Reproduced
            && verdicts::edge_verdict(extent[2].edge_se, Id::GradientEdge) == Verdict::Reproduced
    };
    let extent_small_shorter = edge(1) < edge(0) && edge(3) < edge(2);
    let by_cycle = {
        let (_, _, values, _, both) = &knob_specs()[0];
        let labels = cases(main, sharp, gradient, *both)?
            .into_iter()
            .map(|c| c.0);
        labels
            .zip(results.knob(Unit::Knob(0))?)
            .map(|(label, pts)| {
                let by: Vec<(f64, SweepPoint)> = values
                    .iter()
                    .map(|v| v.0)
                    .zip(pts.iter().cloned())
                    .collect();
                (label, by)
            })
            .collect()
    };
    let xs: Vec<f64> = results
        .extent(Unit::Extent(Side::Main))?
        .first()
        .map_or(Vec::new(), |run| run.profile.iter().map(|p| p.0).collect());
    let refined = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|g| *g > 1e-9)
        .reduce(f64::min)
        .map_or("–".into(), |g| ((g * 100.0).round() / 100.0).to_string());
    Ok(SensitivitySection {
        by_cycle,
        extent_big_matches,
        extent_small_shorter,
        refined,
        sweep_runs: sharp.sweep.as_ref().map_or(0, |s| s.runs),
        rate_se: fixed((0.25 / f64::from(SENS_RUNS)).sqrt(), 1),
        runs: SENS_RUNS,
        x: SENS_X.to_string(),
        tables,
        slope_rows,
        extent_runs: EXTENT_RUNS,
        extent,
    })
}

/// One table and figure per knob of [`knob_specs`], from its unit's results.
fn knob_tables(
    figs: &Path,
    main: Placement,
    sharp: &Scenario,
    gradient: &Scenario,
    all: &Results,
) -> Result<Vec<SensTable>, Error> {
    let mut tables = Vec::new();
    for (k, (key, what, values, log_x, both_placements)) in knob_specs().into_iter().enumerate() {
        let cases = cases(main, sharp, gradient, both_placements)?;
        let labels: Vec<String> = cases.into_iter().map(|c| c.0).collect();
        let results = all.knob(Unit::Knob(k as u8))?;
        let figure = format!("sensitivity-{key}.svg");
        knob_figure(figs, &figure, key, what, &labels, &values, results, log_x)?;
        tables.push(SensTable {
            key,
            what,
            figure,
            cases: labels,
            rows: values
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    std::iter::once(v.0.to_string())
                        .chain(results.iter().map(|pts| cell(&pts[i])))
                        .collect()
                })
                .collect(),
        });
    }
    Ok(tables)
}

/// One knob's figure: success against the knob's value, one line per case.
#[allow(clippy::too_many_arguments)]
fn knob_figure(
    figs: &Path,
    figure: &str,
    key: &str,
    what: &str,
    labels: &[String],
    values: &[(f64, Knob)],
    results: &[Vec<SweepPoint>],
    log_x: bool,
) -> Result<(), Error> {
    let lines: Vec<Line> = labels
        .iter()
        .zip(results)
        .map(|(label, pts)| Line {
            label: label.clone(),
            points: values
                .iter()
                .zip(pts)
                .map(|(v, p)| (v.0, p.success_rate(), 0.0))
                .collect(),
        })
        .collect();
    crate::csv::write_lines_csv(
        &figs.join(figure).with_extension("csv"),
        what,
        "success rate",
        &lines,
    )?;
    plot::xy_figure(
        &figs.join(figure),
        &format!("success from x = {SENS_X} against the {key}, {SENS_RUNS} runs per point"),
        what,
        "success rate",
        &lines,
        (0.0, 1.05),
        &[],
        log_x,
    )?;
    Ok(())
}

/// The slope's rows, and `sensitivity-slope.svg`.
fn slope_rows(
    figs: &Path,
    main: Placement,
    gradient: &Scenario,
    runs: &SlopeRuns,
) -> Result<Vec<[String; 4]>, Error> {
    let line_x = line_x(gradient);
    let slope_rows = runs
        .diversity
        .iter()
        .zip(&runs.success)
        .map(|(&(slope, m, se), success)| {
            [
                slope.to_string(),
                format!("{} ± {}", fixed(m, 1), fixed(se, 1)),
                fixed(success.success_rate(), 2),
                opt(success.mean_success_periods, 1),
            ]
        })
        .collect();
    let lines = [Line {
        label: format!("{} placement", main),
        points: runs.diversity.clone(),
    }];
    crate::csv::write_lines_csv(
        &figs.join("sensitivity-slope.csv"),
        "slope of the ramp / per R",
        "mean V_k",
        &lines,
    )?;
    plot::xy_figure(
        &figs.join("sensitivity-slope.svg"),
        &format!(
            "gradient: the agents' mean diversity with the swarm at x = {line_x}, {SENS_RUNS} runs per slope"
        ),
        "slope of the ramp / per R",
        "mean V_k",
        &lines,
        (0.0, 30.0),
        &[],
        false,
    )?;
    Ok(slope_rows)
}

/// The extent's rows (edges and verdicts), and `sensitivity-extent.svg`.
fn extent_rows(
    figs: &Path,
    main: Placement,
    scns: [&Scenario; 2],
    runs: &[ExtentRun],
    other_runs: &[ExtentRun],
) -> Result<Vec<ExtentRow>, Error> {
    let mut extent = Vec::new();
    let mut lines = Vec::new();
    let cases = scns
        .into_iter()
        .enumerate()
        .flat_map(|(k, scn)| DIAMETERS.map(|d| (k, scn, d, main)))
        .zip(runs)
        .chain(
            scns.into_iter()
                .enumerate()
                .map(|(k, scn)| (k, scn, DIAMETERS[0], main.other()))
                .zip(other_runs),
        );
    for ((k, scn, d, placement), run) in cases {
        let edge = extent_edge(&run.profile);
        let id = [
            crate::claims::Id::SharpEdge,
            crate::claims::Id::GradientEdge,
        ][k];
        extent.push(ExtentRow {
            field: scn.name.clone(),
            placement: placement.to_string(),
            diameter: d.to_string(),
            agents: run.agents,
            edge: edge.map(|e| format!("{} ± {}", fixed(e.0, 2), fixed(e.1, 2))),
            edge_se: edge,
            verdict: verdicts::edge_verdict(edge, id).words(),
        });
        lines.push(Line {
            label: format!(
                "{}, diameter {d} R ({} agents, {placement})",
                scn.name, run.agents
            ),
            points: run.profile.clone(),
        });
    }
    crate::csv::write_lines_csv(
        &figs.join("sensitivity-extent.csv"),
        "x_init / R",
        "mean cos(direction)",
        &lines,
    )?;
    plot::xy_figure(
        &figs.join("sensitivity-extent.svg"),
        &format!(
            "heading of the first move toward +x against the start, {EXTENT_RUNS} runs per point"
        ),
        "x_init / R",
        "mean cos(direction)",
        &lines,
        (-0.3, 1.05),
        &marks::extent(),
        false,
    )?;
    Ok(extent)
}
