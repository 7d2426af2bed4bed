//! What the checks compare the protocol against: the golden vectors and an independent
//! implementation of the frame layout of `docs/protocol.md` §1 (payload format 3: header, hops,
//! optional ray, 25-byte budget; CRC-16/IBM-3740, COBS, XOR with `s`), written from the
//! document rather than from `frame.rs` or `message.rs` (the payload parser below does not
//! call postcard or the protocol's `Deserialize`).

use arbitrary::{Arbitrary, Unstructured};
use protocol::frame::{self, BODY_MAX, CRC_LEN, DELIMITER, FRAME_MAX, FrameError};
use protocol::message::{MAX_TAGS, PAYLOAD_BUDGET, Ray, Tag};
use protocol::{Hop, Level, MAX_HOPS, MAX_SECTORS, Message, Sector};

// The golden vectors of payload format 3, as in `frame.rs`'s tests, computed by
// `protocol/tests/golden/gen_golden.py` (independently of the Rust encoder).

/// One hop, reading 1, no preference (payload `41 01 00`).
pub const GOLDEN_ONE_HOP: &[u8] = b"ss\x70\x32\x72\x70\x43\xa6ss";
/// (1, RIGHT), (0, LEFT), (0, LEFT), (0, none) (payload `44 01 01 00 02 00 02 00 00`).
pub const GOLDEN_FOUR_HOPS: &[u8] = b"ss\x77\x37\x72\x72\x71\x71\x71\x71\x72\x70\x66\x7dss";
/// Two hops with reading `s` (0x73) and no preference (payload `42 73 00 73 00`).
pub const GOLDEN_S_BYTES: &[u8] = b"ss\x70\x31\x00\x71\x00\x70\x37\xb3ss";
/// [`GOLDEN_TAGGED_FOUR`]'s hops and the ray of the LEFT side of a robot with K = 2: 4 robots
/// reading 200, 200, 30, 30 (sum 460, sum of squares 81800), votes [2, 2] (18-byte payload).
pub const GOLDEN_RAY_FOUR: &[u8] =
    b"ss\x75\x27\x72\x72\x72\x62\x71\x51\x7e\x41\x61\x77\xbf\x72\xfb\x4c\x72\x71\x71\x28\x2dss";
/// The first byte of a format-1 payload was the hop count; the old one-hop golden frame is
/// `Undecodable` now.
pub const GOLDEN_V1_ONE_HOP: &[u8] = b"ss\x70\x72\x72\x70\xee\xbbss";
/// Format 2's one-hop golden frame (header `21`): `Undecodable` now too.
pub const GOLDEN_V2_ONE_HOP: &[u8] = b"ss\x70\x52\x72\x70\x28\x3dss";

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
pub const GOLDEN_TAGGED_FOUR: &[u8] = b"ss\x75\x37\x72\x72\x72\x62\x71\x51\x77\x41\x99\x42ss";

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

/// The ray of [`GOLDEN_RAY_FOUR`].
pub fn ray_left_k2() -> Ray {
    let mut votes = [0; MAX_SECTORS];
    votes[..2].copy_from_slice(&[2, 2]);
    Ray {
        sector: sector(1),
        sectors: 2,
        robots: 4,
        sum: 460,
        sum_sq: 81800,
        votes,
        closed: false,
    }
}

/// The message of [`GOLDEN_RAY_FOUR`].
pub fn ray_four() -> Message {
    let mut m = tagged_four();
    assert_eq!(m.set_ray(Some(ray_left_k2())), 0);
    m
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

/// A ray as the fuzz input spells it, always made valid: `sectors` taken as `2 + sectors % 7`,
/// `sector` modulo that, `robots` 0 read as 1, its robots' readings as two values `a` and `b`,
/// `count % (robots + 1)` of them reading `b` and the others `a` (so that the sums are those
/// of real readings), each vote modulo `robots + 1`. Read with the `arbitrary` crate: `u8`
/// sectors, `u8` sector, `u8` robots, `u8` a, `u8` b, `u8` count, 8 `u8`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArbRay(pub Ray);

/// The sums of `n − c` readings `a` and `c` readings `b`.
fn sums(n: u32, a: u32, b: u32, c: u32) -> (u16, u32) {
    ((a * (n - c) + b * c) as u16, a * a * (n - c) + b * b * c)
}

impl<'a> Arbitrary<'a> for ArbRay {
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Self> {
        let k = 2 + u.arbitrary::<u8>()? % 7;
        let s = u.arbitrary::<u8>()? % k;
        let robots = u.arbitrary::<u8>()?.max(1);
        let a = u32::from(u.arbitrary::<u8>()?);
        let b = u32::from(u.arbitrary::<u8>()?);
        let n = u32::from(robots);
        let c = u32::from(u.arbitrary::<u8>()?) % (n + 1);
        let (sum, sum_sq) = sums(n, a, b, c);
        let raw: [u8; MAX_SECTORS] = u.arbitrary()?;
        let mut votes = [0; MAX_SECTORS];
        for (v, r) in votes.iter_mut().zip(raw).take(usize::from(k)) {
            *v = if robots == u8::MAX {
                r
            } else {
                r % (robots + 1)
            };
        }
        let closed = u.arbitrary::<bool>()?;
        Ok(ArbRay(Ray {
            sector: sector(s),
            sectors: k,
            robots,
            sum,
            sum_sq,
            votes,
            closed,
        }))
    }
}

impl ArbRay {
    /// Writes a valid ray of two reading values (as [`ArbRay::arbitrary`] makes them, and the
    /// golden [`ray_left_k2`]) so that it reads back as itself; a ray of more values is written
    /// as the two-valued ray of the same robots and mean nearest to it (searched).
    pub fn write(self, w: &mut crate::input::Writer) {
        let r = self.0;
        let n = u32::from(r.robots);
        let mut best = (u64::MAX, 0u32, 0u32, 0u32);
        'search: for c in 0..=n {
            for a in 0..=255u32 {
                for b in [a, (u32::from(r.sum).saturating_sub(a * (n - c))) / c.max(1)] {
                    if b > 255 {
                        continue;
                    }
                    let (s, q) = sums(n, a, b, c);
                    let miss =
                        u64::from(s.abs_diff(r.sum)) * (1 << 32) + u64::from(q.abs_diff(r.sum_sq));
                    if miss < best.0 {
                        best = (miss, a, b, c);
                        if miss == 0 {
                            break 'search;
                        }
                    }
                }
            }
        }
        let (_, a, b, c) = best;
        w.u8(r.sectors - 2).u8(r.sector.index()).u8(r.robots);
        w.u8(a as u8).u8(b as u8).u8(c as u8);
        for v in r.votes {
            w.u8(v);
        }
        w.u8(u8::from(r.closed));
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

/// Version bits of a format-3 header (its top three bits, `010`).
pub const FORMAT_3: u8 = 0x40;
/// The header's ray bit.
pub const RAY_BIT: u8 = 0x10;

/// The payload of format 3: the header `0b010r_nnnn` (r = a ray follows, n = hops), then per
/// hop the reading and the preference byte, whose high nibble is the robot's tag and low
/// nibble 0 for no preference or `sector + 1`, then the ray if any: `sector << 4 | sectors`,
/// robots, the readings' sum (u16 LE) and sum of squares (u24 LE), one vote byte per sector.
pub fn payload_of(msg: &Message) -> Vec<u8> {
    let n = u8::try_from(msg.len()).expect("at most MAX_HOPS hops");
    assert!(n <= 0x0F);
    let r = msg.ray().map_or(0, |_| RAY_BIT);
    let mut p = vec![FORMAT_3 | r | n];
    for h in msg.hops() {
        p.push(h.reading.0);
        p.push(pref_byte(h));
    }
    if let Some(ray) = msg.ray() {
        p.extend_from_slice(&ray_bytes(ray));
    }
    p
}

/// A ray's bytes: `closed << 7 | sector << 4 | sectors`, robots, sum LE (2), sum of squares
/// LE (3), `votes[..sectors]`.
pub fn ray_bytes(r: &Ray) -> Vec<u8> {
    let mut p = vec![
        u8::from(r.closed) << 7 | r.sector.index() << 4 | r.sectors,
        r.robots,
    ];
    p.extend_from_slice(&r.sum.to_le_bytes());
    p.extend_from_slice(&r.sum_sq.to_le_bytes()[..3]);
    p.extend_from_slice(&r.votes[..usize::from(r.sectors).min(MAX_SECTORS)]);
    p
}

/// True if a ray satisfies the rules of format 3: 2..=8 sectors, its sector below that, at
/// least one robot, sums that `robots` readings of 0..=255 can have (`sum <= 255 · robots`,
/// `sum_sq <= 255 · sum`, `sum² <= robots · sum_sq`), no vote above `robots`, nothing beyond
/// `sectors` votes.
pub fn ray_is_valid(r: &Ray) -> bool {
    let k = usize::from(r.sectors);
    let (n, s, q) = (u64::from(r.robots), u64::from(r.sum), u64::from(r.sum_sq));
    (2..=MAX_SECTORS).contains(&k)
        && usize::from(r.sector.index()) < k
        && r.robots >= 1
        && s <= 255 * n
        && q <= 255 * s
        && s * s <= n * q
        && r.votes.iter().all(|&v| v <= r.robots)
        && r.votes[k..].iter().all(|&v| v == 0)
}

/// Why [`parse_prefix`] refused bytes (for messages only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParseError {
    /// No byte, or fewer than the header announces.
    Short,
    /// Top three bits not `010`, or a hop count of 0 or above MAX_HOPS.
    Header,
    /// A preference nibble above 8.
    Pref,
    /// A ray's sector byte, robots or votes break the rules.
    Ray,
    /// Header, hops and ray are longer than the 25-byte budget.
    Budget,
}

/// Reads one format-3 message from the start of `data`, independently of the protocol's
/// decoder: returns it (built through the public API) and the bytes it used.
pub fn parse_prefix(data: &[u8]) -> Result<(Message, usize), ParseError> {
    let &header = data.first().ok_or(ParseError::Short)?;
    let n = usize::from(header & 0x0F);
    if header & 0xE0 != FORMAT_3 || n == 0 || n > MAX_HOPS {
        return Err(ParseError::Header);
    }
    let hop_bytes = data.get(1..1 + 2 * n).ok_or(ParseError::Short)?;
    let mut hops = Vec::with_capacity(n);
    for c in hop_bytes.chunks(2) {
        let p = c[1] & 0x0F;
        if p > MAX_SECTORS as u8 {
            return Err(ParseError::Pref);
        }
        hops.push(tagged(c[0], c[1] >> 4, p.checked_sub(1)));
    }
    let mut used = 1 + 2 * n;
    let ray = if header & RAY_BIT != 0 {
        let fixed = data.get(used..used + 7).ok_or(ParseError::Short)?;
        // Bit 7: the ray is closed (revision 3.1); bits 6-4 the sector, 3-0 K.
        let (s, k, closed) = (
            (fixed[0] >> 4) & 0x07,
            fixed[0] & 0x0F,
            fixed[0] & 0x80 != 0,
        );
        let robots = fixed[1];
        // The sector byte is checked before the votes are read: its K says how many follow.
        if !(2..=MAX_SECTORS as u8).contains(&k) || s >= k || robots == 0 {
            return Err(ParseError::Ray);
        }
        let v = data
            .get(used + 7..used + 7 + usize::from(k))
            .ok_or(ParseError::Short)?;
        let sum = u16::from_le_bytes([fixed[2], fixed[3]]);
        let sum_sq = u32::from_le_bytes([fixed[4], fixed[5], fixed[6], 0]);
        // Sums of 8-bit readings: sum <= 255 n, sum_sq <= 255 sum, sum² <= n sum_sq.
        let (n64, s64, q64) = (u64::from(robots), u64::from(sum), u64::from(sum_sq));
        if v.iter().any(|&x| x > robots)
            || s64 > 255 * n64
            || q64 > 255 * s64
            || s64 * s64 > n64 * q64
        {
            return Err(ParseError::Ray);
        }
        let mut votes = [0; MAX_SECTORS];
        votes[..v.len()].copy_from_slice(v);
        used += 7 + usize::from(k);
        Some(Ray {
            sector: sector(s),
            sectors: k,
            robots,
            sum,
            sum_sq,
            votes,
            closed,
        })
    } else {
        None
    };
    if used > PAYLOAD_BUDGET {
        return Err(ParseError::Budget);
    }
    let mut m = Message::from_hops(&hops).expect("1..=MAX_HOPS hops");
    assert_eq!(
        m.set_ray(ray),
        0,
        "a message within the budget keeps its hops"
    );
    Ok((m, used))
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

/// A payload with a good frame check: a message if the independent parser reads one that
/// uses every byte.
pub fn decode_payload(payload: &[u8]) -> Result<Message, FrameError> {
    match parse_prefix(payload) {
        Ok((m, used)) if used == payload.len() => Ok(m),
        _ => Err(FrameError::Undecodable),
    }
}

/// What every message that came out of a decoder must satisfy: 1..=MAX_HOPS hops, a valid ray
/// if any, a payload of at most 25 bytes, and its frame (exactly `7 + payload` bytes, at most
/// [`FRAME_MAX`]) is the independent encoder's and decodes back to it.
pub fn check_decoded(msg: &Message) {
    assert!(
        (1..=MAX_HOPS).contains(&msg.len()),
        "decoded message with {} hops",
        msg.len()
    );
    if let Some(r) = msg.ray() {
        assert!(ray_is_valid(r), "invalid ray in {msg:?}");
    }
    let payload = payload_of(msg);
    assert!(payload.len() <= PAYLOAD_BUDGET, "{msg:?} over the budget");
    assert_eq!(msg.encoded_len(), payload.len(), "encoded_len of {msg:?}");
    let f = frame::encode(msg).expect("a decoded message encodes");
    assert_eq!(f.len(), 7 + payload.len(), "frame length of {msg:?}");
    assert!(f.len() <= FRAME_MAX);
    assert_eq!(f.as_slice(), frame_payload(&payload).as_slice());
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
            (GOLDEN_RAY_FOUR, ray_four()),
        ] {
            assert_eq!(frame::encode(&msg).unwrap().as_slice(), bytes);
            assert_eq!(frame_payload(&payload_of(&msg)), bytes);
            assert_eq!(frame::decode_frame(bytes), Ok(msg.clone()));
            assert_eq!(decode_body(&bytes[2..bytes.len() - 2]), Ok(msg.clone()));
            check_decoded(&msg);
        }
        assert_eq!(
            frame::decode_frame(GOLDEN_V1_ONE_HOP),
            Err(FrameError::Undecodable)
        );
        assert_eq!(
            decode_body(&GOLDEN_V1_ONE_HOP[2..GOLDEN_V1_ONE_HOP.len() - 2]),
            Err(FrameError::Undecodable)
        );
    }

    #[test]
    fn the_parser_refuses_what_format_3_refuses() {
        let ok = |p: &[u8]| parse_prefix(p).map(|(m, used)| (m.len(), used));
        assert_eq!(ok(&[0x41, 1, 0]), Ok((1, 3)));
        assert_eq!(ok(&[0x41, 1, 0, 9]), Ok((1, 3)));
        assert_eq!(ok(&[]), Err(ParseError::Short));
        assert_eq!(ok(&[0x42, 1, 0]), Err(ParseError::Short));
        // No hop, 13 hops, formats 1 and 2, other version bits.
        for h in [0x40, 0x4D, 0x4F, 0x50, 0x01, 0x04, 0x21, 0x31, 0x61, 0xE1] {
            assert_eq!(ok(&[h, 1, 0, 1, 0]), Err(ParseError::Header), "{h:#x}");
        }
        assert_eq!(ok(&[0x41, 1, 9]), Err(ParseError::Pref));
        let ray = |r: &[u8]| {
            let mut p = vec![0x51, 1, 0];
            p.extend_from_slice(r);
            ok(&p)
        };
        // Two robots reading 1: sum 2, sum of squares 2.
        assert_eq!(ray(&[0x12, 2, 2, 0, 2, 0, 0, 2, 2]), Ok((1, 12)));
        assert_eq!(ray(&[0x01, 2, 2, 0, 2, 0, 0, 2]), Err(ParseError::Ray));
        assert_eq!(ray(&[0x09, 2, 2, 0, 2, 0, 0]), Err(ParseError::Ray));
        assert_eq!(ray(&[0x22, 2, 2, 0, 2, 0, 0, 2, 2]), Err(ParseError::Ray));
        assert_eq!(ray(&[0x02, 0, 0, 0, 0, 0, 0, 0, 0]), Err(ParseError::Ray));
        assert_eq!(ray(&[0x02, 2, 2, 0, 2, 0, 0, 3, 0]), Err(ParseError::Ray));
        // Sums no readings have: a sum above 255 per robot, a sum of squares above 255 times
        // the sum, a negative variance (sum² above robots × sum of squares).
        assert_eq!(ray(&[0x02, 1, 0, 1, 0, 0, 1, 1, 0]), Err(ParseError::Ray));
        assert_eq!(
            ray(&[0x02, 1, 7, 0, 0xFF, 0x06, 0, 1, 0]),
            Err(ParseError::Ray)
        );
        assert_eq!(ray(&[0x02, 2, 14, 0, 97, 0, 0, 1, 1]), Err(ParseError::Ray));
        assert_eq!(ray(&[0x02, 2, 2, 0, 2, 0, 0, 1]), Err(ParseError::Short));
        let mut big = vec![0x58];
        big.extend_from_slice(&[1, 0].repeat(8));
        big.extend_from_slice(&[0x02, 1, 1, 0, 1, 0, 0, 1, 0]);
        assert_eq!(ok(&big), Err(ParseError::Budget));
        assert!(postcard::from_bytes::<Message>(&big).is_err());
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
