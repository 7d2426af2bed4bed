//! The paper's Figs. 5b and 8b averaged: the observer's average diversity and the agents'
//! consensus against time over many full runs from the scenario's start, and the diversity
//! plateau once the swarm has arrived.
//!
//! Time `t` counts negotiation periods from the start: the value at `t` is what the period that
//! began at `t` measured (its gathering phase, with the swarm where it stood at `t`; its
//! decisions at the period's end, before the move). So `t = 0` is the swarm at its start, as in
//! the paper's figures.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::experiment::{Error, RunOutput, run};
use crate::progress::Progress;
use crate::scenario::Scenario;
use crate::seeds::derive;
use crate::stats;

/// The quantiles over runs of a [`Spread`]'s band (`q10`, `q90`).
pub const BAND: [f64; 2] = [0.1, 0.9];

/// Mean and spread of one quantity over runs at one time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// Mean over runs.
    #[serde(with = "crate::json")]
    pub mean: f64,
    /// 10 % quantile over runs.
    #[serde(with = "crate::json")]
    pub q10: f64,
    /// 90 % quantile over runs.
    #[serde(with = "crate::json")]
    pub q90: f64,
    /// Standard error of the mean.
    #[serde(with = "crate::json")]
    pub se: f64,
}

impl Spread {
    /// The spread of `xs` (NaN for none; the standard error NaN for fewer than two).
    pub fn of(xs: &[f64]) -> Spread {
        Spread {
            mean: stats::mean(xs).unwrap_or(f64::NAN),
            q10: stats::quantile(xs, BAND[0]).unwrap_or(f64::NAN),
            q90: stats::quantile(xs, BAND[1]).unwrap_or(f64::NAN),
            se: stats::standard_error(xs).unwrap_or(f64::NAN),
        }
    }
}

/// One time of the averaged course.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimePoint {
    /// Negotiation periods since the start.
    pub t: u32,
    /// The observer's average diversity (mean over agents of `V_k`).
    pub diversity: Spread,
    /// Mean resultant length of the agents' decided bearings (1 = unanimous).
    pub consensus: Spread,
    /// Runs that had met the success criterion by `t`.
    pub arrived: u32,
}

/// Many full runs of one scenario from its start, averaged.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeCourse {
    /// Runs averaged.
    pub runs: u32,
    /// Per period since the start.
    pub points: Vec<TimePoint>,
    /// Diversity plateau: the mean over the runs that arrived at least `min_after` periods
    /// before the end of their mean diversity after arriving.
    #[serde(with = "crate::json")]
    pub plateau: f64,
    /// Standard error of [`plateau`](Self::plateau) over those runs.
    #[serde(with = "crate::json")]
    pub plateau_se: f64,
    /// Runs that count for the plateau.
    pub plateau_runs: usize,
    /// Periods after which each run first met the criterion (`None`: never).
    pub success_at: Vec<Option<u32>>,
    /// Mean over runs of the fraction of agents at x ≥ 0 at the start (the side of the sharp
    /// border and of the gradient's ramp).
    #[serde(with = "crate::json")]
    pub across_at_start: f64,
    /// Over the runs that arrived: mean |y| of the centre at arrival (R).
    #[serde(with = "crate::json")]
    pub y_at_arrival: f64,
    /// Over the runs that arrived: the x gained until arrival over the path's length (1: every
    /// move straight along +x).
    #[serde(with = "crate::json")]
    pub straightness: f64,
    /// Over the runs that arrived: mean periods until arrival.
    #[serde(with = "crate::json")]
    pub mean_arrival: f64,
}

/// `runs` full runs of `scn` (its periods, not stopped at success) from its start; run `r` uses
/// seed `derive(seed, [r])`. The plateau counts runs that met the criterion at least
/// `min_after` periods before the end.
///
/// # Errors
/// The first run's error, if any run fails.
pub fn time_course(
    scn: &Scenario,
    runs: u32,
    min_after: u32,
    seed: u64,
    progress: &Progress,
) -> Result<TimeCourse, Error> {
    let outs: Vec<RunOutput> = (0..runs)
        .into_par_iter()
        .map(|r| {
            let out = run(
                scn,
                scn.run,
                scn.start,
                scn.periods,
                derive(seed, &[u64::from(r)]),
                false,
            );
            progress.inc();
            out
        })
        .collect::<Result<_, _>>()?;
    Ok(summarise(&outs, min_after))
}

/// The course and plateau of finished runs.
pub fn summarise(outs: &[RunOutput], min_after: u32) -> TimeCourse {
    let len = outs.iter().map(|o| o.periods.len()).max().unwrap_or(0);
    let points = (0..len)
        .map(|k| {
            let at: Vec<_> = outs.iter().filter_map(|o| o.periods.get(k)).collect();
            let div: Vec<f64> = at.iter().map(|p| p.diversity).collect();
            let con: Vec<f64> = at.iter().map(|p| p.consensus).collect();
            TimePoint {
                t: k as u32,
                diversity: Spread::of(&div),
                consensus: Spread::of(&con),
                arrived: outs
                    .iter()
                    .filter(|o| o.success_at.is_some_and(|s| s as usize <= k))
                    .count() as u32,
            }
        })
        .collect();
    let tails: Vec<f64> = outs
        .iter()
        .filter_map(|o| {
            let at = o.success_at?;
            let tail: Vec<f64> = o
                .periods
                .iter()
                .filter(|p| p.index > at)
                .map(|p| p.diversity)
                .collect();
            (tail.len() >= min_after as usize).then(|| stats::mean(&tail).unwrap_or(f64::NAN))
        })
        .collect();
    let (y_at_arrival, straightness, mean_arrival) = paths(outs);
    TimeCourse {
        y_at_arrival,
        straightness,
        mean_arrival,
        runs: outs.len() as u32,
        points,
        plateau: stats::mean(&tails).unwrap_or(f64::NAN),
        plateau_se: stats::standard_error(&tails).unwrap_or(0.0),
        plateau_runs: tails.len(),
        success_at: outs.iter().map(|o| o.success_at).collect(),
        across_at_start: across_at_start(outs),
    }
}

/// Over the runs that arrived, up to their arrival: the mean |y| at arrival, the share of the
/// distance walked that was gained along +x, and the mean periods to arrive.
fn paths(outs: &[RunOutput]) -> (f64, f64, f64) {
    let paths: Vec<(f64, f64, f64)> = outs
        .iter()
        .filter_map(|o| {
            let at = o.success_at? as usize;
            let moves = &o.periods[..at.min(o.periods.len())];
            let end = moves.last().map_or(o.start, |p| p.to);
            let length: f64 = moves.iter().map(|p| (p.to - p.from).norm()).sum();
            let gained = end.x - o.start.x;
            Some((
                end.y.abs(),
                if length > 0.0 {
                    gained / length
                } else {
                    f64::NAN
                },
                at as f64,
            ))
        })
        .collect();
    let col = |f: fn(&(f64, f64, f64)) -> f64| {
        let v: Vec<f64> = paths.iter().map(f).filter(|v| v.is_finite()).collect();
        stats::mean(&v).unwrap_or(f64::NAN)
    };
    (col(|p| p.0), col(|p| p.1), col(|p| p.2))
}

/// The mean over runs of the share of agents at x ≥ 0 at the start.
fn across_at_start(outs: &[RunOutput]) -> f64 {
    stats::mean(
        &outs
            .iter()
            .map(|o| {
                let n = o.swarm.offsets().len().max(1) as f64;
                let across = o
                    .swarm
                    .offsets()
                    .iter()
                    .filter(|v| o.start.x + v.x >= 0.0)
                    .count();
                across as f64 / n
            })
            .collect::<Vec<_>>(),
    )
    .unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Swarm;
    use crate::sim::Period;
    use nalgebra::{Point2, Vector2};

    fn period(index: u32, diversity: f64, consensus: f64) -> Period {
        Period {
            index,
            end_s: u64::from(index) * 2000,
            from: Point2::origin(),
            to: Point2::origin(),
            direction: Some(0.0),
            consensus,
            decided: 1,
            diversity,
        }
    }

    fn out(div: &[f64], success_at: Option<u32>) -> RunOutput {
        RunOutput {
            swarm: Swarm::from_offsets(vec![Vector2::zeros()], 1.0),
            start: Point2::origin(),
            periods: div
                .iter()
                .enumerate()
                .map(|(k, &d)| period(k as u32 + 1, d, d / 10.0))
                .collect(),
            success_at,
        }
    }

    #[test]
    fn the_course_averages_each_period_and_the_plateau_only_arrived_runs() {
        let outs = [
            out(&[1.0, 2.0, 5.0, 5.0, 5.0], Some(2)),
            out(&[3.0, 4.0, 3.0, 7.0, 7.0], Some(3)),
            out(&[2.0, 3.0, 4.0, 1.0, 2.0], None),
        ];
        let c = summarise(&outs, 2);
        assert_eq!(c.points.len(), 5);
        assert_eq!(c.points[0].t, 0);
        assert!((c.points[0].diversity.mean - 2.0).abs() < 1e-12);
        assert!((c.points[0].consensus.mean - 0.2).abs() < 1e-12);
        assert_eq!(
            c.points.iter().map(|p| p.arrived).collect::<Vec<_>>(),
            [0, 0, 1, 2, 2]
        );
        // Run 0: periods 3..5 after arriving at 2 → 5; run 1: periods 4, 5 → 7; run 2 never.
        assert_eq!(c.plateau_runs, 2);
        assert_eq!(c.across_at_start, 1.0);
        assert!((c.plateau - 6.0).abs() < 1e-12);
        assert!((c.plateau_se - 0.5f64.sqrt()).abs() < 1e-12);
        // With min_after = 3 only run 0 counts.
        let c = summarise(&outs, 3);
        assert_eq!(c.plateau_runs, 1);
        assert!((c.plateau - 5.0).abs() < 1e-12);
    }
}
