//! Runs looked at more closely than the sweeps look at them: the experiments that settle the
//! reproduction page's open rows (its section "Settling the open rows").
//!
//! - [`plateaus`]: the diversity at the plateau three ways: the page's mean over agents of
//!   `V_k`, the mean variance per scored message, and the variance of all scored readings
//!   pooled ([`Tap`]);
//! - [`start_diversity`]: the diversity of the first gathering phase of each run, beside the
//!   number of agents that stand across x = 0;
//! - [`msd_after_arrival`]: how the swarm wanders once it has arrived (a walk along the sharp
//!   border, a walk in both dimensions on the gradient);
//! - [`periods_per_bin`]: where a run spends its periods before it arrives;
//! - [`flood`]: a wave without (or with too short) a refractory time, as a model of the
//!   simulator's delivery rule, for the refractory times the protocol refuses.

use nalgebra::Point2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::experiment::{Error, RunOutput, run_tapped};
use crate::geometry::Swarm;
use crate::progress::Progress;
use crate::scenario::Scenario;
use crate::seeds::derive;
use crate::stats;
use crate::tap::Tap;
use crate::timecourse::Spread;

/// One full run with its taps, one per period.
#[derive(Clone, Debug)]
pub struct Tapped {
    /// The run.
    pub out: RunOutput,
    /// What the observer saw of the messages of each period ([`Tap`]), `taps[k]` for
    /// `out.periods[k]`.
    pub taps: Vec<Tap>,
}

/// `runs` full runs of `scn` with `cfg` from `(x, 0)`, tapped; run `r` uses seed
/// `derive(seed, [r])`, so with the scenario's own configuration and start these are the very
/// runs of [`crate::timecourse::time_course`] with that seed (the tap changes nothing).
///
/// # Errors
/// The first run's error.
pub fn tapped_runs(
    scn: &Scenario,
    cfg: crate::sim::RunConfig,
    x: f64,
    periods: u32,
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<Tapped>, Error> {
    (0..runs)
        .into_par_iter()
        .map(|r| {
            let start = Point2::new(x, 0.0);
            let (out, taps) = run_tapped(scn, cfg, start, periods, derive(seed, &[u64::from(r)]))?;
            progress.inc();
            Ok(Tapped { out, taps })
        })
        .collect()
}

/// The diversity at the plateau, three ways, over the runs that arrived.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plateaus {
    /// Runs counted: those that met the criterion at least `min_after` periods before the end.
    pub runs: usize,
    /// The mean over agents of `V_k` (the page's, and the paper's definition).
    pub agents: Spread,
    /// The mean over scored messages of each message's variance.
    pub message: Spread,
    /// The variance of every scored reading, all agents together.
    pub pooled: Spread,
}

/// Each run's mean of the three diversities over its periods after arrival (as
/// [`crate::timecourse::summarise`] takes the plateau), then their spread over runs.
pub fn plateaus(runs: &[Tapped], min_after: u32) -> Plateaus {
    let (mut agents, mut message, mut pooled) = (Vec::new(), Vec::new(), Vec::new());
    for t in runs {
        let Some(at) = t.out.success_at else { continue };
        let tail: Vec<usize> = (0..t.out.periods.len())
            .filter(|&k| t.out.periods[k].index > at)
            .collect();
        if tail.len() < min_after as usize {
            continue;
        }
        let mean_of = |f: &dyn Fn(usize) -> Option<f64>| {
            let v: Vec<f64> = tail.iter().filter_map(|&k| f(k)).collect();
            stats::mean(&v).unwrap_or(f64::NAN)
        };
        agents.push(mean_of(&|k| Some(t.out.periods[k].diversity)));
        message.push(mean_of(&|k| t.taps.get(k)?.per_message()));
        pooled.push(mean_of(&|k| t.taps.get(k)?.pooled()));
    }
    Plateaus {
        runs: agents.len(),
        agents: Spread::of(&agents),
        message: Spread::of(&message),
        pooled: Spread::of(&pooled),
    }
}

/// The first gathering phase of one run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StartRun {
    /// Where the swarm's centre started (y = 0).
    #[serde(with = "crate::json")]
    pub x: f64,
    /// Agents with x ≥ 0 at the start: across the sharp border, or on the ramp.
    pub across: usize,
    /// The observer's average diversity (mean over agents of `V_k`) of the first period.
    #[serde(with = "crate::json")]
    pub diversity: f64,
}

/// One-period runs of `scn` from each `(x, 0)` of `xs`, `runs` each (point `p`, run `r`:
/// seed `derive(seed, [p, r])`): each run's first diversity and its agents across x = 0.
///
/// # Errors
/// The first run's error.
pub fn start_diversity(
    scn: &Scenario,
    xs: &[f64],
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<StartRun>, Error> {
    let n = xs.len() * runs as usize;
    (0..n)
        .into_par_iter()
        .map(|k| {
            let (p, r) = (k / runs as usize, k % runs as usize);
            let s = derive(seed, &[p as u64, r as u64]);
            let start = Point2::new(xs[p], 0.0);
            let out = crate::experiment::run(scn, scn.run, start, 1, s, false)?;
            progress.inc();
            Ok(StartRun {
                x: xs[p],
                across: across(&out.swarm, start),
                diversity: out.periods.first().map_or(f64::NAN, |q| q.diversity),
            })
        })
        .collect()
}

/// Agents of `swarm` centred at `centre` that stand at x ≥ 0.
pub fn across(swarm: &Swarm, centre: Point2<f64>) -> usize {
    swarm
        .offsets()
        .iter()
        .filter(|v| centre.x + v.x >= 0.0)
        .count()
}

/// The mean squared displacement of the swarm's centre at one lag after arrival.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Msd {
    /// Periods between the two positions.
    pub lag: u32,
    /// Mean of Δx² over every pair of positions `lag` periods apart after arrival, R².
    #[serde(with = "crate::json")]
    pub x: f64,
    /// Mean of Δy², R².
    #[serde(with = "crate::json")]
    pub y: f64,
    /// Pairs averaged (over all runs that arrived).
    pub pairs: usize,
}

/// The mean squared displacements along x and y of the runs that arrived, from the position at
/// arrival on, at lags 1 to `max_lag` (every pair of the run's later positions that far apart).
pub fn msd_after_arrival(outs: &[RunOutput], max_lag: u32) -> Vec<Msd> {
    let paths: Vec<Vec<Point2<f64>>> = outs
        .iter()
        .filter_map(|o| {
            let at = o.success_at? as usize;
            let first = if at == 0 {
                o.start
            } else {
                o.periods.get(at - 1)?.to
            };
            let later = o.periods.iter().skip(at).map(|p| p.to);
            Some(std::iter::once(first).chain(later).collect())
        })
        .collect();
    (1..=max_lag)
        .map(|lag| {
            let (mut x, mut y, mut pairs) = (0.0, 0.0, 0usize);
            for path in &paths {
                for w in path.windows(lag as usize + 1) {
                    let d = w[lag as usize] - w[0];
                    x += d.x * d.x;
                    y += d.y * d.y;
                    pairs += 1;
                }
            }
            let n = pairs.max(1) as f64;
            Msd {
                lag,
                x: x / n,
                y: y / n,
                pairs,
            }
        })
        .collect()
}

/// Where the runs that arrived spent their periods before arriving: per bin of x of
/// `width` starting at `lo` (bins up to `hi`), the mean over those runs of the periods that
/// started with the swarm's centre in it. Returns `(bin's centre, mean periods)`.
pub fn periods_per_bin(outs: &[RunOutput], lo: f64, hi: f64, width: f64) -> Vec<(f64, f64)> {
    let bins = ((hi - lo) / width).ceil().max(0.0) as usize;
    let mut count = vec![0usize; bins];
    let mut arrived = 0usize;
    for o in outs {
        let Some(at) = o.success_at else { continue };
        arrived += 1;
        for p in o.periods.iter().take(at as usize) {
            let b = ((p.from.x - lo) / width).floor();
            if b >= 0.0 && (b as usize) < bins {
                count[b as usize] += 1;
            }
        }
    }
    count
        .iter()
        .enumerate()
        .map(|(b, &c)| {
            let centre = lo + width * (b as f64 + 0.5);
            (centre, c as f64 / arrived.max(1) as f64)
        })
        .collect()
}

/// A wave under the simulator's delivery rule, as a model that takes any refractory time: at
/// second 0 agent `initiator` transmits; a transmission at second `t` reaches every neighbour;
/// a neighbour that is receptive then (not waiting to relay, and at least `refractory_s` after
/// its own last transmission) relays at `t + relay_s`. It is the rule the protocol's agents
/// follow in the simulator (checked against it for the refractory times the protocol accepts),
/// for the refractory times it refuses (not above the relay delay).
///
/// Returns the transmissions per second for seconds `0..=horizon`.
pub fn flood(
    swarm: &Swarm,
    initiator: usize,
    relay_s: u64,
    refractory_s: u64,
    horizon: u64,
) -> Vec<u32> {
    let n = swarm.len();
    let mut sends = vec![0u32; horizon as usize + 1];
    if initiator >= n || relay_s == 0 {
        return sends;
    }
    // Per agent: the second of its pending relay, and the first second it is receptive again.
    let mut relay_at: Vec<Option<u64>> = vec![None; n];
    let mut receptive_from = vec![0u64; n];
    relay_at[initiator] = Some(0);
    let mut senders = Vec::new();
    for t in 0..=horizon {
        senders.clear();
        senders.extend((0..n).filter(|&i| relay_at[i] == Some(t)));
        for &i in &senders {
            relay_at[i] = None;
            receptive_from[i] = t + refractory_s;
        }
        sends[t as usize] = senders.len() as u32;
        for &i in &senders {
            for l in swarm.neighbours(i) {
                let r = l.agent as usize;
                if relay_at[r].is_none() && t >= receptive_from[r] {
                    relay_at[r] = Some(t + relay_s);
                }
            }
        }
    }
    sends
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use rand::SeedableRng;
    use rand_pcg::Pcg64Mcg;

    fn line(n: usize) -> Swarm {
        let offsets = (0..n)
            .map(|i| nalgebra::Vector2::new(0.8 * i as f64, 0.0))
            .collect();
        Swarm::from_offsets(offsets, 1.0)
    }

    #[test]
    fn a_long_enough_refractory_time_lets_every_agent_send_once() {
        let s = line(5);
        let sends = flood(&s, 0, 1, 2, 30);
        assert_eq!(&sends[..6], &[1, 1, 1, 1, 1, 0]);
        assert_eq!(sends.iter().sum::<u32>(), 5);
    }

    #[test]
    fn without_refractory_time_the_wave_comes_back_and_never_ends() {
        let s = line(3);
        for refractory in [0, 1] {
            let sends = flood(&s, 0, 1, refractory, 40);
            assert!(
                sends[30..].iter().all(|&k| k > 0),
                "{refractory}: {sends:?}"
            );
        }
    }

    #[test]
    fn the_model_is_the_protocols_wave_where_the_protocol_takes_the_refractory_time() {
        use crate::waves::{WaveSpec, one_wave};
        for refractory_s in [2, 3, 10] {
            let spec = WaveSpec {
                refractory_s,
                ..WaveSpec::paper()
            };
            let w = one_wave(&spec, 5).unwrap();
            let sends = flood(&w.swarm, w.initiator, 1, refractory_s, 40);
            let mut expected = vec![0u32; 41];
            for t in w.sent_at.iter().flatten() {
                expected[*t as usize] += 1;
            }
            assert_eq!(sends, expected, "refractory {refractory_s} s");
            assert_eq!(sends.iter().sum::<u32>() as usize, w.len());
        }
    }

    #[test]
    fn the_tap_sees_every_scored_message_and_changes_nothing() {
        let scn = Scenario::builtin("sharp").unwrap();
        let start = Point2::new(-0.5, 0.0);
        let plain = crate::experiment::run(&scn, scn.run, start, 2, 7, false).unwrap();
        let (tapped, taps) = run_tapped(&scn, scn.run, start, 2, 7).unwrap();
        assert_eq!(plain.periods, tapped.periods);
        assert_eq!(taps.len(), 2);
        // Straddling the border, messages carry both sides' readings.
        for t in &taps {
            assert!(t.messages > 0);
            let (m, p) = (t.per_message().unwrap(), t.pooled().unwrap());
            assert!(m > 0.0 && p > m, "{m} {p}");
        }
    }

    #[test]
    fn a_tap_pools_and_averages_messages() {
        let mut t = Tap::default();
        assert_eq!((t.per_message(), t.pooled()), (None, None));
        t.add([0.0, 2.0].into_iter());
        t.add([4.0].into_iter());
        t.add(std::iter::empty());
        assert_eq!(t.messages, 2);
        assert_eq!(t.per_message(), Some(0.5));
        assert!((t.pooled().unwrap() - 8.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn msd_and_bins_read_the_runs_that_arrived() {
        let mut rng = Pcg64Mcg::seed_from_u64(1);
        let swarm = Swarm::place(7, Shape::Disk { diameter: 2.0 }, 1.0, &mut rng).unwrap();
        let step = |i: u32, from: (f64, f64), to: (f64, f64)| crate::sim::Period {
            index: i,
            end_s: 0,
            from: Point2::new(from.0, from.1),
            to: Point2::new(to.0, to.1),
            direction: None,
            consensus: 0.0,
            decided: 0,
            diversity: 0.0,
        };
        // Arrives after period 1 at (0, 0), then walks +y one R per period.
        let out = RunOutput {
            swarm,
            start: Point2::new(-1.0, 0.0),
            periods: vec![
                step(1, (-1.0, 0.0), (0.0, 0.0)),
                step(2, (0.0, 0.0), (0.0, 1.0)),
                step(3, (0.0, 1.0), (0.0, 2.0)),
            ],
            success_at: Some(1),
        };
        let m = msd_after_arrival(std::slice::from_ref(&out), 2);
        assert_eq!((m[0].x, m[0].y, m[0].pairs), (0.0, 1.0, 2));
        assert_eq!((m[1].x, m[1].y, m[1].pairs), (0.0, 4.0, 1));
        let bins = periods_per_bin(std::slice::from_ref(&out), -1.0, 1.0, 0.5);
        assert_eq!(bins[0], (-0.75, 1.0));
        assert_eq!(bins.iter().map(|b| b.1).sum::<f64>(), 1.0);
    }
}

/// How one negotiation period's decisions split along x ([`splits`]): the agents that decided
/// to move left (a bearing with cos < 0), right (cos > 0), and the swarm's size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Split {
    /// Agents in the swarm.
    pub agents: usize,
    /// Agents whose decided bearing points to −x.
    pub left: u32,
    /// Agents whose decided bearing points to +x.
    pub right: u32,
}

impl Split {
    /// As many agents decided left as right: the paper's "indecision point" (two robots left,
    /// two right), for a swarm of any size.
    pub fn tied(&self) -> bool {
        self.left == self.right
    }
}

/// One negotiation period of a swarm of each size of `sizes` (`scn`'s shape scaled to keep its
/// density), centred at `start`, `runs` each (size `p`, run `r`: seed `derive(seed, [p, r])`):
/// how the agents' decisions split along x. Single-quantity scenarios only.
///
/// # Errors
/// The first run's error.
pub fn splits(
    scn: &Scenario,
    sizes: &[usize],
    start: Point2<f64>,
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<Split>, Error> {
    let n = sizes.len() * runs as usize;
    (0..n)
        .into_par_iter()
        .map(|k| {
            let (p, r) = (k / runs as usize, k % runs as usize);
            let s = derive(seed, &[p as u64, r as u64]);
            let swarm = crate::experiment::place(scn, sizes[p], s)?;
            let mut sim = crate::sim::Sim::<f32>::new(&swarm, &scn.field, scn.run, start, s)?;
            // Only the decisions are read.
            sim.without_diversity();
            sim.run_period()?;
            let (mut left, mut right) = (0, 0);
            for b in sim.agents().iter().filter_map(|a| a.decision()) {
                let c = b.cos();
                left += u32::from(c < 0.0);
                right += u32::from(c > 0.0);
            }
            progress.inc();
            Ok(Split {
                agents: sizes[p],
                left,
                right,
            })
        })
        .collect()
}
