//! Authenticated frames end to end: the real robot program (`firmware::Robot::run`) with a
//! swarm key on emulated hardware (`hal-emu`), in the emulated light medium.
//!
//! - With a key the lab experiment still succeeds, and the frames on air are the keyed ones.
//! - Robots with the key ignore a robot without it or with another one: its frames are dropped
//!   and counted as bad MACs, and its light does not reach their decisions.

mod common;

use common::RUN;
use firmware::{Config, LedColor, Stats};
use hal_emu::judge::{PAPER_PATTERNS, expected, judge, leds_str, parse_pattern};
use hal_emu::{ArenaConfig, TraceEvent, run};
use protocol::SwarmKey;
use protocol::frame::FRAME_MAX;

const SWARM: SwarmKey = SwarmKey::new(*b"CIMAX swarm key!");
const FOREIGN: SwarmKey = SwarmKey::new(*b"another swarm...");

/// The lab line of [`common::lab`], every robot with `key`.
fn lab(pattern: &str, seed: u64, key: Option<SwarmKey>) -> ArenaConfig {
    let mut cfg = common::lab(pattern, seed);
    cfg.robot.key = key;
    cfg
}

/// Lengths of every frame robots put on air.
fn sent_lengths(trace: &[TraceEvent]) -> Vec<usize> {
    trace
        .iter()
        .filter_map(|e| match e {
            TraceEvent::Sent { len, .. } => Some(*len),
            _ => None,
        })
        .collect()
}

#[test]
fn with_a_key_the_six_patterns_light_the_expected_leds() {
    for pattern in PAPER_PATTERNS {
        for seed in 1..=3 {
            let mut cfg = lab(pattern, seed, Some(SWARM));
            cfg.trace = seed == 1;
            let r = judge(&cfg).unwrap();
            assert!(
                r.success,
                "pattern {pattern}: LEDs {} expected {}; replay with --key and seed {seed}",
                leds_str(&r.leds),
                leds_str(r.expected.as_deref().unwrap_or_default())
            );
            let messages: u32 = r.report.robots.iter().map(|s| s.messages).sum();
            assert!(messages > 200, "pattern {pattern}, seed {seed}: {messages}");
            if cfg.trace {
                // Keyed frames: 10 + 2 × hops bytes and the two-sector ray's 9 (a plain
                // one-hop frame with its ray is 19), at most 32.
                let lens = sent_lengths(&r.report.trace);
                assert!(!lens.is_empty());
                assert!(
                    lens.iter()
                        .all(|&n| n % 2 == 1 && (21..=FRAME_MAX).contains(&n)),
                    "{lens:?}"
                );
                assert!(lens.contains(&21), "initiations are 21 bytes: {lens:?}");
            }
        }
    }
}

#[test]
fn a_plain_run_sends_plain_frames() {
    // The control for the length check above: without a key an initiation is 19 bytes.
    let mut cfg = lab("1000", 1, None);
    cfg.trace = true;
    let r = judge(&cfg).unwrap();
    assert!(r.success);
    let lens = sent_lengths(&r.report.trace);
    assert!(lens.contains(&19), "{lens:?}");
    assert!(r.report.robots.iter().all(|s| s.bad_mac == 0));
}

#[test]
fn with_a_key_corrupted_frames_are_dropped_as_bad_macs_and_the_lab_still_succeeds() {
    for seed in 1..=3 {
        let mut cfg = lab("1100", seed, Some(SWARM));
        cfg.medium.byte_error_rate = 2e-3;
        let r = judge(&cfg).unwrap();
        assert!(r.success, "LEDs {}; seed {seed}", leds_str(&r.leds));
        assert!(r.report.medium.corrupted_bytes > 0);
        // The tag is the keyed frame's check: corruption that keeps the stuffing valid shows
        // up as a bad MAC (there is no CRC to fail).
        let bad_mac: u32 = r.report.robots.iter().map(|s| s.bad_mac).sum();
        let errors: u32 = r.report.robots.iter().map(|s| s.frame_errors).sum();
        assert!(bad_mac > 0 && bad_mac <= errors, "{:?}", r.report.robots);
    }
}

// ---------------------------------------------------------------------------------------------
// Mixed lines: robots with different keys in one medium.

/// How a mixed line ended.
struct Mixed {
    leds: Vec<LedColor>,
    decisions: Vec<u32>,
    stats: Vec<Stats>,
}

/// Robots in a line 1 m apart (each hears only its neighbours), robot `i` lit if
/// `pattern[i] == '1'` and keyed with `keys[i]` (its own configuration,
/// [`ArenaConfig::with_config`]), in the emulated medium without collisions (so that every bad
/// MAC is a frame from another swarm), for [`RUN`]. The sensors read 1 lit and 0 dark, without
/// noise.
fn mixed_line(pattern: &str, keys: &[Option<SwarmKey>], seed: u64) -> Mixed {
    let lights = parse_pattern(pattern).unwrap();
    assert_eq!(lights.len(), keys.len());
    let mut cfg = ArenaConfig::line(lights, 1.0, RUN, seed);
    cfg.medium.collisions = false;
    (cfg.env.lit, cfg.env.dark, cfg.env.noise) = (1, 0, 0);
    for (i, &key) in keys.iter().enumerate() {
        let config = Config { key, ..cfg.robot };
        cfg = cfg.with_config(i, config);
    }
    let r = run(&cfg).unwrap();
    Mixed {
        leds: r.final_leds,
        decisions: r.robots.iter().map(|s| s.decisions).collect(),
        stats: r.robots,
    }
}

#[test]
fn keyed_robots_ignore_a_robot_without_their_key() {
    for seed in 1..=3 {
        for outsider in [None, Some(FOREIGN)] {
            // Only the outsider (robot 3) is lit. If the swarm heard it, it would decide RRRR
            // (the paper's 0001, checked below with the outsider keyed).
            let keys = [Some(SWARM), Some(SWARM), Some(SWARM), outsider];
            let m = mixed_line("0001", &keys, seed);
            let ctx = format!("seed {seed}, outsider key {outsider:?}: {:?}", m.stats);
            assert!(m.decisions.iter().all(|&d| d >= 2), "{ctx}");
            // Dark robots that only hear dark robots have no evidence: undecided, LEDs off.
            // The outsider, deaf to the swarm, too.
            assert_eq!(m.leds, [LedColor::Off; 4], "{ctx}");
            // The swarm heard itself...
            for s in &m.stats[..3] {
                assert!(s.messages > 20, "{ctx}");
            }
            // ...and dropped every frame of the outsider as a bad MAC, counted by its neighbour
            // only (no collisions, no byte errors: there are no other bad frames).
            assert!(m.stats[2].bad_mac > 20, "{ctx}");
            assert_eq!(m.stats[2].frame_errors, m.stats[2].bad_mac, "{ctx}");
            for s in &m.stats[..2] {
                assert_eq!((s.bad_mac, s.frame_errors), (0, 0), "{ctx}");
            }
            // The outsider understood nothing of the swarm either.
            let o = &m.stats[3];
            assert_eq!(o.messages, 0, "{ctx}");
            assert!(o.frame_errors > 20, "{ctx}");
            match outsider {
                Some(_) => assert_eq!(o.bad_mac, o.frame_errors, "{ctx}"),
                None => assert_eq!(o.bad_mac, 0, "{ctx}: a plain robot checks CRCs"),
            }
        }
    }
}

#[test]
fn the_same_line_with_the_outsider_keyed_follows_its_light() {
    let want = expected(&parse_pattern("0001").unwrap()).unwrap();
    assert_eq!(leds_str(&want), "RRRR");
    for seed in 1..=3 {
        let m = mixed_line("0001", &[Some(SWARM); 4], seed);
        assert_eq!(m.leds, want, "seed {seed}: {:?}", m.stats);
        assert!(m.stats.iter().all(|s| s.bad_mac == 0 && s.messages > 20));
    }
}

#[test]
fn two_swarms_in_one_line_decide_apart() {
    // Robots 0-1 share one key, robots 2-3 another: two lines of two. Each pair hears only
    // itself: the lit pair 11 and the dark pair 00 have no border, so both stay undecided,
    // where one swarm of four would decide RRLL.
    let keys = [Some(SWARM), Some(SWARM), Some(FOREIGN), Some(FOREIGN)];
    let m = mixed_line("1100", &keys, 4);
    assert_eq!(m.leds, [LedColor::Off; 4], "{:?}", m.stats);
    assert!(m.stats[1].bad_mac > 20 && m.stats[2].bad_mac > 20);
    assert_eq!((m.stats[0].bad_mac, m.stats[3].bad_mac), (0, 0));
    let one = mixed_line("1100", &[Some(SWARM); 4], 4);
    assert_eq!(leds_str(&one.leds), "RRLL");
}
