//! # Emulated aMussel hardware
//!
//! Implements the firmware's hardware traits ([`firmware::hal`]) on a PC, so virtual robots run
//! the unchanged robot program ([`firmware::Robot::run`]) in a simulated world:
//!
//! - [`medium`]: the modulated-light medium. Robots have positions and a range; a frame reaches
//!   the receiver facing the sender of every robot in range, after an airtime set by its length
//!   and the bitrate. Overlapping frames at one receiver collide and arrive garbled; a robot
//!   cannot receive while it transmits; frames are lost per receiver with a probability and
//!   bytes are corrupted at a byte error rate. Every frame sent, received or dropped (with why)
//!   is traced.
//! - [`env`]: what each robot's sensor reads: a light pattern (lit or dark, with noise) that can
//!   change at scheduled times.
//! - [`clock`]: the robots' clock on tokio's paused clock, so virtual time runs as fast as the
//!   CPU allows and task order is deterministic.
//! - [`adversary`]: a rogue transmitter sending random bytes and a replayer sending captured
//!   frames again, both nodes of the same medium.
//! - [`arena`]: a whole run: robots in a line, scheduled pattern changes, kills and restarts,
//!   adversaries, LED changes recorded with their times. The same seed gives the same trace,
//!   bit for bit.
//!
//! Nothing in `firmware` knows it is emulated: these types only implement its traits.
//!
//! ## What it never does
//! Read the wall clock or an unseeded RNG (except to report wall time), share state between
//! runs, or use threads: one run is one current-thread tokio runtime, so runs can be spread
//! over threads by the caller and stay reproducible.

#![forbid(unsafe_code)]

pub mod adversary;
pub mod arena;
pub mod clock;
pub mod env;
pub mod field;
pub mod lab;
pub mod medium;

pub use adversary::{Adversary, AdversaryKind, Replayer, Rogue};
pub use arena::{ArenaConfig, ArenaError, LedChange, RunReport, run};
pub use clock::EmuClock;
pub use env::Environment;
pub use medium::{DropReason, MediumParams, MediumStats, TraceEvent};
/// Positions in the arena, metres (re-exported so callers need not depend on nalgebra).
pub use nalgebra::Point2;
