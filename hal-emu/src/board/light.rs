//! The board's light: a robot's transmitter and its per-sector receivers, the firmware's
//! byte streams ([`embedded_io_async::Write`] and [`Read`]).
//!
//! A transmitter broadcasts each write as one frame into the [`Air`] and returns when its
//! airtime is over; a receiver reads the bytes of the frames that reached its sector, one frame
//! after the other, from a channel. What happens on the way (range, airtime, collisions, loss)
//! is the world's business: the world's light medium implements [`Air`], makes these types
//! when a robot boots and feeds the receivers' channels. These types only hand bytes over.

use std::fmt;

use embedded_io_async::{ErrorKind, ErrorType, Read, Write};
use firmware::Clock;
use protocol::Instant;
use tokio::sync::mpsc::UnboundedReceiver;

use crate::board::clock::EmuClock;

/// The light a robot's transmitter sends into, as the board sees it: the world's light medium
/// implements it (`world::medium`).
pub trait Air: fmt::Debug {
    /// Starts robot `robot`'s transmission of `frame` now; returns when its airtime ends.
    fn transmit(&self, robot: usize, frame: &[u8]) -> Instant;
}

/// A robot's light transmitter: an [`embedded_io_async::Write`] that broadcasts each write as
/// one frame and returns when its airtime is over.
#[derive(Debug)]
pub struct EmuTransmitter {
    air: Box<dyn Air>,
    clock: EmuClock,
    robot: usize,
}

impl EmuTransmitter {
    /// Robot `robot`'s transmitter into `air`, waiting out each frame's airtime on `clock`
    /// (the world's medium hands them out when the robot boots).
    pub(crate) fn new(air: Box<dyn Air>, clock: EmuClock, robot: usize) -> Self {
        EmuTransmitter { air, clock, robot }
    }
}

impl ErrorType for EmuTransmitter {
    type Error = ErrorKind;
}

impl Write for EmuTransmitter {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        if buf.is_empty() {
            return Ok(0);
        }
        let end = self.air.transmit(self.robot, buf);
        self.clock.sleep_until(end).await;
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

/// A robot's light receiver for one sector: an [`embedded_io_async::Read`] of the bytes that
/// reached it.
#[derive(Debug)]
pub struct EmuReceiver {
    rx: UnboundedReceiver<Vec<u8>>,
    buf: Vec<u8>,
    pos: usize,
}

impl EmuReceiver {
    /// A receiver reading what the world puts into `rx`, one frame per message (the world's
    /// medium hands them out when the robot boots).
    pub(crate) fn new(rx: UnboundedReceiver<Vec<u8>>) -> Self {
        EmuReceiver {
            rx,
            buf: Vec::new(),
            pos: 0,
        }
    }
}

impl ErrorType for EmuReceiver {
    type Error = ErrorKind;
}

impl Read for EmuReceiver {
    async fn read(&mut self, out: &mut [u8]) -> Result<usize, ErrorKind> {
        if out.is_empty() {
            return Ok(0);
        }
        while self.pos >= self.buf.len() {
            match self.rx.recv().await {
                Some(b) => {
                    self.buf = b;
                    self.pos = 0;
                }
                None => return Ok(0),
            }
        }
        let n = out.len().min(self.buf.len() - self.pos);
        out[..n].copy_from_slice(&self.buf[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}
