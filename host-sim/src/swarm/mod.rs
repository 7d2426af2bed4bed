//! The paper's 2D swarm simulator (section 3): the engine ([`sim`]) over the swarm's
//! [`geometry`] and the environment's [`field`]s, the [`scenario`]s, the [`experiment`]s run on
//! them (runs, sweeps, direction maps, profiles), and [`reproduce`], which runs them all for
//! `docs/reproduction.md`.

pub mod experiment;
/// The environment's fields, shared with the emulated arena (they live in `hal-emu`).
pub use hal_emu::world::field;
pub mod geometry;
pub mod measure;
pub mod reproduce;
pub mod scenario;
pub mod sensitivity;
pub mod shapes;
pub mod sim;
pub mod timecourse;
pub mod waves;
