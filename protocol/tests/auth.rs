//! Property tests of authenticated frames: keyed round trips, and every frame not made with the
//! swarm key rejected (random tags, other keys, plain frames, bit flips), with its counter.

mod common;

use common::ray;
use proptest::prelude::*;
use protocol::frame::{
    DELIMITER, Deframer, EncodeError, FrameError, KEYED_MAX_HOPS, KEYED_PAYLOAD_MAX,
    decode_frame_keyed, encode, encode_keyed,
};
use protocol::{
    Duration, FusedNode, Hop, Instant, Level, MAX_HOPS, MAX_SECTORS, MAX_TAGS, Message, Params,
    Sector, SwarmKey, Tag,
};
use rand_pcg::Pcg32;

/// Any hop but one of robot tag 15 (the node of `a_keyed_node_only_relays_…` has that tag).
fn hop() -> impl Strategy<Value = Hop> {
    (
        any::<u8>(),
        proptest::option::of(0..MAX_SECTORS as u8),
        0..MAX_TAGS as u8 - 1,
    )
        .prop_map(|(r, p, t)| Hop {
            reading: Level(r),
            pref: p.and_then(Sector::new),
            tag: Tag::new(t).unwrap(),
        })
}

/// Any message of at most `max` hops and, half the time, a ray; cut (oldest hops first) to
/// the payload of `max` plain hops, `1 + 2·max` bytes, as a node with `max_hops = max` does.
fn message(max: usize) -> impl Strategy<Value = Message> {
    (
        proptest::collection::vec(hop(), 1..=max),
        proptest::option::of(ray()),
    )
        .prop_map(move |(h, r)| {
            let mut m = Message::from_hops(&h).unwrap();
            m.set_ray(r);
            m.fit(1 + 2 * max);
            m
        })
}

fn key() -> impl Strategy<Value = SwarmKey> {
    any::<[u8; 16]>().prop_map(SwarmKey::new)
}

/// Two different keys.
fn two_keys() -> impl Strategy<Value = (SwarmKey, SwarmKey)> {
    (key(), key()).prop_filter("different keys", |(a, b)| a != b)
}

/// A frame of `payload ‖ check`, stuffed and delimited as the encoders do.
fn frame_of(payload: &[u8], check: &[u8]) -> Vec<u8> {
    let mut raw = payload.to_vec();
    raw.extend_from_slice(check);
    let mut body = [0u8; 64];
    let n = cobs::encode(&raw, &mut body);
    let mut f = b"ss".to_vec();
    f.extend(body[..n].iter().map(|b| b ^ DELIMITER));
    f.extend_from_slice(b"ss");
    f
}

fn postcard_payload(m: &Message) -> Vec<u8> {
    let mut buf = [0u8; 32];
    postcard::to_slice(m, &mut buf).unwrap().to_vec()
}

/// Everything a fresh keyed deframer makes of `bytes`.
fn deframe(key: SwarmKey, bytes: &[u8]) -> (Vec<Result<Message, FrameError>>, Deframer) {
    let mut d = Deframer::with_key(key);
    let got = d.frames(bytes).collect();
    (got, d)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn any_keyed_message_survives_encode_frame_deframe(m in message(KEYED_MAX_HOPS), k in key()) {
        let f = encode_keyed(&m, &k).unwrap();
        prop_assert!(f.len() <= 32);
        prop_assert_eq!(f.len(), encode(&m).unwrap().len() + 2);
        prop_assert!(!f[2..f.len() - 2].contains(&b's'));
        prop_assert_eq!(decode_frame_keyed(&f, &k), Ok(m.clone()));
        let mut d = Deframer::with_key(k);
        let got: Vec<_> = f.iter().filter_map(|&b| d.push(b)).collect();
        prop_assert_eq!(got, vec![Ok(m)]);
        prop_assert_eq!((d.stats().frames, d.stats().errors()), (1, 0));
    }

    #[test]
    fn messages_over_eleven_hops_are_refused_not_cut(m in message(MAX_HOPS), k in key()) {
        let r = encode_keyed(&m, &k);
        if m.len() > KEYED_MAX_HOPS || m.encoded_len() > KEYED_PAYLOAD_MAX {
            prop_assert_eq!(r, Err(EncodeError::TooManyHops));
        } else {
            prop_assert!(r.is_ok());
        }
        // Refused, not cut: the same message cut to the keyed payload encodes.
        let mut short = m.clone();
        short.fit(KEYED_PAYLOAD_MAX);
        let f = encode_keyed(&short, &k).unwrap();
        prop_assert_eq!(decode_frame_keyed(&f, &k), Ok(short));
    }

    #[test]
    fn random_tags_are_rejected(m in message(KEYED_MAX_HOPS), k in key(), tag in any::<[u8; 4]>()) {
        let payload = postcard_payload(&m);
        prop_assume!(tag != k.tag(&payload));
        let (got, d) = deframe(k, &frame_of(&payload, &tag));
        prop_assert_eq!(got, vec![Err(FrameError::BadMac)]);
        prop_assert_eq!((d.stats().bad_mac, d.stats().frames), (1, 0));
    }

    #[test]
    fn frames_made_with_another_key_are_rejected(m in message(KEYED_MAX_HOPS), (k, other) in two_keys()) {
        let f = encode_keyed(&m, &other).unwrap();
        prop_assert_eq!(decode_frame_keyed(&f, &k), Err(FrameError::BadMac));
    }

    #[test]
    fn plain_frames_are_rejected_by_a_keyed_deframer(m in message(MAX_HOPS), k in key()) {
        let (got, d) = deframe(k, &encode(&m).unwrap());
        prop_assert_eq!(got, vec![Err(FrameError::BadMac)]);
        prop_assert_eq!(d.stats().bad_mac, 1);
    }

    #[test]
    fn keyed_frames_are_rejected_by_a_plain_deframer(m in message(KEYED_MAX_HOPS), k in key()) {
        let mut d = Deframer::new();
        let got: Vec<_> = d.frames(&encode_keyed(&m, &k).unwrap()).collect();
        prop_assert_eq!(got.len(), 1);
        prop_assert!(got[0].is_err(), "{:?}", got);
        prop_assert_eq!(d.stats().bad_mac, 0, "a plain deframer never says BadMac");
    }

    #[test]
    fn a_flipped_bit_never_gets_through(m in message(KEYED_MAX_HOPS), k in key(), at in any::<prop::sample::Index>(), bit in 0u8..8) {
        let mut f = encode_keyed(&m, &k).unwrap().to_vec();
        let i = at.index(f.len());
        f[i] ^= 1 << bit;
        let (got, _) = deframe(k, &f);
        prop_assert!(got.iter().all(Result::is_err), "byte {} bit {}: {:?}", i, bit, got);
    }

    #[test]
    fn a_stream_of_mixed_frames_keeps_only_the_swarms(
        parts in proptest::collection::vec((0u8..3, message(KEYED_MAX_HOPS)), 1..16),
        (k, other) in two_keys(),
        chunk in 1usize..40,
    ) {
        let mut stream = Vec::new();
        let mut ours = Vec::new();
        for (kind, m) in &parts {
            let f = match kind {
                0 => { ours.push(m.clone()); encode_keyed(m, &k) }
                1 => encode_keyed(m, &other),
                _ => encode(m),
            };
            stream.extend_from_slice(&f.unwrap());
        }
        let mut d = Deframer::with_key(k);
        let mut got = Vec::new();
        for c in stream.chunks(chunk) {
            got.extend(d.frames(c));
        }
        let accepted: Vec<Message> = got.iter().filter_map(|r| r.clone().ok()).collect();
        prop_assert_eq!(accepted, ours.clone());
        let s = d.stats();
        prop_assert_eq!(s.frames as usize, ours.len());
        prop_assert_eq!(s.bad_mac as usize, parts.len() - ours.len());
        prop_assert_eq!(s.errors(), s.bad_mac);
    }

    #[test]
    fn arbitrary_bytes_never_panic_a_keyed_deframer(bytes in proptest::collection::vec(any::<u8>(), 0..600), k in key()) {
        let (got, d) = deframe(k, &bytes);
        let s = d.stats();
        prop_assert_eq!(got.len() as u32, s.frames + s.errors());
        let _ = decode_frame_keyed(&bytes, &k);
    }

    #[test]
    fn a_keyed_node_only_relays_what_a_keyed_frame_holds(
        seed in any::<u64>(),
        msgs in proptest::collection::vec(message(MAX_HOPS), 1..20),
        k in key(),
    ) {
        let mut rng = Pcg32::new(seed, 1);
        let params = Params { max_hops: KEYED_MAX_HOPS as u8, ..Params::robots() };
        let tag = Tag::new(MAX_TAGS as u8 - 1).unwrap();
        let mut n = FusedNode::new(params, tag, Instant::ZERO, &mut rng).unwrap();
        let mut t = Instant::ZERO;
        let mut relayed = 0;
        for m in &msgs {
            t += Duration::from_secs(6);
            n.handle_message(t, Sector::LEFT, m, &mut rng);
            n.handle_timeout(t + Duration::from_secs(1), &mut rng);
            while let Some(out) = n.poll_transmit() {
                prop_assert!(out.len() <= KEYED_MAX_HOPS);
                prop_assert!(out.encoded_len() <= KEYED_PAYLOAD_MAX);
                prop_assert!(encode_keyed(&out, &k).is_ok());
                relayed += 1;
            }
        }
        prop_assert!(relayed > 0);
    }
}

/// Exhaustively: every single-bit flip of a keyed frame is rejected, and a flip inside the
/// stuffed bytes or the tag that still stuffs and delimits correctly is a bad MAC.
#[test]
fn every_bit_flip_of_a_keyed_frame_is_rejected() {
    let k = SwarmKey::new(core::array::from_fn(|i| i as u8));
    let m = Message::from_hops(
        &[Hop {
            reading: Level(200),
            pref: Some(Sector::LEFT),
            tag: Tag::new(9).unwrap(),
        }; KEYED_MAX_HOPS],
    )
    .unwrap();
    let f = encode_keyed(&m, &k).unwrap();
    let mut bad_macs = 0;
    for i in 0..f.len() {
        for bit in 0..8 {
            let mut g = f.to_vec();
            g[i] ^= 1 << bit;
            let (got, d) = deframe(k, &g);
            assert!(
                got.iter().all(Result::is_err),
                "byte {i} bit {bit}: {got:?}"
            );
            bad_macs += d.stats().bad_mac;
        }
    }
    assert!(bad_macs > 100, "{bad_macs} of {} flips", f.len() * 8);
}
