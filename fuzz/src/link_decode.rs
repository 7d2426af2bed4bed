//! `link_decode`: `firmware::hil::LinkDecoder::push`, byte by byte, against the independent
//! model of the link's framing ([`crate::link_ref`], `docs/hil.md` "Frame", "Messages",
//! "Errors").
//!
//! Input: a mode byte (modulo 3), then
//!
//! - **0, stream**: any bytes, pushed one by one;
//! - **1, payload**: the bytes as a payload with its correct CRC, framed by the model (COBS,
//!   0x00), so that the fuzzer reaches the postcard layer;
//! - **2, body**: the bytes with every 0x00 removed, as one body ending in 0x00.
//!
//! Checks, after every byte: the decoder's result is the model's (the message, or the error
//! kind: `TooLong` at the byte past [`LINK_FRAME_MAX`], `BadCobs`, `TooShort`, `BadCheck`,
//! `Undecodable`, `UnknownVersion(v)` for a `Hello` of a version `v` ≠ 2), never `Encode`, and
//! its `LinkStats` are the model's (each result counted once under its kind, `errors()` their
//! sum). Every message decoded re-encodes (`encode`, into [`LINK_FRAME_MAX`] bytes) to the
//! model's canonical frame, at most [`LINK_FRAME_MAX`] bytes with one 0x00 at its end, which
//! decodes back to it. Then recovery: after the stream and a 0x00 (which ends what the stream
//! left: at most one result), a whole frame decodes to exactly its message, counted once more
//! in `frames`; without the 0x00, a whole frame costs at most the frame it runs into, and the
//! one after it decodes. The decoder is a fixed-size value (no heap): memory is bounded by
//! construction.

use firmware::hil::{LINK_FRAME_MAX, LinkDecoder, LinkError, LinkMsg, encode};

use crate::link_ref::{self, ModelDecoder};

/// The mode bytes.
pub const STREAM: u8 = 0;
/// See the module documentation.
pub const PAYLOAD: u8 = 1;
/// See the module documentation.
pub const BODY: u8 = 2;

/// The byte stream an input stands for.
pub fn stream(data: &[u8]) -> Vec<u8> {
    let Some((&mode, rest)) = data.split_first() else {
        return Vec::new();
    };
    match mode % 3 {
        STREAM => rest.to_vec(),
        PAYLOAD => link_ref::frame_payload(rest),
        _ => {
            let mut s: Vec<u8> = rest.iter().copied().filter(|&b| b != 0).collect();
            s.push(0);
            s
        }
    }
}

/// Pushes `bytes` into both decoders, checking each result and the counters; returns the
/// results.
pub fn push_both(
    d: &mut LinkDecoder,
    m: &mut ModelDecoder,
    bytes: &[u8],
) -> Vec<Result<LinkMsg, LinkError>> {
    let mut out = Vec::new();
    for (i, &b) in bytes.iter().enumerate() {
        let got = d.push(b);
        let want = m.push(b);
        assert_eq!(got, want, "byte {i} ({b:#04x}) of {bytes:02x?}");
        assert_eq!(*d.stats(), m.stats, "counters after byte {i}");
        if let Some(r) = got {
            if let Ok(msg) = &r {
                check_message(msg);
            }
            out.push(r);
        }
    }
    let s = d.stats();
    assert_eq!(
        s.errors(),
        s.too_long + s.bad_cobs + s.too_short + s.bad_check + s.undecodable + s.unknown_version
    );
    out
}

/// What every decoded message satisfies: it encodes to the model's canonical frame (at most
/// LINK_FRAME_MAX bytes, one 0x00, at the end), which both decoders read back as it.
pub fn check_message(msg: &LinkMsg) {
    let mut buf = [0u8; LINK_FRAME_MAX];
    let f = encode(msg, &mut buf).expect("every message fits LINK_FRAME_MAX");
    assert_eq!(f, link_ref::frame(msg).as_slice(), "{msg:?}");
    assert!(f.len() <= LINK_FRAME_MAX);
    assert_eq!(f.iter().position(|&b| b == 0), Some(f.len() - 1));
    let mut d = LinkDecoder::new();
    let back: Vec<_> = f.iter().filter_map(|&b| d.push(b)).collect();
    assert_eq!(back, [Ok(msg.clone())]);
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let s = stream(data);
    let mut d = LinkDecoder::new();
    let mut m = ModelDecoder::default();
    push_both(&mut d, &mut m, &s);
    assert!(core::mem::size_of::<LinkDecoder>() <= LINK_FRAME_MAX + 64);

    // A 0x00 (it ends what the stream left, as the model says) and a whole frame: exactly its
    // message.
    let hb = LinkMsg::Heartbeat(s.len() as u32);
    let frame = link_ref::frame(&hb);
    let mut d2 = d.clone();
    let mut m2 = m.clone();
    assert!(push_both(&mut d2, &mut m2, &[0]).len() <= 1);
    let frames = d2.stats().frames;
    assert_eq!(push_both(&mut d2, &mut m2, &frame), [Ok(hb.clone())]);
    assert_eq!(d2.stats().frames, frames + 1);

    // No 0x00 first: the frame runs into what is left of the stream and gives at most one
    // result; the next frame is in step.
    let got = push_both(&mut d, &mut m, &frame);
    assert!(got.len() <= 1, "{got:?}");
    assert_eq!(push_both(&mut d, &mut m, &frame), [Ok(hb)]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_and_the_longest_body() {
        for msg in link_ref::every_kind() {
            let mut data = vec![PAYLOAD];
            data.extend_from_slice(&link_ref::payload_of(&msg));
            check(&data);
        }
        // A body of LINK_FRAME_MAX bytes is still decoded (as something), one more is TooLong.
        let mut m = ModelDecoder::default();
        let r = m.all(&[[1u8; LINK_FRAME_MAX].as_slice(), &[0]].concat());
        assert_eq!(r.len(), 1);
        assert_ne!(r[0], Err(LinkError::TooLong));
        let r = m.all(&[[1u8; LINK_FRAME_MAX + 1].as_slice(), &[0]].concat());
        assert_eq!(r, [Err(LinkError::TooLong)]);
        check(&[[STREAM].as_slice(), &[1; LINK_FRAME_MAX + 1]].concat());
    }
}
