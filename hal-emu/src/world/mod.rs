//! The world the emulated robots live in: everything around the board, nothing the firmware
//! knows of.
//!
//! - [`medium`]: the modulated-light medium (range, direction, airtime, collisions, half
//!   duplex, loss, corruption), with its trace and counters;
//! - [`env`](mod@env): what the sensors read, a light pattern over time or a [`field`] over the plane;
//! - [`field`]: the scalar fields of the 2D simulator, shared with `cimax swarm`;
//! - [`adversary`]: a rogue transmitter and a replayer, nodes of the same medium;
//! - [`hil`]: robots in the loop, running the real image elsewhere, bridged into the medium
//!   over the link of `docs/hil.md`;
//! - [`arena`]: a whole run, the orchestrator: it builds the world from an
//!   [`ArenaConfig`](arena::ArenaConfig), boots each robot on its board, kills and restarts
//!   robots, moves the swarm, and reports.
//!
//! ## Layering
//! The world sits on the board ([`crate::board`]), never the reverse: it implements what the
//! board's devices ask of their surroundings ([`Air`](crate::board::light::Air) by the
//! medium, [`Surroundings`](crate::board::sensor::Surroundings) by the environment,
//! [`Camera`](crate::board::leds::Camera) by the arena's LED record) and builds each robot's
//! board when it boots. Virtual time is the board's clock
//! ([`EmuClock`](crate::board::clock::EmuClock)), shared by the world.
//!
//! Within the world, imports point one way too: [`field`] and [`medium`] use nothing of the
//! world; [`env`](mod@env) uses `field`; [`adversary`] uses `medium`; [`hil`] uses only the
//! board; [`arena`] uses them all, and nothing in the world uses it.

pub mod adversary;
pub mod arena;
pub mod env;
pub mod field;
pub mod hil;
pub mod medium;
