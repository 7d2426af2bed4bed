//! The environment: the mean of the measured quantity X at every point of the plane.
//!
//! A [`Field`] is a sum of [`Layer`]s. A layer is a piecewise-linear profile of one coordinate
//! (`x`, `y`, or the distance from a centre): a list of [`Segment`]s, each starting at `from`
//! with `level` and rising by `slope` per R until the next segment starts. A repeated jump is a
//! sharp border; a non-zero slope is a gradient; a radial profile is a cloud. The built-in
//! scenarios (`swarm-sim/scenarios/*.toml`) are written in exactly this form. The 2D swarm
//! simulator (`cimax swarm`) and the emulated arena on a plane (`cimax arena --field`) both
//! read it from here.
//!
//! The time-dependent noise ξ is not part of the field: the simulator adds it to every reading.

use nalgebra::Point2;

/// The coordinate a layer's profile depends on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Along {
    /// The x coordinate.
    X,
    /// The y coordinate.
    Y,
    /// The distance from `centre`.
    Radial {
        /// Centre of the radial profile.
        centre: Point2<f64>,
    },
}

/// One piece of a profile: from `from` on (until the next piece), `level + slope · (s − from)`.
/// A piece starting at `-inf` must be flat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Where the piece starts (in R; `-inf` for "everything below the next piece").
    pub from: f64,
    /// The value at `from`.
    pub level: f64,
    /// The rise per R.
    pub slope: f64,
}

/// A piecewise-linear profile along one coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// The coordinate.
    pub along: Along,
    /// Pieces by increasing `from`; the first also covers everything below its `from`.
    pub segments: Vec<Segment>,
}

impl Layer {
    /// The layer's value at `p`.
    pub fn value(&self, p: Point2<f64>) -> f64 {
        let s = match self.along {
            Along::X => p.x,
            Along::Y => p.y,
            Along::Radial { centre } => (p - centre).norm(),
        };
        let i = self.segments.partition_point(|g| g.from <= s);
        let Some(g) = self.segments.get(i.saturating_sub(1)) else {
            return 0.0;
        };
        if g.slope == 0.0 {
            g.level
        } else {
            g.level + g.slope * (s - g.from)
        }
    }
}

/// The mean of X everywhere: the sum of its layers (0 with none).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Field {
    /// The layers, summed.
    pub layers: Vec<Layer>,
}

impl Field {
    /// The mean of X at `p`.
    pub fn mean(&self, p: Point2<f64>) -> f64 {
        self.layers.iter().map(|l| l.value(p)).sum()
    }

    /// The smallest and largest mean over a grid covering `[x0, x1] × [y0, y1]` (for colour scales).
    pub fn range_over(&self, x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for i in 0..=100 {
            for j in 0..=100 {
                let p = Point2::new(
                    x.0 + (x.1 - x.0) * f64::from(i) / 100.0,
                    y.0 + (y.1 - y.0) * f64::from(j) / 100.0,
                );
                let v = self.mean(p);
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(from: f64, level: f64, slope: f64) -> Segment {
        Segment { from, level, slope }
    }

    #[test]
    fn steps_ramps_and_radial_profiles() {
        let sharp = Layer {
            along: Along::X,
            segments: vec![seg(f64::NEG_INFINITY, 0.0, 0.0), seg(0.0, 5.0, 0.0)],
        };
        assert_eq!(sharp.value(Point2::new(-0.01, 3.0)), 0.0);
        assert_eq!(sharp.value(Point2::new(0.0, 3.0)), 5.0);
        let ramp = Layer {
            along: Along::X,
            segments: vec![seg(f64::NEG_INFINITY, 0.0, 0.0), seg(0.0, 0.0, 2.0)],
        };
        assert_eq!(ramp.value(Point2::new(-3.0, 0.0)), 0.0);
        assert_eq!(ramp.value(Point2::new(2.5, 0.0)), 5.0);
        let cloud = Layer {
            along: Along::Radial {
                centre: Point2::new(1.0, 1.0),
            },
            segments: vec![
                seg(0.0, 0.0, 0.0),
                seg(3.0, 0.0, 5.0 / 1.5),
                seg(4.5, 5.0, 0.0),
            ],
        };
        assert_eq!(cloud.value(Point2::new(1.0, 3.0)), 0.0);
        assert!((cloud.value(Point2::new(1.0, 4.75)) - 2.5).abs() < 1e-12);
        assert_eq!(cloud.value(Point2::new(10.0, 1.0)), 5.0);
        let f = Field {
            layers: vec![sharp, ramp],
        };
        assert_eq!(f.mean(Point2::new(1.0, 0.0)), 7.0);
        assert_eq!(Field::default().mean(Point2::origin()), 0.0);
    }
}
