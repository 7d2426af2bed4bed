//! Two sections of the campaign page beyond its bars: where the lab swarm breaks under frame
//! loss (a sweep from 10 % to 80 %), and how often the robots initiate a wave per negotiation
//! period (the paper: "every aMussel initiated at least 10 messages").
//!
//! Both run the same emulated lab as the campaign ([`campaign::run_one`]), seeded the same way,
//! so the page regenerates byte for byte.

use std::fmt::Write as _;

use protocol::Params;
use rayon::prelude::*;

use crate::campaign::{self, Decide, Outcome, Report, SCENARIOS, quantile};

/// Frame losses of the sweep.
pub const LOSSES: [f64; 8] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8];

/// Seeds per loss of the sweep (fewer than the campaign's 200: it maps a curve, it sets no bar).
pub const SWEEP_SEEDS: u64 = 50;

/// The scenario whose initiations are counted: the fault-free baseline.
const BASELINE: &str = "cycle-spread";

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
/// [`LOSSES`] for `seeds` seeds from `seed`, in parallel.
///
/// # Errors
/// A message if a run cannot start.
pub fn loss_sweep(decide: Decide, seed: u64, seeds: u64) -> Result<Vec<LossPoint>, String> {
    let scenario = SCENARIOS
        .iter()
        .find(|s| matches!(s.fault, campaign::Fault::Loss(_)))
        .ok_or("the campaign has no loss scenario")?;
    LOSSES
        .iter()
        .map(|&loss| {
            let runs = (0..seeds)
                .into_par_iter()
                .map(|k| campaign::run_one(scenario, seed.wrapping_add(k), Some(loss), decide))
                .collect::<Result<Vec<_>, String>>()?;
            Ok(LossPoint { loss, runs })
        })
        .collect()
}

fn pct(x: f64) -> String {
    format!("{:.0} %", 100.0 * x)
}

fn secs(x: Option<f64>) -> String {
    x.map_or("-".into(), |s| format!("{s:.0}"))
}

/// The sweep of both rules as a Markdown section.
pub fn loss_section(fixed: &[LossPoint], adaptive: &[LossPoint], seeds: u64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## Where the swarm breaks: frame loss from 10 % to 80 %\n"
    );
    let _ = writeln!(
        s,
        "The lab of the loss scenarios (the six patterns in turn, seeds from the campaign's \
         first), {seeds} seeds per loss and rule; each frame is lost at each receiver with the \
         given probability, independently. A run succeeds as in the campaign (right LEDs at the \
         end, no change after consensus). No bar: the curve shows how much margin the bars at \
         10 % and 20 % have.\n"
    );
    let _ = writeln!(
        s,
        "| loss | fixed: success | fixed: median s | adaptive: success | adaptive: median s |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|");
    for (f, a) in fixed.iter().zip(adaptive) {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            pct(f.loss),
            pct(f.success()),
            secs(f.median_s()),
            pct(a.success()),
            secs(a.median_s())
        );
    }
    let breaks = |points: &[LossPoint]| {
        points
            .iter()
            .find(|p| p.success() < 0.95)
            .map_or("not within 80 %".to_string(), |p| {
                format!("at {} loss", pct(p.loss))
            })
    };
    let _ = writeln!(
        s,
        "\nSuccess first falls below 95 %: fixed rule {}, adaptive rule {}.",
        breaks(fixed),
        breaks(adaptive)
    );
    s
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

/// Initiations per negotiation period of both rules in the baseline scenario, as a Markdown
/// section.
pub fn initiations_section(fixed: &Report, adaptive: &Report) -> String {
    let params = Params::robots();
    let mut s = String::new();
    let _ = writeln!(s, "\n## Initiations per negotiation period\n");
    let _ = writeln!(
        s,
        "The paper says every aMussel initiated at least 10 messages in a negotiation period. \
         Counted here in the `{BASELINE}` scenario (the fault-free baseline): for each robot of \
         each run, the waves it initiated and the initiations it skipped because it was active \
         or refractory at the time (docs/protocol.md §3), per nominal negotiation period \
         ({} cycles of {} s), averaged over the run.\n",
        params.negotiation_cycles,
        params.wave.cycle.as_secs_f64()
    );
    let _ = writeln!(
        s,
        "| rule | robot-runs | initiated: min | p5 | median | mean | skipped: median | at least 10 |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|");
    for report in [fixed, adaptive] {
        let Some(r) = report.results.iter().find(|r| r.scenario.name == BASELINE) else {
            continue;
        };
        let (init, skip) = per_period(&r.runs, &params);
        let mean = init.iter().sum::<f64>() / init.len().max(1) as f64;
        let ten = init.iter().filter(|&&x| x >= 10.0).count() as f64 / init.len().max(1) as f64;
        let f = |x: Option<f64>| x.map_or("-".into(), |v| format!("{v:.1}"));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.1} | {} | {} |",
            report.plan.decide.name(),
            init.len(),
            f(init.first().copied()),
            f(quantile(&init, 0.05)),
            f(quantile(&init, 0.5)),
            mean,
            f(quantile(&skip, 0.5)),
            pct(ten)
        );
    }
    s
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
        let section = loss_section(std::slice::from_ref(&p), std::slice::from_ref(&p), 4);
        assert!(
            section.contains("| 50 % | 75 % | 200 | 75 % | 200 |"),
            "{section}"
        );
        assert!(section.contains("fixed rule at 50 % loss"), "{section}");
    }
}
