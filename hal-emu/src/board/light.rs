//! The board's light: a robot's transmitter and its per-sector receivers, the firmware's
//! byte streams ([`embedded_io_async::Write`] and [`Read`]) over the world's light medium
//! ([`crate::world::medium`]).
//!
//! A transmitter broadcasts each write as one frame and returns when its airtime is over; a
//! receiver reads the bytes of the frames that reached its sector, one frame after the other.
//! What happens on the way (range, airtime, collisions, loss) is the medium's business: these
//! types only hand bytes over. [`Medium::attach`] makes them when a robot boots.

use embedded_io_async::{ErrorKind, ErrorType, Read, Write};
use firmware::Clock;
use tokio::sync::mpsc::UnboundedReceiver;

use crate::world::medium::{Emission, Medium, SharedMedium};

/// A robot's light transmitter: an [`embedded_io_async::Write`] that broadcasts each write as
/// one frame and returns when its airtime is over.
#[derive(Debug)]
pub struct EmuTransmitter {
    medium: SharedMedium,
    robot: usize,
}

impl EmuTransmitter {
    /// Robot `robot`'s transmitter into `medium` ([`Medium::attach`] hands them out).
    pub(crate) fn new(medium: SharedMedium, robot: usize) -> Self {
        EmuTransmitter { medium, robot }
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
        let end = Medium::transmit(&self.medium, self.robot, buf, Emission::Frame);
        let clock = self.medium.borrow().clock();
        clock.sleep_until(end).await;
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
    /// A receiver reading what the medium puts into `rx`, one frame per message
    /// ([`Medium::attach`] hands them out).
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
