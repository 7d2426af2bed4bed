//! `keyed`: authenticated frames (`docs/protocol.md` §10): [`encode_keyed`],
//! [`decode_frame_keyed`], [`Deframer::with_key`] and [`SwarmKey`]'s text form.
//!
//! This is the only module that uses the keyed API; the other targets do not depend on it.
//!
//! Input: a mode byte (modulo 3), then
//!
//! - **0, stream**: a 16-byte key (zero-filled if short), then a `deframer` input (header, cut
//!   bytes, stream) for a keyed deframer. Every check of [`crate::deframer`] holds with the
//!   keyed counters (`bad_mac` in place of `bad_check`, which a keyed deframer never reports),
//!   frames of at least 10 bytes, `decode_frame_keyed` as the first result, and keyed frames for
//!   the recovery checks; every decoded message has 1..=KEYED_MAX_HOPS hops, a payload of at
//!   most KEYED_PAYLOAD_MAX (23) bytes, and re-encodes with `encode_keyed` to a frame that
//!   decodes back to it.
//! - **1, framing**: a 16-byte key, then a `roundtrip` input (hops, position, mask, ray): the
//!   newest 12 hops with the ray set (`set_ray`). No hop: `Empty`; a payload over
//!   KEYED_PAYLOAD_MAX (23 bytes: more than KEYED_MAX_HOPS hops, or a ray and too many hops):
//!   `TooManyHops`, and the message cut by `fit(23)` is checked instead; the frame is
//!   `9 + payload` ≤ FRAME_MAX bytes (`10 + 2·len` without a ray), `ss`…`ss` with no `s`
//!   inside, and is exactly the §10.1
//!   layout: the payload and the first 4 little-endian bytes of SipHash-2-4 (an independent
//!   implementation, [`siphash24`], checked against the SipHash paper's vector) over it. It
//!   decodes back under the key (also twice back to back through a keyed deframer), is
//!   `BadMac` under a key differing in one byte, is never a message to a plain decoder, and the
//!   plain frame of the same message is never a message to a keyed decoder; one corrupted body
//!   byte gives `LoneDelimiter`, `BadStuffing` or `BadMac`.
//! - **2, key text**: the bytes (lossily UTF-8) as a hex key: `SwarmKey::from_hex` and `parse`
//!   agree, accept exactly 32 hex digits (either case) and name the first non-hex character
//!   (1-based byte position) or the digit count; an accepted key prints back to the same key
//!   and its `Debug` never shows it.

use protocol::auth::{KEY_LEN, KeyError, TAG_LEN};
use protocol::frame::{
    DELIMITER, DeframerStats, EncodeError, FRAME_MAX, FrameError, KEYED_PAYLOAD_MAX, decode_frame,
    decode_frame_keyed, encode, encode_keyed,
};
use protocol::{Deframer, KEYED_MAX_HOPS, MAX_HOPS, Message, SwarmKey};

use crate::deframer::{self, Flavour};
use crate::reference::{self, cobs_decode, frame_raw, payload_of};
use crate::roundtrip;

type Outcome = Result<Message, FrameError>;

/// The key of `docs/protocol.md` §10.3: bytes 0, 1, … 15.
pub const GOLDEN_KEY: [u8; KEY_LEN] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];
// Keyed golden vectors of payload format 2, as in `frame.rs`'s tests (computed by
// `protocol/tests/golden/gen_golden.py`).
/// The one-hop message under [`GOLDEN_KEY`].
pub const GOLDEN_KEYED_ONE_HOP: &[u8] = b"ss\x70\x32\x72\x76\xd0\x78\xe9\x68ss";
/// The four-hop message under [`GOLDEN_KEY`].
pub const GOLDEN_KEYED_FOUR_HOPS: &[u8] =
    b"ss\x77\x37\x72\x72\x71\x71\x71\x71\x72\x76\x9f\x4a\x44\xfess";
/// The `s` message under [`GOLDEN_KEY`].
pub const GOLDEN_KEYED_S_BYTES: &[u8] = b"ss\x70\x31\x00\x71\x00\x76\xae\x49\xd2\x28ss";
/// The ray message ([`reference::GOLDEN_RAY_FOUR`]'s) under [`GOLDEN_KEY`].
pub const GOLDEN_KEYED_RAY_FOUR: &[u8] = b"ss\x75\x27\x72\x72\x72\x62\x71\x51\x7c\x41\x61\x77\xbf\x72\xfb\x4c\x72\x71\x71\xdb\x6c\xee\xbbss";

/// The mode bytes.
pub const STREAM: u8 = 0;
/// See [`STREAM`].
pub const FRAMING: u8 = 1;
/// See [`STREAM`].
pub const KEY_TEXT: u8 = 2;

/// SipHash-2-4 (Aumasson and Bernstein), written from the paper.
pub fn siphash24(key: &[u8; KEY_LEN], m: &[u8]) -> u64 {
    fn round(v: &mut [u64; 4]) {
        v[0] = v[0].wrapping_add(v[1]);
        v[1] = v[1].rotate_left(13) ^ v[0];
        v[0] = v[0].rotate_left(32);
        v[2] = v[2].wrapping_add(v[3]);
        v[3] = v[3].rotate_left(16) ^ v[2];
        v[0] = v[0].wrapping_add(v[3]);
        v[3] = v[3].rotate_left(21) ^ v[0];
        v[2] = v[2].wrapping_add(v[1]);
        v[1] = v[1].rotate_left(17) ^ v[2];
        v[2] = v[2].rotate_left(32);
    }
    let word = |b: &[u8]| {
        let mut w = [0u8; 8];
        w[..b.len()].copy_from_slice(b);
        u64::from_le_bytes(w)
    };
    let (k0, k1) = (word(&key[..8]), word(&key[8..]));
    let mut v = [
        k0 ^ 0x736f_6d65_7073_6575,
        k1 ^ 0x646f_7261_6e64_6f6d,
        k0 ^ 0x6c79_6765_6e65_7261,
        k1 ^ 0x7465_6462_7974_6573,
    ];
    let mut compress = |mi: u64| {
        v[3] ^= mi;
        round(&mut v);
        round(&mut v);
        v[0] ^= mi;
    };
    let blocks = m.chunks_exact(8);
    let rest = blocks.remainder();
    for b in blocks {
        compress(word(b));
    }
    compress(word(rest) | (m.len() as u64 & 0xFF) << 56);
    v[2] ^= 0xFF;
    for _ in 0..4 {
        round(&mut v);
    }
    v[0] ^ v[1] ^ v[2] ^ v[3]
}

/// The §10.1 tag: the first 4 bytes of the little-endian SipHash-2-4 output.
pub fn reference_tag(key: &[u8; KEY_LEN], payload: &[u8]) -> [u8; TAG_LEN] {
    let h = siphash24(key, payload).to_le_bytes();
    [h[0], h[1], h[2], h[3]]
}

/// The keyed frame of any payload, built without the protocol's code.
pub fn reference_frame(key: &[u8; KEY_LEN], payload: &[u8]) -> Vec<u8> {
    let mut raw = payload.to_vec();
    raw.extend_from_slice(&reference_tag(key, payload));
    frame_raw(&raw)
}

/// The key at the start of `data` (zero-filled) and the rest.
pub fn split_key(data: &[u8]) -> ([u8; KEY_LEN], &[u8]) {
    let n = data.len().min(KEY_LEN);
    let mut key = [0u8; KEY_LEN];
    key[..n].copy_from_slice(&data[..n]);
    (key, &data[n..])
}

/// An input of mode `mode` with `key` and the mode's `rest`.
pub fn input(mode: u8, key: &[u8; KEY_LEN], rest: &[u8]) -> Vec<u8> {
    let mut v = vec![mode];
    v.extend_from_slice(key);
    v.extend_from_slice(rest);
    v
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    match mode % 3 {
        STREAM => {
            let (key, rest) = split_key(rest);
            stream(&key, rest);
        }
        FRAMING => {
            let (key, rest) = split_key(rest);
            framing(&key, &roundtrip::Input::read(rest));
        }
        _ => key_text(&String::from_utf8_lossy(rest)),
    }
}

/// The counters a keyed deframer's results imply.
pub fn keyed_stats_of(results: &[Outcome], skipped: u32) -> DeframerStats {
    let n = |e: FrameError| results.iter().filter(|r| **r == Err(e)).count() as u32;
    DeframerStats {
        bad_mac: n(FrameError::BadMac),
        ..deframer::stats_of(results, skipped)
    }
}

/// What every message a keyed deframer decoded must satisfy.
pub fn check_keyed_message(key: &SwarmKey, m: &Message) {
    assert!(
        (1..=KEYED_MAX_HOPS).contains(&m.len()),
        "keyed message of {} hops",
        m.len()
    );
    let payload = payload_of(m);
    assert!(payload.len() <= KEYED_PAYLOAD_MAX, "keyed {m:?}");
    if let Some(r) = m.ray() {
        assert!(reference::ray_is_valid(r), "{m:?}");
    }
    let f = encode_keyed(m, key).expect("a decoded keyed message encodes");
    assert_eq!(f.len(), 9 + payload.len());
    assert_eq!(decode_frame_keyed(&f, key).as_ref(), Ok(m));
}

fn stream(key_bytes: &[u8; KEY_LEN], data: &[u8]) {
    let key = SwarmKey::new(*key_bytes);
    let new = || Deframer::with_key(key);
    assert!(new().is_keyed());
    let first = |b: &[u8]| decode_frame_keyed(b, &key);
    let check_message = |m: &Message| check_keyed_message(&key, m);
    let frame = |m: Message| (encode_keyed(&m, &key).expect("encodes").to_vec(), m);
    let flavour = Flavour {
        new: &new,
        stats_of: &keyed_stats_of,
        decode_first: &first,
        check_message: &check_message,
        recovery: [frame(reference::four_hops()), frame(reference::one_hop())],
        // A one-hop body: 3 payload + 4 tag + 1 COBS bytes, and a closing `ss`.
        min_frame: 10,
    };
    deframer::check_with(&flavour, data);
    let (_, stream) = deframer::split(data);
    let (got, _) = deframer::by_push_into(new(), stream);
    assert!(!got.contains(&Err(FrameError::BadCheck)), "{got:?}");
}

fn framing(key_bytes: &[u8; KEY_LEN], input: &roundtrip::Input) {
    let key = SwarmKey::new(*key_bytes);
    assert_eq!(key.to_bytes(), *key_bytes);
    let hops = &input.hops;
    let newest = &hops[hops.len().saturating_sub(MAX_HOPS)..];
    let Some(mut m) = Message::from_hops(newest) else {
        assert_eq!(
            encode_keyed(&Message::default(), &key),
            Err(EncodeError::Empty)
        );
        return;
    };
    m.set_ray(input.ray);
    let len = payload_of(&m).len();
    if m.len() > KEYED_MAX_HOPS || len > KEYED_PAYLOAD_MAX {
        assert!(len > KEYED_PAYLOAD_MAX, "{m:?}");
        assert_eq!(encode_keyed(&m, &key), Err(EncodeError::TooManyHops));
        let dropped = m.fit(KEYED_PAYLOAD_MAX);
        assert_eq!(dropped, (len - KEYED_PAYLOAD_MAX).div_ceil(2));
    }
    let payload = payload_of(&m);
    assert!(payload.len() <= KEYED_PAYLOAD_MAX && m.len() <= KEYED_MAX_HOPS);
    let f = encode_keyed(&m, &key).expect("a payload of at most 23 bytes encodes");
    assert_eq!(f.len(), 9 + payload.len());
    if m.ray().is_none() {
        assert_eq!(f.len(), 10 + 2 * m.len());
    }
    assert!(f.len() <= FRAME_MAX);
    assert!(f.starts_with(b"ss") && f.ends_with(b"ss"));
    let body = &f[2..f.len() - 2];
    assert!(!body.contains(&DELIMITER), "an `s` in the body: {f:02x?}");
    let unxored: Vec<u8> = body.iter().map(|b| b ^ DELIMITER).collect();
    let raw = cobs_decode(&unxored).expect("valid COBS");
    assert_eq!(raw[..payload.len()], payload[..]);
    assert_eq!(raw[payload.len()..], reference_tag(key_bytes, &payload));
    assert_eq!(
        f.as_slice(),
        reference_frame(key_bytes, &payload).as_slice()
    );
    assert_eq!(key.tag(&payload), reference_tag(key_bytes, &payload));
    assert!(key.verify(&payload, &reference_tag(key_bytes, &payload)));

    assert_eq!(decode_frame_keyed(&f, &key).as_ref(), Ok(&m));
    let mut d = Deframer::with_key(key);
    let twice: Vec<_> = f
        .iter()
        .chain(f.iter())
        .filter_map(|&b| d.push(b))
        .collect();
    assert_eq!(twice, [Ok(m.clone()), Ok(m.clone())]);
    assert_eq!((d.stats().errors(), d.stats().skipped_bytes), (0, 0));

    let mut other = *key_bytes;
    other[usize::from(input.at) % KEY_LEN] ^= input.mask.max(1);
    let other = SwarmKey::new(other);
    assert_eq!(decode_frame_keyed(&f, &other), Err(FrameError::BadMac));
    let plain = decode_frame(&f);
    assert!(
        plain.is_err(),
        "a plain decoder took a keyed frame: {plain:?}"
    );
    let plain_frame = encode(&m).expect("encodes");
    let keyed = decode_frame_keyed(&plain_frame, &key);
    assert!(
        keyed.is_err(),
        "a keyed decoder took a plain frame: {keyed:?}"
    );

    let mut bad = f.to_vec();
    let i = 2 + usize::from(input.at) % body.len();
    bad[i] ^= input.mask.max(1);
    let got = decode_frame_keyed(&bad, &key);
    assert!(
        matches!(
            got,
            Err(FrameError::LoneDelimiter | FrameError::BadStuffing | FrameError::BadMac)
        ),
        "{bad:02x?} (byte {i} of {f:02x?}) gave {got:?}"
    );
}

/// What `SwarmKey::from_hex` must say for `text`.
pub fn expected_key(text: &str) -> Result<[u8; KEY_LEN], KeyError> {
    let b = text.as_bytes();
    if let Some(i) = b.iter().position(|c| !c.is_ascii_hexdigit()) {
        return Err(KeyError::NotHex { position: i + 1 });
    }
    if b.len() != 2 * KEY_LEN {
        return Err(KeyError::Length { digits: b.len() });
    }
    let mut key = [0u8; KEY_LEN];
    for (k, pair) in key.iter_mut().zip(b.chunks(2)) {
        let s = core::str::from_utf8(pair).expect("ASCII");
        *k = u8::from_str_radix(s, 16).expect("two hex digits");
    }
    Ok(key)
}

fn key_text(text: &str) {
    let parsed = SwarmKey::from_hex(text);
    assert_eq!(text.parse::<SwarmKey>(), parsed);
    assert_eq!(parsed.map(|k| k.to_bytes()), expected_key(text), "{text:?}");
    if let Ok(k) = parsed {
        let hex: String = k.to_bytes().iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(SwarmKey::from_hex(&hex), Ok(k));
        assert_eq!(format!("{k:?}"), "SwarmKey(<secret>)");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn siphash_matches_the_papers_vector() {
        // SipHash paper, appendix A: key 00..0f, message 00..0e.
        let m: Vec<u8> = (0..15).collect();
        assert_eq!(siphash24(&GOLDEN_KEY, &m), 0xa129_ca61_49be_45e5);
    }

    #[test]
    fn golden_keyed_vectors() {
        let k = SwarmKey::new(GOLDEN_KEY);
        for (bytes, m) in [
            (GOLDEN_KEYED_ONE_HOP, reference::one_hop()),
            (GOLDEN_KEYED_FOUR_HOPS, reference::four_hops()),
            (GOLDEN_KEYED_S_BYTES, reference::s_bytes()),
            (GOLDEN_KEYED_RAY_FOUR, reference::ray_four()),
        ] {
            assert_eq!(encode_keyed(&m, &k).unwrap().as_slice(), bytes);
            assert_eq!(reference_frame(&GOLDEN_KEY, &payload_of(&m)), bytes);
            assert_eq!(decode_frame_keyed(bytes, &k), Ok(m));
        }
        // The eleven-hop frame's tag (`frame.rs`'s GOLDEN_KEYED_ELEVEN).
        let eleven = [0xFF, 8].repeat(11);
        let payload = [&[0x2Bu8][..], &eleven].concat();
        assert_eq!(
            reference_tag(&GOLDEN_KEY, &payload),
            [0x11, 0xfa, 0x3d, 0x3f]
        );
    }

    #[test]
    fn key_text_rules() {
        assert_eq!(
            expected_key("000102030405060708090a0b0c0d0e0F"),
            Ok(GOLDEN_KEY)
        );
        assert_eq!(expected_key("00x"), Err(KeyError::NotHex { position: 3 }));
        assert_eq!(expected_key("abc"), Err(KeyError::Length { digits: 3 }));
        for t in ["", "00", "000102030405060708090a0b0c0d0e0f", "é", "0g"] {
            key_text(t);
        }
    }

    #[test]
    fn modes_run() {
        check(&input(
            STREAM,
            &GOLDEN_KEY,
            &deframer::input(&[3], GOLDEN_KEYED_ONE_HOP),
        ));
        let rt = roundtrip::Input {
            hops: vec![reference::hop(1, None); 11],
            at: 1,
            mask: 2,
            ray: None,
        };
        check(&input(FRAMING, &GOLDEN_KEY, &rt.write()));
        let rt = roundtrip::Input {
            ray: Some(reference::ray_left_k2()),
            ..rt
        };
        check(&input(FRAMING, &GOLDEN_KEY, &rt.write()));
        check(&[KEY_TEXT, b'a']);
        check(&[]);
    }
}
