//! Robots in the loop without QEMU: the host's end of the link (`hal_emu::world::hil`) against the
//! unchanged robot program behind the robot's end (`firmware::hil::robot::run`), in this
//! process over a channel (`loopback`), on the run's virtual clock. The same bridge serves QEMU
//! robots and boards (`cimax arena --hil`, `.ci/run`).

mod common;

use hal_emu::judge::{PAPER_PATTERNS, judge, leds_str};
use hal_emu::world::hil::{HilRobot, Transport};
use hal_emu::{ArenaConfig, ArenaError};
use protocol::Duration;

/// The lab line of [`common::lab`] with the robots at `in_loop` in the loop, in this process.
fn lab(pattern: &str, seed: u64, in_loop: &[usize]) -> ArenaConfig {
    let mut c = common::lab(pattern, seed);
    c.hil = in_loop
        .iter()
        .map(|&robot| HilRobot {
            clock: hal_emu::world::hil::HilClock::Wall,
            robot,
            transport: Transport::InProcess,
        })
        .collect();
    c
}

#[test]
fn four_robots_in_the_loop_light_the_expected_leds() {
    for pattern in PAPER_PATTERNS {
        for seed in 1..=2 {
            let cfg = lab(pattern, seed, &[0, 1, 2, 3]);
            assert!(
                !cfg.real_time(),
                "in-process robots share the virtual clock"
            );
            let r = judge(&cfg).unwrap();
            assert!(
                r.success,
                "pattern {pattern} seed {seed}: LEDs {} expected {}",
                leds_str(&r.leds),
                leds_str(r.expected.as_deref().unwrap_or_default())
            );
            let hil = &r.report.hil;
            assert_eq!(hil.len(), 4);
            for (i, h) in hil.iter().enumerate() {
                assert_eq!((h.robot, h.hello_id), (i, i as u16));
                assert_eq!(h.transport, "loopback");
                assert_eq!(h.link_errors, 0, "{h:?}");
                // Every robot transmits its initiations (one per cycle, 30 cycles) and hears
                // its neighbours'.
                assert!(h.tx >= 25, "{h:?}");
                assert!(h.rx_bytes > 100, "{h:?}");
                assert!(h.frames_received > h.tx, "{h:?}");
                // It answered the host's heartbeats (two a second), at once in virtual time.
                assert!(h.round_trips > 4000, "{h:?}");
                assert_eq!(h.rtt_max_us, 0, "{h:?}");
                assert!(h.bytes_sent > h.frames_sent && h.bytes_received > h.frames_received);
            }
            // The medium put their frames on air like any robot's.
            assert!(r.report.medium.delivered > 50, "{:?}", r.report.medium);
        }
    }
}

#[test]
fn a_mixed_line_of_linked_and_virtual_robots_decides_right() {
    for (pattern, in_loop) in [("11000", &[0, 1][..]), ("1110000000", &[4, 9])] {
        for seed in 1..=3 {
            let mut cfg = lab(pattern, seed, in_loop);
            cfg.duration = Duration::from_secs(4 * 10 * 70);
            let r = judge(&cfg).unwrap();
            assert!(
                r.success,
                "{pattern} with {in_loop:?} in the loop, seed {seed}: LEDs {}",
                leds_str(&r.leds)
            );
            assert_eq!(r.report.hil.len(), in_loop.len());
        }
    }
}

#[test]
fn the_same_seed_gives_the_same_run() {
    let cfg = lab("1100", 5, &[1, 2]);
    let a = judge(&cfg).unwrap();
    let b = judge(&cfg).unwrap();
    assert_eq!(a.report.leds, b.report.leds);
    assert_eq!(a.report.hil, b.report.hil);
}

#[test]
fn places_the_link_cannot_take_are_refused() {
    let bad = |cfg: ArenaConfig, why: &str| {
        let e = hal_emu::run(&cfg).unwrap_err();
        assert!(matches!(&e, ArenaError::Hil(m) if m.contains(why)), "{e}");
    };
    bad(lab("1100", 1, &[4]), "no place 4");
    bad(lab("1100", 1, &[1, 1]), "taken twice");
    let mut c = lab("1100", 1, &[1]);
    c.kills = vec![(protocol::Instant::from_secs(10), 1)];
    bad(c, "cannot be killed");
    let mut c = lab("1100", 1, &[1]);
    c.robot.key = Some(protocol::SwarmKey::new(*b"sixteen byte key"));
    bad(c, "gives the swarm key only to robots on the arena's clock");
}

/// A robot on a TCP socket that follows `script` (what it writes after accepting, then
/// whether it keeps the socket open), and the run's error with it in place 0 of a lab line.
fn scripted(script: Vec<Vec<u8>>, keep_open: bool) -> String {
    use std::io::Write;
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let robot = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        for b in script {
            s.write_all(&b).unwrap();
        }
        if keep_open {
            // Hold the socket until the host closes it.
            let mut sink = [0u8; 256];
            while std::io::Read::read(&mut s, &mut sink).is_ok_and(|n| n > 0) {}
        }
    });
    let mut cfg = lab("1100", 1, &[]);
    cfg.hil = vec![HilRobot {
        clock: hal_emu::world::hil::HilClock::Wall,
        robot: 0,
        transport: Transport::Tcp(format!("127.0.0.1:{port}")),
    }];
    cfg.hil_timeouts.hello = Duration::from_millis(1500);
    cfg.hil_timeouts.silence = Duration::from_millis(1500);
    assert!(cfg.real_time());
    let wall = std::time::Instant::now();
    let e = hal_emu::run(&cfg).expect_err("the robot fails the run");
    // The run ends at the failure, not at its end (2100 s).
    assert!(wall.elapsed() < std::time::Duration::from_secs(20));
    robot.join().unwrap();
    let ArenaError::Robot(f) = e else {
        panic!("not a robot failure: {e}");
    };
    assert_eq!((f.robot, f.seed, f.panicked), (0, 1, false));
    f.what()
}

fn frame(msg: &firmware::hil::LinkMsg) -> Vec<u8> {
    let mut buf = [0u8; firmware::hil::LINK_FRAME_MAX];
    firmware::hil::encode(msg, &mut buf).unwrap().to_vec()
}

fn hello(version: u8, sectors: u8) -> Vec<u8> {
    frame(&firmware::hil::LinkMsg::Hello {
        version,
        id: 0,
        sectors,
        host_clock: false,
    })
}

#[test]
fn a_robot_that_never_says_hello_fails_the_run_by_name() {
    // Garbage, but no hello.
    let e = scripted(vec![b"\x00garbage\x00".to_vec()], true);
    assert!(
        e.starts_with("robot 0 failed: never said hello over tcp:127.0.0.1:"),
        "{e}"
    );
}

#[test]
fn another_link_version_or_other_sectors_are_refused_by_name() {
    let e = scripted(vec![hello(1, 2)], true);
    assert!(e.contains("speaks link version 1"), "{e}");
    assert!(
        e.contains(&format!("this host speaks {}", firmware::hil::LINK_VERSION)),
        "{e}"
    );
    let e = scripted(vec![hello(firmware::hil::LINK_VERSION, 3)], true);
    assert!(e.contains("has 3 receivers"), "{e}");
}

#[test]
fn a_robot_that_disconnects_or_goes_silent_fails_the_run() {
    let e = scripted(vec![hello(firmware::hil::LINK_VERSION, 2)], false);
    assert!(e.contains("link ended (disconnected)"), "{e}");
    let e = scripted(
        vec![
            hello(firmware::hil::LINK_VERSION, 2),
            frame(&firmware::hil::LinkMsg::Heartbeat(0)),
        ],
        true,
    );
    assert!(e.contains("stopped its heartbeat"), "{e}");
}

#[test]
fn a_robot_that_reboots_during_the_run_fails_it() {
    let e = scripted(
        vec![
            hello(firmware::hil::LINK_VERSION, 2),
            frame(&firmware::hil::LinkMsg::Heartbeat(0)),
            hello(firmware::hil::LINK_VERSION, 2),
        ],
        true,
    );
    assert!(e.contains("rebooted during the run"), "{e}");
}

#[test]
fn a_transport_that_cannot_open_fails_the_run_by_name() {
    let mut cfg = lab("1100", 1, &[]);
    cfg.hil = vec![HilRobot {
        clock: hal_emu::world::hil::HilClock::Wall,
        robot: 1,
        transport: Transport::Qemu("/nonexistent/hil".into()),
    }];
    let e = hal_emu::run(&cfg).unwrap_err();
    assert!(
        e.to_string().contains("robot 1 failed") && e.to_string().contains("no HIL image"),
        "{e}"
    );
}

/// A robot on a TCP socket that says hello, answers every heartbeat, and otherwise does what
/// `on_setup` says (bytes to send once it gets its setup); the run's error with it in place 0
/// of a lab line of 2 s cycles, 8 s long.
fn responder(on_setup: Vec<u8>) -> String {
    use firmware::hil::{LinkDecoder, LinkMsg};
    use std::io::{Read, Write};
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let robot = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        s.write_all(&hello(firmware::hil::LINK_VERSION, 2)).unwrap();
        let mut d = LinkDecoder::new();
        let mut buf = [0u8; 256];
        while let Ok(n @ 1..) = s.read(&mut buf) {
            for m in buf[..n].iter().filter_map(|&b| d.push(b)).flatten() {
                let reply = match m {
                    LinkMsg::Heartbeat(seq) => frame(&LinkMsg::Heartbeat(seq)),
                    LinkMsg::Setup(_) => on_setup.clone(),
                    _ => continue,
                };
                if s.write_all(&reply).is_err() {
                    return;
                }
            }
        }
    });
    let mut cfg = lab("1100", 1, &[]);
    let w = &mut cfg.robot.params.wave;
    w.cycle = Duration::from_millis(2_000);
    w.cycle_spread = Duration::from_millis(500);
    w.relay_delay = Duration::from_millis(40);
    w.refractory = Duration::from_millis(150);
    cfg.duration = Duration::from_secs(8);
    cfg.hil = vec![HilRobot {
        clock: hal_emu::world::hil::HilClock::Wall,
        robot: 0,
        transport: Transport::Tcp(format!("127.0.0.1:{port}")),
    }];
    let e = hal_emu::run(&cfg).expect_err("the robot fails the run");
    robot.join().unwrap();
    e.to_string()
}

#[test]
fn a_robot_that_refuses_its_setup_or_never_transmits_fails_the_run() {
    let e = responder(frame(&firmware::hil::LinkMsg::Refused(2)));
    assert!(
        e.contains("refused the run's setup") && e.contains("receivers and the sectors differ"),
        "{e}"
    );
    // It answers its heartbeats but its robot program never sends light.
    let e = responder(Vec::new());
    assert!(
        e.contains("sent no light") && e.contains("not running"),
        "{e}"
    );
}
