//! The modulated-light medium, modelled on purpose (in the spirit of Cooja's radio medium):
//! users want to know what breaks the swarm.
//!
//! - **Range and direction.** A frame reaches every live robot within `range` of the sender,
//!   on the receiver facing the sender: the sector of the bearing from receiver to sender
//!   ([`protocol::Sector::from_bearing`]).
//! - **Airtime.** A frame of `n` bytes occupies the light for `n × bits_per_byte / bitrate`
//!   (rounded up to the millisecond) and arrives whole at its end; the transmitter is busy
//!   until then.
//! - **Collisions.** Two frames whose airtimes overlap at the same receiver both arrive
//!   garbled (about half of their bytes replaced by noise), as overlapping light pulses would.
//! - **Half duplex.** A robot cannot receive while it transmits: a frame whose airtime overlaps
//!   the receiver's own transmission is dropped.
//! - **Loss and corruption.** Each frame is lost at each receiver with probability `loss`;
//!   each byte that arrives is corrupted (XOR with a random non-zero byte) with probability
//!   `byte_error_rate`.
//!
//! - **Adversaries.** Nodes that are not robots ([`crate::world::adversary`]) use the same model: a
//!   rogue transmitter's bursts and a replayer's frames take airtime, reach the receiver facing
//!   them within range, collide and are lost like any frame; a replayer hears (captures) frames
//!   like a robot's receiver would. Node numbers: robots first (`0..robots`), then the
//!   adversaries in the order of [`crate::ArenaConfig::adversaries`]; the trace's `from` is a
//!   node number.
//!
//! All randomness comes from the medium's own seeded RNG, drawn in the deterministic order of
//! the current-thread runtime.
//!
//! This is the world's side of the light: the medium is the board's [`Air`]. A robot's side,
//! its transmitter and receivers, is the board's ([`crate::board::light`]);
//! [`Medium::attach`] hands them out. Every event is traced ([`trace`]).

use std::cell::RefCell;
use std::rc::Rc;

use firmware::Clock;
use nalgebra::Point2;
use protocol::{Duration, Instant, Sector};
use rand::Rng;
use rand_pcg::Pcg32;
use serde::Serialize;
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};

use crate::board::clock::EmuClock;
use crate::board::light::{self, Air, EmuReceivers, EmuTransmitter, Light};

mod error;
pub mod trace;

pub use error::MediumError;
pub use trace::{DropReason, TraceEvent};

/// How the light behaves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumParams {
    /// Bits per second on air.
    pub bitrate: u32,
    /// Bits on air per byte (10 for a UART's 8N1 framing).
    pub bits_per_byte: u32,
    /// How far a robot's light carries, in metres.
    pub range: f64,
    /// Probability that a frame is lost at one receiver.
    pub loss: f64,
    /// Probability that one received byte is corrupted.
    pub byte_error_rate: f64,
    /// Whether overlapping frames at one receiver garble each other.
    pub collisions: bool,
}

impl MediumParams {
    /// The light's range in the lab, metres: robots 1 m apart hear only their neighbours.
    pub const LAB_RANGE: f64 = 1.5;
}

impl Default for MediumParams {
    /// The link the Nucleo image ships: 9600 bit/s IrDA SIR, 10 bits per byte (start, 8 data,
    /// stop: a 32-byte frame takes 34 ms), 1.5 m range (robots 1 m apart hear only their
    /// neighbours), no loss, no byte errors, collisions on.
    fn default() -> Self {
        MediumParams {
            bitrate: firmware::LIGHT_BITRATE,
            bits_per_byte: firmware::LIGHT_BITS_PER_BYTE,
            range: Self::LAB_RANGE,
            loss: 0.0,
            byte_error_rate: 0.0,
            collisions: true,
        }
    }
}

impl MediumParams {
    /// Airtime of a frame of `bytes` bytes (at least 1 ms).
    pub fn airtime(&self, bytes: usize) -> Duration {
        let bits = bytes as u64 * u64::from(self.bits_per_byte);
        let ms = (bits * 1000).div_ceil(u64::from(self.bitrate.max(1)));
        Duration::from_millis(ms.max(1))
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// The first bad parameter.
    pub fn validate(&self) -> Result<(), MediumError> {
        if self.bitrate == 0 || self.bits_per_byte == 0 {
            return Err(MediumError::Rate);
        }
        if !(self.range.is_finite() && self.range > 0.0) {
            return Err(MediumError::Range(self.range));
        }
        for (name, p) in [
            ("loss", self.loss),
            ("byte error rate", self.byte_error_rate),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(MediumError::Probability { name, value: p });
            }
        }
        Ok(())
    }
}

/// Frame counts kept by the medium. Deliveries, drops, garbling and corruption count what
/// reached (or failed to reach) robots, whoever sent it; what adversaries hear is counted in
/// `captured` and `capture_missed` only.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct MediumStats {
    /// Frames sent by robots.
    pub sent: u64,
    /// Frame deliveries to robots (one per receiver reached), garbled ones included.
    pub delivered: u64,
    /// Deliveries garbled by a collision.
    pub garbled: u64,
    /// Bytes corrupted by the byte error rate.
    pub corrupted_bytes: u64,
    /// Deliveries dropped by loss.
    pub lost: u64,
    /// Deliveries dropped because the receiver was transmitting.
    pub receiver_transmitting: u64,
    /// Deliveries dropped because the receiver was dead.
    pub receiver_dead: u64,
    /// Bursts of random bytes sent by rogue transmitters.
    pub rogue_bursts: u64,
    /// Frames retransmitted by replayers.
    pub replayed: u64,
    /// Deliveries to robots of what an adversary sent (bursts and replays), garbled included.
    pub adversary_delivered: u64,
    /// Robot frames a replayer heard intact and kept for replay.
    pub captured: u64,
    /// Frames that reached a replayer unusable (lost, garbled, corrupted, while it transmitted,
    /// or not a robot's).
    pub capture_missed: u64,
}

/// A node number the medium does not have (nodes are `0..nodes`: the robots, then the
/// adversaries).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoSuchNode {
    /// The node asked for.
    pub node: usize,
    /// How many nodes the medium has.
    pub nodes: usize,
}

impl std::fmt::Display for NoSuchNode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the medium has no node {} (it has {}: 0 to {})",
            self.node,
            self.nodes,
            self.nodes.saturating_sub(1)
        )
    }
}

impl std::error::Error for NoSuchNode {}

/// What kind of node of the medium.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A robot running the robot program: receives into its per-sector receivers.
    Robot,
    /// A rogue transmitter: sends random bytes, receives nothing.
    Rogue,
    /// A replayer: captures robot frames and sends them again later.
    Replayer,
}

/// A robot frame a replayer heard intact.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Capture {
    /// When its airtime ended.
    pub t: Instant,
    /// The robot that sent it.
    pub from: usize,
    /// Its bytes, as they arrived.
    pub bytes: Vec<u8>,
}

/// What a transmission is, for the counters and the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Emission {
    /// A robot's frame.
    Frame,
    /// A rogue transmitter's burst of random bytes.
    Noise,
    /// A replayer's copy of a frame `from` sent, captured at `captured`.
    Replay {
        /// The robot that sent the original.
        from: usize,
        /// When the original was captured.
        captured: Instant,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fate {
    Clear,
    Collided,
    Deaf,
}

#[derive(Debug)]
struct Arrival {
    id: u64,
    to: usize,
    sector: u8,
    from: usize,
    end: Instant,
    /// Shared by the transmission's arrivals until the light damages one (one allocation a
    /// transmission, not one an arrival).
    bytes: Rc<[u8]>,
    fate: Fate,
}

#[derive(Debug)]
struct Node {
    pos: Point2<f64>,
    sectors: u8,
    role: Role,
    alive: bool,
    /// The end of this node's current or last transmission.
    tx_until: Instant,
    /// A robot's receivers, while it is attached.
    light: Option<Light>,
    /// A replayer's captures.
    captures: Option<UnboundedSender<Capture>>,
}

/// The nodes a node's light reaches, each with the sector it arrives on.
type Reach = Rc<[(usize, u8)]>;

/// The shared medium: every robot's position, every frame in flight, the trace.
#[derive(Debug)]
pub struct Medium {
    params: MediumParams,
    clock: EmuClock,
    rng: Pcg32,
    nodes: Vec<Node>,
    /// Frames in flight, by the node they are arriving at: a transmission looks only at its
    /// receivers' (collisions, half duplex), not at every frame in the air.
    pending: Vec<Vec<Arrival>>,
    /// Per node, who its light reaches ([`Medium::neighbours`]), worked out when it first sends.
    neighbours: Vec<Option<Reach>>,
    next_id: u64,
    record: bool,
    trace: Vec<TraceEvent>,
    stats: MediumStats,
}

/// A handle on the medium, shared by the robots' hardware in one run.
pub type SharedMedium = Rc<RefCell<Medium>>;

impl Medium {
    /// A medium with robots at `positions`, each with `sectors` receivers. `record` keeps a
    /// full trace (costs memory on long runs).
    pub fn new(
        params: MediumParams,
        clock: EmuClock,
        rng: Pcg32,
        positions: &[Point2<f64>],
        sectors: u8,
        record: bool,
    ) -> SharedMedium {
        let nodes = positions
            .iter()
            .map(|&pos| Node {
                pos,
                sectors,
                role: Role::Robot,
                alive: false,
                tx_until: Instant::ZERO,
                light: None,
                captures: None,
            })
            .collect();
        Rc::new(RefCell::new(Medium {
            params,
            clock,
            rng,
            nodes,
            pending: Vec::new(),
            neighbours: Vec::new(),
            next_id: 0,
            record,
            trace: Vec::new(),
            stats: MediumStats::default(),
        }))
    }

    /// The counters so far.
    pub fn stats(&self) -> MediumStats {
        self.stats
    }

    /// Takes the trace recorded so far.
    pub fn take_trace(&mut self) -> Vec<TraceEvent> {
        std::mem::take(&mut self.trace)
    }

    /// Records `e` if tracing.
    pub fn log(&mut self, e: TraceEvent) {
        if self.record {
            self.trace.push(e);
        }
    }

    /// The time now.
    pub fn now(&self) -> Instant {
        self.clock.now()
    }

    /// The clock the medium runs on (the run's).
    pub fn clock(&self) -> EmuClock {
        self.clock.clone()
    }

    /// Adds a rogue transmitter at `pos`; returns its node number.
    pub fn add_rogue(this: &SharedMedium, pos: Point2<f64>) -> usize {
        Medium::add_node(this, pos, Role::Rogue, None)
    }

    /// Adds a replayer at `pos` with receivers like a robot's; returns its node number and the
    /// frames it captures.
    pub fn add_replayer(
        this: &SharedMedium,
        pos: Point2<f64>,
    ) -> (usize, UnboundedReceiver<Capture>) {
        let (tx, rx) = unbounded_channel();
        (Medium::add_node(this, pos, Role::Replayer, Some(tx)), rx)
    }

    fn add_node(
        this: &SharedMedium,
        pos: Point2<f64>,
        role: Role,
        captures: Option<UnboundedSender<Capture>>,
    ) -> usize {
        let mut m = this.borrow_mut();
        let sectors = m.nodes.first().map_or(2, |n| n.sectors);
        m.nodes.push(Node {
            pos,
            sectors,
            role,
            alive: true,
            tx_until: Instant::ZERO,
            light: None,
            captures,
        });
        m.nodes.len() - 1
    }

    /// When node `node`'s current or last transmission ends.
    pub fn busy_until(&self, node: usize) -> Instant {
        self.nodes.get(node).map_or(Instant::ZERO, |n| n.tx_until)
    }

    /// Brings robot `robot` (back) to life: returns its new transmitter and its receivers, one
    /// per sector.
    ///
    /// # Errors
    /// [`NoSuchNode`] if the medium has no node `robot`; nothing changes then. An error, not a
    /// no-op: a robot booting without a radio would run deaf and mute and its run would look
    /// valid, so the caller (the arena, booting a robot) must know and fail the run instead.
    pub fn attach(
        this: &SharedMedium,
        robot: usize,
    ) -> Result<(EmuTransmitter, EmuReceivers), NoSuchNode> {
        let mut m = this.borrow_mut();
        let nodes = m.nodes.len();
        let node = m
            .nodes
            .get_mut(robot)
            .ok_or(NoSuchNode { node: robot, nodes })?;
        let (feed, receivers) = light::receivers(usize::from(node.sectors));
        node.light = Some(feed);
        node.alive = true;
        let transmitter = EmuTransmitter::new(Box::new(this.clone()), m.clock.clone(), robot);
        Ok((transmitter, receivers))
    }

    /// Robot `robot` dies: it hears nothing more until attached again.
    pub fn detach(&mut self, robot: usize) {
        if let Some(n) = self.nodes.get_mut(robot) {
            n.alive = false;
            n.light = None;
        }
    }

    /// Starts node `from`'s transmission of `bytes` now; returns when its airtime ends.
    ///
    /// A node the medium does not have sends nothing: no airtime (the time returned is now),
    /// nothing counted or traced, nobody reached. A documented no-op rather than an error
    /// because no caller could act on one: every caller holds a node number the medium gave it
    /// (a robot's [`EmuTransmitter`] comes from [`attach`](Self::attach), which checks the
    /// node; an adversary transmits from the node it added), and nodes are never removed, so an
    /// unknown node is a bug in the caller, made harmless here instead of a panic.
    pub fn transmit(this: &SharedMedium, from: usize, bytes: &[u8], what: Emission) -> Instant {
        let mut guard = this.borrow_mut();
        let m = &mut *guard;
        let t0 = m.clock.now();
        let Some(sender) = m.nodes.get_mut(from) else {
            return t0;
        };
        let t1 = t0 + m.params.airtime(bytes.len());
        sender.tx_until = t1;
        m.emitted(t0, from, bytes.len(), what);
        // Half duplex: what the sender was receiving is lost under its own light.
        if let Some(arriving) = m.pending.get_mut(from) {
            for a in arriving.iter_mut().filter(|a| a.end > t0) {
                a.fate = Fate::Deaf;
            }
        }
        let reach = m.neighbours(from);
        // Sized once: growing it cost a reallocation or two per transmission.
        let mut ids = Vec::with_capacity(reach.len());
        let shared: Rc<[u8]> = Rc::from(bytes);
        for &(to, sector) in reach.iter() {
            let Some(fate) = m.reception(from, to, sector, t0, t1) else {
                continue;
            };
            let id = m.next_id;
            m.next_id += 1;
            ids.push((to, id));
            m.arriving(to).push(Arrival {
                id,
                to,
                sector,
                from,
                end: t1,
                bytes: shared.clone(),
                fate,
            });
        }
        // One task per transmission delivers its arrivals, in order, when its airtime ends.
        if !ids.is_empty() {
            let medium = this.clone();
            let clock = m.clock.clone();
            m.clock.spawn(async move {
                clock.sleep_until(t1).await;
                for (to, id) in ids {
                    Medium::deliver(&medium, to, id);
                }
            });
        }
        t1
    }

    /// Counts and traces node `from`'s transmission of `len` bytes, started at `t0`.
    fn emitted(&mut self, t0: Instant, from: usize, len: usize, what: Emission) {
        let t_ms = t0.as_millis();
        match what {
            Emission::Frame => {
                self.stats.sent += 1;
                self.log(TraceEvent::Sent {
                    t_ms,
                    robot: from,
                    len,
                });
            }
            Emission::Noise => {
                self.stats.rogue_bursts += 1;
                self.log(TraceEvent::RogueSent {
                    t_ms,
                    node: from,
                    len,
                });
            }
            Emission::Replay {
                from: original,
                captured,
            } => {
                self.stats.replayed += 1;
                self.log(TraceEvent::Replayed {
                    t_ms,
                    node: from,
                    len,
                    from: original,
                    captured_ms: captured.as_millis(),
                });
            }
        }
    }

    /// The nodes that node `from`'s light reaches and are not rogues, in node order, each with
    /// the sector it arrives on (of the bearing from it to `from`). Worked out once per sender:
    /// nodes never move in the medium (a swarm's move shifts the field under it), and a new
    /// node clears them all.
    fn neighbours(&mut self, from: usize) -> Reach {
        if self.neighbours.len() != self.nodes.len() {
            self.neighbours = vec![None; self.nodes.len()];
        }
        if let Some(n) = &self.neighbours[from] {
            return n.clone();
        }
        let src = self.nodes[from].pos;
        let list: Reach = self
            .nodes
            .iter()
            .enumerate()
            .filter(|&(to, node)| {
                to != from
                    && node.role != Role::Rogue
                    && nalgebra::distance(&node.pos, &src) <= self.params.range
            })
            .map(|(to, node)| {
                let d = src - node.pos;
                let sector = Sector::from_bearing(d.y.atan2(d.x) as f32, node.sectors).index();
                (to, sector)
            })
            .collect();
        self.neighbours[from] = Some(list.clone());
        list
    }

    /// Whether node `to`, within reach of node `from`, receives what `from` sends during
    /// `t0..t1`: its fate so far, or `None` if it does not (dead, or dropped: counted and
    /// traced).
    fn reception(
        &mut self,
        from: usize,
        to: usize,
        sector: u8,
        t0: Instant,
        t1: Instant,
    ) -> Option<Fate> {
        let node = &self.nodes[to];
        if !node.alive {
            return None;
        }
        if node.tx_until > t0 {
            self.dropped(t1, to, from, DropReason::ReceiverTransmitting);
            return None;
        }
        if self.params.loss > 0.0 && self.rng.random_bool(self.params.loss) {
            self.dropped(t1, to, from, DropReason::Loss);
            return None;
        }
        Some(self.collide(to, sector, t0))
    }

    /// With collisions on, a frame arriving at `to`'s receiver `sector` from `t0` on garbles
    /// every frame still arriving there, and is garbled by them: its fate.
    fn collide(&mut self, to: usize, sector: u8, t0: Instant) -> Fate {
        let mut fate = Fate::Clear;
        if self.params.collisions {
            for a in self
                .arriving(to)
                .iter_mut()
                .filter(|a| a.sector == sector && a.end > t0)
            {
                if a.fate == Fate::Clear {
                    a.fate = Fate::Collided;
                }
                fate = Fate::Collided;
            }
        }
        fate
    }

    /// Counts and traces a frame from `from` that did not reach `to` (at `t`, its airtime's end).
    fn dropped(&mut self, t: Instant, to: usize, from: usize, reason: DropReason) {
        match reason {
            _ if self.nodes[to].role != Role::Robot => self.stats.capture_missed += 1,
            DropReason::ReceiverDead => self.stats.receiver_dead += 1,
            DropReason::ReceiverTransmitting => self.stats.receiver_transmitting += 1,
            DropReason::Loss => self.stats.lost += 1,
        }
        self.log(TraceEvent::Dropped {
            t_ms: t.as_millis(),
            robot: to,
            from,
            reason,
        });
    }

    /// The frames arriving at node `to`.
    fn arriving(&mut self, to: usize) -> &mut Vec<Arrival> {
        if self.pending.len() <= to {
            self.pending.resize_with(to + 1, Vec::new);
        }
        &mut self.pending[to]
    }

    /// The airtime of arrival `id` at node `to` is over: hand its bytes to the receiver.
    fn deliver(this: &SharedMedium, to: usize, id: u64) {
        let mut guard = this.borrow_mut();
        let m = &mut *guard;
        let Some(arriving) = m.pending.get_mut(to) else {
            return;
        };
        let Some(i) = arriving.iter().position(|a| a.id == id) else {
            return;
        };
        let mut a = arriving.swap_remove(i);
        if !m.nodes[a.to].alive {
            return m.dropped(a.end, a.to, a.from, DropReason::ReceiverDead);
        }
        if a.fate == Fate::Deaf {
            return m.dropped(a.end, a.to, a.from, DropReason::ReceiverTransmitting);
        }
        let garbled = a.fate == Fate::Collided;
        let to_robot = m.nodes[a.to].role == Role::Robot;
        if garbled && to_robot {
            m.stats.garbled += 1;
        }
        let corrupted = m.damage(&mut a.bytes, garbled);
        if to_robot {
            m.received(a, garbled, corrupted);
        } else {
            m.captured(a, garbled, corrupted);
        }
    }

    /// What the light does to `bytes` on the way ([`damage_bytes`](Self::damage_bytes)), on a
    /// copy of its own if it can do anything.
    fn damage(&mut self, bytes: &mut Rc<[u8]>, garbled: bool) -> u32 {
        let errors = self.params.byte_error_rate > 0.0;
        if !garbled && !errors {
            return 0;
        }
        let mut own = bytes.to_vec();
        let corrupted = self.damage_bytes(&mut own, garbled);
        *bytes = Rc::from(own);
        corrupted
    }

    /// What the light does to `bytes` on the way: if `garbled` by a collision, about half of
    /// them replaced by noise; then each corrupted at the byte error rate. Returns how many
    /// were corrupted.
    fn damage_bytes(&mut self, bytes: &mut [u8], garbled: bool) -> u32 {
        if garbled {
            for b in bytes.iter_mut() {
                if self.rng.random_bool(0.5) {
                    *b = self.rng.random();
                }
            }
        }
        let mut corrupted = 0u32;
        if self.params.byte_error_rate > 0.0 {
            for b in bytes.iter_mut() {
                if self.rng.random_bool(self.params.byte_error_rate) {
                    *b ^= self.rng.random_range(1..=255u8);
                    corrupted += 1;
                }
            }
        }
        corrupted
    }

    /// Arrival `a` reaches a robot's receiver: counted, traced and put into the receiver's
    /// inbox.
    fn received(&mut self, a: Arrival, garbled: bool, corrupted: u32) {
        self.stats.corrupted_bytes += u64::from(corrupted);
        self.stats.delivered += 1;
        if self.nodes[a.from].role != Role::Robot {
            self.stats.adversary_delivered += 1;
        }
        self.log(TraceEvent::Received {
            t_ms: a.end.as_millis(),
            robot: a.to,
            from: a.from,
            sector: a.sector,
            len: a.bytes.len(),
            garbled,
            corrupted,
        });
        if let Some(light) = &self.nodes[a.to].light {
            light.put(usize::from(a.sector), a.bytes);
        }
    }

    /// Arrival `a` reaches a replayer: kept for replay if a robot sent it and it came intact.
    fn captured(&mut self, a: Arrival, garbled: bool, corrupted: u32) {
        let kept = self.nodes[a.from].role == Role::Robot && !garbled && corrupted == 0;
        if kept {
            self.stats.captured += 1;
        } else {
            self.stats.capture_missed += 1;
        }
        self.log(TraceEvent::Captured {
            t_ms: a.end.as_millis(),
            node: a.to,
            from: a.from,
            len: a.bytes.len(),
            kept,
        });
        if let (true, Some(c)) = (kept, &self.nodes[a.to].captures) {
            let _ = c.send(Capture {
                t: a.end,
                from: a.from,
                bytes: a.bytes.to_vec(),
            });
        }
    }
}

/// A robot's transmitter ([`EmuTransmitter`]) sends its frames into the medium.
impl Air for SharedMedium {
    fn transmit(&self, robot: usize, frame: &[u8]) -> Instant {
        Medium::transmit(self, robot, frame, Emission::Frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn airtime_follows_length_and_bitrate() {
        // The board's link: 9600 bit/s, 10 bits per byte; rounded up to whole milliseconds.
        let p = MediumParams::default();
        assert_eq!((p.bitrate, p.bits_per_byte), (9600, 10));
        assert_eq!(p.airtime(32), Duration::from_millis(34));
        assert_eq!(p.airtime(1), Duration::from_millis(2));
        let slow = MediumParams { bitrate: 2400, ..p };
        assert_eq!(slow.airtime(32), Duration::from_millis(134));
        assert_eq!(slow.airtime(1), Duration::from_millis(5));
        assert!(MediumParams { loss: 1.5, ..p }.validate().is_err());
        assert!(MediumParams { range: 0.0, ..p }.validate().is_err());
        assert!(p.validate().is_ok());
    }

    fn two_robots() -> SharedMedium {
        let clock = EmuClock::new(tokio::time::Instant::now());
        let positions = [Point2::new(0.0, 0.0), Point2::new(1.0, 0.0)];
        Medium::new(
            MediumParams::default(),
            clock,
            Pcg32::new(1, 1),
            &positions,
            2,
            true,
        )
    }

    #[test]
    fn attaching_a_node_the_medium_does_not_have_is_an_error() {
        let m = two_robots();
        let Err(e) = Medium::attach(&m, 2) else {
            panic!("node 2 of 2 attached");
        };
        assert_eq!(e, NoSuchNode { node: 2, nodes: 2 });
        assert!(e.to_string().contains("no node 2"), "{e}");
        assert!(Medium::attach(&m, usize::MAX).is_err());
        let (_, receivers) = Medium::attach(&m, 1).expect("robot 1 exists");
        assert_eq!(receivers.sectors(), 2, "one receiver per sector");
    }

    #[test]
    fn transmitting_from_a_node_the_medium_does_not_have_sends_nothing() {
        let m = two_robots();
        let now = m.borrow().now();
        for from in [2, 7, usize::MAX] {
            let end = Medium::transmit(&m, from, b"frame", Emission::Frame);
            assert_eq!(end, now, "no airtime from node {from}");
        }
        let mut m = m.borrow_mut();
        assert_eq!(m.stats(), MediumStats::default());
        assert!(m.take_trace().is_empty());
        assert_eq!(m.busy_until(0), Instant::ZERO);
        assert_eq!(m.busy_until(7), Instant::ZERO);
    }
}
