//! [`Reading`]: what an agent of the 2D simulator reads, one quantity (the paper) or two, and
//! the measure that scores it.

use std::fmt;

use protocol::{Diversity, PerQuantity};
use rand::Rng;
use rand_pcg::Pcg64Mcg;

use crate::measure::Measure;

/// What an agent reads: one quantity (`f32`, the paper) or two at once (`[f32; 2]`, beyond
/// the paper: a scenario with `[[field2]]`), and the measure that scores it.
pub trait Reading: Copy + Default + fmt::Debug + PartialEq + Send + Sync + 'static {
    /// Quantities per reading: the fields a run needs.
    const QUANTITIES: usize;
    /// The agents' diversity for readings of this type.
    type Measure: Diversity<Self> + Clone + fmt::Debug + Send + Sync;
    /// The diversity for the run's [`Measure`]: the measure itself for one quantity, the sum
    /// over the quantities of it ([`PerQuantity`]) for several.
    fn measure(m: Measure) -> Self::Measure;
    /// A noisy reading from the fields' means at the agent (`QUANTITIES` values): each
    /// quantity gets its own noise draw, in order.
    fn sample(means: &[f64], noise: f64, rng: &mut Pcg64Mcg) -> Self;
    /// The first quantity, as the observer's [`Tap`](crate::tap::Tap) pools it.
    fn first(&self) -> f64;
}

impl Reading for f32 {
    const QUANTITIES: usize = 1;
    type Measure = Measure;

    fn measure(m: Measure) -> Measure {
        m
    }

    #[inline]
    fn sample(means: &[f64], noise: f64, rng: &mut Pcg64Mcg) -> f32 {
        let xi = noise * (rng.random::<f64>() - 0.5);
        (means[0] + xi) as f32
    }

    fn first(&self) -> f64 {
        f64::from(*self)
    }
}

impl Reading for [f32; 2] {
    const QUANTITIES: usize = 2;
    type Measure = PerQuantity<Measure, 2>;

    fn measure(m: Measure) -> Self::Measure {
        PerQuantity(m)
    }

    #[inline]
    fn sample(means: &[f64], noise: f64, rng: &mut Pcg64Mcg) -> [f32; 2] {
        [
            f32::sample(&means[..1], noise, rng),
            f32::sample(&means[1..2], noise, rng),
        ]
    }

    fn first(&self) -> f64 {
        f64::from(self[0])
    }
}
