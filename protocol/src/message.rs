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
use serde::{Deserialize, Serialize};

use crate::direction::Sector;

/// Hops per message: the most that fit a 32-byte frame in the worst case (12).
pub const MAX_HOPS: usize = 12;

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

/// What one relaying robot appended: its reading and its preferred direction (if any).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hop {
    /// The robot's sensor reading.
    pub reading: Level,
    /// The robot's preferred direction when it relayed; `None` while it has none. On the wire
    /// one byte: 0 for none, `sector + 1` otherwise.
    #[serde(with = "pref_byte")]
    pub pref: Option<Sector>,
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

/// Serde for `Option<Sector>` as one byte: 0 = none, `index + 1` otherwise.
mod pref_byte {
    use serde::de::{Error, Unexpected};
    use serde::{Deserialize, Deserializer, Serializer};

    use crate::direction::Sector;

    /// Serde's "expected" text for a bad preference byte.
    const PREF_EXPECTED: &str = "a preference byte 0..=8 (0 = none, sector + 1)";

    pub fn serialize<S: Serializer>(pref: &Option<Sector>, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(pref.map_or(0, |p| p.index() + 1))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Sector>, D::Error> {
        match u8::deserialize(d)? {
            0 => Ok(None),
            b => Sector::new(b - 1).map(Some).ok_or_else(|| {
                D::Error::invalid_value(Unexpected::Unsigned(u64::from(b)), &PREF_EXPECTED)
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hop(r: u8) -> Hop {
        Hop {
            reading: Level(r),
            pref: None,
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
}
