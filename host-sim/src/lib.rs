//! # host-sim: the CIMAX simulators
//!
//! The library behind the `cimax` command-line tool. `cimax swarm ...` is the paper's 2D
//! simulation (section 3): N agents running the `protocol` crate's three-phase CIMAX
//! ([`protocol::ThreePhaseAgent`]), stepped in whole seconds, in a swarm that moves rigidly after
//! every negotiation period.
//!
//! ## Where to start reading
//! - [`sim`]: the engine (message delivery, readings, the move) over [`geometry`] (placement and
//!   neighbour lists) and [`field`] (the environment);
//! - [`scenario`]: the built-in scenarios and the TOML scenario files;
//! - [`experiment`]: runs, sweeps, preferred-direction grids, spread over all cores;
//! - [`plot`] and [`report`]: SVG figures, CSV files and `docs/reproduction.md`.
//!
//! ## What it never does
//! - implement CIMAX a second time: every decision is made by `protocol`'s state machines;
//! - depend on the number of threads: every run has its own seed ([`seeds`]), runs are
//!   independent, and results are collected in run order.

pub mod campaign;
pub mod experiment;
/// The environment's fields, shared with the emulated arena (they live in `hal-emu`).
pub use hal_emu::field;
pub mod geometry;
pub mod plane;
pub mod plot;
pub mod report;
pub mod scenario;
pub mod seeds;
pub mod sim;
pub mod stress;
