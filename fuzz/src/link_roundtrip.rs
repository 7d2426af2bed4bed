//! `link_roundtrip`: arbitrary [`LinkMsg`]s through `firmware::hil::encode` and back through
//! `LinkDecoder`, whole, after garbage, truncated and corrupted.
//!
//! Input (format in [`crate::input`]): a message ([`link_ref::read_msg`]: a variant byte modulo
//! 10, then its fields; a `Hello` of any version, chunks of 0..=32 bytes), then garbage (a byte
//! list of at most [`GARBAGE_MAX`] bytes, 0x00 included), a cut position, a byte position and
//! an XOR mask. Checks:
//!
//! - `encode` into [`LINK_FRAME_MAX`] bytes gives the model's frame: COBS of the canonical
//!   payload (at most [`PAYLOAD_MAX`] bytes) and its CRC, then 0x00, the only 0x00, at most
//!   [`LINK_FRAME_MAX`] bytes; into a buffer one byte short (and into the cut length, if
//!   shorter) it is `Err(Encode)`, into exactly the frame's length the same frame;
//! - a fresh decoder reads the frame back as the message, or as `UnknownVersion(v)` for a
//!   `Hello` of version `v` ≠ [`LINK_VERSION`], counted once;
//! - resynchronisation: garbage then 0x00 then the frame; the frame cut short then 0x00 then
//!   the frame; the frame cut short then the frame twice (no 0x00 between); the frame with one
//!   body byte corrupted (it may become a 0x00) then the frame: each stream decodes exactly as
//!   the model ([`link_decode::push_both`], counters after every byte), and its last result is
//!   the frame's.

use arbitrary::Unstructured;
use firmware::hil::{
    LINK_FRAME_MAX, LINK_VERSION, LinkDecoder, LinkError, LinkMsg, PAYLOAD_MAX, encode,
};

use crate::input::{Writer, byte_list, get};
use crate::link_decode::push_both;
use crate::link_ref::{self, ModelDecoder};

/// Garbage bytes read at most (more than two frames).
pub const GARBAGE_MAX: usize = 3 * LINK_FRAME_MAX;

/// A parsed input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The message.
    pub msg: LinkMsg,
    /// Bytes before it.
    pub garbage: Vec<u8>,
    /// Where to cut the frame (modulo its length).
    pub cut: u8,
    /// Which body byte to corrupt (modulo the body length).
    pub at: u8,
    /// The corruption (an XOR mask; 0 is replaced by 1).
    pub mask: u8,
}

impl Input {
    /// Reads an input.
    pub fn read(data: &[u8]) -> Input {
        let mut u = Unstructured::new(data);
        Input {
            msg: link_ref::read_msg(&mut u),
            garbage: byte_list(&mut u, GARBAGE_MAX),
            cut: get(&mut u),
            at: get(&mut u),
            mask: get(&mut u),
        }
    }

    /// The bytes [`read`](Self::read) turns into this input.
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        link_ref::write_msg(&mut w, &self.msg);
        w.byte_list(&self.garbage)
            .u8(self.cut)
            .u8(self.at)
            .u8(self.mask);
        w.finish()
    }
}

/// Runs `stream` through a fresh decoder and the model; returns the results.
fn decode(stream: &[u8]) -> Vec<Result<LinkMsg, LinkError>> {
    push_both(
        &mut LinkDecoder::new(),
        &mut ModelDecoder::default(),
        stream,
    )
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let input = Input::read(data);
    let msg = &input.msg;

    let payload = link_ref::payload_of(msg);
    assert!(
        payload.len() <= PAYLOAD_MAX,
        "{msg:?}: {} bytes",
        payload.len()
    );
    let want = link_ref::frame(msg);
    let mut buf = [0u8; LINK_FRAME_MAX];
    let frame = encode(msg, &mut buf).expect("every message fits LINK_FRAME_MAX");
    assert_eq!(frame, want.as_slice(), "{msg:?}");
    assert!(frame.len() <= LINK_FRAME_MAX);
    assert_eq!(frame.iter().position(|&b| b == 0), Some(frame.len() - 1));
    let frame = frame.to_vec();
    let n = frame.len();
    let mut exact = vec![0u8; n];
    assert_eq!(
        encode(msg, &mut exact).map(<[u8]>::to_vec),
        Ok(frame.clone())
    );
    for short in [n - 1, usize::from(input.cut) % n] {
        let mut buf = vec![0u8; short];
        assert_eq!(
            encode(msg, &mut buf),
            Err(LinkError::Encode),
            "{short} bytes"
        );
    }

    let expected = match msg {
        LinkMsg::Hello { version, .. } if *version != LINK_VERSION => {
            Err(LinkError::UnknownVersion(*version))
        }
        m => Ok(m.clone()),
    };
    let mut d = LinkDecoder::new();
    let got: Vec<_> = frame.iter().filter_map(|&b| d.push(b)).collect();
    assert_eq!(got, std::slice::from_ref(&expected));
    assert_eq!(d.stats().frames, u32::from(expected.is_ok()));
    assert_eq!(d.stats().errors(), u32::from(expected.is_err()));
    assert_eq!(d.stats().unknown_version, u32::from(expected.is_err()));

    let cut = &frame[..usize::from(input.cut) % n];
    let body = n - 1;
    let mut corrupted = frame.clone();
    corrupted[usize::from(input.at) % body] ^= input.mask.max(1);
    for stream in [
        [input.garbage.as_slice(), &[0], &frame].concat(),
        [cut, &[0], &frame].concat(),
        [cut, &frame, &frame].concat(),
        [corrupted.as_slice(), &frame].concat(),
    ] {
        let results = decode(&stream);
        assert_eq!(results.last(), Some(&expected), "{stream:02x?}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_reads_back_and_passes() {
        for msg in link_ref::every_kind() {
            let i = Input {
                msg,
                garbage: b"noise\0\x01\x02".to_vec(),
                cut: 3,
                at: 1,
                mask: 0x40,
            };
            let bytes = i.write();
            assert_eq!(Input::read(&bytes), i);
            check(&bytes);
        }
    }
}
