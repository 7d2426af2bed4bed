//! Hardware made of memory: robots wired together in one process.
//!
//! The QEMU board runs four robots in one image with these, and the host tests use them too.
//! A [`Wire`] is one receiver's input (an `embassy_sync` pipe; `&Wire` is an
//! [`embedded_io_async::Read`]); a [`Broadcast`] transmitter writes each frame into the wires of
//! the receivers that can see it. Like light, it never waits: bytes that do not fit a
//! receiver's wire are lost and counted. [`FixedSensor`] reads constant levels, [`LedState`]
//! remembers what the LEDs show so that a supervisor can check it. [`run_line`] puts it all
//! together: robots in a line, each running the unchanged [`Robot::run`].
//!
//! One of three direct lines of robots, each at its own depth (see `protocol::line`'s top
//! comment): `protocol::line` drives the protocol core alone, synchronously, under the
//! protocol's own tests; this one runs the whole robot program without an emulator, `no_std`
//! and on any executor, as the QEMU board needs; `hal-emu`'s arena runs it in a modelled light
//! medium on tokio. Neither of the others could run on the QEMU board.

use core::cell::Cell;
use core::convert::Infallible;

use embassy_futures::join::join_array;
use embassy_futures::select::{Either, select};
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::pipe::Pipe;
use protocol::{Duration, Instant, Level, Sector};
use rand_core::RngCore;

use crate::hal::{Clock, ErrorType, LedColor, Leds, Sensor};
use crate::robot::{Hardware, Observer, Robot, Stats};

/// Bytes of buffer per receiver in [`run_line`]: two full frames.
pub const LINE_WIRE: usize = 64;

/// One receiver's input: bytes written by the transmitters that reach it, `CAP` bytes of buffer.
pub type Wire<const CAP: usize> = Pipe<NoopRawMutex, CAP>;

/// A transmitter wired to up to `K` receivers.
#[derive(Debug)]
pub struct Broadcast<'a, const CAP: usize, const K: usize> {
    wires: [Option<&'a Wire<CAP>>; K],
    lost: u32,
}

impl<'a, const CAP: usize, const K: usize> Broadcast<'a, CAP, K> {
    /// A transmitter reaching the receivers behind `wires` (`None`: nobody on that side).
    pub fn new(wires: [Option<&'a Wire<CAP>>; K]) -> Self {
        Broadcast { wires, lost: 0 }
    }

    /// Bytes lost because a receiver's wire was full.
    pub fn lost(&self) -> u32 {
        self.lost
    }
}

impl<const CAP: usize, const K: usize> embedded_io_async::ErrorType for Broadcast<'_, CAP, K> {
    type Error = Infallible;
}

impl<const CAP: usize, const K: usize> embedded_io_async::Write for Broadcast<'_, CAP, K> {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for wire in self.wires.iter().flatten() {
            // A pipe takes at most what fits before its ring buffer wraps: write in pieces.
            let mut rest = buf;
            while let Ok(n @ 1..) = wire.try_write(rest) {
                rest = rest.get(n..).unwrap_or(&[]);
            }
            let lost = u32::try_from(rest.len()).unwrap_or(u32::MAX);
            self.lost = self.lost.saturating_add(lost);
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// A sensor that always reads the same levels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FixedSensor {
    /// What [`Sensor::ambient_light`] returns.
    pub ambient_light: Level,
    /// What [`Sensor::oxygen`] returns.
    pub oxygen: Level,
}

impl ErrorType for FixedSensor {
    type Error = Infallible;
}

impl Sensor for FixedSensor {
    async fn ambient_light(&mut self) -> Result<Level, Infallible> {
        Ok(self.ambient_light)
    }

    async fn oxygen(&mut self) -> Result<Level, Infallible> {
        Ok(self.oxygen)
    }
}

/// LEDs that remember what they show; `&LedState` is the [`Leds`] a robot gets.
#[derive(Debug, Default)]
pub struct LedState {
    color: Cell<LedColor>,
    updates: Cell<u32>,
}

impl LedState {
    /// Both LEDs off, never updated.
    pub const fn new() -> Self {
        LedState {
            color: Cell::new(LedColor::Off),
            updates: Cell::new(0),
        }
    }

    /// What the LEDs show.
    pub fn color(&self) -> LedColor {
        self.color.get()
    }

    /// How many times they were set (once per decision).
    pub fn updates(&self) -> u32 {
        self.updates.get()
    }
}

impl ErrorType for &LedState {
    type Error = Infallible;
}

impl Leds for &LedState {
    async fn show(&mut self, color: LedColor) -> Result<(), Infallible> {
        self.color.set(color);
        self.updates.set(self.updates.get().wrapping_add(1));
        Ok(())
    }
}

/// How a [`run_line`] ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineReport<const N: usize> {
    /// True if every robot decided the number of times asked for before the deadline.
    pub finished: bool,
    /// When it ended, on the line's clock.
    pub at: Instant,
    /// What each robot's LEDs show, left to right.
    pub shown: [LedColor; N],
    /// Each robot's decisions so far.
    pub decisions: [u32; N],
    /// Bytes each robot's transmitter lost to full wires.
    pub lost: [u32; N],
}

impl<const N: usize> LineReport<N> {
    /// The decisions the LEDs show, left to right.
    pub fn shown_decisions(&self) -> [Option<Sector>; N] {
        self.shown.map(LedColor::decision)
    }
}

/// Runs `robots` (left to right) in a line on `clock` until each has decided `periods` times
/// or `deadline` passes, whichever is first. Robot `i` reads `readings[i]` (both quantities);
/// its transmitter reaches the right receiver of robot `i - 1` and the left receiver of robot
/// `i + 1`, at once and without loss unless a wire is full.
///
/// The robots keep their state: the caller can inspect them afterwards, or run them on.
pub async fn run_line<G: RngCore, C: Clock, const N: usize>(
    robots: &mut [Robot<G, 2>; N],
    readings: [Level; N],
    clock: &C,
    periods: u32,
    deadline: Instant,
) -> LineReport<N> {
    let mut observers = [(); N];
    run_line_observed(robots, &mut observers, readings, clock, periods, deadline).await
}

/// [`run_line`], robot `i` telling `observers[i]` its events and main-loop rounds
/// ([`Robot::run_observed`]): the QEMU board feeds its watchdog this way.
pub async fn run_line_observed<G: RngCore, C: Clock, O: Observer, const N: usize>(
    robots: &mut [Robot<G, 2>; N],
    observers: &mut [O; N],
    readings: [Level; N],
    clock: &C,
    periods: u32,
    deadline: Instant,
) -> LineReport<N> {
    const LEFT: usize = Sector::LEFT.index() as usize;
    const RIGHT: usize = Sector::RIGHT.index() as usize;
    let wires: [[Wire<LINE_WIRE>; 2]; N] = core::array::from_fn(|_| [Wire::new(), Wire::new()]);
    let leds: [LedState; N] = core::array::from_fn(|_| LedState::new());
    let mut hardware: [_; N] = core::array::from_fn(|i| {
        let left_neighbour = i
            .checked_sub(1)
            .and_then(|j| wires.get(j))
            .map(|w| &w[RIGHT]);
        let right_neighbour = wires.get(i + 1).map(|w| &w[LEFT]);
        let level = readings.get(i).copied().unwrap_or_default();
        Hardware::line(
            Broadcast::new([left_neighbour, right_neighbour]),
            &wires[i][LEFT],
            &wires[i][RIGHT],
            FixedSensor {
                ambient_light: level,
                oxygen: level,
            },
            &leds[i],
            clock,
        )
    });
    let mut hw = hardware.iter_mut();
    let mut observers = observers.iter_mut();
    let runs = robots.each_mut().map(|robot| {
        let hw = hw.next();
        let observer = observers.next();
        async move {
            match (hw, observer) {
                (Some(hw), Some(observer)) => robot.run_observed(hw, observer).await,
                _ => core::future::pending().await,
            }
        }
    });
    let done = || leds.iter().all(|l| l.updates() >= periods);
    let watch = async {
        loop {
            if done() {
                return true;
            }
            let now = clock.now();
            if now >= deadline {
                return false;
            }
            clock
                .sleep_until(deadline.min(now + Duration::from_secs(1)))
                .await;
        }
    };
    let finished = match select(join_array(runs), watch).await {
        // Only with no robot at all.
        Either::First(_) => done(),
        Either::Second(finished) => finished,
    };
    LineReport {
        finished,
        at: clock.now(),
        shown: core::array::from_fn(|i| leds[i].color()),
        decisions: core::array::from_fn(|i| leds[i].updates()),
        lost: core::array::from_fn(|i| hardware[i].transmitter.lost()),
    }
}

/// Sums the robots' counters (for a one-line summary).
pub fn total_stats<G: RngCore, const N: usize>(robots: &[Robot<G, 2>; N]) -> Stats {
    robots.iter().fold(Stats::default(), |a, r| {
        let s = r.stats();
        Stats {
            messages: a.messages.wrapping_add(s.messages),
            frame_errors: a.frame_errors.wrapping_add(s.frame_errors),
            bad_mac: a.bad_mac.wrapping_add(s.bad_mac),
            rx_errors: a.rx_errors.wrapping_add(s.rx_errors),
            rx_closed: a.rx_closed.wrapping_add(s.rx_closed),
            transmitted: a.transmitted.wrapping_add(s.transmitted),
            tx_errors: a.tx_errors.wrapping_add(s.tx_errors),
            sensor_errors: a.sensor_errors.wrapping_add(s.sensor_errors),
            led_errors: a.led_errors.wrapping_add(s.led_errors),
            decisions: a.decisions.wrapping_add(s.decisions),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use embassy_futures::block_on;
    use embedded_io_async::{Read, Write};

    #[test]
    fn broadcast_reaches_every_wire_and_counts_overflow() {
        let a: Wire<4> = Wire::new();
        let b: Wire<4> = Wire::new();
        let mut tx = Broadcast::new([Some(&a), None, Some(&b)]);
        assert_eq!(block_on(tx.write(b"abc")), Ok(3));
        assert_eq!(tx.lost(), 0);
        assert_eq!(block_on(tx.write(b"de")), Ok(2), "light never waits");
        assert_eq!(tx.lost(), 2, "one byte lost on each full wire");
        let mut buf = [0u8; 8];
        let n = block_on(Read::read(&mut &a, &mut buf)).unwrap();
        assert_eq!(&buf[..n], b"abcd");
        let n = block_on(Read::read(&mut &b, &mut buf)).unwrap();
        assert_eq!(&buf[..n], b"abcd");
    }

    #[test]
    fn broadcast_wraps_around_a_wire() {
        let w: Wire<4> = Wire::new();
        let mut tx = Broadcast::new([Some(&w)]);
        let mut buf = [0u8; 4];
        block_on(tx.write(b"abc")).unwrap();
        assert_eq!(block_on(Read::read(&mut &w, &mut buf)), Ok(3));
        // The pipe's free space now wraps past its end: all of it is used.
        block_on(tx.write(b"defg")).unwrap();
        assert_eq!(tx.lost(), 0);
        let mut got = [0u8; 8];
        let mut n = 0;
        while !w.is_empty() {
            n += block_on(Read::read(&mut &w, &mut got[n..])).unwrap();
        }
        assert_eq!(&got[..n], b"defg");
    }

    #[test]
    fn led_state_remembers() {
        let s = LedState::new();
        let mut leds = &s;
        block_on(leds.show(LedColor::Blue)).unwrap();
        assert_eq!((s.color(), s.updates()), (LedColor::Blue, 1));
    }
}
