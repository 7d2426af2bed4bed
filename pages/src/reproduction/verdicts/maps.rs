//! The summary table's rows read off the direction maps and the first move's heading against
//! the start (the perception edges), where the two views of one fact share a verdict.

use super::{Judged, Report, edge_verdict, field_of};
use crate::claims::{Claim, Id, Kind, claim};
use crate::verdict::{self, CONE_DEG, Heading, Verdict};
use report::csv_files::fixed;
use swarm_sim::experiment::Arrow;
use swarm_sim::stats;

/// "Random for x < −2.2" on the gradient map is the same fact as the gradient's perception
/// edge (`GradientEdge`): as [`sharp_map_far`], the weaker of the two verdicts.
pub(super) fn gradient_map_left(r: &Report<'_>, c: &'static Claim) -> Judged {
    with_edge(r, c, Id::GradientEdge)
}

/// The bearing an arrow at `at` should point in: at the border (sharp) or toward +x
/// (gradient).
pub(super) fn target(sharp: bool, a: &Arrow) -> f64 {
    if sharp && a.at.x > 0.0 {
        std::f64::consts::PI
    } else {
        0.0
    }
}

/// Arrows of a direction map inside a claim's range, counted inside the ±45° cone around
/// their target, with the mean cosine to it (an arrow without a direction counts 0); the map
/// of each placement, the weaker verdict.
pub(super) fn directions(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = if field_of(c.id) == 0 { 0 } else { 1 };
    let toward = matches!(c.kind, Kind::Direction { toward: true });
    let rule = match (toward, k == 0) {
        _ if c.id == Id::GradientMapLeft => {
            format!("the rule: about a quarter within ±{CONE_DEG}°, as uniform directions give")
        }
        (true, _) => format!(
            "the rule: at least {} % of the arrows within ±{CONE_DEG}° of the target direction",
            fixed(100.0 * verdict::TOWARD_SHARE, 0)
        ),
        (false, true) => format!(
            "the rule: about a quarter within ±{CONE_DEG}°, as uniform directions give; at the map's first column beyond the claim our swarm (radius {} R) still touches the border, so those arrows point at it",
            fixed(crate::marks::swarm_radius(r.sharp), 1)
        ),
        (false, false) => format!(
            "the rule: about a quarter within ±{CONE_DEG}°, as uniform directions give; past the ramp's start the swarm prefers the direction in which it extends farthest along the ramp"
        ),
    } + &format!(
        " (the {other} placement's maps in figures/*-field-{other}.svg)",
        other = r.main.other()
    );
    super::on_both(r, |side| {
        let (verdict, ours) = on_map(&[r.maps, r.other_maps][side][k], c);
        Judged {
            ours,
            verdict,
            why: rule.clone(),
        }
    })
}

/// One map's verdict on claim `c`, and what it shows.
fn on_map(arrows: &[Arrow], c: &'static Claim) -> (verdict::Verdict, String) {
    let sharp = field_of(c.id) == 0;
    let (a, b) = c.over.unwrap_or_default();
    let far = matches!(c.id, Id::SharpMapFar | Id::GradientMapFar);
    let left = c.id == Id::GradientMapLeft;
    let keep = |x: f64| match (sharp, far) {
        _ if left => x < b - 1e-9,
        (true, false) => x != 0.0 && x.abs() <= b + 1e-9,
        (true, true) => x.abs() > b + 1e-9,
        (false, false) => x > a - 1e-9 && x < b + 1e-9,
        (false, true) => x > a + 1e-9,
    };
    let sel: Vec<&Arrow> = arrows.iter().filter(|a| keep(a.at.x)).collect();
    let cos: Vec<f64> = sel
        .iter()
        .map(|a| a.direction.map_or(0.0, |d| (d - target(sharp, a)).cos()))
        .collect();
    let cone = CONE_DEG.to_radians().cos();
    let inside = cos.iter().filter(|&&c| c >= cone - 1e-12).count();
    let half = cos.iter().filter(|&&c| c > 0.0).count();
    let toward = matches!(c.kind, Kind::Direction { toward: true });
    let heading = if toward {
        Heading::Toward {
            share: verdict::TOWARD_SHARE,
        }
    } else {
        Heading::Random
    };
    let v = verdict::direction(inside, sel.len(), heading);
    let mean_cos = stats::mean(&cos).unwrap_or(f64::NAN);
    (
        v,
        format!(
            "{inside} of {} within ±{CONE_DEG}°, mean cos {}, {half} with a component toward it",
            sel.len(),
            fixed(mean_cos, 2)
        ),
    )
}

/// "Random beyond 2.5 R" on the sharp map is the same fact as the sharp border's perception
/// edge (`SharpEdge`: where the first move stops heading for the border): one computation,
/// two views. The map's arrows are judged as for any "random" claim, the edge as its own row
/// does, and the row gets the weaker verdict, so the two rows cannot contradict each other.
pub(super) fn sharp_map_far(r: &Report<'_>, c: &'static Claim) -> Judged {
    with_edge(r, c, Id::SharpEdge)
}

/// The map row `c` and the perception edge `edge` (one fact, two views): the map's verdict and
/// the edge row's, the weaker of the two.
fn with_edge(r: &Report<'_>, c: &'static Claim, edge_id: Id) -> Judged {
    let mut j = directions(r, c);
    let e = edge(r, claim(edge_id));
    j.why = format!(
        "{}; the same fact as the perception edge's row (where the first move stops heading for the border: {}, {}), so the weaker of the two verdicts (map: {}, edge: {})",
        j.why,
        e.ours,
        e.verdict.words(),
        j.verdict.words(),
        e.verdict.words()
    );
    j.verdict = j.verdict.both(e.verdict);
    j
}

/// The farthest start from which the first move heads for the border, both extents; the
/// page's extent with both placements, the weaker verdict.
pub(super) fn edge(r: &Report<'_>, c: &'static Claim) -> Judged {
    let k = field_of(c.id);
    let big = &r.sensitivity.extent[2 * k];
    let small = &r.sensitivity.extent[2 * k + 1];
    let other = r.sensitivity.extent.get(4 + k);
    let vo = other.map_or(Verdict::NotReproduced, |o| edge_verdict(o.edge_se, c.id));
    let v = edge_verdict(big.edge_se, c.id).both(vo);
    let show = |e: Option<(f64, f64)>| {
        e.map_or("none".into(), |(d, se)| {
            format!("{} ± {} R", fixed(d, 2), fixed(se, 2))
        })
    };
    Judged {
        ours: format!(
            "{} ({} R swarm, {}); {} ({}); {} for a {} R one",
            show(big.edge_se),
            big.diameter,
            big.placement,
            show(other.and_then(|o| o.edge_se)),
            other.map_or("–", |o| o.placement.as_str()),
            show(small.edge_se),
            small.diameter
        ),
        verdict: v,
        why: format!(
            "where the mean heading toward the border falls through {}, interpolated on the starts' grid, refined around the claim; the smaller swarm's edge is {}",
            crate::reproduction::sensitivity::EDGE_LEVEL,
            match (big.edge_se, small.edge_se) {
                (Some(b), Some(s)) if s.0 < b.0 => "shorter",
                (Some(_), Some(_)) => "not shorter",
                _ => "missing",
            }
        ),
    }
}
