//! The simulator's calendar of the agents' due seconds ([`Calendar`]), the engine's
//! (`crate::sim`) event queue.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The agents' due seconds: a wheel of one-second slots covering `[now, now + WHEEL)` and a
/// heap for anything later. Each agent is due at one second at most (the simulator's
/// `scheduled`): in the wheel it sits in its slot's list, linked through per-agent `next`/`prev`
/// arrays, so moving it to another second is O(1) and allocates nothing. Heap entries are
/// checked against `scheduled` when the window reaches them (an agent moved since is skipped).
pub(crate) struct Calendar {
    /// Per slot, the first agent of its list ([`NONE`]: empty).
    head: Vec<u32>,
    /// Per agent, the next agent in its slot's list.
    next: Vec<u32>,
    /// Per agent, the previous agent in its slot's list ([`NONE`]: it is the head).
    prev: Vec<u32>,
    /// Per agent, the slot whose list it is in ([`NONE`]: none).
    slot_of: Vec<u32>,
    in_wheel: usize,
    later: BinaryHeap<Reverse<(u64, u32)>>,
    now: u64,
}

/// No agent.
const NONE: u32 = u32::MAX;

impl Calendar {
    const WHEEL: u64 = 4096;

    pub(crate) fn new(agents: usize) -> Self {
        Calendar {
            head: vec![NONE; Self::WHEEL as usize],
            next: vec![NONE; agents],
            prev: vec![NONE; agents],
            slot_of: vec![NONE; agents],
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
        self.next[i as usize] = h;
        self.prev[i as usize] = NONE;
        if h != NONE {
            self.prev[h as usize] = i;
        }
        self.head[s] = i;
        self.slot_of[i as usize] = s as u32;
        self.in_wheel += 1;
    }

    /// Moves agent `i` to second `t` (a second already passed counts as now), out of the
    /// slot it was in, if any.
    pub(crate) fn reschedule(&mut self, t: u64, i: u32) {
        let iu = i as usize;
        let slot = self.slot_of[iu];
        if slot != NONE {
            let (p, n) = (self.prev[iu], self.next[iu]);
            if p == NONE {
                self.head[slot as usize] = n;
            } else {
                self.next[p as usize] = n;
            }
            if n != NONE {
                self.prev[n as usize] = p;
            }
            self.slot_of[iu] = NONE;
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
            if scheduled[i as usize] == t && self.slot_of[i as usize] == NONE {
                self.link(t, i);
            }
        }
    }

    /// The first second at or before `until` with an agent due, if any; the window moves up
    /// to it.
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
            if self.head[Self::slot(self.now)] != NONE {
                return Some(self.now);
            }
            self.now += 1;
            self.refill(scheduled);
        }
    }

    /// Appends the agents due at second `t` (the current second) to `out`, unlinked, in the
    /// order they were queued (mostly by increasing index already).
    pub(crate) fn take(&mut self, t: u64, out: &mut Vec<u32>) {
        debug_assert_eq!(t, self.now);
        let s = Self::slot(t);
        let from = out.len();
        let mut i = self.head[s];
        while i != NONE {
            out.push(i);
            self.slot_of[i as usize] = NONE;
            self.in_wheel -= 1;
            i = self.next[i as usize];
        }
        self.head[s] = NONE;
        out[from..].reverse();
    }
}
