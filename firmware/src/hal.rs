//! The hardware seam: what a board (or the emulator) must provide to run the robot program.
//!
//! | Hardware                         | Trait                                          |
//! |----------------------------------|------------------------------------------------|
//! | modulated-light transmitter (one, broadcasting) | [`embedded_io_async::Write`]    |
//! | modulated-light receivers (one per sector)      | [`Receivers`]: an array of [`embedded_io_async::Read`] |
//! | environmental sensor (ambient light, oxygen)    | [`Sensor`]                      |
//! | top-cap LEDs (green = left, blue = right)       | [`Leds`]                        |
//! | time                                            | [`Clock`]                       |
//!
//! The light link is a byte stream both ways, so a UART driver (embassy-stm32's `UartTx` and
//! `RingBufferedUartRx`, an `embassy_sync::pipe::Pipe`, a tokio stream behind
//! `embedded-io-adapters`) plugs in with no glue: an array of receivers, one per sector, is
//! [`Receivers`], read as one. A board that hears every sector through one source (the
//! emulator's light) implements [`Receivers`] itself. The other traits follow embedded-hal-async:
//! fallible `async fn`s, an associated error type whose [`Error::kind`] says what went wrong,
//! and blanket implementations for `&mut T` (and `&T` for the clock).
//!
//! Nothing here reads a global clock: the robot program only knows the time its [`Clock`] tells
//! it, so the emulator can run robots in virtual time.

// The traits are used generically on one executor; callers never need `Send` futures.
#![allow(async_fn_in_trait)]

use embassy_futures::select::select_array;
use protocol::{Instant, Level, Sector};

/// A robot's light receivers, one per sector, read as one: a read waits until some sector has
/// bytes (or an error, or the end of its stream) and returns that sector's.
///
/// One future for every sector: the robot waits on "a receiver OR the next deadline", one
/// look at one source per wake, instead of one listener per sector joined beside it.
///
/// An array of byte streams, `[R; N]` with `R:` [`embedded_io_async::Read`], is
/// `Receivers`, receiver `i` facing sector `i`; see its implementation for what it needs of
/// `R`. Sector numbers are indices: with two sectors, 0 is [`Sector::RIGHT`] and 1
/// [`Sector::LEFT`].
pub trait Receivers {
    /// Returned by a receiver that failed.
    type Error: embedded_io_async::Error;

    /// Waits until one of the sectors in `sectors` (bit `i` for sector `i`) has bytes, an
    /// error, or the end of its stream, and returns that sector with what it read into `buf`:
    /// `Ok(n)` bytes (`n >= 1` for a non-empty `buf`), `Ok(0)` at the end of its stream (it is
    /// not read again), or its error. With no sector in `sectors` it waits for ever. When more
    /// than one sector has something, the lowest-numbered goes first.
    ///
    /// Cancel-safe: the robot drops this future when its next deadline comes first, and a
    /// read dropped before it completed must lose no byte.
    async fn read(&mut self, sectors: u8, buf: &mut [u8]) -> (usize, Result<usize, Self::Error>);
}

/// `N` byte streams, one per sector, indexed by sector: each read polls the streams of the
/// sectors asked for, lowest first, each into its share of `buf` (`buf.len() / N` bytes, so
/// `buf` needs at least one byte per sector: with fewer, the last sectors are not read), and
/// returns the first that has something, its bytes copied to the front of `buf`.
///
/// `R::read` must be cancel-safe (the other streams' reads are dropped): embassy-stm32's
/// `RingBufferedUartRx` and `BufferedUartRx`, embassy-sync's `Pipe` and a tokio channel's
/// receiver are.
impl<R: embedded_io_async::Read, const N: usize> Receivers for [R; N] {
    type Error = R::Error;

    async fn read(&mut self, sectors: u8, buf: &mut [u8]) -> (usize, Result<usize, R::Error>) {
        let share = (buf.len() / N.max(1)).max(1);
        let (winner, got) = {
            let mut streams = self.iter_mut();
            let mut shares = buf.chunks_mut(share);
            let mut i = 0;
            let reads: [_; N] = core::array::from_fn(|_| {
                let asked = i < 8 && sectors & (1 << i) != 0;
                i += 1;
                let (rx, out) = (streams.next(), shares.next());
                async move {
                    match (rx, out) {
                        (Some(rx), Some(out)) if asked => rx.read(out).await,
                        _ => core::future::pending().await,
                    }
                }
            });
            let (got, winner) = select_array(reads).await;
            (winner, got)
        };
        let got = got.map(|n| {
            // `min`: a driver claiming more than its share cannot make us index out of bounds.
            let n = n.min(share);
            // Shares do not overlap the front (`n <= share <= start`): a copy, not a move.
            let (front, rest) = buf.split_at_mut((winner * share).min(buf.len()));
            if let (Some(to), Some(from)) = (front.get_mut(..n), rest.get(..n)) {
                to.copy_from_slice(from);
            }
            n
        });
        (winner, got)
    }
}

impl<T: Receivers + ?Sized> Receivers for &mut T {
    type Error = T::Error;

    async fn read(&mut self, sectors: u8, buf: &mut [u8]) -> (usize, Result<usize, T::Error>) {
        T::read(self, sectors, buf).await
    }
}

/// What kind of failure a [`Sensor`] or [`Leds`] error is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorKind {
    /// The device did not answer in time.
    Timeout,
    /// The device is not ready (still powering up, being calibrated, busy).
    NotReady,
    /// The device answered with a value that cannot be right (out of range, saturated).
    OutOfRange,
    /// The bus or peripheral failed.
    Bus,
    /// Anything else.
    Other,
}

/// A device error: anything that can say what kind of failure it is.
pub trait Error: core::fmt::Debug {
    /// The kind of failure.
    fn kind(&self) -> ErrorKind;
}

impl Error for ErrorKind {
    fn kind(&self) -> ErrorKind {
        *self
    }
}

impl Error for core::convert::Infallible {
    fn kind(&self) -> ErrorKind {
        match *self {}
    }
}

/// The error type of a device.
pub trait ErrorType {
    /// Returned by the device's fallible operations.
    type Error: Error;
}

impl<T: ErrorType + ?Sized> ErrorType for &mut T {
    type Error = T::Error;
}

/// A quantity the environmental sensor measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Quantity {
    /// Ambient light (the lab experiments: lamps over part of the line).
    AmbientLight,
    /// Dissolved oxygen.
    Oxygen,
}

/// The environmental sensor: ambient light and oxygen, each quantised to a [`Level`].
///
/// The quantisation (ADC counts to 0..=255) is the driver's business; CIMAX only compares
/// readings, so it only has to be the same on every robot.
pub trait Sensor: ErrorType {
    /// Measures the ambient light.
    ///
    /// # Errors
    /// The device's error if the measurement failed.
    async fn ambient_light(&mut self) -> Result<Level, Self::Error>;

    /// Measures the dissolved oxygen.
    ///
    /// # Errors
    /// The device's error if the measurement failed.
    async fn oxygen(&mut self) -> Result<Level, Self::Error>;

    /// Measures `quantity`.
    ///
    /// # Errors
    /// The device's error if the measurement failed.
    async fn read(&mut self, quantity: Quantity) -> Result<Level, Self::Error> {
        match quantity {
            Quantity::AmbientLight => self.ambient_light().await,
            Quantity::Oxygen => self.oxygen().await,
        }
    }
}

impl<T: Sensor + ?Sized> Sensor for &mut T {
    async fn ambient_light(&mut self) -> Result<Level, Self::Error> {
        T::ambient_light(self).await
    }

    async fn oxygen(&mut self) -> Result<Level, Self::Error> {
        T::oxygen(self).await
    }

    async fn read(&mut self, quantity: Quantity) -> Result<Level, Self::Error> {
        T::read(self, quantity).await
    }
}

/// What the top-cap LEDs show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LedColor {
    /// Both off: undecided.
    #[default]
    Off,
    /// Green: the robot decided to go left.
    Green,
    /// Blue: the robot decided to go right.
    Blue,
    /// A robot with more than two sectors decided to go toward this sector (its index): the
    /// top cap shows the sector's direction (a ring of LEDs, or a code on the two).
    Sector(u8),
}

impl LedColor {
    /// The color for a decision: [`Sector::LEFT`] is green, [`Sector::RIGHT`] blue, anything
    /// else (undecided, or a sector a robot in a line does not have) off.
    pub fn for_decision(decision: Option<Sector>) -> LedColor {
        match decision {
            Some(Sector::LEFT) => LedColor::Green,
            Some(Sector::RIGHT) => LedColor::Blue,
            _ => LedColor::Off,
        }
    }

    /// The color for a decision of a robot with `sectors` receive sectors: as
    /// [`for_decision`](Self::for_decision) for two, [`LedColor::Sector`] for more.
    pub fn for_decision_of(decision: Option<Sector>, sectors: u8) -> LedColor {
        match decision {
            Some(s) if sectors > 2 => LedColor::Sector(s.index()),
            _ => LedColor::for_decision(decision),
        }
    }

    /// The decision this color shows, if any.
    pub fn decision(self) -> Option<Sector> {
        match self {
            LedColor::Off => None,
            LedColor::Green => Some(Sector::LEFT),
            LedColor::Blue => Some(Sector::RIGHT),
            LedColor::Sector(i) => Sector::new(i),
        }
    }
}

/// The top-cap LEDs.
pub trait Leds: ErrorType {
    /// Shows `color` (exactly one LED on, or both off) until told otherwise.
    ///
    /// # Errors
    /// The device's error if the LEDs could not be set.
    async fn show(&mut self, color: LedColor) -> Result<(), Self::Error>;
}

impl<T: Leds + ?Sized> Leds for &mut T {
    async fn show(&mut self, color: LedColor) -> Result<(), Self::Error> {
        T::show(self, color).await
    }
}

/// The robot's only source of time.
///
/// `now` is in the protocol's milliseconds since an epoch of the clock's choosing (boot, the
/// start of an emulation); it must never go backwards. `sleep_until` returns once `now()` has
/// reached `deadline` (at once if it already has); it is cancel-safe, and
/// [`Instant::MAX`] means "never".
pub trait Clock {
    /// The current time.
    fn now(&self) -> Instant;

    /// Waits until `deadline`.
    async fn sleep_until(&self, deadline: Instant);
}

impl<C: Clock + ?Sized> Clock for &C {
    fn now(&self) -> Instant {
        C::now(self)
    }

    async fn sleep_until(&self, deadline: Instant) {
        C::sleep_until(self, deadline).await
    }
}

/// [`Clock`] over embassy-time, for boards with an embassy time driver.
///
/// The epoch is embassy's (boot). Deadlines too far away for embassy's tick counter, such as
/// [`Instant::MAX`], wait for ever.
#[cfg(feature = "embassy-time")]
#[derive(Clone, Copy, Debug, Default)]
pub struct EmbassyClock;

#[cfg(feature = "embassy-time")]
impl Clock for EmbassyClock {
    fn now(&self) -> Instant {
        Instant::from_millis(embassy_time::Instant::now().as_millis())
    }

    async fn sleep_until(&self, deadline: Instant) {
        match deadline_ticks(deadline.as_millis(), embassy_time::TICK_HZ) {
            Some(t) => embassy_time::Timer::at(embassy_time::Instant::from_ticks(t)).await,
            None => core::future::pending().await,
        }
    }
}

/// The first tick of a clock of `hz` ticks per second at or after `millis`: rounded up, so that a
/// sleep never ends before its deadline (rounded down, a 32,768 Hz clock woke the robot up to a
/// tick early, its `now()` still below the deadline, and the main loop spun until it passed).
/// `None` if the deadline is beyond the tick counter (such as [`Instant::MAX`]): wait for ever.
/// `u64` arithmetic only: with `u128` (`ms · hz` exact for every deadline) the image carried
/// 128-bit multiply and divide routines, 1.7 KB of flash; a product that overflows `u64` (over
/// 17,000 years at 32,768 Hz) is beyond any tick counter anyway.
pub fn deadline_ticks(millis: u64, hz: u64) -> Option<u64> {
    let ticks = millis.checked_mul(hz)?.div_ceil(1000);
    (ticks < u64::MAX).then_some(ticks)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deadlines_round_up_to_the_next_tick() {
        for hz in [1_000, 32_768, 1_000_000] {
            for ms in 0..5_000u64 {
                let t = deadline_ticks(ms, hz).unwrap();
                // The tick reached is at or after the deadline, and less than a tick after.
                assert!(
                    u128::from(t) * 1000 >= u128::from(ms) * u128::from(hz),
                    "{ms} ms at {hz} Hz"
                );
                assert!(u128::from(t) * 1000 < u128::from(ms) * u128::from(hz) + 1000);
                // What the clock then reads (milliseconds, rounded down) is not before it.
                assert!(t * 1000 / hz >= ms, "{ms} ms at {hz} Hz woke at {t} ticks");
            }
        }
        assert_eq!(deadline_ticks(1, 32_768), Some(33), "32 ticks is 0.977 ms");
        assert_eq!(deadline_ticks(Instant::MAX.as_millis(), 32_768), None);
        assert_eq!(deadline_ticks(u64::MAX / 2, 32_768), None);
    }

    #[test]
    fn decisions_map_to_colors_and_back() {
        assert_eq!(LedColor::for_decision(Some(Sector::LEFT)), LedColor::Green);
        assert_eq!(LedColor::for_decision(Some(Sector::RIGHT)), LedColor::Blue);
        assert_eq!(LedColor::for_decision(None), LedColor::Off);
        assert_eq!(LedColor::for_decision(Sector::new(5)), LedColor::Off);
        for c in [LedColor::Off, LedColor::Green, LedColor::Blue] {
            assert_eq!(LedColor::for_decision(c.decision()), c);
        }
    }
}
