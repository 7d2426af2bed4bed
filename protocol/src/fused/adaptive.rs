//! [`DecisionRule::Adaptive`], the rule the Nucleo ships: a robot decides as soon as its
//! evidence is settled, the negotiation period being only the cap (`docs/protocol.md` §5.4).
//!
//! After every reception, cycle end and listening window's end the robot tallies its votes into
//! a candidate and shows it once it is informed (every sector heard, or its first listening
//! window of a longest cycle over), every side is known to its end (a [`Ray::closed`] ray, or
//! an empty side: silent for a whole window), the robots without a vote could not overturn it,
//! and, for a change of what it shows, every side has confirmed it. Its rays carry its vote
//! only once it is informed, its preference clear and every side it does not prefer known to
//! its end; a side is scored by its latest ray; news its relays cannot carry back goes out in
//! extra initiations as soon as it is free; stale (replayed) rays are refused.

use rand_core::RngCore;

use super::rule::{Cause, RayPolicy, Rule};
use super::{Core, TIE_TOLERANCE};
use crate::direction::{MAX_SECTORS, Sector};
use crate::message::{Level, Ray, Tag};
use crate::params::{DecisionRule, Params};
use crate::time::{Duration, Instant};
use crate::wave::WaveState;

/// How many times every other direction's diversity the preferred one's must be for the
/// robot to count the preference as a vote (`Adaptive::is_clear`). Four, not two: the ratio of
/// two sides' sensor noise alone exceeds 2 often enough (a robot amid a uniform stretch of a
/// long line) that noisy levels tipped ties (`docs/protocol.md` §5.4).
const CLEAR_RATIO: f32 = 4.0;

/// Extra initiations carrying news (`Adaptive::spread_news`) a robot may ask for per cycle,
/// per sector.
const NEWS_PER_SECTOR: u8 = 4;

/// Rays taken per sector remembered (`Adaptive::is_replay`).
const RAY_HISTORY: usize = 4;

/// What of a ray the rule remembers: who sent it, how many robots it counts and their votes,
/// hashed (FNV-1a), and when it was taken. Digest 0 (never a ray's, [`ray_digest`]) marks an
/// empty place.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Seen {
    digest: u32,
    at: Instant,
}

/// The digest of the decision-relevant part of a ray from `sender`: robots and votes.
fn ray_digest(ray: &Ray, sender: Tag) -> u32 {
    let bytes = [sender.index(), ray.robots, u8::from(ray.closed)]
        .into_iter()
        .chain(ray.votes);
    crate::hash::fnv1a_32(bytes).max(1)
}

/// The adaptive rule's state (module docs).
#[derive(Clone, Debug)]
pub struct Adaptive {
    /// The reading in the last ray this robot sent.
    sent_reading: Level,
    /// A whole listening window (a longest cycle) has passed since the node started: every
    /// neighbour in range has initiated once.
    listened: bool,
    /// Sectors a ray was ever taken from (bit `i` for sector `i`).
    heard: u8,
    /// Sectors any message was heard from in the listening window under way (one longest
    /// cycle, the first starting when the node starts).
    heard_window: u8,
    /// Sectors nothing was heard from in the last whole window, nor since
    /// ([`is_empty_side`](Self::is_empty_side)).
    silent: u8,
    /// When the listening window under way ends.
    window_end: Instant,
    /// The direction the held votes give now ([`Core::tally`]).
    candidate: Option<Sector>,
    /// The sectors whose rays confirmed `candidate` after it was last set.
    confirmed: u8,
    /// Since when the candidate has differed from the shown decision.
    differs_since: Option<Instant>,
    /// Per sector, the last rays taken (digest and time), newest last.
    seen: [[Seen; RAY_HISTORY]; MAX_SECTORS],
    /// The vote the last ray sent carried, and the sectors whose ray, as last sent, is still
    /// current: it carried that vote and the held ray's robots and votes (the others are news
    /// to send, [`spread_news`](Self::spread_news)).
    last_vote: Option<Sector>,
    fresh_rays: u8,
    /// The sector whose ray a pending extra initiation carries.
    trigger: Option<Sector>,
    /// Extra initiations asked for in the cycle under way.
    triggered_in_cycle: u8,
    /// The sector `spread_news` looks at first (the one after its last).
    next_news: u8,
}

impl Rule for Adaptive {
    /// The first listening window starts with the node.
    fn start(params: &Params, now: Instant) -> Self {
        Adaptive {
            sent_reading: Level::default(),
            listened: false,
            heard: 0,
            heard_window: 0,
            silent: 0,
            window_end: now + params.longest_cycle(),
            candidate: None,
            confirmed: 0,
            differs_since: None,
            seen: [[Seen::default(); RAY_HISTORY]; MAX_SECTORS],
            last_vote: None,
            fresh_rays: 0,
            trigger: None,
            triggered_in_cycle: 0,
            next_news: 0,
        }
    }

    fn decides(&self) -> DecisionRule {
        DecisionRule::Adaptive
    }

    /// Every field set: a side is its latest ray, scored even while busy; without a ray the
    /// hops stand for it; rays are taken strictly.
    fn policy(&self) -> RayPolicy {
        RayPolicy {
            latest_ray_scores: true,
            hops_stand_for_side: true,
            strict: true,
        }
    }

    /// The end of the listening window under way.
    fn poll_timeout(&self) -> Instant {
        self.window_end
    }

    /// A reading that moved, since the last ray this robot sent, by more than the spread of
    /// what it sees (the squared change above the preferred side's diversity, that side's ray
    /// with the own reading: a light switched, not sensor noise; ratios only, §5.6) makes
    /// every ray it sends news (docs/protocol.md §5.4, at its next reception or timeout).
    fn on_reading(&mut self, core: &Core, reading: Level) {
        let d = f32::from(reading.0.abs_diff(self.sent_reading.0));
        if core
            .pref
            .and_then(|p| core.weights.weight(p))
            .is_some_and(|w| d * d > w)
        {
            self.fresh_rays = 0;
        }
    }

    fn heard_from(&mut self, from: Sector) {
        self.heard_window |= 1 << from.index();
        self.silent &= !(1 << from.index());
    }

    /// A listening window ended: the sectors silent all through it are empty. Those that just
    /// became so change the ray sent that way (now closed): news, unless an initiation due now
    /// carries it. The robot may now see to the end of every side.
    fn begin_timeout(&mut self, core: &Core, now: Instant) -> bool {
        if now < self.window_end {
            return false;
        }
        let silent = core.all_sectors() & !self.heard_window;
        self.fresh_rays &= !(silent & !self.silent);
        self.silent = silent;
        self.heard_window = 0;
        self.listened = true;
        let next = self.window_end + core.longest_cycle();
        self.window_end = next.max(now + Duration::from_millis(1));
        true
    }

    fn react(&mut self, core: &mut Core, now: Instant, cause: Cause, rng: &mut impl RngCore) {
        match cause {
            Cause::Reception(confirming) => self.settle(core, now, confirming),
            Cause::Timeout => self.settle(core, now, None),
            Cause::Initiated => {}
            Cause::CycleEnded => {
                // Evidence of the last cycle only (and a one-message prior), so that a changed
                // environment shows within a cycle or two.
                core.weights.shrink_to_prior();
                self.settle(core, now, None);
                self.triggered_in_cycle = 0;
            }
        }
        self.spread_news(core, now, rng);
    }

    /// The cap: rays not refreshed within the period are forgotten, and a robot that showed
    /// nothing during the period, or whose candidate has differed from what it shows for a
    /// whole period, decides by the votes held.
    fn end_of_period(&mut self, core: &mut Core, now: Instant) {
        core.expire_rays(now);
        core.count_period();
        let period = core
            .longest_cycle()
            .saturating_mul(u64::from(core.params.negotiation_cycles));
        let stuck = self.differs_since.is_some_and(|t| now - t >= period);
        if core.decision.is_none() || stuck {
            self.candidate = core.decide_by_votes();
            self.differs_since = None;
        }
    }

    fn initiation_sector(&mut self) -> Option<Sector> {
        self.trigger.take()
    }

    /// The vote (`vote`: the preference once informed, clear and every other side known to its
    /// end); a ray the robot starts toward an empty side is closed. Remembers what the ray
    /// sent carries, for the news (`spread_news`).
    fn ray_to_send(&mut self, core: &Core, sector: Sector) -> (Option<Sector>, bool) {
        let vote = self.vote(core);
        if vote != self.last_vote {
            self.last_vote = vote;
            self.fresh_rays = 0;
        }
        self.fresh_rays |= 1 << sector.index();
        self.sent_reading = core.reading;
        (vote, self.is_empty_side(core, sector.index()))
    }

    /// A ray that goes back in time: other than the held one, and the same sender, robots and
    /// votes as one of the last `RAY_HISTORY` (4) distinct rays taken from that sector within a
    /// longest cycle.
    fn is_replay(&self, core: &Core, now: Instant, from: Sector, ray: &Ray, sender: Tag) -> bool {
        let i = usize::from(from.index());
        let digest = ray_digest(ray, sender);
        let longest = core.longest_cycle();
        core.rays
            .get(i)
            .is_some_and(|h| h.is_some_and(|h| ray_digest(&h.ray, h.sender) != digest))
            && self.seen.get(i).is_some_and(|seen| {
                seen.iter()
                    .any(|s| s.digest == digest && now - s.at <= longest)
            })
    }

    fn ray_taken(&mut self, core: &Core, now: Instant, from: Sector, ray: &Ray, sender: Tag) {
        let i = usize::from(from.index());
        let digest = ray_digest(ray, sender);
        if let Some(seen) = self.seen.get_mut(i) {
            // Only changes take a place: a neighbour's ray is mostly the same.
            if seen[RAY_HISTORY - 1].digest != digest {
                crate::message::shift_out(seen, 1);
            }
            seen[RAY_HISTORY - 1] = Seen { digest, at: now };
        }
        let changed = core.rays.get(i).is_none_or(|slot| {
            slot.is_none_or(|h| {
                h.ray.robots != ray.robots || h.ray.votes != ray.votes || h.ray.closed != ray.closed
            })
        });
        if changed {
            self.fresh_rays &= !(1 << from.index());
        }
        self.heard |= 1 << from.index();
    }
}

impl Adaptive {
    /// Nothing lies in `sector`: no ray is held from it, and nothing was heard from it for a
    /// whole listening window of a longest cycle (within which every neighbour initiates; the
    /// first window starts with the node), nor since.
    fn is_empty_side(&self, core: &Core, sector: u8) -> bool {
        self.silent & (1 << sector) != 0
            && core
                .rays
                .get(usize::from(sector))
                .is_some_and(Option::is_none)
    }

    /// The sectors below K in which the robot knows every robot (bit `i` for sector `i`): the
    /// ray it holds from there is [`closed`](Ray::closed), or the side is empty
    /// ([`is_empty_side`](Self::is_empty_side)).
    fn known_to_the_end(&self, core: &Core) -> u8 {
        let mut known = 0u8;
        for s in 0..core.params.sectors.min(MAX_SECTORS as u8) {
            let closed = match core.rays.get(usize::from(s)) {
                Some(Some(h)) => h.ray.closed,
                _ => self.is_empty_side(core, s),
            };
            known |= u8::from(closed) << s;
        }
        known
    }

    /// What this robot votes in the rays it sends: its preference, only once it
    /// [`is_informed`](Self::is_informed), the preference is [`is_clear`](Self::is_clear) and
    /// every side it does not prefer is [known to its end](Self::known_to_the_end) (a
    /// preference formed from one side of a line, between near-equal diversities, or before a
    /// border could be ruled out on the other sides, is no vote yet).
    fn vote(&self, core: &Core) -> Option<Sector> {
        core.pref.filter(|p| {
            let others = core.all_sectors() & !(1 << p.index());
            self.is_informed(core)
                && is_clear(core)
                && self.known_to_the_end(core) & others == others
        })
    }

    /// True once the robot has taken a ray from each of its K sectors, or its first listening
    /// window (a whole longest cycle since it started) is over: by then every neighbour in
    /// range initiated once; a robot at the swarm's edge never hears its outward sides.
    fn is_informed(&self, core: &Core) -> bool {
        self.heard == core.all_sectors() || self.listened
    }

    /// When an initiation carrying news goes: as soon as the robot is free (inactive: now;
    /// else once its relay and refractory time are over), plus a random wait of 1 tick to a
    /// quarter of `relay_delay` (in ticks), so that neighbours freed by the same wave do not
    /// send together.
    fn news_initiation_at(core: &Core, now: Instant, rng: &mut impl RngCore) -> Instant {
        let w = &core.params.wave;
        let tick = w.tick.as_millis().max(1);
        let spread = u32::try_from(w.relay_delay.as_millis() / 4 / tick)
            .unwrap_or(u32::MAX)
            .max(1);
        let jitter =
            Duration::from_millis(u64::from(1 + rng.next_u32() % spread).saturating_mul(tick));
        core.wave.free_at(now) + jitter
    }

    /// If the ray this robot would send for some side is news (its own vote, or the robots or
    /// votes of the ray it holds, changed since it last sent that ray) and the neighbours that
    /// ray serves exist (a ray is held from the opposite sector), asks for one extra initiation
    /// carrying it ([`news_initiation_at`](Self::news_initiation_at)), at most
    /// [`NEWS_PER_SECTOR`] · K per cycle and one at a time. A relay carries news only ahead of
    /// its wave; the robots behind it would otherwise wait for this robot's next initiation. A
    /// pending extra initiation is asked for again while the robot is busy (a wave that arrived
    /// since would make it skip the first), for when it is free.
    fn spread_news(&mut self, core: &mut Core, now: Instant, rng: &mut impl RngCore) {
        let k = core.params.sectors.clamp(1, MAX_SECTORS as u8);
        if self.triggered_in_cycle >= k.saturating_mul(NEWS_PER_SECTOR)
            || (core.wave.extra_pending() && core.wave.state() == WaveState::Inactive)
        {
            return;
        }
        let vote = self.vote(core);
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
            current & (1 << s) == 0 && core.rays.get(opposite).is_some_and(|h| h.is_some())
        });
        let Some(s) = needed.and_then(Sector::new) else {
            return;
        };
        let at = Self::news_initiation_at(core, now, rng);
        if core.wave.initiate_extra(at) {
            self.trigger = Some(s);
            self.next_news = (s.index() + 1) % k;
            self.triggered_in_cycle += 1;
        }
    }

    /// After a reception (`confirming`: the sector whose ray was just taken), a cycle's or a
    /// window's end. The held votes give a candidate direction; each taken ray that gives the
    /// same candidate again confirms it for its sector. The robot shows the candidate once
    /// (`docs/protocol.md` §5.4)
    /// 1. it is informed ([`is_informed`](Self::is_informed)) and has a preference;
    /// 2. every side is [known to its end](Self::known_to_the_end) and it holds a ray;
    /// 3. the robots it holds without a vote could not overturn it, even all for one sector;
    /// 4. for a change of what it shows: every sector it holds a ray from confirmed the
    ///    candidate after it was last set.
    fn settle(&mut self, core: &mut Core, now: Instant, confirming: Option<Sector>) {
        let votes = core.votes();
        let candidate = core.tally(&votes);
        if candidate == core.decision {
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
            || candidate == core.decision
            || core.pref.is_none()
            || !self.is_informed(core)
            || self.known_to_the_end(core) != core.all_sectors()
        {
            return;
        }
        let mut held = 0u8;
        let mut undecided = 0u16;
        for (i, h) in core.rays.iter().enumerate() {
            if let Some(h) = h {
                held |= 1 << i;
                let voted: u16 = h.ray.votes.iter().map(|&v| u16::from(v)).sum();
                undecided = undecided.saturating_add(u16::from(h.ray.robots).saturating_sub(voted));
            }
        }
        // A first decision needs no confirmation; a change needs every side's.
        if held == 0 || (core.decision.is_some() && held & !self.confirmed != 0) {
            return;
        }
        let k = usize::from(core.params.sectors);
        let overturned = undecided > 0
            && (0..k).any(|s| {
                let mut v = votes;
                v[s] = v[s].saturating_add(undecided);
                core.tally(&v) != candidate
            });
        if overturned {
            return;
        }
        core.show(candidate, votes, core.periods.wrapping_add(1));
    }
}

/// True if the preferred direction's average diversity is positive and more than
/// [`CLEAR_RATIO`] times every other's (by more than [`TIE_TOLERANCE`]): a preference between
/// near-equal diversities (a robot amid a uniform stretch of a long line, whose rays do not
/// reach a border yet) is no vote. Only ratios: the test gives the same answer whatever the
/// sensor's unit, gain or offset.
fn is_clear(core: &Core) -> bool {
    let Some(p) = core.pref else { return false };
    let Some(best) = core.weights.weight(p) else {
        return false;
    };
    best > 0.0
        && core.weights.iter().all(|(d, w, _)| {
            d == p
                || (best > CLEAR_RATIO * w
                    && !crate::weights::within(best, CLEAR_RATIO * w, TIE_TOLERANCE))
        })
}

#[cfg(test)]
mod tests {
    use rand_pcg::Pcg32;

    use super::super::tests::{L, R, closed, hear, hear_ray, hop, node, ray, run_to_decision};
    use crate::direction::Sector;
    use crate::fused::{Event, FusedNode, Reception};
    use crate::message::{Level, Message};
    use crate::params::DecisionRule;
    use crate::time::{Duration, Instant};

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
}
