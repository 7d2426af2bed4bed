//! [`Tap`]: what an observer sees of the messages a run's agents score, for the experiments
//! that ask how diversity is taken ([`crate::probe`]).

/// What an observer sees of the messages the agents scored (accepted in a gathering phase),
/// first quantity only: the diversity per message and over all of them pooled. It changes
/// nothing in a run ([`crate::sim::Sim::tap`]).
///
/// A message's readings count with the receiver's own appended, as the receiving agent scores
/// and stores them; the variances are population variances (`1/n`, the paper's `V_k`) in `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tap {
    /// Messages scored.
    pub messages: u64,
    /// Sum over them of the variance of each message's readings.
    message_variance: f64,
    /// Readings pooled (Welford): count, mean, sum of squared deviations.
    n: u64,
    mean: f64,
    m2: f64,
}

impl Tap {
    /// Adds one scored message's readings (the receiver's own included).
    pub fn add(&mut self, readings: impl Iterator<Item = f64> + Clone) {
        let (k, sum) = readings
            .clone()
            .fold((0u64, 0.0), |(k, s), x| (k + 1, s + x));
        if k == 0 {
            return;
        }
        let m = sum / k as f64;
        let var = readings.clone().map(|x| (x - m) * (x - m)).sum::<f64>() / k as f64;
        self.messages += 1;
        self.message_variance += var;
        for x in readings {
            self.n += 1;
            let d = x - self.mean;
            self.mean += d / self.n as f64;
            self.m2 += d * (x - self.mean);
        }
    }

    /// The mean over the messages of each message's variance (`None` without messages).
    pub fn per_message(&self) -> Option<f64> {
        (self.messages > 0).then(|| self.message_variance / self.messages as f64)
    }

    /// The variance of every reading of every message, all agents together (`None` without
    /// readings).
    pub fn pooled(&self) -> Option<f64> {
        (self.n > 0).then(|| self.m2 / self.n as f64)
    }
}
