//! The board's [`Clock`]: tokio time, measured from the start of the run. Every robot of a run
//! and the world around them (its medium, adversaries and schedule) share one value of it, so
//! they all live in the same virtual time.

use std::rc::Rc;

use firmware::Clock;
use protocol::Instant;

use super::timeline::{self, Sleep, Timeline};

/// A [`Clock`] over tokio's clock, or over a run's [`Timeline`] driven by it. Under a paused
/// runtime (`start_paused`) time only moves when every task waits, straight to the next timer:
/// virtual time, as fast as the CPU allows.
#[derive(Clone, Debug)]
pub struct EmuClock {
    epoch: tokio::time::Instant,
    timeline: Option<Rc<Timeline>>,
}

impl EmuClock {
    /// A clock on tokio's clock whose zero is `epoch` (real time, or tokio's virtual time).
    pub fn new(epoch: tokio::time::Instant) -> Self {
        EmuClock {
            epoch,
            timeline: None,
        }
    }

    /// A clock on a new [`Timeline`] whose zero is now, and the timeline's driver, to be
    /// spawned on the run's runtime (paused: virtual time). Every user of the clock then waits
    /// on one queue of deadlines instead of tokio's timer wheel.
    pub fn on_timeline() -> (Self, impl std::future::Future<Output = ()>) {
        let epoch = tokio::time::Instant::now();
        let timeline = Rc::new(Timeline::default());
        let driver = timeline::drive(timeline.clone(), epoch);
        let clock = EmuClock {
            epoch,
            timeline: Some(timeline),
        };
        (clock, driver)
    }

    /// The tokio instant of a protocol instant, or `None` for [`Instant::MAX`] ("never") and
    /// anything too far away.
    pub fn to_tokio(&self, t: Instant) -> Option<tokio::time::Instant> {
        if t == Instant::MAX {
            return None;
        }
        self.epoch
            .checked_add(std::time::Duration::from_millis(t.as_millis()))
    }
}

impl Clock for EmuClock {
    fn now(&self) -> Instant {
        if let Some(t) = &self.timeline {
            return t.now();
        }
        let d = tokio::time::Instant::now().saturating_duration_since(self.epoch);
        Instant::from_millis(u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
    }

    async fn sleep_until(&self, deadline: Instant) {
        if let Some(t) = &self.timeline {
            return Sleep::until(t.clone(), deadline).await;
        }
        match self.to_tokio(deadline) {
            Some(t) => tokio::time::sleep_until(t).await,
            None => std::future::pending().await,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn virtual_time_jumps_to_deadlines() {
        let c = EmuClock::new(tokio::time::Instant::now());
        assert_eq!(c.now(), Instant::ZERO);
        let wall = std::time::Instant::now();
        c.sleep_until(Instant::from_secs(3600)).await;
        assert_eq!(c.now(), Instant::from_secs(3600));
        assert!(wall.elapsed() < std::time::Duration::from_secs(5));
        assert!(c.to_tokio(Instant::MAX).is_none());
    }
}
