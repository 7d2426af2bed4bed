//! `message_decode`: decoding a [`Message`] from arbitrary bytes, four ways.
//!
//! 1. **postcard**, as the frame module does (`postcard::take_from_bytes::<Message>`): never
//!    panics; accepts exactly what the independent format-2 parser
//!    [`crate::reference::parse_prefix`] accepts (header `0b001r_nnnn` with 1..=12 hops,
//!    preference nibbles 0..=8, a ray with 2..=8 sectors, sector < sectors, robots ≥ 1, votes
//!    ≤ robots, at most 25 bytes in all), gives the same message and uses the same bytes,
//!    which are exactly the layout [`crate::reference::payload_of`] writes; the message
//!    serialises back to them and re-frames to itself. A lone [`Hop`] reads back exactly when
//!    its preference byte's low nibble is 0..=8 (the high nibble is the robot's tag), and
//!    keeps both nibbles.
//! 2. **`decode_frame`** on the raw bytes: never panics, a message passes
//!    [`crate::reference::check_decoded`].
//! 3. **The bytes as a payload** with a correct frame check (CRC, COBS, XOR, `ss` around):
//!    `decode_frame` must say exactly what §2.2 says: `TooShort` for no payload, `TooLong` for a
//!    body over BODY_MAX, the message if the independent parser reads one using every byte,
//!    `Undecodable` otherwise (a format-1 payload among them). This reaches the CRC-valid paths
//!    random bytes almost never do.
//! 4. **The bytes as a body** (every `s` removed, `ss` around): `decode_frame` must agree with
//!    the independent body decoder [`crate::reference::decode_body`] (or say `Incomplete` for
//!    an empty body).

use protocol::frame::{self, BODY_MAX, DELIMITER, FrameError};
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
    let model = reference::parse_prefix(data);
    match (postcard::take_from_bytes::<Message>(data), model) {
        (Ok((m, rest)), Ok((expected, used))) => {
            assert_eq!(
                m, expected,
                "postcard and the model read {data:02x?} differently"
            );
            assert!(data.ends_with(rest));
            assert_eq!(data.len() - rest.len(), used, "bytes used of {data:02x?}");
            assert!(!m.is_empty() && m.len() <= MAX_HOPS);
            let layout = reference::payload_of(&m);
            assert_eq!(&data[..used], layout.as_slice());
            let mut buf = [0u8; 64];
            let out = postcard::to_slice(&m, &mut buf).expect("a message serialises");
            assert_eq!(out, layout.as_slice(), "serialised layout of {m:?}");
            assert_eq!(postcard::from_bytes::<Message>(out).as_ref(), Ok(&m));
            reference::check_decoded(&m);
        }
        (Err(_), Err(_)) => {}
        (got, model) => panic!("{data:02x?}: postcard {got:?}, model {model:?}"),
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
        // Every payload is canonical: the protocol's encoder gives these very bytes.
        assert_eq!(frame::encode(m).expect("encodes").as_slice(), f.as_slice());
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
    use crate::reference::{four_hops, one_hop, payload_of, ray_four};

    #[test]
    fn payload_expectations() {
        assert_eq!(expected_for_payload(&[]), Err(FrameError::TooShort));
        assert_eq!(expected_for_payload(&[0x41, 1, 0]), Ok(one_hop()));
        assert_eq!(
            expected_for_payload(&[0x21, 1, 0]),
            Err(FrameError::Undecodable)
        );
        assert_eq!(
            expected_for_payload(&payload_of(&four_hops())),
            Ok(four_hops())
        );
        assert_eq!(
            expected_for_payload(&payload_of(&ray_four())),
            Ok(ray_four())
        );
        for bad in [
            &[0x22u8, 1, 0][..],
            &[0x20],
            &[0x21, 0, 9],
            &[1, 1, 0],
            &[0x04, 1, 1, 0, 2, 0, 2, 0, 0],
            &[0x21, 1, 0, 0],
        ] {
            assert_eq!(
                expected_for_payload(bad),
                Err(FrameError::Undecodable),
                "{bad:02x?}"
            );
        }
        assert_eq!(expected_for_payload(&[0; 26]), Err(FrameError::TooLong));
        for data in [&[0x21u8, 1, 0][..], &[2, 1, 0], &[], &[0x73; 30]] {
            check(data);
        }
        check(&payload_of(&ray_four()));
    }
}
