//! Virtual time for a whole emulated run: one queue of deadlines for every robot, the medium
//! and the schedule. Without robots in the loop the timeline also runs the run's tasks
//! ([`Timeline::block_on`], `board::exec`) and its driver is [`drive_virtual`]; with them, a
//! single tokio timer drives it ([`drive`]).
//!
//! Under tokio's paused clock every `sleep` is a timer-wheel entry, every `now` a lock and a
//! subtraction; a robot wakes about twice per emulated second, so with a thousand robots those
//! dominated the run. Here a deadline is an entry in a wheel of one bucket per millisecond for
//! the next four seconds (a heap beyond), `now` a cell, and the one [`drive`]r task sleeps on
//! tokio's clock until the earliest deadline, sets `now` and wakes whoever waited for it.
//! Deadlines that fall on the same millisecond wake in the order they were set: a run is the
//! same run for the same seed.

use std::cell::{Cell, RefCell};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::future::Future;
use std::pin::Pin;
use std::rc::Rc;
use std::task::{Context, Poll, Waker};

use protocol::Instant;
use slab::Slab;

use super::exec::Executor;

/// Milliseconds ahead that a deadline goes straight into the [`Wheel`] (a robot's deadlines
/// are its next sample, a second ahead, its wave timers and its frames' airtimes); later ones
/// wait in a heap until they come within it.
const WHEEL_MS: u64 = 4096;

/// A wait on the timeline: its sequence number and slot in `Timeline::waiting`.
type Entry = (u64, usize);

/// The deadlines of the next [`WHEEL_MS`] milliseconds, one bucket per millisecond (bucket
/// `ms % WHEEL_MS`), each in the order its waits were set, with a bit per bucket that has any:
/// setting a deadline is a push, finding the next a scan of 64 words.
#[derive(Debug)]
struct Wheel {
    buckets: Vec<Vec<Entry>>,
    occupied: [u64; (WHEEL_MS / 64) as usize],
}

impl Default for Wheel {
    fn default() -> Self {
        Wheel {
            buckets: vec![Vec::new(); WHEEL_MS as usize],
            occupied: [0; (WHEEL_MS / 64) as usize],
        }
    }
}

impl Wheel {
    fn push(&mut self, ms: u64, e: Entry) {
        let b = (ms % WHEEL_MS) as usize;
        self.buckets[b].push(e);
        self.occupied[b / 64] |= 1 << (b % 64);
    }

    /// The first occupied bucket at or after `ms`, within `span` milliseconds: its millisecond.
    fn first(&self, ms: u64, span: u64) -> Option<u64> {
        let mut off = 0;
        while off < span {
            let b = ((ms + off) % WHEEL_MS) as usize;
            let bits = self.occupied[b / 64] >> (b % 64);
            if bits != 0 {
                let at = off + u64::from(bits.trailing_zeros());
                return (at < span).then_some(ms + at);
            }
            off += 64 - (b % 64) as u64;
        }
        None
    }

    /// Empties the bucket of `ms` into `into`. A bucket keeps room for a few waits, not that of
    /// its busiest millisecond (robots booted together sample on the same milliseconds: a
    /// thousand waits in one bucket every second, in a different bucket each time round the
    /// wheel, held 2 MB at 1000 robots).
    fn take(&mut self, ms: u64, into: &mut Vec<Entry>) {
        let b = (ms % WHEEL_MS) as usize;
        let bucket = &mut self.buckets[b];
        into.append(bucket);
        if bucket.capacity() > 64 {
            *bucket = Vec::new();
        }
        self.occupied[b / 64] &= !(1 << (b % 64));
    }
}

/// The deadlines of a run and its time now.
#[derive(Debug, Default)]
pub struct Timeline {
    now: Cell<Instant>,
    /// Deadlines waited for within [`WHEEL_MS`] of now. Entries whose wait ended early stay
    /// until their time and are skipped then.
    wheel: RefCell<Wheel>,
    /// Deadlines further away, earliest first, ties in the order they were set: `(deadline,
    /// sequence number, slot)`. They move into the wheel as time comes near them, before any
    /// wait for the same millisecond can be set there, so every millisecond's waits stay in the
    /// order they were set.
    far: RefCell<BinaryHeap<Reverse<(Instant, u64, usize)>>>,
    /// Who waits: `(sequence number, waker)`, by slot.
    waiting: RefCell<Slab<(u64, Waker)>>,
    next_seq: Cell<u64>,
    /// The deadline the driver sleeps until, and its waker (told when an earlier one is set).
    armed: Cell<Instant>,
    driver: RefCell<Option<Waker>>,
    /// The entries and wakers of one step, kept between steps.
    step: RefCell<Vec<Entry>>,
    due: RefCell<Vec<Waker>>,
    /// The run's tasks, when the timeline runs them itself ([`Timeline::block_on`]) instead of
    /// a tokio runtime.
    exec: Executor,
    /// Under [`Timeline::block_on`]: the time the driver's alarm last went off (a paused
    /// tokio clock's time).
    fired: Cell<Instant>,
    /// What else must settle before time moves on: robots in the loop on this clock
    /// ([`Gate`]).
    gate: RefCell<Option<Rc<dyn Gate>>>,
}

/// Something outside the run's tasks that time waits for (conservative lockstep): robots in
/// the loop whose clocks follow this one. When no task can run, [`Timeline::block_on`] asks it
/// to [`settle`](Gate::settle) before moving time on.
pub trait Gate: std::fmt::Debug {
    /// Called at `now` when no task can run: brings whatever is outside up to `now` (it may
    /// block the thread while it waits for it), handing what it learnt to the run's tasks.
    /// Returns `true` if it woke a task (time stays), `false` if time may move on.
    fn settle(&self, now: Instant) -> bool;
}

/// One wait on a [`Timeline`]: its slot and sequence number.
type Ticket = (usize, u64);

impl Timeline {
    /// The time now.
    pub fn now(&self) -> Instant {
        self.now.get()
    }

    /// The run queue of [`Timeline::block_on`].
    pub fn executor(&self) -> &Executor {
        &self.exec
    }

    /// Makes time wait for `gate` ([`Gate`]) from now on, in [`Timeline::block_on`].
    pub fn set_gate(&self, gate: Rc<dyn Gate>) {
        *self.gate.borrow_mut() = Some(gate);
    }

    /// Takes the gate away (the run ended; it may hold what holds this timeline).
    pub fn take_gate(&self) -> Option<Rc<dyn Gate>> {
        self.gate.borrow_mut().take()
    }

    /// [`Gate::settle`] of the gate set, if any: `true` if it woke a task.
    fn settle_gate(&self) -> bool {
        let gate = self.gate.borrow().clone();
        gate.is_some_and(|g| g.settle(self.now()))
    }

    /// No task can run: the driver's alarm goes off (a paused runtime's clock jumps to its
    /// timer). `false` if no alarm is set.
    fn fire(&self) -> bool {
        let at = self.armed.get();
        let driver = self.driver.borrow();
        match driver.as_ref() {
            Some(d) if at != Instant::MAX => {
                self.fired.set(at);
                d.wake_by_ref();
                true
            }
            _ => false,
        }
    }

    fn wait(&self, deadline: Instant, waker: &Waker) -> Ticket {
        let seq = self.next_seq.get();
        self.next_seq.set(seq + 1);
        let slot = self.waiting.borrow_mut().insert((seq, waker.clone()));
        let now = self.now.get().as_millis();
        // A `Sleep` waits only for deadlines after now; one that is not would wake at the
        // next millisecond.
        let ms = deadline.as_millis().max(now + 1);
        if ms - now < WHEEL_MS {
            self.wheel.borrow_mut().push(ms, (seq, slot));
        } else {
            self.far.borrow_mut().push(Reverse((deadline, seq, slot)));
        }
        if deadline < self.armed.get()
            && let Some(d) = self.driver.borrow().as_ref()
        {
            d.wake_by_ref();
        }
        (slot, seq)
    }

    fn rewake(&self, (slot, seq): Ticket, waker: &Waker) {
        if let Some(w) = self.waiting.borrow_mut().get_mut(slot)
            && w.0 == seq
            && !w.1.will_wake(waker)
        {
            w.1 = waker.clone();
        }
    }

    /// A wait ended before its time: it is skipped when its time comes (taking it out of its
    /// bucket at once cost 5 % more instructions at 1000 robots: robots booted together have
    /// their samples due in the same millisecond, a thousand waits in one bucket).
    fn cancel(&self, (slot, seq): Ticket) {
        let mut waiting = self.waiting.borrow_mut();
        if waiting.get(slot).is_some_and(|w| w.0 == seq) {
            waiting.remove(slot);
        }
    }

    /// The earliest deadline still waited for (dropping those whose wait ended), or `None`.
    fn next(&self) -> Option<Instant> {
        let waiting = self.waiting.borrow();
        let live = |&(seq, slot): &Entry| waiting.get(slot).is_some_and(|w| w.0 == seq);
        let now = self.now.get().as_millis();
        let mut wheel = self.wheel.borrow_mut();
        let mut from = now + 1;
        while let Some(ms) = wheel.first(from, now + WHEEL_MS - from) {
            let b = (ms % WHEEL_MS) as usize;
            if wheel.buckets[b].iter().any(live) {
                return Some(Instant::from_millis(ms));
            }
            // Only ended waits: forget them.
            wheel.buckets[b].clear();
            wheel.occupied[b / 64] &= !(1 << (b % 64));
            from = ms + 1;
        }
        let mut far = self.far.borrow_mut();
        while let Some(&Reverse((t, seq, slot))) = far.peek() {
            if live(&(seq, slot)) {
                return Some(t);
            }
            far.pop();
        }
        None
    }

    /// Time moves to `t` (the earliest deadline waited for, [`next`](Self::next)): wakes every
    /// wait due by then, in deadline and then set order.
    fn advance(&self, t: Instant) {
        let before = self.now.get().as_millis();
        let ms = t.as_millis();
        self.now.set(t);
        let mut step = std::mem::take(&mut *self.step.borrow_mut());
        let mut due = std::mem::take(&mut *self.due.borrow_mut());
        {
            let mut wheel = self.wheel.borrow_mut();
            let mut far = self.far.borrow_mut();
            let mut waiting = self.waiting.borrow_mut();
            // The wheel's milliseconds up to `t`, in order (only `t`'s can hold live waits).
            let span = ms.saturating_sub(before).min(WHEEL_MS - 1);
            let mut from = before + 1;
            while let Some(m) = wheel.first(from, before + 1 + span - from) {
                wheel.take(m, &mut step);
                from = m + 1;
            }
            // Or the far heap's, when `t` was beyond the wheel.
            while let Some(&Reverse((d, seq, slot))) = far.peek() {
                if d > t {
                    break;
                }
                far.pop();
                step.push((seq, slot));
            }
            for (seq, slot) in step.drain(..) {
                if waiting.get(slot).is_some_and(|w| w.0 == seq) {
                    due.push(waiting.remove(slot).1);
                }
            }
            // What comes within the wheel now moves into it.
            while let Some(&Reverse((d, seq, slot))) = far.peek() {
                if d.as_millis() - ms >= WHEEL_MS {
                    break;
                }
                far.pop();
                if waiting.get(slot).is_some_and(|w| w.0 == seq) {
                    wheel.push(d.as_millis(), (seq, slot));
                }
            }
        }
        for w in due.drain(..) {
            w.wake();
        }
        // The buffers are kept for the next time (no allocation per step).
        *self.step.borrow_mut() = step;
        *self.due.borrow_mut() = due;
    }
}

/// A wait until `deadline` on a timeline.
#[derive(Debug)]
pub struct Sleep {
    timeline: Rc<Timeline>,
    deadline: Instant,
    ticket: Option<Ticket>,
}

impl Sleep {
    /// Waits on `timeline` until `deadline` ([`Instant::MAX`]: for ever).
    pub fn until(timeline: Rc<Timeline>, deadline: Instant) -> Self {
        Sleep {
            timeline,
            deadline,
            ticket: None,
        }
    }
}

impl Future for Sleep {
    type Output = ();

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<()> {
        let this = self.get_mut();
        if this.timeline.now() >= this.deadline {
            if let Some(t) = this.ticket.take() {
                this.timeline.cancel(t);
            }
            return Poll::Ready(());
        }
        if this.deadline == Instant::MAX {
            return Poll::Pending;
        }
        match this.ticket {
            Some(t) => this.timeline.rewake(t, cx.waker()),
            None => this.ticket = Some(this.timeline.wait(this.deadline, cx.waker())),
        }
        Poll::Pending
    }
}

impl Drop for Sleep {
    fn drop(&mut self) {
        if let Some(t) = self.ticket.take() {
            self.timeline.cancel(t);
        }
    }
}

/// Drives `timeline` on tokio's clock (paused: virtual time), `epoch` being its zero: sleeps
/// until the earliest deadline, then moves time there and wakes its waiters. Runs for ever;
/// spawn it beside the run's tasks.
pub async fn drive(timeline: Rc<Timeline>, epoch: tokio::time::Instant) {
    let sleep = tokio::time::sleep_until(epoch);
    tokio::pin!(sleep);
    timeline.armed.set(Instant::MAX);
    std::future::poll_fn(|cx| {
        poll_drive(&timeline, cx, |next, armed, cx| {
            if next != armed {
                let at = epoch + std::time::Duration::from_millis(next.as_millis());
                sleep.as_mut().reset(at);
            }
            sleep.as_mut().poll(cx).is_ready()
        })
    })
    .await
}

/// Drives `timeline` when it runs its own tasks ([`Timeline::block_on`]): as [`drive`], with
/// the executor's alarm for tokio's timer, so that a run takes the same steps in the same
/// order as under tokio. Runs for ever; spawn it first.
pub async fn drive_virtual(timeline: Rc<Timeline>) {
    timeline.armed.set(Instant::MAX);
    std::future::poll_fn(|cx| poll_drive(&timeline, cx, |next, _, _| timeline.fired.get() >= next))
        .await
}

/// One poll of a driver: while the earliest deadline is due, time moves there; then the
/// driver waits. `due(next, armed, cx)` sets the driver's alarm for `next` (it was set for
/// `armed`) and says whether it went off.
fn poll_drive(
    timeline: &Timeline,
    cx: &mut Context<'_>,
    mut due: impl FnMut(Instant, Instant, &mut Context<'_>) -> bool,
) -> Poll<()> {
    loop {
        let Some(next) = timeline.next() else {
            timeline.armed.set(Instant::MAX);
            *timeline.driver.borrow_mut() = Some(cx.waker().clone());
            return Poll::Pending;
        };
        let armed = timeline.armed.replace(next);
        if due(next, armed, cx) {
            timeline.armed.set(Instant::MAX);
            timeline.advance(next);
            continue;
        }
        let mut d = timeline.driver.borrow_mut();
        if !d.as_ref().is_some_and(|w| w.will_wake(cx.waker())) {
            *d = Some(cx.waker().clone());
        }
        return Poll::Pending;
    }
}

impl Timeline {
    /// Runs `main` and every task spawned on this timeline's clock until `main` ends, time
    /// moving on whenever no task can run: a virtual-time run on the calling thread. Tasks
    /// left then are dropped. When nothing can run, robots in the loop catch up first (they
    /// may wake a task), then the driver's deadline is due.
    ///
    /// # Panics
    /// If `main` panics; or if nothing can run and nobody waits for a time (a run that would
    /// wait for ever).
    pub fn block_on<F: Future>(self: &Rc<Self>, main: F) -> F::Output {
        self.executor()
            .block_on(main, || self.settle_gate() || self.fire())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration as StdDuration;

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn waits_end_in_deadline_then_set_order_in_virtual_time() {
        let local = tokio::task::LocalSet::new();
        local
            .run_until(async {
                let tl = Rc::new(Timeline::default());
                let epoch = tokio::time::Instant::now();
                tokio::task::spawn_local(drive(tl.clone(), epoch));
                let order = Rc::new(RefCell::new(Vec::new()));
                for (name, ms) in [("c", 300), ("a", 100), ("b", 300), ("never", u64::MAX)] {
                    let (tl, order) = (tl.clone(), order.clone());
                    tokio::task::spawn_local(async move {
                        let t = if ms == u64::MAX {
                            Instant::MAX
                        } else {
                            Instant::from_millis(ms)
                        };
                        Sleep::until(tl.clone(), t).await;
                        order.borrow_mut().push((name, tl.now().as_millis()));
                    });
                }
                // A wait dropped before its time wakes nobody.
                let dropped = Sleep::until(tl.clone(), Instant::from_millis(200));
                let wall = std::time::Instant::now();
                Sleep::until(tl.clone(), Instant::from_millis(3_600_000)).await;
                drop(dropped);
                assert_eq!(tl.now(), Instant::from_millis(3_600_000));
                assert_eq!(
                    tokio::time::Instant::now() - epoch,
                    StdDuration::from_secs(3600)
                );
                assert!(wall.elapsed() < StdDuration::from_secs(5));
                assert_eq!(*order.borrow(), vec![("a", 100), ("c", 300), ("b", 300)]);
                // A deadline already past is no wait.
                Sleep::until(tl.clone(), Instant::from_millis(5)).await;
            })
            .await;
    }

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn an_earlier_deadline_set_later_rearms_the_driver() {
        let local = tokio::task::LocalSet::new();
        local
            .run_until(async {
                let tl = Rc::new(Timeline::default());
                tokio::task::spawn_local(drive(tl.clone(), tokio::time::Instant::now()));
                let late =
                    tokio::task::spawn_local(Sleep::until(tl.clone(), Instant::from_secs(100)));
                tokio::task::yield_now().await;
                Sleep::until(tl.clone(), Instant::from_secs(1)).await;
                assert_eq!(tl.now(), Instant::from_secs(1), "not at the later deadline");
                late.await.unwrap();
                assert_eq!(tl.now(), Instant::from_secs(100));
            })
            .await;
    }

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn far_deadlines_keep_their_order_as_they_come_near() {
        let local = tokio::task::LocalSet::new();
        local
            .run_until(async {
                let tl = Rc::new(Timeline::default());
                tokio::task::spawn_local(drive(tl.clone(), tokio::time::Instant::now()));
                let order = Rc::new(RefCell::new(Vec::new()));
                let at = |name: &'static str, ms: u64| {
                    let (tl, order) = (tl.clone(), order.clone());
                    tokio::task::spawn_local(async move {
                        Sleep::until(tl.clone(), Instant::from_millis(ms)).await;
                        order.borrow_mut().push((name, tl.now().as_millis()));
                    })
                };
                // Beyond the wheel when set: "far" and "farther" wait in the heap.
                let far = at("far", 5_000);
                let farther = at("farther", 3 * WHEEL_MS + 7);
                tokio::task::yield_now().await;
                // At 2 s, 5 s is within the wheel: "near" is set straight into it, after "far".
                Sleep::until(tl.clone(), Instant::from_secs(2)).await;
                let near = at("near", 5_000);
                // A wait set and ended before its time wakes nobody.
                drop(Sleep::until(tl.clone(), Instant::from_millis(4_000)));
                for h in [far, near, farther] {
                    h.await.unwrap();
                }
                assert_eq!(
                    *order.borrow(),
                    vec![
                        ("far", 5_000),
                        ("near", 5_000),
                        ("farther", 3 * WHEEL_MS + 7)
                    ]
                );
                // Time jumps over whole turns of the wheel to a lone far deadline.
                Sleep::until(tl.clone(), Instant::from_secs(1_000_000)).await;
                assert_eq!(tl.now(), Instant::from_secs(1_000_000));
            })
            .await;
    }
}
