//! `link_pump`: the robot's end of the link (`firmware::hil::robot::Link`): its receive pump
//! ([`Link::pump`]), what it does with each message (held until a `Sync` on the host's clock,
//! dispatched at once otherwise), its idle hook ([`Link::on_idle`]) and the answers of its
//! beat ([`Link::beat`]), against a model of `docs/hil.md` ("Messages", "Errors", "Time").
//!
//! The futures are polled by hand with a no-op waker (the pump, then the beat, after each
//! step), over a scripted UART: the reader hands over a step's bytes (32 per read, the pump's
//! buffer) and then is pending, or fails once; the writer records what the robot sends, or
//! fails. The [`HostClock`] hooks record their calls and act as both real drivers do (the QEMU
//! image's and the host twin's): `follow(true)` sets the time to 0, `set_now` keeps the later
//! time. The clock the beat gets never fires, so the beat says `Hello` only when asked.
//!
//! Input (format in [`crate::input`]): whether the link can follow the host's clock
//! ([`Link::with_host_clock`] or [`Link::new`]), then up to [`OPS_MAX`] steps ([`Op`]): link
//! messages ([`link_ref::read_msg`], up to [`MSGS_MAX`], framed and sent as one burst), raw
//! bytes, a UART error, the executor's idle hook, a receiver read, the driver's next timer, and
//! whether the writer fails. After every step:
//!
//! - the pump comes back to the reader within a bounded number of polls (no hang, no spin),
//!   and returns once the stream ends;
//! - `stats()` is the model's: the decoder's counters (the model decoder of
//!   [`crate::link_ref`]), light bytes lost to a full 128-byte pipe, unexpected messages (an
//!   `Rx` for a sector ≥ N, a robot's message, a `Reading` of another quantity, a `Sync` or
//!   `Idle` on the own clock), UART errors (reading and writing), setups, frames sent, and
//!   messages that found the hold full (`held_over`);
//! - on the host's clock (from a `Setup` with `host_clock` to a link that can follow, that
//!   `Setup` included, even on the own clock), every message but a `Sync` is held, at most
//!   [`HELD`]; one more is taken at once and counted; at a
//!   `Sync(T)` the held messages are taken in order, then `set_now(T)` is called, and the next
//!   idle hook makes the beat say `Idle { now: T, next }` with the driver's next timer (`u32::MAX`
//!   beyond `u32`); on the own clock every message is taken at once;
//! - the hooks are called exactly as the model says (`follow(host_clock)` at each `Setup` a
//!   following link takes, `set_now(T)` at each `Sync` on the host's clock), and the driver's
//!   time never goes backwards but at a `follow(true)` (a new run);
//! - every receiver holds exactly the light bytes the model's pipe holds (read back in order),
//!   and the sensor gives the last level taken for each quantity (`NotReady` before one);
//! - the beat's frames decode to exactly the model's answers: `Hello` (`LINK_VERSION`, the id, N
//!   sectors, whether it can follow) when the host asked, the number of the last heartbeat taken,
//!   and each `Idle` owed, the heartbeat's answer first; before the beat has seen the first
//!   `Setup`, a heartbeat's answer (or an `Idle`) is kept, a later one replacing it, and sent
//!   when the beat next wakes after the `Setup` (README, findings).

use std::cell::RefCell;
use std::collections::VecDeque;
use std::future::Future;
use std::pin::pin;
use std::rc::Rc;
use std::task::{Context, Poll, Waker};

use arbitrary::Unstructured;
use firmware::embedded_io_async::{self, ErrorKind};
use firmware::hil::robot::{HELD, HilStats, HostClock, Link, RX_PIPE};
use firmware::hil::{LINK_VERSION, LinkDecoder, LinkMsg};
use firmware::{Clock, Sensor};
use protocol::{Instant, Level};

use crate::input::{Writer, byte_list, get, list};
use crate::link_ref::{self, ModelDecoder};

/// Receivers of the robot (a robot in a line).
pub const N: usize = 2;
/// Its id (in its `Hello`).
pub const ID: u16 = 0x0A17;
/// Steps read at most.
pub const OPS_MAX: usize = 32;
/// Messages in one burst at most (more than [`HELD`]).
pub const MSGS_MAX: usize = HELD + 4;
/// Raw bytes in one step at most.
pub const BYTES_MAX: usize = 96;

/// One step of the script.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Op {
    /// These messages, framed, as one burst of bytes from the host.
    Msgs(Vec<LinkMsg>),
    /// These bytes from the host.
    Bytes(Vec<u8>),
    /// The UART's next read fails.
    UartError,
    /// The executor finds nothing to run: [`Link::on_idle`].
    Idle,
    /// The robot program reads up to `n` bytes from receiver `sector % N`.
    Read {
        /// The receiver (modulo N).
        sector: u8,
        /// Bytes to read at most.
        n: u8,
    },
    /// The driver's next timer is now this (`u64::MAX`: none).
    Alarm(u64),
    /// From now on the UART's writes fail (`true`) or succeed.
    WriterFails(bool),
}

impl Op {
    fn read(u: &mut Unstructured<'_>) -> Op {
        match get::<u8>(u) % 7 {
            0 => Op::Msgs(list(u, MSGS_MAX, link_ref::read_msg)),
            1 => Op::Bytes(byte_list(u, BYTES_MAX)),
            2 => Op::UartError,
            3 => Op::Idle,
            4 => Op::Read {
                sector: get(u),
                n: get(u),
            },
            5 => Op::Alarm(get(u)),
            _ => Op::WriterFails(get(u)),
        }
    }

    fn write(&self, w: &mut Writer) {
        match self {
            Op::Msgs(msgs) => {
                w.u8(0);
                for m in msgs {
                    w.item();
                    link_ref::write_msg(w, m);
                }
                w.end();
            }
            Op::Bytes(b) => {
                w.u8(1).byte_list(b);
            }
            Op::UartError => {
                w.u8(2);
            }
            Op::Idle => {
                w.u8(3);
            }
            Op::Read { sector, n } => {
                w.u8(4).u8(*sector).u8(*n);
            }
            Op::Alarm(t) => {
                w.u8(5).u64(*t);
            }
            Op::WriterFails(f) => {
                w.u8(6).bool(*f);
            }
        }
    }
}

/// A parsed input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The link can follow the host's clock ([`Link::with_host_clock`]).
    pub can_follow: bool,
    /// The steps.
    pub ops: Vec<Op>,
}

impl Input {
    /// Reads an input.
    pub fn read(data: &[u8]) -> Input {
        let mut u = Unstructured::new(data);
        let can_follow = get(&mut u);
        let ops = list(&mut u, OPS_MAX, Op::read);
        Input { can_follow, ops }
    }

    /// The bytes [`read`](Self::read) turns into this input.
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        w.bool(self.can_follow);
        for op in &self.ops {
            w.item();
            op.write(&mut w);
        }
        w.end();
        w.finish()
    }
}

/// A call of a [`HostClock`] hook.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hook {
    /// `follow(on)`.
    Follow(bool),
    /// `set_now(ms)`.
    SetNow(u64),
}

/// The image's time driver, as the hooks see it.
#[derive(Debug, Default)]
struct Driver {
    calls: Vec<Hook>,
    now: u64,
    alarm: u64,
}

thread_local! {
    static DRIVER: RefCell<Driver> = RefCell::new(Driver::default());
}

const HOOKS: HostClock = HostClock {
    follow: |on| {
        DRIVER.with_borrow_mut(|d| {
            d.calls.push(Hook::Follow(on));
            if on {
                d.now = 0;
            }
        });
    },
    set_now: |ms| {
        DRIVER.with_borrow_mut(|d| {
            d.calls.push(Hook::SetNow(ms));
            d.now = d.now.max(ms);
        });
    },
    next_alarm: || DRIVER.with_borrow(|d| d.alarm),
};

/// The host's end of the UART, shared by the scripted reader and writer.
#[derive(Debug, Default)]
struct Uart {
    /// Bytes the robot has not read yet.
    to_robot: VecDeque<u8>,
    /// The next read fails.
    fail_read: bool,
    /// The stream has ended.
    ended: bool,
    /// A read found nothing (the pump waits for the host).
    waiting: bool,
    /// What the robot wrote.
    from_robot: Vec<u8>,
    /// Writes fail.
    fail_write: bool,
}

struct UartRx(Rc<RefCell<Uart>>);
struct UartTx(Rc<RefCell<Uart>>);

impl embedded_io_async::ErrorType for UartRx {
    type Error = ErrorKind;
}

impl embedded_io_async::Read for UartRx {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, ErrorKind> {
        core::future::poll_fn(|_| {
            let mut u = self.0.borrow_mut();
            if std::mem::take(&mut u.fail_read) {
                return Poll::Ready(Err(ErrorKind::Other));
            }
            if u.to_robot.is_empty() {
                if u.ended {
                    return Poll::Ready(Ok(0));
                }
                u.waiting = true;
                return Poll::Pending;
            }
            let n = buf.len().min(u.to_robot.len());
            for (slot, b) in buf.iter_mut().zip(u.to_robot.drain(..n)) {
                *slot = b;
            }
            Poll::Ready(Ok(n))
        })
        .await
    }
}

impl embedded_io_async::ErrorType for UartTx {
    type Error = ErrorKind;
}

impl embedded_io_async::Write for UartTx {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        let mut u = self.0.borrow_mut();
        if u.fail_write {
            return Err(ErrorKind::Other);
        }
        u.from_robot.extend_from_slice(buf);
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

/// A clock that never fires (the beat's `Hello` period never ends).
struct Still;

impl Clock for Still {
    fn now(&self) -> Instant {
        Instant::ZERO
    }

    async fn sleep_until(&self, _deadline: Instant) {
        core::future::pending::<()>().await;
    }
}

/// What the beat owes the host (the model of its two signals).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Answer {
    Beat(u32),
    Hello,
    Idle(u32),
}

/// The model of the robot's end.
#[derive(Debug)]
struct Model {
    can_follow: bool,
    following: bool,
    held: VecDeque<LinkMsg>,
    /// The `Sync` whose `Idle` is owed.
    owed: Option<u32>,
    pipes: [VecDeque<u8>; N],
    ambient: Option<u8>,
    oxygen: Option<u8>,
    stats: HilStats,
    decoder: ModelDecoder,
    set_up: bool,
    /// The beat was polled once; it has seen `set_up`.
    beat_started: bool,
    beat_set_up: bool,
    /// The echo signal, the idle signal, and the answer the beat took before its setup.
    echo: Option<Answer>,
    idle: Option<u32>,
    beat_owed: Option<Answer>,
    hooks: Vec<Hook>,
    clock: u64,
    alarm: u64,
    fail_write: bool,
    /// What the robot must have sent since the last check.
    sent: Vec<LinkMsg>,
}

impl Model {
    fn new(can_follow: bool) -> Self {
        Model {
            can_follow,
            following: false,
            held: VecDeque::new(),
            owed: None,
            pipes: Default::default(),
            ambient: None,
            oxygen: None,
            stats: HilStats::default(),
            decoder: ModelDecoder::default(),
            set_up: false,
            beat_started: false,
            beat_set_up: false,
            echo: None,
            idle: None,
            beat_owed: None,
            hooks: Vec::new(),
            clock: 0,
            alarm: 0,
            fail_write: false,
            sent: Vec::new(),
        }
    }

    fn unexpected(&mut self) {
        self.stats.unexpected += 1;
    }

    /// Bytes from the host.
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if let Some(Ok(msg)) = self.decoder.push(b) {
                self.take(msg);
            }
        }
        self.stats.link = self.decoder.stats;
    }

    fn take(&mut self, msg: LinkMsg) {
        // A `Setup` asking for the host's clock is held even by a link still on its own clock
        // (a freshly booted robot): its program starts at the `Sync`, at the host's time.
        if self.can_follow && matches!(&msg, LinkMsg::Setup(s) if s.host_clock) {
            self.following = true;
        }
        if !self.following {
            return self.dispatch(msg);
        }
        if let LinkMsg::Sync(t) = msg {
            while let Some(m) = self.held.pop_front() {
                self.dispatch(m);
            }
            self.hooks.push(Hook::SetNow(u64::from(t)));
            self.clock = self.clock.max(u64::from(t));
            self.owed = Some(t);
        } else if self.held.len() < HELD {
            self.held.push_back(msg);
        } else {
            self.stats.held_over += 1;
            self.dispatch(msg);
        }
    }

    fn dispatch(&mut self, msg: LinkMsg) {
        match msg {
            LinkMsg::Rx { sector, bytes } => {
                let Some(pipe) = self.pipes.get_mut(usize::from(sector)) else {
                    return self.unexpected();
                };
                let room = RX_PIPE - pipe.len();
                let n = room.min(bytes.len());
                pipe.extend(&bytes[..n]);
                self.stats.rx_lost += (bytes.len() - n) as u32;
            }
            LinkMsg::Reading { quantity: 0, level } => self.ambient = Some(level),
            LinkMsg::Reading { quantity: 1, level } => self.oxygen = Some(level),
            LinkMsg::Setup(s) => {
                self.stats.setups += 1;
                if self.can_follow {
                    self.following = s.host_clock;
                    self.hooks.push(Hook::Follow(s.host_clock));
                    if s.host_clock {
                        self.clock = 0;
                    }
                }
                self.set_up = true;
            }
            LinkMsg::Heartbeat(seq) => self.echo = Some(Answer::Beat(seq)),
            LinkMsg::Hello { .. } => self.echo = Some(Answer::Hello),
            // Kept for the next `Setup` by a link that follows; nothing to see here.
            LinkMsg::Key(_) if self.can_follow => {}
            LinkMsg::Reading { .. }
            | LinkMsg::Tx(_)
            | LinkMsg::Led(_)
            | LinkMsg::Refused(_)
            | LinkMsg::Sync(_)
            | LinkMsg::Idle { .. }
            | LinkMsg::Key(_) => self.unexpected(),
        }
    }

    fn on_idle(&mut self) {
        if self.can_follow
            && let Some(t) = self.owed.take()
        {
            self.idle = Some(t);
        }
    }

    fn hello(&self) -> LinkMsg {
        LinkMsg::Hello {
            version: LINK_VERSION,
            id: ID,
            sectors: N as u8,
            host_clock: self.can_follow,
        }
    }

    /// The answer's message, as the beat builds it when it sends it (an `Idle` with the
    /// driver's next timer then).
    fn message(&self, a: Answer) -> LinkMsg {
        match a {
            Answer::Beat(seq) => LinkMsg::Heartbeat(seq),
            Answer::Hello => self.hello(),
            Answer::Idle(now) => LinkMsg::Idle {
                now,
                next: u32::try_from(self.alarm).unwrap_or(u32::MAX),
            },
        }
    }

    fn send(&mut self, msg: LinkMsg) {
        if self.fail_write {
            self.stats.uart_errors += 1;
        } else {
            self.stats.sent += 1;
            self.sent.push(msg);
        }
    }

    /// The beat, polled until it waits. It looks at `set_up` only at the top of its loop: at
    /// its first poll and after each answer; until it sees it, a `Hello` asked for is said at
    /// once and any other answer kept (a later one replaces it), to be sent first once it sees
    /// it. Then each answer is sent: the echo before the idle signal.
    fn beat(&mut self) {
        let mut at_top = !std::mem::replace(&mut self.beat_started, true);
        loop {
            if at_top && self.set_up {
                self.beat_set_up = true;
            }
            at_top = true;
            if self.beat_set_up
                && let Some(owed) = self.beat_owed.take()
            {
                self.send(self.message(owed));
                continue;
            }
            let Some(a) = self
                .echo
                .take()
                .or_else(|| self.idle.take().map(Answer::Idle))
            else {
                return;
            };
            match a {
                _ if self.beat_set_up => self.send(self.message(a)),
                Answer::Hello => self.send(self.hello()),
                owed => self.beat_owed = Some(owed),
            }
        }
    }
}

/// Polls `f` until the reader waits for the host (or `f` ends): `true` if it ended.
fn drive(f: std::pin::Pin<&mut impl Future>, uart: &RefCell<Uart>, cx: &mut Context<'_>) -> bool {
    let mut f = f;
    let bound = uart.borrow().to_robot.len() / 32 + 8;
    for _ in 0..bound {
        uart.borrow_mut().waiting = false;
        if f.as_mut().poll(cx).is_ready() {
            return true;
        }
        if uart.borrow().waiting {
            return false;
        }
    }
    panic!("the pump did not come back to the reader within {bound} polls");
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let input = Input::read(data);
    DRIVER.with_borrow_mut(|d| *d = Driver::default());
    let uart = Rc::new(RefCell::new(Uart::default()));
    let link: Link<UartTx, N> = if input.can_follow {
        Link::with_host_clock(UartTx(uart.clone()), HOOKS)
    } else {
        Link::new(UartTx(uart.clone()))
    };
    let mut model = Model::new(input.can_follow);
    let mut host = LinkDecoder::new();
    let mut cx = Context::from_waker(Waker::noop());
    let mut pump = pin!(link.pump(UartRx(uart.clone())));
    let mut beat = pin!(link.beat(&Still, ID));

    let mut hw = link.hardware(Still);
    for (step, op) in input.ops.iter().enumerate() {
        match op {
            Op::Msgs(msgs) => {
                let bytes: Vec<u8> = msgs.iter().flat_map(link_ref::frame).collect();
                uart.borrow_mut().to_robot.extend(&bytes);
                model.bytes(&bytes);
            }
            Op::Bytes(bytes) => {
                uart.borrow_mut().to_robot.extend(bytes);
                model.bytes(bytes);
            }
            Op::UartError => {
                uart.borrow_mut().fail_read = true;
                model.stats.uart_errors += 1;
            }
            Op::Idle => {
                link.on_idle();
                model.on_idle();
            }
            Op::Read { sector, n } => {
                let s = usize::from(*sector) % N;
                let mut got = Vec::new();
                let mut buf = vec![0u8; usize::from(*n)];
                while got.len() < buf.len() {
                    let want = buf.len() - got.len();
                    match hw.receivers[s].try_read(&mut buf[..want]) {
                        Ok(k) => got.extend_from_slice(&buf[..k]),
                        Err(_) => break,
                    }
                }
                let pipe = &mut model.pipes[s];
                let k = pipe.len().min(usize::from(*n));
                let want: Vec<u8> = pipe.drain(..k).collect();
                assert_eq!(got, want, "step {step}: receiver {s}");
            }
            Op::Alarm(t) => {
                DRIVER.with_borrow_mut(|d| d.alarm = *t);
                model.alarm = *t;
            }
            Op::WriterFails(f) => {
                uart.borrow_mut().fail_write = *f;
                model.fail_write = *f;
            }
        }
        assert!(
            !drive(pump.as_mut(), &uart, &mut cx),
            "step {step}: the pump returned before the stream ended"
        );
        assert!(
            beat.as_mut().poll(&mut cx).is_pending(),
            "the beat never ends"
        );
        model.beat();

        // The counters, the hooks, the driver's time, the receivers, the sensor, what was sent.
        assert_eq!(link.stats(), model.stats, "step {step}: {op:?}");
        let (calls, now) = DRIVER.with_borrow_mut(|d| (std::mem::take(&mut d.calls), d.now));
        assert_eq!(
            calls,
            std::mem::take(&mut model.hooks),
            "step {step}: hooks"
        );
        assert_eq!(now, model.clock, "step {step}: the driver's time");
        for (s, p) in model.pipes.iter().enumerate() {
            assert_eq!(hw.receivers[s].len(), p.len(), "step {step}: receiver {s}");
        }
        let level = |r: Poll<Result<Level, firmware::ErrorKind>>| match r {
            Poll::Ready(r) => r.ok().map(|l| l.0),
            Poll::Pending => panic!("the sensor waits"),
        };
        assert_eq!(
            level(pin!(hw.sensor.ambient_light()).poll(&mut cx)),
            model.ambient
        );
        assert_eq!(level(pin!(hw.sensor.oxygen()).poll(&mut cx)), model.oxygen);
        let written = std::mem::take(&mut uart.borrow_mut().from_robot);
        let said: Vec<LinkMsg> = written
            .iter()
            .filter_map(|&b| host.push(b))
            .map(|r| r.expect("the robot's frames decode"))
            .collect();
        assert_eq!(said, std::mem::take(&mut model.sent), "step {step}: sent");
        assert_eq!(host.stats().errors(), 0);
    }

    // The stream ends: the pump returns.
    uart.borrow_mut().ended = true;
    assert!(
        drive(pump.as_mut(), &uart, &mut cx),
        "the pump did not return at the end of the stream"
    );
}

/// The counters the model expects at the end of `input` (for the seeds' tests).
pub fn run_model(input: &Input) -> HilStats {
    let mut model = Model::new(input.can_follow);
    for op in &input.ops {
        match op {
            Op::Msgs(msgs) => {
                let bytes: Vec<u8> = msgs.iter().flat_map(link_ref::frame).collect();
                model.bytes(&bytes);
            }
            Op::Bytes(bytes) => model.bytes(bytes),
            Op::UartError => model.stats.uart_errors += 1,
            Op::Idle => model.on_idle(),
            Op::Read { sector, n } => {
                let p = &mut model.pipes[usize::from(*sector) % N];
                let k = p.len().min(usize::from(*n));
                p.drain(..k);
            }
            Op::Alarm(t) => model.alarm = *t,
            Op::WriterFails(f) => model.fail_write = *f,
        }
        model.beat();
    }
    model.stats
}
