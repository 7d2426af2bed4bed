//! The wave paradigm (paper section 2.1, WOSPP): each robot is inactive, active or refractory,
//! as slime-mould cells are.
//!
//! ```text
//!              receive (inactive only)               relay_delay elapsed: transmit
//!   Inactive ──────────────────────────▶ Active ─────────────────────────────────▶ Refractory
//!      ▲   │ own initiation time, inactive: transmit at once                            │
//!      │   └────────────────────────────────────────────────────────────────────────▶ │
//!      └──────────────────────────── refractory time elapsed ◀──────────────────────────┘
//! ```
//!
//! Every robot initiates once per cycle (see [`InitiationPoint`]). An initiation that falls
//! while the robot is active or refractory is skipped and counted: the robot has just put its
//! reading into a passing wave, and a deferred initiation would start right behind that wave, in
//! step with its neighbours' deferred ones. A robot that has just transmitted ignores everything
//! for the refractory time, so its own wave (relayed back by the neighbours it activated, after
//! the relay delay) cannot re-activate it; [`crate::Params::validate`] enforces
//! `refractory > relay_delay`.
//!
//! [`WaveNode`] only keeps time; the variants decide what is sent. Drive it with
//! [`WaveNode::on_receive`] and [`WaveNode::poll`] until it returns `None`, and sleep until
//! [`WaveNode::poll_timeout`].

use rand::Rng;
use rand_core::RngCore;

use crate::params::{InitiationPoint, WaveParams};
use crate::time::{Duration, Instant};

/// The three states of the communication paradigm.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WaveState {
    /// Listening.
    Inactive,
    /// Heard a message; will relay it when the relay delay is over.
    Active,
    /// Has transmitted; deaf until the refractory time is over.
    Refractory,
}

/// Something the wave node did when polled; the variant acts on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WaveAction {
    /// Initiate a wave now: send a new message; the node is now refractory.
    Initiate,
    /// Relay the message received a relay delay ago now; the node is now refractory.
    Relay,
    /// The refractory time is over; the node is inactive again.
    Rested,
    /// A cycle ended (the count of cycles completed so far is given).
    CycleEnded(u32),
}

/// Counters kept by a [`WaveNode`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WaveStats {
    /// Waves initiated.
    pub initiated: u32,
    /// Messages relayed.
    pub relayed: u32,
    /// Messages ignored because the node was active or refractory.
    pub ignored: u32,
    /// Initiations skipped because the node was active or refractory at the time.
    pub skipped_initiations: u32,
}

/// The inactive/active/refractory state machine with its cycle clock.
#[derive(Clone, Debug)]
pub struct WaveNode {
    params: WaveParams,
    state: WaveState,
    relay_at: Instant,
    refractory_until: Instant,
    cycle_end: Instant,
    /// The cycle's initiation, while pending ([`Instant::MAX`]: none; "never" is never due,
    /// so a plain instant: [`WaveNode::timers_at`], read at every call, is two `min`s).
    initiate_at: Instant,
    /// An extra initiation asked for by the variant ([`WaveNode::initiate_extra`];
    /// [`Instant::MAX`]: none).
    extra_at: Instant,
    /// Cycle initiations skipped while busy and not yet made up by an extra initiation.
    owed: u32,
    /// Whether the last initiation that went out was an extra one.
    last_extra: bool,
    cycles: u32,
    stats: WaveStats,
}

impl WaveNode {
    /// A node that starts its first cycle at `now`, inactive. `params` should have passed
    /// [`crate::Params::validate`]; if not, the node still never panics.
    pub fn new(params: WaveParams, now: Instant, rng: &mut impl RngCore) -> Self {
        let mut n = WaveNode {
            params,
            state: WaveState::Inactive,
            relay_at: Instant::MAX,
            refractory_until: Instant::MAX,
            cycle_end: now,
            initiate_at: Instant::MAX,
            extra_at: Instant::MAX,
            owed: 0,
            last_extra: false,
            cycles: 0,
            stats: WaveStats::default(),
        };
        n.start_cycle(now, rng);
        n
    }

    /// The current state.
    pub fn state(&self) -> WaveState {
        self.state
    }

    /// Cycles completed so far.
    pub fn cycles(&self) -> u32 {
        self.cycles
    }

    /// The counters.
    pub fn stats(&self) -> &WaveStats {
        &self.stats
    }

    /// A message was heard at `now`. Returns `true` if it activated the node (it was
    /// inactive): the caller must prepare the relay, which [`poll`](Self::poll) asks for after
    /// the relay delay. Returns `false` if the node was active or refractory and ignores it.
    pub fn on_receive(&mut self, now: Instant) -> bool {
        if self.state != WaveState::Inactive {
            self.stats.ignored = self.stats.ignored.wrapping_add(1);
            return false;
        }
        self.state = WaveState::Active;
        self.relay_at = now + self.params.relay_delay;
        true
    }

    /// Asks for one initiation at `at`, beside the cycle's own: the variant has news that the
    /// passing waves do not carry. Like the cycle's, it is skipped if the node is active or
    /// refractory then. Replaces an extra initiation still pending; returns `false` (and does
    /// nothing) if `at` is `Instant::MAX`.
    pub fn initiate_extra(&mut self, at: Instant) -> bool {
        if at == Instant::MAX {
            return false;
        }
        self.extra_at = at;
        true
    }

    /// The cycle's own initiations skipped while the node was busy and not yet made up: each
    /// extra initiation that goes out ([`initiate_extra`](Self::initiate_extra)) makes up one.
    /// The variant decides whether to make them up (the fused variant does).
    pub fn owed(&self) -> u32 {
        self.owed
    }

    /// True if the last [`WaveAction::Initiate`] was an extra initiation, not the cycle's own.
    pub fn last_was_extra(&self) -> bool {
        self.last_extra
    }

    /// When the cycle under way ends.
    pub fn cycle_end(&self) -> Instant {
        self.cycle_end
    }

    /// The first instant, at or after `now`, at which the node is inactive again if nothing
    /// else arrives: `now` if it is inactive, the end of its refractory time otherwise (for an
    /// active node, after the relay it owes).
    pub fn free_at(&self, now: Instant) -> Instant {
        match self.state {
            WaveState::Inactive => now,
            WaveState::Active => self.relay_at + self.params.refractory,
            WaveState::Refractory => self.refractory_until,
        }
        .max(now)
    }

    /// When the pending extra initiation is due, if one is.
    pub fn extra_at(&self) -> Option<Instant> {
        (self.extra_at != Instant::MAX).then_some(self.extra_at)
    }

    /// True while an extra initiation is pending.
    pub fn extra_pending(&self) -> bool {
        self.extra_at != Instant::MAX
    }

    /// Forgets a pending extra initiation.
    pub fn cancel_extra(&mut self) {
        self.extra_at = Instant::MAX;
    }

    /// The next instant at which [`poll`](Self::poll) has something to do.
    #[inline]
    pub fn poll_timeout(&self) -> Instant {
        let t = self.timers_at();
        match self.state {
            WaveState::Active => t.min(self.relay_at),
            WaveState::Refractory => t.min(self.refractory_until),
            WaveState::Inactive => t,
        }
    }

    /// [`poll_timeout`](Self::poll_timeout) as it will be once the refractory time has ended:
    /// the earliest of the cycle's end and the pending initiations (for an active node, its
    /// relay too).
    #[inline]
    pub fn poll_timeout_rested(&self) -> Instant {
        let t = self.timers_at();
        match self.state {
            WaveState::Active => t.min(self.relay_at),
            _ => t,
        }
    }

    /// When the relay is due, while the node is active.
    #[inline]
    pub fn relay_due(&self) -> Option<Instant> {
        (self.state == WaveState::Active).then_some(self.relay_at)
    }

    /// When the refractory time ends, while the node is refractory.
    #[inline]
    pub fn rest_due(&self) -> Option<Instant> {
        (self.state == WaveState::Refractory).then_some(self.refractory_until)
    }

    /// The earliest of the cycle's end and the pending initiations: the node's timers, which
    /// change only in a [`poll`](Self::poll) at one of them and through
    /// [`initiate_extra`](Self::initiate_extra) and [`cancel_extra`](Self::cancel_extra)
    /// ([`poll_timeout`](Self::poll_timeout) is the earliest of these,
    /// [`relay_due`](Self::relay_due) and [`rest_due`](Self::rest_due)).
    #[inline]
    pub fn timers_at(&self) -> Instant {
        self.cycle_end.min(self.initiate_at).min(self.extra_at)
    }

    /// If the relay is the first transition due at `now` (the node is active, its relay is
    /// due by `now` and nothing else is due before it; ties go to the relay, as in
    /// [`poll`](Self::poll)), performs it and returns `true`, as `poll` would returning
    /// [`WaveAction::Relay`]; otherwise does nothing and returns `false`. Whatever else is due
    /// is left to `poll`.
    #[inline]
    pub fn relay_if_first_due(&mut self, now: Instant) -> bool {
        let at = self.relay_at;
        if self.state != WaveState::Active
            || at > now
            || at == Instant::MAX
            || at > self.timers_at()
        {
            return false;
        }
        self.stats.relayed = self.stats.relayed.wrapping_add(1);
        self.transmitted(at);
        true
    }

    /// True if the only transition due at `now` is the end of the refractory time: the node
    /// is refractory until `now` or earlier and nothing else is due by `now` (sufficient, not
    /// necessary: a late call may find a skipped initiation due before the rest).
    #[inline]
    pub fn only_rest_due(&self, now: Instant) -> bool {
        self.state == WaveState::Refractory
            && self.refractory_until <= now
            && self.poll_timeout_rested() > now
    }

    /// If [`only_rest_due`](Self::only_rest_due) at `now`, rests the node (as
    /// [`poll`](Self::poll) would, returning [`WaveAction::Rested`], with nothing left due
    /// after) and returns `true`; otherwise does nothing and returns `false`.
    #[inline]
    pub fn rest_if_only_due(&mut self, now: Instant) -> bool {
        let rest = self.only_rest_due(now);
        if rest {
            self.state = WaveState::Inactive;
        }
        rest
    }

    /// Performs the earliest transition due at or before `now`, if any. Call it until it
    /// returns `None`. Transitions are timed from when they were due, not from `now`, so a late
    /// caller gets the same schedule; ties go refractory end, relay, initiation, cycle end.
    ///
    /// [`Instant::MAX`] means "never" and is never due: a schedule that saturates at the end of
    /// time stops there (otherwise a cycle ending at `MAX` would start another one ending at
    /// `MAX`, and `poll(Instant::MAX)` would never return `None`).
    #[inline]
    pub fn poll(&mut self, now: Instant, rng: &mut impl RngCore) -> Option<WaveAction> {
        // Nothing due: the common case (every message an agent hears calls this first), and
        // `poll_timeout` is the earliest of the same candidates. Inlined; the rest is not.
        if self.poll_timeout() > now {
            return None;
        }
        self.poll_due(now, rng)
    }

    /// [`poll`](Self::poll) once something is due.
    fn poll_due(&mut self, now: Instant, rng: &mut impl RngCore) -> Option<WaveAction> {
        // The earliest due candidate; among equal instants the first in this order (refractory
        // end, relay, initiation, cycle end, extra initiation). Written out rather than as an
        // iterator chain: this is the simulator's hottest function.
        let mut best: Option<(u8, Instant)> = None;
        let mut consider = |which: u8, t: Option<Instant>| {
            if let Some(t) = t
                && t <= now
                && t != Instant::MAX
                && best.is_none_or(|(_, b)| t < b)
            {
                best = Some((which, t));
            }
        };
        consider(
            0,
            (self.state == WaveState::Refractory).then_some(self.refractory_until),
        );
        consider(
            1,
            (self.state == WaveState::Active).then_some(self.relay_at),
        );
        consider(2, Some(self.initiate_at));
        consider(3, Some(self.cycle_end));
        consider(4, Some(self.extra_at));
        let (which, at) = best?;
        Some(match which {
            0 => {
                self.state = WaveState::Inactive;
                WaveAction::Rested
            }
            1 => {
                self.stats.relayed = self.stats.relayed.wrapping_add(1);
                self.transmitted(at);
                WaveAction::Relay
            }
            2 | 4 => {
                if which == 2 {
                    self.initiate_at = Instant::MAX;
                } else {
                    self.extra_at = Instant::MAX;
                }
                if self.state != WaveState::Inactive {
                    self.stats.skipped_initiations = self.stats.skipped_initiations.wrapping_add(1);
                    if which == 2 {
                        self.owed = self.owed.saturating_add(1);
                    }
                    return self.poll(now, rng);
                }
                if which == 4 {
                    self.owed = self.owed.saturating_sub(1);
                }
                self.last_extra = which == 4;
                self.stats.initiated = self.stats.initiated.wrapping_add(1);
                self.transmitted(at);
                WaveAction::Initiate
            }
            3 => {
                self.cycles = self.cycles.wrapping_add(1);
                self.start_cycle(at, rng);
                WaveAction::CycleEnded(self.cycles)
            }
            _ => return None,
        })
    }

    fn transmitted(&mut self, at: Instant) {
        self.state = WaveState::Refractory;
        self.refractory_until = at + self.params.refractory;
    }

    /// Starts a cycle at `start`: draws its length and its initiation time.
    fn start_cycle(&mut self, start: Instant, rng: &mut impl RngCore) {
        let p = &self.params;
        let tick = p.tick.as_millis().max(1);
        let lo = (p.cycle - p.cycle_spread).as_millis() / tick;
        let hi = (p.cycle + p.cycle_spread).as_millis() / tick;
        let len_ticks = if hi > lo {
            rng.random_range(lo..=hi)
        } else {
            lo
        }
        .max(1);
        let len = Duration::from_millis(len_ticks.saturating_mul(tick));
        self.cycle_end = start + len;
        self.initiate_at = match p.initiation {
            InitiationPoint::EndOfCycle => self.cycle_end,
            InitiationPoint::Uniform => {
                start + Duration::from_millis(rng.random_range(1..=len_ticks).saturating_mul(tick))
            }
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;
    use rand_pcg::Pcg32;

    fn drain(n: &mut WaveNode, now: Instant, rng: &mut Pcg32) -> heapless::Vec<WaveAction, 8> {
        let mut v = heapless::Vec::new();
        while let Some(a) = n.poll(now, rng) {
            v.push(a).unwrap();
        }
        v
    }

    #[test]
    fn relays_after_the_delay_then_ignores_for_the_refractory_time() {
        let mut rng = Pcg32::new(1, 1);
        let p = Params::robots().wave;
        let mut n = WaveNode::new(p, Instant::ZERO, &mut rng);
        let t0 = Instant::from_secs(10);
        assert!(n.on_receive(t0));
        assert_eq!(n.state(), WaveState::Active);
        assert!(!n.on_receive(t0), "active nodes ignore");
        assert_eq!(n.poll_timeout(), t0 + p.relay_delay);
        assert!(drain(&mut n, Instant::from_millis(10_999), &mut rng).is_empty());
        assert_eq!(
            drain(&mut n, Instant::from_secs(11), &mut rng),
            [WaveAction::Relay]
        );
        assert_eq!(n.state(), WaveState::Refractory);
        assert!(
            !n.on_receive(Instant::from_secs(14)),
            "refractory nodes ignore"
        );
        assert_eq!(
            drain(&mut n, Instant::from_secs(15), &mut rng),
            [WaveAction::Rested]
        );
        assert!(n.on_receive(Instant::from_secs(15)));
        assert_eq!(n.stats().ignored, 2);
        assert_eq!(n.stats().relayed, 1);
    }

    #[test]
    fn the_short_ways_to_rest_and_relay_are_the_polls_ways() {
        // Random receptions and calls over many cycles: wherever `only_rest_due` holds, polling
        // gives exactly one `Rested` and the node that took the short way is the same node (it
        // may not hold where polling rests all the same: a late call whose skipped initiation
        // was due first); wherever `relay_if_first_due` relays, polling relays first and then
        // does the same.
        let mut rng = Pcg32::new(5, 9);
        let mut draw = Pcg32::new(6, 1);
        let mut p = Params::simulation_2d().wave;
        p.cycle = Duration::from_secs(60);
        let mut n = WaveNode::new(p, Instant::ZERO, &mut rng);
        let (mut t, mut shortcuts, mut relays) = (Instant::ZERO, 0, 0);
        for _ in 0..20_000 {
            t += Duration::from_secs(u64::from(draw.next_u32() % 4));
            if draw.next_u32().is_multiple_of(3) {
                n.on_receive(t);
            }
            let (mut short, mut short_rng) = (n.clone(), rng.clone());
            let (mut relay, mut relay_rng) = (n.clone(), rng.clone());
            let polled = drain(&mut n, t, &mut rng);
            if relay.relay_if_first_due(t) {
                relays += 1;
                let mut after = heapless::Vec::<_, 8>::new();
                after.push(WaveAction::Relay).unwrap();
                after.extend(drain(&mut relay, t, &mut relay_rng));
                assert_eq!(after, polled, "at {t:?}");
                assert_eq!(relay.poll_timeout(), n.poll_timeout());
                assert_eq!(relay.stats(), n.stats());
            }
            if short.rest_if_only_due(t) {
                shortcuts += 1;
                assert_eq!(polled, [WaveAction::Rested], "at {t:?}");
                assert_eq!(short.state(), n.state());
                assert_eq!(short.poll_timeout(), n.poll_timeout());
                assert!(drain(&mut short, t, &mut short_rng).is_empty());
            }
            if n.state() != WaveState::Refractory {
                assert_eq!(n.poll_timeout_rested(), n.poll_timeout());
            }
        }
        assert!(shortcuts > 1000, "{shortcuts}");
        assert!(relays > 1000, "{relays}");
    }

    #[test]
    fn robots_initiate_once_per_cycle_of_40_to_70_s() {
        let mut rng = Pcg32::new(7, 3);
        let mut n = WaveNode::new(Params::robots().wave, Instant::ZERO, &mut rng);
        let mut last = Instant::ZERO;
        let mut initiations = 0;
        for _ in 0..200 {
            let t = n.poll_timeout();
            for a in drain(&mut n, t, &mut rng) {
                if a == WaveAction::Initiate {
                    let gap = (t - last).as_millis();
                    assert!((40_000..=70_000).contains(&gap), "gap {gap} ms");
                    last = t;
                    initiations += 1;
                }
            }
        }
        assert!(initiations > 50);
        assert_eq!(n.stats().skipped_initiations, 0);
    }

    #[test]
    fn uniform_initiation_stays_inside_fixed_cycles() {
        let mut rng = Pcg32::new(9, 9);
        let p = Params::simulation_2d().wave;
        let mut n = WaveNode::new(p, Instant::ZERO, &mut rng);
        let mut per_cycle = [0u32; 20];
        while n.cycles() < 20 {
            let t = n.poll_timeout();
            let cycle = n.cycles() as usize;
            for a in drain(&mut n, t, &mut rng) {
                if a == WaveAction::Initiate {
                    assert_eq!(t.as_millis() % 1000, 0, "whole seconds");
                    per_cycle[cycle] += 1;
                }
                if let WaveAction::CycleEnded(c) = a {
                    assert_eq!(t, Instant::ZERO + p.cycle.saturating_mul(u64::from(c)));
                }
            }
        }
        assert_eq!(per_cycle, [1; 20]);
    }

    #[test]
    fn an_extra_initiation_fires_once_and_is_skipped_while_busy() {
        let mut rng = Pcg32::new(5, 5);
        let p = Params::robots().wave;
        let mut n = WaveNode::new(p, Instant::ZERO, &mut rng);
        assert!(!n.initiate_extra(Instant::MAX));
        assert!(n.initiate_extra(Instant::from_secs(10)));
        assert!(n.extra_pending());
        assert_eq!(n.poll_timeout(), Instant::from_secs(10));
        let acts = drain(&mut n, Instant::from_secs(10), &mut rng);
        assert_eq!(acts.as_slice(), [WaveAction::Initiate]);
        assert!(!n.extra_pending());
        assert_eq!(n.stats().initiated, 1);
        // While refractory (until 14 s) an extra initiation is skipped and counted.
        assert!(n.initiate_extra(Instant::from_secs(12)));
        let acts = drain(&mut n, Instant::from_secs(12), &mut rng);
        assert!(!acts.contains(&WaveAction::Initiate), "{acts:?}");
        assert_eq!(n.stats().skipped_initiations, 1);
        // Cancelled, it never fires.
        assert!(n.initiate_extra(Instant::from_secs(20)));
        n.cancel_extra();
        let acts = drain(&mut n, Instant::from_secs(30), &mut rng);
        assert!(!acts.contains(&WaveAction::Initiate), "{acts:?}");
    }

    #[test]
    fn initiation_while_refractory_is_skipped() {
        let mut rng = Pcg32::new(5, 5);
        let p = Params::robots().wave;
        let mut n = WaveNode::new(p, Instant::ZERO, &mut rng);
        let init = n.initiate_at;
        // Heard a message 2 s before its initiation: relays 1 s before, refractory across it.
        assert!(n.on_receive(init - Duration::from_secs(2)));
        let acts = drain(&mut n, init, &mut rng);
        assert_eq!(acts.first(), Some(&WaveAction::Relay));
        assert!(!acts.contains(&WaveAction::Initiate));
        assert_eq!(n.stats().skipped_initiations, 1);
    }

    #[test]
    fn a_late_caller_gets_the_same_schedule() {
        let p = Params::robots().wave;
        let mut a = WaveNode::new(p, Instant::ZERO, &mut Pcg32::new(3, 4));
        let mut b = a.clone();
        let mut ra = Pcg32::new(8, 8);
        let mut rb = ra.clone();
        // `a` polls at every deadline, `b` once every 100 s: same actions, same cycle ends.
        let mut acts_a = std::vec::Vec::new();
        while a.poll_timeout() < Instant::from_secs(2000) {
            let t = a.poll_timeout();
            acts_a.extend(drain(&mut a, t, &mut ra));
        }
        let mut acts_b = std::vec::Vec::new();
        let mut t = Instant::ZERO;
        while b.poll_timeout() < Instant::from_secs(2000) {
            t += Duration::from_secs(100);
            while b.poll_timeout() <= t && b.poll_timeout() < Instant::from_secs(2000) {
                acts_b.extend(b.poll(t, &mut rb));
            }
        }
        assert_eq!(acts_a, acts_b);
    }

    /// Regression (found by `fuzz/` target `fused_node`, also `three_phase`): a node whose
    /// schedule saturated at `Instant::MAX` found its cycle end due at `Instant::MAX` for ever,
    /// so `poll(Instant::MAX)`, and with it `handle_timeout`/`handle_message`, never returned.
    #[test]
    fn the_end_of_time_is_never_due() {
        let mut rng = Pcg32::new(3, 3);
        for p in [Params::robots().wave, Params::simulation_2d().wave] {
            let start = Instant::MAX - Duration::from_secs(131);
            let mut n = WaveNode::new(p, start, &mut rng);
            let mut actions = 0;
            while n.poll(Instant::MAX, &mut rng).is_some() {
                actions += 1;
                assert!(actions < 100, "poll(Instant::MAX) does not run dry");
            }
            assert_eq!(n.poll_timeout(), Instant::MAX, "nothing left but never");
            // A message heard at the end of time still activates the node; its relay, due
            // at `MAX`, never comes.
            if n.state() == WaveState::Inactive {
                assert!(n.on_receive(Instant::MAX));
                assert_eq!(n.poll(Instant::MAX, &mut rng), None);
                assert_eq!(n.state(), WaveState::Active);
            }
        }
        // The robots' cycles (40..70 s) still end before the end of time.
        let mut n = WaveNode::new(
            Params::robots().wave,
            Instant::MAX - Duration::from_secs(131),
            &mut rng,
        );
        while n.poll(Instant::MAX, &mut rng).is_some() {}
        assert!(n.cycles() >= 1);
    }
}
