//! The world the emulated robots live in: everything around the board, nothing the firmware
//! knows of.
//!
//! - [`medium`]: the modulated-light medium (range, direction, airtime, collisions, half
//!   duplex, loss, corruption), with its trace and counters;
//! - [`env`](mod@env): what the sensors read, a light pattern over time or a [`field`] over the plane;
//! - [`field`]: the scalar fields of the 2D simulator, shared with `cimax swarm`;
//! - [`adversary`]: a rogue transmitter and a replayer, nodes of the same medium;
//! - [`clock`]: virtual time on tokio's paused clock;
//! - [`hil`]: robots in the loop, running the real image elsewhere, bridged into the medium
//!   over the link of `docs/hil.md`;
//! - [`arena`]: a whole run, the orchestrator: it builds the world from an
//!   [`ArenaConfig`](arena::ArenaConfig), boots each robot on its board, kills and restarts
//!   robots, moves the swarm, and reports.

pub mod adversary;
pub mod arena;
pub mod clock;
pub mod env;
pub mod field;
pub mod hil;
pub mod medium;
