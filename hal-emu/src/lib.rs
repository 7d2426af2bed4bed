//! # Emulated aMussel hardware
//!
//! Implements the firmware's hardware traits ([`firmware::hal`]) on a PC, so virtual robots run
//! the unchanged robot program ([`firmware::Robot::run`]) in a simulated world. Three parts,
//! kept apart:
//!
//! - [`board`]: **the board**, the firmware traits' emulated implementations. hal-emu is just
//!   another board: the light transmitter and receivers ([`board::light`]), the environmental
//!   sensor ([`board::sensor`]), the LEDs ([`board::leds`]) and the clock ([`board::clock`],
//!   virtual time) implement the firmware's traits and nothing else, like the Nucleo and QEMU
//!   boards do.
//! - [`world`]: **the world** the boards live in, the simulated environment. The light medium
//!   ([`world::medium`]: positions and range; a frame reaches the receiver facing the sender
//!   after an airtime set by its length and the bitrate; overlapping frames collide, a robot
//!   cannot receive while it transmits, frames are lost and bytes corrupted at set rates;
//!   every frame is traced), what the sensors read ([`world::env`], [`world::field`]),
//!   adversaries in the light ([`world::adversary`]), robots in the loop ([`world::hil`]), and
//!   the run that puts it all together ([`world::arena`]: robots in a line or on a
//!   plane, each with the shared or its own [`firmware::Config`], scheduled pattern changes,
//!   kills and restarts, adversaries, LED changes recorded with their times). The same seed
//!   gives the same trace, bit for bit.
//! - [`judge`]: **the judge**. The paper's lab experiment as runs of the world, and the check
//!   a person makes by looking at the top-cap LEDs.
//!
//! Nothing in `firmware` knows it is emulated: the board only implements its traits.
//!
//! ## Layering
//! The three parts are layers, each using only those below it: `judge → world → board`. The
//! board imports nothing of the world: what its devices need of their surroundings (the light
//! a transmitter sends into, what a sensor reads, what sees the LEDs) it states as small traits
//! of its own ([`board::light::Air`], [`board::sensor::Surroundings`], [`board::leds::Camera`]),
//! which the world implements. The world and the board know nothing of the judge.
//!
//! Where to start reading: [`run`] and [`ArenaConfig`], then [`judge::judge`].
//!
//! ## Paths
//! Each module lives where the list above says (`hal_emu::world::arena`, `hal_emu::judge`,
//! `hal_emu::board::light`); what most callers need is also at the top ([`run`],
//! [`ArenaConfig`], [`TraceEvent`], ...). There are no other paths: the old ones
//! (`hal_emu::lab`, `hal_emu::medium`, `hal_emu::arena`, ...) are gone.
//!
//! ## What it never does
//! Read the wall clock or an unseeded RNG (except to report wall time), share state between
//! runs, or use threads: one run runs on one thread (its timeline's own executor, or a
//! current-thread tokio runtime with robots in the loop), so runs can be spread over threads by
//! the caller and stay reproducible.
//!
//! It has one `unsafe` block: the executor's cache prefetch (`board::exec`), a hint that can
//! neither fault nor change what a run does. Everything else is safe code (`deny`, not
//! `forbid`, so that this one block can say so).

#![deny(unsafe_code)]

pub mod board;
pub mod judge;
pub mod world;

pub use board::clock::EmuClock;
/// Positions in the arena, metres (re-exported so callers need not depend on nalgebra).
pub use nalgebra::Point2;
pub use world::adversary::{Adversary, AdversaryKind, Replayer, Rogue};
pub use world::arena::{ArenaConfig, ArenaError, LedChange, RunReport, run};
pub use world::env::{Environment, Readings, ReadingsError};
pub use world::medium::{DropReason, MediumParams, MediumStats, TraceEvent};
