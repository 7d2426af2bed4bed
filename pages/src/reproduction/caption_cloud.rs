//! The cloud of Fig. 11's caption (`cloud-caption`: radius 5, X rising linearly from 0 at the
//! centre to 5 at the edge, noise in [0, 1)) beside the text's (`cloud`): its direction map
//! and radial profile, their figures and CSV files, and the numbers the page compares.

use std::path::Path;

use serde::Serialize;

use super::{outward_limit, perception_limit};
use crate::csv::{write_field_csv, write_radial_csv};
use crate::figures;
use crate::marks;
use report::csv_files::fixed;
use reproduce::results::Results;
use reproduce::units::{Side, Unit};
use reproduce::{PROFILE_RUNS, builtin_placed};
use swarm_sim::experiment::{Arrow, Error, RadialPoint};
use swarm_sim::scenario::Placement;

/// Mean inward alignment that counts as heading in (and its negative as heading out), as for
/// the text's cloud.
const THRESHOLD: f64 = 0.5;

/// The map's rings (d from, to: `from < d ≤ to`) whose arrows should point toward the centre
/// (outside the caption's ramp, within reach) and away from it (inside the ramp).
const INWARD_RING: [f64; 2] = [5.0, 7.0];
const OUTWARD_RING: [f64; 2] = [0.0, 4.0];

/// The caption's cloud's results.
pub(super) struct CaptionCloud {
    /// One arrow per grid point.
    pub(super) arrows: Vec<Arrow>,
    /// Inward alignment against distance.
    pub(super) profile: Vec<RadialPoint>,
    /// The same with the other placement.
    pub(super) other_profile: Vec<RadialPoint>,
    /// The placement its swarm had.
    pub(super) placement: Placement,
}

/// Writes `cloud-caption-field.{csv,svg}` and `cloud-caption-profile.{csv,svg}` from the
/// caption's cloud's units (run with the `main` placement); its results.
///
/// # Errors
/// If a unit has no result or a file cannot be written.
pub(super) fn write(
    figs: &Path,
    main: Placement,
    results: &Results,
) -> Result<CaptionCloud, Error> {
    let scn = builtin_placed("cloud-caption", main)?;
    let grid = scn.grid.as_ref().ok_or(super::WriteError::NoGrid)?;
    let arrows = results.map(Unit::CaptionMap)?;
    write_field_csv(&figs.join("cloud-caption-field.csv"), arrows)?;
    figures::direction_figure(
        &figs.join("cloud-caption-field.svg"),
        &scn,
        grid,
        arrows,
        &marks::map(&scn.name),
    )?;
    let profile = results.profile(Unit::CaptionProfile(Side::Main))?;
    let other_profile = results.profile(Unit::CaptionProfile(Side::Other))?;
    write_radial_csv(
        &figs.join(format!("cloud-caption-profile-{}.csv", main.other())),
        other_profile,
    )?;
    write_radial_csv(&figs.join("cloud-caption-profile.csv"), profile)?;
    figures::radial_figure(
        &figs.join("cloud-caption-profile.svg"),
        &format!(
            "caption's cloud: heading of a swarm against its distance from the centre, {PROFILE_RUNS} runs per point"
        ),
        profile,
        &marks::profile_lines(&scn),
    )?;
    Ok(CaptionCloud {
        arrows: arrows.clone(),
        profile: profile.clone(),
        other_profile: other_profile.clone(),
        placement: main,
    })
}

/// The caption's cloud on the page (`reproduction/cloud_caption.md.j2`), every number
/// formatted; distances in R.
#[derive(Serialize)]
pub(super) struct CaptionSection {
    /// Runs per distance of the profile.
    runs: u32,
    /// The alignment the heading limits are read at ([`THRESHOLD`]).
    threshold: String,
    /// [`INWARD_RING`] and [`OUTWARD_RING`].
    rings: [[String; 2]; 2],
    /// Where the mean inward alignment last falls through 0.5 ([`perception_limit`]).
    limit: Option<String>,
    /// Where the mean inward alignment first turns positive going out ([`outward_limit`]).
    outward: Option<String>,
    /// The nearest and farthest distance with mean inward alignment ≥ 0.5.
    inward: Option<[String; 2]>,
    /// The strongest mean outward alignment (most negative) and its distance.
    most_outward: [String; 2],
    /// The text's cloud's [`perception_limit`] and [`outward_limit`], for the comparison.
    text_limit: Option<String>,
    text_outward: Option<String>,
    /// The caption cloud's edge, the swarm's radius and their sum ([`super::reach`]).
    reach: [String; 3],
    /// Arrows of the map with a component toward the centre, among those with 5 < d ≤ 7.
    map_inward: String,
    /// Arrows of the map with a component away from the centre, among those with 0 < d ≤ 4.
    map_outward: String,
}

/// Whether `from < d ≤ to` (to rounding).
fn in_ring([from, to]: [f64; 2], d: f64) -> bool {
    d > from + 1e-9 && d <= to + 1e-9
}

/// Arrows with `keep(d)` (d: distance from the centre) pointing toward (`toward`) or away
/// from the centre: `ok of n`.
fn radial_arrows(arrows: &[Arrow], keep: impl Fn(f64) -> bool, toward: bool) -> String {
    let sel: Vec<&Arrow> = arrows.iter().filter(|a| keep(a.at.coords.norm())).collect();
    let ok = sel
        .iter()
        .filter(|a| {
            a.direction.is_some_and(|th| {
                let radial = th.cos() * a.at.x + th.sin() * a.at.y;
                if toward { radial < 0.0 } else { radial > 0.0 }
            })
        })
        .count();
    format!("{ok} of {}", sel.len())
}

/// The page's numbers for the caption's cloud `c`, beside the text's cloud's `text_profile`.
pub(super) fn section(
    c: &CaptionCloud,
    text_profile: &[RadialPoint],
) -> Result<CaptionSection, Error> {
    let inward: Vec<f64> = c
        .profile
        .iter()
        .filter(|p| p.inward >= THRESHOLD)
        .map(|p| p.distance)
        .collect();
    let most_outward = c
        .profile
        .iter()
        .min_by(|a, b| a.inward.total_cmp(&b.inward))
        .map_or([String::from("–"), String::from("–")], |p| {
            [fixed(p.inward, 2), fixed(p.distance, 1)]
        });
    Ok(CaptionSection {
        reach: super::page::reach(&builtin_placed("cloud-caption", c.placement)?),
        runs: PROFILE_RUNS,
        threshold: THRESHOLD.to_string(),
        rings: [INWARD_RING, OUTWARD_RING].map(|r| r.map(|d| d.to_string())),
        limit: perception_limit(&c.profile, THRESHOLD).map(|d| fixed(d.0, 1)),
        outward: outward_limit(&c.profile).map(|d| fixed(d.0, 1)),
        inward: inward
            .first()
            .zip(inward.last())
            .map(|(a, b)| [fixed(*a, 1), fixed(*b, 1)]),
        most_outward,
        text_limit: perception_limit(text_profile, THRESHOLD).map(|d| fixed(d.0, 1)),
        text_outward: outward_limit(text_profile).map(|d| fixed(d.0, 1)),
        map_inward: radial_arrows(&c.arrows, |d| in_ring(INWARD_RING, d), true),
        map_outward: radial_arrows(&c.arrows, |d| in_ring(OUTWARD_RING, d), false),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    fn point(distance: f64, inward: f64) -> RadialPoint {
        RadialPoint {
            distance,
            runs: 40,
            inward,
            inward_se: 0.0,
        }
    }

    #[test]
    fn the_section_reads_the_limits_off_the_profile() {
        let profile: Vec<RadialPoint> = [
            (0.0, 0.0),
            (1.0, -0.8),
            (2.0, -0.6),
            (3.0, 0.4),
            (5.0, 0.9),
            (7.0, 0.6),
            (7.5, 0.1),
            (8.0, 0.3),
        ]
        .into_iter()
        .map(|(d, v)| point(d, v))
        .collect();
        let arrows = vec![
            Arrow {
                at: Point2::new(6.0, 0.0),
                direction: Some(std::f64::consts::PI),
                consensus: 1.0,
                decided: 61,
            },
            Arrow {
                at: Point2::new(0.0, 2.0),
                direction: Some(std::f64::consts::FRAC_PI_2),
                consensus: 1.0,
                decided: 61,
            },
        ];
        let s = section(
            &CaptionCloud {
                arrows,
                profile,
                other_profile: Vec::new(),
                placement: Placement::Lattice,
            },
            &[point(0.0, 1.0)],
        )
        .unwrap();
        // Falls through 0.5 between 7 (0.6) and 7.5 (0.1); turns positive between 2 and 3.
        assert_eq!(s.limit.as_deref(), Some("7.1"));
        assert_eq!(s.outward.as_deref(), Some("2.6"));
        assert_eq!(s.inward, Some(["5.0".into(), "7.0".into()]));
        assert_eq!(s.most_outward, ["-0.80".to_string(), "1.0".to_string()]);
        assert_eq!(s.text_limit, None);
        assert_eq!(
            (s.map_inward.as_str(), s.map_outward.as_str()),
            ("1 of 1", "1 of 1")
        );
    }
}
