//! An independent model of the hardware-in-the-loop link's framing (`docs/hil.md`, "Frame",
//! "Messages", "Errors", link version 3), written from the document rather than from
//! `firmware::hil`: the payload parser and encoder below do not call postcard or the
//! firmware's `Deserialize`; COBS is [`reference::cobs_decode`] / [`reference::cobs_encode`].
//!
//! ```text
//!  frame   = COBS(payload ‖ crc) 0x00          at most LINK_FRAME_MAX = 43 bytes
//!  payload = postcard(LinkMsg)                  at most PAYLOAD_MAX = 39 bytes (canonical)
//!  crc     = CRC-16/IBM-3740 of the payload, 2 bytes little-endian
//! ```
//!
//! What the model accepts as postcard, as postcard 1.1 reads it: the variant index and every
//! `u16`/`u32` and chunk length as a varint **not necessarily canonical** (`81 00` is 1; a
//! `u32` takes at most 5 bytes with at most 4 bits in the last, a `u16` 3 with 2 bits, a length
//! 10 with 1 bit), `u8` raw, `bool` exactly 0 or 1, chunks of at most [`CHUNK_MAX`] bytes, and
//! nothing left over. The decoder keeps [`LINK_FRAME_MAX`] bytes of a frame (one more than the
//! longest body a sender writes, 42): the next non-zero byte is `TooLong`.
//!
//! It also holds the structured-input form of a [`LinkMsg`] ([`read_msg`], [`write_msg`]).

use arbitrary::Unstructured;
use firmware::hil::{
    CHUNK_MAX, LINK_FRAME_MAX, LINK_VERSION, LinkError, LinkMsg, LinkStats, Setup,
};

use firmware::protocol::auth::SwarmKey;

use crate::input::{Writer, byte_list, get};
use crate::reference::{CRC16, cobs_decode, cobs_encode};

/// Bytes of the frame check.
pub const CRC_LEN: usize = 2;

/// Non-zero bytes a decoder keeps before a 0x00: one more is `TooLong`.
pub const BODY_LIMIT: usize = LINK_FRAME_MAX;

/// The variant indices of `docs/hil.md`'s table.
pub const HELLO: u8 = 0;
/// `Tx`.
pub const TX: u8 = 1;
/// `Rx`.
pub const RX: u8 = 2;
/// `Reading`.
pub const READING: u8 = 3;
/// `Led`.
pub const LED: u8 = 4;
/// `Heartbeat`.
pub const HEARTBEAT: u8 = 5;
/// `Setup`.
pub const SETUP: u8 = 6;
/// `Refused`.
pub const REFUSED: u8 = 7;
/// `Sync`.
pub const SYNC: u8 = 8;
/// `Idle`.
pub const IDLE: u8 = 9;
/// `Key`.
pub const KEY: u8 = 10;
/// The variants: [`read_msg`] reads the variant byte modulo this.
pub const VARIANTS: u8 = 11;

/// A canonical varint: 7 bits a byte, least significant first, the top bit "more follows".
pub fn varint(out: &mut Vec<u8>, mut x: u64) {
    loop {
        let b = (x & 0x7F) as u8;
        x >>= 7;
        if x == 0 {
            out.push(b);
            return;
        }
        out.push(b | 0x80);
    }
}

/// The payload of `msg` as `docs/hil.md` defines it (canonical varints).
pub fn payload_of(msg: &LinkMsg) -> Vec<u8> {
    let mut p = Vec::new();
    let chunk = |p: &mut Vec<u8>, bytes: &[u8]| {
        varint(p, bytes.len() as u64);
        p.extend_from_slice(bytes);
    };
    match msg {
        LinkMsg::Hello {
            version,
            id,
            sectors,
            host_clock,
        } => {
            p.push(HELLO);
            p.push(*version);
            varint(&mut p, u64::from(*id));
            p.push(*sectors);
            p.push(u8::from(*host_clock));
        }
        LinkMsg::Tx(bytes) => {
            p.push(TX);
            chunk(&mut p, bytes);
        }
        LinkMsg::Rx { sector, bytes } => {
            p.push(RX);
            p.push(*sector);
            chunk(&mut p, bytes);
        }
        LinkMsg::Reading { quantity, level } => p.extend_from_slice(&[READING, *quantity, *level]),
        LinkMsg::Led(code) => p.extend_from_slice(&[LED, *code]),
        LinkMsg::Heartbeat(seq) => {
            p.push(HEARTBEAT);
            varint(&mut p, u64::from(*seq));
        }
        LinkMsg::Setup(s) => {
            p.push(SETUP);
            varint(&mut p, u64::from(s.id));
            for v in [s.seed, s.cycle_ms, s.spread_ms, s.relay_ms, s.refractory_ms] {
                varint(&mut p, u64::from(v));
            }
            varint(&mut p, u64::from(s.negotiation));
            p.push(u8::from(s.adaptive));
            varint(&mut p, u64::from(s.sample_ms));
            p.push(u8::from(s.host_clock));
        }
        LinkMsg::Refused(code) => p.extend_from_slice(&[REFUSED, *code]),
        LinkMsg::Sync(now) => {
            p.push(SYNC);
            varint(&mut p, u64::from(*now));
        }
        LinkMsg::Idle { now, next } => {
            p.push(IDLE);
            varint(&mut p, u64::from(*now));
            varint(&mut p, u64::from(*next));
        }
        LinkMsg::Key(key) => {
            p.push(KEY);
            p.extend_from_slice(&key.to_bytes());
        }
    }
    p
}

/// COBS of `payload ‖ crc`, then 0x00: the frame of any payload, with its correct check.
pub fn frame_payload(payload: &[u8]) -> Vec<u8> {
    let mut raw = payload.to_vec();
    raw.extend_from_slice(&CRC16.checksum(payload).to_le_bytes());
    let mut f = cobs_encode(&raw);
    f.push(0);
    f
}

/// The frame of `msg`.
pub fn frame(msg: &LinkMsg) -> Vec<u8> {
    frame_payload(&payload_of(msg))
}

/// A reader of payload bytes; every failure is "undecodable".
struct Cursor<'a> {
    data: &'a [u8],
}

impl Cursor<'_> {
    fn byte(&mut self) -> Option<u8> {
        let (&b, rest) = self.data.split_first()?;
        self.data = rest;
        Some(b)
    }

    /// A varint of at most `max_bytes` bytes whose last byte holds at most `last_bits` bits.
    fn varint(&mut self, max_bytes: u32, last_bits: u32) -> Option<u64> {
        let mut x = 0u64;
        for i in 0..max_bytes {
            let b = self.byte()?;
            x |= u64::from(b & 0x7F) << (7 * i);
            if b & 0x80 == 0 {
                return (i + 1 < max_bytes || u32::from(b) < (1 << last_bits)).then_some(x);
            }
        }
        None
    }

    fn u16(&mut self) -> Option<u16> {
        u16::try_from(self.varint(3, 2)?).ok()
    }

    fn u32(&mut self) -> Option<u32> {
        u32::try_from(self.varint(5, 4)?).ok()
    }

    fn bool(&mut self) -> Option<bool> {
        match self.byte()? {
            0 => Some(false),
            1 => Some(true),
            _ => None,
        }
    }

    fn chunk(&mut self) -> Option<heapless::Vec<u8, CHUNK_MAX>> {
        let n = usize::try_from(self.varint(10, 1)?).ok()?;
        if n > CHUNK_MAX || n > self.data.len() {
            return None;
        }
        let (bytes, rest) = self.data.split_at(n);
        self.data = rest;
        heapless::Vec::from_slice(bytes).ok()
    }
}

/// Parses a payload whose check passed: the message, `UnknownVersion` for a `Hello` of another
/// version, else `Undecodable`.
pub fn parse_payload(payload: &[u8]) -> Result<LinkMsg, LinkError> {
    let mut c = Cursor { data: payload };
    let msg = parse(&mut c).ok_or(LinkError::Undecodable)?;
    if !c.data.is_empty() {
        return Err(LinkError::Undecodable);
    }
    match msg {
        LinkMsg::Hello { version, .. } if version != LINK_VERSION => {
            Err(LinkError::UnknownVersion(version))
        }
        m => Ok(m),
    }
}

fn parse(c: &mut Cursor<'_>) -> Option<LinkMsg> {
    let index = c.u32()?;
    Some(match index {
        0 => LinkMsg::Hello {
            version: c.byte()?,
            id: c.u16()?,
            sectors: c.byte()?,
            host_clock: c.bool()?,
        },
        1 => LinkMsg::Tx(c.chunk()?),
        2 => LinkMsg::Rx {
            sector: c.byte()?,
            bytes: c.chunk()?,
        },
        3 => LinkMsg::Reading {
            quantity: c.byte()?,
            level: c.byte()?,
        },
        4 => LinkMsg::Led(c.byte()?),
        5 => LinkMsg::Heartbeat(c.u32()?),
        6 => LinkMsg::Setup(Setup {
            id: c.u16()?,
            seed: c.u32()?,
            cycle_ms: c.u32()?,
            spread_ms: c.u32()?,
            relay_ms: c.u32()?,
            refractory_ms: c.u32()?,
            negotiation: c.u16()?,
            adaptive: c.bool()?,
            sample_ms: c.u32()?,
            host_clock: c.bool()?,
        }),
        7 => LinkMsg::Refused(c.byte()?),
        8 => LinkMsg::Sync(c.u32()?),
        9 => LinkMsg::Idle {
            now: c.u32()?,
            next: c.u32()?,
        },
        // The key's 16 bytes as they are (a byte array, no length).
        10 => {
            let mut key = [0u8; 16];
            for b in &mut key {
                *b = c.byte()?;
            }
            LinkMsg::Key(SwarmKey::new(key))
        }
        _ => return None,
    })
}

/// Decodes one body (the bytes before a 0x00, none of them 0x00, at most [`BODY_LIMIT`]).
pub fn decode_body(body: &[u8]) -> Result<LinkMsg, LinkError> {
    assert!(!body.contains(&0), "a body never holds 0x00");
    assert!(body.len() <= BODY_LIMIT, "a body the decoder keeps");
    let raw = cobs_decode(body).ok_or(LinkError::BadCobs)?;
    if raw.len() <= CRC_LEN {
        return Err(LinkError::TooShort);
    }
    let (payload, check) = raw.split_at(raw.len() - CRC_LEN);
    if CRC16.checksum(payload).to_le_bytes() != check {
        return Err(LinkError::BadCheck);
    }
    parse_payload(payload)
}

/// The counters after one more `result`.
pub fn count(stats: &mut LinkStats, result: &Result<LinkMsg, LinkError>) {
    let c = match result {
        Ok(_) => &mut stats.frames,
        Err(LinkError::TooLong) => &mut stats.too_long,
        Err(LinkError::BadCobs) => &mut stats.bad_cobs,
        Err(LinkError::TooShort) => &mut stats.too_short,
        Err(LinkError::BadCheck) => &mut stats.bad_check,
        Err(LinkError::Undecodable) => &mut stats.undecodable,
        Err(LinkError::UnknownVersion(_)) => &mut stats.unknown_version,
        Err(LinkError::Encode) => panic!("a decoder reported an encoding error"),
    };
    *c += 1;
}

/// The model of `LinkDecoder`: a body up to each 0x00, `TooLong` once at the byte past
/// [`BODY_LIMIT`] and nothing more until the next 0x00, empty frames nothing.
#[derive(Clone, Debug, Default)]
pub struct ModelDecoder {
    body: Vec<u8>,
    overflow: bool,
    /// The counters it expects.
    pub stats: LinkStats,
}

impl ModelDecoder {
    /// One byte.
    pub fn push(&mut self, byte: u8) -> Option<Result<LinkMsg, LinkError>> {
        let out = if byte == 0 {
            let body = std::mem::take(&mut self.body);
            if std::mem::take(&mut self.overflow) || body.is_empty() {
                None
            } else {
                Some(decode_body(&body))
            }
        } else if self.overflow {
            None
        } else if self.body.len() == BODY_LIMIT {
            self.body.clear();
            self.overflow = true;
            Some(Err(LinkError::TooLong))
        } else {
            self.body.push(byte);
            None
        };
        if let Some(r) = &out {
            count(&mut self.stats, r);
        }
        out
    }

    /// Every result of `bytes`.
    pub fn all(&mut self, bytes: &[u8]) -> Vec<Result<LinkMsg, LinkError>> {
        bytes.iter().filter_map(|&b| self.push(b)).collect()
    }
}

/// Reads a message: a variant byte (modulo [`VARIANTS`]), then its fields in order (`u8`, `u16`, `u32`,
/// `bool` as [`crate::input`] reads them; a chunk as a byte list of at most [`CHUNK_MAX`]).
pub fn read_msg(u: &mut Unstructured<'_>) -> LinkMsg {
    let chunk = |u: &mut Unstructured<'_>| {
        heapless::Vec::from_slice(&byte_list(u, CHUNK_MAX)).expect("at most CHUNK_MAX")
    };
    match get::<u8>(u) % VARIANTS {
        HELLO => LinkMsg::Hello {
            version: get(u),
            id: get(u),
            sectors: get(u),
            host_clock: get(u),
        },
        TX => LinkMsg::Tx(chunk(u)),
        RX => LinkMsg::Rx {
            sector: get(u),
            bytes: chunk(u),
        },
        READING => LinkMsg::Reading {
            quantity: get(u),
            level: get(u),
        },
        LED => LinkMsg::Led(get(u)),
        HEARTBEAT => LinkMsg::Heartbeat(get(u)),
        SETUP => LinkMsg::Setup(Setup {
            id: get(u),
            seed: get(u),
            cycle_ms: get(u),
            spread_ms: get(u),
            relay_ms: get(u),
            refractory_ms: get(u),
            negotiation: get(u),
            adaptive: get(u),
            sample_ms: get(u),
            host_clock: get(u),
        }),
        REFUSED => LinkMsg::Refused(get(u)),
        SYNC => LinkMsg::Sync(get(u)),
        KEY => LinkMsg::Key(SwarmKey::new(std::array::from_fn(|_| get(u)))),
        _ => LinkMsg::Idle {
            now: get(u),
            next: get(u),
        },
    }
}

/// Writes `msg` as [`read_msg`] reads it.
pub fn write_msg(w: &mut Writer, msg: &LinkMsg) {
    match msg {
        LinkMsg::Hello {
            version,
            id,
            sectors,
            host_clock,
        } => {
            w.u8(HELLO)
                .u8(*version)
                .u16(*id)
                .u8(*sectors)
                .bool(*host_clock);
        }
        LinkMsg::Tx(bytes) => {
            w.u8(TX).byte_list(bytes);
        }
        LinkMsg::Rx { sector, bytes } => {
            w.u8(RX).u8(*sector).byte_list(bytes);
        }
        LinkMsg::Reading { quantity, level } => {
            w.u8(READING).u8(*quantity).u8(*level);
        }
        LinkMsg::Led(code) => {
            w.u8(LED).u8(*code);
        }
        LinkMsg::Heartbeat(seq) => {
            w.u8(HEARTBEAT).u32(*seq);
        }
        LinkMsg::Setup(s) => {
            w.u8(SETUP).u16(s.id);
            for v in [s.seed, s.cycle_ms, s.spread_ms, s.relay_ms, s.refractory_ms] {
                w.u32(v);
            }
            w.u16(s.negotiation)
                .bool(s.adaptive)
                .u32(s.sample_ms)
                .bool(s.host_clock);
        }
        LinkMsg::Refused(code) => {
            w.u8(REFUSED).u8(*code);
        }
        LinkMsg::Sync(now) => {
            w.u8(SYNC).u32(*now);
        }
        LinkMsg::Idle { now, next } => {
            w.u8(IDLE).u32(*now).u32(*next);
        }
        LinkMsg::Key(key) => {
            w.u8(KEY);
            for b in key.to_bytes() {
                w.u8(b);
            }
        }
    }
}

/// A chunk of these bytes (at most [`CHUNK_MAX`]).
pub fn chunk(bytes: &[u8]) -> heapless::Vec<u8, CHUNK_MAX> {
    heapless::Vec::from_slice(&bytes[..bytes.len().min(CHUNK_MAX)]).expect("at most CHUNK_MAX")
}

/// A `Setup` with every field at its longest encoding (the 39-byte payload).
pub const LONGEST_SETUP: Setup = Setup {
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

/// One message of every variant (and the longest `Setup`, `Rx` and `Idle`).
pub fn every_kind() -> Vec<LinkMsg> {
    vec![
        LinkMsg::Hello {
            version: LINK_VERSION,
            id: 300,
            sectors: 2,
            host_clock: true,
        },
        LinkMsg::Tx(chunk(b"ss\x70\x32\x72\x70\x43\xa6ss")),
        LinkMsg::Rx {
            sector: 1,
            bytes: chunk(&[0; CHUNK_MAX]),
        },
        LinkMsg::Reading {
            quantity: 1,
            level: 200,
        },
        LinkMsg::Led(2),
        LinkMsg::Heartbeat(u32::MAX),
        LinkMsg::Setup(LONGEST_SETUP),
        LinkMsg::Refused(5),
        LinkMsg::Sync(55_000),
        LinkMsg::Idle {
            now: u32::MAX,
            next: u32::MAX,
        },
        LinkMsg::Key(SwarmKey::new([0xFF; 16])),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The golden frames of `firmware::hil`'s tests and docs/hil.md ("Examples").
    #[test]
    fn golden_frames() {
        assert_eq!(
            frame(&LinkMsg::Heartbeat(1)),
            [0x05, 0x05, 0x01, 0xDB, 0xF2, 0x00]
        );
        let hello = LinkMsg::Hello {
            version: 3,
            id: 300,
            sectors: 2,
            host_clock: true,
        };
        let golden = [0x01, 0x08, 0x03, 0xAC, 0x02, 0x02, 0x01, 0xA5, 0x5D, 0x00];
        assert_eq!(frame(&hello), golden);
        assert_eq!(ModelDecoder::default().all(&golden), [Ok(hello)]);
        assert_eq!(
            frame(&LinkMsg::Sync(55_000)),
            [0x07, 0x08, 0xD8, 0xAD, 0x03, 0x77, 0x96, 0x00]
        );
        assert_eq!(
            frame(&LinkMsg::Idle { now: 0, next: 55 }),
            [0x02, 0x09, 0x04, 0x37, 0xB9, 0x14, 0x00]
        );
        let key = LinkMsg::Key(SwarmKey::new(std::array::from_fn(|i| i as u8)));
        let golden = [
            0x02, 0x0A, 0x12, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B,
            0x0C, 0x0D, 0x0E, 0x0F, 0x05, 0x30, 0x00,
        ];
        assert_eq!(frame(&key), golden);
        assert_eq!(ModelDecoder::default().all(&golden), [Ok(key)]);
        assert_eq!(payload_of(&LinkMsg::Setup(LONGEST_SETUP)).len(), 39);
        assert_eq!(frame(&LinkMsg::Setup(LONGEST_SETUP)).len(), LINK_FRAME_MAX);
    }

    #[test]
    fn varints_as_postcard_reads_them() {
        let u32_of = |b: &[u8]| Cursor { data: b }.u32();
        assert_eq!(u32_of(&[0x81, 0x00]), Some(1));
        assert_eq!(u32_of(&[0xFF, 0xFF, 0xFF, 0xFF, 0x0F]), Some(u32::MAX));
        assert_eq!(u32_of(&[0xFF, 0xFF, 0xFF, 0xFF, 0x10]), None);
        assert_eq!(u32_of(&[0x80, 0x80, 0x80, 0x80, 0x80, 0x00]), None);
        assert_eq!(u32_of(&[0x80]), None);
        let u16_of = |b: &[u8]| Cursor { data: b }.u16();
        assert_eq!(u16_of(&[0xFF, 0xFF, 0x03]), Some(u16::MAX));
        assert_eq!(u16_of(&[0xFF, 0xFF, 0x04]), None);
    }

    #[test]
    fn messages_read_back() {
        for m in every_kind() {
            let mut w = Writer::new();
            write_msg(&mut w, &m);
            let bytes = w.finish();
            assert_eq!(read_msg(&mut Unstructured::new(&bytes)), m);
            assert_eq!(parse_payload(&payload_of(&m)), Ok(m));
        }
    }
}
