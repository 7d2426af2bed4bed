//! After arrival: the paper's swarm walks along the sharp border ("a one-dimensional random
//! walk", §3.1) and diffuses in both dimensions on the gradient (§3.2). Measured as the mean
//! squared displacement of the swarm's centre along x and along y against the lag, from the
//! position at arrival on, over the averaged courses' runs.

use std::path::Path;

use serde::Serialize;

use super::{pm, write_csv};
use report::csv_files::fixed;
use report::plot::{self, Line};
use reproduce::settle::wander::MAX_LAG;
use swarm_sim::experiment::Error;
use swarm_sim::probe::Msd;
use swarm_sim::stats;

/// Lags shown in the table.
const SHOWN: [u32; 5] = [1, 2, 5, 10, 20];

/// One field's walk after arrival, as the comparison judges it.
#[derive(Clone, Copy, Debug)]
pub(in super::super) struct Walk {
    /// Growth of the mean squared displacement per period along x and along y (R² per
    /// period, least squares over lags 1 to [`MAX_LAG`]) with their 95 % half-widths.
    pub(in super::super) x_slope: (f64, f64),
    pub(in super::super) y_slope: (f64, f64),
    /// The mean squared displacements at the longest lag, x and y.
    pub(in super::super) at_max: (f64, f64),
    /// The longest lag.
    pub(in super::super) max_lag: u32,
}

/// Both fields' walks.
pub(in super::super) struct Walks {
    /// Along the sharp border.
    pub(in super::super) sharp: Walk,
    /// On the gradient.
    pub(in super::super) gradient: Walk,
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct WanderPart {
    runs: u32,
    max_lag: u32,
    /// Per shown lag: lag, then sharp x, y, gradient x, y.
    rows: Vec<Vec<String>>,
    /// Slopes (R² per period), x and y, per field.
    sharp_x: String,
    sharp_y: String,
    gradient_x: String,
    gradient_y: String,
    /// The ratio y / x of the mean squared displacements at the longest lag, per field.
    sharp_ratio: String,
    gradient_ratio: String,
}

/// Both fields' walks from their mean squared displacements (sharp, gradient).
pub(super) fn walks([sharp, gradient]: [&Vec<Msd>; 2]) -> Walks {
    Walks {
        sharp: walk(sharp),
        gradient: walk(gradient),
    }
}

/// The part from the walks after arrival of both fields' courses' runs ([`msd`]); writes
/// `settle-wander.{csv,svg}`.
///
/// # Errors
/// If a file cannot be written.
pub(super) fn write(figs: &Path, msds: [&Vec<Msd>; 2]) -> Result<(WanderPart, Walks), Error> {
    let [sharp, gradient] = msds;
    let walks = walks(msds);
    let rows = SHOWN
        .iter()
        .filter_map(|&lag| {
            let (s, g) = (
                sharp.get(lag as usize - 1)?,
                gradient.get(lag as usize - 1)?,
            );
            Some(vec![
                lag.to_string(),
                fixed(s.x, 2),
                fixed(s.y, 2),
                fixed(g.x, 2),
                fixed(g.y, 2),
            ])
        })
        .collect();
    let csv_rows: Vec<Vec<String>> = sharp
        .iter()
        .zip(gradient)
        .map(|(s, g)| {
            vec![
                s.lag.to_string(),
                fixed(s.x, 4),
                fixed(s.y, 4),
                s.pairs.to_string(),
                fixed(g.x, 4),
                fixed(g.y, 4),
                g.pairs.to_string(),
            ]
        })
        .collect();
    write_csv(
        figs,
        "settle-wander.csv",
        &[
            "lag",
            "sharp_msd_x",
            "sharp_msd_y",
            "sharp_pairs",
            "gradient_msd_x",
            "gradient_msd_y",
            "gradient_pairs",
        ],
        &csv_rows,
    )?;
    figure(figs, sharp, gradient)?;
    let slope = |s: (f64, f64)| pm(s.0, s.1, 4);
    let ratio = |w: &Walk| fixed(w.at_max.1 / w.at_max.0.max(1e-12), 1);
    let part = WanderPart {
        runs: super::super::COURSE_RUNS,
        max_lag: MAX_LAG,
        rows,
        sharp_x: slope(walks.sharp.x_slope),
        sharp_y: slope(walks.sharp.y_slope),
        gradient_x: slope(walks.gradient.x_slope),
        gradient_y: slope(walks.gradient.y_slope),
        sharp_ratio: ratio(&walks.sharp),
        gradient_ratio: ratio(&walks.gradient),
    };
    Ok((part, walks))
}

/// The slopes of a field's mean squared displacements against the lag.
fn walk(msd: &[Msd]) -> Walk {
    let fit = |pick: fn(&Msd) -> f64| {
        let pts: Vec<(f64, f64)> = msd.iter().map(|m| (f64::from(m.lag), pick(m))).collect();
        stats::line_fit(&pts).map_or((f64::NAN, f64::NAN), |f| (f.slope, f.slope_ci))
    };
    let last = msd.last();
    Walk {
        x_slope: fit(|m| m.x),
        y_slope: fit(|m| m.y),
        at_max: last.map_or((f64::NAN, f64::NAN), |m| (m.x, m.y)),
        max_lag: last.map_or(0, |m| m.lag),
    }
}

fn figure(figs: &Path, sharp: &[Msd], gradient: &[Msd]) -> Result<(), Error> {
    let line = |label: &str, msd: &[Msd], pick: fn(&Msd) -> f64| Line {
        label: label.into(),
        points: msd
            .iter()
            .map(|m| (f64::from(m.lag), pick(m), 0.0))
            .collect(),
    };
    let lines = [
        line("sharp: along x (across the border)", sharp, |m| m.x),
        line("sharp: along y (along the border)", sharp, |m| m.y),
        line("gradient: along x (along the ramp)", gradient, |m| m.x),
        line("gradient: along y", gradient, |m| m.y),
    ];
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .fold(1.0, f64::max);
    plot::xy_figure(
        &figs.join("settle-wander.svg"),
        "after arrival: mean squared displacement of the swarm's centre",
        "lag / periods",
        "mean squared displacement / R²",
        &lines,
        (0.0, (top * 1.1).ceil()),
        &[],
        false,
    )?;
    Ok(())
}
