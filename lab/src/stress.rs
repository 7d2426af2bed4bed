//! Two experiments of the campaign page beyond its bars: where the lab swarm breaks under frame
//! loss (a sweep from 10 % to 80 %), and how often the robots initiate a wave per negotiation
//! period (the paper: "every aMussel initiated at least 10 messages"). Their sections are
//! `pages::reliability::stress`.
//!
//! Both run the same emulated lab as the campaign ([`campaign::run_one`]), seeded the same way,
//! so the page regenerates byte for byte.

use protocol::Params;
use rayon::prelude::*;

use crate::campaign::{self, CampaignError, Decide, Outcome, SCENARIOS};
use swarm_sim::stats::quantile;

/// Frame losses of the sweep.
pub const LOSSES: [f64; 8] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8];

/// Seeds per loss of the sweep (fewer than the campaign's 200: it maps a curve, it sets no bar).
pub const SWEEP_SEEDS: u64 = 50;

/// The scenario whose initiations are counted: the fault-free baseline.
pub const BASELINE: &str = "cycle-spread";

/// One point of the loss sweep.
#[derive(Clone, Debug)]
pub struct LossPoint {
    /// Probability that a frame is lost at a receiver.
    pub loss: f64,
    /// The runs, in seed order.
    pub runs: Vec<Outcome>,
}

impl LossPoint {
    /// Share of successful runs (0 to 1).
    pub fn success(&self) -> f64 {
        let ok = self.runs.iter().filter(|o| o.success).count();
        ok as f64 / self.runs.len().max(1) as f64
    }

    /// Median time to consensus of the successful runs, s.
    pub fn median_s(&self) -> Option<f64> {
        let mut t: Vec<f64> = self
            .runs
            .iter()
            .filter(|o| o.success)
            .filter_map(|o| o.consensus_s)
            .collect();
        t.sort_by(f64::total_cmp);
        quantile(&t, 0.5)
    }
}

/// Runs the lab (the campaign's loss scenario, its loss replaced) at every loss of
/// [`LOSSES`] for `seeds` seeds from `seed`, in parallel: [`loss_run`] for each, put together
/// by [`loss_points`].
///
/// # Errors
/// Why a run cannot start.
pub fn loss_sweep(decide: Decide, seed: u64, seeds: u64) -> Result<Vec<LossPoint>, StressError> {
    let runs = (0..LOSSES.len())
        .map(|l| {
            (0..seeds)
                .into_par_iter()
                .map(|k| loss_run(decide, l, seed.wrapping_add(k)))
                .collect::<Result<Vec<_>, StressError>>()
        })
        .collect::<Result<Vec<_>, StressError>>()?;
    Ok(loss_points(runs.concat(), seeds))
}

/// One run of the loss sweep: the campaign's loss scenario at loss `LOSSES[loss]`, seed `seed`.
///
/// # Errors
/// Why the run cannot start, or there is no such loss.
pub fn loss_run(decide: Decide, loss: usize, seed: u64) -> Result<Outcome, StressError> {
    let scenario = SCENARIOS
        .iter()
        .find(|s| matches!(s.fault, campaign::Fault::Loss(_)))
        .ok_or(StressError::NoLossScenario)?;
    let p = LOSSES.get(loss).ok_or(StressError::NoLoss(loss))?;
    Ok(campaign::run_one(scenario, seed, Some(*p), decide)?)
}

/// Why a run of the loss sweep could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StressError {
    /// The campaign has no loss scenario to sweep.
    #[error("the campaign has no loss scenario")]
    NoLossScenario,
    /// A loss number past [`LOSSES`].
    #[error("the loss sweep has no loss number {0}")]
    NoLoss(usize),
    /// The run could not start.
    #[error(transparent)]
    Campaign(#[from] CampaignError),
}

/// The loss sweep's points from its runs ([`loss_run`]), loss by loss, `seeds` each, in order.
pub fn loss_points(runs: Vec<Outcome>, seeds: u64) -> Vec<LossPoint> {
    let mut runs = runs.into_iter();
    LOSSES
        .iter()
        .map(|&loss| LossPoint {
            loss,
            runs: runs.by_ref().take(seeds as usize).collect(),
        })
        .collect()
}

/// Initiations per robot and nominal negotiation period in the runs of one scenario: for each
/// robot of each run, its waves initiated (and initiations skipped while busy) times the
/// nominal period over the run's length.
pub fn per_period(runs: &[Outcome], params: &Params) -> (Vec<f64>, Vec<f64>) {
    let period = params.wave.cycle.as_secs_f64() * f64::from(params.negotiation_cycles);
    let mut initiated = Vec::new();
    let mut skipped = Vec::new();
    for o in runs.iter().filter(|o| o.duration_s > 0.0) {
        let periods = o.duration_s / period;
        for w in &o.waves {
            initiated.push(f64::from(w.initiated) / periods);
            skipped.push(f64::from(w.skipped_initiations) / periods);
        }
    }
    initiated.sort_by(f64::total_cmp);
    skipped.sort_by(f64::total_cmp);
    (initiated, skipped)
}

/// Negotiation periods the robots of `runs` completed, and the share of them in which the robot
/// initiated at least one wave per cycle (`NodeStats::periods_short`); `None` without periods.
pub fn full_periods(runs: &[Outcome]) -> (u64, Option<f64>) {
    let (mut periods, mut short) = (0u64, 0u64);
    for n in runs.iter().flat_map(|o| &o.nodes) {
        periods += u64::from(n.periods);
        short += u64::from(n.periods_short);
    }
    let share = (periods > 0).then(|| (periods - short) as f64 / periods as f64);
    (periods, share)
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::wave::WaveStats;

    fn outcome(success: bool, consensus: Option<f64>, waves: &[(u32, u32)]) -> Outcome {
        Outcome {
            seed: 1,
            pattern: "1000".into(),
            expected: "GGGG".into(),
            leds: "GGGG".into(),
            success,
            why: None,
            crashed: false,
            consensus_s: consensus,
            restore_s: None,
            medium: Default::default(),
            frame_errors: 0,
            nodes: Vec::new(),
            waves: waves
                .iter()
                .map(|&(initiated, skipped_initiations)| WaveStats {
                    initiated,
                    skipped_initiations,
                    ..WaveStats::default()
                })
                .collect(),
            duration_s: 1650.0,
        }
    }

    #[test]
    fn initiations_are_counted_per_nominal_period() {
        // Params::robots(): 10 cycles of 55 s = 550 s; a 1650 s run is three periods.
        let runs = [outcome(true, Some(500.0), &[(30, 3), (27, 6)])];
        let (init, skip) = per_period(&runs, &Params::robots());
        assert_eq!(init, [9.0, 10.0]);
        assert_eq!(skip, [1.0, 2.0]);
    }

    #[test]
    fn full_periods_count_the_robots_own_periods() {
        use protocol::fused::NodeStats;
        let mut o = outcome(true, Some(500.0), &[]);
        o.nodes = vec![
            NodeStats {
                periods: 3,
                periods_short: 1,
                ..NodeStats::default()
            },
            NodeStats {
                periods: 5,
                ..NodeStats::default()
            },
        ];
        assert_eq!(full_periods(&[o]), (8, Some(7.0 / 8.0)));
        assert_eq!(full_periods(&[]), (0, None));
    }

    #[test]
    fn a_point_reports_its_success_and_median_of_the_successes() {
        let p = LossPoint {
            loss: 0.5,
            runs: vec![
                outcome(true, Some(100.0), &[]),
                outcome(false, Some(10.0), &[]),
                outcome(true, Some(300.0), &[]),
                outcome(true, Some(200.0), &[]),
            ],
        };
        assert_eq!(p.success(), 0.75);
        assert_eq!(p.median_s(), Some(200.0));
    }
}
