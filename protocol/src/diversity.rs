//! How diverse the readings of one message are (paper section 2.2, "Evaluation").
//!
//! The paper uses the population variance; its discussion asks for entropy or several quantities
//! at once. A [`Diversity`] is therefore a trait: the variants are generic over it and default to
//! [`Variance`]. [`Entropy`] is the second measure (beyond the paper): the Shannon entropy of
//! the readings binned at a fixed width.
//!
//! A measure scores one message ([`Diversity::measure`]) and also says how the observer's
//! "diversity of all stored readings" is accumulated without keeping the readings
//! ([`Diversity::Pool`]: [`Moments`] for the variance, [`Histogram`] for the entropy).

/// A measure of how diverse a set of readings of type `R` is (one quantity, `f32`, unless
/// said otherwise; [`PerQuantity`] measures readings of several). Larger means more informative.
///
/// Implementations must return a finite value `>= 0` for any finite input and `0` for fewer
/// than two readings, and must not panic on any input (NaN included).
pub trait Diversity<R = f32> {
    /// Accumulates readings one at a time for the same measure over all of them (the
    /// observer's `V_k` of a gathering phase), in fixed memory.
    type Pool: Pool<R> + Clone + core::fmt::Debug;

    /// The diversity of `readings`. The iterator is `Clone` so a measure may make two passes.
    fn measure<I>(&self, readings: I) -> f32
    where
        I: Iterator<Item = R> + Clone;

    /// An empty pool for this measure.
    fn pool(&self) -> Self::Pool;

    /// The diversity of a message's `readings` followed by the receiver's `own`: the same as
    /// [`measure`](Self::measure) of the two chained (a measure may override it with a
    /// faster loop over the slice, with the same result bit for bit).
    fn measure_message(&self, readings: &[R], own: R) -> f32
    where
        R: Copy,
    {
        self.measure(readings.iter().copied().chain(core::iter::once(own)))
    }
}

/// Readings pushed one at a time, and the diversity of all of them so far.
pub trait Pool<R = f32> {
    /// Adds one reading (non-finite ones may be ignored, never a panic).
    fn push(&mut self, x: R);
    /// Adds every reading of `xs` in order (the same as [`push`](Self::push) on each; a pool
    /// that dispatches at run time overrides it to dispatch once).
    fn push_all<I: Iterator<Item = R>>(&mut self, xs: I) {
        xs.for_each(|x| self.push(x));
    }
    /// The diversity of everything pushed (finite, `>= 0`).
    fn value(&self) -> f32;
}

/// Population variance, the paper's equation for `V_k`: `1/n Σ (m_j − m̄)²`.
///
/// Computed in two passes in `f32` (the mean first), which avoids the cancellation of the
/// one-pass `E[x²] − E[x]²`. `f32` is exact for the sums of a message's 8-bit readings and
/// is what the Cortex-M4F computes in hardware (`f64` would cost about 3 KiB of soft-float code).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Variance;

impl Diversity for Variance {
    type Pool = Moments;

    fn pool(&self) -> Moments {
        Moments::default()
    }

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

    /// [`measure`](Diversity::measure) of `readings` then `own` in plain loops over the slice
    /// (the 2D simulator scores every message it delivers with this): the same sums in the
    /// same order, so the same value bit for bit.
    #[inline]
    fn measure_message(&self, readings: &[f32], own: f32) -> f32 {
        let mut sum = 0f32;
        for &x in readings {
            sum += x;
        }
        Variance::measure_summed(readings, sum, own)
    }
}

impl Variance {
    /// [`measure_message`](Diversity::measure_message) of `readings` then `own`, given `sum`,
    /// the sum of `readings` added up in order from `0.0` (as `measure_message` adds them, so
    /// the same value bit for bit). A relay appends one reading to the message it heard, so
    /// the 2D simulator keeps each message's sum as it grows instead of adding it up again at
    /// every receiver.
    #[inline]
    pub fn measure_summed(readings: &[f32], sum: f32, own: f32) -> f32 {
        let n = readings.len() + 1;
        if n < 2 {
            return 0.0;
        }
        let mean = (sum + own) / n as f32;
        let mut ss = 0f32;
        for &x in readings {
            ss += (x - mean) * (x - mean);
        }
        ss += (own - mean) * (own - mean);
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
    #[inline]
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

impl Pool for Moments {
    #[inline]
    fn push(&mut self, x: f32) {
        Moments::push(self, x);
    }

    fn value(&self) -> f32 {
        let v = self.variance();
        if v.is_finite() { v } else { 0.0 }
    }
}

/// Shannon entropy in bits of the readings binned at width `bin` (beyond the paper; its
/// discussion names "information entropy" as an alternative to the variance).
///
/// Bin `i` holds the readings `x` with `i·bin <= x < (i+1)·bin` (edges at the multiples of
/// `bin`, `i = floor(x / bin)` saturated to `i32`). With `n` finite readings and `c_i` in bin `i`,
/// `H = −Σ (c_i/n) log2(c_i/n)`: 0 if all readings share a bin, `log2 k` if they are spread
/// evenly over `k` bins. Unlike the variance it ignores how far apart the bins are: two
/// readings 0.5 or 50 apart (in different bins) both give 1 bit, so it saturates at
/// `log2 n` for a message of `n` readings and does not grow with the field's slope.
///
/// The choice of a fixed grid (rather than bins relative to the message's minimum) makes the
/// measure order-independent (up to the rounding of the sum over bins) and cheap: one pass, no sort, a fixed array of at most
/// [`Histogram::CAPACITY`] distinct bins on the stack (a message has at most 33 readings with
/// the scorer's own, so a message is binned exactly). Non-finite readings are ignored; an invalid
/// `bin` (not finite or `<= 0`) gives 0 for every input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Entropy {
    /// Bin width, in the readings' unit.
    pub bin: f32,
}

impl Entropy {
    /// The entropy at bin width `bin`, `None` unless `bin` is finite and `> 0`.
    pub fn new(bin: f32) -> Option<Self> {
        (bin.is_finite() && bin > 0.0).then_some(Entropy { bin })
    }
}

impl Diversity for Entropy {
    type Pool = Histogram;

    fn pool(&self) -> Histogram {
        Histogram::new(self.bin)
    }

    fn measure<I>(&self, readings: I) -> f32
    where
        I: Iterator<Item = f32> + Clone,
    {
        let mut h = Histogram::new(self.bin);
        readings.for_each(|x| h.push(x));
        h.entropy()
    }
}

/// Counts of readings per bin of a fixed width, for [`Entropy`]: at most [`Histogram::CAPACITY`]
/// distinct bins in a fixed array (no heap). Readings falling in further distinct bins are
/// pooled into one overflow bin (counted, so [`Histogram::overflowed`] says when the entropy is
/// an underestimate); with readings of a few units and a bin of 0.5 that never happens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Histogram {
    bin: f32,
    keys: [i32; Histogram::CAPACITY],
    counts: [u32; Histogram::CAPACITY],
    len: usize,
    overflow: u32,
}

impl Histogram {
    /// Distinct bins held exactly.
    pub const CAPACITY: usize = 40;

    /// An empty histogram of bin width `bin` (an invalid width counts nothing).
    pub fn new(bin: f32) -> Self {
        Histogram {
            bin,
            keys: [0; Self::CAPACITY],
            counts: [0; Self::CAPACITY],
            len: 0,
            overflow: 0,
        }
    }

    /// Readings counted (finite ones).
    pub fn count(&self) -> u32 {
        self.counts[..self.len]
            .iter()
            .fold(self.overflow, |a, &c| a.saturating_add(c))
    }

    /// Readings that fell beyond [`Histogram::CAPACITY`] distinct bins.
    pub fn overflowed(&self) -> u32 {
        self.overflow
    }

    /// Adds one reading; ignored if it or the bin width is not finite.
    pub fn push(&mut self, x: f32) {
        if !(self.bin.is_finite() && self.bin > 0.0) {
            return;
        }
        let q = x / self.bin;
        if !q.is_finite() {
            return;
        }
        // floor(q) saturated to i32 (`as` saturates; no libm call).
        let t = q as i32;
        let k = if (t as f32) > q {
            t.saturating_sub(1)
        } else {
            t
        };
        match self.keys[..self.len].iter().position(|&b| b == k) {
            Some(i) => self.counts[i] = self.counts[i].saturating_add(1),
            None if self.len < Self::CAPACITY => {
                self.keys[self.len] = k;
                self.counts[self.len] = 1;
                self.len += 1;
            }
            None => self.overflow = self.overflow.saturating_add(1),
        }
    }

    /// Shannon entropy in bits of the counts (0 for fewer than two readings).
    pub fn entropy(&self) -> f32 {
        let n = self.count();
        if n < 2 {
            return 0.0;
        }
        let n = n as f32;
        let h: f32 = self.counts[..self.len]
            .iter()
            .chain(core::iter::once(&self.overflow))
            .filter(|&&c| c > 0)
            .map(|&c| {
                let p = c as f32 / n;
                -p * libm::log2f(p)
            })
            .sum();
        if h.is_finite() && h > 0.0 { h } else { 0.0 }
    }
}

impl Pool for Histogram {
    fn push(&mut self, x: f32) {
        Histogram::push(self, x);
    }

    fn value(&self) -> f32 {
        self.entropy()
    }
}

/// Several quantities at once (beyond the paper; its discussion suggests measuring e.g. light
/// and oxygen together): readings are `[f32; K]`, one value per quantity, and the diversity is
/// the sum over the quantities of `D`'s measure of that quantity alone (the sum of the
/// per-quantity variances, or of the per-quantity entropies in bits).
///
/// A sum weighs the quantities by their own scales: with the variance, a quantity whose
/// readings span ten times the range counts a hundred times as much (rescale the readings to
/// weigh them otherwise); the entropy counts bins and so is scale-free once each quantity's
/// bin width suits it. `K` passes over the readings; no heap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerQuantity<D, const K: usize>(pub D);

impl<D: Diversity, const K: usize> Diversity<[f32; K]> for PerQuantity<D, K> {
    type Pool = PerQuantityPool<D::Pool, K>;

    fn measure<I>(&self, readings: I) -> f32
    where
        I: Iterator<Item = [f32; K]> + Clone,
    {
        let v: f32 = (0..K)
            .map(|k| self.0.measure(readings.clone().map(move |r| r[k])))
            .sum();
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }

    fn pool(&self) -> Self::Pool {
        PerQuantityPool(core::array::from_fn(|_| self.0.pool()))
    }
}

/// The pool of [`PerQuantity`]: one pool per quantity; its value is their sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerQuantityPool<P, const K: usize>(pub [P; K]);

impl<P: Pool, const K: usize> Pool<[f32; K]> for PerQuantityPool<P, K> {
    fn push(&mut self, x: [f32; K]) {
        self.0.iter_mut().zip(x).for_each(|(p, v)| p.push(v));
    }

    fn value(&self) -> f32 {
        let v: f32 = self.0.iter().map(Pool::value).sum();
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variance_of_a_message_is_the_chained_measure_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg32::seed_from_u64(11);
        let special = [0.0, -0.0, f32::NAN, f32::INFINITY, 1e30, -1e-30];
        for case in 0..20_000 {
            let n = rng.random_range(0..=32);
            let xs: heapless::Vec<f32, 32> = (0..n)
                .map(|_| match rng.random_range(0..20) {
                    0 => special[rng.random_range(0..special.len())],
                    1..=9 => f32::from(rng.random_range(0u8..=255)),
                    _ => rng.random_range(-3.0f32..8.0),
                })
                .collect();
            let own = rng.random_range(-1.0f32..6.0);
            let chained = Variance.measure(xs.iter().copied().chain(core::iter::once(own)));
            let fast = Variance.measure_message(&xs, own);
            assert_eq!(
                fast.to_bits(),
                chained.to_bits(),
                "case {case}: {xs:?} then {own}"
            );
        }
    }

    #[test]
    fn per_quantity_sums_the_quantities_measures() {
        let xs = [[1.0f32, 0.0], [0.0, 0.0], [0.0, 3.0], [0.0, 0.0]];
        let m = PerQuantity::<Variance, 2>(Variance);
        // 3/16 for the first quantity, 27/16 for the second.
        assert!((m.measure(xs.iter().copied()) - 30.0 / 16.0).abs() < 1e-6);
        let e = PerQuantity::<Entropy, 2>(Entropy { bin: 1.0 });
        // Bins (1, 0, 0, 0) and (0, 0, 3, 0): 0.811 bits each.
        assert!((e.measure(xs.iter().copied()) - 2.0 * 0.811_278).abs() < 1e-5);
        for (d, p) in [
            (m.measure(xs.iter().copied()), {
                let mut p = m.pool();
                p.push_all(xs.iter().copied());
                p.value()
            }),
            (e.measure(xs.iter().copied()), {
                let mut p = e.pool();
                p.push_all(xs.iter().copied());
                p.value()
            }),
        ] {
            assert!((d - p).abs() < 1e-5, "{d} {p}");
        }
        // One quantity alone is the plain measure; hostile input gives 0, not NaN.
        let one = PerQuantity::<Variance, 1>(Variance);
        assert_eq!(one.measure([[1.0], [0.0]].into_iter()), 0.25);
        assert_eq!(m.measure([[f32::NAN, 1.0], [0.0, 1.0]].into_iter()), 0.0);
        assert_eq!(m.measure(core::iter::empty()), 0.0);
    }

    fn ent(bin: f32, xs: &[f32]) -> f32 {
        Entropy { bin }.measure(xs.iter().copied())
    }

    #[test]
    fn entropy_of_an_even_spread_is_log2_k() {
        assert_eq!(ent(0.5, &[]), 0.0);
        assert_eq!(ent(0.5, &[3.0]), 0.0);
        // All in one bin (0.5 <= x < 1.0): 0 bits.
        assert_eq!(ent(0.5, &[0.5, 0.6, 0.99, 0.7]), 0.0);
        for k in 1..=32u32 {
            // Two readings in each of k bins, including negative ones.
            let xs: [f32; 64] = core::array::from_fn(|i| (i as f32 % k as f32) - 7.3);
            let xs = &xs[..2 * k as usize];
            let h = ent(1.0, xs);
            assert!((h - libm::log2f(k as f32)).abs() < 1e-5, "{k}: {h}");
        }
        // 3 in one bin, 1 in another: −(3/4 log2 3/4 + 1/4 log2 1/4) = 0.8113.
        assert!((ent(1.0, &[0.1, 0.2, 0.3, 1.5]) - 0.811_278).abs() < 1e-5);
    }

    #[test]
    fn entropy_bins_at_multiples_of_the_width() {
        // -0.1 is in bin -1, 0.1 in bin 0: different bins although 0.2 apart.
        assert_eq!(ent(0.5, &[-0.1, 0.1]), 1.0);
        assert_eq!(ent(0.5, &[0.0, 0.49]), 0.0);
        assert_eq!(ent(0.5, &[-0.5, -0.01]), 0.0);
    }

    #[test]
    fn entropy_is_order_independent() {
        let xs = [0.3f32, 2.7, 1.1, 0.3, 5.0, -1.2, 2.6, 1.0, 0.9];
        let h = ent(0.5, &xs);
        let mut ys = xs;
        // The bins are the same sets; only the order of the sum over them changes.
        ys.reverse();
        assert!((ent(0.5, &ys) - h).abs() < 1e-6);
        ys.rotate_left(4);
        assert!((ent(0.5, &ys) - h).abs() < 1e-6);
    }

    #[test]
    fn entropy_ignores_non_finite_readings_and_bad_widths() {
        assert_eq!(ent(0.5, &[f32::NAN, 1.0]), 0.0);
        assert_eq!(ent(0.5, &[f32::NAN, f32::INFINITY, f32::NEG_INFINITY]), 0.0);
        assert_eq!(ent(0.5, &[f32::NAN, 0.1, 1.1]), 1.0);
        // Huge readings saturate to the extreme bins, no overflow; x / bin = ±inf is ignored.
        assert_eq!(ent(1.0, &[f32::MAX, -f32::MAX, 0.0, 1.0]), 2.0);
        assert_eq!(ent(0.5, &[f32::MAX, -f32::MAX, 0.0, 1.0]), 1.0);
        assert_eq!(ent(1e-30, &[1.0, 2.0]), 0.0, "both saturate to i32::MAX");
        for bin in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(ent(bin, &[0.0, 1.0, 2.0]), 0.0);
        }
        assert!(Entropy::new(0.0).is_none());
        assert_eq!(Entropy::new(0.5), Some(Entropy { bin: 0.5 }));
    }

    #[test]
    fn histogram_pools_beyond_capacity_without_panic() {
        let mut h = Histogram::new(1.0);
        (0..100).for_each(|i| h.push(i as f32));
        assert_eq!(h.count(), 100);
        assert_eq!(h.overflowed(), 100 - Histogram::CAPACITY as u32);
        let e = h.entropy();
        assert!(e.is_finite() && e > 0.0 && e < libm::log2f(100.0));
        // A pool and the one-shot measure agree.
        let mut p = Entropy { bin: 0.5 }.pool();
        [0.1f32, 0.7, 1.2, 0.2]
            .iter()
            .for_each(|&x| Pool::push(&mut p, x));
        assert_eq!(p.value(), ent(0.5, &[0.1, 0.7, 1.2, 0.2]));
    }

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
