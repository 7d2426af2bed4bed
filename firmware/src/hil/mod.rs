//! The hardware-in-the-loop link, version 3 (`docs/hil.md`): what a robot and the host say to
//! each other over one byte stream (a UART, a QEMU serial port, a TCP socket), so that a robot
//! running the real image can sit in the emulated light medium among virtual robots.
//!
//! ```text
//!  frame   = COBS(payload ‖ crc) 0x00          at most LINK_FRAME_MAX bytes
//!  payload = postcard(LinkMsg)                  at most PAYLOAD_MAX bytes
//!  crc     = CRC-16/IBM-3740 of payload, 2 bytes little-endian (as the light frame's, §1.3)
//! ```
//!
//! COBS removes every 0x00 from the frame, so 0x00 only ends one: a receiver that starts in
//! the middle of a stream, or meets garbage, loses at most the frame under way and is in step
//! again at the next 0x00 ([`LinkDecoder`]). Every error is typed ([`LinkError`]) and counted
//! ([`LinkStats`]); nothing here panics, allocates or blocks.
//!
//! This module is the codec; [`robot`] runs the unchanged robot program over it (the
//! `Hardware` adaptor over one UART). The host's end is `hal-emu`'s `hil` module.

pub mod robot;

use heapless::Vec;
use serde::{Deserialize, Serialize};

/// The link's version, sent in [`LinkMsg::Hello`]; a decoder refuses any other. (2 added the
/// host's clock, `Sync` and `Idle`; 3 the swarm key, [`LinkMsg::Key`].)
pub const LINK_VERSION: u8 = 3;

/// Most light bytes one [`LinkMsg::Tx`] or [`LinkMsg::Rx`] carries: a whole light frame
/// (`protocol::frame::FRAME_MAX`, 32). A stream of more is sent as several messages.
pub const CHUNK_MAX: usize = 32;

/// Largest payload: a [`LinkMsg::Setup`] with every field at its longest varint (39 bytes:
/// the tag, 3 for the id, 5 for each of the seed and five durations, 3 for the negotiation
/// period, 1 for the rule, 1 for the clock). An `Rx` of [`CHUNK_MAX`] bytes takes 35, a `Key`
/// 17, an `Idle` at most 11, a `Sync` at most 6, a `Hello` at most 7, a `Heartbeat` at most 6.
pub const PAYLOAD_MAX: usize = 39;

/// Bytes of the frame check.
const CRC_LEN: usize = 2;

/// Largest frame on the link, its 0x00 included (43 bytes). A [`LinkDecoder`] keeps this many
/// bytes of a frame before its 0x00, one more than any sender writes.
pub const LINK_FRAME_MAX: usize = cobs::max_encoding_length(PAYLOAD_MAX + CRC_LEN) + 1;

/// The frame check: the light frame's CRC (`docs/protocol.md` §1.3).
const CRC16: crc::Crc<u16, crc::NoTable> =
    crc::Crc::<u16, crc::NoTable>::new(&crc::CRC_16_IBM_3740);

/// One message of the link. Postcard encodes the variant as its index (a varint), then the
/// fields in order: `u8` raw, `u16`/`u32` as varints, byte vectors as a varint length and the
/// bytes. `Sync`, `Idle` and `Key` exist with the `host-clock` feature only: a robot that
/// cannot follow the host's clock never meets them (the host sends them only to one whose
/// `Hello` said it can), and would count one as undecodable; without them the Nucleo image in
/// the loop is 0.2 KB smaller.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LinkMsg {
    /// 0, robot → host, first after a (re)start: which robot this is.
    Hello {
        /// [`LINK_VERSION`].
        version: u8,
        /// The robot's id (its tag is `id mod 16`).
        id: u16,
        /// Its receive sectors K, `2..=8`.
        sectors: u8,
        /// True if its clock can follow the host's ([`Setup::host_clock`], [`LinkMsg::Sync`]).
        host_clock: bool,
    },
    /// 1, robot → host: bytes its light transmitter sent, in order.
    Tx(Vec<u8, CHUNK_MAX>),
    /// 2, host → robot: bytes the receiver facing `sector` heard, in order.
    Rx {
        /// The receiver, `0..K`.
        sector: u8,
        /// What it heard.
        bytes: Vec<u8, CHUNK_MAX>,
    },
    /// 3, host → robot: a sensor reading.
    Reading {
        /// 0 ambient light, 1 oxygen.
        quantity: u8,
        /// The level.
        level: u8,
    },
    /// 4, robot → host: what the top-cap LEDs show now: 0 off, `1 + sector` a decision.
    Led(u8),
    /// 5, both ways: still alive; the sequence number counts up from 0.
    Heartbeat(u32),
    /// 6, host → robot, after the robot's `Hello` and again before every run: (re)start the
    /// robot program with fresh state, this id and seed and this timing. The robot runs
    /// nothing before its first `Setup`.
    Setup(Setup),
    /// 7, robot → host: it cannot run the last `Setup` (its robot program refused it), and
    /// waits for another. The code says why: 1 bad protocol parameters, 2 receivers and
    /// sectors differ, 3 a zero duration, 4 a swarm key without keyed framing, 5 a host clock
    /// it cannot follow, 0 anything else.
    Refused(u8),
    /// 8, host → robot, on the host's clock ([`Setup::host_clock`]): the time is now this many
    /// milliseconds since the run's start (a `u32`: runs up to 49 days; a `u64` cost the
    /// Nucleo image in the loop 0.9 KB of 64-bit varint code). The robot takes what came since the last `Sync`
    /// (held until now) at this instant, runs every timer due by then, and once nothing is
    /// left to do says [`LinkMsg::Idle`].
    #[cfg(feature = "host-clock")]
    Sync(u32),
    /// 9, robot → host, on the host's clock: everything up to `now` is done (what the robot
    /// sent for it came before this), and nothing is due before `next` (`u32::MAX`: no timer
    /// set) unless the host sends something.
    #[cfg(feature = "host-clock")]
    Idle {
        /// The instant of the `Sync` answered, milliseconds.
        now: u32,
        /// The robot's next timer, milliseconds.
        next: u32,
    },
    /// 10, host → robot, just before a [`LinkMsg::Setup`]: the swarm key of the run it sets up
    /// (a `Setup` with no `Key` since the last one runs with the image's own key, if it was
    /// built with one: none for the QEMU images). The robot program then sends and accepts
    /// keyed frames only (`docs/protocol.md`, "Authenticated frames"); an image built without
    /// the firmware's `keyed` feature refuses the `Setup` (code 4). With the `host-clock`
    /// feature only, as `Sync` and `Idle`: the host sends it only to robots on its clock.
    #[cfg(feature = "host-clock")]
    Key(protocol::auth::SwarmKey),
}

/// What [`LinkMsg::Setup`] tells a robot: who it is in this run, its seed, and the protocol's
/// timing (the arena shrinks the paper's to make a run in real time short). Everything else
/// is the robot image's own [`Config`](crate::Config).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Setup {
    /// The robot's id in this run (its tag on the wire is `id mod 16`).
    pub id: u16,
    /// The seed of the robot's random draws in this run.
    pub seed: u32,
    /// Mean cycle, milliseconds (`WaveParams::cycle`).
    pub cycle_ms: u32,
    /// Cycle spread, milliseconds.
    pub spread_ms: u32,
    /// Relay delay, milliseconds.
    pub relay_ms: u32,
    /// Refractory time, milliseconds.
    pub refractory_ms: u32,
    /// Negotiation period, cycles.
    pub negotiation: u16,
    /// The decision rule: false fixed, true adaptive.
    pub adaptive: bool,
    /// How often the robot reads its sensor, milliseconds.
    pub sample_ms: u32,
    /// True: the robot's clock follows the host's from this `Setup` on (it starts at 0, moves
    /// only at each [`LinkMsg::Sync`], and the robot answers each with [`LinkMsg::Idle`]);
    /// false: its own clock (a robot whose `Hello` says it cannot follow refuses true).
    pub host_clock: bool,
}

/// What went wrong with one frame of the link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkError {
    /// More than [`LINK_FRAME_MAX`] bytes before a 0x00 (a lost delimiter, noise); the rest
    /// up to the next 0x00 is dropped.
    TooLong,
    /// Not valid COBS (a code byte points past the frame).
    BadCobs,
    /// No room for a payload and its check.
    TooShort,
    /// The CRC does not match.
    BadCheck,
    /// The check matches but the payload is no [`LinkMsg`] (unknown variant, a chunk over
    /// [`CHUNK_MAX`], bytes left over).
    Undecodable,
    /// A `Hello` of another link version: the two ends cannot talk.
    UnknownVersion(u8),
    /// Encoding only: the buffer is too small (cannot happen with [`LINK_FRAME_MAX`]).
    Encode,
}

/// Counters of a [`LinkDecoder`]. They wrap after 2³² events.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkStats {
    /// Messages decoded.
    pub frames: u32,
    /// [`LinkError::TooLong`].
    pub too_long: u32,
    /// [`LinkError::BadCobs`].
    pub bad_cobs: u32,
    /// [`LinkError::TooShort`].
    pub too_short: u32,
    /// [`LinkError::BadCheck`].
    pub bad_check: u32,
    /// [`LinkError::Undecodable`].
    pub undecodable: u32,
    /// [`LinkError::UnknownVersion`].
    pub unknown_version: u32,
}

impl LinkStats {
    /// Every error counted.
    pub fn errors(&self) -> u32 {
        [
            self.too_long,
            self.bad_cobs,
            self.too_short,
            self.bad_check,
            self.undecodable,
            self.unknown_version,
        ]
        .iter()
        .fold(0u32, |a, &b| a.wrapping_add(b))
    }
}

/// Encodes `msg` into `out`: COBS of the payload and its CRC, then 0x00. Returns the frame.
///
/// # Errors
/// [`LinkError::Encode`] if `out` is shorter than the frame (never with
/// [`LINK_FRAME_MAX`] bytes).
pub fn encode<'o>(msg: &LinkMsg, out: &'o mut [u8]) -> Result<&'o [u8], LinkError> {
    let mut raw = [0u8; PAYLOAD_MAX + CRC_LEN];
    let n = postcard::to_slice(msg, &mut raw[..PAYLOAD_MAX])
        .map_err(|_| LinkError::Encode)?
        .len();
    let crc = CRC16.checksum(&raw[..n]).to_le_bytes();
    raw[n..n + CRC_LEN].copy_from_slice(&crc);
    let m = cobs::try_encode(&raw[..n + CRC_LEN], out).map_err(|_| LinkError::Encode)?;
    let end = out.get_mut(m).ok_or(LinkError::Encode)?;
    *end = 0;
    Ok(&out[..=m])
}

/// A streaming receiver of the link in fixed memory: feed it bytes as they arrive.
#[derive(Clone, Debug)]
pub struct LinkDecoder {
    buf: [u8; LINK_FRAME_MAX],
    len: usize,
    overflow: bool,
    stats: LinkStats,
}

impl Default for LinkDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl LinkDecoder {
    /// A decoder that takes the first 0x00 as the end of a (possibly partial) frame.
    pub const fn new() -> Self {
        LinkDecoder {
            buf: [0; LINK_FRAME_MAX],
            len: 0,
            overflow: false,
            stats: LinkStats {
                frames: 0,
                too_long: 0,
                bad_cobs: 0,
                too_short: 0,
                bad_check: 0,
                undecodable: 0,
                unknown_version: 0,
            },
        }
    }

    /// The counters.
    pub fn stats(&self) -> &LinkStats {
        &self.stats
    }

    /// One byte. Returns a message or an error when a frame ends (at its 0x00, or at the byte
    /// that makes it too long), and `None` otherwise (also for empty frames: several 0x00 in
    /// a row).
    pub fn push(&mut self, byte: u8) -> Option<Result<LinkMsg, LinkError>> {
        let out = self.step(byte);
        if let Some(r) = &out {
            let s = &mut self.stats;
            let c = match r {
                Ok(_) => &mut s.frames,
                Err(LinkError::TooLong) => &mut s.too_long,
                Err(LinkError::BadCobs) => &mut s.bad_cobs,
                Err(LinkError::TooShort) => &mut s.too_short,
                Err(LinkError::BadCheck) => &mut s.bad_check,
                Err(LinkError::Undecodable | LinkError::Encode) => &mut s.undecodable,
                Err(LinkError::UnknownVersion(_)) => &mut s.unknown_version,
            };
            *c = c.wrapping_add(1);
        }
        out
    }

    fn step(&mut self, byte: u8) -> Option<Result<LinkMsg, LinkError>> {
        if byte == 0 {
            let len = core::mem::take(&mut self.len);
            if core::mem::take(&mut self.overflow) || len == 0 {
                return None;
            }
            return Some(decode_frame(self.buf.get_mut(..len)?));
        }
        if self.overflow {
            return None;
        }
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                *slot = byte;
                self.len += 1;
                None
            }
            None => {
                self.overflow = true;
                Some(Err(LinkError::TooLong))
            }
        }
    }
}

/// Decodes one frame without its 0x00, in place.
fn decode_frame(frame: &mut [u8]) -> Result<LinkMsg, LinkError> {
    let n = cobs::decode_in_place(frame).map_err(|_| LinkError::BadCobs)?;
    let raw = frame.get(..n).ok_or(LinkError::BadCobs)?;
    if raw.len() <= CRC_LEN {
        return Err(LinkError::TooShort);
    }
    let (payload, check) = raw.split_at(raw.len() - CRC_LEN);
    if CRC16.checksum(payload).to_le_bytes() != check {
        return Err(LinkError::BadCheck);
    }
    match postcard::take_from_bytes::<LinkMsg>(payload) {
        Ok((LinkMsg::Hello { version, .. }, [])) if version != LINK_VERSION => {
            Err(LinkError::UnknownVersion(version))
        }
        Ok((msg, [])) => Ok(msg),
        _ => Err(LinkError::Undecodable),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::{RngCore, SeedableRng};

    fn frame(msg: &LinkMsg) -> std::vec::Vec<u8> {
        let mut out = [0u8; LINK_FRAME_MAX];
        encode(msg, &mut out).unwrap().to_vec()
    }

    fn all(d: &mut LinkDecoder, bytes: &[u8]) -> std::vec::Vec<Result<LinkMsg, LinkError>> {
        bytes.iter().filter_map(|&b| d.push(b)).collect()
    }

    fn chunk(b: &[u8]) -> Vec<u8, CHUNK_MAX> {
        Vec::from_slice(b).unwrap()
    }

    /// A `Setup` with every field at its longest encoding.
    const LONGEST_SETUP: Setup = Setup {
        id: u16::MAX,
        seed: u32::MAX,
        cycle_ms: u32::MAX,
        spread_ms: u32::MAX,
        relay_ms: u32::MAX,
        refractory_ms: u32::MAX,
        negotiation: u16::MAX,
        adaptive: true,
        sample_ms: u32::MAX,
        host_clock: true,
    };

    fn every_kind() -> [LinkMsg; 13] {
        [
            LinkMsg::Hello {
                version: LINK_VERSION,
                id: 300,
                sectors: 2,
                host_clock: true,
            },
            LinkMsg::Tx(chunk(b"ss\x70\x32\x72\x70\x43\xa6ss")),
            LinkMsg::Rx {
                sector: 1,
                bytes: chunk(&[0x73; CHUNK_MAX]),
            },
            LinkMsg::Rx {
                sector: 0,
                bytes: chunk(&[0; CHUNK_MAX]),
            },
            LinkMsg::Reading {
                quantity: 0,
                level: 200,
            },
            LinkMsg::Led(2),
            LinkMsg::Heartbeat(u32::MAX),
            LinkMsg::Setup(LONGEST_SETUP),
            LinkMsg::Refused(1),
            LinkMsg::Sync(u32::MAX),
            LinkMsg::Idle {
                now: u32::MAX,
                next: u32::MAX,
            },
            LinkMsg::Idle { now: 0, next: 55 },
            LinkMsg::Key(protocol::auth::SwarmKey::new([0xFF; 16])),
        ]
    }

    #[test]
    fn every_kind_round_trips_and_fits() {
        for m in every_kind() {
            let f = frame(&m);
            assert!(f.len() <= LINK_FRAME_MAX, "{m:?}: {}", f.len());
            assert_eq!(
                f.iter().filter(|&&b| b == 0).count(),
                1,
                "only the end is 0"
            );
            assert_eq!(f.last(), Some(&0));
            let mut d = LinkDecoder::new();
            assert_eq!(all(&mut d, &f), [Ok(m)]);
            assert_eq!(d.stats().frames, 1);
        }
        // The largest frame is exactly LINK_FRAME_MAX: the longest Setup's payload is
        // PAYLOAD_MAX.
        let mut raw = [0u8; 64];
        let n = postcard::to_slice(&LinkMsg::Setup(LONGEST_SETUP), &mut raw)
            .unwrap()
            .len();
        assert_eq!(n, PAYLOAD_MAX);
        let big = frame(&LinkMsg::Setup(LONGEST_SETUP));
        assert_eq!(big.len(), LINK_FRAME_MAX);
        let rx = frame(&LinkMsg::Rx {
            sector: 7,
            bytes: chunk(&[0xFF; CHUNK_MAX]),
        });
        assert!(rx.len() < LINK_FRAME_MAX);
    }

    /// Golden frames, worked out in docs/hil.md ("Examples"); their CRCs and COBS computed
    /// independently with `protocol/tests/golden/gen_golden.py`'s functions.
    #[test]
    fn golden_frames() {
        // Heartbeat(1): payload 05 01, CRC f2db (LE db f2), COBS code 5, then 0x00.
        assert_eq!(
            frame(&LinkMsg::Heartbeat(1)),
            [0x05, 0x05, 0x01, 0xDB, 0xF2, 0x00]
        );
        // Hello { version 3, id 300, K 2, host clock }: payload 00 03 ac 02 02 01 (300 =
        // varint ac 02), CRC 5da5; the payload's leading 0x00 becomes COBS code 1.
        let hello = LinkMsg::Hello {
            version: 3,
            id: 300,
            sectors: 2,
            host_clock: true,
        };
        let golden = [0x01, 0x08, 0x03, 0xAC, 0x02, 0x02, 0x01, 0xA5, 0x5D, 0x00];
        assert_eq!(frame(&hello), golden);
        let mut d = LinkDecoder::new();
        assert_eq!(all(&mut d, &golden), [Ok(hello)]);
        // Sync(55000): payload 08 d8 ad 03 (55000 = varint d8 ad 03), CRC 9677.
        assert_eq!(
            frame(&LinkMsg::Sync(55_000)),
            [0x07, 0x08, 0xD8, 0xAD, 0x03, 0x77, 0x96, 0x00]
        );
        // Idle { now 0, next 55 }: payload 09 00 37, CRC 14b9; its 0x00 splits the COBS runs.
        assert_eq!(
            frame(&LinkMsg::Idle { now: 0, next: 55 }),
            [0x02, 0x09, 0x04, 0x37, 0xB9, 0x14, 0x00]
        );
        // Key(00 01 .. 0f): payload 0a and the key's 16 bytes as they are, CRC 3005; the key's
        // first byte 0x00 splits the COBS runs.
        let key = LinkMsg::Key(protocol::auth::SwarmKey::new(core::array::from_fn(|i| {
            i as u8
        })));
        let golden = [
            0x02, 0x0A, 0x12, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B,
            0x0C, 0x0D, 0x0E, 0x0F, 0x05, 0x30, 0x00,
        ];
        assert_eq!(frame(&key), golden);
        let mut d = LinkDecoder::new();
        assert_eq!(all(&mut d, &golden), [Ok(key)]);
    }

    #[test]
    fn garbage_truncation_and_overflow_cost_one_frame_each() {
        let hb = frame(&LinkMsg::Heartbeat(7));
        // Garbage without a 0, then two frames: the garbage runs into the first frame's body
        // and the two fail together at its 0; the next frame decodes.
        let mut s = std::vec::Vec::from(&b"noise"[..]);
        s.extend_from_slice(&hb);
        s.extend_from_slice(&hb);
        let mut d = LinkDecoder::new();
        let got = all(&mut d, &s);
        assert_eq!(got.len(), 2);
        assert!(got[0].is_err());
        assert_eq!(got[1], Ok(LinkMsg::Heartbeat(7)));
        // A frame cut short, then a 0 (the sender restarted), then a whole frame.
        let mut s = hb[..3].to_vec();
        s.push(0);
        s.extend_from_slice(&hb);
        let mut d = LinkDecoder::new();
        let got = all(&mut d, &s);
        assert!(got[0].is_err());
        assert_eq!(got[1], Ok(LinkMsg::Heartbeat(7)));
        // A lost 0: too long once, then in step at the next 0.
        let mut s = vec![0x42; LINK_FRAME_MAX + 20];
        s.push(0);
        s.extend_from_slice(&hb);
        let mut d = LinkDecoder::new();
        assert_eq!(
            all(&mut d, &s),
            [Err(LinkError::TooLong), Ok(LinkMsg::Heartbeat(7))]
        );
        assert_eq!(
            (d.stats().too_long, d.stats().frames, d.stats().errors()),
            (1, 1, 1)
        );
        // Empty frames (0 0 0) are nothing.
        let mut d = LinkDecoder::new();
        assert!(all(&mut d, &[0, 0, 0]).is_empty());
    }

    #[test]
    fn another_version_says_so_and_the_link_goes_on() {
        // Version 2: the link before the swarm key.
        let mut s = frame(&LinkMsg::Hello {
            version: 2,
            id: 1,
            sectors: 2,
            host_clock: false,
        });
        s.extend_from_slice(&frame(&LinkMsg::Led(1)));
        let mut d = LinkDecoder::new();
        assert_eq!(
            all(&mut d, &s),
            [Err(LinkError::UnknownVersion(2)), Ok(LinkMsg::Led(1))]
        );
        assert_eq!(d.stats().unknown_version, 1);
    }

    #[test]
    fn bad_payloads_with_a_good_check_are_undecodable() {
        for payload in [
            &[0x0A][..],               // variant 10 does not exist
            &[0x01, 33],               // a chunk of 33 bytes claimed
            &[0x04, 0x01, 0x00],       // a byte left over
            &[0x02, 0x01, 0x02, 0xAA], // Rx cut short
        ] {
            let mut raw = payload.to_vec();
            raw.extend_from_slice(&CRC16.checksum(payload).to_le_bytes());
            let mut f = [0u8; 64];
            let n = cobs::encode(&raw, &mut f);
            let mut s = f[..n].to_vec();
            s.push(0);
            let mut d = LinkDecoder::new();
            assert_eq!(
                all(&mut d, &s),
                [Err(LinkError::Undecodable)],
                "{payload:02x?}"
            );
        }
    }

    /// Any bytes, 20,000 random streams (seeded): no panic, and whatever decodes re-encodes to
    /// a frame that decodes to the same message.
    #[test]
    fn random_streams_never_panic() {
        let mut rng = rand_pcg::Pcg32::seed_from_u64(20);
        let good = frame(&LinkMsg::Heartbeat(3));
        for _ in 0..20_000 {
            let n = (rng.next_u32() % 120) as usize;
            let mut s: std::vec::Vec<u8> = (0..n).map(|_| rng.next_u32() as u8).collect();
            if rng.next_u32() % 2 == 0 {
                s.extend_from_slice(&good);
            }
            let mut d = LinkDecoder::new();
            for m in all(&mut d, &s).into_iter().flatten() {
                let mut again = LinkDecoder::new();
                assert_eq!(all(&mut again, &frame(&m)), [Ok(m)]);
            }
        }
    }
}
