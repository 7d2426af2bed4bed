//! Robots in the loop without QEMU: the host's end of the link (`hal_emu::hil`) against the
//! unchanged robot program behind the robot's end (`firmware::hil::robot::run`), in this
//! process over a channel (`loopback`), on the run's virtual clock. The same bridge serves QEMU
//! robots and boards (`cimax arena --hil`, `.ci/run`).

use hal_emu::hil::{HilRobot, Transport};
use hal_emu::lab::{PAPER_PATTERNS, judge, leds_str, parse_pattern};
use hal_emu::{ArenaConfig, ArenaError};
use protocol::Duration;

/// Three negotiation periods of the longest (70 s) cycles.
const RUN: Duration = Duration::from_secs(3 * 10 * 70);

fn lab(pattern: &str, seed: u64, in_loop: &[usize]) -> ArenaConfig {
    let mut c = ArenaConfig::line(parse_pattern(pattern).unwrap(), 1.0, RUN, seed);
    c.hil = in_loop
        .iter()
        .map(|&robot| HilRobot {
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
    bad(c, "no swarm key");
}
