//! The board's light: a robot's transmitter and its per-sector receivers, the firmware's
//! byte streams ([`embedded_io_async::Write`] and [`Read`]).
//!
//! A transmitter broadcasts each write as one frame into the [`Air`] and returns when its
//! airtime is over; a receiver reads the bytes of the frames that reached its sector, one frame
//! after the other, from a channel. What happens on the way (range, airtime, collisions, loss)
//! is the world's business: the world's light medium implements [`Air`], makes these types
//! when a robot boots and feeds the receivers' channels. These types only hand bytes over.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::fmt;
use std::rc::Rc;
use std::task::{Poll, Waker};

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
///
/// The world feeds a robot's receivers through one [`Light`] (one shared inbox for all of
/// them, [`receivers`]): a frame wakes the robot's task once, and a robot with nothing to read
/// costs a look at one small struct, not one channel per sector. A receiver can also read a
/// channel of byte chunks: a serial link, as the robot in the loop's.
#[derive(Debug)]
pub struct EmuReceiver {
    source: Source,
    buf: Vec<u8>,
    pos: usize,
}

#[derive(Debug)]
enum Source {
    Channel(UnboundedReceiver<Vec<u8>>),
    Light {
        light: Rc<RefCell<Inbox>>,
        sector: usize,
    },
}

/// What the world has put into a robot's receivers and not yet read: frames per sector, in
/// the order they arrived, and who to wake.
#[derive(Debug, Default)]
struct Inbox {
    frames: Vec<VecDeque<Vec<u8>>>,
    wakers: Vec<Option<Waker>>,
    /// The robot is detached from the light: its receivers read to the end of what came, then
    /// end (`Ok(0)`), as a channel whose senders are gone.
    closed: bool,
}

/// The world's end of a robot's receivers: it puts frames in, sector by sector, and closes
/// them when the robot dies. Dropping it closes them too.
#[derive(Debug)]
pub struct Light(Rc<RefCell<Inbox>>);

impl Light {
    /// Puts `frame` into receiver `sector` and wakes its reader; a sector the robot does not
    /// have gets nothing.
    pub fn put(&self, sector: usize, frame: Vec<u8>) {
        let waker = {
            let mut inbox = self.0.borrow_mut();
            let Some(q) = inbox.frames.get_mut(sector) else {
                return;
            };
            q.push_back(frame);
            inbox.wakers.get_mut(sector).and_then(Option::take)
        };
        if let Some(w) = waker {
            w.wake();
        }
    }

    /// Closes every receiver: each reads what it still has, then ends.
    pub fn close(&self) {
        let wakers: Vec<Waker> = {
            let mut inbox = self.0.borrow_mut();
            inbox.closed = true;
            inbox.wakers.iter_mut().filter_map(Option::take).collect()
        };
        for w in wakers {
            w.wake();
        }
    }
}

impl Drop for Light {
    fn drop(&mut self) {
        self.close();
    }
}

/// `sectors` receivers fed through one [`Light`], indexed by sector.
pub fn receivers(sectors: usize) -> (Light, Vec<EmuReceiver>) {
    let inbox = Rc::new(RefCell::new(Inbox {
        frames: (0..sectors).map(|_| VecDeque::new()).collect(),
        wakers: vec![None; sectors],
        closed: false,
    }));
    let rx = (0..sectors)
        .map(|sector| EmuReceiver {
            source: Source::Light {
                light: inbox.clone(),
                sector,
            },
            buf: Vec::new(),
            pos: 0,
        })
        .collect();
    (Light(inbox), rx)
}

impl EmuReceiver {
    /// A receiver reading what the world puts into `rx`, one chunk of bytes per message.
    pub(crate) fn new(rx: UnboundedReceiver<Vec<u8>>) -> Self {
        EmuReceiver {
            source: Source::Channel(rx),
            buf: Vec::new(),
            pos: 0,
        }
    }

    /// The next frame (or chunk), `None` at the end.
    async fn next(&mut self) -> Option<Vec<u8>> {
        match &mut self.source {
            Source::Channel(rx) => rx.recv().await,
            Source::Light { light, sector } => {
                let sector = *sector;
                std::future::poll_fn(|cx| {
                    let mut inbox = light.borrow_mut();
                    if let Some(frame) = inbox.frames.get_mut(sector).and_then(VecDeque::pop_front)
                    {
                        return Poll::Ready(Some(frame));
                    }
                    if inbox.closed {
                        return Poll::Ready(None);
                    }
                    if let Some(slot) = inbox.wakers.get_mut(sector) {
                        match slot {
                            Some(w) if w.will_wake(cx.waker()) => {}
                            _ => *slot = Some(cx.waker().clone()),
                        }
                    }
                    Poll::Pending
                })
                .await
            }
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
            match self.next().await {
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
