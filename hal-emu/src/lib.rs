//! # Emulated aMussel hardware
//!
//! Implements the firmware's hardware traits ([`firmware::hal`]) on a PC, so virtual robots run
//! the unchanged robot program ([`firmware::Robot::run`]) in a simulated world. Three parts,
//! kept apart:
//!
//! - [`board`]: **the board**. hal-emu is just another board: the light transmitter and
//!   receivers ([`board::light`]), the environmental sensor ([`board::sensor`]) and the LEDs
//!   implement the firmware's traits and nothing else, like the Nucleo and QEMU boards do.
//! - [`world`]: **the world** the boards live in. The light medium ([`world::medium`]: positions and
//!   range; a frame reaches the receiver facing the sender after an airtime set by its length
//!   and the bitrate; overlapping frames collide, a robot cannot receive while it transmits,
//!   frames are lost and bytes corrupted at set rates; every frame is traced), what the
//!   sensors read ([`world::env`], [`world::field`]), adversaries in the light
//!   ([`world::adversary`]), virtual time ([`world::clock`]), and the run that puts it all
//!   together ([`world::arena`]: robots in a line or on a
//!   plane, each with the shared or its own [`firmware::Config`], scheduled pattern changes,
//!   kills and restarts, adversaries, LED changes recorded with their times). The same seed
//!   gives the same trace, bit for bit.
//! - [`judge`]: **the judge**. The paper's lab experiment as runs of the world, and the check
//!   a person makes by looking at the top-cap LEDs.
//!
//! Nothing in `firmware` knows it is emulated: the board only implements its traits.
//!
//! Where to start reading: [`run`] and [`ArenaConfig`], then [`judge::judge`].
//!
//! ## Paths
//! Each module lives where the list above says (`hal_emu::world::arena`, `hal_emu::judge`,
//! `hal_emu::board::light`); what most callers need is re-exported at the top ([`run`],
//! [`ArenaConfig`], [`TraceEvent`], ...).
//!
//! ## What it never does
//! Read the wall clock or an unseeded RNG (except to report wall time), share state between
//! runs, or use threads: one run is one current-thread tokio runtime, so runs can be spread
//! over threads by the caller and stay reproducible.

#![forbid(unsafe_code)]

pub mod board;
pub mod judge;
pub mod world;

/// Positions in the arena, metres (re-exported so callers need not depend on nalgebra).
pub use nalgebra::Point2;
pub use world::adversary::{Adversary, AdversaryKind, Replayer, Rogue};
pub use world::arena::{ArenaConfig, ArenaError, LedChange, RunReport, run};
pub use world::clock::EmuClock;
pub use world::env::{Environment, Readings, ReadingsError};
pub use world::medium::{DropReason, MediumParams, MediumStats, TraceEvent};
