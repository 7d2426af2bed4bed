//! `message_decode`: decoding a [`Message`] from arbitrary bytes, four ways.
//!
//! 1. **postcard**, as the frame module does (`postcard::take_from_bytes::<Message>`): never
//!    panics; a result has at most MAX_HOPS hops, consumed at least `1 + 2·len` bytes (exactly
//!    the §1.2 layout when the count byte is canonical, i.e. below 0x80), serialises back to the
//!    §1.2 layout and reads back equal; an empty one is refused by `encode`, any other
//!    re-frames to itself. A lone [`Hop`] reads back exactly when its preference byte's low
//!    nibble is 0..=8 (the high nibble is the robot's tag), and keeps both nibbles.
//! 2. **`decode_frame`** on the raw bytes: never panics, a message passes
//!    [`crate::reference::check_decoded`].
//! 3. **The bytes as a payload** with a correct frame check (CRC, COBS, XOR, `ss` around):
//!    `decode_frame` must say exactly what §2.2 says: `TooShort` for no payload, `TooLong` for a
//!    body over BODY_MAX, the message if postcard reads one using every byte with ≥ 1 hop,
//!    `Undecodable` otherwise. This reaches the CRC-valid paths random bytes almost never do.
//! 4. **The bytes as a body** (every `s` removed, `ss` around): `decode_frame` must agree with
//!    the independent body decoder [`crate::reference::decode_body`] (or say `Incomplete` for
//!    an empty body).

use protocol::frame::{self, BODY_MAX, DELIMITER, EncodeError, FrameError};
use protocol::{Hop, MAX_HOPS, MAX_SECTORS, Message};

use crate::reference;

/// The check of this target.
pub fn check(data: &[u8]) {
    postcard_path(data);

    if let Ok(m) = frame::decode_frame(data) {
        reference::check_decoded(&m);
    }

    as_payload(data);
    as_body(data);
}

fn postcard_path(data: &[u8]) {
    if let Ok((m, rest)) = postcard::take_from_bytes::<Message>(data) {
        assert!(m.len() <= MAX_HOPS);
        assert!(data.ends_with(rest));
        let consumed = data.len() - rest.len();
        let layout = reference::payload_of(&m);
        assert!(consumed >= layout.len(), "{consumed} bytes for {m:?}");
        if data[0] < 0x80 {
            assert_eq!(&data[..consumed], layout.as_slice());
        }
        let mut buf = [0u8; 64];
        let out = postcard::to_slice(&m, &mut buf).expect("a message serialises");
        assert_eq!(out, layout.as_slice(), "serialised layout of {m:?}");
        assert_eq!(postcard::from_bytes::<Message>(out).as_ref(), Ok(&m));
        if m.is_empty() {
            assert_eq!(frame::encode(&m), Err(EncodeError::Empty));
        } else {
            reference::check_decoded(&m);
        }
    }
    match postcard::take_from_bytes::<Hop>(data) {
        Ok((h, _)) => {
            assert_eq!(h.reading.0, data[0]);
            assert!(data[1] & 0x0F <= MAX_SECTORS as u8);
            assert_eq!(reference::pref_byte(&h), data[1]);
        }
        Err(_) if data.len() >= 2 => {
            assert!(
                data[1] & 0x0F > MAX_SECTORS as u8,
                "hop {:02x?} refused",
                &data[..2]
            );
        }
        Err(_) => {}
    }
}

/// What `decode_frame` must give for `payload` framed with a correct frame check.
pub fn expected_for_payload(payload: &[u8]) -> Result<Message, FrameError> {
    if payload.is_empty() {
        Err(FrameError::TooShort)
    } else if reference::frame_payload(payload).len() - 4 > BODY_MAX {
        Err(FrameError::TooLong)
    } else {
        reference::decode_payload(payload)
    }
}

fn as_payload(data: &[u8]) {
    let f = reference::frame_payload(data);
    let got = frame::decode_frame(&f);
    assert_eq!(got, expected_for_payload(data), "payload {data:02x?}");
    if let Ok(m) = &got {
        reference::check_decoded(m);
        if data[0] < 0x80 {
            // A canonical payload: the protocol's encoder gives these very bytes.
            assert_eq!(frame::encode(m).expect("encodes").as_slice(), f.as_slice());
        }
    }
}

fn as_body(data: &[u8]) {
    let body: Vec<u8> = data.iter().copied().filter(|&b| b != DELIMITER).collect();
    let mut f = vec![DELIMITER, DELIMITER];
    f.extend_from_slice(&body);
    f.extend_from_slice(&[DELIMITER, DELIMITER]);
    let expected = if body.is_empty() {
        Err(FrameError::Incomplete)
    } else {
        reference::decode_body(&body)
    };
    assert_eq!(frame::decode_frame(&f), expected, "body {body:02x?}");
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{four_hops, one_hop, payload_of};

    #[test]
    fn payload_expectations() {
        assert_eq!(expected_for_payload(&[]), Err(FrameError::TooShort));
        assert_eq!(expected_for_payload(&[1, 1, 0]), Ok(one_hop()));
        assert_eq!(
            expected_for_payload(&payload_of(&four_hops())),
            Ok(four_hops())
        );
        assert_eq!(
            expected_for_payload(&[2, 1, 0]),
            Err(FrameError::Undecodable)
        );
        assert_eq!(expected_for_payload(&[0]), Err(FrameError::Undecodable));
        assert_eq!(
            expected_for_payload(&[1, 0, 9]),
            Err(FrameError::Undecodable)
        );
        assert_eq!(expected_for_payload(&[0; 26]), Err(FrameError::TooLong));
        for data in [&[1u8, 1, 0][..], &[2, 1, 0], &[], &[0x73; 30]] {
            check(data);
        }
    }
}
