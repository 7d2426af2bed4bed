//! The lab experiment end to end: the real robot program (`firmware::Robot::run`) on emulated
//! hardware (`hal-emu`) in the emulated light medium, judged by the LEDs.

mod common;

use common::{RUN, lab};
use firmware::LedColor;
use hal_emu::MediumParams;
use hal_emu::judge::{PAPER_PATTERNS, expected, judge, leds_str, mirrored, parse_pattern};
use protocol::{Duration, Instant};

#[test]
fn six_patterns_light_the_expected_leds() {
    for pattern in PAPER_PATTERNS {
        for seed in 1..=5 {
            let r = judge(&lab(pattern, seed)).unwrap();
            assert!(
                r.success,
                "pattern {pattern}: LEDs {} expected {}; replay with seed {seed}",
                leds_str(&r.leds),
                leds_str(r.expected.as_deref().unwrap_or_default())
            );
            assert!(
                r.consensus_s
                    .is_some_and(|s| s > 0.0 && s < RUN.as_secs_f64())
            );
        }
    }
}

#[test]
fn alternating_experiment_switches_the_leds_from_every_pattern() {
    for pattern in PAPER_PATTERNS {
        let first = parse_pattern(pattern).unwrap();
        let then = mirrored(&first);
        for seed in 1..=3 {
            let mut cfg = lab(pattern, seed);
            cfg.env.schedule.push((Instant::ZERO + RUN, then.clone()));
            cfg.duration = RUN.saturating_mul(2);
            let r = judge(&cfg).unwrap();
            let replay = format!(
                "cimax arena --lights {pattern} --switch-at {} --then {} --seed {seed} --runs 1",
                RUN.as_secs_f64(),
                leds_pattern(&then)
            );
            assert!(r.success, "LEDs {}; replay: {replay}", leds_str(&r.leds));
            assert_eq!(Some(r.leds.clone()), expected(&then), "{replay}");
            assert_eq!(
                Some(r.report.leds_at(Instant::ZERO + RUN)),
                expected(&first),
                "{replay}"
            );
        }
    }
}

/// A pattern as `--lights` spells it.
fn leds_pattern(p: &[bool]) -> String {
    p.iter().map(|&l| if l { '1' } else { '0' }).collect()
}

/// Every lab pattern with sensors of another resolution, gain or offset, under both rules:
/// the same LEDs (docs/lab-experiment.md, "Readings").
#[test]
fn every_pattern_decides_right_with_binary_coarse_and_scaled_readings() {
    use hal_emu::Readings;
    use protocol::params::DecisionRule;
    let readings = [
        Readings::Binary,
        Readings::Quantised(4),
        Readings::Scaled {
            gain: 0.25,
            offset: 7.0,
        },
    ];
    for decide in [DecisionRule::Fixed, DecisionRule::Adaptive] {
        for r in readings {
            for pattern in PAPER_PATTERNS {
                let seed = 11;
                let mut cfg = lab(pattern, seed);
                cfg.env.readings = r;
                cfg.robot.params.decide = decide;
                let j = judge(&cfg).unwrap();
                assert!(
                    j.success,
                    "LEDs {}; replay: cimax arena --lights {pattern} --readings {r} --decide {} \
                     --seed {seed} --runs 1",
                    leds_str(&j.leds),
                    if decide == DecisionRule::Adaptive {
                        "adaptive"
                    } else {
                        "fixed"
                    }
                );
            }
        }
    }
}

#[test]
fn same_seed_gives_the_same_trace_bit_for_bit() {
    let trace = |seed| {
        let mut cfg = lab("1100", seed);
        cfg.trace = true;
        cfg.medium.loss = 0.1;
        cfg.medium.byte_error_rate = 1e-3;
        let r = judge(&cfg).unwrap();
        serde_json::to_string(&r.report.trace).unwrap()
    };
    let a = trace(7);
    assert!(a.len() > 10_000, "a real trace: {} bytes", a.len());
    assert_eq!(a, trace(7));
    assert_ne!(a, trace(8));
}

#[test]
fn ten_percent_frame_loss_still_succeeds() {
    for seed in 1..=10 {
        for pattern in ["1000", "1100"] {
            let mut cfg = lab(pattern, seed);
            cfg.medium = MediumParams {
                loss: 0.1,
                ..MediumParams::default()
            };
            let r = judge(&cfg).unwrap();
            assert!(r.report.medium.lost > 0);
            assert!(
                r.success,
                "pattern {pattern}, LEDs {}; replay with seed {seed}",
                leds_str(&r.leds)
            );
        }
    }
}

#[test]
fn a_killed_robot_goes_dark_and_a_restarted_one_rejoins() {
    let mut cfg = lab("1000", 3);
    cfg.kills.push((Instant::from_secs(1000), 3));
    cfg.restarts.push((Instant::from_secs(1100), 3));
    cfg.duration = Duration::from_secs(1100 + 2 * 10 * 70 + 70);
    let r = judge(&cfg).unwrap();
    assert_eq!(r.report.leds_at(Instant::from_secs(1050))[3], LedColor::Off);
    assert!(r.success, "LEDs {}", leds_str(&r.leds));
    assert_eq!(Some(r.leds), expected(&parse_pattern("1000").unwrap()));
}
