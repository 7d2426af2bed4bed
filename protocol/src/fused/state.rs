//! What a robot knows whatever its decision rule: its wave node, reading, preference, shown
//! decision, per-direction diversities and rays, period counters and queues, and the tally
//! that turns held votes into a direction. A [`Rule`](super::Rule) reads and changes it
//! through the hooks [`FusedNode`](super::FusedNode) calls.

use heapless::Deque;
use rand_core::RngCore;

use super::{EVENT_QUEUE, Event, NodeStats, OUTBOX, Votes};
use crate::direction::{MAX_SECTORS, Sector};
use crate::message::{Hop, Level, Message, Ray, Tag};
use crate::params::Params;
use crate::time::{Duration, Instant};
use crate::wave::{WaveNode, WaveState};
use crate::weights::DirectionWeights;

/// The ray held for one direction.
#[derive(Clone, Copy, Debug)]
pub(super) struct Held {
    pub(super) ray: Ray,
    /// When it was heard.
    pub(super) at: Instant,
    /// The tag of the neighbour it came from (the message's last hop).
    pub(super) sender: Tag,
}

/// The state every decision rule shares (module docs). Its fields are the `fused` module's
/// own: a [`Rule`](super::Rule) of this crate reads and changes them in its hooks.
#[derive(Clone, Debug)]
pub struct Core {
    pub(super) params: Params,
    pub(super) tag: Tag,
    pub(super) wave: WaveNode,
    pub(super) reading: Level,
    pub(super) pref: Option<Sector>,
    pub(super) decision: Option<Sector>,
    pub(super) weights: DirectionWeights<Sector, MAX_SECTORS>,
    /// The latest ray heard from each sector, when, and from whom.
    pub(super) rays: [Option<Held>; MAX_SECTORS],
    /// The sector whose ray the next initiation carries (round robin).
    pub(super) next_initiation_ray: u8,
    pub(super) period_cycles: u16,
    /// Waves initiated in the period under way.
    pub(super) period_initiations: u16,
    /// While `decide_pending`: waves initiated in the period that follows.
    pub(super) next_period_initiations: u16,
    /// The period's last cycle ended while an initiation was owed: the period's end (the fixed
    /// rule's decision, the adaptive rule's cap) waits for it, at most until the next cycle's
    /// end.
    pub(super) decide_pending: bool,
    /// Negotiation periods completed, as [`NodeStats::periods`]: a counter of its own here
    /// keeps the robot image 280 B smaller than reading the stats' (measured, 2026-11-24).
    pub(super) periods: u32,
    /// The accepted message waiting for its relay, and the sector it came from.
    pub(super) pending: Option<(Message, Sector)>,
    pub(super) outbox: Deque<Message, OUTBOX>,
    pub(super) events: Deque<Event, EVENT_QUEUE>,
    pub(super) stats: NodeStats,
}

impl Core {
    /// A robot's shared state at `now`; `params` are valid.
    pub(super) fn new(params: Params, tag: Tag, now: Instant, rng: &mut impl RngCore) -> Self {
        Core {
            params,
            tag,
            wave: WaveNode::new(params.wave, now, rng),
            reading: Level::default(),
            pref: None,
            decision: None,
            weights: DirectionWeights::default(),
            rays: [None; MAX_SECTORS],
            next_initiation_ray: 0,
            period_cycles: 0,
            period_initiations: 0,
            next_period_initiations: 0,
            decide_pending: false,
            periods: 0,
            pending: None,
            outbox: Deque::new(),
            events: Deque::new(),
            stats: NodeStats::default(),
        }
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The current preferred direction.
    pub fn preference(&self) -> Option<Sector> {
        self.pref
    }

    /// What the LEDs show.
    pub fn decision(&self) -> Option<Sector> {
        self.decision
    }

    /// The mask of sectors `0..K`.
    pub(super) fn all_sectors(&self) -> u8 {
        ((1u16 << self.params.sectors.min(MAX_SECTORS as u8)) - 1) as u8
    }

    /// The longest cycle a robot can draw: within it every neighbour sends at least once.
    pub(super) fn longest_cycle(&self) -> Duration {
        self.params.longest_cycle()
    }

    /// The ray held for `sector`, if any.
    pub(super) fn ray_from(&self, sector: Sector) -> Option<&Ray> {
        self.rays
            .get(usize::from(sector.index()))
            .and_then(|r| r.as_ref())
            .map(|h| &h.ray)
    }

    /// The hop this robot adds: its reading, preference and tag.
    pub(super) fn own_hop(&self) -> Hop {
        Hop {
            reading: self.reading,
            pref: self.pref,
            tag: self.tag,
        }
    }

    pub(super) fn count_evicted(&mut self, dropped: usize) {
        let dropped = u32::try_from(dropped).unwrap_or(u32::MAX);
        self.stats.hops_evicted = self.stats.hops_evicted.wrapping_add(dropped);
    }

    pub(super) fn transmit(&mut self, m: Message) {
        if self.outbox.is_full() {
            self.outbox.pop_front();
            self.stats.transmits_lost = self.stats.transmits_lost.wrapping_add(1);
        }
        let _ = self.outbox.push_back(m);
        self.push_event(Event::State(WaveState::Refractory));
    }

    pub(super) fn push_event(&mut self, e: Event) {
        if self.events.is_full() {
            self.events.pop_front();
            self.stats.events_lost = self.stats.events_lost.wrapping_add(1);
        }
        let _ = self.events.push_back(e);
    }

    /// The sector whose ray an initiation carries: one with the fewest robots held (none
    /// held counts as zero), the next such after the last one chosen. An initiation is heard
    /// on every side, but its ray is only taken on one; relays carry the rays along the waves,
    /// so initiations matter for the robots at the swarm's edge, whose outward sectors hold
    /// nothing and are never relayed from. Sending the short side also keeps a replayer that
    /// moves an initiation to the other side of its sender from planting a ray that counts
    /// the receiver itself (`docs/protocol.md` §5.3).
    pub(super) fn initiation_ray(&mut self) -> Sector {
        let k = self.params.sectors.clamp(1, MAX_SECTORS as u8);
        let held = |i: u8| {
            self.rays
                .get(usize::from(i))
                .and_then(|r| r.as_ref())
                .map_or(0, |h| h.ray.robots)
        };
        let fewest = (0..k).map(held).min().unwrap_or(0);
        let start = self.next_initiation_ray % k;
        let i = (0..k)
            .map(|j| (start + j) % k)
            .find(|&i| held(i) == fewest)
            .unwrap_or(start);
        self.next_initiation_ray = (i + 1) % k;
        Sector::new(i).unwrap_or(Sector::RIGHT)
    }

    /// When a skipped initiation is made up: as [`extra_initiation_at`](Self::extra_initiation_at),
    /// but within the cycle under way where it leaves room (a relay delay and a refractory
    /// time), so that the initiation counts in the negotiation period it was due in.
    pub(super) fn deferred_initiation_at(&self, now: Instant, rng: &mut impl RngCore) -> Instant {
        let w = &self.params.wave;
        let earliest = now + w.relay_delay + w.refractory;
        let at = self.extra_initiation_at(now, rng);
        let last = self.wave.cycle_end() - w.tick.max(Duration::from_millis(1));
        if at > last && earliest <= last {
            last
        } else {
            at
        }
    }

    /// When an extra initiation asked for at `now` goes: after a relay delay and a refractory
    /// time, plus a random wait of up to a tenth of a cycle (in ticks), so that neighbours
    /// moved by the same wave do not initiate together. (`next_u32` modulo the span: its bias
    /// is about 1e-6 for the robots' 5.5 s span of milliseconds.)
    fn extra_initiation_at(&self, now: Instant, rng: &mut impl RngCore) -> Instant {
        let w = &self.params.wave;
        let tick = w.tick.as_millis().max(1);
        let spread = (w.cycle.as_millis() / 10 / tick).max(1);
        let jitter =
            Duration::from_millis((u64::from(rng.next_u32()) % (spread + 1)).saturating_mul(tick));
        now + w.relay_delay + w.refractory + jitter
    }

    /// The votes: the robot's own preference plus, for each sector, the votes of the ray held
    /// from it (every robot on that side, once); sectors `≥ K` are not counted.
    pub fn votes(&self) -> Votes {
        let k = usize::from(self.params.sectors);
        let mut votes = [0u16; MAX_SECTORS];
        for held in self.rays.iter().flatten() {
            for (v, &r) in votes.iter_mut().zip(&held.ray.votes).take(k) {
                *v = v.saturating_add(u16::from(r));
            }
        }
        if let Some(i) = self.pref.map(|p| usize::from(p.index())).filter(|&i| i < k) {
            votes[i] = votes[i].saturating_add(1);
        }
        votes
    }

    /// Forgets rays not refreshed within the last negotiation period (a robot that died, a
    /// neighbour that moved away).
    pub(super) fn expire_rays(&mut self, now: Instant) {
        let period = self
            .longest_cycle()
            .saturating_mul(u64::from(self.params.negotiation_cycles));
        let cutoff = now - period;
        for slot in &mut self.rays {
            if slot.is_some_and(|h| h.at < cutoff) {
                *slot = None;
            }
        }
    }

    /// The direction `votes` give: the sector with the highest score (the votes projected on
    /// its direction, `resultant_scores`); on a tie
    /// the own preference if it is among the top, else the shown decision if it is, else none.
    pub fn tally(&self, votes: &Votes) -> Option<Sector> {
        let k = usize::from(self.params.sectors);
        let scores = resultant_scores(votes, self.params.sectors);
        let scores = &scores[..k];
        let max = scores.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let is_top = |s: Option<Sector>| {
            s.and_then(|s| scores.get(usize::from(s.index())))
                .is_some_and(|&v| v == max)
        };
        let tops = scores.iter().filter(|&&v| v == max).count();
        if votes.iter().all(|&v| v == 0) {
            None
        } else if tops == 1 {
            scores
                .iter()
                .position(|&v| v == max)
                .and_then(|i| Sector::new(i as u8))
        } else if is_top(self.pref) {
            self.pref
        } else if is_top(self.decision) {
            self.decision
        } else {
            None
        }
    }

    /// Decides by the votes held (the fixed rule at a period's end, the adaptive rule's cap).
    pub(super) fn decide_by_votes(&mut self) -> Option<Sector> {
        let votes = self.votes();
        let decision = self.tally(&votes);
        self.show(decision, votes, self.periods);
        decision
    }

    /// The end of a negotiation period (both rules): counts it, and whether the robot
    /// initiated a wave per cycle in it.
    pub(super) fn count_period(&mut self) {
        self.periods = self.periods.wrapping_add(1);
        self.stats.periods = self.stats.periods.wrapping_add(1);
        if self.period_initiations < self.params.negotiation_cycles {
            self.stats.periods_short = self.stats.periods_short.wrapping_add(1);
        }
        self.period_cycles = 0;
        self.period_initiations = core::mem::take(&mut self.next_period_initiations);
    }

    /// Shows `decision` (emits [`Event::Decided`]).
    pub(super) fn show(&mut self, decision: Option<Sector>, votes: Votes, period: u32) {
        let changed = decision != self.decision;
        self.decision = decision;
        self.push_event(Event::Decided {
            period,
            decision,
            changed,
            votes,
        });
    }
}

/// `COSINES[k][d]` = cos(2π·d/k), rounded to 2⁻²⁰ so that exact zeros and halves stay exact:
/// the cosine between two sectors `d` apart of a robot with `k` sectors. A table rather than
/// `libm::cosf`, which computes in `f64` and would pull software double arithmetic into the
/// robot's image (the Cortex-M4F has a single-precision FPU only).
#[allow(clippy::approx_constant, clippy::excessive_precision)]
pub(super) const COSINES: [[f32; MAX_SECTORS]; MAX_SECTORS + 1] = [
    [0.0; MAX_SECTORS],
    [0.0; MAX_SECTORS],
    [1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, -0.5, -0.5, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        1.0,
        0.3090171813964844,
        -0.8090171813964844,
        -0.8090171813964844,
        0.3090171813964844,
        0.0,
        0.0,
        0.0,
    ],
    [1.0, 0.5, -0.5, -1.0, -0.5, 0.5, 0.0, 0.0],
    [
        1.0,
        0.6234893798828125,
        -0.2225208282470703,
        -0.9009685516357422,
        -0.9009685516357422,
        -0.2225208282470703,
        0.6234893798828125,
        0.0,
    ],
    [
        1.0,
        0.7071065902709961,
        0.0,
        -0.7071065902709961,
        -1.0,
        -0.7071065902709961,
        0.0,
        0.7071065902709961,
    ],
];

/// Each sector's score: the votes projected on its direction, `Σ_t votes[t] · cos(θ_s − θ_t)`.
/// With K = 2 that is the difference of the two counts (a plain majority); in the plane the
/// sector nearest the votes' resultant scores highest, so votes for neighbouring sectors add
/// up instead of splitting.
pub(super) fn resultant_scores(votes: &Votes, sectors: u8) -> [f32; MAX_SECTORS] {
    let k = usize::from(sectors.clamp(1, MAX_SECTORS as u8));
    let cos = &COSINES[k];
    let mut scores = [0f32; MAX_SECTORS];
    for (s, score) in scores.iter_mut().enumerate().take(k) {
        *score = votes
            .iter()
            .enumerate()
            .take(k)
            .map(|(t, &v)| f32::from(v) * cos[(s + k - t) % k])
            .sum();
    }
    scores
}
