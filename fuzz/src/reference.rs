//! What the checks compare the protocol against: the golden vectors and an independent
//! implementation of the frame layout of `docs/protocol.md` §1 (payload layout, CRC-16/IBM-3740,
//! COBS, XOR with `s`), written from the document rather than from `frame.rs`.

use arbitrary::{Arbitrary, Unstructured};
use protocol::frame::{self, BODY_MAX, CRC_LEN, DELIMITER, FRAME_MAX, FrameError};
use protocol::message::{MAX_TAGS, Tag};
use protocol::{Hop, Level, MAX_HOPS, MAX_SECTORS, Message, Sector};

/// `docs/protocol.md` §1.6: one hop, reading 1, no preference.
pub const GOLDEN_ONE_HOP: &[u8] = b"ss\x70\x72\x72\x70\xee\xbbss";
/// `docs/protocol.md` §1.6: (1, RIGHT), (0, LEFT), (0, LEFT), (0, none).
pub const GOLDEN_FOUR_HOPS: &[u8] = b"ss\x77\x77\x72\x72\x71\x71\x71\x71\x72\x70\xbf\x22ss";
/// `docs/protocol.md` §1.6: two hops with reading `s` (0x73) and no preference.
pub const GOLDEN_S_BYTES: &[u8] = b"ss\x70\x71\x00\x71\x00\x70\x5f\xa2ss";

/// The frame check of §1.3.
pub const CRC16: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740);

/// Largest variance of 8-bit readings, (255 / 2)², with room for `f32` rounding.
pub const MAX_LEVEL_VARIANCE: f32 = 16_257.0;

/// A hop of the robot with tag 0; `pref` is a sector index below [`MAX_SECTORS`].
pub fn hop(reading: u8, pref: Option<u8>) -> Hop {
    tagged(reading, 0, pref)
}

/// A hop of the robot with tag `tag % 16`.
pub fn tagged(reading: u8, tag_index: u8, pref: Option<u8>) -> Hop {
    Hop {
        reading: Level(reading),
        pref: pref.map(sector),
        tag: tag(tag_index),
    }
}

/// The robot tag `index % MAX_TAGS`, through the public constructor, which must accept exactly
/// the values below [`MAX_TAGS`].
pub fn tag(index: u8) -> Tag {
    let t = Tag::new(index);
    assert_eq!(
        t.is_some(),
        usize::from(index) < MAX_TAGS,
        "Tag::new({index})"
    );
    assert_eq!(
        Tag::from_id(u16::from(index)).index(),
        index % MAX_TAGS as u8
    );
    Tag::new(index % MAX_TAGS as u8).expect("a value below MAX_TAGS is a tag")
}

/// The sector `index % MAX_SECTORS`, through the public constructor, which must accept exactly
/// the indices below [`MAX_SECTORS`].
pub fn sector(index: u8) -> Sector {
    let s = Sector::new(index);
    assert_eq!(
        s.is_some(),
        usize::from(index) < MAX_SECTORS,
        "Sector::new({index})"
    );
    Sector::new(index % MAX_SECTORS as u8).expect("an index below MAX_SECTORS is a sector")
}

/// The message of [`GOLDEN_ONE_HOP`].
pub fn one_hop() -> Message {
    Message::initiate(hop(1, None))
}

/// The message of [`GOLDEN_FOUR_HOPS`].
pub fn four_hops() -> Message {
    Message::from_hops(&[
        hop(1, Some(0)),
        hop(0, Some(1)),
        hop(0, Some(1)),
        hop(0, None),
    ])
    .expect("four hops fit")
}

/// `frame.rs` tests: pattern `1100` as robot 3 relays it, (1, tag 0, RIGHT), (1, tag 1,
/// RIGHT), (0, tag 2, LEFT), (0, tag 3, LEFT).
pub const GOLDEN_TAGGED_FOUR: &[u8] = b"ss\x75\x77\x72\x72\x72\x62\x71\x51\x77\x41\x40\x1dss";

/// The message of [`GOLDEN_TAGGED_FOUR`].
pub fn tagged_four() -> Message {
    Message::from_hops(&[
        tagged(1, 0, Some(0)),
        tagged(1, 1, Some(0)),
        tagged(0, 2, Some(1)),
        tagged(0, 3, Some(1)),
    ])
    .expect("four hops fit")
}

/// The message of [`GOLDEN_S_BYTES`].
pub fn s_bytes() -> Message {
    Message::from_hops(&[hop(b's', None), hop(b's', None)]).expect("two hops fit")
}

/// A hop as the fuzz input spells it: a reading byte, an optional sector byte (taken modulo
/// [`MAX_SECTORS`]) and a robot tag byte (modulo [`MAX_TAGS`]). Read with the `arbitrary`
/// crate: `u8`, `Option<u8>`, `u8`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArbHop {
    /// The reading.
    pub reading: u8,
    /// The preference's sector index, before the modulo.
    pub pref: Option<u8>,
    /// The robot's tag, before the modulo.
    pub tag: u8,
}

impl<'a> Arbitrary<'a> for ArbHop {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        Ok(ArbHop {
            reading: u.arbitrary()?,
            pref: u.arbitrary()?,
            tag: u.arbitrary()?,
        })
    }
}

impl ArbHop {
    /// The protocol's hop.
    pub fn hop(self) -> Hop {
        tagged(self.reading, self.tag, self.pref)
    }

    /// Writes this hop in the input format (see [`crate::input`]).
    pub fn write(self, w: &mut crate::input::Writer) {
        w.u8(self.reading);
        match self.pref {
            Some(p) => w.bool(true).u8(p),
            None => w.bool(false),
        };
        w.u8(self.tag);
    }
}

/// Reads a list of hops (at most `max`), as written by [`write_hops`].
pub fn read_hops(u: &mut Unstructured<'_>, max: usize) -> Vec<Hop> {
    crate::input::list(u, max, |u| {
        u.arbitrary::<ArbHop>()
            .unwrap_or(ArbHop {
                reading: 0,
                pref: None,
                tag: 0,
            })
            .hop()
    })
}

/// Writes a list of hops for [`read_hops`].
pub fn write_hops(w: &mut crate::input::Writer, hops: &[Hop]) {
    for h in hops {
        w.item();
        ArbHop {
            reading: h.reading.0,
            pref: h.pref.map(Sector::index),
            tag: h.tag.index(),
        }
        .write(w);
    }
    w.end();
}

/// A message from up to [`MAX_HOPS`] hops, or the empty message for none.
pub fn message(hops: &[Hop]) -> Message {
    Message::from_hops(hops).unwrap_or_default()
}

/// The payload of §1.2: hop count, then per hop the reading and the preference byte, whose
/// high nibble is the robot's tag and low nibble 0 for no preference or `sector + 1`.
pub fn payload_of(msg: &Message) -> Vec<u8> {
    let mut p = vec![u8::try_from(msg.len()).expect("at most MAX_HOPS hops")];
    for h in msg.hops() {
        p.push(h.reading.0);
        p.push(pref_byte(h));
    }
    p
}

/// A hop's preference byte: `tag << 4 | (0 or sector + 1)`.
pub fn pref_byte(h: &Hop) -> u8 {
    h.tag.index() << 4 | h.pref.map_or(0, |s| s.index() + 1)
}

/// COBS encoding (Cheshire and Baker), from the algorithm: blocks of up to 254 non-zero bytes,
/// each led by its length plus one; a zero ends a block.
pub fn cobs_encode(raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0];
    let mut code_at = 0;
    for &b in raw {
        if b == 0 {
            out[code_at] = u8::try_from(out.len() - code_at).expect("block below 255");
            code_at = out.len();
            out.push(0);
        } else {
            out.push(b);
            if out.len() - code_at == 0xFF {
                out[code_at] = 0xFF;
                code_at = out.len();
                out.push(0);
            }
        }
    }
    out[code_at] = u8::try_from(out.len() - code_at).expect("block below 255");
    out
}

/// COBS decoding as §2.2 describes it: `None` if a code byte is zero or points past the end.
/// A zero follows every block but a 0xFF one and the last.
pub fn cobs_decode(enc: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < enc.len() {
        let code = usize::from(enc[i]);
        if code == 0 || i + code > enc.len() {
            return None;
        }
        out.extend_from_slice(&enc[i + 1..i + code]);
        i += code;
        if code != 0xFF && i < enc.len() {
            out.push(0);
        }
    }
    Some(out)
}

/// `ss` + (COBS(`raw`) XOR `s`) + `ss`: the frame of §1.1 around any unstuffed bytes.
pub fn frame_raw(raw: &[u8]) -> Vec<u8> {
    let mut f = vec![DELIMITER, DELIMITER];
    f.extend(cobs_encode(raw).iter().map(|b| b ^ DELIMITER));
    f.extend_from_slice(&[DELIMITER, DELIMITER]);
    f
}

/// The frame of any payload, with its correct frame check.
pub fn frame_payload(payload: &[u8]) -> Vec<u8> {
    let mut raw = payload.to_vec();
    raw.extend_from_slice(&CRC16.checksum(payload).to_le_bytes());
    frame_raw(&raw)
}

/// Decodes one body (bytes between two delimiters, none of them `s`) the way §2.2 specifies,
/// without the protocol's code: XOR, COBS, length, CRC, then postcard.
pub fn decode_body(body: &[u8]) -> Result<Message, FrameError> {
    assert!(!body.contains(&DELIMITER), "a body never holds `s`");
    if body.len() > BODY_MAX {
        return Err(FrameError::TooLong);
    }
    let unxored: Vec<u8> = body.iter().map(|b| b ^ DELIMITER).collect();
    let raw = cobs_decode(&unxored).ok_or(FrameError::BadStuffing)?;
    if raw.len() <= CRC_LEN {
        return Err(FrameError::TooShort);
    }
    let (payload, crc) = raw.split_at(raw.len() - CRC_LEN);
    if CRC16.checksum(payload).to_le_bytes() != crc {
        return Err(FrameError::BadCheck);
    }
    decode_payload(payload)
}

/// A payload with a good frame check: a message if postcard reads one that uses every byte and
/// has at least one hop.
pub fn decode_payload(payload: &[u8]) -> Result<Message, FrameError> {
    match postcard::take_from_bytes::<Message>(payload) {
        Ok((m, rest)) if rest.is_empty() && !m.is_empty() => Ok(m),
        _ => Err(FrameError::Undecodable),
    }
}

/// What every message that came out of a decoder must satisfy: 1..=MAX_HOPS hops, and its
/// frame (exactly `8 + 2·len` bytes, at most [`FRAME_MAX`]) decodes back to it.
pub fn check_decoded(msg: &Message) {
    assert!(
        (1..=MAX_HOPS).contains(&msg.len()),
        "decoded message with {} hops",
        msg.len()
    );
    let f = frame::encode(msg).expect("a decoded message encodes");
    assert_eq!(f.len(), 8 + 2 * msg.len(), "frame length of {msg:?}");
    assert!(f.len() <= FRAME_MAX);
    assert_eq!(
        frame::decode_frame(&f).as_ref(),
        Ok(msg),
        "re-encoded {msg:?}"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_vectors_match_the_protocol_and_the_reference() {
        for (bytes, msg) in [
            (GOLDEN_ONE_HOP, one_hop()),
            (GOLDEN_FOUR_HOPS, four_hops()),
            (GOLDEN_S_BYTES, s_bytes()),
            (GOLDEN_TAGGED_FOUR, tagged_four()),
        ] {
            assert_eq!(frame::encode(&msg).unwrap().as_slice(), bytes);
            assert_eq!(frame_payload(&payload_of(&msg)), bytes);
            assert_eq!(frame::decode_frame(bytes), Ok(msg.clone()));
            assert_eq!(decode_body(&bytes[2..bytes.len() - 2]), Ok(msg));
        }
    }

    #[test]
    fn cobs_reference_agrees_with_the_cobs_crate() {
        let cases: [&[u8]; 6] = [&[], &[0], &[1, 0, 2], &[0x73; 30], &[0; 3], &[5; 300]];
        for raw in cases {
            let mut buf = [0u8; 400];
            let n = cobs::encode(raw, &mut buf);
            assert_eq!(cobs_encode(raw), &buf[..n], "{raw:?}");
            assert_eq!(cobs_decode(&buf[..n]).as_deref(), Some(raw), "{raw:?}");
        }
        assert_eq!(cobs_decode(&[3, 1]), None, "code past the end");
        assert_eq!(cobs_decode(&[0]), None, "zero code");
    }

    #[test]
    fn sector_and_tag_take_their_modulo() {
        assert_eq!(sector(9).index(), 1);
        assert_eq!(sector(7).index(), 7);
        assert_eq!(tag(17).index(), 1);
        assert_eq!(pref_byte(&tagged(0, 15, Some(7))), 0xF8);
    }
}
