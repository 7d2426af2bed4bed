//! The colours of a field's levels: pale yellow (low X) to red (high X), as in the paper's
//! figures; the field under a figure and the legend's colour ramp use the same.

use plotters::prelude::RGBColor;

const LOW: (f64, f64, f64) = (255.0, 243.0, 176.0);
const HIGH: (f64, f64, f64) = (222.0, 45.0, 38.0);

/// Pale yellow (low X) to red (high X), as in the paper's figures.
fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    let t = if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let c = |a: f64, b: f64| (a + t * (b - a)).round() as u8;
    RGBColor(c(LOW.0, HIGH.0), c(LOW.1, HIGH.1), c(LOW.2, HIGH.2))
}

/// The colour of level `l` (0..=23, low to high X): pale yellow to red, or red to pale yellow
/// when `high_is_yellow`.
pub fn level_colour(l: u8, high_is_yellow: bool) -> RGBColor {
    let l = if high_is_yellow { 23 - l.min(23) } else { l };
    colour(f64::from(l), 0.0, 23.0)
}
