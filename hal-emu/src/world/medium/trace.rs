//! The medium's trace: one [`TraceEvent`] per frame sent, received or dropped, LED change,
//! protocol event, move, kill, restart, pattern change and adversary action, in time order.
//! `cimax arena --trace` writes them as JSON lines (`{"event":"sent","t_ms":…}`, snake case) and
//! `cimax view` reads them back, so renaming a variant or a field changes that format.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

/// Why a frame did not reach a receiver.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DropReason {
    /// Lost on the way (the `loss` probability).
    Loss,
    /// The receiving robot was transmitting during the frame's airtime.
    ReceiverTransmitting,
    /// The receiving robot was dead (killed, not yet restarted).
    ReceiverDead,
}

/// One line of the trace (`cimax arena --trace` writes them as JSON lines, `cimax view` reads
/// them back).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum TraceEvent {
    /// A robot started sending a frame.
    Sent {
        /// Emulated time, ms.
        t_ms: u64,
        /// Sender.
        robot: usize,
        /// Frame length, bytes.
        len: usize,
    },
    /// A frame arrived at a receiver (possibly garbled or corrupted).
    Received {
        /// Emulated time, ms.
        t_ms: u64,
        /// Receiver.
        robot: usize,
        /// Sender.
        from: usize,
        /// The receiving robot's sector.
        sector: u8,
        /// Frame length, bytes.
        len: usize,
        /// True if it collided with another frame.
        garbled: bool,
        /// Bytes corrupted by the byte error rate.
        corrupted: u32,
    },
    /// A frame did not arrive.
    Dropped {
        /// Emulated time, ms.
        t_ms: u64,
        /// Would-be receiver.
        robot: usize,
        /// Sender.
        from: usize,
        /// Why.
        reason: DropReason,
    },
    /// A robot's LEDs changed.
    Led {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
        /// `green` (left), `blue` (right), `off`, or `sector N` (robots with more than two sectors).
        color: Cow<'static, str>,
    },
    /// A robot's wave state changed (from the robot program's protocol events).
    State {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
        /// `inactive`, `active` or `refractory`.
        state: Cow<'static, str>,
    },
    /// A robot's preferred direction changed.
    Preference {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
        /// `left`, `right`, `none` or `sector N`.
        preference: String,
    },
    /// A robot decided (the robot program's `Event::Decided`): what its LEDs show next, and
    /// what it was based on.
    Decided {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
        /// The negotiation period, counted from 1.
        period: u32,
        /// The sector decided, if any (with two: 0 right, 1 left).
        decision: Option<u8>,
        /// Votes counted per sector (K entries).
        votes: Vec<u16>,
        /// The average diversity heard per sector (K entries; `None`: nothing heard).
        scores: Vec<Option<f32>>,
        /// The robot's last sensor reading (a level, 0 to 255; in the 2D simulator the
        /// field's X where the agent is).
        reading: f32,
    },
    /// The swarm moved (robots on a plane): by `step` R along `heading` from `centre`.
    Moved {
        /// Emulated time, ms.
        t_ms: u64,
        /// The centre of mass before the move, in R.
        centre: [f64; 2],
        /// The heading (radians), if any robot had decided.
        heading: Option<f64>,
        /// The length of the move, in R (0 without a heading).
        step: f64,
        /// Fraction of all robots whose LEDs show the sector nearest the heading.
        consensus: f64,
    },
    /// A robot was killed.
    Killed {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
    },
    /// A robot was restarted with fresh state.
    Restarted {
        /// Emulated time, ms.
        t_ms: u64,
        /// Robot.
        robot: usize,
    },
    /// The light pattern changed.
    Pattern {
        /// Emulated time, ms.
        t_ms: u64,
        /// One character per robot, `1` lit.
        lights: String,
    },
    /// A rogue transmitter started a burst of random bytes.
    RogueSent {
        /// Emulated time, ms.
        t_ms: u64,
        /// The rogue's node number.
        node: usize,
        /// Burst length, bytes.
        len: usize,
    },
    /// A replayer started sending a captured frame again.
    Replayed {
        /// Emulated time, ms.
        t_ms: u64,
        /// The replayer's node number.
        node: usize,
        /// Frame length, bytes.
        len: usize,
        /// The robot that sent the original.
        from: usize,
        /// When the original was captured, ms.
        captured_ms: u64,
    },
    /// A frame reached a replayer (kept for replay if it came from a robot, intact).
    Captured {
        /// Emulated time, ms.
        t_ms: u64,
        /// The replayer's node number.
        node: usize,
        /// Sender.
        from: usize,
        /// Frame length, bytes.
        len: usize,
        /// True if kept for replay.
        kept: bool,
    },
}
