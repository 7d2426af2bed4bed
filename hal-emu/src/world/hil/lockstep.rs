//! Robots in the loop on the arena's clock (link version 2, `docs/hil.md` "Time"): conservative
//! lockstep, as BabbleSim blocks a node until the simulated medium answers.
//!
//! The run's tasks (virtual robots, medium, schedule, and one bridge per robot in the loop) run
//! on the timeline's own executor. When none can run at instant `T`, the executor asks the
//! [`Lockstep`] to settle ([`Gate::settle`]): it sends each follower what its bridge queued for
//! it since its last `Sync` (at most [`HELD`] − 1 messages) and `Sync(T)`, if it has anything
//! or its own timer is due; then it blocks the thread until every follower it synced says
//! `Idle`, and hands each bridge everything its follower said before that `Idle`, in robot
//! order. Only then do the tasks run again, and time moves on only when no follower owes an
//! `Idle`: no robot sees time `T` before every robot has finished with the instants before.
//!
//! What a follower says is handed over in whole batches, one per `Sync`, however the bytes
//! arrived: the same seed gives the same run, whatever the machine's load.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::mpsc::RecvTimeoutError;
use std::time::{Duration as WallDuration, Instant as WallInstant};

use firmware::hil::robot::{HELD, led_decision};
use firmware::hil::{CHUNK_MAX, LinkDecoder, LinkMsg};
use firmware::{Clock, Config, LedColor, Leds, Quantity, Sensor};
use protocol::{Duration, Instant};
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};

use super::bridge::{Bridge, HilReport, hear, put_on_air, refusal};
use super::error::HilError;
use super::follower::{Follower, FromRobot, frame};
use super::twin::{self, Twin};
use crate::board::clock::EmuClock;
use crate::board::timeline::Gate;

/// Messages a follower may send for one `Sync` before the host calls it a flood.
pub const FLOOD: usize = 4096;

/// What a bridge gets from the lockstep.
#[derive(Debug)]
pub(crate) enum Batch {
    /// Everything the follower said for one `Sync`, its `Idle` last.
    Msgs(Vec<LinkMsg>),
    /// The follower failed (the error names it; its QEMU is gone).
    Failed(HilError),
}

/// How a follower boots when a life of it begins with nothing on its link: restarted in the
/// run (killed before), or dead from the start.
#[derive(Debug)]
pub(crate) enum Boot {
    /// A fresh QEMU process on this image ([`Follower::boot`]): the robot reboots.
    Qemu {
        /// The HIL image.
        image: PathBuf,
        /// Its receivers.
        sectors: u8,
        /// How long its `Hello` may take.
        hello: WallDuration,
    },
    /// A fresh host twin with this configuration on this clock's executor.
    Twin(EmuClock, Config),
    /// A robot on a socket: the arena cannot reboot it (the run's check refuses its restarts).
    Socket,
}

/// One follower's place in the run.
#[derive(Debug)]
struct Slot {
    /// Its place in the arena.
    robot: usize,
    /// How it boots again.
    boot: Boot,
    follower: Option<Follower>,
    /// The host twin in this process instead of a follower over a link.
    twin: Option<TwinState>,
    /// What it said since its last batch (a twin's come in over several settles).
    said: Vec<LinkMsg>,
    /// Queued for it by its bridge, sent before its next `Sync`.
    out: VecDeque<LinkMsg>,
    /// Its own timer is due: it needs a `Sync` even with nothing queued.
    wants: bool,
    /// The instant of the `Sync` whose `Idle` it owes.
    owes: Option<Instant>,
    to_bridge: Option<UnboundedSender<Batch>>,
    /// It answered a `Sync` in this run (a `Hello` now means it rebooted).
    answered: bool,
    /// Lockstep rounds (a `Sync` and its `Idle`).
    rounds: u64,
    /// Link frames sent to it.
    frames_sent: u64,
    /// Link frames received from it.
    frames_received: u64,
    /// Bytes of the frames it said for the `Sync`s of this run (not of the `Hello`s it says on
    /// its own clock before its setup, whose number depends on wall time).
    bytes_received: u64,
}

/// A host twin's link ([`twin`](super::twin)): channels, its decoder, and whether its `Idle` was
/// asked for.
#[derive(Debug)]
struct TwinState {
    twin: Twin,
    decoder: LinkDecoder,
    /// The `Sync` it owes went in this settle: it has not run since.
    fresh: bool,
    /// Its idle hook was called for the `Sync` it owes: the `Idle` must be there by the next
    /// settle.
    asked: bool,
    bytes_sent: u64,
}

impl TwinState {
    fn new(twin: Twin) -> Self {
        TwinState {
            twin,
            decoder: LinkDecoder::new(),
            fresh: false,
            asked: false,
            bytes_sent: 0,
        }
    }
}

impl Slot {
    fn new(robot: usize, boot: Boot) -> Self {
        Slot {
            robot,
            boot,
            follower: None,
            twin: None,
            said: Vec::new(),
            out: VecDeque::new(),
            wants: false,
            owes: None,
            to_bridge: None,
            answered: false,
            rounds: 0,
            frames_sent: 0,
            frames_received: 0,
            bytes_received: 0,
        }
    }

    /// Its transport, for messages.
    fn over(&self) -> String {
        match &self.follower {
            Some(f) => f.name.clone(),
            None => "loopback".into(),
        }
    }

    /// True while it can be synced: a follower or twin, and a bridge.
    fn live(&self) -> bool {
        (self.follower.is_some() || self.twin.is_some()) && self.to_bridge.is_some()
    }
}

/// The robots in the loop of one run whose clocks follow the arena's (module docs).
#[derive(Debug, Default)]
pub struct Lockstep {
    slots: RefCell<Vec<Slot>>,
    /// How long to wait, in wall time, for a follower's `Idle` ([`super::HilTimeouts::silence`]).
    patience: WallDuration,
}

impl Lockstep {
    /// No followers yet; each will be given `patience` (wall time) to answer a `Sync`.
    pub(crate) fn new(patience: WallDuration) -> Self {
        Lockstep {
            slots: RefCell::new(Vec::new()),
            patience,
        }
    }

    /// Adds the follower at `robot`: `follower` if it is booted and greeted already (`None`:
    /// it is dead from the start), and how it boots again.
    pub(crate) fn add(&self, robot: usize, follower: Option<Follower>, boot: Boot) {
        let mut slot = Slot::new(robot, boot);
        slot.follower = follower;
        self.slots.borrow_mut().push(slot);
    }

    /// Adds the host twin at `robot` ([`twin`](super::twin)) with the image's `base`
    /// configuration, started on `clock`'s executor now, or at its first life if `dead` now.
    pub(crate) fn add_twin(&self, robot: usize, clock: &EmuClock, base: Config, dead: bool) {
        let mut slot = Slot::new(robot, Boot::Twin(clock.clone(), base));
        if !dead {
            slot.twin = Some(TwinState::new(twin::start(clock, base)));
        }
        self.slots.borrow_mut().push(slot);
    }

    /// True if the robot at `robot` is one of these followers.
    pub(crate) fn has(&self, robot: usize) -> bool {
        self.slots.borrow().iter().any(|s| s.robot == robot)
    }

    /// Connects a new life of the robot at `robot` to its bridge: what its follower says comes
    /// out of the returned channel. A follower with nothing on its link (killed before, or
    /// dead from the start) boots first ([`Boot`]): its QEMU starts afresh, or a fresh twin.
    /// Its link's counters start from zero.
    ///
    /// # Errors
    /// It is none of these followers, or it cannot boot (the message says why).
    fn attach(&self, robot: usize) -> Result<UnboundedReceiver<Batch>, HilError> {
        let mut slots = self.slots.borrow_mut();
        let Some(s) = slots.iter_mut().find(|s| s.robot == robot) else {
            return Err(HilError::NotInLockstep);
        };
        if s.follower.is_none() && s.twin.is_none() {
            match &s.boot {
                Boot::Qemu {
                    image,
                    sectors,
                    hello,
                } => s.follower = Some(Follower::boot(image, *sectors, *hello)?),
                Boot::Twin(clock, base) => {
                    s.twin = Some(TwinState::new(twin::start(clock, *base)));
                }
                Boot::Socket => return Err(HilError::CannotBoot),
            }
        }
        let (tx, rx) = unbounded_channel();
        s.to_bridge = Some(tx);
        s.answered = false;
        s.rounds = 0;
        s.frames_sent = 0;
        s.frames_received = 0;
        s.bytes_received = 0;
        if let Some(f) = s.follower.as_mut() {
            f.sent = 0;
        }
        if let Some(t) = s.twin.as_mut() {
            t.bytes_sent = 0;
        }
        Ok(rx)
    }

    /// Ends the life of the robot at `robot` (it is killed, or the run ends): its QEMU process
    /// is killed (or its twin dropped), nothing more is sent to it, and nothing it owes is
    /// waited for.
    fn detach(&self, robot: usize) {
        self.with_slot(robot, |s| {
            s.follower = None;
            s.twin = None;
            s.to_bridge = None;
            s.said.clear();
            s.out.clear();
            s.wants = false;
            s.owes = None;
        });
    }

    /// Queues `msg` for the robot at `robot`, sent before its next `Sync`.
    fn push(&self, robot: usize, msg: LinkMsg) {
        self.with_slot(robot, |s| s.out.push_back(msg));
    }

    /// The robot at `robot` needs a `Sync` (its timer is due).
    fn want(&self, robot: usize) {
        self.with_slot(robot, |s| s.wants = true);
    }

    /// `f` of the slot of the robot at `robot`, if it is one of these followers.
    fn with_slot(&self, robot: usize, f: impl FnOnce(&mut Slot)) {
        if let Some(s) = self
            .slots
            .borrow_mut()
            .iter_mut()
            .find(|s| s.robot == robot)
        {
            f(s);
        }
    }

    /// What the robot at `robot`'s link did in this run, into `report`.
    fn fill(&self, robot: usize, report: &mut HilReport) {
        if let Some(s) = self.slots.borrow().iter().find(|s| s.robot == robot) {
            report.frames_sent = s.frames_sent;
            report.frames_received = s.frames_received;
            report.round_trips = s.rounds;
            report.lockstep = true;
            if let Some(t) = &s.twin {
                report.bytes_sent = t.bytes_sent;
                report.link_errors = u64::from(t.decoder.stats().errors());
            }
            if let Some(f) = &s.follower {
                report.hello_id = f.hello_id;
                report.hello_ms = u64::try_from(f.hello.as_millis()).unwrap_or(u64::MAX);
                report.bytes_sent = f.sent;
                report.link_errors = f.link_errors();
            }
            report.bytes_received = s.bytes_received;
        }
    }

    /// Sends slot `s` what it has queued (at most [`HELD`] − 1 messages) and `Sync(now)`.
    fn sync(s: &mut Slot, now: Instant) -> Result<(), HilError> {
        let mut bytes = Vec::new();
        let mut frames = 0;
        while frames < HELD - 1 {
            let Some(m) = s.out.pop_front() else { break };
            bytes.extend_from_slice(&frame(&m));
            frames += 1;
        }
        let ms = u32::try_from(now.as_millis()).map_err(|_| HilError::ClockOverflow)?;
        bytes.extend_from_slice(&frame(&LinkMsg::Sync(ms)));
        if let Some(t) = s.twin.as_mut() {
            t.bytes_sent += bytes.len() as u64;
            t.fresh = true;
            t.asked = false;
            t.twin
                .to_robot
                .send(bytes)
                .map_err(|_| HilError::LoopbackEnded)?;
        } else if let Some(f) = s.follower.as_mut() {
            f.write(&bytes)?;
        } else {
            return Err(HilError::QemuGone);
        }
        s.frames_sent += frames as u64 + 1;
        s.owes = Some(now);
        s.wants = false;
        s.rounds += 1;
        Ok(())
    }

    /// Waits for slot `s`'s `Idle` for `now`: everything it said before it, the `Idle` last.
    fn collect(
        s: &mut Slot,
        now: Instant,
        patience: WallDuration,
    ) -> Result<Vec<LinkMsg>, HilError> {
        let over = s.over();
        let deadline = WallInstant::now() + patience;
        let mut batch = Vec::new();
        loop {
            let Some(f) = s.follower.as_ref() else {
                return Err(HilError::QemuGone);
            };
            let left = deadline.saturating_duration_since(WallInstant::now());
            let msg = match f.from.recv_timeout(left) {
                Ok(FromRobot::Msg(m)) => m,
                Ok(FromRobot::Version(version)) => {
                    return Err(HilError::Version { version, over });
                }
                Ok(FromRobot::Ended) | Err(RecvTimeoutError::Disconnected) => {
                    return Err(HilError::Disconnected { over });
                }
                Err(RecvTimeoutError::Timeout) => {
                    return Err(HilError::Silent {
                        over,
                        patience,
                        now,
                    });
                }
            };
            if Self::take(s, msg, now, &over, &mut batch)? {
                return Ok(batch);
            }
        }
    }

    /// One message `msg` of slot `s` for the `Sync` of `now`, into `batch`: `true` once it is
    /// the `Idle` that ends it.
    fn take(
        s: &mut Slot,
        msg: LinkMsg,
        now: Instant,
        over: &str,
        batch: &mut Vec<LinkMsg>,
    ) -> Result<bool, HilError> {
        match msg {
            LinkMsg::Idle { now: t, .. } if u64::from(t) != now.as_millis() => {
                return Err(HilError::IdleAt {
                    said: t,
                    over: over.to_string(),
                    now,
                });
            }
            LinkMsg::Hello { .. } if s.answered => {
                return Err(HilError::Rebooted {
                    over: over.to_string(),
                });
            }
            // Hellos from before its setup (it says hello on its own clock until then, so
            // their number depends on wall time: they are not counted).
            LinkMsg::Hello { .. } | LinkMsg::Heartbeat(_) => return Ok(false),
            _ => {}
        }
        s.frames_received += 1;
        s.bytes_received += frame(&msg).len() as u64;
        let idle = matches!(msg, LinkMsg::Idle { .. });
        batch.push(msg);
        if idle {
            s.answered = true;
            return Ok(true);
        }
        if batch.len() > FLOOD {
            return Err(HilError::Flood {
                over: over.to_string(),
                most: FLOOD,
                now,
            });
        }
        Ok(false)
    }

    /// A twin's part of a settle for the `Sync` of `now` it owes: what it wrote so far is
    /// decoded; `Some(batch)` once its `Idle` came. The settle that sends the `Sync` leaves it
    /// to run; the next finds it idle (nothing can run) and calls its idle hook; its `Idle` is
    /// there by the one after.
    fn collect_twin(s: &mut Slot, now: Instant) -> Result<Option<Vec<LinkMsg>>, HilError> {
        if let Some(t) = s.twin.as_mut()
            && std::mem::take(&mut t.fresh)
        {
            // It takes the `Sync` when it runs next.
            return Ok(None);
        }
        let mut msgs = Vec::new();
        if let Some(t) = s.twin.as_mut() {
            while let Ok(bytes) = t.twin.from_robot.try_recv() {
                msgs.extend(bytes.iter().filter_map(|&b| t.decoder.push(b)?.ok()));
            }
        }
        let mut batch = std::mem::take(&mut s.said);
        for m in msgs {
            if Self::take(s, m, now, "loopback", &mut batch)? {
                return Ok(Some(batch));
            }
        }
        s.said = batch;
        let Some(t) = s.twin.as_mut() else {
            return Err(HilError::LoopbackGone);
        };
        if t.asked {
            return Err(HilError::NoIdle { now });
        }
        t.asked = true;
        (t.twin.idle)();
        Ok(None)
    }

    /// Slot `s` failed: its bridge is told, its QEMU killed.
    fn fail(s: &mut Slot, why: HilError) {
        let why = match &s.follower {
            Some(f) => why.with_output(f.output()),
            None => why,
        };
        if let Some(b) = s.to_bridge.take() {
            let _ = b.send(Batch::Failed(why));
        }
        s.follower = None;
        s.twin = None;
        s.owes = None;
        s.out.clear();
    }
}

impl Gate for Lockstep {
    fn settle(&self, now: Instant) -> bool {
        let mut slots = self.slots.borrow_mut();
        let mut woke = false;
        for s in slots.iter_mut() {
            if s.live()
                && s.owes.is_none()
                && (s.wants || !s.out.is_empty())
                && let Err(e) = Self::sync(s, now)
            {
                Self::fail(s, e);
            }
        }
        // Twins first: they run on this executor, so a settle only takes what they said and
        // asks the next step of them (woke: their tasks run before the next settle).
        let twins_pending = slots.iter().any(|s| s.twin.is_some() && s.owes.is_some());
        for s in slots.iter_mut() {
            let Some(at) = s.owes else { continue };
            let out = if s.twin.is_some() {
                match Self::collect_twin(s, at) {
                    Ok(None) => {
                        woke = true;
                        continue;
                    }
                    Ok(Some(batch)) => Ok(batch),
                    Err(e) => Err(e),
                }
            } else if twins_pending {
                // Followers over a link wait until the twins are through this round.
                continue;
            } else {
                Self::collect(s, at, self.patience)
            };
            match out {
                Ok(batch) => {
                    s.owes = None;
                    let gone = s
                        .to_bridge
                        .as_ref()
                        .is_none_or(|b| b.send(Batch::Msgs(batch)).is_err());
                    if gone {
                        s.to_bridge = None;
                    }
                }
                Err(e) => Self::fail(s, e),
            }
            woke = true;
        }
        woke
    }
}

/// The bridge of a follower at its place in the run: its sensor's readings and the run's
/// `Setup` first, then what the medium delivers to its receivers, its readings every sample
/// period, its light and LEDs, until `stop` fires (`Ok`, with its report) or it fails.
pub(crate) async fn serve(
    mut bridge: Bridge,
    lockstep: Rc<Lockstep>,
    mut stop: tokio::sync::oneshot::Receiver<()>,
) -> Result<HilReport, HilError> {
    let robot = bridge.robot;
    let mut report = HilReport {
        robot,
        transport: bridge.transport.to_string(),
        ..HilReport::default()
    };
    let mut batches = lockstep.attach(robot)?;
    let clock = bridge.clock.clone();
    let t0 = clock.now();
    readings(&mut bridge, &lockstep).await;
    let mut setup = bridge.setup;
    setup.host_clock = true;
    // A keyed run: its swarm key just before the setup (link version 3).
    if let Some(key) = bridge.config.key {
        lockstep.push(robot, LinkMsg::Key(key));
    }
    lockstep.push(robot, LinkMsg::Setup(setup));
    let (mut heard, air) = start_light(&mut bridge);
    let mut alarm = Instant::MAX;
    let mut next_sample = t0 + bridge.config.sample_period;
    loop {
        let wake = alarm.min(next_sample);
        let input = tokio::select! {
            biased;
            _ = &mut stop => None,
            b = batches.recv() => Some(Input::Batch(b)),
            Some((s, b)) = heard.recv() => Some(Input::Heard(s, b)),
            () = clock.sleep_until(wake) => Some(Input::Tick),
        };
        let now = clock.now();
        match input {
            None => {
                lockstep.fill(robot, &mut report);
                lockstep.detach(robot);
                return check_at_end(&bridge, now.saturating_since(t0), &report);
            }
            Some(Input::Batch(None)) => return Err(HilError::LockstepEnded),
            Some(Input::Batch(Some(Batch::Failed(why)))) => return Err(why),
            Some(Input::Batch(Some(Batch::Msgs(msgs)))) => {
                for m in msgs {
                    if let Some(next) = on_message(&mut bridge, m, &air, &mut report).await? {
                        alarm = next.max(now + Duration::from_millis(1));
                    }
                }
            }
            Some(Input::Heard(sector, bytes)) => {
                report.rx_bytes += bytes.len() as u64;
                let Ok(sector) = u8::try_from(sector) else {
                    continue;
                };
                for c in bytes.chunks(CHUNK_MAX) {
                    let bytes = heapless::Vec::from_slice(c).unwrap_or_default();
                    lockstep.push(robot, LinkMsg::Rx { sector, bytes });
                }
            }
            Some(Input::Tick) => {
                if now >= next_sample {
                    readings(&mut bridge, &lockstep).await;
                    next_sample = now + bridge.config.sample_period;
                }
                if now >= alarm {
                    lockstep.want(robot);
                    alarm = Instant::MAX;
                }
            }
        }
    }
}

/// What a follower's receivers heard, `(sector, bytes)`, and where its light goes on air.
type Light = (
    UnboundedReceiver<(usize, Vec<u8>)>,
    UnboundedSender<Vec<u8>>,
);

/// What one of the bridge's sources gave.
enum Input {
    Batch(Option<Batch>),
    Heard(usize, Vec<u8>),
    Tick,
}

/// One message of a follower's batch; an `Idle` gives its next timer.
async fn on_message(
    bridge: &mut Bridge,
    msg: LinkMsg,
    air: &UnboundedSender<Vec<u8>>,
    report: &mut HilReport,
) -> Result<Option<Instant>, HilError> {
    match msg {
        LinkMsg::Tx(chunk) => {
            report.tx += 1;
            let _ = air.send(chunk.to_vec());
        }
        LinkMsg::Led(code) => {
            let sectors = bridge.config.params.sectors;
            let color = LedColor::for_decision_of(led_decision(code), sectors);
            let _ = bridge.leds.show(color).await;
        }
        LinkMsg::Refused(code) => {
            return Err(HilError::Refused {
                over: bridge.transport.to_string(),
                why: refusal(code),
                code,
            });
        }
        LinkMsg::Idle { next, .. } => {
            return Ok(Some(if next == u32::MAX {
                Instant::MAX
            } else {
                Instant::from_millis(u64::from(next))
            }));
        }
        _ => {}
    }
    Ok(None)
}

/// Queues what the bridge's sensor reads now, both quantities (a failed read sends nothing).
async fn readings(bridge: &mut Bridge, lockstep: &Lockstep) {
    for (q, quantity) in [(0u8, Quantity::AmbientLight), (1, Quantity::Oxygen)] {
        if let Ok(level) = bridge.sensor.read(quantity).await {
            lockstep.push(
                bridge.robot,
                LinkMsg::Reading {
                    quantity: q,
                    level: level.0,
                },
            );
        }
    }
}

/// Starts the robot's light on the run's executor: a task handing what reaches its receivers
/// to the returned channel with the sector, and one putting the frames sent into the returned
/// sender on air, one at a time as from the robot's own transmitter. They end with the run.
fn start_light(bridge: &mut Bridge) -> Light {
    let (heard_tx, heard) = unbounded_channel::<(usize, Vec<u8>)>();
    if let Some(rx) = bridge.receivers.take() {
        bridge.clock.spawn(hear(rx, heard_tx));
    }
    let (air, air_rx) = unbounded_channel::<Vec<u8>>();
    if let Some(transmitter) = bridge.transmitter.take() {
        bridge.clock.spawn(put_on_air(transmitter, air_rx));
    }
    (heard, air)
}

/// At the end of a run that lasted `ran`: a robot program that runs initiates a wave every
/// cycle, so one that sent no light in three cycles' time is not running.
fn check_at_end(bridge: &Bridge, ran: Duration, report: &HilReport) -> Result<HilReport, HilError> {
    let cycles = bridge.config.params.longest_cycle().saturating_mul(3);
    if report.tx == 0 && ran > cycles {
        return Err(HilError::Dark {
            over: bridge.transport.to_string(),
            ran,
        });
    }
    Ok(report.clone())
}
