//! The caption of Fig. 11: "for d ≲ 7.5 the swarm consistently moves towards the border
//! between the two domains". The border of the caption's cloud is its edge (radius 5), so
//! heading for the border means heading out inside it and in outside it: the radial profile's
//! inward alignment, its sign turned inside the edge.

use std::path::Path;

use serde::Serialize;

use super::{pm, write_csv};
use crate::claims::{Id, claim};
use crate::marks;
use report::csv_files::fixed;
use report::plot::{self, Line};
use swarm_sim::experiment::{Error, RadialPoint};

use super::super::caption_cloud::CaptionCloud;

/// Mean alignment that counts as heading for the border (the page's threshold elsewhere).
const THRESHOLD: f64 = 0.5;

/// Heading for the border, as the comparison judges it.
pub(in super::super) struct TowardBorder {
    /// The edge (the border), R.
    pub(in super::super) edge: f64,
    /// The claim's reach, R.
    pub(in super::super) reach: f64,
    /// Per profile distance below the reach: `(d, mean alignment toward the border, s.e.)`.
    pub(in super::super) points: Vec<(f64, f64, f64)>,
    /// Where the alignment turns from toward the border to away from it going out inside the
    /// cloud: where the swarm's centre settles ([`swarm_sim::stats::crossing`]).
    pub(in super::super) settles_at: Option<(f64, f64)>,
    /// The least alignment [`crate::verdict::profile`] asks for.
    pub(in super::super) threshold: f64,
}

/// The part of the section the template sees.
#[derive(Serialize)]
pub(super) struct CaptionPart {
    runs: u32,
    edge: String,
    reach: String,
    threshold: String,
    /// Per distance: d, alignment toward the border.
    rows: Vec<Vec<String>>,
    toward: String,
    short: String,
    /// Where the centre settles inside the cloud (± s.e.), the distances inside between which
    /// the swarm heads away from the border, and the swarm's radius.
    settles_at: Option<String>,
    away: Option<[String; 2]>,
    radius: String,
    /// The distances outside the edge below the reach with the alignment at least the
    /// threshold: the nearest and farthest.
    outside: Option<[String; 2]>,
}

/// The nearest and farthest distance of `points`.
fn span<'a>(points: impl Iterator<Item = &'a (f64, f64, f64)>) -> Option<[String; 2]> {
    let (lo, hi) = points.fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    (lo <= hi).then(|| [fixed(lo, 2), fixed(hi, 2)])
}

/// Reads the caption's cloud's radial profile (run by its own section); writes
/// `settle-caption.{csv,svg}`.
///
/// # Errors
/// If the scenario is missing or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    cloud: &CaptionCloud,
) -> Result<(CaptionPart, [TowardBorder; 2]), Error> {
    let scn = super::super::builtin_placed("cloud-caption", cloud.placement)?;
    let (edge, _) = marks::cloud_reach(&scn).ok_or(super::super::WriteError::NoEdge)?;
    let reach = claim(Id::CaptionToward)
        .values()
        .first()
        .map_or(f64::NAN, |v| v.0);
    let paper_mark = format!("paper: d ≲ {reach}");
    let judged = toward_border(&cloud.profile, edge, reach);
    let other = toward_border(&cloud.other_profile, edge, reach);
    let toward = judged.points.clone();
    let rows: Vec<Vec<String>> = toward
        .iter()
        .map(|&(d, m, se)| vec![fixed(d, 2), pm(m, se, 2)])
        .collect();
    write_csv(
        figs,
        "settle-caption.csv",
        &["distance", "toward_border"],
        &rows,
    )?;
    plot::xy_figure(
        &figs.join("settle-caption.svg"),
        &format!("caption's cloud: heading for its border (radius {edge}) against the distance"),
        "distance of the swarm's centre from the cloud's centre / R",
        "mean alignment toward the border",
        &[Line {
            label: "mean cos(direction − direction to the nearest point of the border)".into(),
            points: toward.clone(),
        }],
        (-1.05, 1.05),
        &[
            (edge, "the border (the cloud's edge)"),
            (reach, &paper_mark),
        ],
        false,
    )?;
    let short: Vec<String> = toward
        .iter()
        .filter(|t| t.1 < THRESHOLD)
        .map(|t| fixed(t.0, 2))
        .collect();
    let part = CaptionPart {
        runs: super::super::PROFILE_RUNS,
        edge: fixed(edge, 1),
        reach: fixed(reach, 1),
        threshold: fixed(THRESHOLD, 1),
        rows,
        toward: format!("{} of {}", toward.len() - short.len(), toward.len()),
        short: short.join(", "),
        settles_at: judged.settles_at.map(|(d, se)| super::pm(d, se, 2)),
        away: span(toward.iter().filter(|t| t.0 < edge && t.1 < 0.0)),
        radius: fixed(marks::swarm_radius(&scn), 1),
        outside: span(toward.iter().filter(|t| t.0 >= edge && t.1 >= THRESHOLD)),
    };
    Ok((part, [judged, other]))
}

/// The alignment toward the border (at `edge`) of a radial profile below the claim's `reach`.
fn toward_border(profile: &[RadialPoint], edge: f64, reach: f64) -> TowardBorder {
    let points: Vec<(f64, f64, f64)> = profile
        .iter()
        .filter(|p| p.distance > 0.0 && p.distance < reach)
        .map(|p| {
            let sign = if p.distance < edge { -1.0 } else { 1.0 };
            (p.distance, sign * p.inward, p.inward_se)
        })
        .collect();
    let inside: Vec<(f64, f64, f64)> = points.iter().copied().filter(|t| t.0 < edge).collect();
    TowardBorder {
        edge,
        reach,
        settles_at: swarm_sim::stats::crossing(&inside, 0.0, false),
        points,
        threshold: THRESHOLD,
    }
}
