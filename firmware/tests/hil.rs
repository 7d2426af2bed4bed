//! The robot's end of the HIL link (`firmware::hil::robot::run`) against a scripted host, over
//! two in-memory pipes, under tokio's paused clock. The host's real end (`hal_emu::world::hil`) is
//! tested against it in `tests/tests/hil.rs`.

use embassy_futures::select::{Either, select};
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::pipe::Pipe;
use firmware::Config;
use firmware::hil::robot::{Link, RNG_STREAM, run};
use firmware::hil::{LINK_FRAME_MAX, LinkDecoder, LinkMsg, Setup, encode};
use firmware::protocol::frame::encode as encode_light;
use firmware::protocol::{Hop, Instant, Level, Message, Tag};
use rand_pcg::Pcg32;

mod common;
use common::TokioClock;
use firmware::Clock as _;

type Wire = Pipe<NoopRawMutex, 4096>;

fn frame(msg: &LinkMsg) -> Vec<u8> {
    let mut buf = [0u8; LINK_FRAME_MAX];
    encode(msg, &mut buf).unwrap().to_vec()
}

fn setup(id: u16) -> Setup {
    Setup {
        id,
        seed: 7,
        cycle_ms: 2_000,
        spread_ms: 500,
        relay_ms: 40,
        refractory_ms: 150,
        negotiation: 10,
        adaptive: false,
        sample_ms: 40,
        host_clock: false,
    }
}

/// Everything the robot said on `wire` so far.
fn said(wire: &Wire, decoder: &mut LinkDecoder) -> Vec<LinkMsg> {
    let mut buf = [0u8; 256];
    let mut out = Vec::new();
    while let Ok(n @ 1..) = wire.try_read(&mut buf) {
        out.extend(buf[..n].iter().filter_map(|&b| decoder.push(b)).flatten());
    }
    out
}

/// Runs the robot's end with 2 receivers until `until`, the host writing `script` (at its
/// times) into the robot's input; returns what the robot said, and its link's counters.
async fn session(
    script: Vec<(Instant, Vec<u8>)>,
    until: Instant,
) -> (Vec<LinkMsg>, firmware::hil::robot::HilStats) {
    let to_robot = Wire::new();
    let from_robot = Wire::new();
    let clock = TokioClock::new();
    let link = Link::<_, 2>::new(&from_robot);
    let base = Config {
        id: 9,
        ..Config::robots()
    };
    let mut observer = ();
    let robot = run(
        &link,
        &to_robot,
        &clock,
        base,
        |seed| Pcg32::new(u64::from(seed), RNG_STREAM),
        &mut observer,
    );
    let host = async {
        for (t, bytes) in script {
            clock.sleep_until(t).await;
            to_robot.write_all(&bytes).await;
        }
        clock.sleep_until(until).await;
    };
    match select(robot, host).await {
        Either::First(never) => match never {},
        Either::Second(()) => {}
    }
    let mut d = LinkDecoder::new();
    (said(&from_robot, &mut d), link.stats())
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn it_says_hello_until_set_up_then_runs_and_answers_heartbeats() {
    let t = Instant::from_millis;
    let script = vec![
        (
            t(1_200),
            frame(&LinkMsg::Reading {
                quantity: 0,
                level: 200,
            }),
        ),
        (t(1_200), frame(&LinkMsg::Setup(setup(3)))),
        (t(1_700), frame(&LinkMsg::Heartbeat(0))),
        (t(2_200), frame(&LinkMsg::Heartbeat(1))),
    ];
    let (msgs, stats) = session(script, t(10_000)).await;
    // Hellos at 0, 0.5 and 1 s (id 9, two receivers, version 1), then none.
    let hellos: Vec<_> = msgs
        .iter()
        .take_while(|m| matches!(m, LinkMsg::Hello { .. }))
        .collect();
    assert_eq!(hellos.len(), 3, "{msgs:?}");
    assert_eq!(
        hellos[0],
        &LinkMsg::Hello {
            version: firmware::hil::LINK_VERSION,
            id: 9,
            sectors: 2,
            host_clock: false,
        }
    );
    assert_eq!(
        msgs.iter()
            .filter(|m| matches!(m, LinkMsg::Hello { .. }))
            .count(),
        3
    );
    // Each heartbeat answered with its number, once.
    let beats: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            LinkMsg::Heartbeat(s) => Some(*s),
            _ => None,
        })
        .collect();
    assert_eq!(beats, [0, 1]);
    // The robot program ran with the setup's timing: an initiation per 2 s cycle (at least 3
    // in 8.8 s), each a light frame carrying the robot's reading 200 and its tag (id 3).
    let tx: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            LinkMsg::Tx(b) => Some(b.clone()),
            _ => None,
        })
        .collect();
    assert!(tx.len() >= 3, "{msgs:?}");
    let mut light = firmware::protocol::Deframer::new();
    let first = light.frames(&tx[0]).next().unwrap().unwrap();
    assert_eq!(first.hops()[0].reading, Level(200));
    assert_eq!(first.hops()[0].tag, Tag::from_id(3));
    assert_eq!(stats.setups, 1);
    assert_eq!(stats.link.errors(), 0);
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn light_reaches_its_receiver_and_bad_input_is_counted_not_fatal() {
    let t = Instant::from_millis;
    // A neighbour's initiation on the left receiver (sector 1) every 2 s, lit (200) while the
    // robot reads dark (30): the left side is the diverse one.
    let hop = Hop {
        reading: Level(200),
        pref: None,
        tag: Tag::from_id(1),
    };
    let light = encode_light(&Message::from_hops(&[hop]).unwrap()).unwrap();
    let rx = frame(&LinkMsg::Rx {
        sector: 1,
        bytes: heapless::Vec::from_slice(&light).unwrap(),
    });
    let mut script = vec![
        (
            t(0),
            frame(&LinkMsg::Reading {
                quantity: 0,
                level: 30,
            }),
        ),
        (t(0), frame(&LinkMsg::Setup(setup(2)))),
        // Garbage, an Rx for a sector it does not have, a message only a robot sends.
        (t(100), b"\x00noise\x00".to_vec()),
        (
            t(100),
            frame(&LinkMsg::Rx {
                sector: 5,
                bytes: heapless::Vec::from_slice(b"ss").unwrap(),
            }),
        ),
        (t(100), frame(&LinkMsg::Led(1))),
    ];
    for k in 0..30u64 {
        script.push((t(300 + 2_000 * k), rx.clone()));
        script.push((t(300 + 2_000 * k), frame(&LinkMsg::Heartbeat(k as u32))));
    }
    let (msgs, stats) = session(script, t(62_000)).await;
    assert_eq!(stats.link.errors(), 1, "the garbage: {stats:?}");
    assert_eq!(stats.unexpected, 2, "{stats:?}");
    assert_eq!(stats.rx_lost, 0);
    // It relayed what it heard, and decided left (green: code 2) at a period's end.
    let leds: Vec<u8> = msgs
        .iter()
        .filter_map(|m| match m {
            LinkMsg::Led(c) => Some(*c),
            _ => None,
        })
        .collect();
    assert!(leds.contains(&2), "{leds:?}");
    // Every heartbeat answered.
    let beats = msgs
        .iter()
        .filter(|m| matches!(m, LinkMsg::Heartbeat(_)))
        .count();
    assert_eq!(beats, 30);
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn a_second_setup_restarts_the_robot_program_afresh() {
    let t = Instant::from_millis;
    let script = vec![
        (
            t(0),
            frame(&LinkMsg::Reading {
                quantity: 0,
                level: 100,
            }),
        ),
        (t(0), frame(&LinkMsg::Setup(setup(1)))),
        (t(5_000), frame(&LinkMsg::Setup(setup(4)))),
    ];
    let (msgs, stats) = session(script, t(9_000)).await;
    assert_eq!(stats.setups, 2);
    // Frames before 5 s carry tag 1, after it tag 4.
    let mut light = firmware::protocol::Deframer::new();
    let tags: Vec<Tag> = msgs
        .iter()
        .filter_map(|m| match m {
            LinkMsg::Tx(b) => light.frames(b).next().and_then(Result::ok),
            _ => None,
        })
        .map(|m| m.hops()[0].tag)
        .collect();
    assert!(
        tags.contains(&Tag::from_id(1)) && tags.contains(&Tag::from_id(4)),
        "{tags:?}"
    );
    let last = tags.last().copied();
    assert_eq!(last, Some(Tag::from_id(4)));
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn an_image_with_six_receivers_runs_whatever_its_configuration_says() {
    // The image's base configuration is the lab's (two sectors); its link has six receivers,
    // as QEMU's hil6 image: the robot program runs with six (it once refused the setup and the
    // robot sat silent in the plane).
    let to_robot = Wire::new();
    let from_robot = Wire::new();
    let clock = TokioClock::new();
    let link = Link::<_, 6>::new(&from_robot);
    let mut observer = ();
    let robot = run(
        &link,
        &to_robot,
        &clock,
        Config::robots(),
        |seed| Pcg32::new(u64::from(seed), RNG_STREAM),
        &mut observer,
    );
    let host = async {
        to_robot
            .write_all(&frame(&LinkMsg::Reading {
                quantity: 0,
                level: 90,
            }))
            .await;
        to_robot.write_all(&frame(&LinkMsg::Setup(setup(5)))).await;
        clock.sleep_until(Instant::from_secs(7)).await;
    };
    if let Either::First(never) = select(robot, host).await {
        match never {}
    }
    let msgs = said(&from_robot, &mut LinkDecoder::new());
    assert!(
        msgs.iter()
            .any(|m| matches!(m, LinkMsg::Hello { sectors: 6, .. })),
        "{msgs:?}"
    );
    let tx = msgs.iter().filter(|m| matches!(m, LinkMsg::Tx(_))).count();
    assert!(tx >= 2, "{msgs:?}");
    assert!(!msgs.iter().any(|m| matches!(m, LinkMsg::Refused(_))));
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn a_setup_the_robot_program_refuses_is_answered_with_why() {
    let t = Instant::from_millis;
    let bad = Setup {
        spread_ms: 5_000,
        ..setup(1)
    };
    let script = vec![(t(0), frame(&LinkMsg::Setup(bad)))];
    let (msgs, stats) = session(script, t(3_000)).await;
    assert_eq!(stats.setups, 1);
    assert!(msgs.contains(&LinkMsg::Refused(1)), "{msgs:?}");
    assert!(!msgs.iter().any(|m| matches!(m, LinkMsg::Tx(_))));
}

#[tokio::test(flavor = "current_thread", start_paused = true)]
async fn a_running_robot_says_hello_when_asked_and_restarts_at_the_next_setup() {
    // A board that ran already meets a new host (the next run over a serial port): the host
    // asks who it is, the robot says hello, and the new setup restarts it.
    let t = Instant::from_millis;
    let ask = frame(&LinkMsg::Hello {
        version: firmware::hil::LINK_VERSION,
        id: 0,
        sectors: 0,
        host_clock: false,
    });
    let script = vec![
        (
            t(0),
            frame(&LinkMsg::Reading {
                quantity: 0,
                level: 100,
            }),
        ),
        (t(0), frame(&LinkMsg::Setup(setup(1)))),
        (t(0), frame(&LinkMsg::Heartbeat(0))),
        (t(4_000), ask),
        (t(4_100), frame(&LinkMsg::Setup(setup(6)))),
        (t(4_100), frame(&LinkMsg::Heartbeat(0))),
    ];
    let (msgs, stats) = session(script, t(8_000)).await;
    assert_eq!(stats.setups, 2);
    // One hello at boot, one when asked; each heartbeat answered.
    let hellos = msgs
        .iter()
        .filter(|m| matches!(m, LinkMsg::Hello { .. }))
        .count();
    assert_eq!(hellos, 2, "{msgs:?}");
    let beats = msgs
        .iter()
        .filter(|m| matches!(m, LinkMsg::Heartbeat(0)))
        .count();
    assert_eq!(beats, 2, "{msgs:?}");
    let mut light = firmware::protocol::Deframer::new();
    let last = msgs
        .iter()
        .filter_map(|m| match m {
            LinkMsg::Tx(b) => light.frames(b).next().and_then(Result::ok),
            _ => None,
        })
        .last()
        .map(|m| m.hops()[0].tag);
    assert_eq!(last, Some(Tag::from_id(6)));
}
