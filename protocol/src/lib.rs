//! # CIMAX protocol core
//!
//! Collective information maximisation (Hornischer et al., "CIMAX: Collective Information
//! Maximization in Robotic Swarms Using Local Communication") for swarms of small robots that
//! talk with modulated light: the wave paradigm, both CIMAX variants and the `ss…ss` frame.
//!
//! ## What it never does
//! - allocate (`no_std`, no allocator; every buffer is a fixed-size `heapless` value);
//! - read a clock, draw unseeded randomness, or touch I/O: time ([`Instant`]), randomness
//!   (`rand_core::RngCore`) and received bytes come in as arguments, and outputs are polled out
//!   (`poll_transmit`, `poll_timeout`, `poll_event`), as in quinn-proto and smoltcp;
//! - keep global state: any number of robots can share one process;
//! - panic on input: hostile bytes, times and readings give typed errors or are counted.
//!
//! ## Where to start reading
//! - [`wave`]: the inactive / active / refractory state machine and its cycle clock;
//! - [`fused`]: [`FusedNode`], what the aMussels ran, with its decision rule;
//! - [`three_phase`]: [`ThreePhaseAgent`], the paper's 2D-simulation variant;
//! - [`message`] and [`frame`]: the hops and the 32-byte `ss…ss` frame with its [`Deframer`];
//! - [`auth`]: the optional [`SwarmKey`] and the MAC of authenticated frames;
//! - [`diversity`] and [`weights`]: how a direction is scored;
//! - [`params`]: every parameter with the paper's defaults;
//! - [`line`](mod@line): a direct-wired line of robots for tests and quick experiments;
//! - [`lab`]: the paper's six lab patterns and their expected decisions, for every harness.
//!
//! `docs/protocol.md` at the top of the repository has the byte diagram, golden vectors and
//! state machine in one place.

#![no_std]
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

pub mod auth;
pub mod direction;
pub mod diversity;
pub mod frame;
pub mod fused;
pub mod hash;
pub mod lab;
pub mod line;
pub mod message;
pub mod params;
pub mod three_phase;
pub mod time;
pub mod wave;
pub mod weights;

pub use auth::{KeyError, SwarmKey};
pub use direction::{MAX_SECTORS, Sector};
pub use diversity::{Diversity, Entropy, PerQuantity, Variance};
#[cfg(feature = "keyed")]
pub use frame::encode_keyed;
pub use frame::{Deframer, FrameError, KEYED_MAX_HOPS, encode};
pub use fused::{Event, FusedNode, Reception};
pub use message::{Hop, Level, MAX_HOPS, MAX_TAGS, Message, Tag};
pub use params::{InitiationPoint, ParamError, Params, WaveParams};
pub use three_phase::{SimMessage, ThreePhaseAgent};
pub use time::{Duration, Instant};
pub use wave::{WaveNode, WaveState};
