//! The byte format the structured targets read, and a writer for it (to build seeds).
//!
//! Structured targets read their input with [`arbitrary::Unstructured`], through the
//! primitives below only: an integer takes its size in bytes, little-endian (zero-filled once
//! the input runs out), a `bool` is one byte's lowest bit, an `Option<T>` is a `bool` and then
//! `T` if it is `true`, and a list is a `bool` ("one more") before every element and a `false`
//! at its end, as `Unstructured::arbitrary_iter` reads it. [`Writer`] writes exactly that, so
//! the seed generator can spell out an input value by value; `tests/corpus.rs` checks that
//! every seed reads back as the value it was written from.

use arbitrary::{Arbitrary, Unstructured};

/// Reads one `T`; an exhausted input gives the zero-filled value, a failed read the default.
pub fn get<'a, T: Arbitrary<'a> + Default>(u: &mut Unstructured<'a>) -> T {
    u.arbitrary().unwrap_or_default()
}

/// Reads list elements with `item` while the input says "one more", at most `max` of them:
/// a "one more" after the `max`-th element ends the list like an end marker (the bytes of the
/// element it announced are read by the next field instead). This keeps every input's work
/// bounded, and a list of exactly `max` elements written with its end marker reads back whole.
pub fn list<'a, T>(
    u: &mut Unstructured<'a>,
    max: usize,
    mut item: impl FnMut(&mut Unstructured<'a>) -> T,
) -> Vec<T> {
    let mut out = Vec::new();
    while get::<bool>(u) && out.len() < max {
        out.push(item(u));
    }
    out
}

/// Builds an input in the format above.
#[derive(Clone, Debug, Default)]
pub struct Writer {
    bytes: Vec<u8>,
}

impl Writer {
    /// An empty input.
    pub fn new() -> Self {
        Self::default()
    }

    /// One byte.
    pub fn u8(&mut self, x: u8) -> &mut Self {
        self.bytes.push(x);
        self
    }

    /// Two bytes, little-endian.
    pub fn u16(&mut self, x: u16) -> &mut Self {
        self.bytes.extend_from_slice(&x.to_le_bytes());
        self
    }

    /// Four bytes, little-endian.
    pub fn u32(&mut self, x: u32) -> &mut Self {
        self.bytes.extend_from_slice(&x.to_le_bytes());
        self
    }

    /// Eight bytes, little-endian.
    pub fn u64(&mut self, x: u64) -> &mut Self {
        self.bytes.extend_from_slice(&x.to_le_bytes());
        self
    }

    /// A float as its bits.
    pub fn f32(&mut self, x: f32) -> &mut Self {
        self.u32(x.to_bits())
    }

    /// A `bool`.
    pub fn bool(&mut self, b: bool) -> &mut Self {
        self.u8(u8::from(b))
    }

    /// "One more element" before a list element.
    pub fn item(&mut self) -> &mut Self {
        self.bool(true)
    }

    /// The end of a list.
    pub fn end(&mut self) -> &mut Self {
        self.bool(false)
    }

    /// Raw bytes (a list's elements are written with [`item`](Self::item) each instead).
    pub fn raw(&mut self, bytes: &[u8]) -> &mut Self {
        self.bytes.extend_from_slice(bytes);
        self
    }

    /// A list of bytes: "one more" and the byte, for each, then the end.
    pub fn byte_list(&mut self, bytes: &[u8]) -> &mut Self {
        for &b in bytes {
            self.item().u8(b);
        }
        self.end()
    }

    /// The input built so far.
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// The finished input.
    pub fn finish(&mut self) -> Vec<u8> {
        core::mem::take(&mut self.bytes)
    }
}

/// Reads a list of bytes written by [`Writer::byte_list`].
pub fn byte_list(u: &mut Unstructured<'_>, max: usize) -> Vec<u8> {
    list(u, max, get::<u8>)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writer_matches_unstructured() {
        let bytes = Writer::new()
            .u8(7)
            .u16(0x1234)
            .u32(0xDEAD_BEEF)
            .u64(u64::MAX - 3)
            .f32(-1.5)
            .bool(true)
            .byte_list(&[1, 2, 3])
            .finish();
        let mut u = Unstructured::new(&bytes);
        assert_eq!(get::<u8>(&mut u), 7);
        assert_eq!(get::<u16>(&mut u), 0x1234);
        assert_eq!(get::<u32>(&mut u), 0xDEAD_BEEF);
        assert_eq!(get::<u64>(&mut u), u64::MAX - 3);
        assert_eq!(u.arbitrary::<f32>().unwrap(), -1.5);
        assert!(get::<bool>(&mut u));
        assert_eq!(byte_list(&mut u, 10), [1, 2, 3]);
        assert!(u.is_empty());
        // Exhausted input: zeros, `false`, empty lists.
        assert_eq!(get::<u32>(&mut u), 0);
        assert!(!get::<bool>(&mut u));
        assert!(byte_list(&mut u, 10).is_empty());
    }

    #[test]
    fn list_stops_at_its_bound() {
        let bytes = Writer::new().byte_list(&[9; 5]).finish();
        let mut u = Unstructured::new(&bytes);
        assert_eq!(byte_list(&mut u, 3), [9, 9, 9]);
        // The 4th "one more" ended the list; its element is left for the next reader.
        assert_eq!(get::<u8>(&mut u), 9);
        // Exactly `max` elements and the end marker: all read, nothing left over.
        let bytes = Writer::new().byte_list(&[1, 2]).u8(7).finish();
        let mut u = Unstructured::new(&bytes);
        assert_eq!(byte_list(&mut u, 2), [1, 2]);
        assert_eq!(get::<u8>(&mut u), 7);
    }

    #[test]
    fn option_is_a_bool_then_the_value() {
        let bytes = Writer::new().bool(true).u8(5).bool(false).finish();
        let mut u = Unstructured::new(&bytes);
        assert_eq!(u.arbitrary::<Option<u8>>().unwrap(), Some(5));
        assert_eq!(u.arbitrary::<Option<u8>>().unwrap(), None);
    }
}
