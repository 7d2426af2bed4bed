//! The three-phase CIMAX of the paper's 2D simulations (section 2.2, Algs. 1–3).
//!
//! A negotiation period is `gather_cycles` of **information gathering** (Alg. 1: waves carry
//! readings; each activated agent appends its own, scores the message by its diversity and
//! stores that score under the exact bearing it was heard from), then **evaluation** (Alg. 2: the
//! preferred direction is the bearing with the largest average diversity; storage is emptied),
//! then `decide_cycles` of **collective decision** (Alg. 3: waves carry opinions; an activated
//! agent turns its own preferred bearing `diffusion` (10 %) of the shorter arc toward the received
//! one, then relays its own). At the end of the period the agent emits [`SimEvent::Decided`].
//!
//! Phases are counted in the agent's own cycles. Agents created at the same instant with no
//! cycle spread ([`crate::Params::simulation_2d`]) share cycle boundaries and so phases; a message
//! of the other phase (a wave straddling a boundary) is ignored and counted.
//!
//! An agent without a preferred bearing (it heard nothing, or nothing diverse) adopts the first
//! opinion it hears outright and relays "no opinion" until then.

use heapless::{Deque, Vec};
use rand_core::RngCore;

use crate::direction::{Opposite, turn_toward_by, wrap_positive};
use crate::diversity::{Diversity, Pool, Variance};
use crate::message::push_evicting;
use crate::params::{ParamError, Params};
use crate::time::Instant;
use crate::wave::{WaveAction, WaveNode, WaveState, WaveStats};
use crate::weights::DirectionWeights;

const EVENT_QUEUE: usize = 8;
const OUTBOX: usize = 2;

/// The phase an agent is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Phase {
    /// Information gathering (Alg. 1).
    Gathering,
    /// Collective decision by opinion diffusion (Alg. 3).
    Deciding,
}

/// A message of the three-phase variant, up to `N` readings of type `R` long (`f32`: one
/// quantity; `[f32; K]`: K quantities at once). In memory only: the 2D simulator hands messages
/// to neighbours directly.
#[derive(Clone, Debug, PartialEq)]
pub enum SimMessage<const N: usize, R = f32> {
    /// Gathering: the readings along the wave's path, oldest first (full: oldest dropped).
    Readings(Vec<R, N>),
    /// Deciding: the sender's preferred bearing in radians, if it has one.
    Opinion(Option<f32>),
}

/// Something the simulator may record.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SimEvent {
    /// The wave state changed.
    State(WaveState),
    /// Evaluation ended the gathering phase with this preferred bearing and this diversity of
    /// all readings stored (the paper's `V_k`).
    Evaluated {
        /// Preferred bearing, radians in `[0, 2π)`.
        preferred: Option<f32>,
        /// The measure over every reading in every stored message ([`Diversity::Pool`]).
        diversity: f32,
    },
    /// The negotiation period ended; the agent's decision is its preferred bearing.
    Decided {
        /// Periods completed so far.
        period: u32,
        /// Decided bearing, radians in `[0, 2π)`.
        bearing: Option<f32>,
    },
}

/// Counters kept by a [`ThreePhaseAgent`] beyond its wave node's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AgentStats {
    /// Messages scored or diffused.
    pub accepted: u32,
    /// Messages of the other phase, ignored.
    pub wrong_phase: u32,
    /// Messages whose bearing found no free direction slot (more than `S` neighbours).
    pub slots_full: u32,
    /// Transmissions or events dropped because they were not polled in time.
    pub lost: u32,
}

impl<const N: usize, R: Copy> SimMessage<N, R> {
    /// Makes `self` a copy of `src` in place: only `src`'s readings are copied, not the whole
    /// `N`-reading buffer a move or a clone carries.
    pub fn copy_from(&mut self, src: &Self) {
        match (self, src) {
            (SimMessage::Readings(d), SimMessage::Readings(s)) => {
                d.clear();
                // Cannot fail: both hold up to `N`.
                let _ = d.extend_from_slice(s);
            }
            // Written field by field: a clone of the whole enum would copy the `N`-reading
            // buffer an opinion does not use.
            (d, SimMessage::Opinion(o)) => *d = SimMessage::Opinion(*o),
            (d, s) => *d = s.clone(),
        }
    }

    /// An empty message of `phase` (no readings, no opinion), written in place.
    fn reset(&mut self, phase: Phase) {
        match (phase, &mut *self) {
            (Phase::Gathering, SimMessage::Readings(r)) => r.clear(),
            (Phase::Gathering, m) => *m = SimMessage::Readings(Vec::new()),
            (Phase::Deciding, m) => *m = SimMessage::Opinion(None),
        }
    }
}

/// An agent's message buffers: the message to relay (while one is pending) and the messages
/// sent and not yet polled, oldest first, up to [`OUTBOX`]; a send into a full outbox drops the
/// oldest. A message holds up to `N` readings, and copying it whole at every hop was most of
/// the 2D simulator's time: a relay turns the relay buffer itself into the message sent (its
/// index goes into the outbox) and takes a free buffer as the next relay buffer, so a hop
/// copies a message once, as it is heard. `OUTBOX + 1` buffers: the outbox's and the relay's.
#[derive(Clone, Debug)]
struct Buffers<M> {
    bufs: [M; OUTBOX + 1],
    /// The relay buffer's index.
    relay: u8,
    /// The outbox: buffer indices, a ring of `OUTBOX` from `head`, `len` long.
    out: [u8; OUTBOX],
    head: u8,
    len: u8,
}

impl<M> Buffers<M> {
    fn new(mut empty: impl FnMut() -> M) -> Self {
        Buffers {
            bufs: core::array::from_fn(|_| empty()),
            relay: 0,
            out: [0; OUTBOX],
            head: 0,
            len: 0,
        }
    }

    /// The outbox's `k`-th oldest buffer index.
    fn out_at(&self, k: u8) -> u8 {
        self.out[usize::from(self.head + k) % OUTBOX]
    }

    /// A buffer that is neither the relay buffer nor in the outbox: there is one unless the
    /// outbox is full and the relay buffer is not in it.
    fn free(&self) -> u8 {
        let mut used = 1u8 << self.relay;
        for k in 0..self.len {
            used |= 1 << self.out_at(k);
        }
        debug_assert!(used.count_ones() as usize <= OUTBOX, "no free buffer");
        // The lowest clear bit.
        (!used).trailing_zeros() as u8
    }

    /// Drops the oldest message if the outbox is full; `true` if one was.
    fn make_room(&mut self) -> bool {
        let full = usize::from(self.len) == OUTBOX;
        if full {
            self.head = ((usize::from(self.head) + 1) % OUTBOX) as u8;
            self.len -= 1;
        }
        full
    }

    /// Puts buffer `b` at the back of the outbox (which has room).
    fn push(&mut self, b: u8) {
        let i = (usize::from(self.head) + usize::from(self.len)) % OUTBOX;
        self.out[i] = b;
        self.len += 1;
    }

    /// The oldest message's buffer index, removed from the outbox (the buffer is reused by a
    /// later send).
    fn pop_front(&mut self) -> Option<u8> {
        if self.len == 0 {
            return None;
        }
        let b = self.out[usize::from(self.head)];
        self.head = ((usize::from(self.head) + 1) % OUTBOX) as u8;
        self.len -= 1;
        Some(b)
    }

    fn relay(&mut self) -> &mut M {
        &mut self.bufs[usize::from(self.relay)]
    }
}

/// A message an agent sent, as [`ThreePhaseAgent::poll_transmit_sent`] hands it out: read it
/// with [`ThreePhaseAgent::sent`] until the agent's next call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sent(u8);

/// Key of a direction slot: the bearing's bits, so "the same neighbour" is exact equality.
type BearingKey = u32;

fn key(bearing: f32) -> BearingKey {
    // wrap_positive maps -0.0 to 0.0 and every NaN to NaN; fold NaNs into one key.
    let b = wrap_positive(bearing);
    if b.is_nan() { u32::MAX } else { b.to_bits() }
}

/// One agent of the 2D simulations. `N` readings per message, `S` distinct bearings per period,
/// readings of type `R` (one quantity, `f32`, unless a [`crate::diversity::PerQuantity`]
/// measure scores several at once). Sans-IO, with the same call order as
/// [`crate::fused::FusedNode`].
#[derive(Clone, Debug)]
pub struct ThreePhaseAgent<
    D: Diversity<R> = Variance,
    const N: usize = 32,
    const S: usize = 16,
    R: Copy + Default = f32,
> {
    params: Params,
    diversity: D,
    wave: WaveNode,
    /// `wave.poll_timeout()` as of the end of the last call: the wave node changes only in this
    /// agent's calls, and every call (and the simulator's check of whom to serve) reads it.
    next: Instant,
    reading: R,
    phase: Phase,
    phase_cycles: u16,
    periods: u32,
    weights: DirectionWeights<BearingKey, S>,
    stored: D::Pool,
    /// Whether `stored` is filled ([`ThreePhaseAgent::set_pooling`]).
    pooling: bool,
    last_diversity: f32,
    preferred: Option<f32>,
    decision: Option<f32>,
    /// The message to relay (while `pending`) and the messages sent, not yet polled.
    buffers: Buffers<SimMessage<N, R>>,
    pending: bool,
    events: Deque<SimEvent, EVENT_QUEUE>,
    /// Whether events are queued ([`ThreePhaseAgent::set_events`]).
    events_on: bool,
    stats: AgentStats,
    opposite: Opposite,
}

impl<const N: usize, const S: usize> ThreePhaseAgent<Variance, N, S> {
    /// An agent using the variance, starting its first cycle (gathering) at `now`.
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate.
    pub fn new(params: Params, now: Instant, rng: &mut impl RngCore) -> Result<Self, ParamError> {
        Self::with_diversity(params, Variance, now, rng)
    }
}

impl<D: Diversity<R>, const N: usize, const S: usize, R: Copy + Default>
    ThreePhaseAgent<D, N, S, R>
{
    /// An agent with a custom diversity measure.
    ///
    /// # Errors
    /// The [`ParamError`] if `params` do not validate.
    pub fn with_diversity(
        params: Params,
        diversity: D,
        now: Instant,
        rng: &mut impl RngCore,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        let stored = diversity.pool();
        let wave = WaveNode::new(params.wave, now, rng);
        Ok(ThreePhaseAgent {
            params,
            diversity,
            next: wave.poll_timeout(),
            wave,
            reading: R::default(),
            phase: Phase::Gathering,
            phase_cycles: 0,
            periods: 0,
            weights: DirectionWeights::default(),
            stored,
            pooling: true,
            last_diversity: 0.0,
            preferred: None,
            decision: None,
            buffers: Buffers::new(|| SimMessage::Opinion(None)),
            pending: false,
            events: Deque::new(),
            events_on: true,
            stats: AgentStats::default(),
            opposite: Opposite::CounterClockwise,
        })
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The current preferred bearing (radians in `[0, 2π)`).
    pub fn preferred(&self) -> Option<f32> {
        self.preferred
    }

    /// The bearing decided at the end of the last period.
    pub fn decision(&self) -> Option<f32> {
        self.decision
    }

    /// The directions heard from in the current gathering phase: bearing (radians), average
    /// diversity and message count, for diagnosis.
    pub fn weights(&self) -> impl Iterator<Item = (f32, f32, u32)> + '_ {
        self.weights
            .iter()
            .map(|(k, w, n)| (f32::from_bits(k), w, n))
    }

    /// The diversity `V_k` of all readings stored in the last completed gathering phase.
    pub fn diversity(&self) -> f32 {
        self.last_diversity
    }

    /// Periods completed.
    pub fn periods(&self) -> u32 {
        self.periods
    }

    /// The wave state.
    pub fn state(&self) -> WaveState {
        self.wave.state()
    }

    /// Sets what the agent does with an opinion exactly opposite its own during diffusion
    /// ([`Opposite`]; counter-clockwise unless set).
    pub fn set_opposite(&mut self, rule: Opposite) {
        self.opposite = rule;
    }

    /// Whether [`SimEvent`]s are queued for [`poll_event`](Self::poll_event) (they are unless
    /// turned off): a caller that never looks at them turns them off and saves the work.
    /// Nothing else changes; with events off, none is queued, so none is lost.
    pub fn set_events(&mut self, on: bool) {
        self.events_on = on;
    }

    /// Whether the readings of scored messages are pooled for the observer's diversity `V_k`
    /// ([`diversity`](Self::diversity), [`SimEvent::Evaluated`]); they are unless turned off.
    /// Off, `V_k` is 0 from the next evaluation on and nothing else changes: the pool plays no
    /// part in the agent's decisions, and a caller that never reads it saves the work.
    pub fn set_pooling(&mut self, on: bool) {
        self.pooling = on;
    }

    /// Counters.
    pub fn stats(&self) -> &AgentStats {
        &self.stats
    }

    /// The wave node: its state and when each of its transitions is due.
    pub fn wave(&self) -> &WaveNode {
        &self.wave
    }

    /// The wave node's counters.
    pub fn wave_stats(&self) -> &WaveStats {
        self.wave.stats()
    }

    /// A new (noisy) reading of the quantity X (or quantities) at the agent's position.
    pub fn handle_reading(&mut self, reading: R) {
        self.reading = reading;
    }

    /// A message heard at `now` from a neighbour at `bearing` (radians). Whatever was due up
    /// to `now` is done first. Returns `true` if the agent was activated by it.
    pub fn handle_message(
        &mut self,
        now: Instant,
        bearing: f32,
        msg: &SimMessage<N, R>,
        rng: &mut impl RngCore,
    ) -> bool {
        self.handle_timeout(now, rng);
        let in_phase = matches!(
            (self.phase, msg),
            (Phase::Gathering, SimMessage::Readings(r)) if !r.is_empty()
        ) || matches!((self.phase, msg), (Phase::Deciding, SimMessage::Opinion(_)));
        if !in_phase {
            self.stats.wrong_phase = self.stats.wrong_phase.wrapping_add(1);
            return false;
        }
        if !self.wave.on_receive(now) {
            return false;
        }
        // Inactive, the node's next timeout was its timers'; now its relay is due too.
        if let Some(relay) = self.wave.relay_due() {
            self.next = self.next.min(relay);
        }
        self.stats.accepted = self.stats.accepted.wrapping_add(1);
        self.push_event(SimEvent::State(WaveState::Active));
        match msg {
            SimMessage::Readings(r) => {
                let own = core::iter::once(self.reading);
                let v = self.diversity.measure_message(r, self.reading);
                if !self.weights.add(key(bearing), v) {
                    self.stats.slots_full = self.stats.slots_full.wrapping_add(1);
                }
                if self.pooling {
                    self.stored.push_all(r.iter().copied().chain(own));
                }
            }
            SimMessage::Opinion(Some(o)) if o.is_finite() => {
                self.preferred = Some(match self.preferred {
                    None => wrap_positive(*o),
                    Some(p) => turn_toward_by(p, *o, self.params.diffusion, self.opposite),
                });
            }
            SimMessage::Opinion(_) => {}
        }
        self.buffers.relay().copy_from(msg);
        self.pending = true;
        true
    }

    /// Does whatever is due at `now`.
    #[inline]
    pub fn handle_timeout(&mut self, now: Instant, rng: &mut impl RngCore) {
        // Nothing due (every message heard first calls this) or the end of a refractory time
        // alone (a third of all calls in the 2D simulator): the short ways, inlined, with the
        // same outcome as the loop's ([`WaveNode::rest_if_only_due`]).
        if self.next > now {
            return;
        }
        if self.wave.rest_if_only_due(now) {
            self.next = self.wave.poll_timeout();
            self.push_event(SimEvent::State(WaveState::Inactive));
            return;
        }
        self.handle_due(now, rng);
    }

    /// [`handle_timeout`](Self::handle_timeout) with more than a rest due (kept out of line
    /// so that the short ways inline).
    #[inline(never)]
    fn handle_due(&mut self, now: Instant, rng: &mut impl RngCore) {
        // A relay due first (another third of the calls) takes a short way too; whatever else
        // is due follows in the loop.
        if self.wave.relay_if_first_due(now) {
            self.relayed();
            // Most often nothing else is due: the loop's first `poll` would find so.
            let next = self.wave.poll_timeout();
            if next > now {
                self.next = next;
                return;
            }
        }
        while let Some(action) = self.wave.poll(now, rng) {
            match action {
                WaveAction::Initiate => self.send(false),
                WaveAction::Relay => self.relayed(),
                WaveAction::Rested => self.push_event(SimEvent::State(WaveState::Inactive)),
                WaveAction::CycleEnded(_) => self.end_cycle(),
            }
        }
        self.next = self.wave.poll_timeout();
    }

    /// The wave node has relayed: the message to relay goes out.
    fn relayed(&mut self) {
        if self.pending {
            self.pending = false;
            self.send(true);
        } else {
            // The phase changed while the agent was active: the relay is dropped (receivers
            // would ignore it) but the agent still goes refractory.
            self.push_event(SimEvent::State(WaveState::Refractory));
        }
    }

    /// When [`handle_timeout`](Self::handle_timeout) must be called next.
    #[inline]
    pub fn poll_timeout(&self) -> Instant {
        debug_assert_eq!(self.next, self.wave.poll_timeout());
        self.next
    }

    /// The next message to broadcast to every neighbour in range.
    pub fn poll_transmit(&mut self) -> Option<SimMessage<N, R>> {
        self.poll_transmit_sent().map(|b| self.sent(b).clone())
    }

    /// [`poll_transmit`](Self::poll_transmit) without a copy: the message stays in the agent,
    /// and [`sent`](Self::sent) reads it until the agent's next call (a later send may reuse
    /// its buffer).
    pub fn poll_transmit_sent(&mut self) -> Option<Sent> {
        self.buffers.pop_front().map(Sent)
    }

    /// The message `s` that [`poll_transmit_sent`](Self::poll_transmit_sent) returned, as
    /// long as the agent has not been called since.
    pub fn sent(&self, s: Sent) -> &SimMessage<N, R> {
        &self.buffers.bufs[usize::from(s.0) % (OUTBOX + 1)]
    }

    /// The next event.
    pub fn poll_event(&mut self) -> Option<SimEvent> {
        self.events.pop_front()
    }

    /// Queues the message to relay (`relay`) or a new one of the phase, with this agent's
    /// own contribution put in.
    #[inline]
    fn send(&mut self, relay: bool) {
        if self.buffers.make_room() {
            self.stats.lost = self.stats.lost.wrapping_add(1);
        }
        let b = if relay {
            // The relay buffer is the message sent; a free one is the next relay buffer.
            let b = self.buffers.relay;
            self.buffers.push(b);
            self.buffers.relay = self.buffers.free();
            b
        } else {
            let b = self.buffers.free();
            self.buffers.bufs[usize::from(b)].reset(self.phase);
            self.buffers.push(b);
            b
        };
        match &mut self.buffers.bufs[usize::from(b)] {
            SimMessage::Readings(r) => {
                // Room left (almost always): a plain push.
                if let Err(x) = r.push(self.reading) {
                    push_evicting(r, x);
                }
            }
            SimMessage::Opinion(o) => *o = self.preferred,
        }
        self.push_event(SimEvent::State(WaveState::Refractory));
    }

    fn end_cycle(&mut self) {
        self.phase_cycles = self.phase_cycles.saturating_add(1);
        match self.phase {
            Phase::Gathering if self.phase_cycles >= self.params.gather_cycles => {
                // Alg. 2: evaluation, then empty storage.
                self.preferred = self
                    .weights
                    .heaviest()
                    .map(f32::from_bits)
                    .filter(|b| b.is_finite());
                self.last_diversity = self.stored.value();
                self.weights.clear();
                self.stored = self.diversity.pool();
                self.push_event(SimEvent::Evaluated {
                    preferred: self.preferred,
                    diversity: self.last_diversity,
                });
                self.phase = Phase::Deciding;
                self.phase_cycles = 0;
                self.pending = false;
            }
            Phase::Deciding if self.phase_cycles >= self.params.decide_cycles => {
                self.periods = self.periods.wrapping_add(1);
                self.decision = self.preferred;
                self.push_event(SimEvent::Decided {
                    period: self.periods,
                    bearing: self.decision,
                });
                self.phase = Phase::Gathering;
                self.phase_cycles = 0;
                self.pending = false;
            }
            _ => {}
        }
    }

    fn push_event(&mut self, e: SimEvent) {
        if !self.events_on {
            return;
        }
        if self.events.is_full() {
            self.events.pop_front();
            self.stats.lost = self.stats.lost.wrapping_add(1);
        }
        let _ = self.events.push_back(e);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::Duration;
    use core::f32::consts::PI;
    use rand_pcg::Pcg32;

    type Agent = ThreePhaseAgent<Variance, 8, 4>;

    fn readings(xs: &[f32]) -> SimMessage<8> {
        SimMessage::Readings(Vec::from_slice(xs).unwrap())
    }

    fn agent() -> (Agent, Pcg32) {
        let mut rng = Pcg32::new(2, 2);
        (
            Agent::new(Params::simulation_2d(), Instant::ZERO, &mut rng).unwrap(),
            rng,
        )
    }

    /// Runs the agent alone until `pred` holds for an event; returns that event.
    fn run_until(a: &mut Agent, rng: &mut Pcg32, pred: impl Fn(&SimEvent) -> bool) -> SimEvent {
        loop {
            let t = a.poll_timeout();
            a.handle_timeout(t, rng);
            while a.poll_transmit().is_some() {}
            while let Some(e) = a.poll_event() {
                if pred(&e) {
                    return e;
                }
            }
        }
    }

    #[test]
    fn gathers_evaluates_diffuses_and_decides() {
        let (mut a, mut rng) = agent();
        a.handle_reading(0.0);
        let east = 0.0;
        let west = PI;
        let t = Instant::from_secs(1);
        let r = &mut rng;
        assert!(a.handle_message(t, east, &readings(&[5.0, 5.0]), r));
        assert!(
            !a.handle_message(t, west, &readings(&[0.0]), r),
            "active: ignored"
        );
        let t = t + Duration::from_secs(20);
        assert!(a.poll_transmit().is_none());
        assert!(a.handle_message(t, west, &readings(&[0.0, 0.0]), r));
        assert!(
            matches!(a.poll_transmit(), Some(SimMessage::Readings(_))),
            "first relay"
        );
        a.handle_timeout(t + Duration::from_secs(1), r);
        match a.poll_transmit() {
            Some(SimMessage::Readings(r)) => assert_eq!(r.as_slice(), &[0.0, 0.0, 0.0]),
            other => panic!("{other:?}"),
        }
        let e = run_until(&mut a, &mut rng, |e| {
            matches!(e, SimEvent::Evaluated { .. })
        });
        let SimEvent::Evaluated {
            preferred,
            diversity,
        } = e
        else {
            unreachable!()
        };
        assert_eq!(preferred, Some(east));
        // Stored readings: 5, 5, 0 and 0, 0, 0: variance 50/9.
        assert!((diversity - 50.0 / 9.0).abs() < 1e-4, "{diversity}");
        assert_eq!(a.phase(), Phase::Deciding);

        // Opinion diffusion: 10 % of the shorter arc toward 90°.
        let t = Instant::from_secs(1010);
        let r = &mut rng;
        assert!(
            !a.handle_message(t, west, &readings(&[1.0]), r),
            "wrong phase"
        );
        assert!(a.handle_message(t, west, &SimMessage::Opinion(Some(PI / 2.0)), r));
        assert!((a.preferred().unwrap() - PI / 20.0).abs() < 1e-5);
        a.handle_timeout(t + Duration::from_secs(1), &mut rng);
        assert_eq!(a.poll_transmit(), Some(SimMessage::Opinion(a.preferred())));
        let e = run_until(&mut a, &mut rng, |e| matches!(e, SimEvent::Decided { .. }));
        assert_eq!(
            e,
            SimEvent::Decided {
                period: 1,
                bearing: a.preferred()
            }
        );
        assert_eq!(a.phase(), Phase::Gathering);
        assert_eq!(a.stats().wrong_phase, 1);
    }

    /// An agent nobody polls keeps its last two messages whole, the relays built in its relay
    /// buffer included, and counts the one it dropped; polling without a copy reads the same.
    #[test]
    fn an_unpolled_agent_keeps_its_last_two_messages_and_counts_the_dropped() {
        let (mut a, mut rng) = agent();
        // Only the messages count as lost.
        a.set_events(false);
        let init = a.wave().timers_at();
        assert!(
            init < a.wave().cycle_end() - Duration::from_secs(100),
            "{init:?}"
        );
        a.handle_reading(7.0);
        a.handle_timeout(init, &mut rng);
        for (k, x) in [1.0, 2.0, 3.0].into_iter().enumerate() {
            let heard = init + Duration::from_secs(20 * (k as u64 + 1));
            a.handle_reading(10.0 * x);
            assert!(a.handle_message(heard, 0.0, &readings(&[x]), &mut rng));
            a.handle_timeout(heard + Duration::from_secs(1), &mut rng);
        }
        assert_eq!(a.stats().lost, 2, "the initiation and the first relay");
        let b = a.poll_transmit_sent().unwrap();
        assert_eq!(a.sent(b), &readings(&[2.0, 20.0]));
        assert_eq!(a.poll_transmit(), Some(readings(&[3.0, 30.0])));
        assert_eq!(a.poll_transmit_sent(), None);
        // The buffers stay apart: a fourth relay leaves the polled third as it was.
        a.handle_reading(40.0);
        let heard = init + Duration::from_secs(80);
        assert!(a.handle_message(heard, 0.0, &readings(&[4.0]), &mut rng));
        a.handle_timeout(heard + Duration::from_secs(1), &mut rng);
        assert_eq!(a.poll_transmit(), Some(readings(&[4.0, 40.0])));
        assert_eq!(a.stats().lost, 2);
    }

    #[test]
    fn an_entropy_agent_prefers_the_most_varied_bins_and_pools_them() {
        use crate::diversity::Entropy;
        let mut rng = Pcg32::new(2, 2);
        let params = Params::simulation_2d();
        let mut a = ThreePhaseAgent::<Entropy, 8, 4>::with_diversity(
            params,
            Entropy { bin: 1.0 },
            Instant::ZERO,
            &mut rng,
        )
        .unwrap();
        a.handle_reading(0.0);
        let (east, west) = (0.0, PI);
        let t = Instant::from_secs(1);
        // East: 5, 5, 5 and the own 0: 0.811 bits. West 20 s later: 0, 1, 2, 0: 1.5 bits.
        // The variance would prefer east (4.69 against 0.69).
        assert!(a.handle_message(t, east, &readings(&[5.0, 5.0, 5.0]), &mut rng));
        let t = t + Duration::from_secs(20);
        assert!(a.handle_message(t, west, &readings(&[0.0, 1.0, 2.0]), &mut rng));
        let (preferred, diversity) = loop {
            let t = a.poll_timeout();
            a.handle_timeout(t, &mut rng);
            while a.poll_transmit().is_some() {}
            if let Some(SimEvent::Evaluated {
                preferred,
                diversity,
            }) = core::iter::from_fn(|| a.poll_event())
                .find(|e| matches!(e, SimEvent::Evaluated { .. }))
            {
                break (preferred, diversity);
            }
        };
        assert_eq!(preferred, Some(west));
        // Stored: bins 5 ×3, 0 ×3, 1, 2: 2 · 3/8 · log2(8/3) + 2 · 1/8 · 3 = 1.8113 bits.
        assert!((diversity - 1.811_278).abs() < 1e-5, "{diversity}");
        assert_eq!(a.diversity(), diversity);
    }

    #[test]
    fn an_agent_of_two_quantities_scores_both() {
        use crate::diversity::PerQuantity;
        let mut rng = Pcg32::new(2, 2);
        let mut a = ThreePhaseAgent::<PerQuantity<Variance, 2>, 8, 4, [f32; 2]>::with_diversity(
            Params::simulation_2d(),
            PerQuantity(Variance),
            Instant::ZERO,
            &mut rng,
        )
        .unwrap();
        a.handle_reading([0.0, 0.0]);
        let (east, west) = (0.0, PI);
        let msg = |xs: &[[f32; 2]]| SimMessage::Readings(Vec::from_slice(xs).unwrap());
        // East varies in the first quantity (1, 0, 0: variance 2/9), west in the second
        // (3, 0, 0: variance 2): west is preferred.
        let t = Instant::from_secs(1);
        assert!(a.handle_message(t, east, &msg(&[[1.0, 0.0], [0.0, 0.0]]), &mut rng));
        let t = t + Duration::from_secs(20);
        assert!(a.handle_message(t, west, &msg(&[[0.0, 3.0], [0.0, 0.0]]), &mut rng));
        assert_eq!(
            a.poll_transmit(),
            Some(msg(&[[1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])),
            "the first relay carries the own reading"
        );
        let diversity = loop {
            let t = a.poll_timeout();
            a.handle_timeout(t, &mut rng);
            while a.poll_transmit().is_some() {}
            if let Some(SimEvent::Evaluated {
                preferred,
                diversity,
            }) = core::iter::from_fn(|| a.poll_event())
                .find(|e| matches!(e, SimEvent::Evaluated { .. }))
            {
                assert_eq!(preferred, Some(west));
                break diversity;
            }
        };
        // Stored: first quantity 1, 0, 0, 0, 0, 0 (5/36); second 0, 0, 0, 3, 0, 0 (45/36).
        assert!((diversity - 50.0 / 36.0).abs() < 1e-5, "{diversity}");
    }

    #[test]
    fn an_agent_without_opinion_adopts_the_first_it_hears() {
        let (mut a, mut rng) = agent();
        run_until(&mut a, &mut rng, |e| {
            matches!(e, SimEvent::Evaluated { .. })
        });
        assert_eq!(a.preferred(), None);
        let t = Instant::from_secs(1100);
        assert!(a.handle_message(t, 1.0, &SimMessage::Opinion(Some(-PI / 2.0)), &mut rng));
        assert!((a.preferred().unwrap() - 1.5 * PI).abs() < 1e-5);
    }

    #[test]
    fn more_bearings_than_slots_are_counted_not_fatal() {
        let (mut a, mut rng) = agent();
        let mut t = Instant::from_secs(1);
        for i in 0..6u8 {
            let bearing = f32::from(i) * 0.5;
            assert!(a.handle_message(t, bearing, &readings(&[1.0, 2.0]), &mut rng));
            t += Duration::from_secs(11);
        }
        assert_eq!(a.stats().slots_full, 2);
        assert_eq!(a.stats().accepted, 6);
        let heard: std::vec::Vec<(f32, f32, u32)> = a.weights().collect();
        assert_eq!(heard.len(), 4);
        // Readings 1, 2 and the agent's own 0: variance 2/3.
        assert_eq!(heard[1], (0.5, 2.0 / 3.0, 1));
    }
}
