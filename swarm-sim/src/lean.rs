//! The lean engine: the plain runs of [`Sim`](crate::sim::Sim) (one quantity, the variance,
//! a fresh reading per activation, nothing recorded or tapped), with the three-phase agents'
//! rules written out over plain per-agent records instead of stepping
//! [`ThreePhaseAgent`](protocol::ThreePhaseAgent)s. [`crate::experiment`]'s runs use it
//! whenever it covers the run (`LeanSim::new` says); everything else (recording, taps,
//! entropy, two quantities, one reading per period, the agents' own counters) stays on
//! [`Sim`](crate::sim::Sim).
//!
//! It is a second implementation of the same rules, so it is held to the first bit for bit:
//! the same random draws in the same order, the same messages, scores, opinions and moves.
//! `tests::the_lean_engine_runs_the_agents_runs_bit_for_bit` runs both over many seeds and
//! settings (cycle spread, initiation point, phase lengths, fractional delays, the opposite
//! rule, with and without the observer's diversity) and compares every period, so a change
//! to `ThreePhaseAgent` or `WaveNode` that is not made here too fails it; the reproduction
//! page, made with it, is CI's other check (it must come out the same). What it saves is
//! the generality the agent needs and a plain run does not: the events, the outbox, the
//! per-call bookkeeping of a sans-IO node, the timer wheel (a run has two timers per agent
//! and cycle), the generic reading and measure types.
//!
//! Time is in milliseconds (the protocol's `Instant`s), served at whole seconds as the
//! simulator serves them (a part of a second counting as the next).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use nalgebra::Point2;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use hal_emu::world::field::Field;
use protocol::direction::{turn_toward_by, wrap_positive};
use protocol::diversity::{Diversity, Moments, Pool, Variance};
use protocol::params::{InitiationPoint, Params};
use protocol::weights::DirectionWeights;

use crate::geometry::Swarm;
use crate::measure::Measure;
use crate::reading::Reading;
use crate::sim::{MESSAGE_READINGS, Period, RunConfig, Sensor, SimError, next_period};

/// "Never" (and "none" for a pending initiation).
const NEVER: u64 = u64::MAX;

/// The wave states.
const INACTIVE: u8 = 0;
const ACTIVE: u8 = 1;
const REFRACTORY: u8 = 2;

/// The distinct bearings an agent scores per period, as [`crate::sim::AgentOf`] has them.
const SLOTS: usize = 16;

/// What a poll of an agent's wave timers did ([`protocol::wave::WaveAction`]).
enum Action {
    Initiate,
    Relay,
    Rested,
    CycleEnded,
}

/// One agent: its wave node's timers and state, its three-phase state and its message.
#[derive(Clone)]
struct Agent {
    state: u8,
    gathering: bool,
    pending: bool,
    /// Whether `msg` is a gathering message (readings) or an opinion.
    msg_readings: bool,
    msg_len: u8,
    phase_cycles: u16,
    /// The sum of the readings of `msg`, added up in order from `0.0` as they were appended
    /// (what [`Variance::measure_summed`] needs: the same bits as adding them up again).
    msg_sum: f32,
    relay_at: u64,
    rest_at: u64,
    cycle_end: u64,
    init_at: u64,
    /// When something is next due (the wave node's `poll_timeout` as of the last call).
    next: u64,
    reading: f32,
    preferred: Option<f32>,
    decision: Option<f32>,
    last_diversity: f32,
    weights: DirectionWeights<u32, SLOTS>,
    stored: Moments,
    /// The message to relay, or the one last sent (a receiver reads it in the second it went
    /// out; the sender is then refractory and overwrites it only when it hears again).
    msg: [f32; MESSAGE_READINGS],
}

impl Agent {
    /// An agent starting its first cycle (gathering) at 0, inactive: `WaveNode::new` and
    /// `ThreePhaseAgent::with_diversity`, with the same draws.
    fn new(params: &Params, rng: &mut Pcg64Mcg) -> Agent {
        let mut a = Agent {
            state: INACTIVE,
            gathering: true,
            pending: false,
            msg_readings: false,
            msg_len: 0,
            phase_cycles: 0,
            msg_sum: 0.0,
            relay_at: NEVER,
            rest_at: NEVER,
            cycle_end: 0,
            init_at: NEVER,
            next: 0,
            reading: 0.0,
            preferred: None,
            decision: None,
            last_diversity: 0.0,
            weights: DirectionWeights::default(),
            stored: Variance.pool(),
            msg: [0.0; MESSAGE_READINGS],
        };
        start_cycle(params, &mut a, 0, rng);
        a.next = a.poll_timeout();
        a
    }

    #[inline]
    fn timers_at(&self) -> u64 {
        self.cycle_end.min(self.init_at)
    }

    #[inline]
    fn poll_timeout(&self) -> u64 {
        let t = self.timers_at();
        match self.state {
            ACTIVE => t.min(self.relay_at),
            REFRACTORY => t.min(self.rest_at),
            _ => t,
        }
    }

    #[inline]
    fn poll_timeout_rested(&self) -> u64 {
        let t = self.timers_at();
        if self.state == ACTIVE {
            t.min(self.relay_at)
        } else {
            t
        }
    }

    /// [`crate::sim`]'s `hears_from`: the first instant it hears a message.
    #[inline]
    fn hears_from(&self) -> u64 {
        match self.state {
            INACTIVE => 0,
            ACTIVE => NEVER,
            _ => self.rest_at,
        }
    }
}

/// A run of the lean engine; see the module.
pub struct LeanSim<'a> {
    swarm: &'a Swarm,
    field: &'a Field,
    cfg: RunConfig,
    params: Params,
    agents: Vec<Agent>,
    /// Per agent, as [`crate::sim::Sim`]'s: the first instant it hears.
    hears: Vec<u64>,
    /// Per link of [`Swarm::neighbours`] (all agents' in order), the neighbour and the slot
    /// key of the bearing it hears from: what a delivery reads, side by side.
    links: Vec<(u32, u32)>,
    /// Per agent, where its links start in `links` (and, last, where they end).
    link_start: Vec<u32>,
    centre: Point2<f64>,
    periods: u32,
    proto_rng: Pcg64Mcg,
    noise_rng: Pcg64Mcg,
    /// The agents' timer seconds, with stale entries (an entry is current if `timer_s` says so).
    timers: BinaryHeap<Reverse<(u64, u32)>>,
    timer_s: Vec<u64>,
    /// Relays by second.
    relays: Relays,
    due: Vec<u32>,
    tx: Vec<u32>,
    relay_secs: u64,
    pooling: bool,
    means: Vec<f64>,
}

/// The relays of a run by the second they are due. The relay delay is the same for every agent
/// of a run, so the relays heard in second `t` are all due at `t + d` (`d` whole seconds, a
/// part counting as one), and at any time the lists pending are of `d + 1` consecutive
/// seconds at most: a ring of lists, one per second modulo a power of two `≥ d + 1`, each with
/// the second it holds. (The order within a second does not matter: a second's due agents are
/// served in index order.)
struct Relays {
    /// Per slot, its second ([`NEVER`]: empty) and its agents.
    slots: Vec<(u64, Vec<u32>)>,
    mask: u64,
}

impl Relays {
    fn new(delay_secs: u64) -> Relays {
        let len = delay_secs.saturating_add(1).next_power_of_two();
        Relays {
            slots: (0..len).map(|_| (NEVER, Vec::new())).collect(),
            mask: len - 1,
        }
    }

    /// The earliest second with a relay due ([`NEVER`]: none).
    #[inline]
    fn first_second(&self) -> u64 {
        self.slots.iter().map(|s| s.0).min().unwrap_or(NEVER)
    }

    /// Agent `i` relays at second `s`.
    #[inline]
    fn push(&mut self, s: u64, i: u32) {
        let slot = &mut self.slots[(s & self.mask) as usize];
        debug_assert!(slot.0 == NEVER || slot.0 == s, "two seconds in one slot");
        slot.0 = s;
        slot.1.push(i);
    }

    /// Appends the agents relaying at second `t` to `out` and forgets them.
    #[inline]
    fn take(&mut self, t: u64, out: &mut Vec<u32>) {
        let slot = &mut self.slots[(t & self.mask) as usize];
        if slot.0 == t {
            out.extend_from_slice(&slot.1);
            slot.1.clear();
            slot.0 = NEVER;
        }
    }
}

/// The slot key of a bearing, as `ThreePhaseAgent` keys it.
fn key(bearing: f32) -> u32 {
    let b = wrap_positive(bearing);
    if b.is_nan() { u32::MAX } else { b.to_bits() }
}

impl<'a> LeanSim<'a> {
    /// The run [`Sim::new`](crate::sim::Sim::new) would make, if the lean engine can run it:
    /// `Ok(None)` for a run it does not cover (a measure other than the variance, or one
    /// reading per period).
    ///
    /// # Errors
    /// As [`Sim::new`](crate::sim::Sim::new).
    pub fn new(
        swarm: &'a Swarm,
        field: &'a Field,
        cfg: RunConfig,
        centre: Point2<f64>,
        seed: u64,
    ) -> Result<Option<Self>, SimError> {
        if cfg.diversity != Measure::Variance || cfg.sensor != Sensor::PerActivation {
            return Ok(None);
        }
        cfg.check()?;
        let params = cfg.params;
        let mut proto_rng = Pcg64Mcg::seed_from_u64(crate::seeds::derive(seed, &[1]));
        let noise_rng = Pcg64Mcg::seed_from_u64(crate::seeds::derive(seed, &[2]));
        let n = swarm.len();
        let agents: Vec<Agent> = (0..n)
            .map(|_| Agent::new(&params, &mut proto_rng))
            .collect();
        let mut links = Vec::new();
        let mut link_start = Vec::with_capacity(n + 1);
        for i in 0..n {
            link_start.push(links.len() as u32);
            links.extend(
                swarm
                    .neighbours(i)
                    .iter()
                    .map(|l| (l.agent, key(l.bearing))),
            );
        }
        link_start.push(links.len() as u32);
        let relay_secs = secs_ms(params.wave.relay_delay.as_millis());
        let timer_s: Vec<u64> = agents.iter().map(|a| secs_ms(a.timers_at())).collect();
        let timers = timer_s
            .iter()
            .enumerate()
            .map(|(i, &s)| Reverse((s, i as u32)))
            .collect();
        let mut sim = LeanSim {
            swarm,
            field,
            cfg,
            params,
            hears: agents.iter().map(Agent::hears_from).collect(),
            agents,
            links,
            link_start,
            centre,
            periods: 0,
            proto_rng,
            noise_rng,
            timers,
            timer_s,
            relays: Relays::new(relay_secs),
            due: Vec::new(),
            tx: Vec::new(),
            relay_secs,
            pooling: true,
            means: Vec::with_capacity(n),
        };
        sim.place_means();
        Ok(Some(sim))
    }

    /// [`Sim::without_diversity`](crate::sim::Sim::without_diversity).
    pub fn without_diversity(&mut self) {
        self.pooling = false;
    }

    /// The centre of mass.
    pub fn centre(&self) -> Point2<f64> {
        self.centre
    }

    fn place_means(&mut self) {
        self.means.clear();
        for i in 0..self.swarm.len() {
            let at = self.swarm.position(i, self.centre);
            self.means.push(self.field.mean(at));
        }
    }

    #[inline]
    fn draw(&mut self, i: usize) -> f32 {
        f32::sample(&self.means[i..i + 1], self.cfg.noise, &mut self.noise_rng)
    }

    /// [`Sim::run_period`](crate::sim::Sim::run_period).
    ///
    /// # Errors
    /// As [`Sim::run_period`](crate::sim::Sim::run_period).
    pub fn run_period(&mut self) -> Result<Period, SimError> {
        let (index, end) = next_period(&self.cfg, self.periods)?;
        self.advance_to(end);
        self.periods = index;
        let p = Period::ending(
            index,
            end,
            self.centre,
            self.cfg.step,
            self.agents.iter().map(|a| (a.decision, a.last_diversity)),
        );
        if p.direction.is_some() {
            self.centre = p.to;
            self.place_means();
        }
        Ok(p)
    }

    fn advance_to(&mut self, until: u64) {
        loop {
            while let Some(&Reverse((s, i))) = self.timers.peek() {
                if self.timer_s[i as usize] == s {
                    break;
                }
                self.timers.pop();
            }
            let h = self.timers.peek().map_or(NEVER, |r| r.0.0);
            let q = self.relays.first_second();
            let t = h.min(q);
            if t == NEVER || t > until {
                return;
            }
            self.second(t);
        }
    }

    fn second(&mut self, t: u64) {
        let now = t.saturating_mul(1000);
        let mut due = std::mem::take(&mut self.due);
        while let Some(&Reverse((s, i))) = self.timers.peek() {
            if s != t {
                break;
            }
            self.timers.pop();
            if self.timer_s[i as usize] == s {
                due.push(i);
            }
        }
        self.relays.take(t, &mut due);
        due.sort_unstable();
        due.dedup();
        for &i in &due {
            self.serve(i as usize, now);
        }
        due.clear();
        self.due = due;
        self.deliver(t, now);
    }

    /// Sim's `serve_due` for agent `i`.
    #[inline]
    fn serve(&mut self, i: usize, now: u64) {
        // Most calls: a relay due and its timers not (the agent is active, so no reading is
        // drawn): what `handle_timeout` does then, written out.
        let a = &mut self.agents[i];
        let timers = a.timers_at();
        if a.state == ACTIVE && a.relay_at <= now && timers > now {
            a.state = REFRACTORY;
            a.rest_at = a
                .relay_at
                .saturating_add(self.params.wave.refractory.as_millis());
            a.next = timers.min(a.rest_at);
            self.hears[i] = a.rest_at;
            if a.pending {
                a.pending = false;
                a.add_own();
                self.tx.push(i as u32);
            }
            return;
        }
        if self.hears[i] != NEVER && self.agents[i].timers_at() <= now {
            let x = self.draw(i);
            self.agents[i].reading = x;
        }
        self.handle_timeout(i, now);
        let a = &self.agents[i];
        self.hears[i] = a.hears_from();
        let s = secs_ms(a.timers_at());
        if s != self.timer_s[i] {
            self.timer_s[i] = s;
            self.timers.push(Reverse((s, i as u32)));
        }
    }

    /// `ThreePhaseAgent::handle_timeout`: inlined (nothing due, or a lone rest, is most calls).
    #[inline(always)]
    fn handle_timeout(&mut self, i: usize, now: u64) {
        let a = &mut self.agents[i];
        if a.next > now {
            return;
        }
        if a.state == REFRACTORY && a.rest_at <= now && a.poll_timeout_rested() > now {
            a.state = INACTIVE;
            a.next = a.poll_timeout();
            return;
        }
        self.handle_due(i, now);
    }

    /// `ThreePhaseAgent::handle_due`.
    #[inline(never)]
    fn handle_due(&mut self, i: usize, now: u64) {
        let a = &mut self.agents[i];
        let at = a.relay_at;
        if a.state == ACTIVE && at <= now && at != NEVER && at <= a.timers_at() {
            a.state = REFRACTORY;
            a.rest_at = at.saturating_add(self.params.wave.refractory.as_millis());
            self.relayed(i);
            let a = &mut self.agents[i];
            let next = a.poll_timeout();
            if next > now {
                a.next = next;
                return;
            }
        }
        while let Some(action) = self.poll(i, now) {
            match action {
                Action::Initiate => self.send(i, false),
                Action::Relay => self.relayed(i),
                Action::Rested => {}
                Action::CycleEnded => self.end_cycle(i),
            }
        }
        let a = &mut self.agents[i];
        a.next = a.poll_timeout();
    }

    /// `WaveNode::poll`: the earliest transition due, ties in the order refractory end,
    /// relay, initiation, cycle end.
    fn poll(&mut self, i: usize, now: u64) -> Option<Action> {
        let refractory = self.params.wave.refractory.as_millis();
        loop {
            let a = &mut self.agents[i];
            if a.poll_timeout() > now {
                return None;
            }
            let mut best: Option<(u8, u64)> = None;
            let mut consider = |which: u8, t: u64| {
                if t <= now && t != NEVER && best.is_none_or(|(_, b)| t < b) {
                    best = Some((which, t));
                }
            };
            if a.state == REFRACTORY {
                consider(0, a.rest_at);
            }
            if a.state == ACTIVE {
                consider(1, a.relay_at);
            }
            consider(2, a.init_at);
            consider(3, a.cycle_end);
            let (which, at) = best?;
            return Some(match which {
                0 => {
                    a.state = INACTIVE;
                    Action::Rested
                }
                1 => {
                    a.state = REFRACTORY;
                    a.rest_at = at.saturating_add(refractory);
                    Action::Relay
                }
                2 => {
                    a.init_at = NEVER;
                    if a.state != INACTIVE {
                        // Skipped while busy: whatever else is due.
                        continue;
                    }
                    a.state = REFRACTORY;
                    a.rest_at = at.saturating_add(refractory);
                    Action::Initiate
                }
                _ => {
                    start_cycle(&self.params, a, at, &mut self.proto_rng);
                    Action::CycleEnded
                }
            });
        }
    }

    fn relayed(&mut self, i: usize) {
        let a = &mut self.agents[i];
        if a.pending {
            a.pending = false;
            self.send(i, true);
        }
    }

    /// `ThreePhaseAgent::send`: the message to relay (or a new one of the phase) with the
    /// agent's own contribution, out this second.
    fn send(&mut self, i: usize, relay: bool) {
        let a = &mut self.agents[i];
        if !relay {
            a.msg_readings = a.gathering;
            a.msg_len = 0;
            a.msg_sum = 0.0;
        }
        a.add_own();
        self.tx.push(i as u32);
    }

    /// `ThreePhaseAgent::end_cycle`.
    fn end_cycle(&mut self, i: usize) {
        let (gather, decide) = (self.params.gather_cycles, self.params.decide_cycles);
        let a = &mut self.agents[i];
        a.phase_cycles = a.phase_cycles.saturating_add(1);
        if a.gathering && a.phase_cycles >= gather {
            a.preferred = a
                .weights
                .heaviest()
                .map(f32::from_bits)
                .filter(|b| b.is_finite());
            a.last_diversity = a.stored.value();
            a.weights.clear();
            a.stored = Variance.pool();
            a.gathering = false;
            a.phase_cycles = 0;
            a.pending = false;
        } else if !a.gathering && a.phase_cycles >= decide {
            a.decision = a.preferred;
            a.gathering = true;
            a.phase_cycles = 0;
            a.pending = false;
        }
    }

    /// Sim's `deliver`: this second's messages to every neighbour that hears.
    fn deliver(&mut self, t: u64, now: u64) {
        let tx = std::mem::take(&mut self.tx);
        // Out of `self` while it is read (the calls below borrow `self` mutably).
        let links = std::mem::take(&mut self.links);
        let due = t + self.relay_secs;
        for &s in &tx {
            let s = s as usize;
            let span = self.link_start[s] as usize..self.link_start[s + 1] as usize;
            for &(r, key) in &links[span] {
                let r = r as usize;
                if now < self.hears[r] {
                    continue;
                }
                let own = self.draw(r);
                self.agents[r].reading = own;
                self.handle_timeout(r, now);
                let accepted = self.hear(s, r, key, now);
                self.hears[r] = if accepted { NEVER } else { 0 };
                if accepted {
                    self.relays.push(due, r as u32);
                }
            }
        }
        self.links = links;
        // A receiver's call only rests it or makes it active: it sends nothing now.
        debug_assert!(self.tx.is_empty());
        let mut tx = tx;
        tx.clear();
        self.tx = tx;
    }

    /// `ThreePhaseAgent::handle_message` after its timeout: agent `r` hears `s`'s message
    /// from the bearing keyed `key`; `true` if it became active.
    #[inline]
    fn hear(&mut self, s: usize, r: usize, key: u32, now: u64) -> bool {
        let (diffusion, opposite, relay_ms) = (
            self.params.diffusion,
            self.cfg.opposite,
            self.params.wave.relay_delay.as_millis(),
        );
        let pooling = self.pooling;
        let Ok([from, to]) = self.agents.get_disjoint_mut([s, r]) else {
            return false;
        };
        let in_phase = if to.gathering {
            from.msg_readings && from.msg_len > 0
        } else {
            !from.msg_readings
        };
        if !in_phase || to.state != INACTIVE {
            return false;
        }
        to.state = ACTIVE;
        to.relay_at = now.saturating_add(relay_ms);
        to.next = to.next.min(to.relay_at);
        if from.msg_readings {
            let rs = &from.msg[..usize::from(from.msg_len)];
            let v = Variance::measure_summed(rs, from.msg_sum, to.reading);
            let _ = to.weights.add(key, v);
            if pooling {
                for &x in rs {
                    Pool::push(&mut to.stored, x);
                }
                Pool::push(&mut to.stored, to.reading);
            }
            to.msg[..rs.len()].copy_from_slice(rs);
            to.msg_len = from.msg_len;
            to.msg_sum = from.msg_sum;
            to.msg_readings = true;
        } else {
            if let Some(o) = from.preferred_sent()
                && o.is_finite()
            {
                to.preferred = Some(match to.preferred {
                    None => wrap_positive(o),
                    Some(p) => turn_toward_by(p, o, diffusion, opposite),
                });
            }
            to.msg_readings = false;
        }
        to.pending = true;
        true
    }
}

impl Agent {
    /// Puts the agent's own contribution into its message as it goes out: its reading (a
    /// full message drops its oldest), or nothing for an opinion, which is its preferred
    /// bearing as it stands ([`Agent::preferred_sent`]).
    #[inline]
    fn add_own(&mut self) {
        if self.msg_readings {
            let len = usize::from(self.msg_len);
            if len < MESSAGE_READINGS {
                self.msg[len] = self.reading;
                self.msg_len += 1;
                self.msg_sum += self.reading;
            } else {
                self.msg.copy_within(1.., 0);
                self.msg[MESSAGE_READINGS - 1] = self.reading;
                self.msg_sum = 0.0;
                for &x in &self.msg {
                    self.msg_sum += x;
                }
            }
        }
    }

    /// The opinion its last message carried: its preferred bearing as it sent it, which is
    /// its preferred bearing now (it is refractory since, and only a message heard changes
    /// it).
    #[inline]
    fn preferred_sent(&self) -> Option<f32> {
        self.preferred
    }
}

/// The second an instant in milliseconds is served at (a part of a second counts as
/// the next).
#[inline]
fn secs_ms(ms: u64) -> u64 {
    ms.div_ceil(1000)
}

/// `WaveNode::start_cycle`: a cycle starting at `start` (ms): its length and initiation.
fn start_cycle(p: &Params, a: &mut Agent, start: u64, rng: &mut Pcg64Mcg) {
    let w = &p.wave;
    let tick = w.tick.as_millis().max(1);
    let lo = (w.cycle - w.cycle_spread).as_millis() / tick;
    let hi = (w.cycle + w.cycle_spread).as_millis() / tick;
    let len_ticks = if hi > lo {
        rng.random_range(lo..=hi)
    } else {
        lo
    }
    .max(1);
    a.cycle_end = start.saturating_add(len_ticks.saturating_mul(tick));
    a.init_at = match w.initiation {
        InitiationPoint::EndOfCycle => a.cycle_end,
        InitiationPoint::Uniform => {
            start.saturating_add(rng.random_range(1..=len_ticks).saturating_mul(tick))
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;
    use crate::sim::Sim;
    use nalgebra::Vector2;
    use protocol::direction::Opposite;
    use protocol::params::InitiationPoint;
    use protocol::time::Duration;

    /// A setting of the protocol the lean engine must follow as the agents do.
    fn settings() -> Vec<(&'static str, RunConfig)> {
        let base = RunConfig {
            params: Params::simulation_2d(),
            step: 0.33,
            noise: 1.0,
            diversity: Measure::Variance,
            opposite: Opposite::default(),
            sensor: Sensor::default(),
        };
        let with = |f: &dyn Fn(&mut RunConfig)| {
            let mut c = base;
            f(&mut c);
            c
        };
        vec![
            ("the paper's", base),
            (
                "short cycle, keep on opposite",
                with(&|c| {
                    c.params.wave.cycle = Duration::from_secs(20);
                    c.opposite = Opposite::Keep;
                }),
            ),
            (
                "cycle spread, end-of-cycle initiation",
                with(&|c| {
                    c.params.wave.cycle = Duration::from_secs(60);
                    c.params.wave.cycle_spread = Duration::from_secs(15);
                    c.params.wave.initiation = InitiationPoint::EndOfCycle;
                }),
            ),
            (
                "longer phases, fractional delays",
                with(&|c| {
                    c.params.wave.cycle = Duration::from_millis(45_500);
                    c.params.wave.tick = Duration::from_millis(500);
                    c.params.wave.relay_delay = Duration::from_millis(1_500);
                    c.params.wave.refractory = Duration::from_millis(7_300);
                    c.params.gather_cycles = 2;
                    c.params.decide_cycles = 3;
                    c.params.diffusion = 0.3;
                }),
            ),
            (
                "noisy, short refractory",
                with(&|c| {
                    c.params.wave.cycle = Duration::from_secs(30);
                    c.params.wave.refractory = Duration::from_secs(2);
                    c.noise = 4.0;
                }),
            ),
        ]
    }

    /// Every period of the lean engine equals the agents' (`Sim`'s) bit for bit: where the
    /// swarm went, the consensus, the decided count and the observer's diversity, over
    /// placements (random disks of several sizes, a lattice), fields, the settings above, and
    /// with the observer's diversity pooled or not. A failing case prints its seed.
    #[test]
    fn the_lean_engine_runs_the_agents_runs_bit_for_bit() {
        let fields = ["sharp", "gradient", "cloud"].map(|n| {
            crate::scenario::Scenario::builtin(n)
                .expect("a built-in scenario")
                .field
        });
        for (name, cfg) in settings() {
            for seed in 0..12u64 {
                let mut rng = Pcg64Mcg::seed_from_u64(seed);
                let (n, shape) = match seed % 4 {
                    0 => (61, Shape::Lattice { spacing: 0.75 }),
                    1 => (61, Shape::Disk { diameter: 6.0 }),
                    2 => (12, Shape::Disk { diameter: 2.0 }),
                    _ => (120, Shape::Disk { diameter: 9.0 }),
                };
                let swarm = Swarm::place(n, shape, 1.0, &mut rng).expect("a placement");
                let field = &fields[(seed % 3) as usize];
                let start = Point2::new(-2.5 + 0.4 * seed as f64, 0.3);
                let pooled = seed % 2 == 0;
                let mut sim = Sim::new(&swarm, field, cfg, start, seed).unwrap();
                let mut lean = LeanSim::new(&swarm, field, cfg, start, seed)
                    .unwrap()
                    .expect("the lean engine covers the variance, a reading per activation");
                if !pooled {
                    sim.without_diversity();
                    lean.without_diversity();
                }
                for k in 0..4 {
                    let (a, b) = (sim.run_period().unwrap(), lean.run_period().unwrap());
                    assert_eq!(
                        format!("{a:?}"),
                        format!("{b:?}"),
                        "{name}, seed {seed}, period {k}, pooled {pooled}"
                    );
                }
            }
        }
    }

    #[test]
    fn runs_it_does_not_cover_are_left_to_the_agents() {
        let swarm = Swarm::from_offsets(vec![Vector2::zeros(), Vector2::new(0.5, 0.0)], 1.0);
        let field = crate::scenario::Scenario::builtin("sharp").unwrap().field;
        let cfg = settings()[0].1;
        let at = Point2::origin();
        for other in [
            RunConfig {
                sensor: Sensor::PerPeriod,
                ..cfg
            },
            RunConfig {
                diversity: Measure::entropy(0.5).unwrap(),
                ..cfg
            },
        ] {
            assert!(
                LeanSim::new(&swarm, &field, other, at, 1)
                    .unwrap()
                    .is_none()
            );
        }
        assert!(LeanSim::new(&swarm, &field, cfg, at, 1).unwrap().is_some());
    }
}
