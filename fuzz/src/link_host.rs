//! `link_host`: the host's end of the link reading a robot, as `hal-emu`'s `read_link`
//! (`world/hil/follower.rs`: a QEMU or socket robot, 512-byte reads) and `collect_twin`
//! (`world/hil/lockstep.rs`: the host twin, whatever chunks its channel gives) decode it: a
//! `LinkDecoder` kept across reads of any size.
//!
//! The lockstep's batch rules (`Lockstep::take`: an `Idle` for another instant, a `Hello` after
//! the first answer and more than `FLOOD` messages fail the run) are private to `hal-emu`, which
//! brings tokio, serialport and nalgebra: they are not fuzzed here (the scripted-robot tests
//! `tests/tests/hil_lockstep.rs` cover them). What this target checks is the decoding they
//! rely on: the robot's messages reach the host whole and in order however the bytes were
//! split.
//!
//! Input: a mode byte (modulo 2), then
//!
//! - **0, stream**: a `deframer` input (a header, up to 15 cut bytes, then any byte stream);
//! - **1, batch**: a list of up to [`BATCH_MAX`] items, each optional garbage (a byte list,
//!   sent with a 0x00 after it) and a message ([`link_ref::read_msg`]), then up to 15 cut bytes
//!   (a byte list): the stream is every item's garbage, 0x00 and frame.
//!
//! Checks: the events `read_link` makes of the stream (a message, a `Version(v)` for
//! `UnknownVersion(v)`, an error counted for every other error) are the same fed in one piece,
//! in the cut lengths (0..=40, in turn; the decoder also cloned at each of the first 4 cuts and
//! the clone going on), in 512-byte reads, and byte by byte through the model decoder
//! ([`crate::link_ref`]), with the model's counters; the twin's path (only the messages kept)
//! gives the messages of those events. In batch mode the events are exactly, item by item, what
//! its garbage gives on its own and then its message (a `Hello` of another version as its
//! `Version`): garbage set off by a 0x00 costs no message of the robot's.

use arbitrary::Unstructured;
use firmware::hil::{LINK_VERSION, LinkDecoder, LinkError, LinkMsg};

use crate::deframer::{self, slices};
use crate::input::{Writer, byte_list, get, list};
use crate::link_ref::{self, ModelDecoder};

/// Items of a batch at most.
pub const BATCH_MAX: usize = 24;
/// Garbage bytes before an item at most.
pub const GARBAGE_MAX: usize = 48;

/// Cuts at which a copy of the decoder is checked (each costs a pass over the rest).
pub const CLONED_CUTS: usize = 4;

/// The mode bytes.
pub const STREAM: u8 = 0;
/// See the module documentation.
pub const BATCH: u8 = 1;

/// What the host's reader makes of one result.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Event {
    /// A message for the lockstep.
    Msg(LinkMsg),
    /// The robot speaks another link version (the run fails).
    Version(u8),
    /// A bad frame, counted.
    Error,
}

/// `read_link`'s mapping of a decoder result.
pub fn event(r: Result<LinkMsg, LinkError>) -> Event {
    match r {
        Ok(m) => Event::Msg(m),
        Err(LinkError::UnknownVersion(v)) => Event::Version(v),
        Err(_) => Event::Error,
    }
}

/// One item of a batch.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Item {
    /// Bytes sent before it (and a 0x00), if any.
    pub garbage: Option<Vec<u8>>,
    /// The message.
    pub msg: LinkMsg,
}

/// A batch input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Batch {
    /// The items, in order.
    pub items: Vec<Item>,
    /// The read lengths (see [`deframer::slices`]).
    pub cuts: Vec<u8>,
}

impl Batch {
    /// Reads a batch (after the mode byte).
    pub fn read(data: &[u8]) -> Batch {
        let mut u = Unstructured::new(data);
        let items = list(&mut u, BATCH_MAX, |u| Item {
            garbage: get::<bool>(u).then(|| byte_list(u, GARBAGE_MAX)),
            msg: link_ref::read_msg(u),
        });
        let cuts = byte_list(&mut u, deframer::MAX_CUTS);
        Batch { items, cuts }
    }

    /// The input [`check`] reads as this batch (the mode byte included).
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        w.u8(BATCH);
        for i in &self.items {
            w.item();
            match &i.garbage {
                Some(g) => {
                    w.bool(true).byte_list(g);
                }
                None => {
                    w.bool(false);
                }
            }
            link_ref::write_msg(&mut w, &i.msg);
        }
        w.end().byte_list(&self.cuts);
        w.finish()
    }

    /// The byte stream.
    pub fn stream(&self) -> Vec<u8> {
        let mut s = Vec::new();
        for i in &self.items {
            if let Some(g) = &i.garbage {
                s.extend_from_slice(g);
                s.push(0);
            }
            s.extend_from_slice(&link_ref::frame(&i.msg));
        }
        s
    }
}

/// Events of the chunks read in turn by one decoder.
fn read_in(chunks: &[&[u8]]) -> Vec<Event> {
    let mut d = LinkDecoder::new();
    chunks
        .iter()
        .flat_map(|c| c.iter())
        .filter_map(|&b| d.push(b))
        .map(event)
        .collect()
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let (stream, cuts, batch) = if mode % 2 == STREAM {
        let (cuts, stream) = deframer::split(rest);
        (stream.to_vec(), cuts.to_vec(), None)
    } else {
        let b = Batch::read(rest);
        (b.stream(), b.cuts.clone(), Some(b))
    };

    let mut model = ModelDecoder::default();
    let want: Vec<Event> = model.all(&stream).into_iter().map(event).collect();

    let whole = read_in(&[&stream]);
    assert_eq!(whole, want, "{stream:02x?}");
    let cut = slices(&stream, &cuts);
    let mut d = LinkDecoder::new();
    let mut by_cut = Vec::new();
    for (i, c) in cut.iter().enumerate() {
        by_cut.extend(c.iter().filter_map(|&b| d.push(b)).map(event));
        if i >= CLONED_CUTS {
            continue;
        }
        // A copy of the decoder at one of the first cuts reads the rest as the kept one will.
        let mut copy = d.clone();
        let tail: Vec<Event> = cut[i + 1..]
            .iter()
            .flat_map(|c| c.iter())
            .filter_map(|&b| copy.push(b))
            .map(event)
            .collect();
        assert_eq!(
            [by_cut.as_slice(), &tail].concat(),
            want,
            "the decoder cloned at cut {i}"
        );
    }
    assert_eq!(by_cut, want, "in the cut lengths {cuts:?}");
    assert_eq!(*d.stats(), model.stats);
    let reads: Vec<&[u8]> = stream.chunks(512).collect();
    assert_eq!(read_in(&reads), want, "in 512-byte reads");
    let errors = want.iter().filter(|e| **e == Event::Error).count();
    assert_eq!(
        errors as u32,
        model.stats.errors() - model.stats.unknown_version
    );

    // The twin's path: only the messages.
    let mut t = LinkDecoder::new();
    let twin: Vec<LinkMsg> = cut
        .iter()
        .flat_map(|c| c.iter())
        .filter_map(|&b| t.push(b)?.ok())
        .collect();
    let msgs: Vec<LinkMsg> = want
        .iter()
        .filter_map(|e| match e {
            Event::Msg(m) => Some(m.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(twin, msgs);

    if let Some(b) = batch {
        // Each item's garbage starts after a 0x00 (or at the start): what it gives is what it
        // gives alone; then exactly the item's message.
        let mut sent = Vec::new();
        for i in &b.items {
            if let Some(g) = &i.garbage {
                let mut alone = ModelDecoder::default();
                sent.extend(
                    alone
                        .all(&[g.as_slice(), &[0]].concat())
                        .into_iter()
                        .map(event),
                );
            }
            sent.push(match &i.msg {
                LinkMsg::Hello { version, .. } if *version != LINK_VERSION => {
                    Event::Version(*version)
                }
                m => Event::Msg(m.clone()),
            });
        }
        assert_eq!(want, sent, "the batch's messages");
    }
}
