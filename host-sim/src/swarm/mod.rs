//! The paper's 2D swarm simulator (section 3): the engine ([`sim`]) over the swarm's
//! [`geometry`] and the environment's fields ([`hal_emu::world::field`], shared with the
//! arena), the [`scenario`]s, the [`experiment`]s run on them (runs, sweeps, direction maps,
//! profiles). `docs/reproduction.md`, which runs them all, is [`crate::pages::reproduction`].

pub mod experiment;
pub mod geometry;
pub mod json;
pub mod measure;
pub mod probe;
pub mod reading;
pub mod scenario;
pub mod sensitivity;
pub mod shapes;
pub mod sim;
pub mod tap;
pub mod timecourse;
pub mod waves;
