//! A robot in the loop on the host's clock (link version 2, `docs/hil.md` "Time"), driven by a
//! scripted host that plays the arena's lockstep: `Sync(T)`, run until nothing can run, the
//! executor's idle hook, the robot's `Idle { now: T, next }`, then `Sync(next)`.
//!
//! What the robot does from its `Setup` on must not depend on how long it ran on its own clock
//! before (wall time, for a QEMU robot): CI's determinism check once failed on a beat whose
//! own-clock sleep, polled again after the setup, set a timer on the host's clock.

use std::cell::{Cell, RefCell};
use std::future::Future;
use std::pin::pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::task::{Context, Poll, Wake, Waker};

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::pipe::Pipe;
use firmware::Config;
use firmware::hil::robot::{HostClock, Link, RNG_STREAM, run};
use firmware::hil::{LINK_FRAME_MAX, LinkDecoder, LinkMsg, Setup, encode};
use firmware::protocol::auth::SwarmKey;
use firmware::protocol::{Deframer, Instant};
use rand_pcg::Pcg32;

type Wire = Pipe<NoopRawMutex, 8192>;

/// The robot's clock: its own milliseconds until it follows the host's, then the host's; and
/// the timers set on it (as embassy's queue: one per waker, the earliest asked).
#[derive(Default)]
struct TestClock {
    now: Cell<u64>,
    timers: RefCell<Vec<(u64, Waker)>>,
}

thread_local! {
    static CLOCK: TestClock = TestClock::default();
}

/// The [`HostClock`] hooks over [`CLOCK`] (plain functions, as the MCU's driver is a static).
const HOOKS: HostClock = HostClock {
    follow: |on| {
        if on {
            CLOCK.with(|c| {
                c.now.set(0);
                c.timers.borrow_mut().clear();
            });
        }
    },
    set_now: |ms| {
        CLOCK.with(|c| {
            c.now.set(c.now.get().max(ms));
            let now = c.now.get();
            let due: Vec<Waker> = {
                let mut timers = c.timers.borrow_mut();
                let (due, left): (Vec<_>, Vec<_>) =
                    timers.drain(..).partition(|(at, _)| *at <= now);
                *timers = left;
                due.into_iter().map(|(_, w)| w).collect()
            };
            due.into_iter().for_each(Waker::wake);
        });
    },
    next_alarm: || {
        CLOCK.with(|c| {
            c.timers
                .borrow()
                .iter()
                .map(|&(at, _)| at)
                .min()
                .unwrap_or(u64::MAX)
        })
    },
};

/// The robot's [`firmware::Clock`]: [`CLOCK`].
#[derive(Clone, Copy)]
struct Handle;

impl firmware::Clock for Handle {
    fn now(&self) -> Instant {
        Instant::from_millis(CLOCK.with(|c| c.now.get()))
    }

    async fn sleep_until(&self, deadline: Instant) {
        let at = deadline.as_millis();
        std::future::poll_fn(|cx| {
            CLOCK.with(|c| {
                if c.now.get() >= at {
                    return Poll::Ready(());
                }
                let mut timers = c.timers.borrow_mut();
                match timers.iter_mut().find(|(_, w)| w.will_wake(cx.waker())) {
                    Some(t) => t.0 = t.0.min(at),
                    None => timers.push((at, cx.waker().clone())),
                }
                Poll::Pending
            })
        })
        .await;
    }
}

/// A waker that records that it was woken.
struct Flag(AtomicBool);

impl Wake for Flag {
    fn wake(self: Arc<Self>) {
        self.0.store(true, Ordering::SeqCst);
    }
}

fn frame(msg: &LinkMsg) -> Vec<u8> {
    let mut buf = [0u8; LINK_FRAME_MAX];
    encode(msg, &mut buf).unwrap().to_vec()
}

fn setup() -> Setup {
    Setup {
        id: 3,
        seed: 7,
        // The paper's timing (the lab at 55 s cycles): a sensor reading every second, so a
        // stray timer between two readings is the robot's next.
        cycle_ms: 55_000,
        spread_ms: 15_000,
        relay_ms: 1_000,
        refractory_ms: 4_000,
        negotiation: 3,
        adaptive: true,
        sample_ms: 1_000,
        host_clock: true,
    }
}

/// Boots a robot whose own clock reads `booted` ms, lets it say hello, sets it up on the host's
/// clock (with the swarm key `key`: a `Key` before the `Setup`) and plays the lockstep until
/// `until` ms: every message it said from its setup on.
fn lockstep(booted: u64, until: u32, key: Option<SwarmKey>) -> Vec<LinkMsg> {
    CLOCK.with(|c| {
        c.now.set(booted);
        c.timers.borrow_mut().clear();
    });
    let to_robot = Wire::new();
    let from_robot = Wire::new();
    let link = Link::<_, 2>::with_host_clock(&from_robot, HOOKS);
    let base = Config {
        id: 9,
        ..Config::robots()
    };
    let mut observer = ();
    let mut robot = pin!(run(
        &link,
        &to_robot,
        &Handle,
        base,
        |seed| Pcg32::new(u64::from(seed), RNG_STREAM),
        &mut observer,
    ));
    let flag = Arc::new(Flag(AtomicBool::new(true)));
    let waker = Waker::from(flag.clone());
    let mut cx = Context::from_waker(&waker);
    // Polls the robot until nothing can run, then calls the executor's idle hook (once: what
    // it wakes runs, and the robot is idle again).
    let mut settle = |idle_hook: bool| {
        for round in 0..2 {
            let mut polls = 0;
            while flag.0.swap(false, Ordering::SeqCst) {
                assert!(robot.as_mut().poll(&mut cx).is_pending());
                polls += 1;
                assert!(polls < 100_000, "the robot never settles");
            }
            if round == 0 && idle_hook {
                link.on_idle();
            }
        }
    };
    let mut decoder = LinkDecoder::new();
    let said = |decoder: &mut LinkDecoder| {
        let mut buf = [0u8; 512];
        let mut out = Vec::new();
        while let Ok(n @ 1..) = from_robot.try_read(&mut buf) {
            out.extend(buf[..n].iter().filter_map(|&b| decoder.push(b)).flatten());
        }
        out
    };
    // Booted: it says hello on its own clock.
    settle(false);
    let hellos = said(&mut decoder);
    assert!(
        matches!(
            hellos.as_slice(),
            [LinkMsg::Hello {
                host_clock: true,
                ..
            }]
        ),
        "{hellos:?}"
    );
    // The run: a reading, the setup and `Sync(0)`, byte by byte (as a UART delivers them, each
    // byte polling the robot), then `Sync(next)` after each `Idle`.
    let mut bytes = frame(&LinkMsg::Reading {
        quantity: 0,
        level: 120,
    });
    if let Some(key) = key {
        bytes.extend(frame(&LinkMsg::Key(key)));
    }
    bytes.extend(frame(&LinkMsg::Setup(setup())));
    let mut now = 0;
    let mut out = Vec::new();
    loop {
        bytes.extend(frame(&LinkMsg::Sync(now)));
        for b in std::mem::take(&mut bytes) {
            assert_eq!(to_robot.try_write(&[b]), Ok(1));
            flag.0.store(true, Ordering::SeqCst);
            settle(false);
        }
        settle(true);
        let batch = said(&mut decoder);
        let next = match batch.last() {
            Some(&LinkMsg::Idle { now: t, next }) if t == now => next,
            other => panic!("no Idle for Sync({now}) but {other:?} in {batch:?}"),
        };
        out.extend(batch);
        if next >= until {
            return out;
        }
        now = next;
    }
}

#[test]
fn what_a_robot_does_on_the_hosts_clock_does_not_depend_on_its_own_clock_before() {
    let fresh = lockstep(0, 120_000, None);
    let waited = lockstep(1_213, 120_000, None);
    let instants = |msgs: &[LinkMsg]| -> Vec<u32> {
        msgs.iter()
            .filter_map(|m| match m {
                LinkMsg::Idle { now, .. } => Some(*now),
                _ => None,
            })
            .collect()
    };
    // No instant of the own clock's beats (500 ms and 1,713 ms) became a timer (before the
    // fix, the fresh robot said `Idle` at 500 ms: its first program timer came at 1 s).
    assert!(
        !instants(&waited).contains(&1_713),
        "{:?}",
        instants(&waited)
    );
    assert!(!instants(&fresh).contains(&500), "{:?}", instants(&fresh));
    assert_eq!(instants(&fresh), instants(&waited));
    assert_eq!(fresh, waited);
    // The robot program ran: light frames were sent, on the host's clock.
    assert!(
        fresh.iter().any(|m| matches!(m, LinkMsg::Tx(_))),
        "{fresh:?}"
    );
}

/// The light frames a robot sent, as one byte stream.
fn light(msgs: &[LinkMsg]) -> Vec<u8> {
    msgs.iter()
        .filter_map(|m| match m {
            LinkMsg::Tx(b) => Some(b.as_slice()),
            _ => None,
        })
        .flatten()
        .copied()
        .collect()
}

#[test]
fn a_key_before_the_setup_makes_the_run_keyed() {
    let key = SwarmKey::new([0x5A; 16]);
    let keyed = light(&lockstep(0, 120_000, Some(key)));
    let plain = light(&lockstep(0, 120_000, None));
    assert!(!keyed.is_empty() && !plain.is_empty());
    // Every frame of the keyed run carries the key's MAC: the keyed deframer takes them all,
    // a plain one (or one with another key) none.
    let mut with_key = Deframer::with_key(key);
    let good = with_key.frames(&keyed).filter(Result::is_ok).count();
    assert!(good > 0);
    assert_eq!(with_key.frames(&keyed).filter(Result::is_err).count(), 0);
    let mut without = Deframer::new();
    assert_eq!(without.frames(&keyed).filter(Result::is_ok).count(), 0);
    let mut other = Deframer::with_key(SwarmKey::new([0xA5; 16]));
    assert_eq!(other.frames(&keyed).filter(Result::is_ok).count(), 0);
    // Without a `Key` the run is plain.
    let mut plain_deframer = Deframer::new();
    assert!(plain_deframer.frames(&plain).filter(Result::is_ok).count() > 0);
    assert_eq!(with_key.frames(&plain).filter(Result::is_ok).count(), 0);
}
