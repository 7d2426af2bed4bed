//! The statistics every page and table of `cimax` uses, in one place: the mean, the population
//! variance and standard error, quantiles by the nearest-rank method, and the circular mean of
//! directions ([`Resultant`], [`circular_mean`]).
//!
//! Sums run in slice order, so a result is the same bit for bit whatever thread made the slice.

use nalgebra::Vector2;

/// The mean of `xs`; `None` for none.
pub fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// The population variance of `xs` (divided by n); `None` for none.
pub fn variance(xs: &[f64]) -> Option<f64> {
    let m = mean(xs)?;
    Some(xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / xs.len() as f64)
}

/// The standard error of the mean of `xs`, `sqrt(variance / n)` with the population variance;
/// `None` for none.
pub fn standard_error(xs: &[f64]) -> Option<f64> {
    variance(xs).map(|v| (v / xs.len() as f64).sqrt())
}

/// The `p`-quantile (0 to 1) of the finite values of `xs` by the nearest-rank method; `None`
/// if there are none.
pub fn quantile(xs: &[f64], p: f64) -> Option<f64> {
    let mut v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let rank = ((p * v.len() as f64).ceil() as usize).clamp(1, v.len());
    Some(v[rank - 1])
}

/// The confidence of every interval [`line_fit`] gives (its half-width `ci`), and so of every
/// trend and comparison judged with one: 95 %.
pub const CONFIDENCE: f64 = 0.95;

/// A least-squares line through points, with what a trend claim needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineFit {
    /// Slope.
    pub slope: f64,
    /// Intercept at x = 0.
    pub intercept: f64,
    /// Half-width of the slope's two-sided 95 % interval (Student's t with n − 2 degrees of
    /// freedom times the slope's standard error).
    pub slope_ci: f64,
    /// The share of the variance of y the line explains (R²; 1 for points on a line).
    pub r2: f64,
}

/// The curvature of `(x, y)` points: the coefficient of x² in the least-squares parabola
/// `a + b x + c x²` and the half-width of its two-sided [`CONFIDENCE`] interval (Student's t
/// with n − 3 degrees of freedom times its standard error). A trend is linear by this test
/// when the interval contains zero. `None` for fewer than four points or fewer than three
/// distinct x.
pub fn curvature(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    use nalgebra::{DMatrix, DVector};
    use statrs::distribution::{ContinuousCDF, StudentsT};
    let n = points.len();
    if n < 4 {
        return None;
    }
    let x = DMatrix::from_fn(n, 3, |i, j| points[i].0.powi(j as i32));
    let y = DVector::from_iterator(n, points.iter().map(|p| p.1));
    let xtx_inv = (x.transpose() * &x).try_inverse()?;
    let beta = &xtx_inv * x.transpose() * &y;
    let sse = (&y - &x * &beta).norm_squared();
    let df = (n - 3) as f64;
    let se = (sse / df * xtx_inv[(2, 2)]).sqrt();
    let t = StudentsT::new(0.0, 1.0, df)
        .ok()?
        .inverse_cdf((1.0 + CONFIDENCE) / 2.0);
    se.is_finite().then_some((beta[2], t * se))
}

/// The least-squares line through `(x, y)` points; `None` for fewer than three points or when
/// every x is the same.
pub fn line_fit(points: &[(f64, f64)]) -> Option<LineFit> {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    let n = points.len();
    if n < 3 {
        return None;
    }
    let xs: Vec<f64> = points.iter().map(|p| p.0).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
    let (mx, my) = (mean(&xs)?, mean(&ys)?);
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let syy: f64 = ys.iter().map(|y| (y - my) * (y - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let sse: f64 = points
        .iter()
        .map(|(x, y)| (y - intercept - slope * x).powi(2))
        .sum();
    let df = (n - 2) as f64;
    let se = (sse / df / sxx).sqrt();
    let t = StudentsT::new(0.0, 1.0, df)
        .ok()?
        .inverse_cdf((1.0 + CONFIDENCE) / 2.0);
    Some(LineFit {
        slope,
        intercept,
        slope_ci: t * se,
        r2: if syy > 0.0 { 1.0 - sse / syy } else { 1.0 },
    })
}

/// Where a profile `(d, value, standard error)` (by increasing d) crosses `level`, by linear
/// interpolation between the two points either side: the first crossing upward (`up`) or the
/// last crossing downward (`!up`). With its standard error: the two points' mean standard error
/// over the local slope. `None` if it never crosses that way.
pub fn crossing(profile: &[(f64, f64, f64)], level: f64, up: bool) -> Option<(f64, f64)> {
    let pairs = profile.windows(2).map(|w| (w[0], w[1]));
    let hit = |(a, b): &((f64, f64, f64), (f64, f64, f64))| {
        if up {
            a.1 < level && b.1 >= level
        } else {
            a.1 >= level && b.1 < level
        }
    };
    let (a, b) = if up {
        pairs.clone().find(hit)?
    } else {
        pairs.clone().rfind(hit)?
    };
    let slope = (b.1 - a.1) / (b.0 - a.0);
    let d = a.0 + (level - a.1) / slope;
    Some((d, 0.5 * (a.2 + b.2) / slope.abs()))
}

/// Below this length a [`Resultant`] has no direction: its unit vectors cancel.
///
/// An absolute bound: only sums that cancel to within `f64` rounding count as no direction. The
/// 2D simulator has moved its swarm by this rule from the start, and every result of it
/// (`docs/reproduction.md`) was computed with it. `hal_emu::world::arena::swarm_heading` (the
/// arena's swarm reading its LEDs) uses `1e-5 · n` instead, and keeps it: its bearings are the
/// centres of a few LED sectors, so exactly opposite sectors are common, and as `f32` angles
/// they leave about 1e-7 per opposed pair rather than 0; its relative bound calls such a tie no
/// heading. The two are not merged because either change could move a swarm differently in
/// some run, and the pages and tests must stay as they are.
pub const CANCELLED: f64 = 1e-12;

/// The sum of the unit vectors at some angles, and how many there were: their circular mean
/// ([`direction`](Self::direction)) and how well they agree ([`length`](Self::length)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resultant {
    /// The sum of the unit vectors `(cos θ, sin θ)`, in the angles' order.
    pub sum: Vector2<f64>,
    /// How many angles.
    pub n: u32,
}

impl Resultant {
    /// The resultant of `thetas` (radians), summed in order.
    pub fn of(thetas: impl IntoIterator<Item = f64>) -> Resultant {
        let mut n = 0;
        let sum = thetas
            .into_iter()
            .inspect(|_| n += 1)
            .map(|t| Vector2::new(t.cos(), t.sin()))
            .sum();
        Resultant { sum, n }
    }

    /// The circular mean, radians in `(−π, π]`; `None` without angles or if they cancel (the
    /// sum no longer than [`CANCELLED`]).
    pub fn direction(&self) -> Option<f64> {
        (self.n > 0 && self.sum.norm() > CANCELLED).then(|| self.sum.y.atan2(self.sum.x))
    }

    /// The mean resultant length, 0 (no agreement, or no angles) to 1 (all equal).
    pub fn length(&self) -> f64 {
        if self.n > 0 {
            self.sum.norm() / f64::from(self.n)
        } else {
            0.0
        }
    }
}

/// The circular mean of `thetas` (radians): the direction of the sum of their unit vectors, as
/// the simulator moves the swarm; `None` without angles or if they cancel.
pub fn circular_mean(thetas: impl IntoIterator<Item = f64>) -> Option<f64> {
    Resultant::of(thetas).direction()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn means_variances_and_quantiles() {
        assert_eq!(mean(&[]), None);
        assert_eq!(mean(&[1.0, 2.0, 6.0]), Some(3.0));
        assert_eq!(variance(&[1.0, 3.0]), Some(1.0));
        assert_eq!(standard_error(&[1.0, 3.0]), Some(0.5f64.sqrt()));
        assert_eq!(standard_error(&[]), None);
        let xs: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(quantile(&xs, 0.5), Some(50.0));
        assert_eq!(quantile(&xs, 0.95), Some(95.0));
        assert_eq!(quantile(&[3.0, f64::NAN], 0.95), Some(3.0));
        assert_eq!(quantile(&[], 0.5), None);
    }

    #[test]
    fn the_curvature_test_tells_a_parabola_from_a_noisy_line() {
        // A parabola, exactly: c = 0.5 with a vanishing interval.
        let parabola: Vec<(f64, f64)> = (0..6)
            .map(f64::from)
            .map(|x| (x, 1.0 + 2.0 * x + 0.5 * x * x))
            .collect();
        let (c, ci) = curvature(&parabola).unwrap();
        assert!((c - 0.5).abs() < 1e-9 && ci < 1e-6, "{c} ± {ci}");
        // A line with alternating noise: its interval contains zero.
        let line: Vec<(f64, f64)> = (0..6)
            .map(f64::from)
            .map(|x| (x, 3.0 - x + if x as i32 % 2 == 0 { 0.1 } else { -0.1 }))
            .collect();
        let (c, ci) = curvature(&line).unwrap();
        assert!(c.abs() <= ci, "{c} ± {ci}");
        assert_eq!(curvature(&line[..3]), None);
        assert_eq!(curvature(&[(1.0, 1.0); 5]), None);
    }

    #[test]
    fn a_line_fit_finds_the_slope_and_its_interval() {
        let exact = line_fit(&[(0.0, 1.0), (1.0, 3.0), (2.0, 5.0)]).unwrap();
        assert!((exact.slope - 2.0).abs() < 1e-12 && (exact.intercept - 1.0).abs() < 1e-12);
        assert!(exact.slope_ci.abs() < 1e-9 && (exact.r2 - 1.0).abs() < 1e-12);
        // Around y = x at x = 0..4: slope 1.00, s.e. 0.031, t(3) = 3.182, interval ± 0.097.
        let noisy =
            line_fit(&[(0.0, 0.0), (1.0, 1.1), (2.0, 1.9), (3.0, 3.1), (4.0, 4.0)]).unwrap();
        assert!((noisy.slope - 1.0).abs() < 0.05, "{noisy:?}");
        assert!(noisy.slope_ci > 0.05 && noisy.slope_ci < 0.3, "{noisy:?}");
        assert!(noisy.r2 > 0.99 && noisy.r2 < 1.0);
        assert_eq!(line_fit(&[(0.0, 1.0), (1.0, 2.0)]), None);
        assert_eq!(line_fit(&[(1.0, 1.0), (1.0, 2.0), (1.0, 3.0)]), None);
    }

    #[test]
    fn crossings_interpolate_between_the_points_either_side() {
        let p = [
            (0.0, -0.5, 0.1),
            (1.0, -0.2, 0.1),
            (2.0, 0.8, 0.1),
            (3.0, 0.9, 0.1),
            (4.0, 0.1, 0.1),
        ];
        let (d, se) = crossing(&p, 0.0, true).unwrap();
        assert!((d - 1.2).abs() < 1e-12 && (se - 0.1).abs() < 1e-12);
        let (d, _) = crossing(&p, 0.5, false).unwrap();
        assert!((d - 3.5).abs() < 1e-12);
        assert_eq!(crossing(&p, 2.0, true), None);
    }

    #[test]
    fn circular_means_cancel_and_agree() {
        let deg = |d: f64| d.to_radians();
        assert!((circular_mean([0.0, deg(90.0)]).unwrap() - deg(45.0)).abs() < 1e-12);
        assert_eq!(circular_mean([0.0, std::f64::consts::PI]), None);
        assert_eq!(circular_mean([]), None);
        let r = Resultant::of([0.0, 0.0, std::f64::consts::PI]);
        assert_eq!(r.n, 3);
        assert!((r.length() - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(Resultant::of([]).length(), 0.0);
    }
}
