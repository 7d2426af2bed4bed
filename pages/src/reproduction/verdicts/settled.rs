//! The summary table's rows on the claims the settling section tests (the walks after
//! arrival, steeper gradients, the caption's cloud toward its border, the refractory state).

use super::{Judged, Report, field_of};
use crate::claims::{Claim, Kind};
use crate::verdict::{self, Sign};
use report::csv_files::fixed;

/// The walk after arrival (settling section): the growth of the mean squared displacement
/// across and along.
pub(super) fn walk(r: &Report<'_>, c: &'static Claim) -> Judged {
    let sharp = field_of(c.id) == 0;
    super::on_both(r, |k| {
        let w = &r.settled.wander[k];
        walk_on(if sharp { &w.sharp } else { &w.gradient }, c)
    })
}

/// A walk claim on one placement's walk.
fn walk_on(w: &crate::reproduction::settle::wander::Walk, c: &'static Claim) -> Judged {
    let conf = fixed(100.0 * swarm_sim::stats::CONFIDENCE, 0);
    let dims = match c.kind {
        Kind::Walk { dims } => dims,
        _ => 1,
    };
    let pm = |s: (f64, f64)| format!("{} ± {}", fixed(s.0, 4), fixed(s.1, 4));
    let v = verdict::walk(w.x_slope, w.y_slope, dims);
    Judged {
        ours: format!(
            "mean squared displacement after arrival grows {} R² per period along x, {} along y; after {} periods {} and {} R²",
            pm(w.x_slope),
            pm(w.y_slope),
            w.max_lag,
            fixed(w.at_max.0, 2),
            fixed(w.at_max.1, 2)
        ),
        verdict: v,
        why: if dims == 1 {
            format!(
                "the rule: the growth along the border (y) has its {conf} % interval above zero and the growth across it (x) is below it, the interval of their difference above zero ({} ± {}; least squares over lags 1 to {}; the lags overlap, so the intervals are a guide)",
                fixed(w.y_slope.0 - w.x_slope.0, 4),
                fixed(w.x_slope.1.hypot(w.y_slope.1), 4),
                w.max_lag
            )
        } else if v == crate::verdict::Verdict::Reproduced {
            format!(
                "the rule: both growths have their {conf} % intervals above zero and the interval of their difference contains zero (a diffusion in two dimensions is the same along both): difference {} ± {}",
                fixed(w.y_slope.0 - w.x_slope.0, 4),
                fixed(w.x_slope.1.hypot(w.y_slope.1), 4)
            )
        } else {
            format!(
                "the rule: both growths have their {conf} % intervals above zero and the interval of their difference contains zero (a diffusion in two dimensions is the same along both); along x it grows {} times slower than along y (difference {} ± {}), so by the sharp border's test this walk is one along y: below the line the pull toward +x bounds it on one side (settling section)",
                fixed(w.y_slope.0 / w.x_slope.0.max(1e-12), 1),
                fixed(w.y_slope.0 - w.x_slope.0, 4),
                fixed(w.x_slope.1.hypot(w.y_slope.1), 4)
            )
        },
    }
}

/// Steeper ramps (settling section): time to the same line against the slope, on both
/// placements.
pub(super) fn steeper(r: &Report<'_>) -> Judged {
    super::on_both(r, |k| steeper_on(&r.settled.steep[k]))
}

/// Steeper ramps on one placement's runs.
fn steeper_on(s: &crate::reproduction::settle::steep::Steepness) -> Judged {
    let conf = fixed(100.0 * swarm_sim::stats::CONFIDENCE, 0);
    let (lo, hi) = s.slopes;
    let also = s.success.1 >= s.success.0;
    Judged {
        ours: format!(
            "from slope {lo} to {hi} per R: success {} → {}, periods to within {} R of x = 0 {} → {} ({} ± {} per doubling; the sharp border {}), to x ≥ {} {} → {}",
            fixed(s.success.0, 2),
            fixed(s.success.1, 2),
            s.near,
            fixed(s.to_line.0, 1),
            fixed(s.to_line.1, 1),
            fixed(s.per_doubling.0, 2),
            fixed(s.per_doubling.1, 2),
            fixed(s.sharp_time, 1),
            s.line_x,
            fixed(s.to_criterion.0, 1),
            fixed(s.to_criterion.1, 1),
        ),
        verdict: verdict::trend(s.per_doubling.0, s.per_doubling.1, Sign::Falls, also),
        why: {
            use crate::claims::{Id, Value, claim};
            use crate::paper::Fig;
            let at = |id| match claim(id).value {
                Value::At(v) => v.to_string(),
                _ => "?".into(),
            };
            format!(
                "the rule: the time to the same line (the border, or the ramp's start) falls with the slope (its {conf} % interval against log2 of the slope below zero) and success does not; the paper's evidence, the mean success times of its sweeps ({} and {}; its single runs arrive at t = {} and t = {}, {} and {}), times two criteria {} R apart",
                Fig::SharpSweep,
                Fig::GradientSweep,
                at(Id::SharpArrival),
                at(Id::GradientArrival),
                Fig::SharpRun,
                Fig::GradientRun,
                s.line_x,
            )
        },
    }
}

/// The caption's cloud toward its border (settling section), on both placements.
pub(super) fn toward_border(r: &Report<'_>) -> Judged {
    super::on_both(r, |k| toward_border_on(&r.settled.caption[k]))
}

/// The caption's cloud toward its border on one placement's profile.
fn toward_border_on(t: &crate::reproduction::settle::caption::TowardBorder) -> Judged {
    let points: Vec<(f64, f64)> = t.points.iter().map(|p| (p.1, p.2)).collect();
    let short: Vec<String> = t
        .points
        .iter()
        .filter(|p| p.1 < t.threshold)
        .map(|p| fixed(p.0, 2))
        .collect();
    let inside_away = t
        .points
        .iter()
        .filter(|p| p.0 < t.edge && p.1 < 0.0)
        .map(|p| p.0)
        .fold((f64::MAX, f64::MIN), |(a, b), d| (a.min(d), b.max(d)));
    Judged {
        ours: format!(
            "{} of {} distances below {} with mean alignment toward the border ≥ {}",
            t.points.len() - short.len(),
            t.points.len(),
            t.reach,
            t.threshold
        ),
        verdict: verdict::profile(&points, t.threshold),
        why: match t.settles_at {
            Some((d, se)) if inside_away.0 <= inside_away.1 => format!(
                "the rule: at every distance below {} the mean alignment toward the border (r = {}) at least {}; inside the cloud the swarm heads away from the border from {} to {} R and its centre settles {} ± {} R from the centre, where its outer agents straddle the border; short at {}",
                t.reach,
                t.edge,
                t.threshold,
                fixed(inside_away.0, 2),
                fixed(inside_away.1, 2),
                fixed(d, 2),
                fixed(se, 2),
                short.join(", ")
            ),
            _ => format!(
                "the rule: at every distance below {} the mean alignment toward the border (r = {}) at least {}; short at: {}",
                t.reach,
                t.edge,
                t.threshold,
                if short.is_empty() {
                    "none".into()
                } else {
                    short.join(", ")
                }
            ),
        },
    }
}

/// The refractory time off (a model of the simulator's rule) and on (the protocol).
pub(super) fn refractory(r: &Report<'_>) -> Judged {
    let f = &r.settled.refractory;
    Judged {
        ours: format!(
            "without it (model): {} transmissions per agent in {} s, {}; with {} s (the protocol's least): every agent once",
            fixed(f.sends_without, 1),
            f.horizon,
            if f.floods_without { "still going" } else { "over" },
            f.smallest.map_or("–".into(), |s| s.to_string())
        ),
        verdict: verdict::mechanism(f.floods_without, !f.once_with),
        why: "the rule: the wave keeps coming back without a refractory time and every agent sends once with it; the protocol refuses a refractory time not above the relay delay, so the first is the simulator's delivery rule as a model, checked equal to the protocol where both run".into(),
    }
}
