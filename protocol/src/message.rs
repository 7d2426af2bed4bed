//! The message a wave carries: the ordered list of hops, oldest (the initiator) first.
//!
//! Each hop is what one robot added while relaying: its sensor reading and its preferred
//! direction at that moment (the fused variant the aMussels ran, paper section 4). The last hop
//! is the neighbour the message was heard from; in a line, the hop `d` places from the end is the
//! robot `d` places away in the direction of reception.
//!
//! # Capacity and the full-message rule
//! A message holds at most [`MAX_HOPS`] hops: what fits the 32-byte frame in the worst case (see
//! [`crate::frame`], which proves it at compile time). A robot relaying a full message **drops
//! the oldest hop** (the one farthest away along the wave's path) before appending its own. The
//! wave keeps travelling, each receiver still sees the [`MAX_HOPS`] robots nearest to it along
//! the path with fresh preferences, and a message's diversity becomes that of a sliding window:
//! a horizon of [`MAX_HOPS`] hops. Relaying unchanged would freeze the far end of the path and
//! hide the neighbours; refusing to relay would stop the wave.

use heapless::Vec;
use serde::de::{Error as _, Unexpected};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::direction::Sector;

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

/// A wave's message: at least one hop, at most [`MAX_HOPS`].
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Message {
    hops: Vec<Hop, MAX_HOPS>,
}

impl Message {
    /// A new message holding just the initiator's hop.
    pub fn initiate(first: Hop) -> Self {
        let mut m = Message::default();
        m.push_evicting(first);
        m
    }

    /// A message from a list of hops, oldest first; `None` if the list is empty or too long.
    pub fn from_hops(hops: &[Hop]) -> Option<Self> {
        if hops.is_empty() {
            return None;
        }
        Vec::from_slice(hops).ok().map(|hops| Message { hops })
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
        self.hops.is_full()
    }

    /// Appends `hop`, dropping the oldest hop first if the message is full (the module's
    /// full-message rule). Returns the dropped hop, if any.
    pub fn push_evicting(&mut self, hop: Hop) -> Option<Hop> {
        push_evicting(&mut self.hops, hop)
    }

    /// Drops the oldest hops until at most `n` remain; returns how many were dropped.
    pub fn keep_newest(&mut self, n: usize) -> usize {
        let drop = self.hops.len().saturating_sub(n);
        if drop > 0 {
            self.hops.rotate_left(drop);
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

/// Appends to a bounded list, dropping the oldest element when it is full. Returns the dropped
/// element. A zero-capacity list stays empty.
pub(crate) fn push_evicting<T, const N: usize>(v: &mut Vec<T, N>, item: T) -> Option<T> {
    if N == 0 {
        return None;
    }
    let evicted = if v.is_full() { Some(v.remove(0)) } else { None };
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
