//! The paper's Fig. 2: one wave through a swarm of 80 agents, watched through the agents' own
//! states.
//!
//! Nothing here re-implements the wave: [`one_wave`] places the swarm as every experiment does
//! ([`Swarm::place`]), runs the simulator ([`Sim`], i.e. the real
//! [`protocol::ThreePhaseAgent`]s and their [`protocol::WaveNode`]s) one second at a time and
//! records each agent's [`ThreePhaseAgent::state`](protocol::ThreePhaseAgent::state) and its
//! wave counters between seconds.
//!
//! **One wave.** Every agent initiates once per cycle, at a time drawn uniformly in the cycle.
//! With a cycle of [`WaveSpec::paper`]'s 100,000 s the 80 initiation times lie about 1,250 s
//! apart, so the first of them starts a wave that runs its course alone. The initiator is not
//! picked by hand: it is the agent whose drawn initiation comes first. If another agent happens
//! to initiate while that wave is under way (or two share the first second), the protocol's
//! draws are redrawn from the next derived seed, as [`Swarm::place`] redraws a disconnected
//! placement; [`Wave::redraws`] says how often that happened.
//!
//! **Time and state.** t counts seconds from the initiation (second [`Wave::start_s`] of the
//! run). The snapshot at t is every agent's `state()` as second t begins, before the simulator
//! serves it: an agent activated at t − 1 is then active and relays at t. The initiator goes
//! from inactive to refractory in the instant it transmits ([`protocol::WaveNode`] never holds
//! an initiating agent in the active state), so [`Wave::shown`], the paper's colouring, counts
//! as active every agent that transmits at t: the active agents and, at t = 0, the initiator.
//!
//! **Paths.** The simulator delivers the transmissions of one second by increasing sender index
//! and an agent accepts the first message that reaches it while inactive, so the sender of the
//! message that activated agent `i` (its parent) is its lowest-index neighbour among the agents
//! that transmitted in the second before `i` was activated. The message `i` relays carries the
//! readings of the agents on the chain of parents back to the initiator: that chain is the path
//! the message took ([`Wave::path`]).
//!
//! The page's section, figure and CSV file of one wave are `pages::waves`.

use std::collections::VecDeque;
use std::f64::consts::{PI, TAU};

use nalgebra::Point2;
use protocol::{Duration, Params, WaveState};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

use crate::experiment::Error;
use crate::geometry::{Shape, Swarm};
use crate::seeds::derive;
use crate::sim::{RunConfig, Sim};
use hal_emu::world::field::Field;

/// The paper's snapshot times (Fig. 2 a–e), seconds after the initiation.
pub const SNAPSHOTS: [u64; 5] = [0, 2, 4, 11, 16];

/// Sectors around the swarm's centre in which [`Wave::path_ends`] picks the last agent reached
/// (panel f).
pub const PATH_SECTORS: usize = 5;

/// Protocol seeds tried before [`one_wave`] gives up finding a single wave.
const MAX_REDRAWS: u64 = 100;

/// The longest wave [`one_wave`] follows, seconds (a wave lasts its hops + refractory + 1).
const MAX_WAVE_S: u64 = 10_000;

/// What one wave is run with.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WaveSpec {
    /// Number of agents.
    pub agents: usize,
    /// Diameter of the disk they are placed in, in perception ranges R.
    #[serde(with = "crate::json")]
    pub diameter: f64,
    /// Refractory time `t_ref`, seconds.
    pub refractory_s: u64,
    /// Cycle `t_p^max`, seconds: long, so that one initiation falls in the wave's time.
    pub cycle_s: u64,
}

impl WaveSpec {
    /// The paper's Fig. 2: N = 80 agents in a swarm of 5 R, `t_ref` = 10 s; a cycle of
    /// 100,000 s (the figure shows one wave; the paper gives no cycle for it).
    pub const fn paper() -> Self {
        WaveSpec {
            agents: 80,
            diameter: 5.0,
            refractory_s: 10,
            cycle_s: 100_000,
        }
    }

    /// The run's configuration: [`Params::simulation_2d`] with this refractory time and cycle
    /// (relay delay 1 s, no cycle spread); uniform field, noise of width 1.
    pub fn config(&self) -> RunConfig {
        let mut params = Params::simulation_2d();
        params.wave.refractory = Duration::from_secs(self.refractory_s);
        params.wave.cycle = Duration::from_secs(self.cycle_s);
        RunConfig {
            params,
            step: 0.33,
            noise: 1.0,
            diversity: crate::measure::Measure::Variance,
            opposite: protocol::direction::Opposite::default(),
            sensor: crate::sim::Sensor::default(),
        }
    }
}

/// One wave from its initiation until every agent is inactive again.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Wave {
    /// What it was run with.
    pub spec: WaveSpec,
    /// The swarm; its offsets are the positions (centre of mass at the origin), range R = 1.
    pub swarm: Swarm,
    /// The agent that initiated the wave.
    pub initiator: usize,
    /// Second of the run at which it initiated (t = 0).
    pub start_s: u64,
    /// Protocol seeds discarded because a second wave started during this one.
    pub redraws: u64,
    /// `states[t][i]`: agent `i`'s `state()` as second t of the wave begins, for t from 0 to
    /// [`Wave::end_s`] (the first t > 0 at which every agent is inactive).
    #[serde(with = "crate::json")]
    pub states: Vec<Vec<WaveState>>,
    /// Per agent, the second of the wave at which it transmitted (0 for the initiator), `None`
    /// if the wave did not reach it.
    pub sent_at: Vec<Option<u64>>,
    /// Per agent, the neighbour whose message activated it (`None` for the initiator and the
    /// agents not reached).
    pub parent: Vec<Option<usize>>,
    /// Per agent, the messages it accepted (its `stats().accepted`).
    pub accepted: Vec<u32>,
}

/// Where the messages of one wave went, counted per delivery (one transmission heard by one
/// neighbour).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Deliveries {
    /// All deliveries.
    pub total: u64,
    /// Deliveries that activated an inactive agent.
    pub accepted: u64,
    /// Deliveries to agents that transmitted the wave in an earlier second (back toward the
    /// initiator): refractory, they ignore it.
    pub upstream: u64,
    /// Deliveries to agents that transmitted in the same second: refractory too.
    pub same_front: u64,
    /// Deliveries to agents already activated by an earlier delivery of the same second.
    pub already_active: u64,
}

impl Wave {
    /// Number of agents.
    pub fn len(&self) -> usize {
        self.swarm.len()
    }

    /// True for a swarm without agents.
    pub fn is_empty(&self) -> bool {
        self.swarm.is_empty()
    }

    /// Agent `i`'s position.
    pub fn position(&self, i: usize) -> Point2<f64> {
        self.swarm.position(i, Point2::origin())
    }

    /// Agent `i`'s `state()` as second `t` of the wave begins (inactive after the wave).
    pub fn state(&self, i: usize, t: u64) -> WaveState {
        self.states
            .get(t as usize)
            .map_or(WaveState::Inactive, |s| s[i])
    }

    /// Agent `i` at time `t` as the paper colours it: active if it transmits at `t` (an active
    /// agent relays, the initiator initiates at 0), otherwise its [`state`](Self::state).
    pub fn shown(&self, i: usize, t: u64) -> WaveState {
        if self.sent_at[i] == Some(t) {
            WaveState::Active
        } else {
            self.state(i, t)
        }
    }

    /// Agents inactive, active and refractory at `t`, as [`shown`](Self::shown).
    pub fn counts(&self, t: u64) -> [usize; 3] {
        let mut c = [0; 3];
        for i in 0..self.len() {
            c[match self.shown(i, t) {
                WaveState::Inactive => 0,
                WaveState::Active => 1,
                WaveState::Refractory => 2,
            }] += 1;
        }
        c
    }

    /// The first t > 0 at which every agent is inactive again.
    pub fn end_s(&self) -> u64 {
        self.states.len().saturating_sub(1) as u64
    }

    /// Agents the wave reached, the initiator included.
    pub fn reached(&self) -> usize {
        self.sent_at.iter().flatten().count()
    }

    /// The last second at which an agent transmitted: the hops from the initiator to the
    /// farthest agents.
    pub fn last_hop(&self) -> u64 {
        self.sent_at.iter().flatten().copied().max().unwrap_or(0)
    }

    /// The path of the message that activated agent `i`: the initiator, the agents that relayed
    /// it, `i` (just the initiator for the initiator; empty if the wave did not reach `i`).
    pub fn path(&self, i: usize) -> Vec<usize> {
        if self.sent_at[i].is_none() {
            return Vec::new();
        }
        let mut p = vec![i];
        let mut at = i;
        while let Some(up) = self.parent[at] {
            p.push(up);
            at = up;
        }
        p.reverse();
        p
    }

    /// In each of `sectors` equal sectors around the swarm's centre (the first starting at
    /// −π), the agent the wave reached last (ties: the one farthest from the initiator, then
    /// the lowest index); empty sectors give none.
    pub fn path_ends(&self, sectors: usize) -> Vec<usize> {
        let sectors = sectors.max(1);
        let origin = self.position(self.initiator);
        let mut best: Vec<Option<(u64, f64, usize)>> = vec![None; sectors];
        for i in 0..self.len() {
            let Some(h) = self.sent_at[i] else { continue };
            let o = self.swarm.offsets()[i];
            let s = (((o.y.atan2(o.x) + PI) / TAU * sectors as f64) as usize).min(sectors - 1);
            let d = (self.position(i) - origin).norm();
            let better = match best[s] {
                None => true,
                Some((bh, bd, _)) => h > bh || (h == bh && d > bd),
            };
            if better {
                best[s] = Some((h, d, i));
            }
        }
        best.into_iter().flatten().map(|(_, _, i)| i).collect()
    }

    /// Where the wave's messages went, from the seconds at which the agents transmitted and
    /// the neighbour lists (every neighbour hears every transmission).
    pub fn deliveries(&self) -> Deliveries {
        let mut d = Deliveries::default();
        for (j, h) in self.sent_at.iter().enumerate() {
            let Some(h) = *h else { continue };
            for l in self.swarm.neighbours(j) {
                d.total += 1;
                match self.sent_at[l.agent as usize] {
                    Some(hr) if hr < h => d.upstream += 1,
                    Some(hr) if hr == h => d.same_front += 1,
                    _ => d.already_active += 1,
                }
            }
        }
        // Of the deliveries to agents that transmit a second later, one per agent activated it.
        d.accepted = self.reached().saturating_sub(1) as u64;
        d.already_active = d.already_active.saturating_sub(d.accepted);
        d
    }
}

/// One wave through a swarm placed from `seed` (see the module's doc): places `spec.agents`
/// agents in a disk of `spec.diameter` (redrawn until connected), runs the simulator from
/// protocol seeds derived from `seed` until the first initiation's wave is the only one, and
/// records the agents' states every second until all are inactive again.
///
/// # Errors
/// If the swarm cannot be placed, the configuration does not validate, no single wave was found
/// in 100 protocol seeds, or the wave lasts more than 10,000 s.
pub fn one_wave(spec: &WaveSpec, seed: u64) -> Result<Wave, Error> {
    let mut rng = Pcg64Mcg::seed_from_u64(derive(seed, &[0]));
    let swarm = Swarm::place(
        spec.agents,
        Shape::Disk {
            diameter: spec.diameter,
        },
        1.0,
        &mut rng,
    )?;
    for redraws in 0..MAX_REDRAWS {
        if let Some(mut w) = follow(spec, &swarm, derive(seed, &[1, redraws]))? {
            w.redraws = redraws;
            return Ok(w);
        }
    }
    Err(WaveError::NoSingleWave(MAX_REDRAWS).into())
}

/// Why one wave could not be had.
#[derive(Debug, thiserror::Error)]
pub enum WaveError {
    /// Every protocol seed tried started two waves at once.
    #[error("no single wave in {0} protocol seeds")]
    NoSingleWave(u64),
    /// The swarm has no agent.
    #[error("no agents")]
    NoAgents,
    /// The wave was still going at the horizon, seconds.
    #[error("the wave lasted more than {0} s")]
    TooLong(u64),
}

/// Transmissions so far of an agent: waves initiated and messages relayed.
fn transmissions(a: &crate::sim::Agent) -> u32 {
    let s = a.wave_stats();
    s.initiated.wrapping_add(s.relayed)
}

/// Runs one protocol seed; `None` if its first wave is not alone.
fn follow(spec: &WaveSpec, swarm: &Swarm, seed: u64) -> Result<Option<Wave>, Error> {
    let field = Field::default();
    let mut sim = Sim::new(swarm, &field, spec.config(), Point2::origin(), seed)?;
    // The states are read every second.
    sim.keep_states();
    let n = swarm.len();
    // Before anything happens each agent's next timeout is its first initiation.
    let first: Vec<u64> = sim
        .agents()
        .iter()
        .map(|a| a.poll_timeout().as_millis().div_ceil(1000))
        .collect();
    let Some(&start) = first.iter().min() else {
        return Err(WaveError::NoAgents.into());
    };
    let mut firsts = first.iter().enumerate().filter(|&(_, &t)| t == start);
    let Some((initiator, _)) = firsts.next() else {
        return Err(WaveError::NoAgents.into());
    };
    if firsts.next().is_some() {
        return Ok(None);
    }
    sim.run_until(start.saturating_sub(1));
    let mut states = Vec::new();
    let mut sent_at: Vec<Option<u64>> = vec![None; n];
    let mut sent: Vec<u32> = sim.agents().iter().map(transmissions).collect();
    for t in 0..=MAX_WAVE_S {
        let now: Vec<WaveState> = sim.agents().iter().map(|a| a.state()).collect();
        let over = t > 0 && now.iter().all(|&s| s == WaveState::Inactive);
        states.push(now);
        if over {
            let initiated: u32 = sim.agents().iter().map(|a| a.wave_stats().initiated).sum();
            if initiated != 1 {
                return Ok(None);
            }
            let parent = (0..n)
                .map(|i| {
                    let h = sent_at[i]?.checked_sub(1)?;
                    swarm
                        .neighbours(i)
                        .iter()
                        .map(|l| l.agent as usize)
                        .find(|&j| sent_at[j] == Some(h))
                })
                .collect();
            return Ok(Some(Wave {
                spec: *spec,
                swarm: swarm.clone(),
                initiator,
                start_s: start,
                redraws: 0,
                states,
                sent_at,
                parent,
                accepted: sim.agents().iter().map(|a| a.stats().accepted).collect(),
            }));
        }
        sim.run_until(start + t);
        for (i, a) in sim.agents().iter().enumerate() {
            let now = transmissions(a);
            if now != sent[i] {
                if sent_at[i].is_some() {
                    return Ok(None); // a second transmission: a second wave passed
                }
                sent_at[i] = Some(t);
                sent[i] = now;
            }
        }
    }
    Err(WaveError::TooLong(MAX_WAVE_S).into())
}

/// Hops from agent `from` to every agent in the neighbour graph (breadth-first search; `None`
/// for agents it cannot reach).
pub fn hops_from(swarm: &Swarm, from: usize) -> Vec<Option<u64>> {
    let mut d = vec![None; swarm.len()];
    let mut q = VecDeque::new();
    if from < swarm.len() {
        d[from] = Some(0);
        q.push_back((from, 0));
    }
    while let Some((i, h)) = q.pop_front() {
        for l in swarm.neighbours(i) {
            let j = l.agent as usize;
            if d[j].is_none() {
                d[j] = Some(h + 1);
                q.push_back((j, h + 1));
            }
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wave(seed: u64) -> Wave {
        one_wave(&WaveSpec::paper(), seed).unwrap()
    }

    #[test]
    fn one_agent_starts_and_the_front_is_the_agents_t_hops_away() {
        for seed in [1, 2, 3] {
            let w = wave(seed);
            assert_eq!(w.len(), 80);
            assert!(w.swarm.is_connected());
            let d = hops_from(&w.swarm, w.initiator);
            // The initiator is the only agent shown active at t = 0; the protocol holds it
            // inactive until it transmits.
            assert_eq!(w.counts(0), [79, 1, 0]);
            assert_eq!(w.shown(w.initiator, 0), WaveState::Active);
            assert_eq!(w.state(w.initiator, 0), WaveState::Inactive);
            for t in 0..=w.end_s() {
                for (i, &hops) in d.iter().enumerate() {
                    // Active at t: exactly the agents t hops from the initiator.
                    assert_eq!(
                        w.shown(i, t) == WaveState::Active,
                        hops == Some(t),
                        "seed {seed}, agent {i}, t {t}"
                    );
                    // And that is the agents' own state, but for the initiator at 0.
                    if t > 0 {
                        assert_eq!(w.shown(i, t), w.state(i, t));
                    }
                }
            }
            assert_eq!(
                w.sent_at, d,
                "every agent relays t hops after the initiation"
            );
            assert_eq!(w.reached(), 80);
        }
    }

    #[test]
    fn refractory_agents_are_those_that_sent_within_the_refractory_time() {
        let w = wave(1);
        for t in 0..=w.end_s() {
            for i in 0..w.len() {
                let h = w.sent_at[i].unwrap();
                let refractory = h < t && t <= h + 10;
                assert_eq!(
                    w.state(i, t) == WaveState::Refractory,
                    refractory,
                    "agent {i} sent at {h}, t {t}"
                );
            }
        }
        // Panel (d): at t = 11 the initiator is inactive again, the agents 1–10 hops out are
        // refractory.
        assert_eq!(w.state(w.initiator, 10), WaveState::Refractory);
        assert_eq!(w.state(w.initiator, 11), WaveState::Inactive);
        // The wave is over 11 s after the last relay.
        assert_eq!(w.end_s(), w.last_hop() + 11);
        assert!(w.last_hop() >= 4, "a 5 R swarm is several hops across");
    }

    #[test]
    fn no_agent_is_active_twice_and_refractory_agents_block_the_backflow() {
        let w = wave(2);
        for i in 0..w.len() {
            let active = (0..=w.end_s())
                .filter(|&t| w.shown(i, t) == WaveState::Active)
                .count();
            assert_eq!(active, 1, "agent {i}");
            let expected = u32::from(i != w.initiator);
            assert_eq!(w.accepted[i], expected, "agent {i} accepted once");
        }
        let d = w.deliveries();
        assert_eq!(d.accepted, 79);
        assert_eq!(
            d.total,
            (0..w.len())
                .map(|i| w.swarm.neighbours(i).len() as u64)
                .sum::<u64>()
        );
        assert_eq!(
            d.accepted + d.upstream + d.same_front + d.already_active,
            d.total
        );
        assert!(d.upstream > 0);
    }

    #[test]
    fn paths_follow_parents_one_hop_at_a_time_from_the_initiator() {
        let w = wave(3);
        let ends = w.path_ends(PATH_SECTORS);
        assert!((3..=PATH_SECTORS).contains(&ends.len()), "{ends:?}");
        // The agents reached last are the last of their sectors.
        assert!(ends.iter().any(|&e| w.sent_at[e] == Some(w.last_hop())));
        for &e in &ends {
            let p = w.path(e);
            assert_eq!(p[0], w.initiator);
            assert_eq!(*p.last().unwrap(), e);
            assert_eq!(p.len() as u64, w.sent_at[e].unwrap() + 1);
            for (k, pair) in p.windows(2).enumerate() {
                let (a, b) = (pair[0], pair[1]);
                assert_eq!(w.sent_at[a], Some(k as u64));
                assert!((w.position(a) - w.position(b)).norm() <= 1.0, "in range");
                // `b` was activated the second `a` transmitted, and `a` is its first sender.
                assert_eq!(w.state(b, k as u64 + 1), WaveState::Active);
                assert!(
                    w.swarm
                        .neighbours(b)
                        .iter()
                        .map(|l| l.agent as usize)
                        .filter(|&j| w.sent_at[j] == Some(k as u64))
                        .all(|j| j >= a)
                );
            }
        }
        assert_eq!(w.path(w.initiator), vec![w.initiator]);
    }

    #[test]
    fn same_seed_same_wave_and_it_is_cheap() {
        let t = std::time::Instant::now();
        let (a, b) = (wave(7), wave(7));
        assert!(t.elapsed().as_secs_f64() < 1.0);
        assert_eq!(a.initiator, b.initiator);
        assert_eq!(a.states, b.states);
        assert_eq!(a.parent, b.parent);
        assert_ne!(wave(8).swarm.offsets(), a.swarm.offsets());
    }

    #[test]
    fn a_second_wave_is_redrawn() {
        // A cycle so short that other initiations fall inside the first wave: the seeds that
        // give one are skipped, and the wave found is still alone.
        let spec = WaveSpec {
            cycle_s: 2_000,
            ..WaveSpec::paper()
        };
        let found: Vec<Wave> = (0..20).filter_map(|s| one_wave(&spec, s).ok()).collect();
        assert!(found.iter().any(|w| w.redraws > 0));
        for w in &found {
            assert_eq!(w.reached(), 80);
            assert_eq!(w.accepted.iter().sum::<u32>(), 79);
        }
    }
}
