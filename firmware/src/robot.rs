//! The robot program: fused CIMAX ([`protocol::FusedNode`]) bound to the [hardware traits](crate::hal).
//!
//! [`Robot::run`] is one `async fn`, one loop (no tasks, no spawning, no `'static`):
//!
//! ```text
//!  receivers ──(sector, bytes)──▶ deframer[sector] ──(message | frame error)──┐
//!  (one future over every sector,                                              │
//!   hal::Receivers)                                                            ▼
//!  sensor ──every sample_period──▶ main loop: FusedNode ──poll_transmit──▶ encode ──▶ transmitter
//!                                   │  sleeps until a receiver has bytes or
//!                                   │  min(poll_timeout, next sample) is reached
//!                                   └──Event::Decided──▶ LEDs
//! ```
//!
//! With a swarm key ([`Config::key`], feature `keyed`) the deframers are keyed
//! (`Deframer::with_key`): frames without the swarm's MAC are dropped and counted in
//! [`Stats::bad_mac`] before the protocol sees them, and `encode` is `encode_keyed`.
//!
//! The loop waits on "a receiver has something OR the next deadline" with
//! [`embassy_futures::select`], which works the same under embassy and tokio; so a read of
//! the [`Receivers`] must be cancel-safe. The bytes of one read go through their sector's
//! deframer one message at a time: each message is handled, and what it makes the protocol
//! send is sent, before the next is deframed. A receiver that fails is not read for
//! [`Config::rx_error_backoff`]; one whose stream ended is not read again.
//!
//! # What it never does
//! - panic on input: a corrupt frame, a receiver error, a failed or hung sensor, LED or
//!   transmitter is counted in [`Stats`], logged, and the robot carries on;
//! - block for ever: every transmission, sensor read and LED update is bounded by
//!   [`Config::io_timeout`] on the robot's own [`Clock`];
//! - allocate, spawn, or touch global state: everything lives in [`Robot`] and the future
//!   returned by [`Robot::run`] (whose size is fixed at compile time).
//!
//! The hardware traits' futures need not be `Send`: run the robot on an embassy executor,
//! with `block_on`, or under tokio on a `LocalSet` or current-thread runtime.

use core::convert::Infallible;
use core::future::Future;
use core::pin::pin;

use embassy_futures::select::{Either, select};
use embedded_io_async::{Error as _, Write};
use protocol::frame::{Deframer, FrameError, KEYED_MAX_HOPS, encode};
use protocol::fused::{AnyRule, Rule};
use protocol::{
    Duration, Event, FusedNode, Instant, Message, ParamError, Params, Sector, SwarmKey, Tag,
    Variance,
};
use rand_core::RngCore;

use crate::hal::{Clock, Error as _, LedColor, Leds, Quantity, Receivers, Sensor};

/// Bytes the robot asks its receivers for at a time: a whole light frame.
const RX_CHUNK: usize = 32;

/// How a robot runs, beyond the protocol's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// The robot's number: in the logs, and its tag on the wire (`id mod 16`,
    /// [`Tag::from_id`]), which it writes into every hop it adds and by which it recognises
    /// (and drops) messages that passed through it already, and by which its neighbours follow
    /// it. Robots within 8 hops of each other must differ in `id mod 16`: number a line in
    /// order (`docs/protocol.md` §5.3).
    pub id: u16,
    /// The protocol's parameters; `params.sectors` must equal the number of receivers.
    pub params: Params,
    /// The sensor reading CIMAX uses.
    pub quantity: Quantity,
    /// How often the sensor is read.
    pub sample_period: Duration,
    /// Longest wait for one transmission, sensor read or LED update before it counts as failed.
    pub io_timeout: Duration,
    /// Pause after a receiver error before reading that receiver again.
    pub rx_error_backoff: Duration,
    /// The swarm key, if the swarm authenticates its frames: every frame sent carries its MAC
    /// tag (`protocol::frame::encode_keyed`, feature `keyed`) and every frame received without a valid one is
    /// dropped and counted ([`Stats::bad_mac`]). A keyed frame holds one hop fewer, so
    /// [`Robot::new`] lowers `params.max_hops` to [`KEYED_MAX_HOPS`] (11). `None`: plain
    /// frames, checked by CRC.
    pub key: Option<SwarmKey>,
}

impl Config {
    /// The aMussel lab: [`Params::robots`], ambient light sampled every second, 500 ms I/O
    /// timeout, 100 ms back-off after a receiver error, no swarm key.
    pub const fn robots() -> Config {
        Config {
            id: 0,
            params: Params::robots(),
            quantity: Quantity::AmbientLight,
            sample_period: Duration::from_secs(1),
            io_timeout: Duration::from_millis(500),
            rx_error_backoff: Duration::from_millis(100),
            key: None,
        }
    }
}

impl Default for Config {
    fn default() -> Self {
        Config::robots()
    }
}

/// Why a [`Robot`] could not be set up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SetupError {
    /// The protocol's parameters do not validate.
    Params(ParamError),
    /// `params.sectors` differs from the number of receivers.
    Receivers {
        /// Sectors in the parameters.
        sectors: u8,
        /// Receivers of the robot.
        receivers: usize,
    },
    /// The sample period, the I/O timeout or the receiver back-off is zero (the robot could
    /// spin without ever sleeping).
    ZeroDuration,
    /// A swarm key was given to a firmware built without the `keyed` feature, which would
    /// send plain frames the keyed swarm drops.
    KeyedFramingNotBuilt,
}

impl From<ParamError> for SetupError {
    fn from(e: ParamError) -> Self {
        SetupError::Params(e)
    }
}

impl core::fmt::Display for SetupError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SetupError::Params(e) => write!(f, "bad protocol parameters: {e}"),
            SetupError::Receivers { sectors, receivers } => {
                write!(
                    f,
                    "{sectors} sectors configured but {receivers} receivers given"
                )
            }
            SetupError::ZeroDuration => {
                f.write_str("the sample period, I/O timeout and receiver back-off must be positive")
            }
            SetupError::KeyedFramingNotBuilt => {
                f.write_str("a swarm key needs the firmware's `keyed` feature")
            }
        }
    }
}

impl core::error::Error for SetupError {}

/// Counters kept by a [`Robot`]. They wrap after 2³² events.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Stats {
    /// Messages decoded and handed to the protocol.
    pub messages: u32,
    /// Corrupt frames (every [`FrameError`] a deframer reported, [`FrameError::BadMac`]
    /// included).
    pub frame_errors: u32,
    /// Frames dropped because their MAC tag did not verify ([`FrameError::BadMac`], robots with
    /// a [`Config::key`] only): sent without the swarm key or with another one, forged, or
    /// corrupted on the way. Also counted in `frame_errors`.
    pub bad_mac: u32,
    /// Errors reported by a receiver.
    pub rx_errors: u32,
    /// Receivers that reported the end of their stream (`Ok(0)`); they are not read again.
    pub rx_closed: u32,
    /// Frames transmitted.
    pub transmitted: u32,
    /// Transmissions that failed or timed out.
    pub tx_errors: u32,
    /// Sensor reads that failed or timed out; the previous reading is kept.
    pub sensor_errors: u32,
    /// LED updates that failed or timed out.
    pub led_errors: u32,
    /// Decisions taken (negotiation periods completed).
    pub decisions: u32,
}

/// The hardware one robot runs on. Receiver `i` faces sector `i`: with two sectors,
/// `receivers[0]` is the right one ([`Sector::RIGHT`]) and `receivers[1]` the left one; use
/// [`Hardware::line`] to avoid getting them the wrong way round.
#[derive(Debug)]
pub struct Hardware<T, R, S, L, C> {
    /// The broadcasting light transmitter.
    pub transmitter: T,
    /// The light receivers, one per sector ([`Receivers`]): an array of byte streams indexed
    /// by sector, or a board's one source for all of them.
    pub receivers: R,
    /// The environmental sensor.
    pub sensor: S,
    /// The top-cap LEDs.
    pub leds: L,
    /// The clock.
    pub clock: C,
}

impl<T, R, S, L, C> Hardware<T, [R; 2], S, L, C> {
    /// The hardware of a robot in a line: one receiver facing left, one facing right.
    pub fn line(transmitter: T, left: R, right: R, sensor: S, leds: L, clock: C) -> Self {
        // Receivers are indexed by sector.
        const _: () = assert!(Sector::RIGHT.index() == 0 && Sector::LEFT.index() == 1);
        Hardware {
            transmitter,
            receivers: [right, left],
            sensor,
            leds,
            clock,
        }
    }
}

/// What the receivers gave the main loop.
enum Inbound {
    Message(Sector, Message),
    Corrupt(Sector, FrameError),
    RxError(Sector, embedded_io_async::ErrorKind),
    Closed(Sector),
}

/// The receiving side of a running robot: one deframer per sector, and the bytes of the last
/// read not yet deframed.
struct Rx<const N: usize> {
    deframers: [Deframer; N],
    buf: [u8; RX_CHUNK],
    /// `buf[at..len]` came from sector `from` and is still to be deframed.
    at: usize,
    len: usize,
    from: usize,
    /// Sectors still read (bit `i` for sector `i`): a receiver whose stream ended is not.
    open: u8,
    /// Per sector, when a receiver that failed is read again.
    resume: [Instant; N],
}

impl<const N: usize> Rx<N> {
    fn new(config: &Config) -> Self {
        Rx {
            deframers: core::array::from_fn(|_| match config.key {
                #[cfg(feature = "keyed")]
                Some(key) => Deframer::with_key(key),
                // Without `keyed`, `Robot::new` refused every key.
                _ => Deframer::new(),
            }),
            buf: [0; RX_CHUNK],
            at: 0,
            len: 0,
            from: 0,
            // `validate` checked N <= MAX_SECTORS (8).
            open: (0..N).fold(0, |m, i| m | bit(i)),
            resume: [Instant::ZERO; N],
        }
    }

    /// The next message or frame error in the bytes read, if they hold one.
    fn next(&mut self) -> Option<Inbound> {
        let from = sector(self.from);
        let deframer = self.deframers.get_mut(self.from)?;
        let (out, rest) = deframer.feed(self.buf.get(self.at..self.len)?);
        self.at = self.len - rest.len();
        match out? {
            Ok(msg) => Some(Inbound::Message(from, msg)),
            Err(e) => Some(Inbound::Corrupt(from, e)),
        }
    }

    /// The sectors to read at `now`: open ones, not resting after an error.
    fn sectors(&self, now: Instant) -> u8 {
        (0..N).fold(self.open, |m, i| {
            if self.resume.get(i).is_some_and(|&t| t > now) {
                m & !bit(i)
            } else {
                m
            }
        })
    }

    /// When the next resting receiver is read again, after `now` ([`Instant::MAX`]: none).
    fn next_resume(&self, now: Instant) -> Instant {
        self.resume
            .iter()
            .copied()
            .filter(|&t| t > now)
            .min()
            .unwrap_or(Instant::MAX)
    }

    /// Waits until the receivers give something to handle (a message, a frame error, a
    /// receiver's error or end) or `deadline` comes (`None`; also when a resting receiver is
    /// to be read again). One wait on the clock for all the reads it takes.
    async fn receive<R: Receivers, C: Clock>(
        &mut self,
        receivers: &mut R,
        clock: &C,
        deadline: Instant,
        backoff: Duration,
    ) -> Option<Inbound> {
        if let Some(inbound) = self.next() {
            return Some(inbound);
        }
        let now = clock.now();
        let mut sleep = pin!(clock.sleep_until(deadline.min(self.next_resume(now))));
        loop {
            let read = receivers.read(self.sectors(clock.now()), &mut self.buf);
            let (i, got) = match select(read, sleep.as_mut()).await {
                Either::First(got) => got,
                Either::Second(()) => return None,
            };
            let from = sector(i);
            match got {
                Ok(0) => {
                    self.open &= !bit(i);
                    return Some(Inbound::Closed(from));
                }
                Ok(n) => {
                    // `min`: a driver claiming more bytes than the buffer holds cannot panic us.
                    (self.at, self.len, self.from) = (0, n.min(RX_CHUNK), i);
                    if let Some(inbound) = self.next() {
                        return Some(inbound);
                    }
                }
                Err(e) => {
                    if let Some(d) = self.deframers.get_mut(i) {
                        d.resync();
                    }
                    if let Some(t) = self.resume.get_mut(i) {
                        *t = clock.now() + backoff;
                    }
                    return Some(Inbound::RxError(from, e.kind()));
                }
            }
        }
    }
}

/// Sector `i`'s bit in a mask of sectors (none beyond the eighth).
fn bit(i: usize) -> u8 {
    if i < 8 { 1 << i } else { 0 }
}

/// Sector `i` (receivers are indexed by sector; `Robot::new` checked there are at most
/// [`protocol::MAX_SECTORS`]).
fn sector(i: usize) -> Sector {
    u8::try_from(i)
        .ok()
        .and_then(Sector::new)
        .unwrap_or(Sector::RIGHT)
}

/// One robot: its protocol node, randomness and counters. Everything it knows lives here, so
/// any number of robots can share a process.
///
/// `Rl` is the decision rule: by default the one `config.params.decide` names, chosen at run
/// time ([`AnyRule`]); an image that ships one rule names it ([`protocol::fused::Adaptive`] on
/// the Nucleo) and carries no other rule's code.
#[derive(Debug)]
pub struct Robot<G: RngCore, const N: usize, Rl: Rule = AnyRule> {
    config: Config,
    node: FusedNode<Variance, Rl>,
    rng: G,
    stats: Stats,
    shown: Option<LedColor>,
}

impl<G: RngCore, const N: usize, Rl: Rule> Robot<G, N, Rl> {
    /// A robot with `N` receivers whose protocol starts its first cycle at `now` (take it from
    /// the clock the robot will run on).
    ///
    /// # Errors
    /// A [`SetupError`] if the parameters do not validate, `params.sectors != N`, or a
    /// duration of the configuration is zero.
    pub fn new(config: Config, now: Instant, mut rng: G) -> Result<Self, SetupError> {
        if usize::from(config.params.sectors) != N {
            return Err(SetupError::Receivers {
                sectors: config.params.sectors,
                receivers: N,
            });
        }
        let durations = [
            config.sample_period,
            config.io_timeout,
            config.rx_error_backoff,
        ];
        if durations.contains(&Duration::ZERO) {
            return Err(SetupError::ZeroDuration);
        }
        if config.key.is_some() && !cfg!(feature = "keyed") {
            return Err(SetupError::KeyedFramingNotBuilt);
        }
        let mut params = config.params;
        if config.key.is_some() {
            // What a keyed frame holds: relays never build a message encode_keyed refuses.
            params.max_hops = params.max_hops.min(KEYED_MAX_HOPS as u8);
        }
        let node = FusedNode::with_rule(params, Tag::from_id(config.id), Variance, now, &mut rng)?;
        Ok(Robot {
            config,
            node,
            rng,
            stats: Stats::default(),
            shown: None,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The protocol node (preference, decision, its own counters).
    pub fn node(&self) -> &FusedNode<Variance, Rl> {
        &self.node
    }

    /// The counters.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// The decision of the last completed negotiation period.
    pub fn decision(&self) -> Option<Sector> {
        self.node.decision()
    }

    /// What the LEDs were last set to successfully (`None` before the first decision).
    pub fn shown(&self) -> Option<LedColor> {
        self.shown
    }

    /// Runs the robot on `hw` for ever; [`run_observed`](Self::run_observed) without an
    /// observer.
    pub async fn run<T, R, S, L, C>(&mut self, hw: &mut Hardware<T, R, S, L, C>) -> Infallible
    where
        T: Write,
        R: Receivers,
        S: Sensor,
        L: Leds,
        C: Clock,
    {
        self.run_observed(hw, &mut ()).await
    }

    /// Runs the robot on `hw` for ever, telling `observer` every protocol event (wave state
    /// changes, preference changes, decisions) with its time: for traces and test harnesses.
    ///
    /// `hw.receivers` has the robot's `N` sectors (an array of `N` byte streams, or a board's
    /// source for them); a sector beyond them is never asked for.
    ///
    /// To stop it (tests, emulation, a supervisor), drop the future, e.g. by racing it against
    /// something else with `select`; the robot keeps its state and counters and may be run
    /// again (bytes read but not yet deframed at that moment are lost). See the
    /// [module docs](self) for what it does.
    pub async fn run_observed<T, R, S, L, C, O>(
        &mut self,
        hw: &mut Hardware<T, R, S, L, C>,
        observer: &mut O,
    ) -> Infallible
    where
        T: Write,
        R: Receivers,
        S: Sensor,
        L: Leds,
        C: Clock,
        O: Observer,
    {
        let Hardware {
            transmitter,
            receivers,
            sensor,
            leds,
            clock,
        } = hw;
        let mut main = Main {
            config: &self.config,
            node: &mut self.node,
            rng: &mut self.rng,
            stats: &mut self.stats,
            shown: &mut self.shown,
            observer,
        };
        let mut rx = Rx::<N>::new(main.config);
        main.run(transmitter, receivers, &mut rx, sensor, leds, &*clock)
            .await
    }
}

/// Awaits `f` for at most `timeout` on `clock`; `None` if it took longer (and was dropped).
async fn within<C: Clock, F: Future>(clock: &C, timeout: Duration, f: F) -> Option<F::Output> {
    let deadline = clock.now() + timeout;
    match select(f, clock.sleep_until(deadline)).await {
        Either::First(out) => Some(out),
        Either::Second(()) => None,
    }
}

/// Why a frame did not go out.
#[derive(Debug)]
// Only the logs read the kind (through `Debug`, which dead-code analysis ignores).
#[allow(dead_code)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum TxError {
    Io(embedded_io_async::ErrorKind),
    /// The transmitter accepted no byte.
    Stalled,
}

/// Writes all of `bytes` and flushes. Unlike `Write::write_all`, a transmitter that accepts
/// nothing is an error, not a panic.
async fn send_frame<T: Write>(tx: &mut T, mut bytes: &[u8]) -> Result<(), TxError> {
    while !bytes.is_empty() {
        match tx.write(bytes).await {
            Ok(0) => return Err(TxError::Stalled),
            Ok(n) => bytes = bytes.get(n..).unwrap_or(&[]),
            Err(e) => return Err(TxError::Io(e.kind())),
        }
    }
    tx.flush().await.map_err(|e| TxError::Io(e.kind()))
}

/// Sees every protocol event of a running robot (see [`Robot::run_observed`]).
pub trait Observer {
    /// `event` happened at `now`.
    fn event(&mut self, now: Instant, event: &Event);

    /// `event` happened at `now` in `node`, whose state (reading, diversity per sector) an
    /// observer may read: a trace records the scores behind a decision. The default passes
    /// the event to [`event`](Self::event).
    fn event_at<Rl: Rule>(&mut self, now: Instant, event: &Event, node: &FusedNode<Variance, Rl>) {
        let _ = node;
        self.event(now, event);
    }

    /// The main loop finished one round at `now`: it sampled the sensor if due, ran the
    /// protocol's timers, sent what was queued and updated the LEDs, each step bounded by
    /// [`Config::io_timeout`]. It comes round at least every [`Config::sample_period`] plus
    /// those timeouts, so a watchdog fed here (the Nucleo image's IWDG) bites only when the
    /// robot stops making progress: a driver that spins, a task that never yields, a fault.
    fn progress(&mut self, now: Instant) {
        let _ = now;
    }
}

/// No observer.
impl Observer for () {
    fn event(&mut self, _: Instant, _: &Event) {}
}

/// The robot's main loop, borrowing the robot's state while it runs.
struct Main<'r, G, O, Rl: Rule> {
    config: &'r Config,
    node: &'r mut FusedNode<Variance, Rl>,
    rng: &'r mut G,
    stats: &'r mut Stats,
    shown: &'r mut Option<LedColor>,
    observer: &'r mut O,
}

impl<G: RngCore, O: Observer, Rl: Rule> Main<'_, G, O, Rl> {
    async fn run<T: Write, R: Receivers, S: Sensor, L: Leds, C: Clock, const N: usize>(
        &mut self,
        tx: &mut T,
        receivers: &mut R,
        rx: &mut Rx<N>,
        sensor: &mut S,
        leds: &mut L,
        clock: &C,
    ) -> Infallible {
        let id = self.config.id;
        info!(
            "robot {}: running, tag {}, {} receivers, {} frames",
            id,
            self.node.tag().index(),
            self.config.params.sectors,
            if self.config.key.is_some() {
                "authenticated"
            } else {
                "plain"
            }
        );
        let mut next_sample = clock.now();
        loop {
            if clock.now() >= next_sample {
                self.sample(sensor, clock).await;
                next_sample = clock.now() + self.config.sample_period;
            }
            self.node.handle_timeout(clock.now(), self.rng);
            self.drain(tx, leds, clock).await;
            self.observer.progress(clock.now());

            let now = clock.now();
            // At least a millisecond ahead: everything due up to `now` has just been done.
            let wake_at = self
                .node
                .poll_timeout()
                .min(next_sample)
                .max(now + Duration::from_millis(1));
            let backoff = self.config.rx_error_backoff;
            if let Some(inbound) = rx.receive(receivers, clock, wake_at, backoff).await {
                self.receive(inbound, clock);
            }
        }
    }

    async fn sample<S: Sensor, C: Clock>(&mut self, sensor: &mut S, clock: &C) {
        let id = self.config.id;
        match within(
            clock,
            self.config.io_timeout,
            sensor.read(self.config.quantity),
        )
        .await
        {
            Some(Ok(level)) => {
                if level != self.node.reading() {
                    debug!("robot {}: reading {}", id, level.0);
                }
                self.node.handle_reading(level);
            }
            Some(Err(e)) => {
                self.stats.sensor_errors = self.stats.sensor_errors.wrapping_add(1);
                warn!("robot {}: sensor error {:?}", id, e.kind());
            }
            None => {
                self.stats.sensor_errors = self.stats.sensor_errors.wrapping_add(1);
                warn!("robot {}: sensor timed out", id);
            }
        }
    }

    fn receive<C: Clock>(&mut self, inbound: Inbound, clock: &C) {
        let id = self.config.id;
        match inbound {
            Inbound::Message(from, msg) => {
                self.stats.messages = self.stats.messages.wrapping_add(1);
                let r = self.node.handle_message(clock.now(), from, &msg, self.rng);
                debug!("robot {}: {} hops from {:?}: {:?}", id, msg.len(), from, r);
            }
            Inbound::Corrupt(from, e) => {
                self.stats.frame_errors = self.stats.frame_errors.wrapping_add(1);
                if e == FrameError::BadMac {
                    self.stats.bad_mac = self.stats.bad_mac.wrapping_add(1);
                    warn!("robot {}: frame from {:?} dropped: bad MAC", id, from);
                } else {
                    warn!("robot {}: corrupt frame from {:?}: {:?}", id, from, e);
                }
            }
            Inbound::RxError(from, kind) => {
                self.stats.rx_errors = self.stats.rx_errors.wrapping_add(1);
                warn!("robot {}: receiver {:?} error {:?}", id, from, kind);
            }
            Inbound::Closed(from) => {
                self.stats.rx_closed = self.stats.rx_closed.wrapping_add(1);
                warn!("robot {}: receiver {:?} closed", id, from);
            }
        }
    }

    /// Sends what the protocol wants sent and shows its decisions.
    async fn drain<T: Write, L: Leds, C: Clock>(&mut self, tx: &mut T, leds: &mut L, clock: &C) {
        let id = self.config.id;
        let timeout = self.config.io_timeout;
        while let Some(msg) = self.node.poll_transmit() {
            let framed = match &self.config.key {
                #[cfg(feature = "keyed")]
                Some(key) => protocol::frame::encode_keyed(&msg, key),
                // Without `keyed`, `Robot::new` refused every key.
                _ => encode(&msg),
            };
            let frame = match framed {
                Ok(frame) => frame,
                Err(e) => {
                    self.stats.tx_errors = self.stats.tx_errors.wrapping_add(1);
                    warn!("robot {}: cannot frame: {:?}", id, e);
                    continue;
                }
            };
            match within(clock, timeout, send_frame(tx, &frame)).await {
                Some(Ok(())) => {
                    self.stats.transmitted = self.stats.transmitted.wrapping_add(1);
                    debug!("robot {}: sent {} hops", id, msg.len());
                }
                Some(Err(e)) => {
                    self.stats.tx_errors = self.stats.tx_errors.wrapping_add(1);
                    warn!("robot {}: transmitter error {:?}", id, e);
                }
                None => {
                    self.stats.tx_errors = self.stats.tx_errors.wrapping_add(1);
                    warn!("robot {}: transmitter timed out", id);
                }
            }
        }
        while let Some(event) = self.node.poll_event() {
            self.observer.event_at(clock.now(), &event, self.node);
            let Event::Decided {
                period,
                decision,
                votes,
                ..
            } = event
            else {
                continue;
            };
            self.stats.decisions = self.stats.decisions.wrapping_add(1);
            let k = usize::from(self.config.params.sectors).min(votes.len());
            let color = LedColor::for_decision_of(decision, self.config.params.sectors);
            info!(
                "robot {}: period {} decided {:?} ({:?}), votes {:?}",
                id,
                period,
                decision,
                color,
                &votes[..k]
            );
            match within(clock, timeout, leds.show(color)).await {
                Some(Ok(())) => *self.shown = Some(color),
                Some(Err(e)) => {
                    self.stats.led_errors = self.stats.led_errors.wrapping_add(1);
                    warn!("robot {}: LED error {:?}", id, e.kind());
                }
                None => {
                    self.stats.led_errors = self.stats.led_errors.wrapping_add(1);
                    warn!("robot {}: LEDs timed out", id);
                }
            }
        }
    }
}
