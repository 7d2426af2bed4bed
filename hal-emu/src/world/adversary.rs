//! Adversaries in the light medium: devices that are not robots but share the robots' light.
//!
//! - A **rogue transmitter** ([`Rogue`]) sends bursts of random bytes at random times (a
//!   Poisson process: exponential gaps), each burst occupying the light for its airtime, so it
//!   also collides with the robots' frames at every receiver that hears both.
//! - A **replayer** ([`Replayer`]) listens with receivers like a robot's, keeps every robot
//!   frame it hears intact (a careful attacker checks what it records), and sends each one
//!   again once, after a random delay, from its own position: the robots then see an old
//!   message coming from the replayer's direction.
//!
//! Both are nodes of the [`medium`](crate::world::medium) like the robots, numbered after them, so
//! range, receiver sector (bearing), airtime, half duplex, loss, byte errors and collisions
//! apply to them unchanged; what they send and capture is traced
//! ([`TraceEvent::RogueSent`](crate::TraceEvent::RogueSent),
//! [`Replayed`](crate::TraceEvent::Replayed), [`Captured`](crate::TraceEvent::Captured)) and
//! counted in [`MediumStats`](crate::MediumStats). Each adversary draws from its own RNG,
//! seeded from the run's seed.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use embassy_futures::select::{Either, select};
use firmware::Clock;
use nalgebra::Point2;
use protocol::{Duration, Instant};
use rand::Rng;
use rand_pcg::Pcg32;
use tokio::sync::mpsc::UnboundedReceiver;

use crate::board::clock::EmuClock;
use crate::world::medium::{Capture, Emission, Medium, SharedMedium};

/// A device in the arena that is not a robot.
#[derive(Clone, Debug, PartialEq)]
pub struct Adversary {
    /// Where it is, metres (robots of a line are at `(i × spacing, 0)`).
    pub position: Point2<f64>,
    /// What it does.
    pub kind: AdversaryKind,
}

/// What an adversary does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AdversaryKind {
    /// Sends random bytes.
    Rogue(Rogue),
    /// Sends captured robot frames again later.
    Replayer(Replayer),
}

/// A rogue transmitter: bursts of `min_bytes..=max_bytes` random bytes (uniform), with gaps
/// between the end of one burst and the start of the next drawn from an exponential
/// distribution of mean `mean_gap`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rogue {
    /// Shortest burst, bytes (at least 1).
    pub min_bytes: usize,
    /// Longest burst, bytes.
    pub max_bytes: usize,
    /// Mean gap between bursts.
    pub mean_gap: Duration,
    /// Wrap every burst in `ss`…`ss` delimiters, so that each reaches the robots' deframers as
    /// a candidate frame (the harder case: its bytes are checked, and one in about 65 536
    /// passes the CRC) instead of mostly being skipped as noise between frames.
    pub framed: bool,
}

impl Default for Rogue {
    /// Bursts of 4 to 32 bytes, framed, every 2 s on average: about 1 % of the light's time
    /// at 9600 bit/s (19 ms bursts), some ten times the airtime of one robot in the lab.
    fn default() -> Self {
        Rogue {
            min_bytes: 4,
            max_bytes: 32,
            mean_gap: Duration::from_secs(2),
            framed: true,
        }
    }
}

/// A replayer: every robot frame it captures intact is sent again once, after a delay drawn
/// uniformly from `min_delay..=max_delay` (later if it is still transmitting then).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Replayer {
    /// Shortest delay.
    pub min_delay: Duration,
    /// Longest delay.
    pub max_delay: Duration,
}

impl Default for Replayer {
    /// 10 to 60 s: from a fraction of a cycle to more than one, so replays land in every phase
    /// of the robots' waves.
    fn default() -> Self {
        Replayer {
            min_delay: Duration::from_secs(10),
            max_delay: Duration::from_secs(60),
        }
    }
}

impl Adversary {
    /// A rogue transmitter at `position` with default behaviour.
    pub fn rogue(position: Point2<f64>) -> Self {
        Adversary {
            position,
            kind: AdversaryKind::Rogue(Rogue::default()),
        }
    }

    /// A replayer at `position` with default delays.
    pub fn replayer(position: Point2<f64>) -> Self {
        Adversary {
            position,
            kind: AdversaryKind::Replayer(Replayer::default()),
        }
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// The first bad parameter.
    pub fn validate(&self) -> Result<(), AdversaryError> {
        if !(self.position.x.is_finite() && self.position.y.is_finite()) {
            return Err(AdversaryError::Position(self.position));
        }
        match self.kind {
            AdversaryKind::Rogue(r) => {
                if r.min_bytes == 0 || r.min_bytes > r.max_bytes {
                    return Err(AdversaryError::Burst {
                        min: r.min_bytes,
                        max: r.max_bytes,
                    });
                }
                if r.mean_gap == Duration::ZERO {
                    return Err(AdversaryError::Gap);
                }
            }
            AdversaryKind::Replayer(r) => {
                if r.min_delay > r.max_delay {
                    return Err(AdversaryError::Delay {
                        min: r.min_delay,
                        max: r.max_delay,
                    });
                }
            }
        }
        Ok(())
    }
}

/// Why [`Adversary::validate`] refused an adversary's parameters.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AdversaryError {
    /// Its position is not finite.
    #[error("adversary position ({}, {}) is not finite", .0.x, .0.y)]
    Position(Point2<f64>),
    /// A rogue's burst lengths are not `1 <= min <= max`.
    #[error("rogue burst length {min}..={max} bytes: needs 1 <= min <= max")]
    Burst {
        /// The shortest burst, bytes.
        min: usize,
        /// The longest burst, bytes.
        max: usize,
    },
    /// A rogue's mean gap between bursts is zero.
    #[error("the rogue's mean gap between bursts must be positive")]
    Gap,
    /// A replayer's shortest delay exceeds its longest.
    #[error(
        "replay delay {} ms to {} ms: the minimum exceeds the maximum",
        min.as_millis(),
        max.as_millis()
    )]
    Delay {
        /// The shortest delay.
        min: Duration,
        /// The longest delay.
        max: Duration,
    },
}

/// Puts `adversary` into `medium` and spawns its task beside the run's ([`EmuClock::spawn`]);
/// the task runs until the run ends.
pub(crate) fn spawn(medium: &SharedMedium, clock: EmuClock, adversary: &Adversary, rng: Pcg32) {
    match adversary.kind {
        AdversaryKind::Rogue(r) => {
            let node = Medium::add_rogue(medium, adversary.position);
            clock
                .clone()
                .spawn(rogue(medium.clone(), clock, node, r, rng));
        }
        AdversaryKind::Replayer(r) => {
            let (node, captures) = Medium::add_replayer(medium, adversary.position);
            clock
                .clone()
                .spawn(replayer(medium.clone(), clock, node, r, captures, rng));
        }
    }
}

async fn rogue(medium: SharedMedium, clock: EmuClock, node: usize, p: Rogue, mut rng: Pcg32) {
    loop {
        // Exponential gap by inversion; `1 - u` is in (0, 1], so the logarithm is finite.
        let u: f64 = rng.random();
        let gap_ms = -(p.mean_gap.as_millis() as f64) * (1.0 - u).ln();
        clock
            .sleep_until(clock.now() + Duration::from_millis(gap_ms.round() as u64))
            .await;
        let len = rng.random_range(p.min_bytes..=p.max_bytes);
        let mut bytes: Vec<u8> = (0..len).map(|_| rng.random()).collect();
        if p.framed {
            bytes.splice(0..0, *b"ss");
            bytes.extend_from_slice(b"ss");
        }
        let end = Medium::transmit(&medium, node, &bytes, Emission::Noise);
        clock.sleep_until(end).await;
    }
}

/// A replay to send: when, a sequence number, the original's sender and capture time, bytes.
type Due = (Instant, u64, usize, Instant, Vec<u8>);

async fn replayer(
    medium: SharedMedium,
    clock: EmuClock,
    node: usize,
    p: Replayer,
    mut captures: UnboundedReceiver<Capture>,
    mut rng: Pcg32,
) {
    // Due replays, earliest first; the sequence number keeps capture order among equal times.
    let mut due: BinaryHeap<Reverse<Due>> = BinaryHeap::new();
    let mut seq = 0u64;
    loop {
        let next = due.peek().map(|Reverse((t, ..))| *t);
        let capture = match next {
            None => captures.recv().await,
            Some(t) => match select(captures.recv(), clock.sleep_until(t)).await {
                Either::First(c) => c,
                Either::Second(()) => {
                    if let Some(Reverse((_, _, from, captured, bytes))) = due.pop() {
                        let end = Medium::transmit(
                            &medium,
                            node,
                            &bytes,
                            Emission::Replay { from, captured },
                        );
                        clock.sleep_until(end).await;
                    }
                    continue;
                }
            },
        };
        let Some(c) = capture else { return };
        let lo = p.min_delay.as_millis();
        let delay = Duration::from_millis(rng.random_range(lo..=p.max_delay.as_millis().max(lo)));
        // Never before the replayer's own light is free again.
        let at = (c.t + delay).max(medium.borrow().busy_until(node));
        due.push(Reverse((at, seq, c.from, c.t, c.bytes)));
        seq += 1;
    }
}
