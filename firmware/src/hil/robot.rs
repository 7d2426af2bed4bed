//! The robot's end of the link: the unchanged robot program ([`Robot::run`]) on hardware made
//! of one byte stream to the host (`docs/hil.md`).
//!
//! ```text
//!           UART rx ──▶ pump: LinkDecoder ──Rx{sector}──▶ pipe[sector] ──▶ receiver (Read)
//!                                         ──Reading────▶ levels ─────────▶ sensor
//!                                         ──Setup──────▶ (re)start the robot program
//!  transmitter (Write) ──Tx──┐
//!  LEDs ─────────────────Led─┼──▶ writer (one at a time) ──▶ UART tx
//!  beat ──Hello…, Heartbeat──┘        (answers the host's heartbeats)
//! ```
//!
//! [`Link`] holds what the pieces share: the UART's writing half behind an async mutex (one
//! frame at a time), a pipe per receiver, the last sensor levels, the pending [`Setup`] and
//! the counters. [`run`] joins three futures and never returns: the pump (reads the UART,
//! decodes, dispatches), the beat (a `Hello` every period until the first `Setup`, then the
//! answer to each of the host's heartbeats), and the robot program itself, restarted with
//! fresh state at every `Setup`.
//!
//! Nothing here allocates, panics on input or waits for ever on the host: a corrupt link frame
//! is counted ([`LinkStats`]) and skipped, bytes a full pipe cannot take are counted in
//! [`HilStats::rx_lost`], and the robot program bounds every transmission and LED update by its
//! own `io_timeout`. Light bytes are handed over as they are: the host's medium applies airtime,
//! collisions and loss to them, and the robot's deframers see what its receivers would.

use core::cell::Cell;
#[cfg(feature = "host-clock")]
use core::cell::RefCell;
use core::convert::Infallible;

use embassy_futures::join::join3;
use embassy_futures::select::{Either, select};
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::mutex::Mutex;
use embassy_sync::pipe::Pipe;
use embassy_sync::signal::Signal;
use embedded_io_async::{ErrorKind, Read, Write};
use protocol::auth::SwarmKey;
use protocol::params::DecisionRule;
use protocol::{Duration, Level, Sector};
use rand_core::RngCore;

use super::{CHUNK_MAX, LINK_FRAME_MAX, LINK_VERSION, LinkDecoder, LinkMsg, LinkStats, Setup};
use crate::hal::{self, Clock, ErrorType, LedColor, Leds, Quantity, Sensor};
use crate::robot::{Config, Hardware, Observer, Robot, SetupError};

/// Bytes of buffer per receiver: four full light frames.
pub const RX_PIPE: usize = 128;

/// The stream of the robot's random draws (`rand_pcg::Pcg32::new(seed, RNG_STREAM)`): every
/// image and the host's in-process robot draw alike from a `Setup`'s seed.
pub const RNG_STREAM: u64 = 0x0a02_bdbf_7bb3_c0a7;

/// How often the robot says `Hello` before its first `Setup`, and the host its `Heartbeat`.
pub const BEAT: Duration = Duration::from_millis(500);

/// Counters of the robot's end of the link. They wrap after 2³² events.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HilStats {
    /// Link frames sent.
    pub sent: u32,
    /// What the decoder saw: frames received and every kind of bad frame.
    pub link: LinkStats,
    /// Light bytes lost because a receiver's pipe was full.
    pub rx_lost: u32,
    /// `Rx` for a sector the robot does not have, or a message only a robot sends.
    pub unexpected: u32,
    /// Errors of the UART (reading or writing).
    pub uart_errors: u32,
    /// `Setup`s received: runs started.
    pub setups: u32,
    /// Messages that found the hold for the next `Sync` full and were taken at once (on the
    /// host's clock; the host sends at most [`HELD`] between two `Sync`s).
    pub held_over: u32,
}

/// Messages a robot on the host's clock holds until the next `Sync` (the host sends at most
/// this many between two).
pub const HELD: usize = 16;

/// What the image's time driver does for a robot whose clock follows the host's (link version
/// 2, `docs/hil.md` "Time"): plain functions, as the driver is the image's one static.
#[cfg(feature = "host-clock")]
#[derive(Clone, Copy, Debug)]
pub struct HostClock {
    /// `true`: stop the own clock, and from now on move only at `set_now`; the time is 0 and
    /// every timer set so far is forgotten (a new run). `false`: the own clock again.
    pub follow: fn(bool),
    /// The time is now `ms`: every timer due by then wakes. The link passes each `Sync`'s
    /// instant as it came, so a host that sends an earlier one gets it here: the driver keeps
    /// the later time (both drivers do: the QEMU image's and the host twin's).
    pub set_now: fn(u64),
    /// The next timer set, milliseconds (`u64::MAX`: none).
    pub next_alarm: fn() -> u64,
}

/// The host-clock state of a [`Link`].
#[cfg(feature = "host-clock")]
struct Follow {
    hooks: HostClock,
    /// The last `Setup` asked for the host's clock.
    on: Cell<bool>,
    /// What came since the last `Sync`, taken at the next.
    held: RefCell<heapless::Deque<LinkMsg, HELD>>,
    /// A `Sync` was taken: the instant the `Idle` owed answers.
    owed: Cell<Option<u32>>,
    /// Everything is done: the beat sends the `Idle` for this instant.
    idle: Signal<NoopRawMutex, u32>,
    /// The swarm key the next `Setup` runs with ([`LinkMsg::Key`]).
    key: Cell<Option<SwarmKey>>,
    /// The swarm key of the last `Setup`.
    run_key: Cell<Option<SwarmKey>>,
}

/// What the robot's hardware shares over one link: `W` is the UART's writing half, `N` the
/// number of receivers.
pub struct Link<W, const N: usize> {
    writer: Mutex<NoopRawMutex, W>,
    pipes: [Pipe<NoopRawMutex, RX_PIPE>; N],
    ambient: Cell<Option<Level>>,
    oxygen: Cell<Option<Level>>,
    setup: Signal<NoopRawMutex, Setup>,
    set_up: Cell<bool>,
    /// What the beat owes the host: the answer to a heartbeat, or a hello it asked for.
    echo: Signal<NoopRawMutex, Answer>,
    stats: Cell<HilStats>,
    #[cfg(feature = "host-clock")]
    follow: Option<Follow>,
}

impl<W, const N: usize> core::fmt::Debug for Link<W, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Link")
            .field("stats", &self.stats.get())
            .finish_non_exhaustive()
    }
}

impl<W: Write, const N: usize> Link<W, N> {
    /// A link writing to `writer` (the UART's transmitting half).
    pub fn new(writer: W) -> Self {
        Link {
            writer: Mutex::new(writer),
            pipes: core::array::from_fn(|_| Pipe::new()),
            ambient: Cell::new(None),
            oxygen: Cell::new(None),
            setup: Signal::new(),
            set_up: Cell::new(false),
            echo: Signal::new(),
            stats: Cell::new(HilStats::default()),
            #[cfg(feature = "host-clock")]
            follow: None,
        }
    }

    /// A link whose robot can follow the host's clock through `hooks` (its `Hello` says so).
    /// The image's executor must call [`on_idle`](Self::on_idle) whenever nothing is left to
    /// run.
    #[cfg(feature = "host-clock")]
    pub fn with_host_clock(writer: W, hooks: HostClock) -> Self {
        let mut link = Self::new(writer);
        link.follow = Some(Follow {
            hooks,
            on: Cell::new(false),
            held: RefCell::new(heapless::Deque::new()),
            owed: Cell::new(None),
            idle: Signal::new(),
            key: Cell::new(None),
            run_key: Cell::new(None),
        });
        link
    }

    /// Called by the image's executor when no task can run and no byte is being written: if a
    /// `Sync` is owed its `Idle`, everything for its instant is done, and the beat sends it.
    #[cfg(feature = "host-clock")]
    pub fn on_idle(&self) {
        if let Some(f) = &self.follow
            && let Some(t) = f.owed.take()
        {
            f.idle.signal(t);
        }
    }

    /// The swarm key of the last `Setup` ([`LinkMsg::Key`]; none without the host's clock).
    fn run_key(&self) -> Option<SwarmKey> {
        #[cfg(feature = "host-clock")]
        return self.follow.as_ref().and_then(|f| f.run_key.get());
        #[cfg(not(feature = "host-clock"))]
        None
    }

    /// True if the robot's clock can follow the host's.
    fn can_follow(&self) -> bool {
        #[cfg(feature = "host-clock")]
        return self.follow.is_some();
        #[cfg(not(feature = "host-clock"))]
        false
    }

    /// A message from the pump: on the host's clock held until its `Sync`, then taken with the
    /// others at that instant; otherwise taken at once.
    fn take(&self, msg: LinkMsg) {
        #[cfg(feature = "host-clock")]
        if let Some(f) = &self.follow
            && (f.on.get() || matches!(&msg, LinkMsg::Setup(s) if s.host_clock))
        {
            // A `Setup` asking for the host's clock is held too, even while the robot is
            // still on its own clock (a freshly booted robot): its program starts at the
            // `Sync`, at the host's time, however the bytes of the `Sync` trickle in.
            f.on.set(true);
            if let LinkMsg::Sync(t) = msg {
                // What was held first (a `Setup` among it starts the clock again at 0), then
                // the time: no task runs in between, so each sees both.
                loop {
                    let next = f.held.borrow_mut().pop_front();
                    let Some(m) = next else { break };
                    self.dispatch(m);
                }
                (f.hooks.set_now)(u64::from(t));
                f.owed.set(Some(t));
            } else if let Err(m) = f.held.borrow_mut().push_back(msg) {
                self.count(|s| s.held_over = s.held_over.wrapping_add(1));
                self.dispatch(m);
            }
            return;
        }
        self.dispatch(msg);
    }

    /// The counters.
    pub fn stats(&self) -> HilStats {
        self.stats.get()
    }

    fn count(&self, f: impl FnOnce(&mut HilStats)) {
        let mut s = self.stats.get();
        f(&mut s);
        self.stats.set(s);
    }

    /// Sends one message as one link frame.
    ///
    /// # Errors
    /// The UART's error kind if it failed.
    pub async fn send(&self, msg: &LinkMsg) -> Result<(), ErrorKind> {
        let mut buf = [0u8; LINK_FRAME_MAX];
        // Cannot fail: every message fits LINK_FRAME_MAX (the codec's tests).
        let frame = super::encode(msg, &mut buf).map_err(|_| ErrorKind::Other)?;
        let mut w = self.writer.lock().await;
        let r = match w.write_all(frame).await {
            Ok(()) => w.flush().await,
            Err(e) => Err(e),
        };
        match r {
            Ok(()) => {
                self.count(|s| s.sent = s.sent.wrapping_add(1));
                Ok(())
            }
            Err(e) => {
                self.count(|s| s.uart_errors = s.uart_errors.wrapping_add(1));
                Err(embedded_io_async::Error::kind(&e))
            }
        }
    }

    /// Reads the UART's receiving half for as long as it gives bytes, and hands each message
    /// to its place. Returns when the stream ends (`Ok(0)`).
    pub async fn pump<R: Read>(&self, mut reader: R) {
        let mut decoder = LinkDecoder::new();
        let mut buf = [0u8; 32];
        loop {
            match reader.read(&mut buf).await {
                Ok(0) => return,
                Ok(n) => {
                    for &b in buf.get(..n).unwrap_or(&[]) {
                        if let Some(Ok(msg)) = decoder.push(b) {
                            self.take(msg);
                        }
                    }
                    let link = *decoder.stats();
                    self.count(|s| s.link = link);
                }
                Err(_) => {
                    // A framing or overrun error: the decoder resynchronises at the next 0x00.
                    // Yield, so that a UART that keeps failing cannot starve the robot.
                    self.count(|s| s.uart_errors = s.uart_errors.wrapping_add(1));
                    embassy_futures::yield_now().await;
                }
            }
        }
    }

    fn dispatch(&self, msg: LinkMsg) {
        match msg {
            LinkMsg::Rx { sector, bytes } => {
                let Some(pipe) = self.pipes.get(usize::from(sector)) else {
                    self.count(|s| s.unexpected = s.unexpected.wrapping_add(1));
                    return;
                };
                // Like light, the host never waits: what does not fit is lost.
                let mut rest = &bytes[..];
                while let Ok(n @ 1..) = pipe.try_write(rest) {
                    rest = rest.get(n..).unwrap_or(&[]);
                }
                let lost = u32::try_from(rest.len()).unwrap_or(u32::MAX);
                self.count(|s| s.rx_lost = s.rx_lost.wrapping_add(lost));
            }
            LinkMsg::Reading { quantity, level } => match quantity {
                0 => self.ambient.set(Some(Level(level))),
                1 => self.oxygen.set(Some(Level(level))),
                _ => self.count(|s| s.unexpected = s.unexpected.wrapping_add(1)),
            },
            LinkMsg::Setup(setup) => {
                self.count(|s| s.setups = s.setups.wrapping_add(1));
                #[cfg(feature = "host-clock")]
                if let Some(f) = &self.follow {
                    // A new run: the clock starts at 0 with no timer (or the own clock again),
                    // with the key given since the last setup, if any.
                    f.on.set(setup.host_clock);
                    (f.hooks.follow)(setup.host_clock);
                    f.run_key.set(f.key.take());
                }
                self.set_up.set(true);
                self.setup.signal(setup);
            }
            #[cfg(feature = "host-clock")]
            LinkMsg::Key(key) => match &self.follow {
                Some(f) => f.key.set(Some(key)),
                None => self.count(|s| s.unexpected = s.unexpected.wrapping_add(1)),
            },
            // Answered by the beat, at once.
            LinkMsg::Heartbeat(seq) => self.echo.signal(Answer::Beat(seq)),
            // The host asks who this is (it connected to a robot that may be running already).
            LinkMsg::Hello { .. } => self.echo.signal(Answer::Hello),
            LinkMsg::Tx(_) | LinkMsg::Led(_) | LinkMsg::Refused(_) => {
                self.count(|s| s.unexpected = s.unexpected.wrapping_add(1));
            }
            // A `Sync` reaches here only on the own clock: nothing to do.
            #[cfg(feature = "host-clock")]
            LinkMsg::Sync(_) | LinkMsg::Idle { .. } => {
                self.count(|s| s.unexpected = s.unexpected.wrapping_add(1));
            }
        }
    }

    /// Says `Hello` every [`BEAT`] until the first `Setup`; from then on answers each of the
    /// host's heartbeats at once with its number (the host measures the link's round trip,
    /// and a robot that stops answering is one that stopped), and each `Hello` of the host's
    /// with its own, for ever.
    pub async fn beat<C: Clock>(&self, clock: &C, id: u16) -> Infallible {
        let hello = LinkMsg::Hello {
            version: LINK_VERSION,
            id,
            sectors: N as u8,
            host_clock: self.can_follow(),
        };
        let mut next = clock.now();
        // A heartbeat that came while it waited for its setup, answered once set up.
        let mut owed = None;
        loop {
            // A failed write is counted; the next beat tries again.
            if self.set_up.get() {
                let answer = match owed.take() {
                    Some(a) => a,
                    None => self.answer().await,
                };
                let answer = match answer {
                    Answer::Beat(seq) => LinkMsg::Heartbeat(seq),
                    Answer::Hello => hello.clone(),
                    #[cfg(feature = "host-clock")]
                    Answer::Idle(now) => LinkMsg::Idle {
                        now,
                        // A timer beyond u32::MAX ms is none in a run.
                        next: self.follow.as_ref().map_or(u32::MAX, |f| {
                            u32::try_from((f.hooks.next_alarm)()).unwrap_or(u32::MAX)
                        }),
                    },
                };
                let _ = self.send(&answer).await;
            } else {
                // Once the setup came the sleep is not polled again: it never ends, and the
                // answer owed (a heartbeat's, or the first `Idle`) ends the select. (The pump,
                // the beat and the program are one task: every byte the pump takes polls this
                // select again. Polled after a setup for the host's clock, the sleep would set
                // its own clock's next beat as a timer on the host's clock, at an instant that
                // depends on how long the robot waited for its setup in wall time, and the host
                // would send a `Sync` at it.)
                let mut sleep = core::pin::pin!(clock.sleep_until(next));
                let sleep = core::future::poll_fn(|cx| {
                    if self.set_up.get() {
                        core::task::Poll::Pending
                    } else {
                        sleep.as_mut().poll(cx)
                    }
                });
                match select(self.answer(), sleep).await {
                    Either::Second(()) => {
                        let _ = self.send(&hello).await;
                        next += BEAT;
                    }
                    Either::First(Answer::Hello) => {
                        let _ = self.send(&hello).await;
                    }
                    // The setup's first heartbeat (or `Idle`), which woke it: answered at once.
                    Either::First(beat) => owed = Some(beat),
                }
            }
        }
    }

    /// What the beat owes the host next: a heartbeat's answer, a hello, or (on the host's clock)
    /// an `Idle`.
    #[cfg(feature = "host-clock")]
    async fn answer(&self) -> Answer {
        if let Some(f) = &self.follow {
            return match select(self.echo.wait(), f.idle.wait()).await {
                Either::First(a) => a,
                Either::Second(now) => Answer::Idle(now),
            };
        }
        self.echo.wait().await
    }

    /// What the beat owes the host next: a heartbeat's answer or a hello. (Not an `async fn`
    /// of its own: that state machine cost the Nucleo image in the loop 158 B.)
    #[cfg(not(feature = "host-clock"))]
    fn answer(&self) -> impl core::future::Future<Output = Answer> + '_ {
        self.echo.wait()
    }

    /// The robot's hardware over this link, with `clock`.
    pub fn hardware<C: Clock>(
        &self,
        clock: C,
    ) -> Hardware<HilTransmitter<'_, W, N>, Pipes<'_, N>, HilSensor<'_, W, N>, HilLeds<'_, W, N>, C>
    {
        Hardware {
            transmitter: HilTransmitter { link: self },
            receivers: core::array::from_fn(|i| &self.pipes[i]),
            sensor: HilSensor { link: self },
            leds: HilLeds { link: self },
            clock,
        }
    }
}

/// The receivers of a robot in the loop: one pipe per sector, fed by the pump.
pub type Pipes<'a, const N: usize> = [&'a Pipe<NoopRawMutex, RX_PIPE>; N];

/// What the beat owes the host.
#[derive(Clone, Copy, Debug)]
enum Answer {
    /// The answer to heartbeat `seq`.
    Beat(u32),
    /// A `Hello`, asked for.
    Hello,
    /// On the host's clock: everything up to this instant is done.
    #[cfg(feature = "host-clock")]
    Idle(u32),
}

/// `base` with what `setup` sets: id, timing, decision rule, sample period.
pub fn configure(base: Config, setup: &Setup) -> Config {
    let mut c = base;
    c.id = setup.id;
    let ms = |v: u32| Duration::from_millis(u64::from(v));
    c.params.wave.cycle = ms(setup.cycle_ms);
    c.params.wave.cycle_spread = ms(setup.spread_ms);
    c.params.wave.relay_delay = ms(setup.relay_ms);
    c.params.wave.refractory = ms(setup.refractory_ms);
    c.params.negotiation_cycles = setup.negotiation;
    c.params.decide = if setup.adaptive {
        DecisionRule::Adaptive
    } else {
        DecisionRule::Fixed
    };
    c.sample_period = ms(setup.sample_ms);
    c
}

/// Runs a robot in the loop for ever: the pump over `reader`, the beat, and the robot program
/// with `base` as [`configure`]d by each `Setup`, its random draws from `rng(setup.seed)`,
/// telling `observer` what it tells a robot's (the Nucleo image feeds its watchdog there). The
/// robot program starts afresh (new state, empty receivers) at every `Setup`; a `Setup` the
/// program refuses (bad timing) is logged and the robot waits for the next.
pub async fn run<W, R, C, G, O, const N: usize>(
    link: &Link<W, N>,
    reader: R,
    clock: &C,
    base: Config,
    mut rng: impl FnMut(u32) -> G,
    observer: &mut O,
) -> Infallible
where
    W: Write,
    R: Read,
    C: Clock,
    G: RngCore,
    O: Observer,
{
    let robot = async {
        let mut setup = link.setup.wait().await;
        loop {
            for p in &link.pipes {
                p.clear();
            }
            let mut config = configure(base, &setup);
            // The run's swarm key, else the image's own (none for the QEMU images).
            if let Some(key) = link.run_key() {
                config.key = Some(key);
            }
            // The image's receivers are what it has, whatever its configuration says.
            config.params.sectors = N as u8;
            let robot = if setup.host_clock && !link.can_follow() {
                Err(REFUSED_HOST_CLOCK)
            } else {
                Robot::<G, N>::new(config, clock.now(), rng(setup.seed)).map_err(refusal_code)
            };
            match robot {
                Ok(mut robot) => {
                    info!("hil: robot {} starts", config.id);
                    let mut hw = link.hardware(clock);
                    // The next setup first: a robot program woken with it does not run again.
                    match select(link.setup.wait(), robot.run_observed(&mut hw, observer)).await {
                        Either::First(next) => setup = next,
                        Either::Second(never) => match never {},
                    }
                }
                Err(code) => {
                    warn!("hil: setup refused (code {})", code);
                    let _ = link.send(&LinkMsg::Refused(code)).await;
                    setup = link.setup.wait().await;
                }
            }
        }
    };
    let pump = async {
        link.pump(reader).await;
        warn!("hil: the link's stream ended");
        core::future::pending::<Infallible>().await
    };
    let (never, _, _) = join3(robot, pump, link.beat(clock, base.id)).await;
    never
}

/// [`LinkMsg::Refused`]'s code for why the robot program refused a setup.
pub fn refusal_code(e: SetupError) -> u8 {
    match e {
        SetupError::Params(_) => 1,
        SetupError::Receivers { .. } => 2,
        SetupError::ZeroDuration => 3,
        SetupError::KeyedFramingNotBuilt => 4,
    }
}

/// [`LinkMsg::Refused`]'s code for a `Setup` asking for the host's clock from a robot that
/// cannot follow it (its `Hello` said so).
pub const REFUSED_HOST_CLOCK: u8 = 5;

/// The light transmitter over the link: each write goes to the host as `Tx` messages of at most
/// [`CHUNK_MAX`] bytes (a light frame is one).
pub struct HilTransmitter<'a, W, const N: usize> {
    link: &'a Link<W, N>,
}

impl<W: Write, const N: usize> embedded_io_async::ErrorType for HilTransmitter<'_, W, N> {
    type Error = ErrorKind;
}

impl<W: Write, const N: usize> Write for HilTransmitter<'_, W, N> {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        let n = buf.len().min(CHUNK_MAX);
        let chunk =
            heapless::Vec::from_slice(buf.get(..n).unwrap_or(&[])).map_err(|_| ErrorKind::Other)?;
        self.link.send(&LinkMsg::Tx(chunk)).await?;
        Ok(n)
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

/// The sensor over the link: the last level the host sent for each quantity
/// ([`hal::ErrorKind::NotReady`] before the first).
pub struct HilSensor<'a, W, const N: usize> {
    link: &'a Link<W, N>,
}

impl<W, const N: usize> ErrorType for HilSensor<'_, W, N> {
    type Error = hal::ErrorKind;
}

impl<W, const N: usize> Sensor for HilSensor<'_, W, N> {
    async fn ambient_light(&mut self) -> Result<Level, hal::ErrorKind> {
        self.link.ambient.get().ok_or(hal::ErrorKind::NotReady)
    }

    async fn oxygen(&mut self) -> Result<Level, hal::ErrorKind> {
        self.link.oxygen.get().ok_or(hal::ErrorKind::NotReady)
    }

    async fn read(&mut self, quantity: Quantity) -> Result<Level, hal::ErrorKind> {
        match quantity {
            Quantity::AmbientLight => self.ambient_light().await,
            Quantity::Oxygen => self.oxygen().await,
        }
    }
}

/// The LEDs over the link: each change goes to the host as `Led` (0 off, `1 + sector`).
pub struct HilLeds<'a, W, const N: usize> {
    link: &'a Link<W, N>,
}

impl<W, const N: usize> ErrorType for HilLeds<'_, W, N> {
    type Error = hal::ErrorKind;
}

impl<W: Write, const N: usize> Leds for HilLeds<'_, W, N> {
    async fn show(&mut self, color: LedColor) -> Result<(), hal::ErrorKind> {
        let code = led_code(color);
        self.link
            .send(&LinkMsg::Led(code))
            .await
            .map_err(|_| hal::ErrorKind::Bus)
    }
}

/// The `Led` code of `color`: 0 off, `1 + sector` a decision (green is left, sector 1).
pub fn led_code(color: LedColor) -> u8 {
    match color.decision() {
        None => 0,
        Some(s) => s.index().saturating_add(1),
    }
}

/// The decision an `Led` code shows (`None`: off, or a code that is no sector).
pub fn led_decision(code: u8) -> Option<Sector> {
    code.checked_sub(1).and_then(Sector::new)
}
