//! The simulator's calendar of the agents' due seconds ([`Calendar`]), the engine's
//! (`crate::sim`) event queue.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The agents' due seconds: a wheel of one-second slots covering `[now, now + WHEEL)` and a
/// heap for anything later. Each agent is due at one second at most (the simulator's
/// `scheduled`): in the wheel it sits in its slot's list, linked through its per-agent `Links`
/// record, so moving it to another second is O(1) and allocates nothing. Heap entries are
/// checked against `scheduled` when the window reaches them (an agent moved since is skipped).
pub(crate) struct Calendar {
    /// Per slot, the first agent of its list ([`NONE`]: empty). A fixed-size array: a slot
    /// index (`t % WHEEL`) needs no bounds check.
    head: Box<[u32; Calendar::WHEEL as usize]>,
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

    pub(crate) fn new(agents: usize) -> Self {
        let unlinked = Links {
            next: NONE,
            prev: NONE,
            slot: NONE,
        };
        Calendar {
            head: Box::new([NONE; Self::WHEEL as usize]),
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
        self.in_wheel += 1;
    }

    /// Moves agent `i` to second `t` (a second already passed counts as now), out of the
    /// slot it was in, if any.
    pub(crate) fn reschedule(&mut self, t: u64, i: u32) {
        let Links { next, prev, slot } = self.links[i as usize];
        if slot != NONE {
            if prev == NONE {
                self.head[slot as usize % Self::WHEEL as usize] = next;
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
            let l = &mut self.links[i as usize];
            l.slot = NONE;
            self.in_wheel -= 1;
            i = l.next;
        }
        self.head[s] = NONE;
        out[from..].reverse();
    }
}
