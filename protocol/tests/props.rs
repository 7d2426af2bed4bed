//! Property tests: framing round trips, resynchronisation in garbage, and robots that never
//! panic whatever they are fed.

mod common;

use common::ray;
use proptest::prelude::*;
use protocol::frame::{Deframer, decode_frame, encode};
use protocol::fused::{Event, Reception};
use protocol::params::DecisionRule;
use protocol::{
    FusedNode, Hop, Instant, Level, MAX_HOPS, MAX_SECTORS, MAX_TAGS, Message, Params, Sector, Tag,
};
use rand_pcg::Pcg32;

fn hop() -> impl Strategy<Value = Hop> {
    (
        any::<u8>(),
        proptest::option::of(0..MAX_SECTORS as u8),
        0..MAX_TAGS as u8,
    )
        .prop_map(|(r, p, t)| Hop {
            reading: Level(r),
            pref: p.and_then(Sector::new),
            tag: Tag::new(t).unwrap(),
        })
}

/// Any message: 1..=MAX_HOPS hops and, half the time, a ray (which drops the oldest hops
/// until the payload fits its 25 bytes).
fn message() -> impl Strategy<Value = Message> {
    (
        proptest::collection::vec(hop(), 1..=MAX_HOPS),
        proptest::option::of(ray()),
    )
        .prop_map(|(h, r)| {
            let mut m = Message::from_hops(&h).unwrap();
            m.set_ray(r);
            m
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn any_message_survives_encode_frame_deframe(m in message()) {
        let f = encode(&m).unwrap();
        prop_assert!(f.len() <= 32);
        prop_assert!(!f[2..f.len() - 2].contains(&b's'));
        prop_assert_eq!(decode_frame(&f), Ok(m.clone()));
        // Byte by byte, too.
        let mut d = Deframer::new();
        let got: Vec<_> = f.iter().filter_map(|&b| d.push(b)).collect();
        prop_assert_eq!(got, vec![Ok(m)]);
    }

    #[test]
    fn frames_interleaved_with_garbage_are_all_recovered(
        parts in proptest::collection::vec((proptest::collection::vec(any::<u8>(), 0..80), message()), 1..12),
        tail in proptest::collection::vec(any::<u8>(), 0..40),
        chunk in 1usize..40,
    ) {
        let mut stream = Vec::new();
        for (garbage, m) in &parts {
            stream.extend_from_slice(garbage);
            stream.extend_from_slice(&encode(m).unwrap());
        }
        stream.extend_from_slice(&tail);
        let mut d = Deframer::new();
        let mut got = Vec::new();
        for c in stream.chunks(chunk) {
            got.extend(d.frames(c).filter_map(Result::ok));
        }
        let want: Vec<Message> = parts.into_iter().map(|(_, m)| m).collect();
        // Garbage may by chance hold a valid frame of its own; every real one is there, in order.
        let mut it = got.iter();
        for m in &want {
            prop_assert!(it.any(|g| g == m), "lost {:?}", m);
        }
        prop_assert!(d.stats().frames as usize >= want.len());
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let mut d = Deframer::new();
        let n = d.frames(&bytes).count();
        let s = d.stats();
        prop_assert_eq!(n as u32, s.frames + s.errors());
        let _ = decode_frame(&bytes);
    }

    #[test]
    fn a_robot_fed_anything_keeps_its_invariants(
        seed in any::<u64>(),
        ops in proptest::collection::vec(
            (0u8..4, any::<u32>(), 0u8..10, proptest::collection::vec(any::<u8>(), 0..40)),
            1..200,
        ),
    ) {
        let mut rng = Pcg32::new(seed, 1);
        let tag = Tag::from_id(seed as u16);
        let mut n = FusedNode::new(Params::robots(), tag, Instant::ZERO, &mut rng).unwrap();
        let mut d = Deframer::new();
        for (kind, t, sector, bytes) in ops {
            // Times jump around, backwards included.
            let now = Instant::from_millis(u64::from(t) % 5_000_000);
            // Every initiation and every relay (always of an accepted message) queues one
            // transmission; nothing else does under the fixed rule.
            let queued = |n: &FusedNode| {
                let w = n.wave_stats();
                w.initiated.wrapping_add(w.relayed)
            };
            let (queued_before, lost_before) = (queued(&n), n.stats().transmits_lost);
            match kind {
                0 => n.handle_reading(Level(bytes.first().copied().unwrap_or(0))),
                1 => n.handle_timeout(now, &mut rng),
                _ => {
                    let from = Sector::new(sector % 9).unwrap_or(Sector::LEFT);
                    let mut frame = bytes.clone();
                    if kind == 3 {
                        // A well-formed frame around arbitrary hops.
                        let hops: Vec<Hop> = bytes.chunks(2).take(MAX_HOPS).map(|c| {
                            let b = c.get(1).copied().unwrap_or(0);
                            Hop {
                                reading: Level(c[0]),
                                pref: Sector::new(b % 3),
                                tag: Tag::from_id(u16::from(b >> 4)),
                            }
                        }).collect();
                        if let Some(m) = Message::from_hops(&hops) {
                            frame = encode(&m).unwrap().to_vec();
                        }
                    }
                    for m in d.frames(&frame).filter_map(Result::ok) {
                        let own = m.has_tag(tag);
                        let dropped = n.stats().own_tag;
                        let r = n.handle_message(now, from, &m, &mut rng);
                        if own && from.index() < 2 {
                            // Dropped after whatever was due: a second call at the same time
                            // changes nothing but the counter.
                            prop_assert_eq!(r, Reception::OwnTag);
                            let again = (n.state(), n.votes(), n.preference(), *n.wave_stats());
                            prop_assert_eq!(n.handle_message(now, from, &m, &mut rng), r);
                            prop_assert_eq!(
                                (n.state(), n.votes(), n.preference(), *n.wave_stats()),
                                again
                            );
                            prop_assert_eq!(n.stats().own_tag, dropped.wrapping_add(2));
                        } else {
                            prop_assert!(r != Reception::OwnTag);
                            prop_assert_eq!(n.stats().own_tag, dropped);
                        }
                    }
                }
            }
            let mut sent = 0;
            while let Some(m) = n.poll_transmit() {
                prop_assert!(!m.is_empty() && m.len() <= MAX_HOPS);
                sent += 1;
            }
            // The outbox was drained after the previous step and holds two: of what this step
            // queued the newest two are sent, the older ones dropped and counted.
            let produced = queued(&n).wrapping_sub(queued_before);
            let lost = n.stats().transmits_lost.wrapping_sub(lost_before);
            prop_assert_eq!(sent, produced.min(2), "queued {}", produced);
            prop_assert_eq!(lost, produced - sent);
            if kind == 0 {
                prop_assert_eq!(produced, 0, "a reading sends nothing");
            }
            while n.poll_event().is_some() {}
            prop_assert!(n.poll_timeout() > Instant::ZERO);
            prop_assert!(n.preference().is_none_or(|s| s.index() < 2));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// The adaptive decision rule (which `fuzz/` does not model) on anything: messages with or
    /// without rays from any sector (also outside `0..K`), readings, times jumping back and
    /// forth. It never panics, decides only sectors it has, and every transmission frames into
    /// 32 bytes with its own hop last.
    #[test]
    fn an_adaptive_robot_fed_anything_keeps_its_invariants(
        seed in any::<u64>(),
        six in any::<bool>(),
        ops in proptest::collection::vec(
            (0u8..3, any::<u32>(), 0u8..9, any::<u8>(), message()),
            1..150,
        ),
    ) {
        let mut rng = Pcg32::new(seed, 3);
        let mut params = Params::robots();
        params.decide = DecisionRule::Adaptive;
        params.negotiation_cycles = 2;
        if six {
            params.sectors = 6;
        }
        let k = params.sectors;
        let tag = Tag::from_id(seed as u16);
        let mut n = FusedNode::new(params, tag, Instant::ZERO, &mut rng).unwrap();
        let mut clock = 0u64;
        for (kind, t, sector, reading, m) in ops {
            // Mostly forward by up to a minute, sometimes back.
            clock = if t % 7 == 0 {
                clock.saturating_sub(u64::from(t % 90_000))
            } else {
                clock + u64::from(t % 60_000)
            };
            let now = Instant::from_millis(clock);
            match kind {
                0 => n.handle_reading(Level(reading)),
                1 => n.handle_timeout(now, &mut rng),
                _ => {
                    let from = Sector::new(sector).unwrap_or(Sector::LEFT);
                    let r = n.handle_message(now, from, &m, &mut rng);
                    if from.index() >= k {
                        prop_assert_eq!(r, Reception::UnknownSector);
                    }
                }
            }
            while let Some(out) = n.poll_transmit() {
                prop_assert!(encode(&out).unwrap().len() <= 32);
                prop_assert_eq!(out.hops().last().map(|h| h.tag), Some(tag));
            }
            while let Some(e) = n.poll_event() {
                if let Event::Decided { decision, .. } = e {
                    prop_assert!(decision.is_none_or(|d| d.index() < k), "{:?}", decision);
                }
            }
            prop_assert!(n.decision().is_none_or(|d| d.index() < k));
        }
    }
}

proptest! {
    /// `Deframer::feed` (which with `bulk-deframe`, turned on in any workspace build with
    /// hal-emu, copies a body's bytes at once) gives the same results, in the same order, with
    /// the same counters, as `push` byte by byte: over noise rich in delimiters, over-long
    /// bodies and real frames, fed in chunks of any size.
    #[test]
    fn feeding_slices_is_pushing_bytes(
        parts in proptest::collection::vec(
            prop_oneof![
                // Noise, with plenty of delimiters.
                proptest::collection::vec(prop_oneof![Just(b's'), any::<u8>()], 0..80),
                // A long run with no delimiter (overflows a body).
                (1usize..200).prop_map(|n| vec![b'x'; n]),
                // A real frame.
                (0u8..=255, 1u8..12).prop_map(|(r, hops)| {
                    let hops: Vec<protocol::Hop> = (0..hops)
                        .map(|i| protocol::Hop {
                            tag: protocol::Tag::from_id(u16::from(i)),
                            reading: protocol::Level(r.wrapping_add(i)),
                            pref: None,
                        })
                        .collect();
                    let m = protocol::Message::from_hops(&hops).unwrap();
                    protocol::frame::encode(&m).unwrap().to_vec()
                }),
            ],
            0..12,
        ),
        chunk in 1usize..40,
    ) {
        let bytes: Vec<u8> = parts.concat();
        let mut one = protocol::frame::Deframer::new();
        let by_byte: Vec<_> = bytes.iter().filter_map(|&b| one.push(b)).collect();
        let mut many = protocol::frame::Deframer::new();
        let mut by_slice = Vec::new();
        for c in bytes.chunks(chunk) {
            let mut rest = c;
            loop {
                let (r, more) = many.feed(rest);
                match r {
                    Some(r) => by_slice.push(r),
                    None => break,
                }
                rest = more;
            }
        }
        prop_assert_eq!(&by_slice, &by_byte);
        prop_assert_eq!(many.stats(), one.stats());
        // Same state: the same bytes next give the same results.
        let tail = b"xss12ssyy";
        prop_assert_eq!(many.frames(tail).collect::<Vec<_>>(), one.frames(tail).collect::<Vec<_>>());
    }
}
