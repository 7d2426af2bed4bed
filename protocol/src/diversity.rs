//! How diverse the readings of one message are (paper section 2.2, "Evaluation").
//!
//! The paper uses the population variance; its discussion asks for entropy or several quantities
//! at once. A [`Diversity`] is therefore a trait: the variants are generic over it and default to
//! [`Variance`].

/// A measure of how diverse a set of readings is. Larger means more informative.
///
/// Implementations must return a finite value `>= 0` for any finite input and `0` for fewer
/// than two readings, and must not panic on any input (NaN included).
pub trait Diversity {
    /// The diversity of `readings`. The iterator is `Clone` so a measure may make two passes.
    fn measure<I>(&self, readings: I) -> f32
    where
        I: Iterator<Item = f32> + Clone;
}

/// Population variance, the paper's equation for `V_k`: `1/n Σ (m_j − m̄)²`.
///
/// Computed in two passes in `f32` (the mean first), which avoids the cancellation of the
/// one-pass `E[x²] − E[x]²`. `f32` is exact for the sums of a message's 8-bit readings and
/// is what the Cortex-M4F computes in hardware (`f64` would cost about 3 KiB of soft-float code).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Variance;

impl Diversity for Variance {
    fn measure<I>(&self, readings: I) -> f32
    where
        I: Iterator<Item = f32> + Clone,
    {
        let (n, sum) = readings
            .clone()
            .fold((0u32, 0f32), |(n, s), x| (n + 1, s + x));
        if n < 2 {
            return 0.0;
        }
        let mean = sum / n as f32;
        let ss: f32 = readings.map(|x| (x - mean) * (x - mean)).sum();
        let v = ss / n as f32;
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }
}

/// Running count, mean and sum of squared deviations (Welford), mergeable (Chan et al.).
///
/// Used where the readings themselves are not kept, e.g. the observer's "average diversity
/// `V_k` of all stored messages" in the 2D simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moments {
    n: u32,
    mean: f64,
    m2: f64,
}

impl Moments {
    /// Adds one reading.
    pub fn push(&mut self, x: f32) {
        let x = f64::from(x);
        self.n = self.n.saturating_add(1);
        let d = x - self.mean;
        self.mean += d / f64::from(self.n);
        self.m2 += d * (x - self.mean);
    }

    /// Number of readings.
    pub fn count(&self) -> u32 {
        self.n
    }

    /// Population variance of everything pushed (0 for fewer than two readings).
    pub fn variance(&self) -> f32 {
        if self.n < 2 {
            0.0
        } else {
            (self.m2 / f64::from(self.n)) as f32
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(xs: &[f32]) -> f32 {
        Variance.measure(xs.iter().copied())
    }

    #[test]
    fn population_variance() {
        assert_eq!(var(&[]), 0.0);
        assert_eq!(var(&[5.0]), 0.0);
        assert_eq!(var(&[1.0, 1.0, 1.0]), 0.0);
        assert!((var(&[1.0, 0.0]) - 0.25).abs() < 1e-7);
        // 1000: mean 0.25, variance 3/16.
        assert!((var(&[1.0, 0.0, 0.0, 0.0]) - 0.1875).abs() < 1e-7);
        assert!((var(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]) - 4.0).abs() < 1e-6);
    }

    #[test]
    fn hostile_input_gives_zero_not_nan() {
        assert_eq!(var(&[f32::NAN, 1.0]), 0.0);
        assert_eq!(var(&[f32::INFINITY, 1.0]), 0.0);
    }

    #[test]
    fn moments_match_two_pass() {
        let xs = [3.0f32, 1.5, 8.25, 0.0, 255.0, 17.0];
        let mut m = Moments::default();
        xs.iter().for_each(|&x| m.push(x));
        assert_eq!(m.count(), 6);
        assert!((m.variance() - var(&xs)).abs() < 1e-3);
    }
}
