//! The host twin of a QEMU robot on the arena's clock: the same robot-in-the-loop program
//! (`firmware::hil::robot::run`, with the `host-clock` link), built for the host, in this
//! process, on a clock of its own that only the host's `Sync`s move ([`TwinClock`]), just as
//! the QEMU image's time driver with SysTick off. It takes part in the [`Lockstep`] like a QEMU
//! robot: what the host sends it is held until each `Sync`, it answers with `Idle`, and what
//! it says reaches its bridge in whole batches. So `cimax arena conform` compares the two
//! builds on exactly the same inputs at the same instants.
//!
//! [`Lockstep`]: super::lockstep::Lockstep

use std::cell::{Cell, RefCell};
use std::future::Future;
use std::pin::Pin;
use std::rc::Rc;
use std::task::{Context, Poll, Waker};

use firmware::Config;
use firmware::hil::robot::{HostClock, Link, RNG_STREAM, run};
use protocol::Instant;
use rand_pcg::Pcg32;
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};

use super::in_process::ChanWriter;
use crate::board::clock::EmuClock;
use crate::board::light::EmuReceiver;

/// A twin's clock: milliseconds set by the host's `Sync`s, and the timers waiting on it, in
/// the order they were set.
#[derive(Debug, Default)]
pub(crate) struct TwinClock {
    now: Cell<u64>,
    timers: RefCell<Vec<(u64, Waker)>>,
}

impl TwinClock {
    fn follow(&self) {
        self.now.set(0);
        self.timers.borrow_mut().clear();
    }

    fn set_now(&self, ms: u64) {
        self.now.set(self.now.get().max(ms));
        let now = self.now.get();
        let due: Vec<Waker> = {
            let mut timers = self.timers.borrow_mut();
            let (due, left): (Vec<_>, Vec<_>) = timers.drain(..).partition(|(at, _)| *at <= now);
            *timers = left;
            due.into_iter().map(|(_, w)| w).collect()
        };
        for w in due {
            w.wake();
        }
    }

    fn next_alarm(&self) -> u64 {
        self.timers
            .borrow()
            .iter()
            .map(|&(at, _)| at)
            .min()
            .unwrap_or(u64::MAX)
    }
}

thread_local! {
    /// The clock of the twin being polled: the link's [`HostClock`] hooks are plain functions
    /// (the MCU's driver is a static), so the twin's poll says whose clock they move.
    static POLLED: RefCell<Option<Rc<TwinClock>>> = const { RefCell::new(None) };
}

fn with_polled(f: impl FnOnce(&TwinClock)) {
    POLLED.with_borrow(|c| {
        if let Some(c) = c {
            f(c);
        }
    });
}

/// The [`HostClock`] hooks of a twin: they move the clock of the twin being polled.
const HOOKS: HostClock = HostClock {
    follow: |on| {
        if on {
            with_polled(TwinClock::follow);
        }
    },
    set_now: |ms| with_polled(|c| c.set_now(ms)),
    next_alarm: || {
        let mut next = u64::MAX;
        with_polled(|c| next = c.next_alarm());
        next
    },
};

/// The twin's [`firmware::Clock`].
#[derive(Clone, Debug)]
struct Handle(Rc<TwinClock>);

impl firmware::Clock for Handle {
    fn now(&self) -> Instant {
        Instant::from_millis(self.0.now.get())
    }

    async fn sleep_until(&self, deadline: Instant) {
        let at = deadline.as_millis();
        std::future::poll_fn(|cx| {
            if self.0.now.get() >= at {
                return Poll::Ready(());
            }
            if deadline != Instant::MAX {
                // As embassy's queue: one entry per waker, at the earliest time asked.
                let mut timers = self.0.timers.borrow_mut();
                match timers.iter_mut().find(|(_, w)| w.will_wake(cx.waker())) {
                    Some(t) => t.0 = t.0.min(at),
                    None => timers.push((at, cx.waker().clone())),
                }
            }
            Poll::Pending
        })
        .await;
    }
}

/// Polls `inner` with its twin's clock as the one the hooks move.
struct Polled<F> {
    clock: Rc<TwinClock>,
    inner: Pin<Box<F>>,
}

impl<F: Future> Future for Polled<F> {
    type Output = F::Output;

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<F::Output> {
        /// Puts the clock polled before back, however the poll ends (a panic included).
        struct Restore(Option<Rc<TwinClock>>);
        impl Drop for Restore {
            fn drop(&mut self) {
                POLLED.set(self.0.take());
            }
        }
        let _restore = Restore(POLLED.replace(Some(self.clock.clone())));
        self.inner.as_mut().poll(cx)
    }
}

/// A twin in the run: where the host writes to it, what it wrote, and its idle hook.
pub(crate) struct Twin {
    /// Bytes to the robot.
    pub(crate) to_robot: UnboundedSender<Vec<u8>>,
    /// Bytes from the robot.
    pub(crate) from_robot: UnboundedReceiver<Vec<u8>>,
    /// Tells the robot's link that nothing is left to run (its executor's idle hook).
    pub(crate) idle: Rc<dyn Fn()>,
}

impl std::fmt::Debug for Twin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Twin").finish_non_exhaustive()
    }
}

/// Starts a twin with `base` (as the QEMU image's) on `clock`'s executor.
pub(crate) fn start(clock: &EmuClock, base: Config) -> Twin {
    fn with<const N: usize>(clock: &EmuClock, base: Config) -> Twin {
        let (to_host, from_robot) = unbounded_channel::<Vec<u8>>();
        let (to_robot, from_host) = unbounded_channel::<Vec<u8>>();
        let link = Rc::new(Link::<_, N>::with_host_clock(ChanWriter(to_host), HOOKS));
        let twin_clock = Rc::new(TwinClock::default());
        let idle: Rc<dyn Fn()> = {
            let link = link.clone();
            Rc::new(move || link.on_idle())
        };
        let handle = Handle(twin_clock.clone());
        let robot = async move {
            let reader = EmuReceiver::new(from_host);
            let _ = run(
                &*link,
                reader,
                &handle,
                base,
                |seed| Pcg32::new(u64::from(seed), RNG_STREAM),
                &mut (),
            )
            .await;
        };
        clock.spawn(Polled {
            clock: twin_clock,
            inner: Box::pin(robot),
        });
        Twin {
            to_robot,
            from_robot,
            idle,
        }
    }
    match base.params.sectors {
        2 => with::<2>(clock, base),
        3 => with::<3>(clock, base),
        4 => with::<4>(clock, base),
        5 => with::<5>(clock, base),
        6 => with::<6>(clock, base),
        7 => with::<7>(clock, base),
        _ => with::<8>(clock, base),
    }
}
