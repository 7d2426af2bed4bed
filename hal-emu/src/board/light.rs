//! The board's light: a robot's transmitter and its per-sector receivers, the firmware's
//! byte streams ([`embedded_io_async::Write`] and [`Read`]).
//!
//! A transmitter broadcasts each write as one frame into the [`Air`] and returns when its
//! airtime is over; the receivers ([`EmuReceivers`], the firmware's `Receivers`) read the
//! bytes of the frames that reached each sector, one frame after the other. What happens on
//! the way (range, airtime, collisions, loss) is the world's business: the world's light medium implements [`Air`], makes these types
//! when a robot boots and feeds the receivers' channels. These types only hand bytes over.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::fmt;
use std::rc::Rc;
use std::task::{Context, Poll, Waker};

use embedded_io_async::{ErrorKind, ErrorType, Read, Write};
use firmware::Clock;
use firmware::hal::Receivers;
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

/// A robot's light receivers, one per sector, read as one ([`firmware::hal::Receivers`]): the
/// bytes of the frames that reached each sector, one frame after the other.
///
/// The world feeds them through one [`Light`] (one inbox for all sectors, [`receivers`]): a
/// frame wakes the robot once, and a robot with nothing to read costs a look at one bit mask.
#[derive(Debug)]
pub struct EmuReceivers {
    light: Rc<RefCell<Inbox>>,
    /// The rest of a frame longer than the read that took it: its sector, bytes and how far
    /// they were read.
    rest: Option<(usize, Rc<[u8]>, usize)>,
}

/// What the world has put into a robot's receivers and not yet read: frames per sector, in
/// the order they arrived, and who to wake.
#[derive(Debug, Default)]
struct Inbox {
    frames: Vec<VecDeque<Rc<[u8]>>>,
    /// Bit `s` set: sector `s` has frames.
    ready: u8,
    waker: Option<Waker>,
    /// The robot is detached from the light: its receivers read to the end of what came, then
    /// end (`Ok(0)`), as a channel whose senders are gone.
    closed: bool,
}

/// The world's end of a robot's receivers: it puts frames in, sector by sector, and closes
/// them when the robot dies. Dropping it closes them too.
#[derive(Debug)]
pub struct Light(Rc<RefCell<Inbox>>);

impl Light {
    /// Puts `frame` into receiver `sector` and wakes the robot; a sector the robot does not
    /// have gets nothing.
    pub fn put(&self, sector: usize, frame: impl Into<Rc<[u8]>>) {
        let frame = frame.into();
        let waker = {
            let mut inbox = self.0.borrow_mut();
            let Some(q) = inbox.frames.get_mut(sector) else {
                return;
            };
            q.push_back(frame);
            inbox.ready |= bit(sector);
            inbox.waker.take()
        };
        if let Some(w) = waker {
            w.wake();
        }
    }

    /// Closes every receiver: each reads what it still has, then ends.
    pub fn close(&self) {
        let waker = {
            let mut inbox = self.0.borrow_mut();
            inbox.closed = true;
            inbox.waker.take()
        };
        if let Some(w) = waker {
            w.wake();
        }
    }
}

impl Drop for Light {
    fn drop(&mut self) {
        self.close();
    }
}

/// Sector `s`'s bit in a mask (none beyond the eighth).
pub(crate) fn bit(s: usize) -> u8 {
    u32::try_from(s)
        .ok()
        .and_then(|s| 1u8.checked_shl(s))
        .unwrap_or(0)
}

/// `sectors` receivers (at most 8) fed through one [`Light`], indexed by sector.
pub fn receivers(sectors: usize) -> (Light, EmuReceivers) {
    let inbox = Rc::new(RefCell::new(Inbox {
        frames: (0..sectors.min(8)).map(|_| VecDeque::new()).collect(),
        ready: 0,
        waker: None,
        closed: false,
    }));
    let rx = EmuReceivers {
        light: inbox.clone(),
        rest: None,
    };
    (Light(inbox), rx)
}

impl EmuReceivers {
    /// How many sectors the receivers have.
    pub fn sectors(&self) -> usize {
        self.light.borrow().frames.len()
    }

    /// What a read of `sectors` into `out` finds now, if anything.
    fn poll_read(
        &mut self,
        sectors: u8,
        out: &mut [u8],
        cx: &mut Context<'_>,
    ) -> Poll<(usize, Result<usize, ErrorKind>)> {
        if let Some((s, bytes, pos)) = &mut self.rest
            && sectors & bit(*s) != 0
        {
            let s = *s;
            let n = copy(bytes, pos, out);
            if *pos >= bytes.len() {
                self.rest = None;
            }
            return Poll::Ready((s, Ok(n)));
        }
        let mut inbox = self.light.borrow_mut();
        let all = bit(inbox.frames.len()).wrapping_sub(1);
        let ready = inbox.ready & sectors;
        if ready != 0 {
            let s = ready.trailing_zeros() as usize;
            let q = &mut inbox.frames[s];
            let frame = q.pop_front().unwrap_or_default();
            if q.is_empty() {
                inbox.ready &= !bit(s);
            }
            let mut pos = 0;
            let n = copy(&frame, &mut pos, out);
            if pos < frame.len() {
                self.rest = Some((s, frame, pos));
            }
            return Poll::Ready((s, Ok(n)));
        }
        let asked = sectors & all;
        if inbox.closed && asked != 0 {
            return Poll::Ready((asked.trailing_zeros() as usize, Ok(0)));
        }
        match &inbox.waker {
            Some(w) if w.will_wake(cx.waker()) => {}
            _ => inbox.waker = Some(cx.waker().clone()),
        }
        Poll::Pending
    }
}

/// Copies what `out` holds of `bytes[*pos..]` and moves `pos` on; how many.
fn copy(bytes: &[u8], pos: &mut usize, out: &mut [u8]) -> usize {
    let rest = bytes.get(*pos..).unwrap_or(&[]);
    let n = rest.len().min(out.len());
    out[..n].copy_from_slice(&rest[..n]);
    *pos += n;
    n
}

impl Receivers for EmuReceivers {
    type Error = ErrorKind;

    async fn read(&mut self, sectors: u8, buf: &mut [u8]) -> (usize, Result<usize, ErrorKind>) {
        std::future::poll_fn(|cx| self.poll_read(sectors, buf, cx)).await
    }
}

/// A byte stream over a channel of byte chunks ([`embedded_io_async::Read`]): what a light
/// receiver is, for the robot in the loop's link in this process.
#[derive(Debug)]
pub struct EmuReceiver {
    rx: UnboundedReceiver<Vec<u8>>,
    buf: Vec<u8>,
    pos: usize,
}

impl EmuReceiver {
    /// A receiver reading what the world puts into `rx`, one chunk of bytes per message.
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
        Ok(copy(&self.buf, &mut self.pos, out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test(flavor = "current_thread")]
    async fn receivers_read_lowest_sector_first_then_end_when_closed() {
        let (light, mut rx) = receivers(3);
        assert_eq!(rx.sectors(), 3);
        light.put(2, b"two".to_vec());
        light.put(0, b"zero".to_vec());
        light.put(2, vec![9; 40]);
        light.put(7, b"no such sector".to_vec());
        let mut buf = [0u8; 32];
        let mut read = async |asked: u8| {
            let (s, r) = rx.read(asked, &mut buf).await;
            (s, r.map(|n| buf[..n].to_vec()))
        };
        assert_eq!(read(0b111).await, (0, Ok(b"zero".to_vec())));
        // Only the sectors asked for.
        assert_eq!(read(0b110).await, (2, Ok(b"two".to_vec())));
        // A frame longer than the buffer comes in two reads.
        assert_eq!(read(0b111).await, (2, Ok(vec![9; 32])));
        assert_eq!(read(0b111).await, (2, Ok(vec![9; 8])));
        drop(light);
        // Closed and empty: each sector asked for ends, lowest first.
        assert_eq!(read(0b110).await, (1, Ok(vec![])));
        assert_eq!(read(0b100).await, (2, Ok(vec![])));
    }
}
