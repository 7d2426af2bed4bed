//! Swarm-wide agreement in long lines: the robot program over the emulated medium, judged by
//! the LEDs. Every robot must show the direction the majority of robots prefer (each robot
//! prefers the direction of the one border), far beyond a message's hop horizon.

use hal_emu::ArenaConfig;
use hal_emu::judge::{judge, leds_str};
use protocol::Params;

/// `lit` robots lit at the left end of a line of `n`, run with `seed` and frame loss `loss`.
fn line(n: usize, lit: usize, seed: u64, loss: f64) -> ArenaConfig {
    let pattern = (0..n).map(|i| i < lit).collect();
    let mut cfg = ArenaConfig::line(pattern, 1.0, Params::robots().lab_run(), seed);
    cfg.medium.loss = loss;
    cfg
}

fn assert_agree(n: usize, lit: usize, seeds: std::ops::Range<u64>, loss: f64) {
    for seed in seeds {
        let r = judge(&line(n, lit, seed, loss)).unwrap();
        assert!(
            r.success,
            "{n} robots, {lit} lit, loss {loss}: LEDs {} expected {} \
             (replay: cimax arena --lights {} --seed {seed} --runs 1 --loss {loss})",
            leds_str(&r.leds),
            leds_str(r.expected.as_deref().unwrap_or_default()),
            (0..n)
                .map(|i| if i < lit { '1' } else { '0' })
                .collect::<String>(),
        );
    }
}

#[test]
fn sixty_four_robots_follow_the_majority_far_beyond_the_horizon() {
    // 20 lit, 44 dark: the dark majority prefers left; robots 30 and more hops from the border
    // see nothing of it in their messages' 8 hops.
    assert_agree(64, 20, 1..2, 0.0);
    // 40 lit, 24 dark: the lit majority prefers right.
    assert_agree(64, 40, 3..4, 0.0);
}

#[test]
fn thirty_two_robots_agree_with_ten_percent_loss() {
    assert_agree(32, 10, 1..4, 0.1);
    assert_agree(32, 18, 4..6, 0.1);
}

#[test]
fn the_smallest_majorities_win() {
    // 55 % and 11/20: one robot more on one side.
    assert_agree(20, 9, 1..3, 0.0);
    assert_agree(11, 6, 1..3, 0.0);
}
