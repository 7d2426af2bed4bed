//! The statistics every page and table of `cimax` uses, in one place: the mean, the population
//! variance and standard error, and quantiles by the nearest-rank method.
//!
//! Sums run in slice order, so a result is the same bit for bit whatever thread made the slice.

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
}
