//! The paper's values drawn on the figures of `swarm reproduce`, with where in the paper each
//! comes from. Every legend text of a paper value starts with "paper". `cimax swarm field`
//! draws the same marks on the maps of built-in scenarios ([`map_for`]).

use crate::report::plot::{MapMark, MapMarks, MapShape, SweepMark};
use crate::swarm::scenario::Scenario;

/// Fig. 5 and the text of section 3.1: success rate 1 for |x_init| < 2.5 R.
pub fn sharp_sweep() -> Vec<SweepMark> {
    vec![SweepMark::Level {
        x: (-2.5, 2.5),
        y: 1.0,
        label: "paper: 1.0 for |x_init| < 2.5 R".into(),
    }]
}

/// Fig. 8 and sections 3.2 and 4: 85–100 % for −2 ≲ x_init < 2.33 ("the success rates vary
/// between 85 % to 100 %"), and 25 % at x_init = −4.
pub fn gradient_sweep() -> Vec<SweepMark> {
    vec![
        SweepMark::Band {
            x: (-2.0, 2.33),
            y: (0.85, 1.0),
            label: "paper: 85–100 % for −2 ≤ x_init < 2.33".into(),
        },
        SweepMark::Point {
            x: -4.0,
            y: 0.25,
            label: "paper: 25 % at x_init = −4".into(),
        },
    ]
}

/// The paper's marks on the success sweep of the built-in scenario `name` (none for others).
pub fn sweep_for(name: &str) -> Vec<SweepMark> {
    match name {
        "sharp" => sharp_sweep(),
        "gradient" => gradient_sweep(),
        _ => Vec::new(),
    }
}

/// Vertical lines at `xs`.
fn lines(xs: &[f64], label: &str) -> MapMark {
    MapMark {
        shape: MapShape::XLines(xs.to_vec()),
        label: label.into(),
    }
}

/// A circle of radius `radius` around the origin (the clouds' centre).
fn circle(radius: f64, label: &str) -> MapMark {
    MapMark {
        shape: MapShape::Circle {
            centre: (0.0, 0.0),
            radius,
        },
        label: label.into(),
    }
}

/// The marks and colours of the direction map of the built-in scenario `name`:
///
/// - sharp (Fig. 6): |x| = 2.5, within which the arrows point at the border, random beyond;
/// - gradient (Fig. 9 and its text): the dashed line at the onset x = 0, and x = −2.2 and
///   x = 2.2, the swarm centres between which it heads for +x ("for x < −2.2 the swarm moves
///   randomly as it does not perceive the linear gradient", "towards the right up to x = 2.2
///   where it moves randomly"; the caption rounds both to 2);
/// - cloud (Fig. 10, the text's cloud): d = 4, inside which the swarm heads out, and d = 7
///   (text) and 7.5 (caption), beyond which it moves at random; high X pale yellow as in the
///   paper's text (yellow outside, X ≈ 5; red inside, X ≈ 0);
/// - cloud-caption: the cloud's edge r = 5 and d = 7.5, with the same colours.
///
/// Any other name: no marks, the sharp border's colours.
pub fn map(name: &str) -> MapMarks {
    match name {
        "sharp" => MapMarks {
            marks: vec![lines(
                &[-2.5, 2.5],
                "paper: |x| = 2.5 R, toward the border inside, random beyond",
            )],
            high_is_yellow: false,
        },
        "gradient" => MapMarks {
            marks: vec![
                lines(&[0.0], "paper: onset of the rise, x = 0 (its dashed line)"),
                lines(
                    &[-2.2],
                    "paper: x = −2.2, random below (gradient out of sight)",
                ),
                lines(
                    &[2.2],
                    "paper: x = 2.2, random beyond (swarm on the gradient)",
                ),
            ],
            high_is_yellow: false,
        },
        "cloud" => MapMarks {
            marks: vec![
                circle(4.0, "paper (text): d = 4, heads out inside"),
                circle(7.0, "paper (text): d = 7, random beyond"),
                circle(7.5, "paper (caption): d = 7.5, random beyond"),
            ],
            high_is_yellow: true,
        },
        "cloud-caption" => MapMarks {
            marks: vec![
                circle(5.0, "paper (caption): the cloud's edge, r = 5"),
                circle(7.5, "paper (caption): d = 7.5, random beyond"),
            ],
            high_is_yellow: true,
        },
        _ => MapMarks::default(),
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

/// Marker lines of the text's cloud's radial profile: its ramp and the paper's distances.
pub(super) const CLOUD_PROFILE: [(f64, &str); 5] = [
    (3.0, "d = 3: the ramp starts"),
    (4.0, "paper (text): d = 4, heads out inside"),
    (4.5, "d = 4.5: the ramp ends"),
    (7.0, "paper (text): d = 7, random beyond"),
    (
        7.5,
        "paper (caption): d = 7.5, random beyond; = 4.5 + swarm radius",
    ),
];

/// Marker lines of the caption's cloud's radial profile: its edge, the paper's distance and
/// the farthest a swarm can be with an agent on the ramp.
pub(super) const CAPTION_PROFILE: [(f64, &str); 3] = [
    (5.0, "d = 5: the cloud's edge"),
    (7.5, "paper (caption): d = 7.5, random beyond"),
    (8.0, "d = 8 = 5 + swarm radius"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gradient_sweep_carries_the_papers_band_and_its_25_percent_at_minus_4() {
        let marks = gradient_sweep();
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
        assert!(matches!(
            sharp_sweep()[..],
            [SweepMark::Level {
                x: (-2.5, 2.5),
                y: 1.0,
                ..
            }]
        ));
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
        assert_eq!(xs("cloud"), [4.0, 7.0, 7.5]);
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
}
