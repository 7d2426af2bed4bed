//! The seed corpus of the `link_*` targets (the hardware-in-the-loop link, `docs/hil.md`):
//! golden and valid frames of every `LinkMsg` variant, wrong versions, truncated frames,
//! garbage, lost delimiters, bad stuffing and checks, non-canonical varints, and scripted runs
//! of the robot's end on its own clock and on the host's. [`crate::corpus::files`] writes them
//! with the others; `tests/corpus.rs` checks them.

use firmware::hil::robot::HELD;
use firmware::hil::{CHUNK_MAX, LINK_FRAME_MAX, LINK_VERSION, LinkError, LinkMsg, Setup};
use firmware::protocol::auth::SwarmKey;

use crate::link_decode::{BODY, PAYLOAD, STREAM};
use crate::link_host::{self, Batch, Item};
use crate::link_pump::{self, Op};
use crate::link_ref::{self, LONGEST_SETUP, chunk, every_kind, frame};
use crate::link_roundtrip;

/// A `link_decode` seed: the input and every result its stream gives (before the target's own
/// recovery frames).
#[derive(Clone, Debug)]
pub struct DecodeSeed {
    /// File name without extension.
    pub name: &'static str,
    /// The input (mode byte first).
    pub data: Vec<u8>,
    /// Every result of its stream, in order.
    pub expect: Vec<Result<LinkMsg, LinkError>>,
}

fn hello(version: u8) -> LinkMsg {
    LinkMsg::Hello {
        version,
        id: 300,
        sectors: 2,
        host_clock: true,
    }
}

fn with_mode(mode: u8, bytes: &[u8]) -> Vec<u8> {
    [&[mode], bytes].concat()
}

/// The `link_decode` seeds.
pub fn link_decode() -> Vec<DecodeSeed> {
    let hb = frame(&LinkMsg::Heartbeat(7));
    let ok = |m: LinkMsg| Ok::<_, LinkError>(m);
    let all: Vec<u8> = every_kind().iter().flat_map(frame).collect();
    let mut corrupt_crc = hb.clone();
    corrupt_crc[3] ^= 0x01;
    let seed = |name, mode, bytes: Vec<u8>, expect| DecodeSeed {
        name,
        data: with_mode(mode, &bytes),
        expect,
    };
    vec![
        seed(
            "golden-heartbeat-1",
            STREAM,
            vec![0x05, 0x05, 0x01, 0xDB, 0xF2, 0x00],
            vec![ok(LinkMsg::Heartbeat(1))],
        ),
        seed(
            "golden-hello-v3",
            STREAM,
            vec![0x01, 0x08, 0x03, 0xAC, 0x02, 0x02, 0x01, 0xA5, 0x5D, 0x00],
            vec![ok(hello(3))],
        ),
        seed(
            "golden-key-00-0f",
            STREAM,
            vec![
                0x02, 0x0A, 0x12, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0A, 0x0B,
                0x0C, 0x0D, 0x0E, 0x0F, 0x05, 0x30, 0x00,
            ],
            vec![ok(LinkMsg::Key(SwarmKey::new(std::array::from_fn(|i| {
                i as u8
            }))))],
        ),
        seed(
            "hello-version-2",
            STREAM,
            frame(&hello(2)),
            vec![Err(LinkError::UnknownVersion(2))],
        ),
        seed(
            "golden-sync-55000",
            STREAM,
            vec![0x07, 0x08, 0xD8, 0xAD, 0x03, 0x77, 0x96, 0x00],
            vec![ok(LinkMsg::Sync(55_000))],
        ),
        seed(
            "golden-idle-0-55",
            STREAM,
            vec![0x02, 0x09, 0x04, 0x37, 0xB9, 0x14, 0x00],
            vec![ok(LinkMsg::Idle { now: 0, next: 55 })],
        ),
        seed(
            "every-variant-back-to-back",
            STREAM,
            [&[0][..], &all].concat(),
            every_kind().into_iter().map(ok).collect(),
        ),
        seed(
            "hello-version-1",
            STREAM,
            frame(&hello(1)),
            vec![Err(LinkError::UnknownVersion(1))],
        ),
        seed(
            "hello-version-4-then-led",
            STREAM,
            [frame(&hello(4)), frame(&LinkMsg::Led(1))].concat(),
            vec![Err(LinkError::UnknownVersion(4)), ok(LinkMsg::Led(1))],
        ),
        seed(
            "truncated-then-delimiter-then-frame",
            STREAM,
            [&hb[..3], &[0], &hb].concat(),
            vec![Err(LinkError::BadCobs), ok(LinkMsg::Heartbeat(7))],
        ),
        seed(
            "truncated-at-end-of-stream",
            STREAM,
            [hb.as_slice(), &hb[..4]].concat(),
            vec![ok(LinkMsg::Heartbeat(7))],
        ),
        seed(
            "garbage-runs-into-frame",
            STREAM,
            [&b"noise"[..], &hb, &hb].concat(),
            vec![Err(LinkError::BadCobs), ok(LinkMsg::Heartbeat(7))],
        ),
        seed(
            "garbage-delimited-then-frame",
            STREAM,
            [&b"noise\0"[..], &hb].concat(),
            vec![Err(LinkError::BadCobs), ok(LinkMsg::Heartbeat(7))],
        ),
        seed(
            "lost-delimiter-too-long",
            STREAM,
            [&[0x42; LINK_FRAME_MAX + 20][..], &[0], &hb].concat(),
            vec![Err(LinkError::TooLong), ok(LinkMsg::Heartbeat(7))],
        ),
        seed(
            "body-of-link-frame-max-kept",
            STREAM,
            [&[0x01; LINK_FRAME_MAX][..], &[0]].concat(),
            vec![Err(LinkError::BadCheck)],
        ),
        seed(
            "body-one-past-link-frame-max",
            STREAM,
            [&[0x01; LINK_FRAME_MAX + 1][..], &[0], &hb].concat(),
            vec![Err(LinkError::TooLong), ok(LinkMsg::Heartbeat(7))],
        ),
        seed("empty-frames", STREAM, vec![0, 0, 0], vec![]),
        seed(
            "bad-crc",
            STREAM,
            corrupt_crc,
            vec![Err(LinkError::BadCheck)],
        ),
        seed(
            "cobs-code-past-end",
            STREAM,
            vec![0x05, 0x01, 0x00],
            vec![Err(LinkError::BadCobs)],
        ),
        seed(
            "too-short",
            STREAM,
            vec![0x03, 0x01, 0x02, 0x00],
            vec![Err(LinkError::TooShort)],
        ),
        seed(
            "payload-key-without-its-bytes",
            PAYLOAD,
            vec![0x0A],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-key-one-byte-short",
            PAYLOAD,
            [&[0x0A][..], &[0x11; 15]].concat(),
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-variant-11",
            PAYLOAD,
            vec![0x0B],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-chunk-of-33",
            PAYLOAD,
            [&[0x01, 33][..], &[0x55; 33]].concat(),
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-byte-left-over",
            PAYLOAD,
            vec![0x04, 0x01, 0x00],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-rx-cut-short",
            PAYLOAD,
            vec![0x02, 0x01, 0x02, 0xAA],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-empty",
            PAYLOAD,
            vec![],
            vec![Err(LinkError::TooShort)],
        ),
        seed(
            "payload-overlong-variant-varint",
            PAYLOAD,
            vec![0x84, 0x00, 0x02],
            vec![ok(LinkMsg::Led(2))],
        ),
        seed(
            "payload-u32-varint-too-wide",
            PAYLOAD,
            vec![0x05, 0xFF, 0xFF, 0xFF, 0xFF, 0x10],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-hello-bool-2",
            PAYLOAD,
            vec![0x00, 0x02, 0x01, 0x02, 0x02],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-hello-version-0-trailing",
            PAYLOAD,
            vec![0x00, 0x00, 0x01, 0x02, 0x00, 0x00],
            vec![Err(LinkError::Undecodable)],
        ),
        seed(
            "payload-longest-setup",
            PAYLOAD,
            link_ref::payload_of(&LinkMsg::Setup(LONGEST_SETUP)),
            vec![ok(LinkMsg::Setup(LONGEST_SETUP))],
        ),
        seed(
            "payload-setup-overlong-tag-40",
            PAYLOAD,
            [
                &[0x86, 0x00][..],
                &link_ref::payload_of(&LinkMsg::Setup(LONGEST_SETUP))[1..],
            ]
            .concat(),
            vec![ok(LinkMsg::Setup(LONGEST_SETUP))],
        ),
        seed(
            "payload-idle-max",
            PAYLOAD,
            link_ref::payload_of(&LinkMsg::Idle {
                now: u32::MAX,
                next: u32::MAX,
            }),
            vec![ok(LinkMsg::Idle {
                now: u32::MAX,
                next: u32::MAX,
            })],
        ),
        seed(
            "body-without-zeros",
            BODY,
            hb[..hb.len() - 1].to_vec(),
            vec![ok(LinkMsg::Heartbeat(7))],
        ),
    ]
}

/// The `link_roundtrip` seeds.
pub fn link_roundtrip() -> Vec<(&'static str, link_roundtrip::Input)> {
    let names = [
        "hello",
        "tx",
        "rx-zeros",
        "reading",
        "led",
        "heartbeat",
        "longest-setup",
        "refused",
        "sync",
        "idle-max",
    ];
    let mut out: Vec<_> = names
        .into_iter()
        .zip(every_kind())
        .enumerate()
        .map(|(i, (name, msg))| {
            (
                name,
                link_roundtrip::Input {
                    msg,
                    garbage: if i % 2 == 0 {
                        b"noise\0\x01".to_vec()
                    } else {
                        Vec::new()
                    },
                    cut: 3 + i as u8,
                    at: i as u8,
                    mask: 1 << (i % 8),
                },
            )
        })
        .collect();
    let input = |msg, garbage: &[u8], cut, at, mask| link_roundtrip::Input {
        msg,
        garbage: garbage.to_vec(),
        cut,
        at,
        mask,
    };
    out.extend([
        ("hello-version-1", input(hello(1), b"", 5, 2, 0xFF)),
        ("hello-version-255", input(hello(255), b"\0", 0, 0, 0)),
        ("tx-empty", input(LinkMsg::Tx(chunk(&[])), b"", 1, 0, 0x80)),
        (
            "rx-unknown-sector-full-chunk",
            input(
                LinkMsg::Rx {
                    sector: 200,
                    bytes: chunk(&[0xFF; CHUNK_MAX]),
                },
                &[0x42; 2 * LINK_FRAME_MAX],
                40,
                39,
                0x42,
            ),
        ),
        (
            "setup-corrupt-code-byte",
            input(LinkMsg::Setup(LONGEST_SETUP), b"", 20, 0, 0x03),
        ),
    ]);
    out
}

fn host_setup(host_clock: bool) -> LinkMsg {
    LinkMsg::Setup(Setup {
        id: 3,
        seed: 1,
        cycle_ms: 1000,
        spread_ms: 100,
        relay_ms: 50,
        refractory_ms: 200,
        negotiation: 3,
        adaptive: false,
        sample_ms: 500,
        host_clock,
    })
}

fn rx(sector: u8, n: usize) -> LinkMsg {
    LinkMsg::Rx {
        sector,
        bytes: chunk(&vec![0x73; n]),
    }
}

/// The `link_pump` seeds.
pub fn link_pump() -> Vec<(&'static str, link_pump::Input)> {
    let script = |can_follow, ops| link_pump::Input { can_follow, ops };
    let reading = |quantity, level| LinkMsg::Reading { quantity, level };
    vec![
        (
            "own-clock-run",
            script(
                false,
                vec![
                    Op::Msgs(vec![LinkMsg::Hello {
                        version: LINK_VERSION,
                        id: 0,
                        sectors: 0,
                        host_clock: false,
                    }]),
                    Op::Msgs(vec![reading(0, 40), reading(1, 90), host_setup(false)]),
                    Op::Msgs(vec![LinkMsg::Heartbeat(0), rx(0, 10), rx(1, 32)]),
                    Op::Read { sector: 0, n: 4 },
                    Op::Read { sector: 1, n: 200 },
                    Op::Msgs(vec![LinkMsg::Heartbeat(1)]),
                ],
            ),
        ),
        (
            "host-clock-run",
            script(
                true,
                vec![
                    Op::Msgs(vec![
                        reading(0, 40),
                        host_setup(true),
                        LinkMsg::Heartbeat(0),
                    ]),
                    Op::Msgs(vec![LinkMsg::Sync(0)]),
                    Op::Alarm(1000),
                    Op::Idle,
                    Op::Msgs(vec![rx(0, 9), reading(1, 7)]),
                    Op::Idle,
                    Op::Msgs(vec![LinkMsg::Sync(1000)]),
                    Op::Read { sector: 0, n: 9 },
                    Op::Alarm(u64::MAX),
                    Op::Idle,
                ],
            ),
        ),
        (
            "held-overflow",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(0)]),
                    Op::Idle,
                    Op::Msgs((0..HELD + 4).map(|i| rx((i % 2) as u8, 20)).collect()),
                    Op::Msgs(vec![LinkMsg::Sync(5)]),
                    Op::Idle,
                    Op::Read { sector: 0, n: 255 },
                ],
            ),
        ),
        (
            "sync-backwards",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(500)]),
                    Op::Idle,
                    Op::Msgs(vec![LinkMsg::Sync(100)]),
                    Op::Idle,
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(100)]),
                    Op::Idle,
                ],
            ),
        ),
        (
            "two-syncs-one-idle",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(1), LinkMsg::Sync(2)]),
                    Op::Idle,
                    Op::Idle,
                ],
            ),
        ),
        (
            "sync-on-own-clock",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(false), LinkMsg::Sync(5)]),
                    Op::Idle,
                    Op::Msgs(vec![LinkMsg::Idle { now: 5, next: 6 }]),
                ],
            ),
        ),
        (
            "host-clock-asked-of-a-robot-that-cannot",
            script(
                false,
                vec![Op::Msgs(vec![host_setup(true), LinkMsg::Sync(5)]), Op::Idle],
            ),
        ),
        (
            "setup-among-held",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(0)]),
                    Op::Idle,
                    Op::Msgs(vec![
                        rx(0, 5),
                        host_setup(false),
                        rx(1, 5),
                        LinkMsg::Sync(9),
                    ]),
                    Op::Idle,
                    Op::Msgs(vec![rx(0, 1)]),
                ],
            ),
        ),
        (
            "heartbeats-before-setup",
            script(
                true,
                vec![
                    Op::Msgs(vec![LinkMsg::Heartbeat(1), LinkMsg::Heartbeat(2)]),
                    Op::Msgs(vec![hello(LINK_VERSION)]),
                    Op::Msgs(vec![host_setup(false)]),
                    Op::Msgs(vec![LinkMsg::Heartbeat(3), hello(LINK_VERSION)]),
                ],
            ),
        ),
        (
            "pipe-overflow",
            script(false, vec![Op::Msgs((0..5).map(|_| rx(0, 32)).collect())]),
        ),
        (
            "robot-messages-to-a-robot",
            script(
                false,
                vec![Op::Msgs(vec![
                    LinkMsg::Tx(chunk(b"ss")),
                    LinkMsg::Led(1),
                    LinkMsg::Refused(2),
                    rx(5, 3),
                    reading(2, 1),
                    hello(3),
                ])],
            ),
        ),
        (
            "garbage-truncation-uart-errors",
            script(
                true,
                vec![
                    Op::Bytes(b"noise".to_vec()),
                    Op::UartError,
                    Op::Bytes(frame(&host_setup(true))[..5].to_vec()),
                    Op::Bytes(vec![0]),
                    Op::Msgs(vec![host_setup(true)]),
                    Op::Bytes(vec![0x42; 60]),
                    Op::UartError,
                    Op::Bytes(vec![0]),
                    Op::Msgs(vec![LinkMsg::Sync(3)]),
                    Op::Idle,
                ],
            ),
        ),
        (
            "writer-fails",
            script(
                true,
                vec![
                    Op::WriterFails(true),
                    Op::Msgs(vec![
                        hello(LINK_VERSION),
                        LinkMsg::Key(SwarmKey::new([7; 16])),
                        host_setup(true),
                        LinkMsg::Heartbeat(9),
                    ]),
                    Op::Msgs(vec![LinkMsg::Sync(1)]),
                    Op::Idle,
                    Op::WriterFails(false),
                    Op::Msgs(vec![LinkMsg::Heartbeat(10), LinkMsg::Sync(2)]),
                    Op::Idle,
                ],
            ),
        ),
        (
            "alarm-beyond-u32",
            script(
                true,
                vec![
                    Op::Msgs(vec![host_setup(true), LinkMsg::Sync(u32::MAX)]),
                    Op::Alarm(1 << 33),
                    Op::Idle,
                    Op::Msgs(vec![LinkMsg::Sync(u32::MAX)]),
                    Op::Alarm(u64::from(u32::MAX) - 1),
                    Op::Idle,
                ],
            ),
        ),
    ]
}

/// The `link_host` seeds: (name, input).
pub fn link_host() -> Vec<(&'static str, Vec<u8>)> {
    let stream = |cuts: &[u8], s: &[u8]| {
        [&[link_host::STREAM][..], &crate::deframer::input(cuts, s)].concat()
    };
    let all: Vec<u8> = every_kind().iter().flat_map(frame).collect();
    let item = |garbage: Option<&[u8]>, msg| Item {
        garbage: garbage.map(<[u8]>::to_vec),
        msg,
    };
    let batch = |items, cuts: &[u8]| {
        Batch {
            items,
            cuts: cuts.to_vec(),
        }
        .write()
    };
    let answer = vec![
        item(None, LinkMsg::Tx(chunk(b"ss\x70\x32\x72\x70\x43\xa6ss"))),
        item(None, LinkMsg::Led(1)),
        item(None, LinkMsg::Heartbeat(4)),
        item(
            None,
            LinkMsg::Idle {
                now: 1000,
                next: 1500,
            },
        ),
    ];
    vec![
        ("every-variant-whole", stream(&[], &all)),
        ("every-variant-byte-by-byte", stream(&[1], &all)),
        ("every-variant-odd-reads", stream(&[7, 3, 40, 0], &all)),
        (
            "garbage-and-frames",
            stream(
                &[5],
                &[&b"noise"[..], &all, &[0x42; 50], &[0], &all].concat(),
            ),
        ),
        ("a-batch-to-its-idle", batch(answer.clone(), &[3, 11])),
        (
            "a-batch-with-garbage",
            batch(
                vec![
                    item(Some(b"noise"), LinkMsg::Led(2)),
                    item(
                        Some(&[0x42; link_host::GARBAGE_MAX]),
                        LinkMsg::Idle {
                            now: 5,
                            next: u32::MAX,
                        },
                    ),
                    item(Some(&frame(&LinkMsg::Led(9))[..4]), LinkMsg::Led(0)),
                ],
                &[2],
            ),
        ),
        (
            "a-batch-ending-in-another-version",
            batch(vec![item(None, LinkMsg::Led(1)), item(None, hello(1))], &[]),
        ),
        (
            "a-long-batch",
            batch(
                (0..link_host::BATCH_MAX as u32)
                    .map(|i| item(None, LinkMsg::Heartbeat(i)))
                    .collect(),
                &[31, 32, 33],
            ),
        ),
    ]
}
