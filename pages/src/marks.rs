//! The paper's values drawn on the figures of `swarm reproduce`, with where in the paper each
//! comes from. Every legend text of a paper value starts with "paper". `cimax swarm field`
//! draws the same marks on the maps of built-in scenarios ([`map_for`]).

use super::claims::{CLAIMS, Claim, Figure, Id, Value};
use crate::figures::{MapMark, MapMarks, MapShape, PaperMark, SweepMark};
use swarm_sim::scenario::Scenario;

/// The claims drawn on `figure`, in the table's order, with each mark's legend and value: a
/// claim with several values (text, caption) draws its k-th mark on a figure at its k-th value.
fn drawn_on(figure: Figure) -> impl Iterator<Item = (&'static Claim, &'static str, f64)> {
    CLAIMS.iter().flat_map(move |c| {
        let values = c.values();
        c.drawn
            .iter()
            .filter(move |(f, _)| *f == figure)
            .enumerate()
            .map(move |(k, (_, label))| (c, *label, values.get(k).map_or(f64::NAN, |v| v.0)))
    })
}

/// The paper's marks on the success sweep of the built-in scenario `name` (none for others):
/// a rate over a range of starts is a level (one value) or a band (a range); a rate at one
/// start is a point. Sharp border: Fig. 6 and §3.1; gradient: Fig. 9, §3.2 and §4.
pub fn sweep_for(name: &str) -> Vec<SweepMark> {
    let Some(figure) = builtin_name(name).map(Figure::Sweep) else {
        return Vec::new();
    };
    drawn_on(figure)
        .filter_map(|(c, label, _)| {
            let label = label.to_string();
            match (c.value, c.over?) {
                (Value::At(y), (a, b)) if a == b => Some(SweepMark::Point { x: a, y, label }),
                (Value::At(y), x) => Some(SweepMark::Level { x, y, label }),
                (Value::Range(lo, hi), x) => Some(SweepMark::Band {
                    x,
                    y: (lo, hi),
                    label,
                }),
                _ => None,
            }
        })
        .collect()
}

/// `name` as the `'static` name of a built-in scenario the claims are drawn for.
fn builtin_name(name: &str) -> Option<&'static str> {
    ["sharp", "gradient", "cloud", "cloud-caption"]
        .into_iter()
        .find(|n| *n == name)
}

/// The marks and colours of the direction map of the built-in scenario `name`:
///
/// - sharp (Fig. 7): |x| = 2.5, within which the arrows point at the border, random beyond;
/// - gradient (Fig. 10 and its text): the dashed line at the onset x = 0 (the paper's figure),
///   and x = −2.2 and x = 2.2, the swarm centres between which it heads for +x ("for x < −2.2
///   the swarm moves randomly as it does not perceive the linear gradient", "towards the right
///   up to x = 2.2 where it moves randomly"; the caption rounds both to 2);
/// - cloud (Fig. 11, the text's cloud): d = 4, inside which the swarm heads out, and d = 7
///   (text) and 7.5 (caption), beyond which it moves at random; high X pale yellow as in the
///   paper's text (yellow outside, X ≈ 5; red inside, X ≈ 0);
/// - cloud-caption: the cloud's edge r = 5 (the caption's set-up) and d = 7.5, with the same
///   colours.
///
/// The distances and ranges come from [`CLAIMS`]. Any other name: no marks, the sharp border's
/// colours.
pub fn map(name: &str) -> MapMarks {
    let Some(name) = builtin_name(name) else {
        return MapMarks::default();
    };
    let mut marks = Vec::new();
    if name == "gradient" {
        marks.push(MapMark {
            shape: MapShape::XLines(vec![0.0]),
            label: "paper: onset of the rise, x = 0 (its dashed line)".into(),
        });
    }
    if name == "cloud-caption" {
        marks.push(MapMark {
            shape: MapShape::Circle {
                centre: (0.0, 0.0),
                radius: 5.0,
            },
            label: "paper (caption): the cloud's edge, r = 5".into(),
        });
    }
    let is_cloud = name.starts_with("cloud");
    // A claim with several values draws one mark per value, in order, one legend each.
    for (c, label, radius) in drawn_on(Figure::Map(name)) {
        let shape = if is_cloud {
            MapShape::Circle {
                centre: (0.0, 0.0),
                radius,
            }
        } else {
            let (a, b) = c.over.unwrap_or_default();
            MapShape::XLines(vec![a, b])
        };
        marks.push(MapMark {
            shape,
            label: label.into(),
        });
    }
    MapMarks {
        marks,
        high_is_yellow: is_cloud,
    }
}

/// The marks of [`map`] for `scn` if it is a built-in scenario with the built-in's field; none
/// (and the sharp border's colours) for any other, even one that borrows a built-in's name.
pub fn map_for(scn: &Scenario) -> MapMarks {
    match Scenario::builtin(&scn.name) {
        Some(b) if b.field == scn.field => map(&scn.name),
        _ => MapMarks::default(),
    }
}

/// The paper's marks on the averaged time course of `name` (Figs. 5b, 8b): the starting
/// diversity as a point at t = 0, each plateau as a line.
pub fn course(name: &str) -> Vec<PaperMark> {
    let Some(name) = builtin_name(name) else {
        return Vec::new();
    };
    drawn_on(Figure::Course(name))
        .map(|(c, label, value)| PaperMark {
            value,
            label: label.into(),
            at_start: matches!(c.id, Id::SharpStart | Id::GradientStart),
        })
        .collect()
}

/// The paper's perception edges on the figure of the first move's heading against the start:
/// (x, legend), x < 0 (the starts lie left of the border).
pub fn extent() -> Vec<(f64, &'static str)> {
    drawn_on(Figure::Extent)
        .map(|(_, label, d)| (-d, label))
        .collect()
}

/// The paper's distances on a cloud's radial profile (`cloud` or `cloud-caption`), with their
/// legends, before the set-up's own lines.
pub fn profile(name: &str) -> Vec<(f64, String)> {
    let Some(name) = builtin_name(name) else {
        return Vec::new();
    };
    drawn_on(Figure::Profile(name))
        .map(|(_, label, d)| (d, label.to_string()))
        .collect()
}

/// Every line on the radial profile of the cloud scenario `scn`: the paper's distances and the
/// set-up's own ([`setup_profile`]), by distance.
pub fn profile_lines(scn: &Scenario) -> Vec<(f64, String)> {
    let mut lines = profile(&scn.name);
    lines.extend(setup_profile(scn));
    lines.sort_by(|a, b| a.0.total_cmp(&b.0));
    lines
}

/// The radius of `scn`'s swarm: the farthest agent from the centre of a lattice, half the
/// diameter of a disk, half the diagonal of a rectangle.
pub fn swarm_radius(scn: &Scenario) -> f64 {
    use swarm_sim::geometry::{Shape, lattice};
    match scn.shape {
        Shape::Disk { diameter } => diameter / 2.0,
        Shape::Rectangle { width, height } => 0.5 * width.hypot(height),
        Shape::Lattice { spacing } => lattice(scn.agents, spacing)
            .iter()
            .map(|v| v.norm())
            .fold(0.0, f64::max),
    }
}

/// The outer edge of a cloud scenario's radial layer and the swarm's radius: a swarm up to
/// their sum from the centre still has an agent on the cloud. `None` without a radial layer.
pub fn cloud_reach(scn: &Scenario) -> Option<(f64, f64)> {
    use hal_emu::world::field::Along;
    let edge = scn
        .field
        .layers
        .iter()
        .filter(|l| matches!(l.along, Along::Radial { .. }))
        .flat_map(|l| l.segments.iter().map(|s| s.from))
        .filter(|d| d.is_finite() && *d > 0.0)
        .reduce(f64::max)?;
    Some((edge, swarm_radius(scn)))
}

/// The set-up's own lines on the radial profile of a cloud scenario, from its field and swarm:
/// where each ramp of the radial layer starts and ends, and the farthest distance from which
/// the swarm still has an agent on the cloud (its outer edge plus the swarm's radius).
pub fn setup_profile(scn: &Scenario) -> Vec<(f64, String)> {
    use hal_emu::world::field::Along;
    let mut lines = Vec::new();
    for layer in &scn.field.layers {
        if !matches!(layer.along, Along::Radial { .. }) {
            continue;
        }
        let mut rising = false;
        for seg in &layer.segments {
            if seg.from.is_finite() && seg.from > 0.0 {
                let what = match (rising, seg.slope != 0.0) {
                    (false, true) => "the ramp starts",
                    (true, false) => "the ramp ends, the cloud's edge",
                    _ => "the level changes",
                };
                lines.push((seg.from, format!("d = {}: {what}", seg.from)));
            }
            rising = seg.slope != 0.0;
        }
    }
    if let Some((edge, r)) = cloud_reach(scn) {
        let d = edge + r;
        lines.push((
            d,
            format!(
                "d = {}: {edge} + the swarm's radius {}, the farthest with an agent on the cloud",
                report::csv_files::fixed(d, 1),
                report::csv_files::fixed(r, 1)
            ),
        ));
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweeps_carry_the_papers_level_band_and_point() {
        assert!(matches!(
            sweep_for("sharp")[..],
            [SweepMark::Level {
                x: (-2.5, 2.5),
                y: 1.0,
                ..
            }]
        ));
        let marks = sweep_for("gradient");
        assert!(marks.iter().any(|m| matches!(
            m,
            SweepMark::Band { x, y, label }
                if *x == (-2.0, 2.33) && *y == (0.85, 1.0) && label.starts_with("paper")
        )));
        assert!(marks.iter().any(|m| matches!(
            m,
            SweepMark::Point { x, y, label }
                if *x == -4.0 && *y == 0.25 && label.starts_with("paper")
        )));
        assert!(sweep_for("cloud").is_empty() && sweep_for("mine").is_empty());
    }

    #[test]
    fn maps_mark_the_papers_edges_and_the_clouds_swap_colours() {
        let xs = |name: &str| -> Vec<f64> {
            map(name)
                .marks
                .into_iter()
                .flat_map(|m| match m.shape {
                    MapShape::XLines(xs) => xs,
                    MapShape::Circle { radius, .. } => vec![radius],
                })
                .collect()
        };
        assert_eq!(xs("sharp"), [-2.5, 2.5]);
        assert_eq!(xs("gradient"), [0.0, -2.2, 2.2]);
        assert_eq!(xs("cloud"), [7.0, 7.5, 4.0]);
        assert_eq!(xs("cloud-caption"), [5.0, 7.5]);
        for name in ["sharp", "gradient", "cloud", "cloud-caption"] {
            let m = map(name);
            assert!(
                m.marks.iter().all(|m| m.label.starts_with("paper")),
                "{name}"
            );
            assert_eq!(m.high_is_yellow, name.starts_with("cloud"), "{name}");
        }
        assert_eq!(map("other"), MapMarks::default());
        let cloud = Scenario::builtin("cloud").unwrap();
        assert_eq!(map_for(&cloud), map("cloud"));
        let mut borrowed = cloud.clone();
        borrowed.field = Scenario::builtin("sharp").unwrap().field;
        assert_eq!(map_for(&borrowed), MapMarks::default());
    }

    #[test]
    fn courses_profiles_and_the_extent_come_from_the_claims() {
        let sharp: Vec<(f64, bool)> = course("sharp")
            .iter()
            .map(|m| (m.value, m.at_start))
            .collect();
        assert_eq!(sharp, [(0.2, true), (4.5, false)]);
        let gradient: Vec<f64> = course("gradient").iter().map(|m| m.value).collect();
        assert_eq!(gradient, [0.3, 8.0, 20.0]);
        let d: Vec<f64> = profile("cloud").iter().map(|p| p.0).collect();
        assert_eq!(d, [7.0, 7.5, 4.0]);
        assert_eq!(extent(), [(-2.5, " paper: 2.5 R"), (-2.2, " paper: 2.2 R")]);
    }

    #[test]
    fn the_set_up_lines_of_a_profile_come_from_the_field_and_the_swarm() {
        let cloud = Scenario::builtin("cloud").unwrap();
        let lines = setup_profile(&cloud);
        let d: Vec<f64> = lines.iter().map(|l| l.0).collect();
        // The text's cloud: a ramp from 3 to 4.5; a 6 R disk reaches 3 R farther.
        assert_eq!(d, [3.0, 4.5, 7.5]);
        assert!(lines[0].1.contains("ramp starts") && lines[1].1.contains("ramp ends"));
        let caption = Scenario::builtin("cloud-caption").unwrap();
        let d: Vec<f64> = setup_profile(&caption).iter().map(|l| l.0).collect();
        assert_eq!(d, [5.0, 8.0]);
        assert!(setup_profile(&Scenario::builtin("sharp").unwrap()).is_empty());
    }
}
