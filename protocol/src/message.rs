//! The message a wave carries: the ordered list of hops, oldest (the initiator) first.
//!
//! Each hop is what one robot added while relaying: its sensor reading and its preferred
//! direction at that moment (the fused variant the aMussels ran, paper section 4). The last hop
//! is the neighbour the message was heard from; in a line, the hop `d` places from the end is the
//! robot `d` places away in the direction of reception.
//!
//! # Capacity and the full-message rule
//! A message holds at most [`MAX_HOPS`] hops and at most [`PAYLOAD_BUDGET`] bytes encoded, its
//! optional [`Ray`] included (payload format 2, see [`crate::frame`], which proves the sizes at
//! compile time). A robot relaying a full message **drops the oldest hops** (those farthest away
//! along the wave's path) to make room for its own hop and its ray: 7 hops fit beside a
//! two-sector ray. The wave keeps travelling, each receiver still sees the robots nearest to it
//! along the path with fresh preferences, and a message's diversity becomes that of a sliding
//! window; what lies beyond the window is summarised by the ray. Relaying unchanged would freeze
//! the far end of the path and hide the neighbours; refusing to relay would stop the wave.

use heapless::Vec;
use serde::de::{Error as _, Unexpected};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::direction::{MAX_SECTORS, Sector};

/// Hops per message: the most that fit a 32-byte frame in the worst case (12).
pub const MAX_HOPS: usize = 12;

/// Distinct robot tags: 16 (`0..=15`), one nibble of a hop's preference byte.
pub const MAX_TAGS: usize = 16;

/// A sensor reading quantised to 8 bits (0 = darkest/lowest, 255 = brightest/highest). The
/// scaling from the ADC is the firmware's business; CIMAX only compares readings.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Level(pub u8);

impl From<Level> for f32 {
    fn from(l: Level) -> f32 {
        f32::from(l.0)
    }
}

/// A robot's tag on the wire: its id modulo [`MAX_TAGS`] (16), `0..=15`.
///
/// Tags tell robots apart within a message's reach: every robot within [`MAX_HOPS`] hops of
/// another must have a tag of its own. Sixteen robots numbered `0..16` always do; in a longer
/// line numbered in order, two robots with the same tag are 16 apart, so never in the same
/// message (see `docs/protocol.md` §5.3 for what a robot in the middle of such a line counts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tag(u8);

impl Tag {
    /// The tag with this value, if it is below [`MAX_TAGS`].
    pub const fn new(value: u8) -> Option<Tag> {
        if (value as usize) < MAX_TAGS {
            Some(Tag(value))
        } else {
            None
        }
    }

    /// The tag of the robot with this id: `id mod 16`.
    pub const fn from_id(id: u16) -> Tag {
        Tag((id % MAX_TAGS as u16) as u8)
    }

    /// The tag's value, `0..=15`.
    pub const fn index(self) -> u8 {
        self.0
    }
}

/// What one relaying robot appended: its reading, its preferred direction (if any) and its
/// tag.
///
/// On the wire two bytes: the reading, then `tag << 4 | pref` with `pref` 0 for none and
/// `sector + 1` otherwise. Decoding refuses a preference nibble above 8.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hop {
    /// The robot's sensor reading.
    pub reading: Level,
    /// The robot's preferred direction when it relayed; `None` while it has none.
    pub pref: Option<Sector>,
    /// The relaying robot's tag.
    pub tag: Tag,
}

/// Serde's "expected" text for a bad preference byte.
const PREF_EXPECTED: &str = "a preference byte tag << 4 | p with p in 0..=8 (0 = none, sector + 1)";

impl Hop {
    /// The preference byte: tag in the high nibble, `0` or `sector + 1` in the low one.
    fn pref_byte(&self) -> u8 {
        self.tag.0 << 4 | self.pref.map_or(0, |p| p.index() + 1)
    }

    /// The hop of a reading and a preference byte; `None` if the preference nibble is above 8.
    fn from_bytes(reading: u8, pref_byte: u8) -> Option<Hop> {
        let pref = match pref_byte & 0x0F {
            0 => None,
            p => Some(Sector::new(p - 1)?),
        };
        Some(Hop {
            reading: Level(reading),
            pref,
            tag: Tag(pref_byte >> 4),
        })
    }
}

impl Serialize for Hop {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        (self.reading.0, self.pref_byte()).serialize(s)
    }
}

impl<'de> Deserialize<'de> for Hop {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (reading, pref_byte) = <(u8, u8)>::deserialize(d)?;
        Hop::from_bytes(reading, pref_byte).ok_or_else(|| {
            D::Error::invalid_value(Unexpected::Unsigned(u64::from(pref_byte)), &PREF_EXPECTED)
        })
    }
}

/// Version bits of the payload's first byte (its top three bits): `0b010` for this format,
/// format 3 (rays carry exact sums of the readings, `docs/protocol.md` revision 3.0).
///
/// The first format (before rays) began with the hop count as a varint, `1..=12`, whose top
/// three bits are zero; format 2 (rays with a rounded mean and variance) had `0b001`: each
/// format refuses the others' payloads as undecodable.
pub const FORMAT_BITS: u8 = 0x40;
/// Header bit set when a [`Ray`] follows the hops.
const RAY_BIT: u8 = 0x10;
/// Bit of a ray's sector byte set when the ray is [`closed`](Ray::closed) (revision 3.1; the
/// sector takes bits 6–4, as a sector is below 8).
const CLOSED_BIT: u8 = 0x80;
/// Mask of the header's hop count.
const COUNT_MASK: u8 = 0x0F;
/// Mask of the header's version bits.
const VERSION_MASK: u8 = 0xE0;
/// Largest payload of any message: the header and [`MAX_HOPS`] hops, or fewer hops and a ray.
pub const PAYLOAD_BUDGET: usize = 1 + MAX_HOPS * 2;

/// What a robot knows of everything beyond it in one direction: a summary of the robots on
/// that side (the robot itself included), built hop by hop along the waves.
///
/// A message's hops are the last robots of its path (at most [`MAX_HOPS`]); a ray is the
/// *sufficient statistics* of the whole chain of robots beyond, however long: how many there
/// are, the sum and the sum of squares of their readings (exact integers, so the variance
/// derived from them is exact and does not depend on the sensor's unit: §5.3 of
/// `docs/protocol.md`), and how many prefer each sector. A robot keeps the latest ray heard
/// from each of its sectors and, when it transmits, extends the ray of one sector by itself
/// ([`Ray::extended`]).
///
/// On the wire `7 + sectors` bytes: `closed << 7 | sector << 4 | sectors`, `robots`, `sum`
/// (u16 LE), `sum_sq` (u24 LE), then `votes[..sectors]`, one byte each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ray {
    /// The direction summarised, in the sender's sectors (the swarm's common frame): the robots
    /// that lie in this sector of the sender, and the sender.
    pub sector: Sector,
    /// The sender's number of sectors K, `2..=8`; `votes` has this many entries.
    pub sectors: u8,
    /// Robots summarised, `1..=255` (a ray of 255 robots takes no more readings).
    pub robots: u8,
    /// Sum of their readings, exact (at most `255 · robots`).
    pub sum: u16,
    /// Sum of the squares of their readings, exact (at most `255 · sum`, below 2²⁴).
    pub sum_sq: u32,
    /// Robots preferring each sector (saturating); entries `sectors..` are zero.
    pub votes: [u8; MAX_SECTORS],
    /// The ray reaches the end of the swarm that way: its farthest robot knew that it had no
    /// neighbour beyond (it heard nothing from that side for a whole longest cycle), so
    /// `robots` counts every robot of the chain. Kept by [`Ray::extended`]. Only the adaptive
    /// rule sets it (`docs/protocol.md` §5.4, revision 3.1); bit 7 of the sector byte.
    pub closed: bool,
}

impl Ray {
    /// The ray of one robot alone: `sector` of a robot with `sectors` sectors, its reading and
    /// preference. `None` if `sectors` is not `2..=8` or `sector` is not below it.
    pub fn single(
        sector: Sector,
        sectors: u8,
        reading: Level,
        pref: Option<Sector>,
    ) -> Option<Ray> {
        if !(2..=MAX_SECTORS as u8).contains(&sectors) || sector.index() >= sectors {
            return None;
        }
        let x = u16::from(reading.0);
        let mut ray = Ray {
            sector,
            sectors,
            robots: 1,
            sum: x,
            sum_sq: u32::from(x * x),
            votes: [0; MAX_SECTORS],
            closed: false,
        };
        ray.vote(pref);
        Some(ray)
    }

    /// This ray with one more robot, nearer than all it holds (the relaying robot): its reading
    /// joins the sums and its preference the votes. Exact integer arithmetic: no rounding. A
    /// ray of [`RAY_ROBOTS_MAX`] robots is full: its sums stay as they are (the robot's vote
    /// still counts, saturating).
    pub fn extended(&self, reading: Level, pref: Option<Sector>) -> Ray {
        let mut ray = *self;
        if self.robots < RAY_ROBOTS_MAX {
            let x = u16::from(reading.0);
            ray.robots += 1;
            // Cannot overflow for a valid ray: sum <= 255 * 254 + 255 < 2^16,
            // sum_sq <= 65025 * 255 < 2^24; saturate anyway so that no input can panic.
            ray.sum = ray.sum.saturating_add(x);
            ray.sum_sq = ray.sum_sq.saturating_add(u32::from(x * x));
        }
        ray.vote(pref);
        ray
    }

    /// The mean reading, in [`Level`] units.
    pub fn mean_level(&self) -> f32 {
        f32::from(self.sum) / f32::from(self.robots.max(1))
    }

    /// `n² · variance` = `n · Σx² − (Σx)²`, exact: the population variance of the readings
    /// times the number of robots squared (0 for an inconsistent ray).
    pub fn scaled_variance(&self) -> u64 {
        let n = u64::from(self.robots);
        let s = u64::from(self.sum);
        (n * u64::from(self.sum_sq)).saturating_sub(s * s)
    }

    /// The population variance of the readings, in [`Level`] units squared:
    /// [`scaled_variance`](Self::scaled_variance) / n², rounded once to `f32`.
    pub fn variance(&self) -> f32 {
        let n = u32::from(self.robots.max(1));
        div_to_f32(self.scaled_variance(), n * n)
    }

    /// Bytes on the wire.
    pub fn encoded_len(&self) -> usize {
        7 + usize::from(self.sectors)
    }

    /// True if the fields are consistent: `2 <= sectors <= 8`, `sector < sectors`,
    /// `robots >= 1`, sums that `robots` readings in `0..=255` can have
    /// (`sum <= 255 · robots`, `sum² <= robots · sum_sq <= 255 · robots · sum`, which also
    /// keeps `sum_sq` below 2²⁴), no vote beyond `sectors`, no sector with more votes than
    /// robots.
    pub fn is_valid(&self) -> bool {
        let k = usize::from(self.sectors);
        let n = u64::from(self.robots);
        let (s, q) = (u64::from(self.sum), u64::from(self.sum_sq));
        (2..=MAX_SECTORS).contains(&k)
            && usize::from(self.sector.index()) < k
            && self.robots >= 1
            && s <= 255 * n
            && q <= 255 * s
            && s * s <= n * q
            && self.votes[k..].iter().all(|&v| v == 0)
            && self.votes.iter().all(|&v| v <= self.robots)
    }

    fn vote(&mut self, pref: Option<Sector>) {
        if let Some(v) = pref
            .map(|p| usize::from(p.index()))
            .filter(|&i| i < usize::from(self.sectors))
            .and_then(|i| self.votes.get_mut(i))
        {
            *v = v.saturating_add(1);
        }
    }
}

/// The most robots a ray summarises (its count is one byte).
pub const RAY_ROBOTS_MAX: u8 = u8::MAX;

/// `num / den` correctly rounded to the nearest `f32` (ties to even), for `den > 0`; 0 for
/// `den == 0`. Integer arithmetic, then one exact scaling by a power of two: equal fractions
/// give equal results whatever their terms (`f32` division of the two converted integers
/// would round each term first once it passes 2²⁴). 64-bit integers only (a `u128` division
/// would cost the robot image a kilobyte).
pub fn div_to_f32(num: u64, den: u32) -> f32 {
    if num == 0 || den == 0 {
        return 0.0;
    }
    let den = u64::from(den);
    let bits = |x: u64| 64 - x.leading_zeros() as i32;
    // q = ⌊num · 2^s / den⌋ with 2^25 <= q < 2^27 (s may be negative: den shifted instead).
    // Either way the shifted term has at most 26 + 32 bits.
    let s = 26 - (bits(num) - bits(den));
    let (n, d) = if s >= 0 {
        (num << s, den)
    } else {
        (num, den << -s)
    };
    let (q, r) = (n / d, n % d);
    // Keep 24 significant bits; round to nearest, ties to even, the remainder as sticky bit.
    let e = bits(q) - 24;
    let dropped = q & ((1 << e) - 1);
    let half = 1 << (e - 1);
    let mut m = q >> e;
    if dropped > half || (dropped == half && (r != 0 || m & 1 == 1)) {
        m += 1;
    }
    // m <= 2^24 is exact in f32, and so is the scaling by a power of two: the value lies in
    // [2^-32, 2^64], far from f32's subnormals and infinities.
    (m as f32) * pow2(e - s)
}

/// 2^k as an `f32`, for `-126 <= k <= 127`.
fn pow2(k: i32) -> f32 {
    f32::from_bits(((127 + k.clamp(-126, 127)) as u32) << 23)
}

/// A wave's message: at least one hop, at most [`MAX_HOPS`], and optionally the sender's
/// [`Ray`]. Every message fits [`PAYLOAD_BUDGET`] bytes: adding a ray or a hop drops the
/// oldest hops to make room.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Message {
    hops: Vec<Hop, MAX_HOPS>,
    ray: Option<Ray>,
}

impl Serialize for Message {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let ray_len = self.ray.map_or(0, |r| r.encoded_len());
        let mut t = s.serialize_tuple(1 + self.hops.len() + ray_len)?;
        // len <= MAX_HOPS = 12 fits the count nibble.
        let ray_bit = if self.ray.is_some() { RAY_BIT } else { 0 };
        t.serialize_element(&(FORMAT_BITS | ray_bit | self.hops.len() as u8))?;
        for h in &self.hops {
            t.serialize_element(h)?;
        }
        if let Some(r) = &self.ray {
            let k = usize::from(r.sectors);
            let closed = if r.closed { CLOSED_BIT } else { 0 };
            t.serialize_element(&(closed | r.sector.index() << 4 | r.sectors))?;
            t.serialize_element(&r.robots)?;
            t.serialize_element(&r.sum.to_le_bytes())?;
            let q = r.sum_sq.to_le_bytes();
            t.serialize_element(&[q[0], q[1], q[2]])?;
            for v in r.votes.get(..k).unwrap_or(&[]) {
                t.serialize_element(v)?;
            }
        }
        t.end()
    }
}

/// Serde's "expected" text for a bad header.
const HEADER_EXPECTED: &str = "a header 0b010r_nnnn with 1..=12 hops";
/// Serde's "expected" text for a bad ray.
const RAY_EXPECTED: &str = "a ray byte closed << 7 | sector << 4 | sectors with 2..=8 sectors, sector < sectors, robots >= votes >= 0";

struct MessageVisitor;

impl<'de> serde::de::Visitor<'de> for MessageVisitor {
    type Value = Message;

    fn expecting(&self, f: &mut core::fmt::Formatter) -> core::fmt::Result {
        f.write_str("a CIMAX message: header, hops, optional ray")
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Message, A::Error> {
        let missing = || A::Error::custom("message ends early");
        let header: u8 = seq.next_element()?.ok_or_else(missing)?;
        let n = usize::from(header & COUNT_MASK);
        if header & VERSION_MASK != FORMAT_BITS || n == 0 || n > MAX_HOPS {
            return Err(A::Error::invalid_value(
                Unexpected::Unsigned(u64::from(header)),
                &HEADER_EXPECTED,
            ));
        }
        let mut hops = Vec::new();
        for _ in 0..n {
            let h: Hop = seq.next_element()?.ok_or_else(missing)?;
            // Cannot fail: n <= MAX_HOPS.
            let _ = hops.push(h);
        }
        let ray = if header & RAY_BIT != 0 {
            let sk: u8 = seq.next_element()?.ok_or_else(missing)?;
            let robots: u8 = seq.next_element()?.ok_or_else(missing)?;
            let sum: [u8; 2] = seq.next_element()?.ok_or_else(missing)?;
            let sum_sq: [u8; 3] = seq.next_element()?.ok_or_else(missing)?;
            let sectors = sk & 0x0F;
            let bad =
                || A::Error::invalid_value(Unexpected::Unsigned(u64::from(sk)), &RAY_EXPECTED);
            let mut ray = Ray {
                sector: Sector::new((sk >> 4) & 0x07).ok_or_else(bad)?,
                sectors,
                robots,
                sum: u16::from_le_bytes(sum),
                sum_sq: u32::from_le_bytes([sum_sq[0], sum_sq[1], sum_sq[2], 0]),
                votes: [0; MAX_SECTORS],
                closed: sk & CLOSED_BIT != 0,
            };
            if !(2..=MAX_SECTORS as u8).contains(&sectors) {
                return Err(bad());
            }
            for v in ray.votes.iter_mut().take(usize::from(sectors)) {
                *v = seq.next_element()?.ok_or_else(missing)?;
            }
            if !ray.is_valid() {
                return Err(bad());
            }
            Some(ray)
        } else {
            None
        };
        let m = Message { hops, ray };
        if m.encoded_len() > PAYLOAD_BUDGET {
            return Err(A::Error::custom("message longer than a frame holds"));
        }
        Ok(m)
    }
}

impl<'de> Deserialize<'de> for Message {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // Longest possible tuple: header, MAX_HOPS hops, a ray of 4 + MAX_SECTORS elements
        // (sector byte, robots, the sum's 2 bytes and the sum of squares' 3 bytes as arrays).
        d.deserialize_tuple(1 + MAX_HOPS + 4 + MAX_SECTORS, MessageVisitor)
    }
}

impl Message {
    /// A new message holding just the initiator's hop.
    pub fn initiate(first: Hop) -> Self {
        let mut m = Message::default();
        m.push_evicting(first);
        m
    }

    /// A message from a list of hops, oldest first, without a ray; `None` if the list is
    /// empty or too long.
    pub fn from_hops(hops: &[Hop]) -> Option<Self> {
        if hops.is_empty() {
            return None;
        }
        Vec::from_slice(hops)
            .ok()
            .map(|hops| Message { hops, ray: None })
    }

    /// The sender's ray, if the message carries one.
    pub fn ray(&self) -> Option<&Ray> {
        self.ray.as_ref()
    }

    /// Sets (or removes) the ray, dropping the oldest hops until the message fits
    /// [`PAYLOAD_BUDGET`] (at least the newest hop stays: every ray fits beside it). A ray that
    /// is not [valid](Ray::is_valid) (it would encode into a frame every decoder refuses) is
    /// not set: the message is left without one. Returns how many hops were dropped.
    pub fn set_ray(&mut self, ray: Option<Ray>) -> usize {
        self.ray = ray.filter(Ray::is_valid);
        self.fit(PAYLOAD_BUDGET)
    }

    /// Bytes of the postcard payload: header, two per hop, the ray's.
    pub fn encoded_len(&self) -> usize {
        1 + self.hops.len() * 2 + self.ray.map_or(0, |r| r.encoded_len())
    }

    /// Drops the oldest hops until the payload is at most `budget` bytes or one hop is left;
    /// returns how many were dropped.
    pub fn fit(&mut self, budget: usize) -> usize {
        let over = self.encoded_len().saturating_sub(budget);
        let drop = over.div_ceil(2).min(self.hops.len().saturating_sub(1));
        self.keep_newest(self.hops.len() - drop)
    }

    /// The hops, oldest first.
    pub fn hops(&self) -> &[Hop] {
        &self.hops
    }

    /// Number of hops.
    pub fn len(&self) -> usize {
        self.hops.len()
    }

    /// True if the message holds no hop (never true for a message that passed decoding).
    pub fn is_empty(&self) -> bool {
        self.hops.is_empty()
    }

    /// True if the next relay will drop the oldest hop.
    pub fn is_full(&self) -> bool {
        self.hops.is_full() || self.encoded_len() + 2 > PAYLOAD_BUDGET
    }

    /// Appends `hop`, dropping the oldest hop first if the message is full (the module's
    /// full-message rule: [`MAX_HOPS`] hops, or [`PAYLOAD_BUDGET`] bytes with a ray). Returns
    /// the dropped hop, if any.
    pub fn push_evicting(&mut self, hop: Hop) -> Option<Hop> {
        if self.encoded_len() + 2 > PAYLOAD_BUDGET && self.hops.len() > 1 {
            let old = self.hops.first().copied();
            self.keep_newest(self.hops.len() - 1);
            // Now there is room for a hop in the budget, and so in the list.
            let _ = self.hops.push(hop);
            return old;
        }
        push_evicting(&mut self.hops, hop)
    }

    /// Drops the oldest hops until at most `n` remain; returns how many were dropped.
    pub fn keep_newest(&mut self, n: usize) -> usize {
        let drop = self.hops.len().saturating_sub(n);
        if drop > 0 {
            shift_out(&mut self.hops, drop);
            self.hops.truncate(self.hops.len() - drop);
        }
        drop
    }

    /// True if a hop carries `tag`: the robot with that tag relayed this message (or one with
    /// the same tag, which a swarm avoids within [`MAX_HOPS`] hops).
    pub fn has_tag(&self, tag: Tag) -> bool {
        self.hops.iter().any(|h| h.tag == tag)
    }

    /// The readings, oldest first, as floats (for a [`crate::diversity::Diversity`]).
    pub fn readings(&self) -> impl Iterator<Item = f32> + Clone + '_ {
        self.hops.iter().map(|h| f32::from(h.reading))
    }
}

/// Moves `s[n..]` to the front of `s`, element by element (what is left at the end is stale).
/// `rotate_left` or `Vec::remove` would do it with `memmove`, whose general implementation is
/// 1.5 KB of the robot image; these lists hold at most a few dozen bytes.
pub(crate) fn shift_out<T: Copy>(s: &mut [T], n: usize) {
    let mut i = 0;
    while let Some(&x) = s.get(i + n) {
        if let Some(slot) = s.get_mut(i) {
            *slot = x;
        }
        i += 1;
    }
}

/// Appends to a bounded list, dropping the oldest element when it is full. Returns the dropped
/// element. A zero-capacity list stays empty.
pub(crate) fn push_evicting<T: Copy, const N: usize>(v: &mut Vec<T, N>, item: T) -> Option<T> {
    if N == 0 {
        return None;
    }
    let evicted = match v.first().copied() {
        Some(first) if v.is_full() => {
            shift_out(v, 1);
            v.pop();
            Some(first)
        }
        _ => None,
    };
    // Cannot fail: there is room now.
    let _ = v.push(item);
    evicted
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hop(r: u8) -> Hop {
        Hop {
            reading: Level(r),
            pref: None,
            tag: Tag::default(),
        }
    }

    #[test]
    fn full_message_drops_the_oldest_hop() {
        let mut m = Message::initiate(hop(0));
        for r in 1..MAX_HOPS as u8 {
            assert_eq!(m.push_evicting(hop(r)), None);
        }
        assert!(m.is_full());
        assert_eq!(m.push_evicting(hop(100)), Some(hop(0)));
        assert_eq!(m.len(), MAX_HOPS);
        assert_eq!(m.hops()[0], hop(1));
        assert_eq!(m.hops()[MAX_HOPS - 1], hop(100));
    }

    #[test]
    fn keep_newest_drops_the_oldest() {
        let mut m = Message::from_hops(&[hop(1), hop(2), hop(3), hop(4)]).unwrap();
        assert_eq!(m.keep_newest(5), 0);
        assert_eq!(m.len(), 4);
        assert_eq!(m.keep_newest(2), 2);
        assert_eq!(m.hops(), &[hop(3), hop(4)]);
        assert_eq!(m.keep_newest(0), 2);
        assert!(m.is_empty());
    }

    #[test]
    fn from_hops_rejects_empty_and_too_long() {
        assert!(Message::from_hops(&[]).is_none());
        assert!(Message::from_hops(&[hop(1); MAX_HOPS + 1]).is_none());
        assert_eq!(
            Message::from_hops(&[hop(1); MAX_HOPS]).unwrap().len(),
            MAX_HOPS
        );
    }

    #[test]
    fn the_closed_bit_is_bit_7_of_the_ray_byte_and_extension_keeps_it() {
        // Robot 9 (reading 3, for LEFT) alone on an empty LEFT side: 0x80 | 1 << 4 | 2.
        let mut ray = Ray::single(Sector::LEFT, 2, Level(3), Some(Sector::LEFT)).unwrap();
        ray.closed = true;
        let mut m = Message::initiate(hop(3));
        m.set_ray(Some(ray));
        let mut buf = [0u8; PAYLOAD_BUDGET];
        let out = postcard::to_slice(&m, &mut buf).unwrap();
        assert_eq!(out, &[0x51, 3, 0, 0x92, 1, 3, 0, 9, 0, 0, 0, 1]);
        assert_eq!(postcard::from_bytes::<Message>(out).unwrap(), m);
        // The same ray open: only bit 7 differs.
        ray.closed = false;
        m.set_ray(Some(ray));
        let open = postcard::to_slice(&m, &mut buf).unwrap();
        assert_eq!(open[3], 0x12);
        // Extending keeps the bit either way.
        assert!(!ray.extended(Level(1), None).closed);
        ray.closed = true;
        assert!(ray.extended(Level(1), None).closed);
        // Bits 6-4 are still the sector: closed with sector 2 of K = 2 is refused.
        let mut bad = [0x51, 3, 0, 0xA2, 1, 3, 0, 9, 0, 0, 0, 1];
        assert!(postcard::from_bytes::<Message>(&bad).is_err());
        bad[3] = 0x82;
        assert_eq!(
            postcard::from_bytes::<Message>(&bad)
                .unwrap()
                .ray()
                .unwrap()
                .sector,
            Sector::RIGHT
        );
    }

    #[test]
    fn preference_is_one_byte_on_the_wire() {
        let h = Hop {
            reading: Level(7),
            pref: Some(Sector::LEFT),
            tag: Tag::default(),
        };
        let mut buf = [0u8; 4];
        let out = postcard::to_slice(&h, &mut buf).unwrap();
        assert_eq!(out, &[7, 2]);
        let none = postcard::to_slice(&hop(9), &mut buf).unwrap();
        assert_eq!(none, &[9, 0]);
        assert_eq!(postcard::from_bytes::<Hop>(&[9, 0]).unwrap(), hop(9));
        assert!(postcard::from_bytes::<Hop>(&[9, 9]).is_err());
        assert!(postcard::from_bytes::<Hop>(&[9, 255]).is_err());
    }

    #[test]
    fn the_tag_shares_the_preference_byte() {
        let mut buf = [0u8; 4];
        for (tag, pref, byte) in [
            (0, None, 0x00),
            (1, None, 0x10),
            (5, Some(Sector::LEFT), 0x52),
            (15, Sector::new(7), 0xF8),
            (15, None, 0xF0),
        ] {
            let h = Hop {
                reading: Level(0x73),
                pref,
                tag: Tag::new(tag).unwrap(),
            };
            let out = postcard::to_slice(&h, &mut buf).unwrap();
            assert_eq!(out, &[0x73, byte], "{h:?}");
            assert_eq!(postcard::from_bytes::<Hop>(out).unwrap(), h);
        }
        // Every preference nibble above 8 is refused, whatever the tag; no byte panics.
        for byte in 0..=255u8 {
            let got = postcard::from_bytes::<Hop>(&[1, byte]);
            assert_eq!(got.is_ok(), byte & 0x0F <= 8, "{byte:#04x}");
            if let Ok(h) = got {
                assert_eq!(h.tag.index(), byte >> 4);
            }
        }
    }

    #[test]
    fn tags_are_ids_modulo_sixteen() {
        assert_eq!(Tag::from_id(0), Tag::new(0).unwrap());
        assert_eq!(Tag::from_id(15).index(), 15);
        assert_eq!(Tag::from_id(16).index(), 0);
        assert_eq!(Tag::from_id(u16::MAX).index(), 15);
        assert_eq!(Tag::new(16), None);
        let m = Message::from_hops(&[
            hop(1),
            Hop {
                tag: Tag::from_id(3),
                ..hop(2)
            },
        ])
        .unwrap();
        assert!(m.has_tag(Tag::from_id(3)) && m.has_tag(Tag::default()));
        assert!(!m.has_tag(Tag::from_id(4)));
    }
}
