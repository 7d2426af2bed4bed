//! The simulator's calendar of the agents' due seconds ([`Schedule`]), the engine's
//! (`crate::sim`) event queue: the agents' timers in a timing wheel ([`Calendar`]), their
//! relays, and their rests when they are served ([`Schedule::serve_rests`]), in two queues.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use protocol::{Instant, WaveNode};

/// Seconds since the epoch of an instant (the simulation only uses whole seconds; a part of a
/// second counts as the next).
pub(crate) fn secs(t: Instant) -> u64 {
    t.as_millis().div_ceil(1000)
}

/// Every second at which an agent has something due: its relay (while active), the end of its
/// refractory time (while refractory, if rests are served) and its timers (the cycle's end, its
/// initiation). The timers sit in a [`Calendar`]; relays and rests, which come a fixed delay
/// after the call that made the agent active or refractory and are never cancelled, are queued
/// in the order they arose, which is the order of their seconds: most calls then touch no wheel
/// slot at all (a relay or a rest leaves the timers as they were).
pub(crate) struct Schedule {
    timers: Calendar,
    /// Per agent, the second of its timers' entry in `timers`.
    timer_s: Vec<u64>,
    /// Per agent, the instants last seen: a call that changed none of them costs no division.
    seen: Vec<Seen>,
    relays: Fifo,
    rests: Fifo,
    /// The second the wheel returned from the last [`Schedule::next_due`], if it did.
    wheel_due: Option<u64>,
    /// Whether rests are queued ([`Schedule::serve_rests`]).
    rests_on: bool,
}

impl Schedule {
    pub(crate) fn new(agents: usize) -> Self {
        Schedule {
            timers: Calendar::new(agents),
            timer_s: vec![u64::MAX; agents],
            seen: vec![
                Seen {
                    relay: Instant::MAX,
                    rest: Instant::MAX,
                    timers: Instant::MAX,
                };
                agents
            ],
            relays: Fifo::default(),
            rests: Fifo::default(),
            wheel_due: None,
            rests_on: false,
        }
    }

    /// Queues the ends of the agents' refractory times too (they are not unless asked): call
    /// it before any agent is tracked as refractory.
    pub(crate) fn serve_rests(&mut self) {
        self.rests_on = true;
    }

    /// Takes note of agent `i`'s first timers and whatever it has due as it starts (its wave
    /// node `w`).
    pub(crate) fn start(&mut self, i: usize, w: &WaveNode) {
        self.track(i, w, Instant::MAX);
    }

    /// Takes note of what agent `i`, whose wave node is `w`, has due after a call to it at
    /// `now`: a new relay or rest is queued, moved timers are moved in the wheel.
    ///
    /// The timers are read only if they were due by `now` (at or before it): they change only
    /// in a call at one of them (the three-phase agent never asks its node for an extra
    /// initiation, the one other way, [`WaveNode::timers_at`]), and most calls are a relay, a
    /// rest or a message heard.
    #[inline]
    pub(crate) fn track(&mut self, i: usize, w: &WaveNode, now: Instant) {
        let seen = &mut self.seen[i];
        // A relay or a rest is a new one when its instant is: an agent relays (and rests) once
        // per activation, at a later instant each time.
        if let Some(at) = w.relay_due()
            && at != seen.relay
        {
            seen.relay = at;
            self.relays.push(secs(at), i as u32);
        }
        if self.rests_on
            && let Some(at) = w.rest_due()
            && at != seen.rest
        {
            seen.rest = at;
            self.rests.push(secs(at), i as u32);
        }
        if seen.timers > now {
            debug_assert_eq!(
                seen.timers,
                w.timers_at(),
                "agent {i}'s timers moved unseen"
            );
            return;
        }
        let at = w.timers_at();
        if at != seen.timers {
            seen.timers = at;
            let s = secs(at);
            if s != self.timer_s[i] {
                self.timer_s[i] = s;
                self.timers.reschedule(s, i as u32);
            }
        }
    }

    /// [`track`](Self::track) after agent `i` (wave node `w`) heard a message and became
    /// active: only its relay is new (its timers were not due, or it was served first), due
    /// at second `s`.
    #[inline]
    pub(crate) fn track_heard(&mut self, i: usize, w: &WaveNode, s: u64) {
        debug_assert!(self.seen[i].timers == w.timers_at() && w.rest_due().is_none());
        if let Some(at) = w.relay_due() {
            debug_assert_eq!(secs(at), s);
            self.seen[i].relay = at;
            self.relays.push(s, i as u32);
        }
    }

    /// The first second at or before `until` at which anything is due, if any.
    pub(crate) fn next_due(&mut self, until: u64) -> Option<u64> {
        let queued = self.relays.first_second().min(self.rests.first_second());
        self.wheel_due = self.timers.next_due(until.min(queued), &self.timer_s);
        self.wheel_due.or((queued <= until).then_some(queued))
    }

    /// Appends the agents with something due at second `t` (the one
    /// [`next_due`](Self::next_due) returned) to `out` (empty), by increasing index, each once.
    pub(crate) fn take(&mut self, t: u64, out: &mut Vec<u32>) {
        debug_assert!(out.is_empty());
        if self.wheel_due == Some(t) {
            self.timers.take(t, out);
        }
        self.relays.take(t, out);
        self.rests.take(t, out);
        out.sort_unstable();
        // An agent with two things due then (a relay or rest and a timer) is there once.
        out.dedup();
    }
}

/// The instants of an agent's relay, rest and timers when it was last tracked.
#[derive(Clone, Copy)]
struct Seen {
    relay: Instant,
    rest: Instant,
    timers: Instant,
}

/// Agents queued by second, first in first out: a vector read from a cursor (cleared whenever
/// it has been read to the end, compacted when half of it has been read).
#[derive(Default)]
pub(crate) struct Fifo {
    items: Vec<(u64, u32)>,
    read: usize,
}

impl Fifo {
    /// The second of the first entry (`u64::MAX`: none).
    #[inline]
    pub(crate) fn first_second(&self) -> u64 {
        self.items.get(self.read).map_or(u64::MAX, |&(s, _)| s)
    }

    /// Queues agent `i` at second `s`, behind every entry of an earlier or the same second:
    /// at the back, unless a run's delays made an earlier second arise later.
    #[inline]
    pub(crate) fn push(&mut self, s: u64, i: u32) {
        if self.items.last().is_none_or(|&(b, _)| b <= s) {
            self.items.push((s, i));
        } else {
            let at = self.read + self.items[self.read..].partition_point(|&(b, _)| b <= s);
            self.items.insert(at, (s, i));
        }
    }

    /// Appends the agents queued at second `t` to `out` and removes them.
    #[inline]
    pub(crate) fn take(&mut self, t: u64, out: &mut Vec<u32>) {
        while let Some(&(s, i)) = self.items.get(self.read) {
            if s != t {
                debug_assert!(s > t, "a relay or rest of second {s} was missed at {t}");
                break;
            }
            out.push(i);
            self.read += 1;
        }
        if self.read == self.items.len() {
            self.items.clear();
            self.read = 0;
        } else if self.read > self.items.len() / 2 {
            self.items.drain(..self.read);
            self.read = 0;
        }
    }
}

/// The agents' timers: a wheel of one-second slots covering `[now, now + WHEEL)` and a heap
/// for anything later. Each agent is due at one second at most ([`Schedule`]'s `timer_s`, the
/// `scheduled` of the calls below): in the wheel it sits in its slot's list, linked through its per-agent `Links`
/// record, so moving it to another second is O(1) and allocates nothing. Heap entries are
/// checked against `scheduled` when the window reaches them (an agent moved since is skipped).
pub(crate) struct Calendar {
    /// Per slot, the first agent of its list ([`NONE`]: empty). A fixed-size array: a slot
    /// index (`t % WHEEL`) needs no bounds check.
    head: Box<[u32; Calendar::WHEEL as usize]>,
    /// Per slot, one bit: set while its list is not empty. [`Calendar::next_due`] finds the
    /// next busy second in a few words instead of stepping through the idle ones (most of a
    /// run's seconds: a wave lasts a few seconds, a cycle 1000).
    busy: Box<[u64; Calendar::WORDS]>,
    /// Per agent, its links (one record per agent: one bounds check per agent touched).
    links: Vec<Links>,
    in_wheel: usize,
    later: BinaryHeap<Reverse<(u64, u32)>>,
    now: u64,
}

/// Where an agent sits in the wheel.
#[derive(Clone, Copy)]
struct Links {
    /// The next agent in its slot's list.
    next: u32,
    /// The previous agent in its slot's list ([`NONE`]: it is the head).
    prev: u32,
    /// The slot whose list it is in ([`NONE`]: none).
    slot: u32,
}

/// No agent.
const NONE: u32 = u32::MAX;

impl Calendar {
    const WHEEL: u64 = 4096;
    const WORDS: usize = Self::WHEEL as usize / 64;

    pub(crate) fn new(agents: usize) -> Self {
        let unlinked = Links {
            next: NONE,
            prev: NONE,
            slot: NONE,
        };
        Calendar {
            head: Box::new([NONE; Self::WHEEL as usize]),
            busy: Box::new([0; Self::WORDS]),
            links: vec![unlinked; agents],
            in_wheel: 0,
            later: BinaryHeap::new(),
            now: 0,
        }
    }

    pub(crate) fn slot(t: u64) -> usize {
        (t % Self::WHEEL) as usize
    }

    /// Links agent `i` into the slot of second `t`, which the window covers.
    pub(crate) fn link(&mut self, t: u64, i: u32) {
        let s = Self::slot(t);
        let h = self.head[s];
        self.links[i as usize] = Links {
            next: h,
            prev: NONE,
            slot: s as u32,
        };
        if h != NONE {
            self.links[h as usize].prev = i;
        }
        self.head[s] = i;
        self.busy[s / 64] |= 1 << (s % 64);
        self.in_wheel += 1;
    }

    /// Moves agent `i` to second `t` (a second already passed counts as now), out of the
    /// slot it was in, if any.
    pub(crate) fn reschedule(&mut self, t: u64, i: u32) {
        let Links { next, prev, slot } = self.links[i as usize];
        if slot != NONE {
            if prev == NONE {
                let s = slot as usize % Self::WHEEL as usize;
                self.head[s] = next;
                if next == NONE {
                    self.busy[s / 64] &= !(1 << (s % 64));
                }
            } else {
                self.links[prev as usize].next = next;
            }
            if next != NONE {
                self.links[next as usize].prev = prev;
            }
            self.links[i as usize].slot = NONE;
            self.in_wheel -= 1;
        }
        let t = t.max(self.now);
        if t - self.now < Self::WHEEL {
            self.link(t, i);
        } else {
            self.later.push(Reverse((t, i)));
        }
    }

    /// Moves what the window now covers from the heap into the wheel: the entries still
    /// current (`scheduled[i] == t`) and not already linked.
    pub(crate) fn refill(&mut self, scheduled: &[u64]) {
        while let Some(&Reverse((t, i))) = self.later.peek() {
            if t - self.now >= Self::WHEEL {
                break;
            }
            self.later.pop();
            if scheduled[i as usize] == t && self.links[i as usize].slot == NONE {
                self.link(t, i);
            }
        }
    }

    /// The first second at or before `until` with an agent due, if any; the window moves up
    /// to it (past `until` if there is none there but the wheel holds a later one: as a walk
    /// second by second would leave it).
    pub(crate) fn next_due(&mut self, until: u64, scheduled: &[u64]) -> Option<u64> {
        loop {
            if self.now > until {
                return None;
            }
            if self.in_wheel == 0 {
                let &Reverse((t, _)) = self.later.peek()?;
                if t > until {
                    return None;
                }
                self.now = self.now.max(t);
                self.refill(scheduled);
                if self.in_wheel == 0 {
                    // Only stale heap entries up to here: look further.
                    continue;
                }
            }
            // The first busy second of the window, or the heap's first entry if earlier (the
            // window reaching it links it, if it is still current).
            let mut at = self.next_busy();
            if let Some(&Reverse((t, _))) = self.later.peek() {
                at = at.min(t.max(self.now));
            }
            if at > until {
                self.now = until.saturating_add(1);
                self.refill(scheduled);
                return None;
            }
            self.now = at;
            self.refill(scheduled);
            if self.head[Self::slot(self.now)] != NONE {
                return Some(self.now);
            }
            // A stale heap entry: look further.
            self.now += 1;
            self.refill(scheduled);
        }
    }

    /// The first second of the window whose slot is busy (`u64::MAX`: none).
    fn next_busy(&self) -> u64 {
        let start = Self::slot(self.now);
        let (w0, b0) = (start / 64, start % 64);
        // The first word from the current slot on, then the others, then the first word's
        // slots before the current one (the window wraps around the wheel).
        let mut word = self.busy[w0] & (u64::MAX << b0);
        for k in 0..=Self::WORDS {
            let w = (w0 + k) % Self::WORDS;
            if k > 0 {
                word = self.busy[w];
                if k == Self::WORDS {
                    word &= !(u64::MAX << b0);
                }
            }
            if word != 0 {
                let s = w * 64 + word.trailing_zeros() as usize;
                let ahead = (s + Self::WHEEL as usize - start) % Self::WHEEL as usize;
                return self.now + ahead as u64;
            }
        }
        u64::MAX
    }

    /// Appends the agents due at second `t` (the current second) to `out`, unlinked, the last
    /// queued first ([`Schedule::take`] sorts them).
    pub(crate) fn take(&mut self, t: u64, out: &mut Vec<u32>) {
        debug_assert_eq!(t, self.now);
        let s = Self::slot(t);
        let mut i = self.head[s];
        while i != NONE {
            out.push(i);
            let l = &mut self.links[i as usize];
            l.slot = NONE;
            self.in_wheel -= 1;
            i = l.next;
        }
        self.head[s] = NONE;
        self.busy[s / 64] &= !(1 << (s % 64));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg64;
    use std::collections::BTreeMap;

    /// The calendar against a plain model (each agent's second in a map): the same second
    /// found and the same agents taken, over random reschedules near and far (beyond the
    /// wheel, so through the heap, and back to seconds already passed), deadlines before and
    /// after the next due second, and long idle stretches that wrap the wheel around.
    #[test]
    fn the_wheel_finds_what_a_plain_map_finds() {
        const AGENTS: usize = 40;
        for seed in 0..40u64 {
            let mut rng = Pcg64::seed_from_u64(seed);
            let mut cal = Calendar::new(AGENTS);
            let mut scheduled = vec![u64::MAX; AGENTS];
            let mut now = 0u64;
            for _ in 0..400 {
                // Reschedule a few agents.
                for _ in 0..rng.random_range(0..4) {
                    let i = rng.random_range(0..AGENTS);
                    let ahead = match rng.random_range(0..4) {
                        0 => rng.random_range(0..3),
                        1 => rng.random_range(0..200),
                        2 => rng.random_range(0..3 * Calendar::WHEEL),
                        _ => Calendar::WHEEL + rng.random_range(0..3),
                    };
                    let t = now + ahead;
                    if scheduled[i] != t {
                        scheduled[i] = t;
                        cal.reschedule(t, i as u32);
                    }
                }
                let model: BTreeMap<u64, Vec<u32>> =
                    scheduled
                        .iter()
                        .enumerate()
                        .fold(BTreeMap::new(), |mut m, (i, &t)| {
                            if t != u64::MAX {
                                m.entry(t.max(now)).or_default().push(i as u32);
                            }
                            m
                        });
                let first = model.keys().next().copied();
                let until = now + rng.random_range(0..2 * Calendar::WHEEL);
                let want = first.filter(|&t| t <= until);
                let got = cal.next_due(until, &scheduled);
                assert_eq!(got, want, "seed {seed}: next due second up to {until}");
                match got {
                    Some(t) => {
                        let mut taken = Vec::new();
                        cal.take(t, &mut taken);
                        taken.sort_unstable();
                        assert_eq!(taken, model[&t], "seed {seed}: agents due at {t}");
                        for &i in &taken {
                            scheduled[i as usize] = u64::MAX;
                        }
                        now = t + 1;
                    }
                    None => now = until + 1,
                }
            }
        }
    }
}
