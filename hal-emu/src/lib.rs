//! # Emulated aMussel hardware
//!
//! Implements the firmware's hardware traits ([`firmware::hal`]) on a PC, so virtual robots run
//! the unchanged robot program ([`firmware::Robot::run`]) in a simulated world. Three parts,
//! kept apart:
//!
//! - [`board`]: **the board**. hal-emu is just another board: the light transmitter and
//!   receivers ([`board::light`]), the environmental sensor ([`board::sensor`]) and the LEDs
//!   implement the firmware's traits and nothing else, like the Nucleo and QEMU boards do.
//! - [`world`]: **the world** the boards live in. The light medium ([`medium`]: positions and
//!   range; a frame reaches the receiver facing the sender after an airtime set by its length
//!   and the bitrate; overlapping frames collide, a robot cannot receive while it transmits,
//!   frames are lost and bytes corrupted at set rates; every frame is traced), what the
//!   sensors read ([`env`](mod@env), [`field`]), adversaries in the light ([`adversary`]), virtual time
//!   ([`clock`]), and the run that puts it all together ([`arena`]: robots in a line or on a
//!   plane, each with the shared or its own [`firmware::Config`], scheduled pattern changes,
//!   kills and restarts, adversaries, LED changes recorded with their times). The same seed
//!   gives the same trace, bit for bit.
//! - [`judge`]: **the judge**. The paper's lab experiment as runs of the world, and the check
//!   a person makes by looking at the top-cap LEDs (also reachable as [`lab`]).
//!
//! Nothing in `firmware` knows it is emulated: the board only implements its traits.
//!
//! Where to start reading: [`run`] and [`ArenaConfig`], then [`judge::judge`].
//!
//! ## Paths
//! The world's modules are re-exported at the top ([`hal_emu::medium`](medium),
//! [`hal_emu::arena`](arena), ...) and the judge also as [`hal_emu::lab`](lab), the paths the
//! crate had before it was split; `medium` and `env` also still name the board's
//! transceivers and sensor.
//!
//! ## What it never does
//! Read the wall clock or an unseeded RNG (except to report wall time), share state between
//! runs, or use threads: one run is one current-thread tokio runtime, so runs can be spread
//! over threads by the caller and stay reproducible.

#![forbid(unsafe_code)]

pub mod board;
pub mod judge;
pub mod world;

pub use world::{adversary, arena, clock, field, hil};

/// The judge under its former name: `hal_emu::lab::judge` is [`judge::judge`].
pub use judge as lab;

/// The light medium ([`world::medium`]), with the board's transceivers
/// ([`board::light`]) that it hands out, under the path they had before the split.
pub mod medium {
    pub use crate::board::light::{EmuReceiver, EmuTransmitter};
    pub use crate::world::medium::*;
}

/// What the sensors read ([`world::env`]), with the board's sensor ([`board::sensor`]), under
/// the path they had before the split.
pub mod env {
    pub use crate::board::sensor::EmuSensor;
    pub use crate::world::env::*;
}

pub use adversary::{Adversary, AdversaryKind, Replayer, Rogue};
pub use arena::{ArenaConfig, ArenaError, LedChange, RunReport, run};
pub use clock::EmuClock;
pub use env::{Environment, Readings, ReadingsError};
pub use medium::{DropReason, MediumParams, MediumStats, TraceEvent};
/// Positions in the arena, metres (re-exported so callers need not depend on nalgebra).
pub use nalgebra::Point2;
