//! The checks behind the cargo-fuzz targets of the `protocol` crate, and their seed corpus.
//!
//! Each target in `fuzz_targets/` is one line: it hands libFuzzer's bytes to a `check`
//! function here, which drives the protocol through its public API and panics (a libFuzzer
//! crash) when an invariant fails. Keeping the checks in a library lets `cargo test` replay
//! the committed corpus through them on the pinned stable toolchain, and lets the seed
//! generator ([`corpus`]) share the input formats with the readers.
//!
//! | Target           | Check                                  |
//! |------------------|----------------------------------------|
//! | `deframer`       | [`deframer::check`]                    |
//! | `message_decode` | [`message_decode::check`]              |
//! | `roundtrip`      | [`roundtrip::check`]                   |
//! | `fused_node`     | [`fused_node::check`]                  |
//! | `three_phase`    | [`three_phase::check`]                 |
//! | `keyed`          | [`keyed::check`]                       |
//! | `link_decode`    | [`link_decode::check`]                 |
//! | `link_roundtrip` | [`link_roundtrip::check`]              |
//! | `link_pump`      | [`link_pump::check`]                   |
//! | `link_host`      | [`link_host::check`]                   |
//!
//! The `link_*` targets fuzz the hardware-in-the-loop link (`firmware::hil`, `docs/hil.md`):
//! its codec against an independent model ([`link_ref`]), the robot's receive pump and the
//! host's reading of a robot.
//!
//! `README.md` lists every invariant; `docs/protocol.md` and `docs/hil.md` are the
//! specifications they come from.

#![forbid(unsafe_code)]

pub mod corpus;
pub mod deframer;
pub mod fused_node;
pub mod input;
pub mod keyed;
pub mod link_corpus;
pub mod link_decode;
pub mod link_host;
pub mod link_pump;
pub mod link_ref;
pub mod link_roundtrip;
pub mod message_decode;
pub mod reference;
pub mod roundtrip;
pub mod scenario;
pub mod three_phase;

/// The names of the fuzz targets, as in `Cargo.toml` and `corpus/<target>/`.
pub const TARGETS: [&str; 10] = [
    "deframer",
    "message_decode",
    "roundtrip",
    "fused_node",
    "three_phase",
    "keyed",
    "link_decode",
    "link_roundtrip",
    "link_pump",
    "link_host",
];
