//! The fused CIMAX variant the aMussels ran (paper section 4).
//!
//! Gathering and negotiation are one phase. Every hop of a message carries the relaying robot's
//! (reading, preferred direction), and every message its sender's [`Ray`] of one direction: the
//! summary of every robot that lies that way (see *Rays* below). A robot that is activated by a
//! message from sector `d`:
//!
//! 1. scores it: the variance of the ray held for `d` with its own reading (the diversity of
//!    everything that way), or without a ray the diversity of the message's readings plus its
//!    own (Alg. 1), added to `d`'s running average;
//! 2. re-evaluates its preference at once: the sector with the strictly largest average
//!    diversity, if any (no evidence, uniform readings or an exact tie keep the preference);
//! 3. after the relay delay appends `(reading, preference)` as they are then, replaces the ray
//!    by its own ray of `d` and relays (the oldest hops make room, see [`crate::message`]).
//!
//! At the end of every negotiation period (`negotiation_cycles` of its own cycles, 10 on the
//! robots: "every aMussel initiated at least 10 messages") it decides by majority, emits
//! [`Event::Decided`] for the top-cap LEDs, and starts the next period, so the swarm re-decides
//! when the environment changes. The preference itself carries over. That is
//! [`DecisionRule::Fixed`], the paper's; with [`DecisionRule::Adaptive`] a robot decides as
//! soon as its evidence is settled, the period being the cap (see *The adaptive rule* below).
//!
//! **The diversity memory across periods.** The per-sector average diversities are not thrown away but shrunk to a *one-message prior*: each keeps its
//! average with the weight of a single message. With noisy sensors a uniform side has a small
//! but positive diversity, and emptying the averages outright lets the first message after the
//! boundary, from whichever side it comes, set the preference on its own until the other side
//! is heard; neighbours then count that transient preference (seen in the emulator: a
//! robot at the lit end of `1000` flipped in its third period). With the prior, one message
//! cannot flip it, and after an environment change the new messages outweigh the prior within
//! a few messages, so the swarm still re-decides within the next period.
//!
//! # Its own messages
//! Every hop carries the relaying robot's [`Tag`] (its id modulo 16), and a robot writes its
//! own into every hop it adds. A received message holding a hop with the robot's **own tag**
//! passed through it already: an echo of its own relay, or a replay. It is dropped before
//! anything else (not scored, not relayed, no votes, no activation) and counted in
//! [`NodeStats::own_tag`]. In a genuine wave a robot hears its own message again only while it
//! is refractory (it ignores every message then), so the rule never drops a message the robot
//! would have used.
//!
//! # Rays: counting every robot once, however far
//! A robot keeps the latest ray taken from each sector ([`FusedNode::votes`], `take_ray`): how
//! many robots lie that way, the exact sum and sum of squares of their readings and their
//! votes. Relaying a wave from `d` it sends its ray of `d` extended by itself, which the robots
//! ahead of the wave hear from their own side `d`; initiations carry the ray of the side
//! holding the fewest robots (at a swarm's edge, the empty outward side). A ray grows one
//! robot per hop and so summarises a whole line, beyond any message's horizon and without ids:
//! each robot is counted once, in the one ray that reaches it. The decision is the sector
//! nearest the resultant of the robot's own preference and every held ray's votes (K = 2: a
//! plain majority). A robot follows one neighbour per direction (the one whose ray reaches
//! farthest) and refuses a robot it follows on another side, so a replayed frame does not
//! replace its neighbour's ray; rays not refreshed within a period are forgotten.
//! `docs/protocol.md` §5.3 says why rays and not the other designs measured.
//!
//! # The adaptive rule
//! After every reception, cycle end and listening window's end the robot tallies its votes into
//! a candidate and shows it once it is informed (every sector heard, or its first listening
//! window of a longest cycle over), every side is known to its end (a [`Ray::closed`] ray, or
//! an empty side: silent for a whole window), the robots without a vote could not overturn it,
//! and, for a change of what it shows, every side has confirmed it. Its rays carry its vote
//! only once it is informed, its preference clear and every side it does not prefer known to
//! its end; a side is scored by its latest ray; news its relays cannot carry back goes out in
//! extra initiations as soon as it is free; stale (replayed) rays are refused.
//! `docs/protocol.md` §5.4 gives each rule, why it is safe and what was measured.
//!
//! **Tie rule**: if several sectors share the most votes, the robot keeps its own preference if
//! it is one of them, else its previous decision if that is one of them, else it is undecided.
//! In the lab's `1100` pattern every robot sees two votes each way and so moves toward the
//! border, as the paper reports; an odd swarm or a plane swarm rarely ties.

use heapless::Deque;
use rand_core::RngCore;

use crate::direction::{MAX_SECTORS, Sector};
use crate::diversity::{Diversity, Variance};
use crate::message::{Hop, Level, Message, Ray, Tag};
use crate::params::{DecisionRule, ParamError, Params};
use crate::time::Instant;
use crate::wave::{WaveAction, WaveNode, WaveState, WaveStats};
use crate::weights::DirectionWeights;

/// Events are queued here until polled; the oldest is dropped (and counted) when full.
const EVENT_QUEUE: usize = 8;
/// Transmissions waiting to be polled. A caller that polls after every `handle_*` call never
/// finds more than one; a caller late by more than a cycle loses the oldest (counted).
const OUTBOX: usize = 2;

/// Cycles without a ray from the neighbour followed in a direction before a ray from another
/// neighbour is taken instead (`FusedNode::take_ray`).
const SENDER_SWITCH_CYCLES: u32 = 3;

/// Two diversities within this relative distance of each other count as equal (2⁻¹⁰): far
/// above the rounding of `f32` sums (about 2⁻²⁰ relative over a period's messages), so that an
/// exact tie stays a tie, and an order stays an order, whatever the sensor's gain
/// (`docs/protocol.md` §5.6).
pub const TIE_TOLERANCE: f32 = 1.0 / 1024.0;

/// How many times every other direction's diversity the preferred one's must be for the
/// adaptive rule to count the preference as a vote (`FusedNode::is_clear`). Four, not two: the
/// ratio of two sides' sensor noise alone exceeds 2 often enough (a robot amid a uniform
/// stretch of a long line) that noisy levels tipped ties (`docs/protocol.md` §5.4).
const CLEAR_RATIO: f32 = 4.0;

/// Adaptive rule: extra initiations carrying news (`FusedNode::spread_news`) a robot may ask
/// for per cycle, per sector.
const NEWS_PER_SECTOR: u8 = 4;

/// Rays taken per sector remembered by the adaptive rule (`FusedNode::take_ray`).
const RAY_HISTORY: usize = 4;

/// What of a ray the adaptive rule remembers: who sent it, how many robots it counts and
/// their votes, hashed (FNV-1a), and when it was taken. Digest 0 (never a ray's,
/// [`ray_digest`]) marks an empty place.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Seen {
    digest: u32,
    at: Instant,
}

/// The digest of the decision-relevant part of a ray from `sender`: robots and votes.
fn ray_digest(ray: &Ray, sender: Tag) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    let bytes = [sender.index(), ray.robots, u8::from(ray.closed)]
        .into_iter()
        .chain(ray.votes);
    for b in bytes {
        h = (h ^ u32::from(b)).wrapping_mul(0x0100_0193);
    }
    h.max(1)
}

/// The ray held for one direction.
#[derive(Clone, Copy, Debug)]
struct Held {
    ray: Ray,
    /// When it was heard.
    at: Instant,
    /// The tag of the neighbour it came from (the message's last hop).
    sender: Tag,
}

/// Votes per sector at a decision.
pub type Votes = [u16; MAX_SECTORS];

/// Something the robot program should know about (LEDs, logs, traces).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Event {
    /// The wave state changed.
    State(WaveState),
    /// The preferred direction changed.
    Preference(Option<Sector>),
    /// A decision to show on the LEDs: at the end of a negotiation period
    /// ([`DecisionRule::Fixed`]), or when the evidence settled ([`DecisionRule::Adaptive`]).
    Decided {
        /// The negotiation period it belongs to, counted from 1 (fixed rule: the period that
        /// just ended; adaptive rule: the one under way, or the one that ended at the cap).
        period: u32,
        /// The decision; `None` if undecided.
        decision: Option<Sector>,
        /// True if it differs from the previous decision.
        changed: bool,
        /// The votes counted, per sector.
        votes: Votes,
    },
}

/// What became of a received message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Reception {
    /// The robot was inactive: the message was scored and will be relayed.
    Accepted,
    /// The robot was active or refractory and ignored it (normal wave behaviour).
    Ignored,
    /// The sector is not one of this robot's K receivers; dropped and counted.
    UnknownSector,
    /// A hop carries this robot's own tag: the message passed through it already (an echo or
    /// a replay). Dropped before anything else and counted in [`NodeStats::own_tag`].
    OwnTag,
}

/// Counters kept by a [`FusedNode`] beyond its wave node's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NodeStats {
    /// Messages scored.
    pub accepted: u32,
    /// Messages from a sector outside `0..K`.
    pub unknown_sector: u32,
    /// Messages dropped because a hop carries this robot's own tag ([`Reception::OwnTag`]).
    /// In a genuine wave these are the neighbours' relays of the robot's own hop, heard while
    /// it is refractory; replays of messages it relayed add to them.
    pub own_tag: u32,
    /// Hops dropped because a relayed message was full.
    pub hops_evicted: u32,
    /// Rays taken into the robot's picture of a direction (§ *Rays* in the module docs).
    pub rays: u32,
    /// Rays not taken: for another sector than the one they were heard from, from a robot
    /// with another number of sectors, or shorter than a fresh one already held.
    pub rays_refused: u32,
    /// Transmissions dropped because `poll_transmit` was not called in time.
    pub transmits_lost: u32,
    /// Events dropped because `poll_event` was not called in time.
    pub events_lost: u32,
    /// Negotiation periods completed.
    pub periods: u32,
    /// Negotiation periods completed in which the robot initiated fewer waves than the period
    /// has cycles (the paper: "every aMussel initiated at least 10 messages").
    pub periods_short: u32,
}

/// One robot running fused CIMAX. Sans-IO: no clock, no radio, no globals.
///
/// Call order, as with quinn-proto or smoltcp:
/// 1. [`handle_reading`](Self::handle_reading) whenever the sensor gives a new value;
/// 2. [`handle_message`](Self::handle_message) for every message a receiver delivered (the
///    firmware deframes with [`crate::frame::Deframer`]), with its sector;
/// 3. [`handle_timeout`](Self::handle_timeout) when [`poll_timeout`](Self::poll_timeout) is
///    reached;
/// 4. after each of those, drain [`poll_transmit`](Self::poll_transmit) (frame and send it at
///    once) and [`poll_event`](Self::poll_event).
#[derive(Clone, Debug)]
pub struct FusedNode<D: Diversity = Variance> {
    params: Params,
    tag: Tag,
    diversity: D,
    wave: WaveNode,
    reading: Level,
    /// Adaptive rule: the reading in the last ray this robot sent.
    sent_reading: Level,
    pref: Option<Sector>,
    decision: Option<Sector>,
    weights: DirectionWeights<Sector, MAX_SECTORS>,
    /// The latest ray heard from each sector, when, and from whom.
    rays: [Option<Held>; MAX_SECTORS],
    /// The sector whose ray the next initiation carries (round robin).
    next_initiation_ray: u8,
    period_cycles: u16,
    /// Waves initiated in the period under way.
    period_initiations: u16,
    /// While `decide_pending`: waves initiated in the period that follows.
    next_period_initiations: u16,
    /// The period's last cycle ended while an initiation was owed: the period's end (the fixed
    /// rule's decision, the adaptive rule's cap) waits for it, at most until the next cycle's
    /// end.
    decide_pending: bool,
    /// Negotiation periods completed, as [`NodeStats::periods`]: a counter of its own here
    /// keeps the robot image 280 B smaller than reading the stats' (measured, 2026-11-24).
    periods: u32,
    /// Adaptive rule: a whole listening window (a longest cycle) has passed since the node
    /// started: every neighbour in range has initiated once.
    listened: bool,
    /// Sectors a ray was ever taken from (bit `i` for sector `i`).
    heard: u8,
    /// Adaptive rule: sectors any message was heard from in the listening window under way
    /// (one longest cycle, the first starting when the node starts).
    heard_window: u8,
    /// Adaptive rule: sectors nothing was heard from in the last whole window, nor since
    /// ([`is_empty_side`](Self::is_empty_side)).
    silent: u8,
    /// Adaptive rule: when the listening window under way ends (`Instant::MAX` for the fixed
    /// rule).
    window_end: Instant,
    /// Adaptive rule: the direction the held votes give now ([`FusedNode::tally`]).
    candidate: Option<Sector>,
    /// Adaptive rule: the sectors whose rays confirmed `candidate` after it was last set.
    confirmed: u8,
    /// Adaptive rule: since when the candidate has differed from the shown decision.
    differs_since: Option<Instant>,
    /// Adaptive rule: per sector, the last rays taken (digest and time), newest last.
    seen: [[Seen; RAY_HISTORY]; MAX_SECTORS],
    /// The vote the last ray sent carried, and the sectors whose ray, as last sent, is still
    /// current: it carried that vote and the held ray's robots and votes (adaptive rule: the
    /// others are news to send, `spread_news`).
    last_vote: Option<Sector>,
    fresh_rays: u8,
    /// Adaptive rule: the sector whose ray a pending extra initiation carries.
    trigger: Option<Sector>,
    /// Adaptive rule: extra initiations asked for in the cycle under way.
    triggered_in_cycle: u8,
    /// Adaptive rule: the sector `spread_news` looks at first (the one after its last).
    next_news: u8,
    /// The accepted message waiting for its relay, and the sector it came from.
    pending: Option<(Message, Sector)>,
    outbox: Deque<Message, OUTBOX>,
    events: Deque<Event, EVENT_QUEUE>,
    stats: NodeStats,
}

impl FusedNode<Variance> {
    /// A robot with tag `tag` (its id modulo 16, [`Tag::from_id`]) and the variance as
    /// diversity measure, starting its first cycle at `now`. Robots within
    /// [`MAX_HOPS`](crate::message::MAX_HOPS) hops of each other need distinct tags.
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate.
    pub fn new(
        params: Params,
        tag: Tag,
        now: Instant,
        rng: &mut impl RngCore,
    ) -> Result<Self, ParamError> {
        Self::with_diversity(params, tag, Variance, now, rng)
    }
}

impl<D: Diversity> FusedNode<D> {
    /// A robot with a custom diversity measure; otherwise as [`FusedNode::new`].
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate.
    pub fn with_diversity(
        params: Params,
        tag: Tag,
        diversity: D,
        now: Instant,
        rng: &mut impl RngCore,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(FusedNode {
            params,
            tag,
            diversity,
            wave: WaveNode::new(params.wave, now, rng),
            reading: Level::default(),
            sent_reading: Level::default(),
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
            listened: false,
            heard: 0,
            heard_window: 0,
            silent: 0,
            window_end: if params.decide == DecisionRule::Adaptive {
                now + params.longest_cycle()
            } else {
                Instant::MAX
            },
            candidate: None,
            confirmed: 0,
            differs_since: None,
            seen: [[Seen::default(); RAY_HISTORY]; MAX_SECTORS],
            last_vote: None,
            fresh_rays: 0,
            trigger: None,
            triggered_in_cycle: 0,
            next_news: 0,
            pending: None,
            outbox: Deque::new(),
            events: Deque::new(),
            stats: NodeStats::default(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// This robot's tag, written into every hop it adds.
    pub fn tag(&self) -> Tag {
        self.tag
    }

    /// The latest sensor reading.
    pub fn reading(&self) -> Level {
        self.reading
    }

    /// The current preferred direction.
    pub fn preference(&self) -> Option<Sector> {
        self.pref
    }

    /// The decision of the last completed negotiation period (what the LEDs show).
    pub fn decision(&self) -> Option<Sector> {
        self.decision
    }

    /// Negotiation periods completed.
    pub fn periods(&self) -> u32 {
        self.periods
    }

    /// The wave state.
    pub fn state(&self) -> WaveState {
        self.wave.state()
    }

    /// Average diversity heard from `sector` this period, if anything was heard from it.
    pub fn weight(&self, sector: Sector) -> Option<f32> {
        self.weights.weight(sector)
    }

    /// This node's counters.
    pub fn stats(&self) -> &NodeStats {
        &self.stats
    }

    /// The wave node's counters.
    pub fn wave_stats(&self) -> &WaveStats {
        self.wave.stats()
    }

    /// A new sensor reading; it goes into every hop this robot adds from now on.
    ///
    /// Under the adaptive rule a reading that moved, since the last ray this robot sent, by
    /// more than the spread of what it sees (the squared change above the preferred side's
    /// diversity, that side's ray with the own reading: a light switched, not sensor noise;
    /// ratios only, §5.6) makes every ray it sends news (docs/protocol.md §5.4, at
    /// its next reception or timeout).
    pub fn handle_reading(&mut self, reading: Level) {
        if self.params.decide == DecisionRule::Adaptive {
            // The adaptive rule's weights are the held rays' variances with the own reading;
            // the preferred side's is the largest.
            let d = f32::from(reading.0.abs_diff(self.sent_reading.0));
            if self
                .pref
                .and_then(|p| self.weights.weight(p))
                .is_some_and(|w| d * d > w)
            {
                self.fresh_rays = 0;
            }
        }
        self.reading = reading;
    }

    /// A message arrived at `now` on the receiver facing `from`.
    ///
    /// Whatever was due up to `now` is done first (as by
    /// [`handle_timeout`](Self::handle_timeout)), so a message that arrives just as the
    /// refractory time ends is heard, whichever of the two the caller learnt of first.
    // Kept out of the robot's main task: LTO inlined it there whole, 116 B more in the Nucleo
    // image, whose budget has 36 B left (docs/firmware.md, "Footprint").
    #[inline(never)]
    pub fn handle_message(
        &mut self,
        now: Instant,
        from: Sector,
        msg: &Message,
        rng: &mut impl RngCore,
    ) -> Reception {
        self.handle_timeout(now, rng);
        let rays = self.stats.rays;
        let r = self.receive(now, from, msg);
        if self.params.decide == DecisionRule::Adaptive {
            let confirming = (self.stats.rays != rays).then_some(from);
            self.settle(now, confirming);
            self.spread_news(now, rng);
        }
        r
    }

    /// [`handle_message`](Self::handle_message) once what was due is done.
    fn receive(&mut self, now: Instant, from: Sector, msg: &Message) -> Reception {
        if from.index() >= self.params.sectors {
            self.stats.unknown_sector = self.stats.unknown_sector.wrapping_add(1);
            return Reception::UnknownSector;
        }
        self.heard_window |= 1 << from.index();
        self.silent &= !(1 << from.index());
        if msg.has_tag(self.tag) {
            self.stats.own_tag = self.stats.own_tag.wrapping_add(1);
            return Reception::OwnTag;
        }
        let mut took = match (msg.ray(), msg.hops().last()) {
            (Some(ray), Some(sender)) => self.take_ray(now, from, ray, sender.tag),
            _ => false,
        };
        if !took && self.params.decide == DecisionRule::Adaptive && self.ray_from(from).is_none() {
            // Nothing known of that side: the robots the message passed stand for it.
            if let (Some(ray), Some(sender)) = (self.ray_of_hops(from, msg), msg.hops().last()) {
                took = self.take_ray(now, from, &ray, sender.tag);
            }
        }
        if msg.is_empty() || !self.wave.on_receive(now) {
            // The adaptive rule scores a ray also while the robot is busy: a neighbour whose
            // initiations fall while it relays would otherwise never be scored.
            if took && self.params.decide == DecisionRule::Adaptive {
                self.score(from, msg);
            }
            return Reception::Ignored;
        }
        self.stats.accepted = self.stats.accepted.wrapping_add(1);
        self.push_event(Event::State(WaveState::Active));
        self.score(from, msg);
        self.pending = Some((msg.clone(), from));
        Reception::Accepted
    }

    /// The ray of the robots `msg` passed, as seen from sector `from`: their readings and
    /// preferences as votes.
    fn ray_of_hops(&self, from: Sector, msg: &Message) -> Option<Ray> {
        let (first, rest) = msg.hops().split_first()?;
        let k = self.params.sectors;
        let vote = |p: Option<Sector>| p.filter(|s| s.index() < k);
        let ray = Ray::single(from, k, first.reading, vote(first.pref))?;
        Some(
            rest.iter()
                .fold(ray, |r, h| r.extended(h.reading, vote(h.pref))),
        )
    }

    /// Adds the diversity of direction `from` to its average and re-evaluates the preference:
    /// the diversity of the whole ray held for it with the own reading, if one is held (its
    /// moments are the variance's sufficient statistics); else of `msg`'s readings with the own
    /// (Alg. 1).
    fn score(&mut self, from: Sector, msg: &Message) {
        let v = match self.ray_from(from) {
            Some(ray) => ray.extended(self.reading, None).variance(),
            None => {
                let own = f32::from(self.reading);
                self.diversity
                    .measure(msg.readings().chain(core::iter::once(own)))
            }
        };
        if self.params.decide == DecisionRule::Adaptive && self.ray_from(from).is_some() {
            // The adaptive rule scores a direction by its latest ray: a summary of the whole
            // side that supersedes the older ones (a changed environment shows at once).
            self.weights.set(from, v);
        } else {
            self.weights.add(from, v);
        }
        if let Some(best) = self.weights.heaviest_within(TIE_TOLERANCE)
            && self.pref != Some(best)
        {
            self.pref = Some(best);
            self.push_event(Event::Preference(self.pref));
        }
    }

    /// Does whatever is due at `now`: relays, initiations, the end of the refractory time,
    /// cycle and period ends.
    pub fn handle_timeout(&mut self, now: Instant, rng: &mut impl RngCore) {
        // `Instant::MAX` is never due (the fixed rule has no windows).
        let quiet = now >= self.window_end && self.window_end != Instant::MAX;
        if quiet {
            // A listening window ended: the sectors silent all through it are empty. Those
            // that just became so change the ray sent that way (now closed): news, unless an
            // initiation due now carries it. The robot may now see to the end of every side.
            let silent = self.all_sectors() & !self.heard_window;
            self.fresh_rays &= !(silent & !self.silent);
            self.silent = silent;
            self.heard_window = 0;
            self.listened = true;
            let next = self.window_end + self.longest_cycle();
            self.window_end = next.max(now + crate::time::Duration::from_millis(1));
        }
        self.poll_wave(now, rng);
        if self.wave.owed() > 0 && !self.wave.extra_pending() {
            // An initiation that fell while the robot was busy is deferred, not lost (both
            // rules): the paper's robots initiate at least once per cycle.
            let at = self.deferred_initiation_at(now, rng);
            self.wave.initiate_extra(at);
        }
        if quiet {
            self.settle(now, None);
            self.spread_news(now, rng);
        }
    }

    /// Adaptive rule: nothing lies in `sector`: no ray is held from it, and nothing was heard
    /// from it for a whole listening window of a longest cycle (within which every neighbour
    /// initiates; the first window starts with the node), nor since.
    fn is_empty_side(&self, sector: u8) -> bool {
        self.silent & (1 << sector) != 0
            && self
                .rays
                .get(usize::from(sector))
                .is_some_and(Option::is_none)
    }

    /// Adaptive rule: the sectors below K in which the robot knows every robot (bit `i` for
    /// sector `i`): the ray it holds from there is [`closed`](Ray::closed), or the side is
    /// empty ([`is_empty_side`](Self::is_empty_side)).
    fn known_to_the_end(&self) -> u8 {
        let mut known = 0u8;
        for s in 0..self.params.sectors.min(MAX_SECTORS as u8) {
            let closed = match self.rays.get(usize::from(s)) {
                Some(Some(h)) => h.ray.closed,
                _ => self.is_empty_side(s),
            };
            known |= u8::from(closed) << s;
        }
        known
    }

    /// The mask of sectors `0..K`.
    fn all_sectors(&self) -> u8 {
        ((1u16 << self.params.sectors.min(MAX_SECTORS as u8)) - 1) as u8
    }

    /// When a skipped initiation is made up: as [`extra_initiation_at`](Self::extra_initiation_at),
    /// but within the cycle under way where it leaves room (a relay delay and a refractory
    /// time), so that the initiation counts in the negotiation period it was due in.
    fn deferred_initiation_at(&self, now: Instant, rng: &mut impl RngCore) -> Instant {
        let w = &self.params.wave;
        let earliest = now + w.relay_delay + w.refractory;
        let at = self.extra_initiation_at(now, rng);
        let last = self.wave.cycle_end() - w.tick.max(crate::time::Duration::from_millis(1));
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
        let jitter = crate::time::Duration::from_millis(
            (u64::from(rng.next_u32()) % (spread + 1)).saturating_mul(tick),
        );
        now + w.relay_delay + w.refractory + jitter
    }

    /// When an initiation carrying news goes (adaptive rule): as soon as the robot is free
    /// (inactive: now; else once its relay and refractory time are over), plus a random wait of
    /// 1 tick to a quarter of `relay_delay` (in ticks), so that neighbours freed by the same
    /// wave do not send together.
    fn news_initiation_at(&self, now: Instant, rng: &mut impl RngCore) -> Instant {
        let w = &self.params.wave;
        let tick = w.tick.as_millis().max(1);
        let spread = u32::try_from(w.relay_delay.as_millis() / 4 / tick)
            .unwrap_or(u32::MAX)
            .max(1);
        let jitter = crate::time::Duration::from_millis(
            u64::from(1 + rng.next_u32() % spread).saturating_mul(tick),
        );
        self.wave.free_at(now) + jitter
    }

    fn poll_wave(&mut self, now: Instant, rng: &mut impl RngCore) {
        while let Some(action) = self.wave.poll(now, rng) {
            match action {
                WaveAction::Initiate => {
                    if self.decide_pending && !self.wave.last_was_extra() {
                        // The next period's first cycle initiated before the owed one.
                        self.next_period_initiations =
                            self.next_period_initiations.saturating_add(1);
                    } else {
                        self.period_initiations = self.period_initiations.saturating_add(1);
                    }
                    if self.wave.owed() == 0 {
                        // Nothing to make up: this initiation carries any news.
                        self.wave.cancel_extra();
                    }
                    let sector = match self.trigger.take() {
                        Some(s) => s,
                        None => self.initiation_ray(),
                    };
                    let m = Message::initiate(self.own_hop());
                    self.send_with_ray(m, sector);
                    if self.params.decide == DecisionRule::Adaptive {
                        self.spread_news(now, rng);
                    }
                    if self.decide_pending && self.wave.owed() == 0 {
                        self.decide_pending = false;
                        self.end_of_period(now);
                    }
                }
                WaveAction::Relay => {
                    if let Some((mut m, from)) = self.pending.take() {
                        // The received ray goes (this robot sends its own), then room for the
                        // own hop within the capacity (`validate`: at least 1).
                        m.set_ray(None);
                        let cap = usize::from(self.params.max_hops).max(1);
                        let dropped = m.keep_newest(cap - 1);
                        // Cannot evict: no ray, and at most cap - 1 < MAX_HOPS hops remain.
                        m.push_evicting(self.own_hop());
                        self.count_evicted(dropped);
                        self.send_with_ray(m, from);
                    }
                }
                WaveAction::Rested => self.push_event(Event::State(WaveState::Inactive)),
                WaveAction::CycleEnded(_) => {
                    let adaptive = self.params.decide == DecisionRule::Adaptive;
                    if adaptive {
                        // Evidence of the last cycle only (and a one-message prior), so that a
                        // changed environment shows within a cycle or two.
                        self.weights.shrink_to_prior();
                    }
                    if self.decide_pending {
                        // The owed initiation did not go out within a cycle: end the period.
                        self.decide_pending = false;
                        self.end_of_period(now);
                    }
                    self.period_cycles = self.period_cycles.saturating_add(1);
                    if self.period_cycles >= self.params.negotiation_cycles {
                        if self.wave.owed() > 0 {
                            // A period ends once its owed initiation went out: every robot
                            // initiates once per cycle of the period (paper section 4).
                            self.decide_pending = true;
                            self.period_cycles = 0;
                        } else {
                            self.end_of_period(now);
                        }
                    }
                    if adaptive {
                        self.settle(now, None);
                        self.triggered_in_cycle = 0;
                        self.spread_news(now, rng);
                    }
                }
            }
        }
    }

    /// The end of a negotiation period: the fixed rule decides, the adaptive rule applies its
    /// cap ([`end_period`](Self::end_period)).
    fn end_of_period(&mut self, now: Instant) {
        match self.params.decide {
            DecisionRule::Fixed => self.decide(now),
            DecisionRule::Adaptive => self.end_period(now),
        }
    }

    /// When [`handle_timeout`](Self::handle_timeout) must be called next.
    pub fn poll_timeout(&self) -> Instant {
        self.wave.poll_timeout().min(self.window_end)
    }

    /// The next message to broadcast, if any; frame it with [`crate::frame::encode`].
    pub fn poll_transmit(&mut self) -> Option<Message> {
        self.outbox.pop_front()
    }

    /// The next event, if any.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.events.pop_front()
    }

    fn own_hop(&self) -> Hop {
        Hop {
            reading: self.reading,
            pref: self.pref,
            tag: self.tag,
        }
    }

    /// Attaches the ray of `sector` extended by this robot (what lies that way, and itself),
    /// trims the message to the payload budget of `max_hops` and transmits it.
    fn send_with_ray(&mut self, mut m: Message, sector: Sector) {
        let vote = self.vote();
        if vote != self.last_vote {
            self.last_vote = vote;
            self.fresh_rays = 0;
        }
        self.fresh_rays |= 1 << sector.index();
        self.sent_reading = self.reading;
        let closed =
            self.params.decide == DecisionRule::Adaptive && self.is_empty_side(sector.index());
        let ray = match self.ray_from(sector) {
            Some(r) => Some(r.extended(self.reading, vote)),
            None => Ray::single(sector, self.params.sectors, self.reading, vote).map(|mut r| {
                r.closed = closed;
                r
            }),
        };
        let mut dropped = m.set_ray(ray);
        // The payload a frame of `max_hops` plain hops would have (keyed frames: 11 hops).
        dropped += m.fit(1 + 2 * usize::from(self.params.max_hops.max(1)));
        self.count_evicted(dropped);
        self.transmit(m);
    }

    fn count_evicted(&mut self, dropped: usize) {
        let dropped = u32::try_from(dropped).unwrap_or(u32::MAX);
        self.stats.hops_evicted = self.stats.hops_evicted.wrapping_add(dropped);
    }

    /// The ray held for `sector`, if any.
    fn ray_from(&self, sector: Sector) -> Option<&Ray> {
        self.rays
            .get(usize::from(sector.index()))
            .and_then(|r| r.as_ref())
            .map(|h| &h.ray)
    }

    /// The sector whose ray an initiation carries: one with the fewest robots held (none
    /// held counts as zero), the next such after the last one chosen. An initiation is heard
    /// on every side, but its ray is only taken on one; relays carry the rays along the waves,
    /// so initiations matter for the robots at the swarm's edge, whose outward sectors hold
    /// nothing and are never relayed from. Sending the short side also keeps a replayer that
    /// moves an initiation to the other side of its sender from planting a ray that counts
    /// the receiver itself (`docs/protocol.md` §5.3).
    fn initiation_ray(&mut self) -> Sector {
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

    /// The longest cycle a robot can draw: within it every neighbour sends at least once.
    fn longest_cycle(&self) -> crate::time::Duration {
        self.params.longest_cycle()
    }

    /// Takes `ray`, heard at `now` from `from` in a message last relayed by `sender`, as this
    /// robot's picture of that direction, if
    /// - it describes that direction (a relay from the far side of the sender, or an
    ///   initiation meant for this side) and comes from a robot with as many sectors;
    /// - the sender is not the neighbour followed in another direction (a robot heard on one
    ///   side cannot be on another: its frame was moved by a replayer);
    /// - it comes from the neighbour followed in this direction, or reaches farther (more
    ///   robots) than what that neighbour last sent, or that was more than
    ///   [`SENDER_SWITCH_CYCLES`] cycles ago.
    ///
    /// In a line the neighbour's ray always reaches farthest, so a robot follows its
    /// neighbour and ignores what a replayer brings of robots farther along.
    ///
    /// The adaptive rule is stricter (`docs/protocol.md` §5.4): a robot followed on another
    /// side is refused however old that ray is; another robot's ray only if it reaches
    /// farther; the followed robot's shorter ray within the switch time; and a ray that goes
    /// back in time (the same sender, robots and votes as one of the last [`RAY_HISTORY`]
    /// distinct rays taken from that sector within a longest cycle, other than the held one).
    ///
    /// Returns `true` if it was taken.
    fn take_ray(&mut self, now: Instant, from: Sector, ray: &Ray, sender: Tag) -> bool {
        let longest = self.longest_cycle();
        let switch_after = longest.saturating_mul(u64::from(SENDER_SWITCH_CYCLES));
        let i = usize::from(from.index());
        let fits = ray.sector == from && ray.sectors == self.params.sectors;
        let adaptive = self.params.decide == DecisionRule::Adaptive;
        let elsewhere = self.rays.iter().enumerate().any(|(j, h)| {
            j != i
                && h.is_some_and(|h| h.sender == sender && (now - h.at <= switch_after || adaptive))
        });
        let Some(slot) = self.rays.get_mut(i) else {
            return false;
        };
        let follows = match slot {
            Some(held) => {
                let older =
                    adaptive && now - held.at <= switch_after && ray.robots < held.ray.robots;
                (held.sender == sender && !older)
                    || ray.robots > held.ray.robots
                    || (now - held.at > switch_after && !adaptive)
            }
            None => true,
        };
        let digest = ray_digest(ray, sender);
        let back_in_time = adaptive
            && slot.is_some_and(|h| ray_digest(&h.ray, h.sender) != digest)
            && self.seen.get(i).is_some_and(|seen| {
                seen.iter()
                    .any(|s| s.digest == digest && now - s.at <= longest)
            });
        if fits && !elsewhere && follows && !back_in_time {
            if let Some(seen) = self.seen.get_mut(i) {
                // Only changes take a place: a neighbour's ray is mostly the same.
                if seen[RAY_HISTORY - 1].digest != digest {
                    crate::message::shift_out(seen, 1);
                }
                seen[RAY_HISTORY - 1] = Seen { digest, at: now };
            }
            if slot.is_none_or(|h| {
                h.ray.robots != ray.robots || h.ray.votes != ray.votes || h.ray.closed != ray.closed
            }) {
                self.fresh_rays &= !(1 << from.index());
            }
            *slot = Some(Held {
                ray: *ray,
                at: now,
                sender,
            });
            self.heard |= 1 << from.index();
            self.stats.rays = self.stats.rays.wrapping_add(1);
            true
        } else {
            self.stats.rays_refused = self.stats.rays_refused.wrapping_add(1);
            false
        }
    }

    fn transmit(&mut self, m: Message) {
        if self.outbox.is_full() {
            self.outbox.pop_front();
            self.stats.transmits_lost = self.stats.transmits_lost.wrapping_add(1);
        }
        let _ = self.outbox.push_back(m);
        self.push_event(Event::State(WaveState::Refractory));
    }

    fn push_event(&mut self, e: Event) {
        if self.events.is_full() {
            self.events.pop_front();
            self.stats.events_lost = self.stats.events_lost.wrapping_add(1);
        }
        let _ = self.events.push_back(e);
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
    fn expire_rays(&mut self, now: Instant) {
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

    /// The direction `votes` give: the sector with the highest [`resultant_scores`]; on a tie
    /// the own preference if it is among the top, else the shown decision if it is, else none.
    fn tally(&self, votes: &Votes) -> Option<Sector> {
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

    /// The fixed rule at the end of a negotiation period: decide by the votes held.
    fn decide(&mut self, now: Instant) {
        self.expire_rays(now);
        let votes = self.votes();
        let decision = self.tally(&votes);
        self.count_period();
        self.show(decision, votes, self.periods);
        self.weights.shrink_to_prior();
    }

    /// The end of a negotiation period (both rules): counts it, and whether the robot
    /// initiated a wave per cycle in it.
    fn count_period(&mut self) {
        self.periods = self.periods.wrapping_add(1);
        self.stats.periods = self.stats.periods.wrapping_add(1);
        if self.period_initiations < self.params.negotiation_cycles {
            self.stats.periods_short = self.stats.periods_short.wrapping_add(1);
        }
        self.period_cycles = 0;
        self.period_initiations = core::mem::take(&mut self.next_period_initiations);
    }

    /// Shows `decision` (emits [`Event::Decided`]).
    fn show(&mut self, decision: Option<Sector>, votes: Votes, period: u32) {
        let changed = decision != self.decision;
        self.decision = decision;
        self.push_event(Event::Decided {
            period,
            decision,
            changed,
            votes,
        });
    }

    /// What this robot votes in the rays it sends: its preference; under the adaptive rule only
    /// once it [`is_informed`](Self::is_informed), the preference is
    /// [`is_clear`](Self::is_clear) and every side it does not prefer is
    /// [known to its end](Self::known_to_the_end) (a preference formed from one side of a line,
    /// between near-equal diversities, or before a border could be ruled out on the other
    /// sides, is no vote yet).
    fn vote(&self) -> Option<Sector> {
        match self.params.decide {
            DecisionRule::Fixed => self.pref,
            DecisionRule::Adaptive => self.pref.filter(|p| {
                let others = self.all_sectors() & !(1 << p.index());
                self.is_informed() && self.is_clear() && self.known_to_the_end() & others == others
            }),
        }
    }

    /// True if the preferred direction's average diversity is positive and more than
    /// [`CLEAR_RATIO`] times every other's (by more than [`TIE_TOLERANCE`]): a preference
    /// between near-equal diversities (a robot amid a uniform stretch of a long line, whose
    /// rays do not reach a border yet) is no vote. Only ratios: the test gives the same answer
    /// whatever the sensor's unit, gain or offset.
    fn is_clear(&self) -> bool {
        let Some(p) = self.pref else { return false };
        let Some(best) = self.weights.weight(p) else {
            return false;
        };
        best > 0.0
            && self.weights.iter().all(|(d, w, _)| {
                d == p
                    || (best > CLEAR_RATIO * w
                        && !crate::weights::within(best, CLEAR_RATIO * w, TIE_TOLERANCE))
            })
    }

    /// True once the robot has taken a ray from each of its K sectors, or its first listening
    /// window (a whole longest cycle since it started) is over: by then every neighbour in
    /// range initiated once; a robot at the swarm's edge never hears its outward sides.
    fn is_informed(&self) -> bool {
        self.heard == self.all_sectors() || self.listened
    }

    /// Adaptive rule: if the ray this robot would send for some side is news (its own vote, or
    /// the robots or votes of the ray it holds, changed since it last sent that ray) and the
    /// neighbours that ray serves exist (a ray is held from the opposite sector), asks for one
    /// extra initiation carrying it ([`news_initiation_at`](Self::news_initiation_at)), at
    /// most [`NEWS_PER_SECTOR`] · K per cycle and one at a time. A relay carries news only
    /// ahead of its wave; the robots behind it would otherwise wait for this robot's next
    /// initiation. A pending extra initiation is asked for again while the robot is busy (a wave
    /// that arrived since would make it skip the first), for when it is free.
    fn spread_news(&mut self, now: Instant, rng: &mut impl RngCore) {
        let k = self.params.sectors.clamp(1, MAX_SECTORS as u8);
        // A pending extra initiation stays, unless the robot is busy: a wave that arrived since
        // it was asked for would make it skip it, so it is asked for again, for when it is free.
        if self.triggered_in_cycle >= k.saturating_mul(NEWS_PER_SECTOR)
            || (self.wave.extra_pending() && self.wave.state() == WaveState::Inactive)
        {
            return;
        }
        let vote = self.vote();
        let current = if vote == self.last_vote {
            self.fresh_rays
        } else {
            0
        };
        // Round robin from the sector after the last one sent as news: a side whose ray keeps
        // changing must not starve the others.
        let start = self.next_news % k;
        let needed = (0..k).map(|j| (start + j) % k).find(|&s| {
            let opposite = usize::from((s + k / 2) % k);
            current & (1 << s) == 0 && self.rays.get(opposite).is_some_and(|h| h.is_some())
        });
        let Some(s) = needed.and_then(Sector::new) else {
            return;
        };
        let at = self.news_initiation_at(now, rng);
        if self.wave.initiate_extra(at) {
            self.trigger = Some(s);
            self.next_news = (s.index() + 1) % k;
            self.triggered_in_cycle += 1;
        }
    }

    /// The adaptive rule's cap at the end of a negotiation period: rays not refreshed within
    /// it are forgotten, and a robot that showed nothing during the period decides by the
    /// fixed rule.
    fn end_period(&mut self, now: Instant) {
        self.expire_rays(now);
        self.count_period();
        let period = self
            .longest_cycle()
            .saturating_mul(u64::from(self.params.negotiation_cycles));
        let stuck = self.differs_since.is_some_and(|t| now - t >= period);
        let cap = self.decision.is_none() || stuck;
        if cap {
            let votes = self.votes();
            let decision = self.tally(&votes);
            self.show(decision, votes, self.periods);
            self.candidate = decision;
            self.differs_since = None;
        }
    }

    /// The adaptive rule, after a reception (`confirming`: the sector whose ray was just
    /// taken) or a cycle's end. The held votes give a candidate direction; each taken ray that
    /// gives the same candidate again confirms it for its sector. The robot shows the candidate
    /// once (`docs/protocol.md` §5.4)
    /// 1. it is informed ([`is_informed`](Self::is_informed)) and has a preference;
    /// 2. every side is [known to its end](Self::known_to_the_end) and it holds a ray;
    /// 3. the robots it holds without a vote could not overturn it, even all for one sector;
    /// 4. for a change of what it shows: every sector it holds a ray from confirmed the
    ///    candidate after it was last set.
    fn settle(&mut self, now: Instant, confirming: Option<Sector>) {
        let votes = self.votes();
        let candidate = self.tally(&votes);
        if candidate == self.decision {
            self.differs_since = None;
        } else if self.differs_since.is_none() {
            self.differs_since = Some(now);
        }
        if candidate != self.candidate {
            self.candidate = candidate;
            self.confirmed = 0;
        } else if let Some(s) = confirming {
            self.confirmed |= 1 << s.index();
        }
        if candidate.is_none()
            || candidate == self.decision
            || self.pref.is_none()
            || !self.is_informed()
            || self.known_to_the_end() != self.all_sectors()
        {
            return;
        }
        let mut held = 0u8;
        let mut undecided = 0u16;
        for (i, h) in self.rays.iter().enumerate() {
            if let Some(h) = h {
                held |= 1 << i;
                let voted: u16 = h.ray.votes.iter().map(|&v| u16::from(v)).sum();
                undecided = undecided.saturating_add(u16::from(h.ray.robots).saturating_sub(voted));
            }
        }
        // A first decision needs no confirmation; a change needs every side's.
        if held == 0 || (self.decision.is_some() && held & !self.confirmed != 0) {
            return;
        }
        let k = usize::from(self.params.sectors);
        let overturned = undecided > 0
            && (0..k).any(|s| {
                let mut v = votes;
                v[s] = v[s].saturating_add(undecided);
                self.tally(&v) != candidate
            });
        if overturned {
            return;
        }
        self.show(candidate, votes, self.periods.wrapping_add(1));
    }
}

/// `COSINES[k][d]` = cos(2π·d/k), rounded to 2⁻²⁰ so that exact zeros and halves stay exact:
/// the cosine between two sectors `d` apart of a robot with `k` sectors. A table rather than
/// `libm::cosf`, which computes in `f64` and would pull software double arithmetic into the
/// robot's image (the Cortex-M4F has a single-precision FPU only).
#[allow(clippy::approx_constant, clippy::excessive_precision)]
const COSINES: [[f32; MAX_SECTORS]; MAX_SECTORS + 1] = [
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
fn resultant_scores(votes: &Votes, sectors: u8) -> [f32; MAX_SECTORS] {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::message::MAX_HOPS;
    use crate::time::Duration;
    use rand_pcg::Pcg32;

    /// The hop robot `t` adds with reading `r` and preference `p`.
    fn hop(t: u8, r: u8, p: Option<Sector>) -> Hop {
        Hop {
            reading: Level(r),
            pref: p,
            tag: Tag::new(t).unwrap(),
        }
    }

    const L: Option<Sector> = Some(Sector::LEFT);
    const R: Option<Sector> = Some(Sector::RIGHT);

    /// Robot `tag` with reading `reading`, whose first initiation is 600 s away, so that tests
    /// feeding it messages by hand are not disturbed by its own waves.
    fn node(tag: u8, reading: u8) -> (FusedNode, Pcg32) {
        let mut rng = Pcg32::new(11, 13);
        let mut p = Params::robots();
        p.wave.cycle = Duration::from_secs(600);
        p.wave.cycle_spread = Duration::ZERO;
        let tag = Tag::new(tag).unwrap();
        let mut n = FusedNode::new(p, tag, Instant::ZERO, &mut rng).unwrap();
        n.handle_reading(Level(reading));
        (n, rng)
    }

    /// Feeds `msg` at a quiet moment and lets the relay go out; returns what was relayed.
    fn hear(
        n: &mut FusedNode,
        rng: &mut Pcg32,
        t: &mut Instant,
        from: Sector,
        msg: &[Hop],
    ) -> Message {
        *t += Duration::from_secs(12);
        // What went out meanwhile (the adaptive rule's news) is not the relay.
        n.handle_timeout(*t, rng);
        while n.poll_transmit().is_some() {}
        let m = Message::from_hops(msg).unwrap();
        assert_eq!(n.handle_message(*t, from, &m, rng), Reception::Accepted);
        n.handle_timeout(*t + Duration::from_secs(1), rng);
        n.poll_transmit().expect("relayed")
    }

    #[test]
    fn prefers_the_more_diverse_side_and_relays_with_its_own_hop() {
        let (mut n, mut rng) = node(5, 0);
        let mut t = Instant::from_secs(1);
        // From the right, uniform darkness; from the left, a lit robot.
        let out = hear(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(7, 0, None), hop(6, 0, None)],
        );
        assert_eq!(
            out.hops(),
            &[hop(7, 0, None), hop(6, 0, None), hop(5, 0, None)]
        );
        assert_eq!(n.preference(), None, "zero diversity gives no preference");
        let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &[hop(4, 1, R)]);
        assert_eq!(n.preference(), L);
        assert_eq!(
            out.hops(),
            &[hop(4, 1, R), hop(5, 0, L)],
            "relay carries the new preference and the own tag"
        );
        assert_eq!(n.weight(Sector::LEFT), Some(0.25));
        assert_eq!(n.weight(Sector::RIGHT), Some(0.0));
        assert_eq!(n.tag(), Tag::new(5).unwrap());
    }

    #[test]
    fn initiations_carry_the_own_tag() {
        let (mut n, mut rng) = node(9, 3);
        let t = n.poll_timeout();
        n.handle_timeout(t, &mut rng);
        let m = n.poll_transmit().expect("initiated");
        assert_eq!(m.hops(), &[hop(9, 3, None)]);
    }

    #[test]
    fn ignores_while_active_or_refractory_and_unknown_sectors() {
        let (mut n, mut rng) = node(5, 0);
        let m = Message::initiate(hop(4, 1, None));
        let t = Instant::from_secs(1);
        let r = &mut rng;
        assert_eq!(
            n.handle_message(t, Sector::LEFT, &m, r),
            Reception::Accepted
        );
        assert_eq!(
            n.handle_message(t, Sector::RIGHT, &m, r),
            Reception::Ignored
        );
        let t1 = t + Duration::from_secs(1);
        assert_eq!(
            n.handle_message(t1, Sector::RIGHT, &m, r),
            Reception::Ignored
        );
        assert!(n.poll_transmit().is_some(), "relayed on time");
        let t5 = t + Duration::from_secs(5);
        assert_eq!(
            n.handle_message(t5, Sector::LEFT, &m, r),
            Reception::Accepted
        );
        let s7 = Sector::new(7).unwrap();
        let t9 = t + Duration::from_secs(9);
        assert_eq!(n.handle_message(t9, s7, &m, r), Reception::UnknownSector);
        assert_eq!(n.stats().unknown_sector, 1);
        assert_eq!(n.wave_stats().ignored, 2);
    }

    #[test]
    fn a_message_holding_the_own_tag_is_dropped_and_counted() {
        let (mut n, mut rng) = node(1, 1);
        let mut t = Instant::from_secs(1);
        hear(&mut n, &mut rng, &mut t, Sector::LEFT, &[hop(0, 1, R)]);
        while n.poll_event().is_some() {}
        let (votes, prefs, weights) = (n.votes(), n.preference(), n.weight(Sector::RIGHT));
        let (accepted, ignored) = (n.stats().accepted, n.wave_stats().ignored);
        // Its own relay of a wave from the left, come back from the right (an echo, or a replay
        // of what robot 2 relayed), while it could accept a message: dropped, whatever its
        // position, and nothing else happens.
        for msg in [
            &[hop(0, 1, R), hop(1, 1, R), hop(2, 0, L)][..],
            &[hop(1, 1, None)],
            &[hop(1, 1, R), hop(2, 0, L), hop(3, 0, L)],
        ] {
            t += Duration::from_secs(6);
            n.handle_timeout(t, &mut rng);
            while n.poll_event().is_some() {}
            let m = Message::from_hops(msg).unwrap();
            let got = n.handle_message(t, Sector::RIGHT, &m, &mut rng);
            assert_eq!(got, Reception::OwnTag, "{msg:?}");
            assert_eq!(n.state(), WaveState::Inactive, "no activation");
            n.handle_timeout(t + Duration::from_secs(1), &mut rng);
            assert_eq!(n.poll_transmit(), None, "not relayed");
            assert_eq!(n.poll_event(), None, "no event");
        }
        assert_eq!(n.stats().own_tag, 3);
        assert_eq!(n.votes(), votes, "not counted");
        assert_eq!(n.weight(Sector::RIGHT), weights, "not scored");
        assert_eq!(n.preference(), prefs);
        assert_eq!(n.stats().accepted, accepted);
        assert_eq!(n.wave_stats().ignored, ignored, "not the wave's business");
        // Messages without its tag are still heard.
        hear(&mut n, &mut rng, &mut t, Sector::RIGHT, &[hop(3, 0, L)]);
        assert_eq!(n.stats().own_tag, 3);
    }

    /// The ray robots `far..near` (readings and preferences, farthest first) send toward a
    /// robot that hears the nearest of them from `from`.
    fn ray(from: Sector, robots: &[(u8, Option<Sector>)]) -> Ray {
        let (&(r0, p0), rest) = robots.split_first().unwrap();
        let first = Ray::single(from, 2, Level(r0), p0).unwrap();
        rest.iter()
            .fold(first, |ray, &(r, p)| ray.extended(Level(r), p))
    }

    /// `ray` as a ray that reaches the end of its side ([`Ray::closed`]).
    fn closed(mut ray: Ray) -> Ray {
        ray.closed = true;
        ray
    }

    /// Like [`hear`], for a message carrying `ray`.
    fn hear_ray(
        n: &mut FusedNode,
        rng: &mut Pcg32,
        t: &mut Instant,
        from: Sector,
        msg: &[Hop],
        ray: Ray,
    ) -> Message {
        *t += Duration::from_secs(12);
        n.handle_timeout(*t, rng);
        while n.poll_transmit().is_some() {}
        let mut m = Message::from_hops(msg).unwrap();
        m.set_ray(Some(ray));
        assert_eq!(n.handle_message(*t, from, &m, rng), Reception::Accepted);
        n.handle_timeout(*t + Duration::from_secs(1), rng);
        n.poll_transmit().expect("relayed")
    }

    #[test]
    fn full_message_relay_drops_the_oldest_hops_to_make_room_for_the_ray() {
        let (mut n, mut rng) = node(15, 9);
        let mut t = Instant::from_secs(1);
        let full: std::vec::Vec<Hop> = (0..MAX_HOPS as u8).map(|r| hop(r, r, None)).collect();
        let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full);
        // 24 payload bytes: header, a two-sector ray (9 bytes), 7 hops (an eighth does not
        // fit the 25).
        assert_eq!(out.len(), 7);
        assert_eq!(out.encoded_len(), 24);
        assert_eq!(out.hops()[0], hop(6, 6, None));
        let last = out.hops()[6];
        assert_eq!((last.reading, last.tag), (Level(9), n.tag()));
        assert_eq!(n.stats().hops_evicted, 6);
        // Nothing held from the left yet: the ray is the robot alone.
        let ray = out.ray().unwrap();
        assert_eq!(
            (ray.sector, ray.robots, ray.mean_level()),
            (Sector::LEFT, 1, 9.0)
        );
        assert!(crate::frame::encode(&out).is_ok());
    }

    #[test]
    fn relays_keep_at_most_max_hops() {
        let (mut n, mut rng) = node(15, 9);
        let mut p = *n.params();
        p.max_hops = crate::frame::KEYED_MAX_HOPS as u8;
        n = FusedNode::new(p, n.tag(), Instant::ZERO, &mut rng).unwrap();
        n.handle_reading(Level(9));
        let mut t = Instant::from_secs(1);
        // A full plain message (12 hops) relayed by an 11-hop node: a payload of 23 bytes,
        // the ray's 9 and 6 hops.
        let full: std::vec::Vec<Hop> = (0..MAX_HOPS as u8).map(|r| hop(r, r, None)).collect();
        let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full);
        assert_eq!(out.len(), 6);
        assert_eq!(out.encoded_len(), 22);
        assert_eq!(out.hops()[0], hop(7, 7, None));
        assert_eq!(out.hops()[5].reading, Level(9));
        assert_eq!(n.stats().hops_evicted, 7);
        // Shorter ones just grow, and an encoded relay always fits a keyed frame.
        let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full[..3]);
        assert_eq!(out.len(), 4);
        assert_eq!(n.stats().hops_evicted, 7);
        #[cfg(feature = "keyed")]
        assert!(crate::frame::encode_keyed(&out, &crate::auth::SwarmKey::new([5; 16])).is_ok());
    }

    #[test]
    fn rays_count_every_robot_beyond_the_horizon_once() {
        // Robot 20 of a long line: 20 robots to its left (12 preferring R, 8 L), 30 to its
        // right preferring L; the messages hold only the nearest few.
        let (mut n, mut rng) = node(4, 30);
        let mut t = Instant::from_secs(1);
        let mut left: std::vec::Vec<(u8, Option<Sector>)> = std::vec![(200, R); 12];
        left.extend([(30, L); 8]);
        let right = std::vec![(30, L); 30];
        let out = hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(2, 30, L), hop(3, 30, L)],
            ray(Sector::LEFT, &left),
        );
        // The left is diverse (a border somewhere beyond), the right uniform.
        assert_eq!(n.preference(), L);
        // The relay goes right with the left's ray extended by this robot.
        let sent = out.ray().unwrap();
        assert_eq!((sent.sector, sent.robots), (Sector::LEFT, 21));
        assert_eq!(sent.votes[..2], [12, 9]);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(6, 30, L), hop(5, 30, L)],
            ray(Sector::RIGHT, &right),
        );
        assert_eq!(n.preference(), L, "the right is uniform");
        assert_eq!(n.votes()[..2], [12, 39]);
        assert_eq!(n.stats().rays, 2);
        let Event::Decided { decision, .. } = run_to_decision(&mut n, &mut rng) else {
            unreachable!()
        };
        assert_eq!(decision, L);
    }

    #[test]
    fn the_direction_is_scored_by_its_whole_ray() {
        // Robot far to the right of a border: the nearest hops are dark like itself, but the
        // ray from the left holds lit robots beyond the horizon.
        let (mut n, mut rng) = node(4, 30);
        let mut t = Instant::from_secs(1);
        let mut left = std::vec![(200, R); 5];
        left.extend([(30, L); 20]);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(2, 30, L), hop(3, 30, L)],
            ray(Sector::LEFT, &left),
        );
        let expected = ray(Sector::LEFT, &left)
            .extended(Level(30), None)
            .variance();
        assert_eq!(n.weight(Sector::LEFT), Some(expected));
        assert!(expected > 1000.0);
        // Without a ray: the message's readings with the own (Alg. 1), here uniform.
        hear(&mut n, &mut rng, &mut t, Sector::RIGHT, &[hop(6, 30, L)]);
        assert_eq!(n.weight(Sector::RIGHT), Some(0.0));
        assert_eq!(n.preference(), L);
    }

    #[test]
    fn a_ray_is_taken_only_for_its_own_sector_and_from_the_followed_neighbour() {
        let (mut n, mut rng) = node(1, 0);
        let mut t = Instant::from_secs(1);
        let far = [(0, L), (0, L), (0, L)];
        // A ray of the left heard from the right (an initiation meant for the other side).
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 0, L)],
            ray(Sector::LEFT, &far),
        );
        assert_eq!((n.stats().rays, n.stats().rays_refused), (0, 1));
        // Robot 2's ray of the right: followed from now on.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 0, L)],
            ray(Sector::RIGHT, &far),
        );
        assert_eq!(n.votes()[..2], [0, 3]);
        // Robot 3 (two away) sends a shorter ray: refused while robot 2 is heard.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(3, 0, R)],
            ray(Sector::RIGHT, &[(0, R), (0, R)]),
        );
        assert_eq!(n.votes()[..2], [0, 3]);
        // Robot 2 again, preferences changed: it replaces its own ray, shorter or not.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 0, R)],
            ray(Sector::RIGHT, &[(0, R), (0, R)]),
        );
        assert_eq!(n.votes()[..2], [2, 0]);
        // A ray reaching farther, from another neighbour, is taken.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(7, 0, L)],
            ray(Sector::RIGHT, &[(0, L); 4]),
        );
        assert_eq!(n.votes()[..2], [0, 4]);
        // Robot 0 on the left; a frame of robot 0 moved to the right by a replayer, with a ray
        // that reaches farther, is refused: robot 0 is followed on the left.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 1, R)],
            ray(Sector::LEFT, &[(1, R)]),
        );
        let before = n.votes();
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(0, 1, R)],
            ray(Sector::RIGHT, &[(1, R); 9]),
        );
        assert_eq!(n.votes(), before);
        // After three silent cycles of its neighbour another sender is taken, shorter or not.
        t += Duration::from_secs(3 * 600 + 1);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(3, 0, R)],
            ray(Sector::RIGHT, &[(0, R)]),
        );
        assert_eq!(n.votes()[..2], [2, 1], "robot 3 R; its own L");
    }

    #[test]
    fn initiations_carry_the_shortest_sides_ray() {
        let (mut n, mut rng) = node(1, 7);
        let mut t = Instant::from_secs(1);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 0, L)],
            ray(Sector::RIGHT, &[(0, L); 3]),
        );
        let initiate = |n: &mut FusedNode, rng: &mut Pcg32| loop {
            let at = n.poll_timeout();
            n.handle_timeout(at, rng);
            if let Some(m) = n.poll_transmit() {
                return m;
            }
        };
        // Nothing held on the left: the edge's own ray goes out, meant for the right.
        let m = initiate(&mut n, &mut rng);
        assert_eq!(m.hops(), &[hop(1, 7, R)]);
        let r = m.ray().unwrap();
        assert_eq!((r.sector, r.robots, r.votes[0]), (Sector::LEFT, 1, 1));
        // With a longer left, the right is the short side.
        // Rested after the initiation.
        t = n.poll_timeout();
        n.handle_timeout(t, &mut rng);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 0, R)],
            ray(Sector::LEFT, &[(0, R); 5]),
        );
        let r = *initiate(&mut n, &mut rng).ray().unwrap();
        assert_eq!((r.sector, r.robots), (Sector::RIGHT, 4));
    }

    fn run_to_decision(n: &mut FusedNode, rng: &mut Pcg32) -> Event {
        loop {
            let t = n.poll_timeout();
            n.handle_timeout(t, rng);
            while n.poll_transmit().is_some() {}
            while let Some(e) = n.poll_event() {
                if matches!(e, Event::Decided { .. }) {
                    return e;
                }
            }
        }
    }

    /// An adaptive robot (cycle 600 s, so no wave of its own disturbs the test) and the
    /// `Decided` events waiting in it.
    fn adaptive(negotiation: u16) -> (FusedNode, Pcg32) {
        let (n, _) = node(1, 30);
        let mut rng = Pcg32::new(11, 13);
        let mut p = *n.params();
        p.decide = DecisionRule::Adaptive;
        p.negotiation_cycles = negotiation;
        let mut n = FusedNode::new(p, n.tag(), Instant::ZERO, &mut rng).unwrap();
        n.handle_reading(Level(30));
        (n, rng)
    }

    fn decisions(n: &mut FusedNode) -> std::vec::Vec<(u32, Option<Sector>)> {
        core::iter::from_fn(|| n.poll_event())
            .filter_map(|e| match e {
                Event::Decided {
                    period, decision, ..
                } => Some((period, decision)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn adaptive_decides_as_soon_as_both_sides_are_heard_to_their_ends_and_the_votes_are_clear() {
        // Robot 1 of `1000`: left the lit robot 0 (pref R), right robots 2 and 3 (L, L).
        let (mut n, mut rng) = adaptive(10);
        let mut t = Instant::from_secs(1);
        let left = || closed(ray(Sector::LEFT, &[(200, R)]));
        let right = || closed(ray(Sector::RIGHT, &[(30, L), (30, L)]));
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left(),
        );
        assert_eq!(n.preference(), L);
        // One side heard, and less than a cycle gone: not informed, no decision.
        assert_eq!(decisions(&mut n), []);
        // The right's ray does not reach its end yet: robots beyond robot 2 may still come
        // (in a tie they are what decides), so 2 L to 1 R is no decision.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            ray(Sector::RIGHT, &[(30, L)]),
        );
        assert_eq!(n.votes()[..2], [1, 2]);
        assert_eq!(decisions(&mut n), [], "an open ray");
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            right(),
        );
        // Both sides heard to their ends, votes 3 L to 1 R, nobody without a vote: decided,
        // 37 s in.
        assert_eq!(
            decisions(&mut n),
            [(1, L)],
            "decided at {t:?}, in the first cycle"
        );
        assert_eq!(n.decision(), L);
        // Nothing new: no event, however many more rays confirm it.
        for _ in 0..3 {
            hear_ray(
                &mut n,
                &mut rng,
                &mut t,
                Sector::RIGHT,
                &[hop(2, 30, L)],
                right(),
            );
            hear_ray(
                &mut n,
                &mut rng,
                &mut t,
                Sector::LEFT,
                &[hop(0, 200, R)],
                left(),
            );
        }
        assert_eq!(decisions(&mut n), []);
    }

    #[test]
    fn adaptive_a_message_without_a_ray_stands_for_its_side() {
        let (mut n, mut rng) = adaptive(10);
        let mut t = Instant::from_secs(1);
        let left = closed(ray(Sector::LEFT, &[(200, R)]));
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left,
        );
        // A message from the right without a ray: the robots it passed stand for that side
        // until a ray comes (1 L), with the own preference (L); they are not known to be the
        // whole side, so no decision yet.
        hear(&mut n, &mut rng, &mut t, Sector::RIGHT, &[hop(2, 30, L)]);
        assert_eq!(n.votes()[..2], [1, 2]);
        assert_eq!(decisions(&mut n), []);
        // The right's ray, to its end: 3 L to 1 R.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            closed(ray(Sector::RIGHT, &[(30, L), (30, L)])),
        );
        assert_eq!(decisions(&mut n), [(1, L)]);
    }

    #[test]
    fn adaptive_waits_for_a_side_it_hears_but_holds_no_ray_from() {
        let (mut n, mut rng) = adaptive(10);
        let mut t = Instant::from_secs(1);
        let left = closed(ray(Sector::LEFT, &[(200, R)]));
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left,
        );
        // An echo of its own relay from the right: dropped, but a neighbour is there.
        let echo = Message::from_hops(&[hop(0, 200, R), hop(1, 30, L), hop(2, 30, L)]).unwrap();
        t += Duration::from_secs(2);
        assert_eq!(
            n.handle_message(t, Sector::RIGHT, &echo, &mut rng),
            Reception::OwnTag
        );
        // A whole cycle later it is informed by time, and still waits for that side's ray.
        let end = Instant::from_secs(700);
        while n.poll_timeout() <= end {
            let at = n.poll_timeout();
            n.handle_timeout(at, &mut rng);
            while n.poll_transmit().is_some() {}
        }
        assert_eq!(decisions(&mut n), []);
        assert_eq!(n.decision(), None);
    }

    #[test]
    fn adaptive_waits_while_robots_without_a_vote_could_overturn_it_then_the_cap_decides() {
        let (mut n, mut rng) = adaptive(1);
        let mut t = Instant::from_secs(1);
        // Left one robot for R; right two robots without a preference yet: 1 L (own) to 1 R,
        // and two undecided robots could tip it either way.
        let left = || closed(ray(Sector::LEFT, &[(200, R)]));
        let right = || closed(ray(Sector::RIGHT, &[(30, None), (30, None)]));
        for _ in 0..4 {
            hear_ray(
                &mut n,
                &mut rng,
                &mut t,
                Sector::LEFT,
                &[hop(0, 200, R)],
                left(),
            );
            hear_ray(
                &mut n,
                &mut rng,
                &mut t,
                Sector::RIGHT,
                &[hop(2, 30, None)],
                right(),
            );
        }
        assert_eq!(decisions(&mut n), [], "ambiguous evidence: no decision");
        // The cap: at the end of the period (one 600 s cycle) the fixed rule decides (a tie:
        // the own preference).
        let Event::Decided {
            period, decision, ..
        } = run_to_decision(&mut n, &mut rng)
        else {
            unreachable!()
        };
        assert_eq!((period, decision), (1, L));
    }

    #[test]
    fn adaptive_changes_a_shown_decision_only_once_every_side_confirmed_the_change() {
        let (mut n, mut rng) = adaptive(10);
        let mut t = Instant::from_secs(1);
        let left = || closed(ray(Sector::LEFT, &[(200, R)]));
        let right_l = || closed(ray(Sector::RIGHT, &[(30, L), (30, L)]));
        // Three robots on the right, now all for R: 4 R to 1 L.
        let right_r = || closed(ray(Sector::RIGHT, &[(30, R), (30, R), (30, R)]));
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left(),
        );
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            right_l(),
        );
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left(),
        );
        assert_eq!(decisions(&mut n), [(1, L)]);
        // One ray with other votes is not enough to change the LEDs...
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, R)],
            right_r(),
        );
        assert_eq!(decisions(&mut n), []);
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, R)],
            right_r(),
        );
        assert_eq!(decisions(&mut n), [], "the left has not confirmed it");
        // ...the left confirming it is.
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            left(),
        );
        assert_eq!(decisions(&mut n), [(1, R)]);
    }

    #[test]
    fn adaptive_votes_only_once_informed_and_spreads_a_new_vote_backwards() {
        let (mut n, mut rng) = adaptive(10);
        let mut t = Instant::from_secs(1);
        // Heard from the left only: a preference (L), but no vote in the ray it relays.
        let out = hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 200, R)],
            ray(Sector::LEFT, &[(200, R)]),
        );
        assert_eq!(n.preference(), L);
        assert_eq!(out.ray().unwrap().votes[..2], [1, 0], "robot 0's vote only");
        // Heard from both sides, the right (the side it does not prefer) to its end: its vote
        // goes out (the left may still grow; it holds the border whatever lies beyond). The
        // relay of the right's wave carries it to the left (the ray of the right, closed); one
        // extra initiation carries it to the right (the ray of the left, still open).
        let out = hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            closed(ray(Sector::RIGHT, &[(30, L)])),
        );
        assert_eq!(out.ray().unwrap().votes[..2], [0, 2]);
        assert!(
            out.ray().unwrap().closed,
            "the relay extends the right's closed ray"
        );
        // As soon as it is free: relay delay + refractory + a relay delay at most.
        let soon = t + Duration::from_secs(1 + 4 + 1);
        let extra = loop {
            let at = n.poll_timeout();
            assert!(at <= soon, "no extra initiation in time");
            n.handle_timeout(at, &mut rng);
            if let Some(m) = n.poll_transmit() {
                break m;
            }
        };
        assert_eq!(extra.len(), 1, "an initiation");
        let r = extra.ray().unwrap();
        assert_eq!(
            (r.sector, r.robots, r.votes[..2].to_vec(), r.closed),
            (Sector::LEFT, 2, std::vec![1, 1], false)
        );
    }

    #[test]
    fn adaptive_an_end_robot_knows_its_outward_side_is_empty_after_a_silent_longest_cycle() {
        // Robot 0 of `1000` (lit; its cycle is 600 s, no spread): it hears only its right, whose
        // ray reaches robot 3 (L, L, L). It prefers R (the right is diverse with itself).
        let (mut n, mut rng) = adaptive(10);
        n.handle_reading(Level(200));
        let mut t = Instant::from_secs(1);
        let right = closed(ray(Sector::RIGHT, &[(30, L), (30, L), (30, L)]));
        let out = hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(2, 30, L)],
            right,
        );
        assert_eq!(n.preference(), R);
        assert!(out.ray().unwrap().closed, "the right's ray is closed");
        // Nothing lies to its left that it knows of, but a neighbour there may still initiate
        // within a longest cycle: no vote, no decision, and it wakes when that cycle is over.
        while n.poll_timeout() < Instant::from_secs(600) {
            let at = n.poll_timeout();
            n.handle_timeout(at, &mut rng);
            while n.poll_transmit().is_some() {}
        }
        assert_eq!(decisions(&mut n), []);
        assert_eq!(n.poll_timeout(), Instant::from_secs(600));
        n.handle_timeout(Instant::from_secs(600), &mut rng);
        // Now its left is empty: 3 L to its 1 R, every side known to its end.
        assert_eq!(decisions(&mut n), [(1, L)]);
        // And it tells the right at once (here its cycle's own initiation, due now, carries it):
        // its ray of the (empty) left, closed, with its vote.
        let m = loop {
            if let Some(m) = n.poll_transmit() {
                break m;
            }
            let at = n.poll_timeout();
            assert!(at <= Instant::from_secs(601), "news at {at:?}");
            n.handle_timeout(at, &mut rng);
        };
        let r = m.ray().unwrap();
        assert_eq!(
            (r.sector, r.robots, r.votes[..2].to_vec(), r.closed),
            (Sector::LEFT, 1, std::vec![1, 0], true)
        );
    }

    #[test]
    fn tie_keeps_own_preference_and_rays_expire_after_a_period() {
        let (mut n, mut rng) = node(1, 1);
        let mut t = Instant::from_secs(1);
        // 1100 seen by the second robot: left lit (pref R), right dark (prefs L, L).
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(0, 1, R)],
            ray(Sector::LEFT, &[(1, R)]),
        );
        hear_ray(
            &mut n,
            &mut rng,
            &mut t,
            Sector::RIGHT,
            &[hop(3, 0, L), hop(2, 0, L)],
            ray(Sector::RIGHT, &[(0, L), (0, L)]),
        );
        assert_eq!(n.preference(), R);
        let e = run_to_decision(&mut n, &mut rng);
        let Event::Decided {
            decision,
            votes,
            period,
            changed,
        } = e
        else {
            unreachable!()
        };
        assert_eq!((decision, period, changed), (R, 1, true));
        assert_eq!(votes[..2], [2, 2]);
        assert_eq!(n.decision(), R);
        // Nothing heard in the next period: the rays are a period old and forgotten.
        let Event::Decided {
            decision,
            votes,
            changed,
            ..
        } = run_to_decision(&mut n, &mut rng)
        else {
            unreachable!()
        };
        assert_eq!((decision, changed), (R, false));
        assert_eq!(votes[..2], [1, 0], "rays expired");
        // The diversities carry over as one-message priors: the left's 0 (robot 0 lit like
        // this robot), the right's 2/9 (readings 0, 0 and the own 1, exact in the ray's sums).
        let right = n.weight(Sector::RIGHT).unwrap();
        assert_eq!(right, 2.0 / 9.0);
        assert_eq!(n.weight(Sector::LEFT), Some(0.0));
        // Robot 0's light goes out, and a wave from farther left (robots 6, 5, 4: 1, 2, 1)
        // passes it: with the own 1, diversity 2/5. On its own that beats the right's 1/4;
        // averaged with the left's prior it gives 1/5, and the preference holds.
        let v = Variance.measure([1.0, 2.0, 1.0, 0.0, 1.0].into_iter());
        assert!(v > right && v / 2.0 < right, "only the prior keeps it: {v}");
        // Two periods of fixed 600 s cycles have passed; the node last initiated at 12000 s.
        t = Instant::from_secs(12_010);
        hear(
            &mut n,
            &mut rng,
            &mut t,
            Sector::LEFT,
            &[hop(6, 1, R), hop(5, 2, R), hop(4, 1, R), hop(0, 0, R)],
        );
        assert_eq!(n.preference(), R, "one message does not flip it");
        assert_eq!(n.weight(Sector::LEFT), Some(v / 2.0));
    }

    #[test]
    fn the_cosine_table_is_the_cosine() {
        for k in 2..=MAX_SECTORS {
            for (d, &table) in COSINES[k][..k].iter().enumerate() {
                let c = libm::cos(core::f64::consts::TAU * d as f64 / k as f64);
                assert!((f64::from(table) - c).abs() < 1e-6, "{k} {d}");
            }
            assert!(COSINES[k][k..].iter().all(|&c| c == 0.0));
        }
        assert_eq!(COSINES[4][1], 0.0);
        assert_eq!(COSINES[6][1], 0.5);
    }

    #[test]
    fn plane_votes_add_up_along_their_resultant() {
        // K = 6: sector 1 has the plurality, but sectors 0, 1 and 5 all point to +x and
        // sector 0 is nearest their resultant.
        let votes = [2, 3, 0, 0, 0, 2, 0, 0];
        let s = resultant_scores(&votes, 6);
        assert_eq!(s[0], 4.5);
        assert_eq!(s[1], 3.0);
        assert!(s[..6].iter().all(|&x| x <= s[0]));
        // K = 2: the difference of the counts, exact ties stay ties.
        let s = resultant_scores(&[3, 3, 0, 0, 0, 0, 0, 0], 2);
        assert_eq!(s[..2], [0.0, 0.0]);
        // K = 4: perpendicular votes do not count.
        let s = resultant_scores(&[1, 5, 0, 0, 0, 0, 0, 0], 4);
        assert_eq!(s[..4], [1.0, 5.0, -1.0, -5.0]);
    }

    #[test]
    fn a_period_lasts_the_configured_cycles() {
        let (mut n, mut rng) = node(0, 0);
        let Event::Decided { decision, .. } = run_to_decision(&mut n, &mut rng) else {
            unreachable!()
        };
        assert_eq!(decision, None, "no preference, no votes: undecided");
        assert_eq!(n.wave_stats().initiated, 10);
        assert_eq!(n.periods(), 1);
    }

    #[test]
    fn invalid_params_are_refused() {
        let mut p = Params::robots();
        p.sectors = 0;
        assert_eq!(
            FusedNode::new(p, Tag::default(), Instant::ZERO, &mut Pcg32::new(0, 0)).err(),
            Some(ParamError::BadSectorCount)
        );
    }
}
