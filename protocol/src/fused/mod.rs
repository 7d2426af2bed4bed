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
//! [`DecisionRule::Fixed`](crate::params::DecisionRule::Fixed), the paper's; with [`DecisionRule::Adaptive`](crate::params::DecisionRule::Adaptive) a robot decides as
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
//! # Decision rules
//! When to show what, and what a robot votes in the rays it sends, is its [`Rule`] (one file
//! each, behind a small trait the node calls, as quinn-proto keeps congestion control behind
//! its `Controller`): [`Fixed`], the paper's, decides at every period's end; [`Adaptive`] as
//! soon as its evidence is settled (a [`Ray::closed`] ray or a silent side tells it a side is
//! known to its end), the period being the cap. `docs/protocol.md` §5.4 gives each of its
//! rules, why it is safe and what was measured. [`FusedNode`]'s default, [`AnyRule`], runs the
//! one [`Params::decide`](crate::params::Params::decide) names; a build for one rule names it instead
//! ([`FusedNode::with_rule`]).
//!
//! **Tie rule**: if several sectors share the most votes, the robot keeps its own preference if
//! it is one of them, else its previous decision if that is one of them, else it is undecided.
//! In the lab's `1100` pattern every robot sees two votes each way and so moves toward the
//! border, as the paper reports; an odd swarm or a plane swarm rarely ties.

mod adaptive;
mod any;
mod fixed;
mod rule;
mod state;
#[cfg(test)]
mod tests;

use rand_core::RngCore;

pub use self::adaptive::Adaptive;
pub use self::any::AnyRule;
pub use self::fixed::Fixed;
pub use self::rule::{Cause, RayPolicy, Rule};
pub use self::state::Core;

use self::state::Held;
use crate::direction::{MAX_SECTORS, Sector};
use crate::diversity::{Diversity, Variance};
use crate::message::{Level, Message, Ray, Tag};
use crate::params::{ParamError, Params};
use crate::time::Instant;
use crate::wave::{WaveAction, WaveState, WaveStats};

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
    /// ([`DecisionRule::Fixed`](crate::params::DecisionRule::Fixed)), or when the evidence settled ([`DecisionRule::Adaptive`](crate::params::DecisionRule::Adaptive)).
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

/// One robot running fused CIMAX with diversity measure `D` and decision rule `R`. Sans-IO: no
/// clock, no radio, no globals.
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
pub struct FusedNode<D: Diversity = Variance, R: Rule = AnyRule> {
    core: Core,
    diversity: D,
    rule: R,
}

impl FusedNode<Variance> {
    /// A robot with tag `tag` (its id modulo 16, [`Tag::from_id`]), the variance as
    /// diversity measure and the rule `params.decide` names, starting its first cycle at `now`.
    /// Robots within [`MAX_HOPS`](crate::message::MAX_HOPS) hops of each other need distinct
    /// tags.
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
        Self::with_rule(params, tag, diversity, now, rng)
    }
}

impl<D: Diversity, R: Rule> FusedNode<D, R> {
    /// A robot running rule `R` ([`Fixed`], [`Adaptive`], or [`AnyRule`]: the one
    /// `params.decide` names), with diversity measure `diversity`; otherwise as
    /// [`FusedNode::new`]. A build that ships one rule names it, and carries no other's code.
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate, or
    /// [`ParamError::RuleMismatch`] if `params.decide` names another rule than `R`.
    pub fn with_rule(
        params: Params,
        tag: Tag,
        diversity: D,
        now: Instant,
        rng: &mut impl RngCore,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        let rule = R::start(&params, now);
        if rule.decides() != params.decide {
            return Err(ParamError::RuleMismatch);
        }
        Ok(FusedNode {
            core: Core::new(params, tag, now, rng),
            diversity,
            rule,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.core.params
    }

    /// This robot's tag, written into every hop it adds.
    pub fn tag(&self) -> Tag {
        self.core.tag
    }

    /// The latest sensor reading.
    pub fn reading(&self) -> Level {
        self.core.reading
    }

    /// The current preferred direction.
    pub fn preference(&self) -> Option<Sector> {
        self.core.pref
    }

    /// The decision of the last completed negotiation period (what the LEDs show).
    pub fn decision(&self) -> Option<Sector> {
        self.core.decision
    }

    /// Negotiation periods completed.
    pub fn periods(&self) -> u32 {
        self.core.periods
    }

    /// The wave state.
    pub fn state(&self) -> WaveState {
        self.core.wave.state()
    }

    /// Average diversity heard from `sector` this period, if anything was heard from it.
    pub fn weight(&self, sector: Sector) -> Option<f32> {
        self.core.weights.weight(sector)
    }

    /// This node's counters.
    pub fn stats(&self) -> &NodeStats {
        &self.core.stats
    }

    /// The wave node's counters.
    pub fn wave_stats(&self) -> &WaveStats {
        self.core.wave.stats()
    }

    /// The votes: the robot's own preference plus, for each sector, the votes of the ray held
    /// from it (every robot on that side, once); sectors `≥ K` are not counted.
    pub fn votes(&self) -> Votes {
        self.core.votes()
    }

    /// The decision rule.
    pub fn rule(&self) -> &R {
        &self.rule
    }

    /// A new sensor reading; it goes into every hop this robot adds from now on. (Under the
    /// adaptive rule a reading that moved by more than what the robot sees is news,
    /// [`Adaptive`].)
    pub fn handle_reading(&mut self, reading: Level) {
        self.rule.on_reading(&self.core, reading);
        self.core.reading = reading;
    }

    /// A message arrived at `now` on the receiver facing `from`.
    ///
    /// Whatever was due up to `now` is done first (as by
    /// [`handle_timeout`](Self::handle_timeout)), so a message that arrives just as the
    /// refractory time ends is heard, whichever of the two the caller learnt of first.
    // Kept out of the robot's main task: LTO inlined it there whole, 116 B more in the Nucleo
    // image, whose budget has little left (docs/firmware.md, "Footprint").
    #[inline(never)]
    pub fn handle_message(
        &mut self,
        now: Instant,
        from: Sector,
        msg: &Message,
        rng: &mut impl RngCore,
    ) -> Reception {
        self.handle_timeout(now, rng);
        let rays = self.core.stats.rays;
        let r = self.receive(now, from, msg);
        let confirming = (self.core.stats.rays != rays).then_some(from);
        let cause = Cause::Reception(confirming);
        self.rule.react(&mut self.core, now, cause, rng);
        r
    }

    /// [`handle_message`](Self::handle_message) once what was due is done.
    fn receive(&mut self, now: Instant, from: Sector, msg: &Message) -> Reception {
        if from.index() >= self.core.params.sectors {
            let stats = &mut self.core.stats;
            stats.unknown_sector = stats.unknown_sector.wrapping_add(1);
            return Reception::UnknownSector;
        }
        self.rule.heard_from(from);
        if msg.has_tag(self.core.tag) {
            self.core.stats.own_tag = self.core.stats.own_tag.wrapping_add(1);
            return Reception::OwnTag;
        }
        let policy = self.rule.policy();
        let mut took = match (msg.ray(), msg.hops().last()) {
            (Some(ray), Some(sender)) => self.take_ray(now, from, ray, sender.tag),
            _ => false,
        };
        if !took && policy.hops_stand_for_side && self.core.ray_from(from).is_none() {
            // Nothing known of that side: the robots the message passed stand for it.
            if let (Some(ray), Some(sender)) = (self.ray_of_hops(from, msg), msg.hops().last()) {
                took = self.take_ray(now, from, &ray, sender.tag);
            }
        }
        if msg.is_empty() || !self.core.wave.on_receive(now) {
            // The adaptive rule scores a ray also while the robot is busy: a neighbour whose
            // initiations fall while it relays would otherwise never be scored.
            if took && policy.latest_ray_scores {
                self.score(from, msg);
            }
            return Reception::Ignored;
        }
        self.core.stats.accepted = self.core.stats.accepted.wrapping_add(1);
        self.core.push_event(Event::State(WaveState::Active));
        self.score(from, msg);
        self.core.pending = Some((msg.clone(), from));
        Reception::Accepted
    }

    /// The ray of the robots `msg` passed, as seen from sector `from`: their readings and
    /// preferences as votes.
    fn ray_of_hops(&self, from: Sector, msg: &Message) -> Option<Ray> {
        let (first, rest) = msg.hops().split_first()?;
        let k = self.core.params.sectors;
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
    /// (Alg. 1). Under [`RayPolicy::latest_ray_scores`] a held ray's diversity replaces the
    /// average: a summary of the whole side that supersedes the older ones.
    fn score(&mut self, from: Sector, msg: &Message) {
        let core = &mut self.core;
        let v = match core.ray_from(from) {
            Some(ray) => ray.extended(core.reading, None).variance(),
            None => {
                let own = f32::from(core.reading);
                self.diversity
                    .measure(msg.readings().chain(core::iter::once(own)))
            }
        };
        if self.rule.policy().latest_ray_scores && core.ray_from(from).is_some() {
            core.weights.set(from, v);
        } else {
            core.weights.add(from, v);
        }
        if let Some(best) = core.weights.heaviest_within(TIE_TOLERANCE)
            && core.pref != Some(best)
        {
            core.pref = Some(best);
            core.push_event(Event::Preference(core.pref));
        }
    }

    /// Does whatever is due at `now`: relays, initiations, the end of the refractory time,
    /// cycle and period ends, and the rule's own timers.
    pub fn handle_timeout(&mut self, now: Instant, rng: &mut impl RngCore) {
        let react = self.rule.begin_timeout(&self.core, now);
        // Only a call at which the wave has something due can add a debt or use up the
        // deferral, so only such a call schedules one: a deferral that could not be scheduled
        // (it fell at the end of time, `Instant::MAX`) must not be scheduled by a later call
        // before the deadline at an earlier `now` (a clock set back), which would change what
        // the robot does before anything is due (fuzz/README.md, finding 14).
        let due = self.core.wave.poll_timeout() <= now;
        self.poll_wave(now, rng);
        let wave = &self.core.wave;
        if due && wave.owed() > 0 && !wave.extra_pending() {
            // An initiation that fell while the robot was busy is deferred, not lost (both
            // rules): the paper's robots initiate at least once per cycle.
            let at = self.core.deferred_initiation_at(now, rng);
            self.core.wave.initiate_extra(at);
        }
        if react {
            self.rule.react(&mut self.core, now, Cause::Timeout, rng);
        }
    }

    fn poll_wave(&mut self, now: Instant, rng: &mut impl RngCore) {
        while let Some(action) = self.core.wave.poll(now, rng) {
            match action {
                WaveAction::Initiate => self.initiate(now, rng),
                WaveAction::Relay => {
                    if let Some((mut m, from)) = self.core.pending.take() {
                        // The received ray goes (this robot sends its own), then room for the
                        // own hop within the capacity (`validate`: at least 1).
                        m.set_ray(None);
                        let cap = usize::from(self.core.params.max_hops).max(1);
                        let dropped = m.keep_newest(cap - 1);
                        // Cannot evict: no ray, and at most cap - 1 < MAX_HOPS hops remain.
                        m.push_evicting(self.core.own_hop());
                        self.core.count_evicted(dropped);
                        self.send_with_ray(m, from);
                    }
                }
                WaveAction::Rested => self.core.push_event(Event::State(WaveState::Inactive)),
                WaveAction::CycleEnded(_) => self.cycle_ended(now, rng),
            }
        }
    }

    /// The robot's initiation (its own, or an extra one): counted in its period, carrying the
    /// ray the rule asked for or the core's choice.
    fn initiate(&mut self, now: Instant, rng: &mut impl RngCore) {
        let core = &mut self.core;
        if core.decide_pending && !core.wave.last_was_extra() {
            // The next period's first cycle initiated before the owed one.
            core.next_period_initiations = core.next_period_initiations.saturating_add(1);
        } else {
            core.period_initiations = core.period_initiations.saturating_add(1);
        }
        if core.wave.owed() == 0 {
            // Nothing to make up: this initiation carries any news.
            core.wave.cancel_extra();
        }
        let sector = match self.rule.initiation_sector() {
            Some(s) => s,
            None => self.core.initiation_ray(),
        };
        let m = Message::initiate(self.core.own_hop());
        self.send_with_ray(m, sector);
        self.rule.react(&mut self.core, now, Cause::Initiated, rng);
        if self.core.decide_pending && self.core.wave.owed() == 0 {
            self.core.decide_pending = false;
            self.rule.end_of_period(&mut self.core, now);
        }
    }

    /// One of the robot's cycles ended: a period ends after its last cycle, once its owed
    /// initiation went out (paper section 4: every robot initiates once per cycle of it).
    fn cycle_ended(&mut self, now: Instant, rng: &mut impl RngCore) {
        let core = &mut self.core;
        if core.decide_pending {
            // The owed initiation did not go out within a cycle: end the period.
            core.decide_pending = false;
            self.rule.end_of_period(core, now);
        }
        core.period_cycles = core.period_cycles.saturating_add(1);
        if core.period_cycles >= core.params.negotiation_cycles {
            if core.wave.owed() > 0 {
                core.decide_pending = true;
                core.period_cycles = 0;
            } else {
                self.rule.end_of_period(core, now);
            }
        }
        self.rule.react(&mut self.core, now, Cause::CycleEnded, rng);
    }

    /// When [`handle_timeout`](Self::handle_timeout) must be called next.
    pub fn poll_timeout(&self) -> Instant {
        self.core.wave.poll_timeout().min(self.rule.poll_timeout())
    }

    /// The next message to broadcast, if any; frame it with [`crate::frame::encode`].
    pub fn poll_transmit(&mut self) -> Option<Message> {
        self.core.outbox.pop_front()
    }

    /// The next event, if any.
    pub fn poll_event(&mut self) -> Option<Event> {
        self.core.events.pop_front()
    }

    /// Attaches the ray of `sector` extended by this robot (what lies that way, and itself),
    /// with the vote the rule gives, trims the message to the payload budget of `max_hops` and
    /// transmits it.
    fn send_with_ray(&mut self, mut m: Message, sector: Sector) {
        let (vote, closed) = self.rule.ray_to_send(&self.core, sector);
        let core = &mut self.core;
        let ray = match core.ray_from(sector) {
            Some(r) => Some(r.extended(core.reading, vote)),
            None => Ray::single(sector, core.params.sectors, core.reading, vote).map(|mut r| {
                r.closed = closed;
                r
            }),
        };
        let mut dropped = m.set_ray(ray);
        // The payload a frame of `max_hops` plain hops would have (keyed frames: 11 hops).
        dropped += m.fit(1 + 2 * usize::from(core.params.max_hops.max(1)));
        core.count_evicted(dropped);
        core.transmit(m);
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
    /// Under [`RayPolicy::strict`] (`docs/protocol.md` §5.4) a robot followed on another side
    /// is refused however old that ray is; another robot's ray only if it reaches farther; the
    /// followed robot's shorter ray within the switch time; and the rule may refuse a ray as a
    /// replay ([`Rule::is_replay`]).
    ///
    /// Returns `true` if it was taken.
    fn take_ray(&mut self, now: Instant, from: Sector, ray: &Ray, sender: Tag) -> bool {
        let core = &self.core;
        let longest = core.longest_cycle();
        let switch_after = longest.saturating_mul(u64::from(SENDER_SWITCH_CYCLES));
        let i = usize::from(from.index());
        let fits = ray.sector == from && ray.sectors == core.params.sectors;
        let strict = self.rule.policy().strict;
        let elsewhere = core.rays.iter().enumerate().any(|(j, h)| {
            j != i
                && h.is_some_and(|h| h.sender == sender && (now - h.at <= switch_after || strict))
        });
        let Some(slot) = core.rays.get(i) else {
            return false;
        };
        let follows = match slot {
            Some(held) => {
                let older = strict && now - held.at <= switch_after && ray.robots < held.ray.robots;
                (held.sender == sender && !older)
                    || ray.robots > held.ray.robots
                    || (now - held.at > switch_after && !strict)
            }
            None => true,
        };
        if fits && !elsewhere && follows && !self.rule.is_replay(core, now, from, ray, sender) {
            self.rule.ray_taken(core, now, from, ray, sender);
            if let Some(slot) = self.core.rays.get_mut(i) {
                *slot = Some(Held {
                    ray: *ray,
                    at: now,
                    sender,
                });
            }
            self.core.stats.rays = self.core.stats.rays.wrapping_add(1);
            true
        } else {
            let stats = &mut self.core.stats;
            stats.rays_refused = stats.rays_refused.wrapping_add(1);
            false
        }
    }
}
