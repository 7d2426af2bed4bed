//! The cloud's radial profile, drawn as a plain x–y figure ([`xy_figure`]).

use std::path::Path;

use report::plot::{Line, PlotError, xy_figure};
use swarm_sim::experiment::RadialPoint;

/// The radial profile of a cloud: how strongly the swarm heads for the cloud's centre against
/// its distance from it.
///
/// # Errors
/// If the file cannot be written.
pub fn radial_figure(
    path: &Path,
    title: &str,
    points: &[RadialPoint],
    markers: &[(f64, String)],
) -> Result<(), PlotError> {
    let markers: Vec<(f64, &str)> = markers.iter().map(|(d, l)| (*d, l.as_str())).collect();
    let line = Line {
        label: "mean cos(direction − direction to the centre)".into(),
        points: points
            .iter()
            .map(|p| (p.distance, p.inward, p.inward_se))
            .collect(),
    };
    xy_figure(
        path,
        title,
        "distance of the swarm's centre from the cloud's centre / R",
        "inward alignment",
        &[line],
        (-1.05, 1.05),
        &markers,
        false,
    )
}
