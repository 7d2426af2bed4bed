//! The tasks of a virtual-time run, without tokio: a run queue beside the [`Timeline`](super::timeline::Timeline), time
//! moving on when the queue is empty.
//!
//! Under tokio a run was a `LocalSet` on a current-thread runtime with a paused clock, and the
//! timeline's driver slept on one tokio timer. At a thousand robots the runtime cost a sixth
//! of the instructions: task headers and their reference counts, the `LocalSet`'s queues, the
//! paused clock's park and its timer wheel, an aligned allocation per task. This executor keeps
//! tokio's order of events, so that a run stays the same run, byte for byte:
//!
//! - a woken task goes to the back of one queue, and a task woken while it runs goes there
//!   when its poll ends (tokio's `NOTIFIED` bit): wakes are handled in the order they came;
//! - a spawned task is queued at once;
//! - the main future is polled first, then at most [`TASKS_PER_TICK`] queued tasks, and
//!   again when it was woken or the queue was not emptied (the `LocalSet`'s `RunUntil`);
//! - when the queue is empty and the main future is not woken, the timeline's driver wakes
//!   with its deadline due (a paused runtime parks, moves its clock to the driver's timer and
//!   wakes it).
//!
//! A task that panics ends there and the run goes on, as under tokio; the panic is what its
//! [`Join`] gives.
//!
//! Wakers must be `Send` and `Sync`: each task's is an [`Arc`] that puts the task's number in a
//! list, which the executor reads after every poll. On the thread that runs the executor (every
//! wake of a run) that list is thread-local, so a wake takes no lock and no atomic operation;
//! a wake from elsewhere goes into a list behind a mutex. The executor also lends a task its
//! waker for a poll instead of cloning it (no reference count to raise and lower).

use std::any::Any;
use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::future::Future;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::pin::Pin;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll, Wake, Waker};

use slab::Slab;

/// Tasks polled between two polls of the main future (tokio's `LocalSet` runs 61).
pub const TASKS_PER_TICK: usize = 61;

/// The number a task's waker puts in the list: its slot and the slot's generation (a waker
/// kept after its task ended wakes nothing, not the task that took the slot).
type TaskId = (usize, u64);

/// The main future's number.
const MAIN: TaskId = (usize::MAX, 0);

/// Where a task is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// Waiting to be woken.
    Idle,
    /// In the queue.
    Queued,
    /// Being polled.
    Running,
    /// Being polled, and woken meanwhile: queued again when its poll ends.
    Notified,
}

/// A task: its future (out of the slot while it is polled), waker, state and generation.
struct Slot {
    future: Option<Pin<Box<dyn Future<Output = ()>>>>,
    /// Where the task's state is ([`Body::prefetch`]ed before the task runs).
    body: Body,
    waker: Waker,
    state: State,
    generation: u64,
}

/// Numbers executors, so that a waker tells whether its executor runs on the thread that wakes it.
static EXECUTORS: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// The number of the executor running on this thread (0: none).
    static RUNNING: Cell<u64> = const { Cell::new(0) };
    /// The wakes of that executor's tasks on this thread since it last looked, in wake order.
    static LOCAL_WAKES: RefCell<Vec<TaskId>> = const { RefCell::new(Vec::new()) };
}

/// Where a task's state lies in memory: an address and a length, only ever prefetched.
#[derive(Clone, Copy)]
struct Body {
    at: *const u8,
    len: usize,
}

impl Body {
    fn of<T: ?Sized>(state: &T) -> Self {
        Body {
            at: (state as *const T).cast(),
            len: std::mem::size_of_val(state),
        }
    }

    /// Asks the CPU to start loading the body's cache lines, and goes on at once: every other
    /// line, the second-level cache's adjacent-line prefetcher fetching its pair (as fast,
    /// measured, as every line, for half the instructions).
    #[allow(unsafe_code)]
    fn prefetch(self) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            let first = self.at as usize & !63;
            let end = self.at as usize + self.len;
            let mut line = first;
            while line < end {
                // SAFETY: a prefetch is a hint: it never faults and changes nothing a program
                // can observe, whatever the address (`_mm_prefetch` is `unsafe` only because
                // it takes a pointer). The body is a live task's future anyway.
                unsafe { _mm_prefetch::<_MM_HINT_T0>(self.at.wrapping_add(line - first).cast()) };
                line += 128;
            }
        }
    }
}

/// The tasks woken since the executor last looked, in wake order.
///
/// A wake on the thread that runs the executor (in a run, every wake) is a push onto a
/// thread-local list: no lock, no atomic operation (a mutex's two cost 2 % of a 1000-robot
/// run). A wake from elsewhere (another thread, or while the executor is not running) goes
/// into a list behind a mutex, read after the local one.
struct Woken {
    /// The executor's number ([`EXECUTORS`]).
    exec: u64,
    elsewhere: Mutex<Vec<TaskId>>,
    any_elsewhere: AtomicBool,
}

impl Default for Woken {
    fn default() -> Self {
        Woken {
            exec: EXECUTORS.fetch_add(1, Ordering::Relaxed),
            elsewhere: Mutex::new(Vec::new()),
            any_elsewhere: AtomicBool::new(false),
        }
    }
}

impl Woken {
    fn push(&self, id: TaskId) {
        if RUNNING.with(Cell::get) == self.exec {
            LOCAL_WAKES.with_borrow_mut(|w| w.push(id));
            return;
        }
        self.elsewhere
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(id);
        self.any_elsewhere.store(true, Ordering::Release);
    }

    /// Appends the wakes since the last look to `into` (which the caller emptied).
    fn take_into(&self, into: &mut Vec<TaskId>) {
        if RUNNING.with(Cell::get) == self.exec {
            LOCAL_WAKES.with_borrow_mut(|w| std::mem::swap(w, into));
        }
        // A load first: it is no locked instruction, the swap is.
        if self.any_elsewhere.load(Ordering::Acquire)
            && self.any_elsewhere.swap(false, Ordering::Acquire)
        {
            let mut w = self
                .elsewhere
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            into.append(&mut w);
        }
    }

    /// This executor runs on this thread from now on, until the guard is dropped (which
    /// gives the thread back to the executor it had, if one run runs inside another).
    fn enter(&self) -> Entered {
        Entered {
            previous: RUNNING.with(|r| r.replace(self.exec)),
            wakes: LOCAL_WAKES.take(),
        }
    }
}

/// While it lives, an executor runs on this thread ([`Woken::enter`]); it keeps the executor
/// that ran before, and that one's wakes not yet read.
struct Entered {
    previous: u64,
    wakes: Vec<TaskId>,
}

impl Drop for Entered {
    fn drop(&mut self) {
        LOCAL_WAKES.set(std::mem::take(&mut self.wakes));
        RUNNING.with(|r| r.set(self.previous));
    }
}

/// A task's waker.
struct TaskWaker {
    id: TaskId,
    woken: Arc<Woken>,
}

impl Wake for TaskWaker {
    fn wake(self: Arc<Self>) {
        self.woken.push(self.id);
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.woken.push(self.id);
    }
}

/// The run queue of a virtual-time run. It lives in its [`Timeline`](super::timeline::Timeline), which every part of the
/// world reaches through its clock; spawning goes here while [`Timeline::block_on`](super::timeline::Timeline::block_on) runs.
#[derive(Default)]
pub struct Executor {
    running: Cell<bool>,
    tasks: RefCell<Slab<Slot>>,
    queue: RefCell<VecDeque<usize>>,
    woken: Arc<Woken>,
    /// The main future was woken.
    main_woken: Cell<bool>,
    next_generation: Cell<u64>,
    /// Wakes read from `woken`, kept between reads (no allocation per poll).
    scratch: RefCell<Vec<TaskId>>,
}

impl std::fmt::Debug for Executor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Executor")
            .field("running", &self.running.get())
            .field("tasks", &self.tasks.borrow().len())
            .field("queued", &self.queue.borrow().len())
            .finish_non_exhaustive()
    }
}

impl Executor {
    /// Whether [`Timeline::block_on`](super::timeline::Timeline::block_on) is running: tasks spawned now are this executor's.
    pub fn is_running(&self) -> bool {
        self.running.get()
    }

    /// Queues a new task.
    pub fn spawn(&self, future: impl Future<Output = ()> + 'static) {
        let future: Pin<Box<dyn Future<Output = ()>>> = Box::pin(future);
        let body = Body::of(&*future);
        self.spawn_boxed(future, body);
    }

    fn spawn_boxed(&self, future: Pin<Box<dyn Future<Output = ()>>>, body: Body) {
        let generation = self.next_generation.get();
        self.next_generation.set(generation + 1);
        let mut tasks = self.tasks.borrow_mut();
        let entry = tasks.vacant_entry();
        let slot = entry.key();
        let waker = Waker::from(Arc::new(TaskWaker {
            id: (slot, generation),
            woken: self.woken.clone(),
        }));
        entry.insert(Slot {
            future: Some(future),
            body,
            waker,
            state: State::Queued,
            generation,
        });
        self.queue.borrow_mut().push_back(slot);
    }

    /// Queues a new task whose output (or panic) `Join` gives.
    pub fn spawn_joined<T: 'static>(&self, future: impl Future<Output = T> + 'static) -> Join<T> {
        let inner = Rc::new(JoinInner {
            out: RefCell::new(None),
            waker: RefCell::new(None),
        });
        let future: Pin<Box<dyn Future<Output = T>>> = Box::pin(future);
        // What a poll of a joined task reads is in its future's box, not the `Joined`.
        let body = Body::of(&*future);
        self.spawn_boxed(
            Box::pin(Joined {
                future,
                inner: inner.clone(),
            }),
            body,
        );
        Join { inner }
    }

    /// Moves the wakes since the last look into the queue, in order: an idle task goes to the
    /// back, a running one is marked, a queued one stays where it is.
    fn collect_wakes(&self) {
        let mut scratch = self.scratch.borrow_mut();
        self.woken.take_into(&mut scratch);
        if scratch.is_empty() {
            return;
        }
        let mut tasks = self.tasks.borrow_mut();
        let mut queue = self.queue.borrow_mut();
        for &(slot, generation) in scratch.iter() {
            if (slot, generation) == MAIN {
                self.main_woken.set(true);
                continue;
            }
            let Some(t) = tasks.get_mut(slot) else {
                continue;
            };
            if t.generation != generation {
                continue;
            }
            match t.state {
                State::Idle => {
                    t.state = State::Queued;
                    queue.push_back(slot);
                }
                State::Running => t.state = State::Notified,
                State::Queued | State::Notified => {}
            }
        }
        scratch.clear();
    }

    /// Asks the CPU to load the state of the task queued next, while the one just taken from
    /// the queue runs. A robot's task (its whole program and state, 4.3 KB) is out of the
    /// caches by the time it runs again when a thousand robots take turns, and its poll
    /// stalled on each line it read; prefetched, the lines come in together.
    fn prefetch_next(&self) {
        let queue = self.queue.borrow();
        let tasks = self.tasks.borrow();
        if let Some(t) = queue.front().and_then(|&next| tasks.get(next)) {
            t.body.prefetch();
        }
    }

    /// Polls the task in `slot` once; a panic ends it.
    fn run(&self, slot: usize) {
        let (mut future, waker) = {
            let mut tasks = self.tasks.borrow_mut();
            let Some(t) = tasks.get_mut(slot) else {
                return;
            };
            t.state = State::Running;
            let Some(f) = t.future.take() else {
                return;
            };
            // Out of the slot while it is polled, like the future: no reference count to
            // raise and lower (two locked instructions a poll).
            (f, std::mem::replace(&mut t.waker, Waker::noop().clone()))
        };
        let mut cx = Context::from_waker(&waker);
        let done = !matches!(
            catch_unwind(AssertUnwindSafe(|| future.as_mut().poll(&mut cx))),
            Ok(Poll::Pending)
        );
        self.collect_wakes();
        let mut tasks = self.tasks.borrow_mut();
        if done {
            tasks.remove(slot);
            drop(tasks);
            // Dropped outside the borrow: what it holds may reach the executor.
            drop(future);
            return;
        }
        let t = &mut tasks[slot];
        t.future = Some(future);
        t.waker = waker;
        if t.state == State::Notified {
            t.state = State::Queued;
            self.queue.borrow_mut().push_back(slot);
        } else {
            t.state = State::Idle;
        }
    }

    /// Drops every task left (they may hold the timeline: without this they would keep it,
    /// and it them).
    fn clear(&self) {
        let tasks: Vec<Slot> = self.tasks.borrow_mut().drain().collect();
        self.queue.borrow_mut().clear();
        drop(tasks);
    }
}

impl Executor {
    /// Runs `main` and every task spawned on this executor until `main` ends; whenever no task
    /// can run, `idle` moves the world on (robots in the loop catch up, the next deadline is
    /// due) and says whether it could. Tasks left when `main` ends are dropped. The body of
    /// [`Timeline::block_on`](super::timeline::Timeline::block_on)(super::timeline::Timeline::block_on), which owns the clock.
    ///
    /// # Panics
    /// If `main` panics; or if nothing can run and `idle` cannot move on (a run that would
    /// wait for ever).
    pub(super) fn block_on<F: Future>(&self, main: F, mut idle: impl FnMut() -> bool) -> F::Output {
        /// Ends the run however `main` ends, a panic included.
        struct Running<'a>(&'a Executor);
        impl Drop for Running<'_> {
            fn drop(&mut self) {
                self.0.running.set(false);
                self.0.clear();
            }
        }
        // Dropped after `_running`: wakes while the tasks are dropped are still this run's.
        let _entered = self.woken.enter();
        self.running.set(true);
        let _running = Running(self);
        self.run_main(main, &mut idle)
    }

    fn run_main<F: Future>(&self, main: F, idle: &mut impl FnMut() -> bool) -> F::Output {
        let mut main = std::pin::pin!(main);
        let main_waker = Waker::from(Arc::new(TaskWaker {
            id: MAIN,
            woken: self.woken.clone(),
        }));
        self.main_woken.set(true);
        loop {
            if self.main_woken.replace(false) {
                let mut cx = Context::from_waker(&main_waker);
                if let Poll::Ready(out) = main.as_mut().poll(&mut cx) {
                    return out;
                }
                self.collect_wakes();
                let mut ran = 0;
                while ran < TASKS_PER_TICK {
                    let Some(slot) = self.queue.borrow_mut().pop_front() else {
                        break;
                    };
                    self.prefetch_next();
                    self.run(slot);
                    ran += 1;
                }
                if ran == TASKS_PER_TICK {
                    self.main_woken.set(true);
                }
                continue;
            }
            assert!(
                idle(),
                "the run waits for ever: no task can run and none waits for a time"
            );
            self.collect_wakes();
            self.main_woken.set(true);
        }
    }
}

/// What a panicking task left: its payload.
pub type Panic = Box<dyn Any + Send + 'static>;

struct JoinInner<T> {
    out: RefCell<Option<Result<T, Panic>>>,
    waker: RefCell<Option<Waker>>,
}

/// A task's output, or its panic, once it ends ([`Executor::spawn_joined`]).
pub struct Join<T> {
    inner: Rc<JoinInner<T>>,
}

impl<T> std::fmt::Debug for Join<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Join")
            .field("ended", &self.inner.out.borrow().is_some())
            .finish()
    }
}

impl<T> Future for Join<T> {
    type Output = Result<T, Panic>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        if let Some(out) = self.inner.out.borrow_mut().take() {
            return Poll::Ready(out);
        }
        let mut w = self.inner.waker.borrow_mut();
        if !w.as_ref().is_some_and(|w| w.will_wake(cx.waker())) {
            *w = Some(cx.waker().clone());
        }
        Poll::Pending
    }
}

/// A joined task: its future, and where its output goes.
struct Joined<T> {
    future: Pin<Box<dyn Future<Output = T>>>,
    inner: Rc<JoinInner<T>>,
}

impl<T> Future for Joined<T> {
    type Output = ();

    fn poll(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<()> {
        let out = match catch_unwind(AssertUnwindSafe(|| self.future.as_mut().poll(cx))) {
            Ok(Poll::Pending) => return Poll::Pending,
            Ok(Poll::Ready(v)) => Ok(v),
            Err(p) => Err(p),
        };
        *self.inner.out.borrow_mut() = Some(out);
        if let Some(w) = self.inner.waker.borrow_mut().take() {
            w.wake();
        }
        Poll::Ready(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::timeline::{Sleep, Timeline, drive_virtual};
    use protocol::Instant;

    /// Tasks run in wake order, a task woken while it runs goes behind the others, and time
    /// moves on only when nothing can run.
    #[test]
    fn tasks_run_in_wake_order_and_time_moves_when_all_wait() {
        let tl = Rc::new(Timeline::default());
        let log = Rc::new(RefCell::new(Vec::new()));
        let out = tl.block_on({
            let tl = tl.clone();
            let log = log.clone();
            async move {
                let exec = tl.executor();
                exec.spawn(drive_virtual(tl.clone()));
                for name in ["a", "b"] {
                    let (tl, log) = (tl.clone(), log.clone());
                    exec.spawn(async move {
                        log.borrow_mut().push((name, tl.now().as_millis()));
                        // Wakes itself: runs again after the other task.
                        std::future::poll_fn(|cx| {
                            cx.waker().wake_by_ref();
                            Poll::Ready(())
                        })
                        .await;
                        let mut yielded = false;
                        std::future::poll_fn(|cx| {
                            if yielded {
                                return Poll::Ready(());
                            }
                            yielded = true;
                            cx.waker().wake_by_ref();
                            Poll::Pending
                        })
                        .await;
                        log.borrow_mut().push((name, tl.now().as_millis()));
                        Sleep::until(tl.clone(), Instant::from_millis(7)).await;
                        log.borrow_mut().push((name, tl.now().as_millis()));
                    });
                }
                let late = exec.spawn_joined({
                    let tl = tl.clone();
                    async move {
                        Sleep::until(tl.clone(), Instant::from_secs(3600)).await;
                        tl.now().as_millis()
                    }
                });
                let failing = exec.spawn_joined(async { panic!("on purpose") });
                let failed = failing.await.expect_err("it panicked");
                assert_eq!(failed.downcast_ref::<&str>(), Some(&"on purpose"));
                late.await.expect("it ended")
            }
        });
        assert_eq!(out, 3_600_000);
        assert_eq!(
            *log.borrow(),
            vec![("a", 0), ("b", 0), ("a", 0), ("b", 0), ("a", 7), ("b", 7)]
        );
        assert_eq!(tl.executor().tasks.borrow().len(), 0, "left tasks dropped");
    }

    /// A waker kept from one run and woken during another on the same thread wakes nothing
    /// there, though a task of the second run has the same slot and generation.
    #[test]
    fn a_waker_from_another_run_wakes_nothing() {
        /// A task that counts its polls and keeps its waker, waiting for ever.
        fn idle(
            polls: Rc<Cell<u32>>,
            keep: Rc<RefCell<Option<Waker>>>,
        ) -> impl Future<Output = ()> {
            std::future::poll_fn(move |cx| {
                polls.set(polls.get() + 1);
                *keep.borrow_mut() = Some(cx.waker().clone());
                Poll::Pending
            })
        }
        let first = Rc::new(Timeline::default());
        let kept = Rc::new(RefCell::new(None));
        let (polls, keep) = (Rc::new(Cell::new(0)), kept.clone());
        first.block_on({
            let tl = first.clone();
            async move {
                tl.executor().spawn(drive_virtual(tl.clone()));
                tl.executor().spawn(idle(polls, keep));
                Sleep::until(tl.clone(), Instant::from_millis(1)).await;
            }
        });
        let stale = kept
            .borrow_mut()
            .take()
            .expect("the first run's task was polled");
        let second = Rc::new(Timeline::default());
        let polls = Rc::new(Cell::new(0));
        second.block_on({
            let tl = second.clone();
            let polls = polls.clone();
            async move {
                tl.executor().spawn(drive_virtual(tl.clone()));
                // Slot 1, generation 1: the stale waker's task number in the first run.
                tl.executor()
                    .spawn(idle(polls, Rc::new(RefCell::new(None))));
                Sleep::until(tl.clone(), Instant::from_millis(1)).await;
                stale.wake();
                Sleep::until(tl.clone(), Instant::from_millis(2)).await;
            }
        });
        assert_eq!(
            polls.get(),
            1,
            "the stale wake polled the second run's task"
        );
    }

    /// A run inside a task of another run keeps the outer run's wakes: a task that woke
    /// itself before the inner run is polled again after it.
    #[test]
    fn a_run_inside_a_run_keeps_the_outer_wakes() {
        let outer = Rc::new(Timeline::default());
        let polls = Rc::new(Cell::new(0));
        outer.block_on({
            let tl = outer.clone();
            let polls = polls.clone();
            async move {
                tl.executor().spawn(drive_virtual(tl.clone()));
                let p = polls.clone();
                let task = tl.executor().spawn_joined(std::future::poll_fn(move |cx| {
                    p.set(p.get() + 1);
                    if p.get() > 1 {
                        return Poll::Ready(());
                    }
                    cx.waker().wake_by_ref();
                    let inner = Rc::new(Timeline::default());
                    inner.block_on({
                        let tl = inner.clone();
                        async move {
                            tl.executor().spawn(drive_virtual(tl.clone()));
                            Sleep::until(tl.clone(), Instant::from_millis(5)).await;
                        }
                    });
                    Poll::Pending
                }));
                assert!(task.await.is_ok());
            }
        });
        assert_eq!(polls.get(), 2);
    }

    #[test]
    #[should_panic(expected = "waits for ever")]
    fn a_run_that_waits_for_nothing_is_stopped() {
        let tl = Rc::new(Timeline::default());
        tl.block_on(std::future::pending::<()>());
    }
}
