//! The campaign page's loss sweep and initiation sections, from [`lab::stress`]'s
//! runs (`loss` and `initiations` in `templates/reliability/`).

use protocol::Params;
use serde::Serialize;

use lab::campaign::Report;
use lab::stress::{BASELINE, LossPoint, full_periods, per_period};
use swarm_sim::stats::quantile;

/// The loss sweep of both rules, as the page's section shows it (`loss` in
/// `templates/reliability/loss.md.j2`).
#[derive(Serialize)]
pub struct LossSection {
    /// Seeds per loss and rule.
    pub seeds: u64,
    /// Per loss: the loss, then success and median time of the fixed and the adaptive rule.
    pub rows: Vec<[String; 5]>,
    /// Where the fixed rule's success first falls below 95 %.
    pub fixed_breaks: String,
    /// Where the adaptive rule's success first falls below 95 %.
    pub adaptive_breaks: String,
}

/// The sweep of both rules as the page's section.
pub fn loss_section(fixed: &[LossPoint], adaptive: &[LossPoint], seeds: u64) -> LossSection {
    let rows = fixed
        .iter()
        .zip(adaptive)
        .map(|(f, a)| {
            [
                pct(f.loss),
                pct(f.success()),
                secs(f.median_s()),
                pct(a.success()),
                secs(a.median_s()),
            ]
        })
        .collect();
    let breaks = |points: &[LossPoint]| {
        points
            .iter()
            .find(|p| p.success() < 0.95)
            .map_or("not within 80 %".to_string(), |p| {
                format!("at {} loss", pct(p.loss))
            })
    };
    LossSection {
        seeds,
        rows,
        fixed_breaks: breaks(fixed),
        adaptive_breaks: breaks(adaptive),
    }
}

/// Initiations per negotiation period of both rules, as the page's section shows it
/// (`initiations` in `templates/reliability/initiations.md.j2`).
#[derive(Serialize)]
pub struct InitiationsSection {
    /// The scenario counted.
    pub scenario: &'static str,
    /// Cycles per negotiation period.
    pub cycles: u16,
    /// The nominal cycle, s.
    pub cycle_s: String,
    /// Per rule: its name, robot-runs, initiated min, p5, median, mean, skipped median, share
    /// of robot-runs with at least 10 per nominal period, the robots' own negotiation periods
    /// completed and the share of them with at least one initiation per cycle.
    pub rows: Vec<[String; 10]>,
}

/// Initiations per negotiation period of both rules in the baseline scenario, as the page's
/// section.
pub fn initiations_section(fixed: &Report, adaptive: &Report) -> InitiationsSection {
    let params = Params::robots();
    let mut rows = Vec::new();
    for report in [fixed, adaptive] {
        let Some(r) = report.results.iter().find(|r| r.scenario.name == BASELINE) else {
            continue;
        };
        let (init, skip) = per_period(&r.runs, &params);
        let mean = swarm_sim::stats::mean(&init).unwrap_or(0.0);
        let ten = init.iter().filter(|&&x| x >= 10.0).count() as f64 / init.len().max(1) as f64;
        let f = |x: Option<f64>| x.map_or("-".into(), |v| format!("{v:.1}"));
        let (periods, full) = full_periods(&r.runs);
        rows.push([
            report.plan.decide.name().to_string(),
            init.len().to_string(),
            f(init.first().copied()),
            f(quantile(&init, 0.05)),
            f(quantile(&init, 0.5)),
            format!("{mean:.1}"),
            f(quantile(&skip, 0.5)),
            pct(ten),
            periods.to_string(),
            full.map_or("-".into(), pct),
        ]);
    }
    InitiationsSection {
        scenario: BASELINE,
        cycles: params.negotiation_cycles,
        cycle_s: params.wave.cycle.as_secs_f64().to_string(),
        rows,
    }
}

fn pct(x: f64) -> String {
    format!("{:.0} %", 100.0 * x)
}

fn secs(x: Option<f64>) -> String {
    x.map_or("-".into(), |s| format!("{s:.0}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loss_section_shows_success_median_and_where_a_rule_breaks() {
        use lab::campaign::Outcome;
        let run = |success: bool, consensus: f64| Outcome {
            seed: 1,
            pattern: "1000".into(),
            expected: "GGGG".into(),
            leds: "GGGG".into(),
            success,
            why: None,
            crashed: false,
            consensus_s: Some(consensus),
            restore_s: None,
            medium: Default::default(),
            frame_errors: 0,
            nodes: Vec::new(),
            waves: Vec::new(),
            duration_s: 1650.0,
        };
        let p = LossPoint {
            loss: 0.5,
            runs: vec![
                run(true, 100.0),
                run(false, 10.0),
                run(true, 300.0),
                run(true, 200.0),
            ],
        };
        let section = loss_section(std::slice::from_ref(&p), std::slice::from_ref(&p), 4);
        assert_eq!(section.rows, [["50 %", "75 %", "200", "75 %", "200"]]);
        assert_eq!(section.fixed_breaks, "at 50 % loss");
    }
}
