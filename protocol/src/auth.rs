//! The swarm key and the MAC of authenticated frames.
//!
//! A swarm may share one secret [`SwarmKey`] (128 bits). With a key, every frame carries a
//! 4-byte tag in place of the CRC: the first [`TAG_LEN`] bytes of SipHash-2-4 (keyed with the
//! swarm key) of the frame's payload, in SipHash's own little-endian byte order. A receiver
//! holding the key drops every frame whose tag does not match ([`FrameError::BadMac`]): frames
//! from robots without the key or with another one, forgeries, and frames corrupted on the way
//! (the tag is also the frame check). [`crate::frame`] has the keyed encoder and deframer
//! ([`encode_keyed`], [`Deframer::with_key`]); `docs/protocol.md` ("Authenticated frames") the
//! layout, the cost in hops, the forgery odds and what a MAC does not protect against.
//!
//! **Why SipHash-2-4.** It is a pseudorandom function designed for short inputs under a
//! 128-bit key, so a keyed MAC for them; a frame's payload is 3 to 23 bytes, which SipHash
//! hashes in one to three 8-byte rounds. It needs no tables and little code on a 32-bit MCU.
//! Truncating a PRF's output to 32 bits keeps it a MAC with forgery odds of 2⁻³² per try.
//!
//! [`FrameError::BadMac`]: crate::frame::FrameError::BadMac
//! [`encode_keyed`]: crate::frame::encode_keyed
//! [`Deframer::with_key`]: crate::frame::Deframer::with_key

use core::fmt;
use core::str::FromStr;

#[cfg(feature = "keyed")]
use siphasher::sip::SipHasher24;

/// Bytes of a swarm key (128 bits).
pub const KEY_LEN: usize = 16;
/// Bytes of the MAC tag a keyed frame carries in place of the CRC (32 bits).
pub const TAG_LEN: usize = 4;
/// Hex digits of a swarm key written out ([`SwarmKey::from_hex`]).
pub const KEY_HEX_LEN: usize = 2 * KEY_LEN;

/// A frame's MAC tag (not to be confused with a robot's [`crate::message::Tag`]).
pub type MacTag = [u8; TAG_LEN];

/// The secret every robot of a swarm shares: 128 bits keying SipHash-2-4.
///
/// Its `Debug` (and `defmt::Format`) output never shows the key. Serde (the HIL link's `Key`
/// message) writes its 16 bytes as they are.
#[derive(Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct SwarmKey([u8; KEY_LEN]);

impl SwarmKey {
    /// A key from its 16 bytes.
    pub const fn new(bytes: [u8; KEY_LEN]) -> Self {
        SwarmKey(bytes)
    }

    /// The key's 16 bytes.
    pub const fn to_bytes(&self) -> [u8; KEY_LEN] {
        self.0
    }

    /// Parses a key written as exactly [`KEY_HEX_LEN`] (32) hex digits, either case, first byte
    /// first: `000102…0f` is the key whose bytes are 0, 1, 2, … 15. A `const fn`, so a key given
    /// at build time is checked at build time.
    ///
    /// # Errors
    /// [`KeyError::NotHex`] naming the first character that is not a hex digit, else
    /// [`KeyError::Length`] if there are not 32 digits.
    pub const fn from_hex(hex: &str) -> Result<Self, KeyError> {
        let s = hex.as_bytes();
        let mut i = 0;
        while i < s.len() {
            if hex_digit(s[i]).is_none() {
                return Err(KeyError::NotHex { position: i + 1 });
            }
            i += 1;
        }
        if s.len() != KEY_HEX_LEN {
            return Err(KeyError::Length { digits: s.len() });
        }
        let mut key = [0u8; KEY_LEN];
        let mut k = 0;
        while k < KEY_LEN {
            // Both digits were checked above.
            let (Some(hi), Some(lo)) = (hex_digit(s[2 * k]), hex_digit(s[2 * k + 1])) else {
                return Err(KeyError::NotHex {
                    position: 2 * k + 1,
                });
            };
            key[k] = hi << 4 | lo;
            k += 1;
        }
        Ok(SwarmKey(key))
    }

    /// The tag of `payload` under this key: the first [`TAG_LEN`] bytes of the little-endian
    /// SipHash-2-4 output.
    #[cfg(feature = "keyed")]
    pub fn tag(&self, payload: &[u8]) -> MacTag {
        let h = SipHasher24::new_with_key(&self.0)
            .hash(payload)
            .to_le_bytes();
        [h[0], h[1], h[2], h[3]]
    }

    /// True if `tag` is `payload`'s tag under this key. Compares every byte whatever the
    /// first difference (no early exit).
    #[cfg(feature = "keyed")]
    pub fn verify(&self, payload: &[u8], tag: &[u8]) -> bool {
        let expected = self.tag(payload);
        tag.len() == TAG_LEN
            && expected
                .iter()
                .zip(tag)
                .fold(0u8, |acc, (a, b)| acc | (a ^ b))
                == 0
    }
}

const fn hex_digit(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'a'..=b'f' => Some(c - b'a' + 10),
        b'A'..=b'F' => Some(c - b'A' + 10),
        _ => None,
    }
}

impl fmt::Debug for SwarmKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SwarmKey(<secret>)")
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for SwarmKey {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "SwarmKey(<secret>)")
    }
}

impl FromStr for SwarmKey {
    type Err = KeyError;

    fn from_str(s: &str) -> Result<Self, KeyError> {
        SwarmKey::from_hex(s)
    }
}

/// Why text is not a swarm key ([`SwarmKey::from_hex`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum KeyError {
    /// A character is not a hex digit.
    NotHex {
        /// Its position, counting from 1 (in bytes).
        position: usize,
    },
    /// All hex digits, but not [`KEY_HEX_LEN`] of them.
    Length {
        /// How many there were.
        digits: usize,
    },
}

impl fmt::Display for KeyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KeyError::NotHex { position } => write!(
                f,
                "a swarm key is {KEY_HEX_LEN} hex digits (0-9, a-f); character {position} is not one"
            ),
            KeyError::Length { digits } => write!(
                f,
                "a swarm key is {KEY_HEX_LEN} hex digits (128 bits), not {digits}"
            ),
        }
    }
}

impl core::error::Error for KeyError {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    fn seq_key() -> SwarmKey {
        SwarmKey::new(core::array::from_fn(|i| i as u8))
    }

    /// The SipHash paper's reference vectors (Aumasson and Bernstein, appendix A; the
    /// reference implementation's `vectors.h`): key 00..0f, message 00..(n-1).
    #[test]
    #[cfg(feature = "keyed")]
    fn siphash_2_4_reference_vectors() {
        let k = seq_key();
        let msg: [u8; 64] = core::array::from_fn(|i| i as u8);
        let h = |n: usize| SipHasher24::new_with_key(&k.to_bytes()).hash(&msg[..n]);
        assert_eq!(h(0), 0x726f_db47_dd0e_0e31);
        assert_eq!(h(15), 0xa129_ca61_49be_45e5);
        // The tag is the first four bytes of the output, little-endian.
        assert_eq!(k.tag(&[]), [0x31, 0x0e, 0x0e, 0xdd]);
        assert_eq!(k.tag(&msg[..15]), [0xe5, 0x45, 0xbe, 0x49]);
    }

    #[test]
    #[cfg(feature = "keyed")]
    fn verify_accepts_only_the_tag() {
        let k = seq_key();
        let t = k.tag(b"abc");
        assert!(k.verify(b"abc", &t));
        assert!(!k.verify(b"abd", &t));
        assert!(!k.verify(b"abc", &t[..3]));
        let mut bad = t;
        bad[3] ^= 0x80;
        assert!(!k.verify(b"abc", &bad));
        let other = SwarmKey::new([7; KEY_LEN]);
        assert!(!other.verify(b"abc", &t));
    }

    #[test]
    fn hex_keys() {
        let k = SwarmKey::from_hex("000102030405060708090a0B0c0D0e0F").unwrap();
        assert_eq!(k, seq_key());
        assert_eq!("000102030405060708090a0b0c0d0e0f".parse(), Ok(seq_key()));
        assert_eq!(
            SwarmKey::from_hex("0x0102030405060708090a0b0c0d0e0f"),
            Err(KeyError::NotHex { position: 2 })
        );
        assert_eq!(
            SwarmKey::from_hex("00112233"),
            Err(KeyError::Length { digits: 8 })
        );
        assert_eq!(SwarmKey::from_hex(""), Err(KeyError::Length { digits: 0 }));
        assert_eq!(
            SwarmKey::from_hex("é0102030405060708090a0b0c0d0e0f"),
            Err(KeyError::NotHex { position: 1 })
        );
        let e = SwarmKey::from_hex("0011").unwrap_err().to_string();
        assert!(e.contains("32 hex digits") && e.contains("not 4"), "{e}");
        let e = SwarmKey::from_hex("zz").unwrap_err().to_string();
        assert!(e.contains("character 1"), "{e}");
        // Whitespace anywhere is not a hex digit (docs/protocol.md §10).
        assert_eq!(
            SwarmKey::from_hex(" 000102030405060708090a0b0c0d0e0f"),
            Err(KeyError::NotHex { position: 1 })
        );
        assert_eq!(
            SwarmKey::from_hex("00010203 0405060708090a0b0c0d0e0f"),
            Err(KeyError::NotHex { position: 9 })
        );
        assert_eq!(
            SwarmKey::from_hex("000102030405060708090a0b0c0d0e0f\n"),
            Err(KeyError::NotHex { position: 33 })
        );
    }

    #[test]
    fn debug_hides_the_key() {
        let s = std::format!("{:?}", SwarmKey::new([0xAB; KEY_LEN]));
        assert_eq!(s, "SwarmKey(<secret>)");
    }

    // Checked at compile time: a bad build-time key fails the build.
    const _: SwarmKey = match SwarmKey::from_hex("ffeeddccbbaa99887766554433221100") {
        Ok(k) => k,
        Err(_) => panic!("bad key"),
    };
}
