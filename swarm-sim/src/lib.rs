//! # swarm-sim: the paper's 2D swarm simulator (section 3)
//!
//! N agents running the `protocol` crate's three-phase CIMAX ([`protocol::ThreePhaseAgent`]),
//! stepped in whole seconds, in a swarm that moves rigidly after every negotiation period. The
//! engine ([`sim`]; for plain runs its [`lean`] twin, below) runs over the swarm's [`geometry`] and the environment's fields
//! ([`hal_emu::world::field`], shared with the emulated lab), the [`scenario`]s, and the
//! [`experiment`]s run on them (runs, sweeps, direction maps, profiles). The seed derivation
//! ([`seeds`]), the summary statistics ([`stats`]) and the progress bar ([`progress`]) are
//! shared by every crate above it. `docs/reproduction.md`, which runs them all, is made by the
//! `pages` crate.
//!
//! ## What it never does
//! - implement CIMAX a second time without holding it to the first: every run that records,
//!   taps or reads an agent steps `protocol`'s state machines; the plain runs (most of
//!   `docs/reproduction.md`'s time) run on [`lean`], the three-phase rules written out over
//!   plain records for speed, which a test holds to `ThreePhaseAgent` period for period, bit for
//!   bit, over five protocol settings (and the page must come out the same from either);
//! - depend on the number of threads: every run has its own seed ([`seeds`]), runs are
//!   independent, and results are collected in run order.

mod calendar;
pub mod experiment;
pub mod geometry;
pub mod json;
pub mod lean;
pub mod measure;
pub mod probe;
pub mod progress;
pub mod reading;
pub mod scenario;
pub mod seeds;
pub mod sensitivity;
pub mod shapes;
pub mod sim;
pub mod stats;
pub mod tap;
pub mod timecourse;
pub mod waves;
