//! The seed corpus: the classic breakers of a framed protocol, plus golden frames and a few
//! scripted runs of the state machines, each with a descriptive name.
//!
//! `cargo run --example gen_corpus` (from `fuzz/`) writes them to `corpus/<target>/<name>.bin`,
//! replacing what was there; `tests/corpus.rs` checks that the committed files are exactly
//! these, that each passes its target's check, and that the framing seeds give the results
//! listed here. The seeds of the `link_*` targets are in [`crate::link_corpus`].

use std::io;
use std::path::Path;

use protocol::frame::{DELIMITER, FrameError};
use protocol::message::Ray;
use protocol::{Hop, MAX_HOPS, MAX_SECTORS, Message};

use crate::keyed::{
    self, FRAMING, GOLDEN_KEY, GOLDEN_KEYED_FOUR_HOPS, GOLDEN_KEYED_ONE_HOP, GOLDEN_KEYED_RAY_FOUR,
    GOLDEN_KEYED_S_BYTES, KEY_TEXT, STREAM, reference_frame,
};
use crate::reference::{
    self, GOLDEN_FOUR_HOPS, GOLDEN_ONE_HOP, GOLDEN_RAY_FOUR, GOLDEN_S_BYTES, GOLDEN_TAGGED_FOUR,
    GOLDEN_V1_ONE_HOP, four_hops, frame_payload, hop, one_hop, payload_of, ray_four, s_bytes,
    tagged, tagged_four,
};
use crate::scenario::{Custom, ParamsChoice, Setup, Start, TimeStep};
use crate::{deframer, fused_node, link_corpus, roundtrip, three_phase};

type Outcome = Result<Message, FrameError>;

/// A `deframer` seed: the stream, the cut bytes it is fed in, and what a deframer must yield.
#[derive(Clone, Debug)]
pub struct DeframerSeed {
    /// File name without extension.
    pub name: &'static str,
    /// The slice lengths (see [`deframer::slices`]).
    pub cuts: Vec<u8>,
    /// The byte stream.
    pub stream: Vec<u8>,
    /// Every result, in order.
    pub expect: Vec<Outcome>,
}

/// A `message_decode` seed: the bytes, what `decode_frame` gives for them, and, for payloads,
/// what the frame around them with a correct check gives.
#[derive(Clone, Debug)]
pub struct DecodeSeed {
    /// File name without extension.
    pub name: &'static str,
    /// The bytes.
    pub data: Vec<u8>,
    /// `decode_frame(data)`.
    pub frame: Outcome,
    /// `decode_frame` of `data` as a payload with a correct CRC, if this seed is a payload.
    pub as_payload: Option<Outcome>,
}

fn cat(parts: &[&[u8]]) -> Vec<u8> {
    parts.concat()
}

/// `n` hops (reading 0xFF, sector 7): the widest message.
fn widest(n: usize) -> Vec<Hop> {
    vec![hop(0xFF, Some(7)); n]
}

fn msg(hops: &[Hop]) -> Message {
    Message::from_hops(hops).expect("1..=12 hops")
}

/// The message of a valid payload, by the independent parser.
fn decoded(payload: &[u8]) -> Message {
    reference::decode_payload(payload).expect("a valid payload")
}

/// A format-3 payload claiming `n` hops of (0xFF, sector 7) (header `0x40 | n`, so 13 is
/// `0x4D`), with all of them present.
fn wide_payload(n: u8) -> Vec<u8> {
    let mut p = vec![0x40 | n];
    for _ in 0..n {
        p.extend_from_slice(&[0xFF, 8]);
    }
    p
}

/// A payload of `n` hops of (1, no preference) and the ray bytes `ray` (header `0x50 | n`).
fn ray_payload(n: u8, ray: &[u8]) -> Vec<u8> {
    let mut p = vec![0x50 | n];
    for _ in 0..n {
        p.extend_from_slice(&[1, 0]);
    }
    p.extend_from_slice(ray);
    p
}

/// The 7-sector ray bytes of `frame.rs`'s GOLDEN_RAY_LARGEST: sector 6, 200 robots, sum
/// 0x7373, sum of squares 0x700473.
const RAY_K7: [u8; 14] = [
    0x67, 200, 0x73, 0x73, 0x73, 0x04, 0x70, 10, 20, 30, 40, 50, 0, 50,
];

/// Seeds of the `deframer` target.
pub fn deframer() -> Vec<DeframerSeed> {
    let one = GOLDEN_ONE_HOP;
    let four = GOLDEN_FOUR_HOPS;
    let s = GOLDEN_S_BYTES;
    let f4 = four.len();
    let f1 = one.len();
    let widest12 = frame_payload(&payload_of(&msg(&widest(MAX_HOPS))));
    let s_readings = vec![hop(DELIMITER, None); MAX_HOPS];
    let mut bad_crc = four.to_vec();
    bad_crc[12] ^= 0x01;
    let mut lone = four.to_vec();
    lone[6] = DELIMITER;
    let seed = |name, cuts: &[u8], stream: Vec<u8>, expect: Vec<Outcome>| DeframerSeed {
        name,
        cuts: cuts.to_vec(),
        stream,
        expect,
    };
    use FrameError::*;
    vec![
        seed("golden-one-hop", &[], one.to_vec(), vec![Ok(one_hop())]),
        seed(
            "golden-tagged-four-hops",
            &[5],
            GOLDEN_TAGGED_FOUR.to_vec(),
            vec![Ok(tagged_four())],
        ),
        seed(
            "max-length-tag-15",
            &[],
            frame_payload(&payload_of(&msg(&[tagged(0xFF, 15, Some(7)); MAX_HOPS]))),
            vec![Ok(msg(&[tagged(0xFF, 15, Some(7)); MAX_HOPS]))],
        ),
        seed(
            "preference-nibble-9-with-tag",
            &[],
            frame_payload(&[0x41, 0, 0x39]),
            vec![Err(FrameError::Undecodable)],
        ),
        seed(
            "golden-ray-four-then-one-hop",
            &[6],
            cat(&[GOLDEN_RAY_FOUR, one]),
            vec![Ok(ray_four()), Ok(one_hop())],
        ),
        seed(
            "max-length-ray-5-hops-7-sectors",
            &[],
            frame_payload(&ray_payload(5, &RAY_K7)),
            vec![Ok(decoded(&ray_payload(5, &RAY_K7)))],
        ),
        seed(
            "over-budget-ray-6-hops-7-sectors",
            &[],
            frame_payload(&ray_payload(6, &RAY_K7)),
            vec![Err(TooLong)],
        ),
        seed(
            "ray-vote-over-robots",
            &[],
            frame_payload(&ray_payload(1, &[0x12, 2, 2, 0, 2, 0, 0, 3, 0])),
            vec![Err(Undecodable)],
        ),
        seed(
            "golden-four-hops-cut-3-5",
            &[3, 5],
            four.to_vec(),
            vec![Ok(four_hops())],
        ),
        seed(
            "golden-s-bytes-byte-by-byte",
            &[1],
            s.to_vec(),
            vec![Ok(s_bytes())],
        ),
        seed(
            "back-to-back-goldens",
            &[7, 0, 11],
            cat(&[one, four, s]),
            vec![Ok(one_hop()), Ok(four_hops()), Ok(s_bytes())],
        ),
        seed(
            "garbage-before-frame",
            &[],
            cat(&[b"\x00\xffabc", one]),
            vec![Ok(one_hop())],
        ),
        seed(
            "truncated-frame-then-frame",
            &[2],
            cat(&[&four[..5], one]),
            vec![Err(BadStuffing), Ok(one_hop())],
        ),
        seed("truncated-frame-at-end", &[], four[..10].to_vec(), vec![]),
        seed(
            "truncated-before-crc",
            &[],
            cat(&[&four[..f4 - 4], b"ss"]),
            vec![Err(BadStuffing)],
        ),
        seed(
            "missing-end-delimiter-then-frame",
            &[9],
            cat(&[&four[..f4 - 2], &[0x42; 40], one]),
            vec![Err(TooLong), Ok(one_hop())],
        ),
        seed(
            "missing-end-delimiter-at-end",
            &[],
            one[..f1 - 2].to_vec(),
            vec![],
        ),
        seed(
            "half-end-delimiter-then-frame",
            &[],
            cat(&[&one[..f1 - 1], b"x", one]),
            vec![Err(LoneDelimiter), Ok(one_hop())],
        ),
        seed(
            "delimiter-inside-body",
            &[],
            cat(&[&lone, one]),
            vec![Err(LoneDelimiter), Ok(one_hop())],
        ),
        seed(
            "delimiters-in-payload-long-runs",
            &[],
            cat(&[b"ssss", s, b"ssss"]),
            vec![Ok(s_bytes())],
        ),
        seed(
            "delimiters-in-payload-max-length",
            &[],
            frame_payload(&payload_of(&msg(&s_readings))),
            vec![Ok(msg(&s_readings))],
        ),
        seed(
            "max-length-payload",
            &[16],
            widest12.clone(),
            vec![Ok(msg(&widest(MAX_HOPS)))],
        ),
        seed(
            "over-max-length-13-hops",
            &[],
            frame_payload(&wide_payload(13)),
            vec![Err(TooLong)],
        ),
        seed(
            "body-29-bytes",
            &[],
            cat(&[b"ss", &[0x42; 29], b"ss"]),
            vec![Err(TooLong)],
        ),
        seed(
            "zero-length-payload",
            &[],
            frame_payload(&[]),
            vec![Err(TooShort)],
        ),
        seed(
            "zero-hops",
            &[],
            frame_payload(&[0x40]),
            vec![Err(Undecodable)],
        ),
        seed(
            "length-lies-more",
            &[],
            frame_payload(&[0x42, 1, 0]),
            vec![Err(Undecodable)],
        ),
        seed(
            "length-lies-less",
            &[],
            frame_payload(&[0x41, 1, 0, 0, 0]),
            vec![Err(Undecodable)],
        ),
        seed(
            "header-other-version-bits",
            &[],
            frame_payload(&[0xE1, 1, 0]),
            vec![Err(Undecodable)],
        ),
        seed(
            "format-1-one-hop",
            &[],
            frame_payload(&[0x01, 1, 0]),
            vec![Err(Undecodable)],
        ),
        seed(
            "preference-byte-9",
            &[],
            frame_payload(&[0x41, 0, 9]),
            vec![Err(Undecodable)],
        ),
        seed("bad-crc", &[], bad_crc, vec![Err(BadCheck)]),
        seed(
            "bad-stuffing",
            &[],
            b"ss\x00ss".to_vec(),
            vec![Err(BadStuffing)],
        ),
        seed(
            "too-short-body",
            &[],
            b"ss\x72ss".to_vec(),
            vec![Err(TooShort)],
        ),
        seed("empty-fields", &[1], b"ssssssssss".to_vec(), vec![]),
        seed(
            "noise-between-frames",
            &[],
            cat(&[one, b"xyz", one]),
            vec![Ok(one_hop()), Err(BadStuffing), Ok(one_hop())],
        ),
        seed(
            "lone-s-before-sync",
            &[],
            cat(&[b"sx", one]),
            vec![Ok(one_hop())],
        ),
        seed(
            "lone-s-after-overflow",
            &[],
            cat(&[b"ss", &[0x42; 30], b"sx", one]),
            vec![Err(TooLong), Ok(one_hop())],
        ),
        seed(
            "zero-bytes-body",
            &[],
            cat(&[b"ss", &[0; 10], b"ss"]),
            vec![Err(BadStuffing)],
        ),
    ]
}

/// Seeds of the `message_decode` target.
pub fn message_decode() -> Vec<DecodeSeed> {
    use FrameError::*;
    let payload = |name, data: Vec<u8>, as_payload: Outcome| DecodeSeed {
        name,
        data,
        frame: Err(Incomplete),
        as_payload: Some(as_payload),
    };
    let frame = |name, data: Vec<u8>, frame: Outcome| DecodeSeed {
        name,
        data,
        frame,
        as_payload: None,
    };
    let four = GOLDEN_FOUR_HOPS;
    vec![
        payload("payload-one-hop", vec![0x41, 1, 0], Ok(one_hop())),
        payload("payload-ray-four", payload_of(&ray_four()), Ok(ray_four())),
        payload(
            "payload-ray-largest",
            ray_payload(5, &RAY_K7),
            Ok(decoded(&ray_payload(5, &RAY_K7))),
        ),
        payload(
            "payload-ray-over-budget",
            ray_payload(6, &RAY_K7),
            Err(TooLong),
        ),
        payload(
            "payload-ray-1-sector",
            ray_payload(1, &[0x01, 1, 1, 0, 1, 0, 0, 1]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-9-sectors",
            ray_payload(1, &[0x09, 1, 1, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-sector-not-below-k",
            ray_payload(1, &[0x22, 1, 1, 0, 1, 0, 0, 1, 0]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-no-robots",
            ray_payload(1, &[0x02, 0, 0, 0, 0, 0, 0, 0, 0]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-vote-over-robots",
            ray_payload(1, &[0x12, 2, 2, 0, 2, 0, 0, 3, 0]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-cut-short",
            ray_payload(2, &[0x12, 2, 2, 0, 2, 0, 0, 1]),
            Err(Undecodable),
        ),
        payload(
            "payload-ray-bit-no-ray",
            ray_payload(2, &[]),
            Err(Undecodable),
        ),
        payload(
            "payload-format-1-tagged-four",
            vec![0x04, 1, 0x01, 1, 0x11, 0, 0x22, 0, 0x32],
            Err(Undecodable),
        ),
        payload(
            "payload-four-hops",
            payload_of(&four_hops()),
            Ok(four_hops()),
        ),
        payload("payload-s-bytes", payload_of(&s_bytes()), Ok(s_bytes())),
        payload(
            "payload-max-12-hops",
            wide_payload(12),
            Ok(msg(&widest(MAX_HOPS))),
        ),
        payload("payload-13-hops", wide_payload(13), Err(TooLong)),
        payload("payload-zero-length", vec![], Err(TooShort)),
        payload("payload-zero-hops", vec![0x40], Err(Undecodable)),
        payload("payload-13-hops-header", vec![0x4D, 1, 0], Err(Undecodable)),
        payload(
            "payload-format-2-one-hop",
            vec![0x21, 1, 0],
            Err(Undecodable),
        ),
        payload(
            "payload-length-lies-more",
            vec![0x42, 1, 0],
            Err(Undecodable),
        ),
        payload(
            "payload-length-lies-less",
            vec![0x41, 1, 0, 0, 0],
            Err(Undecodable),
        ),
        payload(
            "payload-format-1-one-hop",
            vec![0x01, 1, 0],
            Err(Undecodable),
        ),
        payload(
            "payload-preference-byte-9",
            vec![0x41, 0, 9],
            Err(Undecodable),
        ),
        payload(
            "payload-tag-15-no-preference",
            vec![0x41, 7, 0xF0],
            Ok(msg(&[tagged(7, 15, None)])),
        ),
        payload(
            "payload-tag-3-preference-nibble-9",
            vec![0x41, 7, 0x39],
            Err(Undecodable),
        ),
        payload(
            "payload-tagged-four-hops",
            payload_of(&tagged_four()),
            Ok(tagged_four()),
        ),
        payload("payload-all-s", vec![DELIMITER; 8], Err(Undecodable)),
        frame(
            "frame-golden-one-hop",
            GOLDEN_ONE_HOP.to_vec(),
            Ok(one_hop()),
        ),
        frame("frame-golden-four-hops", four.to_vec(), Ok(four_hops())),
        frame(
            "frame-golden-s-bytes",
            GOLDEN_S_BYTES.to_vec(),
            Ok(s_bytes()),
        ),
        frame("frame-too-short", b"ss\x72ss".to_vec(), Err(TooShort)),
        frame("frame-bad-stuffing", b"ss\x00ss".to_vec(), Err(BadStuffing)),
        frame("frame-empty-fields", b"ssss".to_vec(), Err(Incomplete)),
        frame("frame-truncated", four[..9].to_vec(), Err(Incomplete)),
        frame(
            "frame-missing-end-delimiter",
            four[..four.len() - 2].to_vec(),
            Err(Incomplete),
        ),
        frame(
            "frame-length-lies",
            frame_payload(&[0x42, 1, 0]),
            Err(Undecodable),
        ),
        frame(
            "frame-golden-ray-four",
            GOLDEN_RAY_FOUR.to_vec(),
            Ok(ray_four()),
        ),
        frame(
            "frame-format-1-golden-one-hop",
            GOLDEN_V1_ONE_HOP.to_vec(),
            Err(Undecodable),
        ),
        frame(
            "frame-13-hops",
            frame_payload(&wide_payload(13)),
            Err(TooLong),
        ),
        frame(
            "frame-format-1-one-hop",
            frame_payload(&[0x01, 1, 0]),
            Err(Undecodable),
        ),
    ]
}

/// Seeds of the `roundtrip` target.
pub fn roundtrip() -> Vec<(&'static str, roundtrip::Input)> {
    let input = |hops: Vec<Hop>, at, mask| roundtrip::Input {
        hops,
        at,
        mask,
        ray: None,
    };
    let four: Vec<Hop> = four_hops().hops().to_vec();
    // Body byte 3 of the one-hop golden frame is 0x70; XOR 0x03 makes it an `s`.
    vec![
        ("no-hops", input(vec![], 0, 0)),
        (
            "one-hop-corrupt-cobs-code",
            input(vec![hop(1, None)], 0, 0x01),
        ),
        ("one-hop-corrupt-into-s", input(vec![hop(1, None)], 3, 0x03)),
        ("golden-four-hops-corrupt-crc", input(four, 11, 0x80)),
        (
            "s-readings",
            input(vec![hop(DELIMITER, Some(2)); 5], 4, 0x73),
        ),
        ("max-12-hops", input(widest(MAX_HOPS), 27, 0xFF)),
        (
            "13-hops-evict-one",
            input((0..13).map(|r| hop(r, Some(r % 8))).collect(), 12, 0x10),
        ),
        (
            "36-hops-evict-many",
            input((0..36).map(|r| hop(r * 7, None)).collect(), 200, 0x55),
        ),
        (
            "12-hops-ray-k2-drops-5",
            roundtrip::Input {
                ray: Some(reference::ray_left_k2()),
                ..input(widest(MAX_HOPS), 5, 0x20)
            },
        ),
        (
            "20-hops-ray-k7-keeps-5",
            roundtrip::Input {
                // A 7-sector ray of 200 robots, 45 reading 147 and 155 reading 148 (sum 0x7373):
                // the input spells two reading values (`reference::ArbRay`).
                ray: Some(Ray {
                    sector: reference::sector(6),
                    sectors: 7,
                    robots: 200,
                    sum: 0x7373,
                    sum_sq: 147 * 147 * 45 + 148 * 148 * 155,
                    votes: [10, 20, 30, 40, 50, 0, 50, 0],
                    closed: true,
                }),
                ..input((0..20).map(|r| hop(r, Some(r % 8))).collect(), 17, 0x73)
            },
        ),
    ]
}

fn setup(params: ParamsChoice, start: Start) -> Setup {
    Setup {
        rng_state: 0x5EED,
        rng_stream: 7,
        params,
        start,
    }
}

/// Valid fast parameters: 200 ± 50 ms cycles, relay 10 ms, refractory 40 ms.
fn fast(max_hops: u8, uniform: bool) -> Custom {
    Custom {
        cycle: 200,
        spread: 50,
        relay: 10,
        refractory: 40,
        tick: 1,
        uniform,
        sectors: 3,
        negotiation: 2,
        gather: 2,
        decide: 3,
        diffusion: 0.5,
        max_hops,
    }
}

/// Seeds of the `fused_node` target.
pub fn fused_node() -> Vec<(&'static str, fused_node::Input)> {
    use fused_node::{Action, Input, Step};
    let d = Step::drain;
    let held = |a| Step {
        action: a,
        hold: true,
    };
    let deadlines = |n| (0..n).map(|_| d(Action::Timeout(TimeStep::Deadline)));
    let message = |sector, hops: Vec<Hop>, time| Action::Message {
        sector,
        hops,
        ray: None,
        time,
    };
    let with_ray = |sector, hops: Vec<Hop>, ray: Ray, time| Action::Message {
        sector,
        hops,
        ray: Some(ray),
        time,
    };
    // A ray of `sector` (of `k`), with `robots` robots of which `c` read `b` and the others
    // `a` (exact sums, wire format 3), and `votes`.
    let ray = |sector: u8, k: u8, robots: u8, (a, b, c): (u8, u8, u8), v: &[u8]| {
        let mut votes = [0; MAX_SECTORS];
        votes[..v.len()].copy_from_slice(v);
        let (n, a, b, c) = (u32::from(robots), u32::from(a), u32::from(b), u32::from(c));
        Ray {
            sector: reference::sector(sector),
            sectors: k,
            robots,
            sum: (a * (n - c) + b * c) as u16,
            sum_sq: a * a * (n - c) + b * b * c,
            votes,
            closed: false,
        }
    };
    // The robot is tag 9 unless a seed says otherwise; `hop` is tag 0.
    let input = |setup, steps: Vec<Step>| Input {
        setup,
        tag: 9,
        steps,
    };
    let later = TimeStep::Forward(6_000);
    let quick = ParamsChoice::Quick {
        sectors: 3,
        negotiation: 1,
        max_hops: 10,
    };

    let mut lab = vec![
        d(Action::Reading(1)),
        d(message(1, vec![tagged(1, 0, Some(0))], later)),
        d(message(
            0,
            vec![tagged(0, 3, Some(1)), tagged(0, 2, Some(1))],
            later,
        )),
    ];
    lab.extend(deadlines(40));

    let mut framed = vec![
        d(Action::Reading(200)),
        d(Action::Framed {
            sector: 4,
            noise: b"\x00\xffsx".to_vec(),
            hops: four_hops().hops().to_vec(),
            ray: None,
            time: later,
        }),
        d(Action::Bytes {
            sector: 2,
            bytes: cat(&[GOLDEN_ONE_HOP, b"xyz", GOLDEN_S_BYTES]),
            time: later,
        }),
        d(Action::Framed {
            sector: 7,
            noise: vec![],
            hops: vec![hop(9, None)],
            ray: Some(ray(7, 8, 3, (4, 19, 1), &[0, 0, 0, 0, 0, 0, 0, 3])),
            time: later,
        }),
        d(Action::Bytes {
            sector: 1,
            bytes: cat(&[&GOLDEN_FOUR_HOPS[..7], b"ss\x72ss"]),
            time: TimeStep::Nudge(3),
        }),
    ];
    framed.extend(deadlines(12));

    let mut all_sectors: Vec<Step> = (0..8u8)
        .map(|s| {
            d(message(
                s,
                vec![tagged(s * 30, s, Some(s))],
                TimeStep::Forward(11_000),
            ))
        })
        .collect();
    all_sectors.extend(deadlines(8));

    let mut fast_cap_one = vec![d(Action::Reading(5))];
    for i in 0..6u8 {
        fast_cap_one.push(d(message(i % 3, widest(3), TimeStep::Forward(90))));
        fast_cap_one.push(d(Action::Timeout(TimeStep::Nudge(10))));
    }
    fast_cap_one.extend(deadlines(30));

    let mut invalid = fast(12, false);
    invalid.cycle = 0;

    let backwards = vec![
        d(message(1, vec![hop(3, None)], TimeStep::Forward(20_000))),
        d(Action::Timeout(TimeStep::Backward(u64::MAX))),
        d(message(0, vec![hop(4, Some(1))], TimeStep::Same)),
        d(Action::Timeout(TimeStep::Deadline)),
        d(Action::Timeout(TimeStep::Backward(5_000))),
        d(message(1, vec![hop(250, None)], TimeStep::Nudge(1))),
        d(Action::Timeout(TimeStep::Forward(u32::MAX))),
        d(Action::Timeout(TimeStep::Deadline)),
    ];

    let mut end = vec![d(Action::Reading(9))];
    end.extend(deadlines(10));
    end.push(d(message(1, vec![hop(1, None)], TimeStep::Nudge(255))));
    end.push(d(Action::Timeout(TimeStep::Forward(u32::MAX))));
    end.extend(deadlines(3));

    let mut hold: Vec<Step> = (0..12)
        .map(|_| held(Action::Timeout(TimeStep::Deadline)))
        .collect();
    hold.push(held(message(0, vec![hop(7, None)], TimeStep::Nudge(1))));
    hold.extend(deadlines(4));

    let mut full = vec![d(Action::Reading(77))];
    full.push(d(message(0, widest(MAX_HOPS), later)));
    full.push(d(message(
        1,
        (0..12).map(|r| tagged(r, r, Some(0))).collect(),
        later,
    )));
    full.extend(deadlines(25));

    let odd = vec![
        d(message(1, vec![], TimeStep::Nudge(5))),
        d(message(7, vec![hop(1, None)], TimeStep::Nudge(5))),
        d(message(1, vec![hop(2, None)], TimeStep::Same)),
        d(message(0, vec![hop(2, None)], TimeStep::Same)),
        d(Action::Timeout(TimeStep::Deadline)),
    ];

    // Robot 5: an echo of its own relay, a replay holding its tag among others, and a
    // message where one tag appears twice (its newest hop counts).
    let mut own_tag = vec![
        d(Action::Reading(2)),
        d(message(1, vec![tagged(1, 4, Some(0))], later)),
        d(message(
            0,
            vec![
                tagged(1, 4, Some(0)),
                tagged(2, 5, Some(1)),
                tagged(0, 6, Some(1)),
            ],
            later,
        )),
        d(message(0, vec![tagged(0, 5, None)], later)),
        d(message(
            0,
            vec![
                tagged(0, 7, Some(0)),
                tagged(0, 6, Some(1)),
                tagged(0, 7, Some(1)),
            ],
            later,
        )),
    ];
    own_tag.extend(deadlines(30));

    // The lab's line with rays (K = 2): the left neighbour (tag 0) sends the left side's ray,
    // the right neighbour (tag 3) the right side's; then a ray for the wrong side, one of
    // another K, the left neighbour's frame replayed on the right (followed elsewhere), a
    // farther-reaching ray from another sender, and the largest variance three robots have.
    let mut rays = vec![
        d(Action::Reading(1)),
        d(with_ray(
            1,
            vec![tagged(1, 1, Some(1)), tagged(1, 0, Some(1))],
            ray(1, 2, 2, (1, 1, 0), &[0, 2]),
            later,
        )),
        d(with_ray(
            0,
            vec![tagged(0, 2, Some(0)), tagged(0, 3, Some(0))],
            ray(0, 2, 2, (0, 0, 0), &[2, 0]),
            later,
        )),
        d(with_ray(
            0,
            vec![tagged(0, 3, None)],
            ray(1, 2, 1, (0, 0, 0), &[0, 0]),
            later,
        )),
        d(with_ray(
            1,
            vec![tagged(1, 0, None)],
            ray(1, 3, 3, (1, 1, 0), &[0, 3, 0]),
            later,
        )),
        d(with_ray(
            0,
            vec![tagged(1, 0, Some(1))],
            ray(0, 2, 9, (1, 1, 0), &[0, 9]),
            TimeStep::Nudge(3),
        )),
        d(with_ray(
            1,
            vec![tagged(1, 5, Some(1))],
            ray(1, 2, 30, (0, 2, 15), &[1, 29]),
            later,
        )),
        d(with_ray(
            1,
            vec![tagged(0, 0, Some(1))],
            ray(1, 2, 3, (0, 255, 2), &[0, 3]),
            later,
        )),
    ];
    rays.extend(deadlines(40));

    // K = 8: full 8-sector rays beside 5 hops (25 bytes), from every sector, and a relay
    // capacity the ray leaves no room in.
    let mut rays_k8: Vec<Step> = (0..8u8)
        .map(|s| {
            d(with_ray(
                s,
                widest(5),
                ray(s, 8, 200, (s * 30, s * 30 + 40, 50), &[25; 8]),
                later,
            ))
        })
        .collect();
    rays_k8.extend(deadlines(12));

    vec![
        (
            "robots-lit-left-dark-right-to-decision",
            input(setup(ParamsChoice::Robots, Start::Zero), lab),
        ),
        (
            "robots-rays-taken-refused-replayed",
            input(setup(ParamsChoice::Robots, Start::Zero), rays),
        ),
        (
            "sim2d-k8-full-rays",
            input(setup(ParamsChoice::Simulation2d, Start::Zero), rays_k8),
        ),
        (
            "quick-k5-frames-noise-unknown-sector",
            input(setup(quick, Start::Soon(1_000)), framed),
        ),
        (
            "sim2d-k8-every-sector",
            input(setup(ParamsChoice::Simulation2d, Start::Zero), all_sectors),
        ),
        (
            "fast-cycles-relay-capacity-1",
            input(
                setup(ParamsChoice::Custom(fast(1, false)), Start::Zero),
                fast_cap_one,
            ),
        ),
        (
            "invalid-params-zero-cycle",
            input(
                setup(ParamsChoice::Custom(invalid), Start::Zero),
                deadlines(2).collect(),
            ),
        ),
        (
            "time-goes-backwards",
            input(
                setup(ParamsChoice::Robots, Start::Soon(1_000_000)),
                backwards,
            ),
        ),
        (
            "end-of-time",
            input(setup(ParamsChoice::Robots, Start::NearEnd(131_000)), end),
        ),
        (
            "held-outputs-overflow",
            input(setup(quick, Start::Zero), hold),
        ),
        (
            "full-messages-evict",
            input(setup(ParamsChoice::Robots, Start::Any(1 << 40)), full),
        ),
        (
            "empty-message-and-unknown-sector",
            input(setup(ParamsChoice::Robots, Start::Zero), odd),
        ),
        (
            "own-tag-echo-replay-and-repeated-tag",
            Input {
                tag: 5,
                ..input(setup(ParamsChoice::Robots, Start::Zero), own_tag)
            },
        ),
    ]
}

/// Seeds of the `three_phase` target.
pub fn three_phase() -> Vec<(&'static str, three_phase::Input)> {
    use three_phase::{Action, Input, Msg, Num, Step};
    let d = Step::drain;
    let deadlines = |n| (0..n).map(|_| d(Action::Timeout(TimeStep::Deadline)));
    let small = |x: &[u8]| Msg::Readings(x.iter().map(|&x| Num::Small(x)).collect());
    let from = |b, msg, time| Action::Message {
        bearing: Num::Small(b),
        msg,
        time,
    };
    let input = |setup, small, steps: Vec<Step>| Input {
        setup,
        small,
        steps,
    };
    let sim = ParamsChoice::Simulation2d;
    let later = TimeStep::Forward(11_000);

    let mut lab = vec![
        d(Action::Reading(Num::Small(0))),
        d(from(0, small(&[5, 5]), later)),
        d(from(128, small(&[0, 0]), later)),
    ];
    lab.extend(deadlines(6));
    lab.push(d(from(64, Msg::Opinion(Some(Num::Small(32))), later)));
    lab.push(d(from(64, Msg::Opinion(None), later)));
    lab.extend(deadlines(10));

    let mut many: Vec<Step> = (0..20u8)
        .map(|i| d(from(i * 12, small(&[i, 2 * i, 3]), later)))
        .collect();
    many.extend(deadlines(8));

    let mut full: Vec<Step> = (0..5u8)
        .map(|i| d(from(i * 40, small(&[1, 2, 3, 4, 5, 6]), later)))
        .collect();
    full.extend(deadlines(4));

    let bits = |x: f32| Num::Bits(x.to_bits());
    let mut hostile = vec![
        d(Action::Reading(bits(f32::INFINITY))),
        d(Action::Message {
            bearing: bits(f32::NAN),
            msg: Msg::Readings(vec![bits(f32::NAN), bits(f32::MAX), bits(-f32::MAX)]),
            time: later,
        }),
        d(Action::Message {
            bearing: bits(-0.0),
            msg: Msg::Readings(vec![bits(1e30), bits(-1e30)]),
            time: later,
        }),
        d(Action::Message {
            bearing: bits(0.0),
            msg: Msg::Readings(vec![Num::Small(1)]),
            time: later,
        }),
    ];
    hostile.extend(deadlines(4));
    hostile.push(d(Action::Message {
        bearing: bits(f32::NEG_INFINITY),
        msg: Msg::Opinion(Some(bits(f32::INFINITY))),
        time: later,
    }));
    hostile.push(d(Action::Message {
        bearing: bits(1.0),
        msg: Msg::Opinion(Some(bits(-7.0))),
        time: later,
    }));
    hostile.extend(deadlines(6));

    let mut wrong = vec![
        d(from(
            0,
            Msg::Opinion(Some(Num::Small(1))),
            TimeStep::Nudge(1),
        )),
        d(from(0, Msg::Readings(vec![]), TimeStep::Nudge(1))),
    ];
    wrong.extend(deadlines(4));
    wrong.push(d(from(3, small(&[9]), TimeStep::Same)));

    let mut end = vec![d(Action::Timeout(TimeStep::Forward(2_046_820_352)))];
    end.push(d(from(1, small(&[1]), TimeStep::Nudge(200))));
    end.extend(deadlines(3));

    let mut held: Vec<Step> = (0..10)
        .map(|_| Step {
            action: Action::Timeout(TimeStep::Deadline),
            hold: true,
        })
        .collect();
    held.extend(deadlines(3));

    let mut uniform: Vec<Step> = vec![d(Action::Reading(Num::Small(3)))];
    for i in 0..8u8 {
        uniform.push(d(from(i * 31, small(&[i]), TimeStep::Forward(60))));
        uniform.push(d(from(
            i * 17,
            Msg::Opinion(Some(Num::Small(i * 30))),
            TimeStep::Forward(45),
        )));
    }
    uniform.extend(deadlines(40));

    vec![
        (
            "sim2d-gather-evaluate-diffuse-decide",
            input(setup(sim, Start::Zero), true, lab),
        ),
        (
            "default-size-twenty-bearings",
            input(setup(sim, Start::Zero), false, many),
        ),
        (
            "small-slots-and-messages-full",
            input(setup(sim, Start::Zero), true, full),
        ),
        (
            "nan-inf-and-negative-zero",
            input(setup(sim, Start::Soon(5)), true, hostile),
        ),
        (
            "wrong-phase-and-empty-readings",
            input(setup(sim, Start::Zero), true, wrong),
        ),
        (
            "end-of-time",
            input(setup(sim, Start::NearEnd(131_071)), true, end),
        ),
        (
            "robots-params-held-outputs",
            input(setup(ParamsChoice::Robots, Start::Zero), false, held),
        ),
        (
            "fast-uniform-phases",
            input(
                setup(ParamsChoice::Custom(fast(12, true)), Start::Zero),
                true,
                uniform,
            ),
        ),
    ]
}

/// A `keyed` seed; for the stream mode, what the keyed deframer must yield.
#[derive(Clone, Debug)]
pub struct KeyedSeed {
    /// File name without extension.
    pub name: &'static str,
    /// The input (mode byte first).
    pub bytes: Vec<u8>,
    /// Stream mode: every result of a deframer holding the seed's key, in order.
    pub expect: Option<Vec<Outcome>>,
}

/// Seeds of the `keyed` target.
pub fn keyed() -> Vec<KeyedSeed> {
    use FrameError::*;
    let k = &GOLDEN_KEY;
    let stream = |name, key: &[u8; 16], cuts: &[u8], s: Vec<u8>, expect| KeyedSeed {
        name,
        bytes: keyed::input(STREAM, key, &deframer::input(cuts, &s)),
        expect: Some(expect),
    };
    let framing = |name, key: &[u8; 16], hops: Vec<Hop>| KeyedSeed {
        name,
        bytes: keyed::input(
            FRAMING,
            key,
            &roundtrip::Input {
                hops,
                at: 9,
                mask: 0x40,
                ray: None,
            }
            .write(),
        ),
        expect: None,
    };
    let text = |name, t: &str| KeyedSeed {
        name,
        bytes: [&[KEY_TEXT][..], t.as_bytes()].concat(),
        expect: None,
    };
    let mut bad_tag = GOLDEN_KEYED_ONE_HOP.to_vec();
    bad_tag[8] ^= 0x01;
    vec![
        stream(
            "stream-golden-keyed-one-hop",
            k,
            &[],
            GOLDEN_KEYED_ONE_HOP.to_vec(),
            vec![Ok(one_hop())],
        ),
        stream(
            "stream-golden-keyed-four-hops-cut-4",
            k,
            &[4],
            GOLDEN_KEYED_FOUR_HOPS.to_vec(),
            vec![Ok(four_hops())],
        ),
        stream(
            "stream-golden-keyed-s-bytes-byte-by-byte",
            k,
            &[1],
            GOLDEN_KEYED_S_BYTES.to_vec(),
            vec![Ok(s_bytes())],
        ),
        stream(
            "stream-keyed-max-11-hops",
            k,
            &[],
            reference_frame(k, &wide_payload(11)),
            vec![Ok(msg(&widest(11)))],
        ),
        stream(
            "stream-keyed-12-hops-too-long",
            k,
            &[],
            reference_frame(k, &wide_payload(12)),
            vec![Err(TooLong)],
        ),
        stream(
            "stream-plain-frames-under-a-key",
            k,
            &[],
            cat(&[GOLDEN_ONE_HOP, GOLDEN_FOUR_HOPS]),
            vec![Err(BadMac), Err(BadMac)],
        ),
        stream(
            "stream-other-key",
            &[9; 16],
            &[],
            GOLDEN_KEYED_ONE_HOP.to_vec(),
            vec![Err(BadMac)],
        ),
        stream(
            "stream-truncated-then-whole",
            k,
            &[],
            cat(&[&GOLDEN_KEYED_FOUR_HOPS[..6], GOLDEN_KEYED_ONE_HOP]),
            vec![Err(TooShort), Ok(one_hop())],
        ),
        stream("stream-corrupted-tag", k, &[], bad_tag, vec![Err(BadMac)]),
        stream(
            "stream-length-lies-with-good-tag",
            k,
            &[],
            reference_frame(k, &[0x42, 1, 0]),
            vec![Err(Undecodable)],
        ),
        stream(
            "stream-golden-keyed-ray-four",
            k,
            &[],
            GOLDEN_KEYED_RAY_FOUR.to_vec(),
            vec![Ok(ray_four())],
        ),
        stream(
            "stream-keyed-max-ray-4-hops-7-sectors",
            k,
            &[],
            reference_frame(k, &ray_payload(4, &RAY_K7)),
            vec![Ok(decoded(&ray_payload(4, &RAY_K7)))],
        ),
        stream(
            "stream-keyed-ray-5-hops-7-sectors-too-long",
            k,
            &[],
            reference_frame(k, &ray_payload(5, &RAY_K7)),
            vec![Err(TooLong)],
        ),
        framing("framing-no-hops", k, vec![]),
        framing("framing-one-hop-zero-key", &[0; 16], vec![hop(1, None)]),
        framing("framing-max-11-hops", &[0xFF; 16], widest(11)),
        framing("framing-12-hops-too-many", k, widest(MAX_HOPS)),
        framing("framing-s-readings", k, vec![hop(DELIMITER, Some(3)); 6]),
        KeyedSeed {
            name: "framing-ray-k7-too-long-then-fit",
            bytes: keyed::input(
                FRAMING,
                k,
                &roundtrip::Input {
                    hops: widest(MAX_HOPS),
                    at: 3,
                    mask: 0x11,
                    ray: reference::decode_payload(&ray_payload(1, &RAY_K7))
                        .ok()
                        .and_then(|m| m.ray().copied()),
                }
                .write(),
            ),
            expect: None,
        },
        text("key-text-golden", "000102030405060708090a0b0c0d0e0f"),
        text("key-text-uppercase", "000102030405060708090A0B0C0D0E0F"),
        text("key-text-31-digits", "000102030405060708090a0b0c0d0e0"),
        text("key-text-not-hex", "0001x2030405060708090a0b0c0d0e0f"),
        text("key-text-non-ascii", "00010203040506070809\u{e9}0b0c0d0e0f"),
        text("key-text-empty", ""),
    ]
}

/// Every seed file: target, file name, bytes.
pub fn files() -> Vec<(&'static str, String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut add = |target, name: &str, bytes| out.push((target, format!("{name}.bin"), bytes));
    for s in deframer() {
        add("deframer", s.name, deframer::input(&s.cuts, &s.stream));
    }
    for s in message_decode() {
        add("message_decode", s.name, s.data);
    }
    for (name, i) in roundtrip() {
        add("roundtrip", name, i.write());
    }
    for (name, i) in fused_node() {
        add("fused_node", name, i.write());
    }
    for (name, i) in three_phase() {
        add("three_phase", name, i.write());
    }
    for s in keyed() {
        add("keyed", s.name, s.bytes);
    }
    for s in link_corpus::link_decode() {
        add("link_decode", s.name, s.data);
    }
    for (name, i) in link_corpus::link_roundtrip() {
        add("link_roundtrip", name, i.write());
    }
    for (name, i) in link_corpus::link_pump() {
        add("link_pump", name, i.write());
    }
    for (name, bytes) in link_corpus::link_host() {
        add("link_host", name, bytes);
    }
    out
}

/// Writes every seed under `corpus_dir/<target>/`, after removing what those directories held.
/// Returns the number of files written.
pub fn write(corpus_dir: &Path) -> io::Result<usize> {
    for t in crate::TARGETS {
        let dir = corpus_dir.join(t);
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        std::fs::create_dir_all(&dir)?;
    }
    let files = files();
    for (target, name, bytes) in &files {
        std::fs::write(corpus_dir.join(target).join(name), bytes)?;
    }
    Ok(files.len())
}
