//! The campaign's scenarios: the fault each injects, its bar, and the configuration of its run
//! for a seed.

use hal_emu::judge::{PAPER_PATTERNS, parse_pattern};
use hal_emu::{Adversary, ArenaConfig, Point2};
use protocol::{Duration, Instant, Params};

use swarm_sim::seeds;

use super::error::CampaignError;

/// The fault a scenario injects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fault {
    /// Each frame is lost at each receiver with this probability.
    Loss(f64),
    /// Each received byte is corrupted with this probability (collisions on).
    ByteErrors(f64),
    /// Cycles drawn uniformly from `cycle ± spread` seconds, every cycle.
    CycleSpread {
        /// Mean cycle, s.
        cycle: u64,
        /// Spread, s.
        spread: u64,
    },
    /// One robot at an end of the line is dead from the start.
    DeadEnd,
    /// One robot reboots (killed, restarted 5 s later) at a random time after consensus.
    Reboot,
    /// A rogue transmitter in range of every robot sends random bytes.
    Rogue,
    /// A replayer in range of every robot sends captured frames again later.
    Replayer,
}

/// One scenario of the campaign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scenario {
    /// Its name on the command line.
    pub name: &'static str,
    /// What it does, for the report.
    pub what: &'static str,
    /// The fault.
    pub fault: Fault,
    /// Least success rate (0 to 1) to pass; `None`: reported only.
    pub bar: Option<f64>,
}

/// The campaign's scenarios and their bars.
pub const SCENARIOS: &[Scenario] = &[
    Scenario {
        name: "loss-10",
        what: "10 % of frames lost at each receiver",
        fault: Fault::Loss(0.1),
        bar: Some(0.99),
    },
    Scenario {
        name: "loss-20",
        what: "20 % of frames lost at each receiver",
        fault: Fault::Loss(0.2),
        bar: Some(0.95),
    },
    Scenario {
        name: "loss-30",
        what: "30 % of frames lost at each receiver",
        fault: Fault::Loss(0.3),
        bar: None,
    },
    Scenario {
        name: "byte-errors",
        what: "byte error rate 1e-3 (collisions on, as in every scenario)",
        fault: Fault::ByteErrors(1e-3),
        bar: Some(0.99),
    },
    Scenario {
        name: "cycle-spread",
        what: "cycles drawn from 40-70 s every cycle (the robots' measured spread; also the robot program's default, so this is the fault-free baseline every other scenario adds its fault to)",
        fault: Fault::CycleSpread {
            cycle: 55,
            spread: 15,
        },
        bar: Some(0.99),
    },
    Scenario {
        name: "dead-end",
        what: "a robot at one end dead from the start; the three others judged as a line of three",
        fault: Fault::DeadEnd,
        bar: Some(0.99),
    },
    Scenario {
        name: "reboot",
        what: "a robot reboots after consensus; consensus back within two negotiation periods",
        fault: Fault::Reboot,
        bar: Some(0.99),
    },
    Scenario {
        name: "rogue",
        what: "a rogue transmitter in range of all four sends random bytes",
        fault: Fault::Rogue,
        bar: Some(0.99),
    },
    Scenario {
        name: "replayer",
        what: "a replayer in range of all four sends captured frames again 10-60 s later",
        fault: Fault::Replayer,
        bar: Some(0.99),
    },
];

/// Where the adversaries stand: between robots 1 and 2 of the line of four (1 m apart), 1.5 m
/// from the end robots, so every robot hears them (range 1.5 m), the end robots on the same
/// receiver as their only neighbour.
pub const ADVERSARY_AT: (f64, f64) = (1.5, 0.0);

/// Delay between a reboot's kill and its restart.
pub const REBOOT_DOWN: Duration = Duration::from_secs(5);

/// The pattern seed `seed` uses: the paper's six in turn.
pub fn pattern_for(seed: u64) -> &'static str {
    PAPER_PATTERNS[(seed % PAPER_PATTERNS.len() as u64) as usize]
}

/// The run of `scenario` for `seed`, and the reboot time if it has one.
///
/// # Errors
/// [`CampaignError::Pattern`] if the pattern does not parse (cannot happen for the paper's
/// patterns).
pub fn config(
    scenario: &Scenario,
    seed: u64,
    loss: Option<f64>,
) -> Result<(ArenaConfig, Option<Instant>), CampaignError> {
    let pattern = parse_pattern(pattern_for(seed))?;
    let n = pattern.len();
    let params = Params::robots();
    let mut cfg = ArenaConfig::line(pattern.clone(), 1.0, params.lab_run(), seed);
    // Scenario-specific draws (which robot, when) from their own seed, so they do not disturb
    // the run's other random numbers.
    let draw = |what: u64| seeds::derive(seed, &[what]);
    let at = Point2::new(ADVERSARY_AT.0, ADVERSARY_AT.1);
    let mut reboot = None;
    match scenario.fault {
        Fault::Loss(p) => cfg.medium.loss = p,
        Fault::ByteErrors(p) => {
            cfg.medium.byte_error_rate = p;
            cfg.medium.collisions = true;
        }
        Fault::CycleSpread { cycle, spread } => {
            cfg.robot.params.wave.cycle = Duration::from_secs(cycle);
            cfg.robot.params.wave.cycle_spread = Duration::from_secs(spread);
            cfg.duration = cfg.robot.params.lab_run();
        }
        Fault::DeadEnd => {
            // The end drawn for this seed, or the other one if without it the three others
            // would see no border (1000 without robot 0 is 000: no verdict).
            let (mut end, other) = if draw(1) % 2 == 0 {
                (0, n - 1)
            } else {
                (n - 1, 0)
            };
            let rest = |e: usize| {
                let mut p = pattern.clone();
                p.remove(e);
                hal_emu::judge::expected(&p)
            };
            if rest(end).is_none() {
                end = other;
            }
            cfg.dead_at_start = vec![end];
        }
        Fault::Reboot => {
            // After the first decision (at most 10 cycles of 70 s = 700 s): 800 to 1400 s.
            let t = Instant::from_secs(800 + draw(2) % 601);
            let robot = (draw(3) % n as u64) as usize;
            cfg.kills.push((t, robot));
            cfg.restarts.push((t + REBOOT_DOWN, robot));
            cfg.duration = t.saturating_since(Instant::ZERO) + params.lab_run();
            reboot = Some(t);
        }
        Fault::Rogue => cfg.adversaries.push(Adversary::rogue(at)),
        Fault::Replayer => cfg.adversaries.push(Adversary::replayer(at)),
    }
    if let Some(p) = loss {
        cfg.medium.loss = p;
    }
    Ok((cfg, reboot))
}

/// Where `count` robots in the loop go in `cfg`, a scenario's run: the robots it kills (and
/// restarts) first, then the living ones from the left, the dead from the start last (a robot
/// in the loop dead from the start never runs).
///
/// # Errors
/// More robots in the loop than the run has.
pub fn hil_places(cfg: &ArenaConfig, count: usize) -> Result<Vec<usize>, CampaignError> {
    let n = cfg.positions.len();
    if count > n {
        return Err(CampaignError::TooManyInTheLoop { count, robots: n });
    }
    let killed = |r: &usize| cfg.kills.iter().any(|&(_, k)| k == *r);
    let dead = |r: &usize| cfg.dead_at_start.contains(r);
    let mut places: Vec<usize> = (0..n).filter(killed).collect();
    places.extend((0..n).filter(|r| !killed(r) && !dead(r)));
    places.extend((0..n).filter(|r| !killed(r) && dead(r)));
    places.truncate(count);
    Ok(places)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_rotate_the_six_patterns_and_scenarios_draw_their_own_choices() {
        let six: Vec<&str> = (6..12).map(pattern_for).collect();
        assert_eq!(six, PAPER_PATTERNS);
        let dead = SCENARIOS.iter().find(|s| s.name == "dead-end").unwrap();
        for seed in 0..60 {
            let (cfg, _) = config(dead, seed, None).unwrap();
            let &[end] = cfg.dead_at_start.as_slice() else {
                panic!("one dead robot")
            };
            assert!(end == 0 || end == 3);
            let r = hal_emu::judge::absent(&cfg);
            let p = parse_pattern(pattern_for(seed)).unwrap();
            assert!(
                hal_emu::judge::expected_without(&p, &r).is_some(),
                "seed {seed}"
            );
        }
        let reboot = SCENARIOS.iter().find(|s| s.name == "reboot").unwrap();
        let (cfg, t) = config(reboot, 3, None).unwrap();
        let t = t.unwrap();
        assert!((800..=1400).contains(&(t.as_millis() / 1000)));
        assert_eq!(cfg.restarts, vec![(t + REBOOT_DOWN, cfg.kills[0].1)]);
        // In the loop: the rebooting robot first; the dead one last.
        let r = cfg.kills[0].1;
        let places = hil_places(&cfg, 4).unwrap();
        assert_eq!(places[0], r);
        assert_eq!(hil_places(&cfg, 1).unwrap(), vec![r]);
        let (cfg, _) = config(dead, 5, None).unwrap();
        let places = hil_places(&cfg, 4).unwrap();
        assert_eq!(places[3], cfg.dead_at_start[0]);
        assert!(!hil_places(&cfg, 3).unwrap().contains(&cfg.dead_at_start[0]));
        assert!(
            hil_places(&cfg, 5)
                .unwrap_err()
                .to_string()
                .contains("have 4 robots")
        );
    }
}
