//! The summary table: every claim of [`CLAIMS`] with ours beside it, a [`Verdict`] computed
//! from the runs by the claim's kind ([`crate::verdict`]), and the reason, on every row
//! (reproduced rows keep their caveats).

use serde::Serialize;

use super::{Report, mean_time_at, outward_limit, perception_limit};
use crate::claims::{CLAIMS, Claim, Id, Kind, claim};
use crate::verdict::{self, Verdict};
use report::csv_files::fixed;
use swarm_sim::experiment::SweepPoint;
use swarm_sim::stats;
use swarm_sim::timecourse::BAND;

use crate::figures::timecourse::band_words;

mod maps;
mod outside;
mod settled;
mod sweeps;

/// One row of the table.
#[derive(Serialize)]
pub(super) struct Row {
    quantity: &'static str,
    source: &'static str,
    paper: &'static str,
    ours: String,
    verdict: &'static str,
    why: String,
    #[serde(skip)]
    kind: Verdict,
}

/// Ours, the verdict and the reason for one claim.
struct Judged {
    ours: String,
    verdict: Verdict,
    why: String,
}

fn row(c: &'static Claim, j: Judged) -> Row {
    Row {
        quantity: c.quantity,
        source: c.source,
        paper: c.paper,
        ours: j.ours,
        verdict: j.verdict.words(),
        why: j.why,
        kind: j.verdict,
    }
}

/// `lo–hi`, or one value when they agree to two decimals.
fn span((lo, hi): (f64, f64)) -> String {
    if (hi - lo).abs() < 0.005 {
        fixed(lo, 2)
    } else {
        format!("{}–{}", fixed(lo, 2), fixed(hi, 2))
    }
}

/// The points of `pts` inside the claim's x range ([`Claim::covers`]).
fn within<'a>(pts: &'a [SweepPoint], c: &Claim) -> Vec<&'a SweepPoint> {
    pts.iter().filter(|p| c.covers(p.x_init)).collect()
}

/// A rate claim on one placement's sweep: the worst point inside the claim's range is judged
/// (a range's claim holds at every start). Returns the verdict and the span of rates.
fn rate_claim(c: &Claim, pts: &[SweepPoint]) -> (Verdict, (f64, f64)) {
    let band = c.band().unwrap_or((1.0, 1.0));
    let sel = within(pts, c);
    let worst = sel
        .iter()
        .map(|p| verdict::rate(p.successes, p.runs, band, Some(verdict::PAPER_RUNS)))
        .max_by_key(|v| Verdict::ALL.iter().position(|w| w == v))
        .unwrap_or(Verdict::NotReproduced);
    let rates = sel
        .iter()
        .map(|p| p.success_rate())
        .fold((f64::MAX, f64::MIN), |(lo, hi), r| (lo.min(r), hi.max(r)));
    (worst, rates)
}

/// Every row, computed from the report's runs, in the order of [`CLAIMS`].
pub(super) fn verdicts(r: &Report<'_>) -> Vec<Row> {
    CLAIMS
        .iter()
        .map(|c| {
            let mut j = judge(r, c);
            if let Some(what) = one_placement(c.id) {
                j.why = format!(
                    "{}; judged on the {} placement only: the page does not run {what} with the {} placement",
                    j.why,
                    r.main,
                    r.main.other()
                );
            }
            row(c, j)
        })
        .collect()
}

/// The runs a claim is judged on, where the page runs them with its main placement only
/// (`None`: both placements, or a claim no placement bears on: the shapes' formations, the
/// wave of the paper's figure, the robots' lab).
fn one_placement(id: Id) -> Option<&'static str> {
    match id {
        Id::Initiations => Some("the cycle-length experiment"),
        _ => None,
    }
}

fn judge(r: &Report<'_>, c: &'static Claim) -> Judged {
    match c.id {
        Id::SharpNear | Id::GradientMid | Id::GradientFar => rates(r, c),
        Id::SharpFar => sweeps::sharp_far(r),
        Id::GradientFall => sweeps::gradient_fall(r),
        Id::GradientTime => sweeps::gradient_time(r),
        Id::GradientMapLeft => maps::gradient_map_left(r, c),
        Id::CloudToward => cloud_toward(r, c),
        Id::SharpTime => sweeps::sharp_time(r),
        Id::SharpStart | Id::GradientStart => start(r, c),
        Id::SharpArrival | Id::GradientArrival => arrival(r, c),
        Id::SharpPlateau | Id::GradientPlateau => plateau(r, c),
        Id::SharpMapFar => maps::sharp_map_far(r, c),
        Id::SharpMapNear | Id::GradientMapNear | Id::GradientMapFar => maps::directions(r, c),
        Id::SharpEdge | Id::GradientEdge => maps::edge(r, c),
        Id::CloudLimit | Id::CloudOutward | Id::CaptionLimit => cloud(r, c),
        Id::ShapesLine | Id::ShapesCross => shapes(r, c.id),
        Id::SharpWalk | Id::GradientWalk => settled::walk(r, c),
        Id::Steeper => settled::steeper(r),
        Id::CaptionToward => settled::toward_border(r),
        Id::Refractory => settled::refractory(r),
        Id::Initiations => outside::initiations(r, c),
        Id::Indecision => outside::indecision(r),
        Id::Lab => outside::lab(c),
    }
}

/// Which of the report's two fields a claim is about: 0 sharp, 1 gradient.
fn field_of(id: Id) -> usize {
    match id {
        Id::SharpNear
        | Id::SharpFar
        | Id::SharpTime
        | Id::SharpStart
        | Id::SharpArrival
        | Id::SharpPlateau
        | Id::SharpMapNear
        | Id::SharpMapFar
        | Id::SharpEdge
        | Id::SharpWalk => 0,
        _ => 1,
    }
}

fn runs_of(pts: &[SweepPoint]) -> u32 {
    pts.first().map_or(0, |p| p.runs)
}

/// Rates over a range of starts (or at one), both placements.
fn rates(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = field_of(c.id);
    let (main, other) = (r.main, r.main.other());
    let (vm, sm) = rate_claim(c, &r.sweeps[k]);
    let (vo, so) = rate_claim(c, &r.other_sweeps[k]);
    let short: Vec<String> = within(&r.other_sweeps[k], c)
        .iter()
        .filter(|p| {
            verdict::rate(
                p.successes,
                p.runs,
                c.band().unwrap_or((1.0, 1.0)),
                Some(verdict::PAPER_RUNS),
            ) != Verdict::Reproduced
        })
        .map(|p| format!("{} ({})", p.x_init, fixed(p.success_rate(), 2)))
        .collect();
    let near = match r.sharp.success {
        Some(swarm_sim::scenario::Success::NearX { within, .. }) => within,
        _ => f64::NAN,
    };
    let why = match c.id {
        Id::SharpNear if short.is_empty() => format!(
            "both placements hold; the {other} placement's swarms settle where the border halves their agents, which need not pass within {near} R of the centre of mass (see the sharp border below)"
        ),
        Id::SharpNear => format!(
            "{other} placement short at x = {}: its swarms settle where the border halves their agents, which need not pass within {near} R of the centre of mass (see the sharp border below)",
            short.join(", ")
        ),
        Id::GradientMid => format!(
            "{other} placement{}: its swarms' preferences along the ramp largely cancel (see the gradient below)",
            if short.is_empty() {
                " holds too".to_string()
            } else {
                format!(" short at x = {}", short.join(", "))
            }
        ),
        _ => format!(
            "a rare event at {} R: the paper's value is one rate of a few runs either way",
            c.over.map_or(f64::NAN, |o| -o.0)
        ),
    };
    let (verdict, escape) = cycle_escape(r, c, vm.both(vo));
    Judged {
        ours: format!(
            "{main}: {} ({} runs per start); {other}: {} ({} runs)",
            span(sm),
            runs_of(&r.sweeps[k]),
            span(so),
            runs_of(&r.other_sweeps[k])
        ),
        verdict,
        why: format!("{why}{escape}"),
    }
}

/// The escape through the cycle length, which the paper does not give, for a rate claim
/// covering the sensitivity runs' start x = −2: the same rate test at that start with every
/// cycle of the sensitivity table, each placement it ran. A verdict that some cycle turns
/// (reproduced at the page's, failing at another; or the other way round at every start the
/// row failed on, which x = −2 alone cannot show) depends on the unspecified cycle, as the
/// plateau's row does. Returns the verdict and the words, empty for a claim without x = −2.
fn cycle_escape(r: &Report<'_>, c: &'static Claim, page: Verdict) -> (Verdict, String) {
    let x = reproduce::sensitivity::SENS_X;
    let name = [&r.sharp.name, &r.gradient.name][field_of(c.id)];
    if !c.covers(x) {
        return (page, String::new());
    }
    let band = c.band().unwrap_or((1.0, 1.0));
    let mut off = Vec::new();
    let mut tried = 0;
    for (label, pts) in r.sensitivity.by_cycle.iter() {
        if !label.starts_with(name.as_str()) {
            continue;
        }
        for (cycle, p) in pts {
            tried += 1;
            let v = verdict::rate(p.successes, p.runs, band, Some(verdict::PAPER_RUNS));
            if v != Verdict::Reproduced {
                off.push(format!(
                    "{cycle} s ({label}: {})",
                    fixed(p.success_rate(), 2)
                ));
            }
        }
    }
    let words = if off.is_empty() {
        format!(
            "; the cycle, which the paper does not give: at x = {x} every cycle of the sensitivity table ({tried} cases) reproduces it too"
        )
    } else {
        format!(
            "; the cycle, which the paper does not give: at x = {x} the rate fails with {} (the sensitivity table)",
            off.join(", ")
        )
    };
    let turned = page == Verdict::Reproduced && !off.is_empty();
    (
        if turned {
            Verdict::DependsOnUnspecifiedRule
        } else {
            page
        },
        words,
    )
}

/// The text's cloud, "toward the circular domain" for 7 ≳ d ≳ 4: the mean inward alignment of
/// the radial profile at least 0.5 at every distance strictly between (the worst point
/// decides, [`verdict::profile`]).
fn cloud_toward(r: &Report<'_>, c: &'static Claim) -> Judged {
    on_both(r, |k| cloud_toward_on(c, [r.profile, r.other_profile][k]))
}

/// One claim judged on each placement's runs (`on(0)` the page's, `on(1)` the other): ours
/// from both, the weaker verdict, and both reasons.
fn on_both(r: &Report<'_>, on: impl Fn(usize) -> Judged) -> Judged {
    let (m, o) = (on(0), on(1));
    let other = r.main.other();
    Judged {
        ours: format!("{}: {}; {other}: {}", r.main, m.ours, o.ours),
        verdict: m.verdict.both(o.verdict),
        why: format!(
            "{}; the weaker verdict of the two placements ({}: {}, {other}: {}){}",
            m.why,
            r.main,
            m.verdict.words(),
            o.verdict.words(),
            if o.why == m.why {
                String::new()
            } else {
                format!("; {other}: {}", o.why)
            }
        ),
    }
}

/// The least mean inward alignment that counts as heading for the cloud ("toward" rows and
/// the perception limits: half of a unanimous heading).
const ALIGNED: f64 = 0.5;

fn cloud_toward_on(c: &'static Claim, profile: &[swarm_sim::experiment::RadialPoint]) -> Judged {
    let pts: Vec<&swarm_sim::experiment::RadialPoint> =
        profile.iter().filter(|p| c.covers(p.distance)).collect();
    let v = verdict::profile(
        &pts.iter()
            .map(|p| (p.inward, p.inward_se))
            .collect::<Vec<_>>(),
        ALIGNED,
    );
    let (lo, hi) = c.over.unwrap_or((f64::NAN, f64::NAN));
    let short: Vec<String> = pts
        .iter()
        .filter(|p| p.inward < ALIGNED)
        .map(|p| format!("{} ({})", fixed(p.distance, 2), fixed(p.inward, 2)))
        .collect();
    let lowest = pts.iter().map(|p| p.inward).fold(f64::INFINITY, f64::min);
    Judged {
        ours: format!(
            "{} of {} distances from {lo} to {hi} with mean inward alignment ≥ {ALIGNED} (lowest {})",
            pts.len() - short.len(),
            pts.len(),
            fixed(lowest, 2)
        ),
        verdict: v,
        why: if short.is_empty() {
            format!(
                "the rule: at every distance strictly between {lo} and {hi} the mean inward alignment (the radial profile's) at least {ALIGNED}"
            )
        } else {
            format!(
                "the rule: at every distance strictly between {lo} and {hi} the mean inward alignment (the radial profile's) at least {ALIGNED}; short at {}",
                short.join(", ")
            )
        },
    }
}

/// The level claim `c` judged again on the other placement's averaged course (`m ± se` over
/// `runs` runs): the weaker verdict of the two, and the other placement's value added to ours.
fn other_placement(
    r: &Report<'_>,
    c: &'static Claim,
    mut j: Judged,
    (m, se): (f64, f64),
    runs: String,
    digits: usize,
) -> Judged {
    let paper = c.band().map_or(f64::NAN, |b| b.0);
    let other = verdict::level(m, se, paper, c.tolerance());
    j.ours = format!(
        "{}; {}: {} ± {} ({runs})",
        j.ours,
        r.main.other(),
        fixed(m, digits),
        fixed(se, digits)
    );
    j.why = format!(
        "{}; the weaker verdict of the two placements ({}: {}, {}: {})",
        j.why,
        r.main,
        j.verdict.words(),
        r.main.other(),
        other.words()
    );
    j.verdict = j.verdict.both(other);
    j
}

/// The average diversity at t = 0.
fn start(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = field_of(c.id);
    let course = &r.courses[k][0];
    let first = course.points.first();
    let (m, se) = first.map_or((f64::NAN, f64::NAN), |p| (p.diversity.mean, p.diversity.se));
    let paper = c.band().map_or(f64::NAN, |b| b.0);
    let rel = c.tolerance();
    let noise = [r.sharp, r.gradient][k].run.noise;
    let floor = noise * noise / 12.0;
    let across = fixed(100.0 * course.across_at_start, 0);
    let judged = Judged {
        ours: format!(
            "{}: {} ± {} ({} runs; {}: {}–{})",
            r.main,
            fixed(m, 2),
            fixed(se, 2),
            course.runs,
            band_words(),
            first.map_or("–".into(), |p| fixed(p.diversity.q10, 2)),
            first.map_or("–".into(), |p| fixed(p.diversity.q90, 2)),
        ),
        verdict: verdict::level(m, se, paper, rel),
        why: format!(
            "{}; the noise alone gives {}; {}",
            if m > paper {
                format!(
                    "{across} % of our agents ({}) stand across x = 0 at the start and read the other side",
                    r.settled.start.at_start[k]
                )
            } else {
                format!(
                    "ours is about the noise alone: the {across} % of our agents across x = 0 stand low on the ramp"
                )
            },
            fixed(floor, 2),
            start_against_across(r, k, paper),
        ),
    };
    let o = &r.courses[k][1];
    let (om, ose) = o
        .points
        .first()
        .map_or((f64::NAN, f64::NAN), |p| (p.diversity.mean, p.diversity.se));
    let judged = sensor_both(r, c, judged, |l| l.start, 2);
    other_placement(r, c, judged, (om, ose), format!("{} runs", o.runs), 2)
}

/// A level row judged again under the other sensor model (one reading per agent and period,
/// the settling section): when one model reproduces the claim and the other does not, it
/// depends on that rule; the row's reason gives the other model's value either way.
fn sensor_both(
    r: &Report<'_>,
    c: &'static Claim,
    mut j: Judged,
    pick: fn(&super::results::Levels) -> (f64, f64),
    digits: usize,
) -> Judged {
    let (m, se) = pick(&r.settled.sensor.per_period[field_of(c.id)]);
    let paper = c.band().map_or(f64::NAN, |b| b.0);
    let other = verdict::level(m, se, paper, c.tolerance());
    let reproduced = |v: Verdict| v == Verdict::Reproduced;
    if reproduced(other) != reproduced(j.verdict) {
        j.verdict = Verdict::DependsOnUnspecifiedRule;
    }
    j.why = format!(
        "{}; with one sensor reading per agent and period instead of one per activation: {} ± {} ({})",
        j.why,
        fixed(m, digits),
        fixed(se, digits),
        other.words()
    );
    j
}

/// What the settling section's starts say of the paper's starting diversity: between which
/// counts of agents across (main placement) it lies, or that no count reaches it.
fn start_against_across(r: &Report<'_>, k: usize, paper: f64) -> String {
    let by = if k == 0 {
        &r.settled.start.sharp
    } else {
        &r.settled.start.gradient
    };
    let above = by.iter().position(|&(_, m, _)| m >= paper);
    let count = |n: usize| format!("{n} agent{}", if n == 1 { "" } else { "s" });
    match above {
        Some(0) => format!(
            "with {} across the first period already gives {} (settling section)",
            count(by[0].0),
            fixed(by[0].1, 2)
        ),
        Some(i) => format!(
            "the paper's value lies between what {} and {} across give ({} and {}; settling section)",
            by[i - 1].0,
            count(by[i].0),
            fixed(by[i - 1].1, 2),
            fixed(by[i].1, 2)
        ),
        None => by.last().map_or(String::new(), |&(n, m, _)| {
            format!(
                "no start of the settling section reaches the paper's value: at most {} (with {} across)",
                fixed(m, 2),
                count(n)
            )
        }),
    }
}

/// Periods from the start until the swarm arrives: the paper's one run against our runs' mean.
fn arrival(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = field_of(c.id);
    let course = &r.courses[k][0];
    let at: Vec<f64> = course
        .success_at
        .iter()
        .flatten()
        .map(|&t| f64::from(t))
        .collect();
    let m = stats::mean(&at).unwrap_or(f64::NAN);
    let se = stats::standard_error(&at).unwrap_or(f64::NAN);
    let (q10, q90) = (
        stats::quantile(&at, BAND[0]).unwrap_or(f64::NAN),
        stats::quantile(&at, BAND[1]).unwrap_or(f64::NAN),
    );
    let paper = c.band().map_or(f64::NAN, |b| b.0);
    let rel = c.tolerance();
    let in_spread = (q10..=q90).contains(&paper);
    let judged = Judged {
        ours: format!(
            "{}: {} ± {} (the {} of {} runs that arrived; {}: {}–{})",
            r.main,
            fixed(m, 1),
            fixed(se, 1),
            at.len(),
            course.runs,
            band_words(),
            fixed(q10, 0),
            fixed(q90, 0)
        ),
        verdict: verdict::level(m, se, paper, rel),
        why: format!(
            "the paper's is one run, {} our runs' {} range; {} % of the distance our swarms walk is gained along +x (the averaged courses){}",
            if in_spread { "inside" } else { "outside" },
            band_words(),
            fixed(100.0 * course.straightness, 0),
            if k == 1 {
                arrival_way(r)
            } else {
                String::new()
            }
        ),
    };
    let o = &r.courses[k][1];
    let oat: Vec<f64> = o
        .success_at
        .iter()
        .flatten()
        .map(|&t| f64::from(t))
        .collect();
    let (om, ose) = (
        stats::mean(&oat).unwrap_or(f64::NAN),
        stats::standard_error(&oat).unwrap_or(f64::NAN),
    );
    let runs = format!("the {} of {} runs that arrived", oat.len(), o.runs);
    let judged = sensor_both(r, c, judged, |l| l.arrival, 1);
    other_placement(r, c, judged, (om, ose), runs, 1)
}

/// "rises", "falls" or "changes", as `values` (in order) do.
fn trend_words(values: impl Iterator<Item = f64> + Clone) -> &'static str {
    let v: Vec<f64> = values.collect();
    if v.windows(2).all(|w| w[1] > w[0]) {
        "rises"
    } else if v.windows(2).all(|w| w[1] < w[0]) {
        "falls"
    } else {
        "changes"
    }
}

/// Where the gradient's periods go (settling section).
fn arrival_way(r: &Report<'_>) -> String {
    let a = &r.settled.arrival;
    format!(
        "; {} of our {} runs arrive within the paper's periods (the fastest in {}); they spend {} periods before the ramp and {} on it, {} of them in its last R before the line, where the first move's heading toward +x has faded to {} (settling section)",
        a.within_paper,
        a.arrived,
        fixed(a.fastest, 0),
        fixed(a.before_ramp, 1),
        fixed(a.on_ramp, 1),
        fixed(a.last_r, 1),
        fixed(a.heading_mid_last_r, 2)
    )
}

/// The diversity plateau after arrival.
fn plateau(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = field_of(c.id);
    let (m, se, n) = r.plateaus[k];
    let ours = format!("{} ± {} ({n} runs)", fixed(m, 1), fixed(se, 2));
    match c.kind {
        Kind::Tuned => Judged {
            ours,
            verdict: Verdict::ByConstruction,
            why: format!(
                "the paper gives no slope; ours ({} per R) was chosen to give about {}; it grows with the slope squared (sensitivity below)",
                r.gradient.field.mean(nalgebra::Point2::new(1.0, 0.0))
                    - r.gradient.field.mean(nalgebra::Point2::new(0.0, 0.0)),
                c.values().first().map_or(f64::NAN, |v| v.0)
            ),
        },
        _ => {
            let paper = c.band().map_or(f64::NAN, |b| b.0);
            let rel = c.tolerance();
            let f = &r.settled.plateau;
            let fits = |&&(_, _, m, se): &&(u64, swarm_sim::scenario::Placement, f64, f64)| {
                verdict::level(m, se, paper, rel) == Verdict::Reproduced
            };
            let ours_verdict = verdict::level(m, se, paper, rel);
            // The escape through the cycle the paper does not give works both ways: the row
            // depends on it whenever some cycle tried reproduces the claim and another does
            // not, whether or not ours is among those that do.
            let reproduced = ours_verdict == Verdict::Reproduced;
            let open = f.by_cycle.iter().any(|c| fits(&c) != reproduced);
            let list = f
                .by_cycle
                .iter()
                .filter(|c| c.1 == r.main)
                .map(|c| format!("{} at {} s", fixed(c.2, 2), c.0))
                .collect::<Vec<_>>()
                .join(", ");
            let judged = Judged {
                ours,
                verdict: if open {
                    Verdict::DependsOnUnspecifiedRule
                } else {
                    ours_verdict
                },
                why: format!(
                    "the plateau {} with the cycle length t_p^max, which the paper does not give ({}: {list}; the {} placement within {}); {}; the mean variance per message ({}) and the pooled variance ({}) are farther from the paper's (settling section)",
                    trend_words(f.by_cycle.iter().filter(|c| c.1 == r.main).map(|c| c.2)),
                    r.main,
                    r.main.other(),
                    fixed(
                        f.by_cycle
                            .iter()
                            .filter(|c| c.1 != r.main)
                            .filter_map(|o| {
                                let same =
                                    f.by_cycle.iter().find(|c| c.1 == r.main && c.0 == o.0)?;
                                Some((o.2 - same.2).abs())
                            })
                            .fold(0.0, f64::max),
                        2
                    ),
                    escape_words(open, reproduced, rel, &f.by_cycle, fits),
                    fixed(f.message, 2),
                    fixed(f.pooled, 2)
                ),
            };
            sensor_both(r, c, judged, |l| l.plateau, 2)
        }
    }
}

/// What the cycles tried say of the plateau row: which put it on the other side of the band
/// from ours (`open`), or that none does.
fn escape_words(
    open: bool,
    reproduced: bool,
    rel: f64,
    by_cycle: &[(u64, swarm_sim::scenario::Placement, f64, f64)],
    fits: impl Fn(&&(u64, swarm_sim::scenario::Placement, f64, f64)) -> bool,
) -> String {
    if open && reproduced {
        let not: Vec<String> = by_cycle
            .iter()
            .filter(|c| !fits(c))
            .map(|c| format!("{} s ({})", c.0, c.1))
            .collect();
        format!(
            "outside ± {} % of it with {}",
            fixed(100.0 * rel, 0),
            not.join(", ")
        )
    } else if open {
        let ok: Vec<String> = by_cycle
            .iter()
            .filter(|c| fits(c))
            .map(|c| format!("{} s ({})", c.0, c.1))
            .collect();
        format!(
            "within ± {} % of it with {}",
            fixed(100.0 * rel, 0),
            ok.join(", ")
        )
    } else if reproduced {
        "every cycle tried keeps it within the band".to_string()
    } else {
        "no cycle tried brings it within the band".to_string()
    }
}

/// The verdict on a perception edge `(d, s.e.)` against the claim `id`.
pub(super) fn edge_verdict(edge: Option<(f64, f64)>, id: Id) -> Verdict {
    let c = claim(id);
    verdict::distance(
        edge,
        c.band().unwrap_or((f64::NAN, f64::NAN)),
        c.tolerance(),
    )
}

/// The clouds' distances.
fn cloud(r: &Report<'_>, c: &'static Claim) -> Judged {
    on_both(r, |k| {
        let text = [r.profile, r.other_profile][k];
        let caption = [&r.caption_cloud.profile, &r.caption_cloud.other_profile][k];
        cloud_on(r, c, text, caption)
    })
}

fn cloud_on(
    r: &Report<'_>,
    c: &'static Claim,
    text: &[swarm_sim::experiment::RadialPoint],
    caption: &[swarm_sim::experiment::RadialPoint],
) -> Judged {
    let (d, what) = match c.id {
        Id::CloudLimit => (
            perception_limit(text, ALIGNED),
            format!("where the mean inward alignment last falls through {ALIGNED} going out"),
        ),
        Id::CloudOutward => (
            outward_limit(text),
            "where the mean inward alignment turns from negative to positive going out".into(),
        ),
        _ => (
            perception_limit(caption, ALIGNED),
            format!("where the mean inward alignment last falls through {ALIGNED} going out"),
        ),
    };
    let v = edge_verdict(d, c.id);
    let mut why = format!("{what}, interpolated on the profile's grid, refined around the claim");
    if c.id == Id::CloudOutward {
        let lines = crate::marks::setup_profile(r.cloud);
        if let [start, end, ..] = &lines[..] {
            why.push_str(&format!(
                "; the text's cloud's ramp runs from d = {} to {}, and a swarm between them straddles it",
                start.0, end.0
            ));
        }
    }
    Judged {
        ours: d.map_or("not seen".into(), |(d, se)| {
            format!("{} ± {} R", fixed(d, 2), fixed(se, 2))
        }),
        verdict: v,
        why,
    }
}

/// The discussion's line or cross, run with both rules for an exactly opposite opinion.
fn shapes(r: &Report<'_>, id: Id) -> Judged {
    let s = r.shapes;
    let (name, main, holds) = match id {
        Id::ShapesLine => ("line", &s.key.line, s.line_holds_by_rule),
        _ => ("cross", &s.key.cross, s.cross_holds_by_rule),
    };
    let keep = s
        .keep
        .iter()
        .find(|r| r.name == name)
        .map_or("–".to_string(), |r| r.swarm.clone());
    Judged {
        ours: format!(
            "swarm's direction on its axes: {} turning counter-clockwise (the protocol's rule), {keep} keeping its own bearing",
            main.as_ref().map_or("–".to_string(), |r| r.swarm.clone()),
        ),
        verdict: verdict::open_rule(holds),
        why: format!(
            "an opinion exactly opposite an agent's own (0° against 180°) has no shorter arc, and the paper does not say which way diffusion turns; the claim holds if at least {} of the runs' directions lie within ± {}° of the axes (the shapes section below)",
            s.claim, s.tolerance
        ),
    }
}

/// "N rows: a reproduced, b partly, …" for the page.
pub(super) fn counts(rows: &[Row]) -> String {
    let parts: Vec<String> = Verdict::ALL
        .iter()
        .map(|v| (v, rows.iter().filter(|r| r.kind == *v).count()))
        .filter(|(_, n)| *n > 0)
        .map(|(v, n)| format!("{n} {v}"))
        .collect();
    format!("Of {} rows: {}", rows.len(), parts.join(", "))
}
