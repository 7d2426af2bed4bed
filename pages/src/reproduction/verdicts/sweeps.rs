//! The summary table's rows read off the sweeps (success and mean time against the start),
//! judged on both placements' sweeps, the weaker verdict.

use super::{Judged, Report, mean_time_at, within};
use crate::claims::{Id, claim};
use crate::verdict::{self, Sign, Verdict};
use report::csv_files::fixed;
use swarm_sim::experiment::SweepPoint;
use swarm_sim::stats;

/// "Falls beyond 2.5 R": the rate's slope against x beyond 2.5 R is positive (it falls with the
/// distance) with its whole interval, and the farthest start's rate is below the level inside
/// 2.5 R by more than two standard errors; on both placements' sweeps, the weaker verdict.
pub(super) fn sharp_far(r: &Report<'_>) -> Judged {
    let (_, hi) = claim(Id::SharpNear).over.unwrap_or((f64::NAN, f64::NAN));
    falls(r, 0, -hi, Id::SharpNear, &format!("inside {hi} R"))
}

/// "Falls beyond x = −2" on the gradient: as [`sharp_far`], from −2 and against the rate over
/// the range the paper gives as mostly successful (−2 ≤ x < 2.33); both placements.
pub(super) fn gradient_fall(r: &Report<'_>) -> Judged {
    let (lo, hi) = claim(Id::GradientMid).over.unwrap_or((f64::NAN, f64::NAN));
    falls(
        r,
        1,
        lo,
        Id::GradientMid,
        &format!("over {} … {hi}", lo.to_string().replace('-', "−")),
    )
}

/// A "falls beyond `edge`" row of field `k` ([`far_of`] on each placement's sweep, against the
/// rate over claim `near`'s range, `near_words`), the weaker verdict of the two.
fn falls(r: &Report<'_>, k: usize, edge: f64, near: Id, near_words: &str) -> Judged {
    let (vm, om, sm) = far_of(&r.sweeps[k], edge, near, near_words);
    let (vo, oo, so) = far_of(&r.other_sweeps[k], edge, near, near_words);
    Judged {
        ours: format!("{}: {om}; {}: {oo}", r.main, r.main.other()),
        verdict: vm.both(vo),
        why: format!(
            "the rule, on each placement: the slope's {} % interval above zero (the rate falls with the distance), and the farthest start's rate more than two standard errors ({}: {}, {}: {}) below the rate {near_words}; the weaker verdict of the two ({}: {}, {}: {})",
            fixed(100.0 * stats::CONFIDENCE, 0),
            r.main,
            fixed(2.0 * sm, 2),
            r.main.other(),
            fixed(2.0 * so, 2),
            r.main,
            vm.words(),
            r.main.other(),
            vo.words()
        ),
    }
}

/// "The success times increase with decreasing distance from the border", judged as written:
/// the mean time's slope against x over −2 ≤ x < 0 (where the distance from the border falls
/// as x grows) has its 95 % interval above zero; both placements. The row says what the other
/// reading (times falling toward the border) gives.
pub(super) fn gradient_time(r: &Report<'_>) -> Judged {
    let of = |pts: &[SweepPoint]| {
        let times = mean_times(pts, Id::GradientTime);
        let fit = stats::line_fit(&times);
        let v = fit.map_or(Verdict::NotReproduced, |f| {
            verdict::trend(f.slope, f.slope_ci, Sign::Rises, true)
        });
        let other = fit.map_or(Verdict::NotReproduced, |f| {
            verdict::trend(f.slope, f.slope_ci, Sign::Falls, true)
        });
        let ours = format!(
            "{} periods; {}",
            joined(&times),
            fit.map_or("no fit".into(), |f| format!(
                "{} ± {} periods per R toward the border",
                fixed(f.slope, 1),
                fixed(f.slope_ci, 1)
            ))
        );
        (v, other, ours)
    };
    let (vm, wm, om) = of(&r.sweeps[1]);
    let (vo, wo, oo) = of(&r.other_sweeps[1]);
    Judged {
        ours: format!("{}: {om}; {}: {oo}", r.main, r.main.other()),
        verdict: vm.both(vo),
        why: format!(
            "the rule, as the text words it: the mean time's slope against x from {} to the border has its {} % interval above zero (times rising as the distance falls), on each placement, the weaker verdict; read the other way (times falling toward the border, as in the sharp border's sweep) it is {}",
            claim(Id::GradientTime)
                .over
                .map_or("?".into(), |(lo, _)| lo.to_string().replace('-', "−")),
            fixed(100.0 * stats::CONFIDENCE, 0),
            wm.both(wo).words()
        ),
    }
}

/// A "falls beyond" claim on one placement's sweep: the rate's slope beyond `edge` and the
/// farthest start against the rate over claim `near`'s range. The verdict, ours in words,
/// and the standard error of the fall.
pub(super) fn far_of(
    sweep: &[SweepPoint],
    edge: f64,
    near: Id,
    near_words: &str,
) -> (Verdict, String, f64) {
    let far: Vec<&SweepPoint> = sweep.iter().filter(|p| p.x_init < edge - 1e-9).collect();
    let pts: Vec<(f64, f64)> = far.iter().map(|p| (p.x_init, p.success_rate())).collect();
    let fit = stats::line_fit(&pts);
    let near = within(sweep, claim(near));
    let (ok, n) = near
        .iter()
        .fold((0, 0), |(k, n), p| (k + p.successes, n + p.runs));
    let inside = f64::from(ok) / f64::from(n.max(1));
    let farthest = far.first();
    let (fall, fall_se) = farthest.map_or((0.0, 0.0), |p| {
        let q = p.success_rate();
        let se = (inside * (1.0 - inside) / f64::from(n.max(1))
            + q * (1.0 - q) / f64::from(p.runs.max(1)))
        .sqrt();
        (inside - q, se)
    });
    let falls = fall > 2.0 * fall_se;
    let v = fit.map_or(Verdict::NotReproduced, |f| {
        verdict::trend(f.slope, f.slope_ci, Sign::Rises, falls)
    });
    let ours = format!(
        "{}; slope {} per R; {} {near_words}, {} at x = {}",
        pts.iter()
            .map(|(x, v)| format!("{x}: {}", fixed(*v, 2)))
            .collect::<Vec<_>>()
            .join(", "),
        fit.map_or("–".into(), |f| format!(
            "{} ± {}",
            fixed(f.slope, 2),
            fixed(f.slope_ci, 2)
        )),
        fixed(inside, 2),
        farthest.map_or("–".into(), |p| fixed(p.success_rate(), 2)),
        farthest.map_or("–".into(), |p| p.x_init.to_string()),
    );
    (v, ours, fall_se)
}

/// "Decreases linearly toward the border": the mean time's slope against x is negative with its
/// whole interval, and the points are a line by a stated test: the least-squares parabola's x²
/// coefficient has its 95 % interval around zero ([`stats::curvature`]); on both placements'
/// sweeps, the weaker verdict.
pub(super) fn sharp_time(r: &Report<'_>) -> Judged {
    super::on_both(r, |side| {
        let (verdict, ours) = sharp_time_of(&[r.sweeps, r.other_sweeps][side][0]);
        Judged {
            ours,
            verdict,
            why: format!(
                "the rule: the slope's {pct} % interval below zero, and no curvature (the least-squares parabola's x² coefficient with its {pct} % interval around zero); means of the successful runs only",
                pct = fixed(100.0 * stats::CONFIDENCE, 0),
            ),
        }
    })
}

/// [`sharp_time`] on one placement's sweep: the verdict and ours in words.
pub(super) fn sharp_time_of(sharp: &[SweepPoint]) -> (Verdict, String) {
    let times = mean_times(sharp, Id::SharpTime);
    let fit = stats::line_fit(&times);
    let bend = stats::curvature(&times);
    let straight = bend.is_some_and(|(c, ci)| c.abs() <= ci);
    let v = fit.map_or(Verdict::NotReproduced, |f| {
        verdict::trend(f.slope, f.slope_ci, Sign::Falls, straight)
    });
    let ours = format!(
        "{} periods; {}; curvature {}",
        joined(&times),
        fit.map_or("no fit".into(), |f| format!(
            "{} ± {} periods per R toward the border, R² {}",
            fixed(-f.slope, 1),
            fixed(f.slope_ci, 1),
            fixed(f.r2, 2)
        )),
        bend.map_or("–".into(), |(c, ci)| format!(
            "{} ± {} periods per R²",
            fixed(c, 2),
            fixed(ci, 2)
        ))
    );
    (v, ours)
}

/// `(x, mean success time)` at every start of `pts` inside claim `id`'s range.
fn mean_times(pts: &[SweepPoint], id: Id) -> Vec<(f64, f64)> {
    let c = claim(id);
    pts.iter()
        .filter(|p| c.covers(p.x_init))
        .filter_map(|p| mean_time_at(pts, p.x_init).map(|t| (p.x_init, t)))
        .collect()
}

/// The times of [`mean_times`], one decimal each, comma-separated.
fn joined(times: &[(f64, f64)]) -> String {
    times
        .iter()
        .map(|t| fixed(t.1, 1))
        .collect::<Vec<_>>()
        .join(", ")
}
