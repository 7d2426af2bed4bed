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
//! along the wave's path) to make room for its own hop and its ray: 8 hops fit beside a
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

/// Version bits of the payload's first byte (its top three bits): `0b001` for this format.
///
/// The first format (before rays) began with the hop count as a varint, `1..=12`, whose top
/// three bits are zero: each format refuses the other's payloads as undecodable.
pub const FORMAT_BITS: u8 = 0x20;
/// Header bit set when a [`Ray`] follows the hops.
const RAY_BIT: u8 = 0x10;
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
/// are, the mean and variance of their readings, and how many prefer each sector. A robot
/// keeps the latest ray heard from each of its sectors and, when it transmits, extends the
/// ray of one sector by itself ([`Ray::extended`]). See `docs/protocol.md` §5.3.
///
/// On the wire `6 + sectors` bytes: `sector << 4 | sectors`, `robots`, `mean` (u16 LE),
/// `var` (u16 LE), then `votes[..sectors]`, one byte each.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ray {
    /// The direction summarised, in the sender's sectors (the swarm's common frame): the robots
    /// that lie in this sector of the sender, and the sender.
    pub sector: Sector,
    /// The sender's number of sectors K, `2..=8`; `votes` has this many entries.
    pub sectors: u8,
    /// Robots summarised, `1..=255` (saturating).
    pub robots: u8,
    /// Mean of their readings, fixed point 8.8 (`256` = 1.0).
    pub mean: u16,
    /// Population variance of their readings, in quarters (`4` = 1.0, at most 16256.25).
    pub var: u16,
    /// Robots preferring each sector (saturating); entries `sectors..` are zero.
    pub votes: [u8; MAX_SECTORS],
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
        let mut ray = Ray {
            sector,
            sectors,
            robots: 1,
            mean: u16::from(reading.0) << 8,
            var: 0,
            votes: [0; MAX_SECTORS],
        };
        ray.vote(pref);
        Some(ray)
    }

    /// This ray with one more robot, nearer than all it holds (the relaying robot): its reading
    /// joins the moments (Welford's update) and its preference the votes.
    pub fn extended(&self, reading: Level, pref: Option<Sector>) -> Ray {
        let n1 = f32::from(self.robots);
        let n = n1 + 1.0;
        let m1 = self.mean_level();
        let x = f32::from(reading);
        let m = m1 + (x - m1) / n;
        // Sum of squared deviations: n1 · var1 + (x − m1)(x − m).
        let m2 = n1 * self.variance() + (x - m1) * (x - m);
        let mut ray = Ray {
            robots: self.robots.saturating_add(1),
            mean: quantise(m * 256.0).min(MEAN_MAX),
            var: quantise(m2 / n * 4.0).min(VAR_MAX),
            ..*self
        };
        ray.vote(pref);
        ray
    }

    /// The mean reading, in [`Level`] units.
    pub fn mean_level(&self) -> f32 {
        f32::from(self.mean) / 256.0
    }

    /// The population variance of the readings, in [`Level`] units squared.
    pub fn variance(&self) -> f32 {
        f32::from(self.var) / 4.0
    }

    /// Bytes on the wire.
    pub fn encoded_len(&self) -> usize {
        6 + usize::from(self.sectors)
    }

    /// True if the fields are consistent: `2 <= sectors <= 8`, `sector < sectors`,
    /// `robots >= 1`, a mean of at most 255.0 (`0xFF00`) and a variance of at most 127.5²
    /// (65025 quarters), no vote beyond `sectors`, no sector with more votes than robots.
    pub fn is_valid(&self) -> bool {
        let k = usize::from(self.sectors);
        (2..=MAX_SECTORS).contains(&k)
            && usize::from(self.sector.index()) < k
            && self.robots >= 1
            && self.mean <= MEAN_MAX
            && self.var <= VAR_MAX
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

/// The largest mean a ray can hold: 255.0 in 8.8 fixed point.
const MEAN_MAX: u16 = 255 << 8;
/// The largest population variance of readings in `0..=255`: 127.5², in quarters.
const VAR_MAX: u16 = 65025;

/// `x` rounded to the nearest `u16`, saturating (NaN gives 0).
fn quantise(x: f32) -> u16 {
    // `as` saturates and maps NaN to 0.
    (x + 0.5) as u16
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
            t.serialize_element(&(r.sector.index() << 4 | r.sectors))?;
            t.serialize_element(&r.robots)?;
            t.serialize_element(&r.mean.to_le_bytes())?;
            t.serialize_element(&r.var.to_le_bytes())?;
            for v in r.votes.get(..k).unwrap_or(&[]) {
                t.serialize_element(v)?;
            }
        }
        t.end()
    }
}

/// Serde's "expected" text for a bad header.
const HEADER_EXPECTED: &str = "a header 0b001r_nnnn with 1..=12 hops";
/// Serde's "expected" text for a bad ray.
const RAY_EXPECTED: &str = "a ray with 2..=8 sectors, sector < sectors, robots >= votes >= 0";

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
            let mean: [u8; 2] = seq.next_element()?.ok_or_else(missing)?;
            let var: [u8; 2] = seq.next_element()?.ok_or_else(missing)?;
            let sectors = sk & 0x0F;
            let bad =
                || A::Error::invalid_value(Unexpected::Unsigned(u64::from(sk)), &RAY_EXPECTED);
            let mut ray = Ray {
                sector: Sector::new(sk >> 4).ok_or_else(bad)?,
                sectors,
                robots,
                mean: u16::from_le_bytes(mean),
                var: u16::from_le_bytes(var),
                votes: [0; MAX_SECTORS],
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
        // Longest possible tuple: header, MAX_HOPS hops, a ray of 4 + MAX_SECTORS elements.
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
