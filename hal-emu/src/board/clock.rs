//! The board's [`Clock`]: a run's virtual time (its [`Timeline`]) or tokio's, measured from the
//! start of the run. Every robot of a run and the world around them (its medium, adversaries
//! and schedule) share one value of it, so they all live in the same virtual time.

use std::future::Future;
use std::pin::Pin;
use std::rc::Rc;
use std::task::{Context, Poll};

use firmware::Clock;
use protocol::Instant;

use super::exec::{Join, Panic};
use super::timeline::{self, Sleep, Timeline};

/// A [`Clock`] over a run's [`Timeline`], which runs the run's tasks itself
/// ([`EmuClock::virtual_run`]) or is driven by tokio's clock; or over tokio's clock. Either way
/// time only moves when every task waits, straight to the next deadline: virtual time, as fast
/// as the CPU allows (tokio's clock must be paused for that, `start_paused`).
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

    /// A clock on a new [`Timeline`] that runs the run's tasks itself
    /// ([`Timeline::block_on`], no tokio runtime), and the timeline. Its driver
    /// ([`timeline::drive_virtual`]) must be the first task spawned.
    pub fn virtual_run() -> (Self, Rc<Timeline>) {
        let timeline = Rc::new(Timeline::default());
        let clock = EmuClock {
            epoch: tokio::time::Instant::now(),
            timeline: Some(timeline.clone()),
        };
        (clock, timeline)
    }

    /// Spawns `future` beside the run's other tasks: on the timeline's executor while it runs
    /// them ([`Timeline::block_on`]), else on tokio's current `LocalSet`.
    ///
    /// # Panics
    /// Outside both.
    pub fn spawn(&self, future: impl Future<Output = ()> + 'static) {
        match &self.timeline {
            Some(t) if t.executor().is_running() => t.executor().spawn(future),
            _ => drop(tokio::task::spawn_local(future)),
        }
    }

    /// [`spawn`](Self::spawn), with a handle that gives the task's output or its panic.
    pub fn spawn_joined<T: 'static>(
        &self,
        future: impl Future<Output = T> + 'static,
    ) -> EmuTask<T> {
        match &self.timeline {
            Some(t) if t.executor().is_running() => EmuTask::Own(t.executor().spawn_joined(future)),
            _ => EmuTask::Tokio(tokio::task::spawn_local(future)),
        }
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

/// A task spawned by [`EmuClock::spawn_joined`]: awaiting it gives the task's output, or
/// how it ended without one.
#[derive(Debug)]
pub enum EmuTask<T> {
    /// On tokio's `LocalSet`.
    Tokio(tokio::task::JoinHandle<T>),
    /// On the timeline's executor.
    Own(Join<T>),
}

/// How a task ended without an output.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TaskEnd {
    /// It panicked, with this message.
    Panicked(String),
    /// It was cancelled (its runtime shut down).
    Cancelled,
}

impl TaskEnd {
    fn from_panic(payload: &Panic) -> Self {
        TaskEnd::Panicked(
            payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".to_string()),
        )
    }
}

impl<T> Future for EmuTask<T> {
    type Output = Result<T, TaskEnd>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        match self.get_mut() {
            EmuTask::Tokio(h) => Pin::new(h).poll(cx).map(|r| {
                r.map_err(|e| {
                    if e.is_panic() {
                        TaskEnd::from_panic(&e.into_panic())
                    } else {
                        TaskEnd::Cancelled
                    }
                })
            }),
            EmuTask::Own(j) => Pin::new(j)
                .poll(cx)
                .map(|r| r.map_err(|p| TaskEnd::from_panic(&p))),
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
