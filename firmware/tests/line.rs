//! Four robots running the real robot program, wired in memory ([`firmware::wired::run_line`],
//! what the QEMU board runs), under tokio's paused clock: the lab's six light patterns.

use firmware::protocol::{Instant, Level, Sector, SwarmKey};
use firmware::wired::{run_line, total_stats};
use firmware::{Config, Robot};
use rand_pcg::Pcg32;

mod common;
use common::TokioClock;

const L: Option<Sector> = Some(Sector::LEFT);
const R: Option<Sector> = Some(Sector::RIGHT);

const PATTERNS: [(&str, [Option<Sector>; 4]); 6] = [
    ("1000", [L, L, L, L]),
    ("0111", [L, L, L, L]),
    ("0001", [R, R, R, R]),
    ("1110", [R, R, R, R]),
    ("1100", [R, R, L, L]),
    ("0011", [R, R, L, L]),
];

fn readings(pattern: &str) -> [Level; 4] {
    let b = pattern.as_bytes();
    core::array::from_fn(|i| Level(u8::from(b[i] == b'1')))
}

fn robots(clock: &TokioClock, seed: u64) -> [Robot<Pcg32, 2>; 4] {
    keyed_robots(clock, seed, None)
}

fn keyed_robots(clock: &TokioClock, seed: u64, key: Option<SwarmKey>) -> [Robot<Pcg32, 2>; 4] {
    core::array::from_fn(|i| {
        let config = Config {
            id: i as u16,
            key,
            ..Config::robots()
        };
        Robot::new(
            config,
            firmware::Clock::now(clock),
            Pcg32::new(seed, 2 * i as u64 + 1),
        )
        .unwrap()
    })
}

#[tokio::test(start_paused = true)]
async fn the_lab_patterns_decide_as_in_the_paper() {
    for seed in 0..10 {
        for (pattern, expected) in PATTERNS {
            let clock = TokioClock::new();
            let mut line = robots(&clock, seed);
            // Two decisions each; the slowest robot needs at most 2 × 10 × 70 s.
            let deadline = Instant::from_secs(1_500);
            let report = run_line(&mut line, readings(pattern), &clock, 2, deadline).await;
            assert!(
                report.finished,
                "pattern {pattern}, seed {seed}: {report:?}"
            );
            assert_eq!(
                report.shown_decisions(),
                expected,
                "pattern {pattern}, replay with seed {seed}"
            );
            assert_eq!(
                line.each_ref().map(|r| r.decision()),
                expected,
                "pattern {pattern}, seed {seed}"
            );
            let s = total_stats(&line);
            assert_eq!(report.lost, [0; 4]);
            assert_eq!(
                (s.frame_errors, s.rx_errors, s.tx_errors),
                (0, 0, 0),
                "{s:?}"
            );
            assert!(s.messages > 100, "{s:?}");
        }
    }
}

#[tokio::test(start_paused = true)]
async fn keyed_lines_decide_as_in_the_paper_too() {
    let key = SwarmKey::new(*b"sixteen byte key");
    for seed in 0..3 {
        for (pattern, expected) in PATTERNS {
            let clock = TokioClock::new();
            let mut line = keyed_robots(&clock, seed, Some(key));
            let deadline = Instant::from_secs(1_500);
            let report = run_line(&mut line, readings(pattern), &clock, 2, deadline).await;
            assert!(report.finished, "pattern {pattern}, seed {seed}");
            assert_eq!(
                report.shown_decisions(),
                expected,
                "pattern {pattern}, replay with seed {seed}"
            );
            let s = total_stats(&line);
            assert_eq!((s.frame_errors, s.bad_mac), (0, 0), "{s:?}");
            assert!(s.messages > 100, "{s:?}");
        }
    }
}

#[tokio::test(start_paused = true)]
async fn a_deadline_stops_an_unfinished_line() {
    let clock = TokioClock::new();
    let mut line = robots(&clock, 0);
    let report = run_line(
        &mut line,
        readings("1000"),
        &clock,
        2,
        Instant::from_secs(100),
    )
    .await;
    assert!(!report.finished);
    assert_eq!(report.at, Instant::from_secs(100));
    assert_eq!(report.decisions, [0; 4]);
}
