//! Shared fakes for the host tests.

use std::future::pending;

use firmware::hal::Clock;
use firmware::protocol::Instant;

/// Milliseconds of tokio's (paused) clock since the fake was made.
#[derive(Clone, Copy, Debug)]
pub struct TokioClock {
    epoch: tokio::time::Instant,
}

impl TokioClock {
    pub fn new() -> Self {
        TokioClock {
            epoch: tokio::time::Instant::now(),
        }
    }
}

impl Clock for TokioClock {
    fn now(&self) -> Instant {
        Instant::from_millis(self.epoch.elapsed().as_millis() as u64)
    }

    async fn sleep_until(&self, deadline: Instant) {
        let d = std::time::Duration::from_millis(deadline.as_millis());
        match self.epoch.checked_add(d) {
            Some(t) if d.as_secs() < 1 << 40 => tokio::time::sleep_until(t).await,
            _ => pending().await,
        }
    }
}
