//! Four robots running the real robot program, wired in memory ([`firmware::wired::run_line`],
//! what the QEMU board runs), under tokio's paused clock: the lab's six light patterns.

use firmware::protocol::lab::{LabPattern, PAPER};
use firmware::protocol::{Instant, Level, SwarmKey};
use firmware::wired::{run_line, total_stats};
use firmware::{Config, Robot};
use rand_pcg::Pcg32;

mod common;
use common::TokioClock;

/// Lit robots read 1, dark ones 0.
fn readings(pattern: &LabPattern) -> [Level; 4] {
    pattern.levels(Level(1), Level(0))
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
        for p in PAPER {
            let (pattern, expected) = (p.lights, p.expected());
            let clock = TokioClock::new();
            let mut line = robots(&clock, seed);
            // Two decisions each; the slowest robot needs at most 2 × 10 × 70 s.
            let deadline = Instant::from_secs(1_500);
            let report = run_line(&mut line, readings(&p), &clock, 2, deadline).await;
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
        for p in PAPER {
            let (pattern, expected) = (p.lights, p.expected());
            let clock = TokioClock::new();
            let mut line = keyed_robots(&clock, seed, Some(key));
            let deadline = Instant::from_secs(1_500);
            let report = run_line(&mut line, readings(&p), &clock, 2, deadline).await;
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
        readings(&LabPattern::find("1000").unwrap()),
        &clock,
        2,
        Instant::from_secs(100),
    )
    .await;
    assert!(!report.finished);
    assert_eq!(report.at, Instant::from_secs(100));
    assert_eq!(report.decisions, [0; 4]);
}
