//! # host-sim: the `cimax` command-line tool
//!
//! The binary (`src/main.rs`, its command line in `src/cli/`) drives the host crates, one per
//! layer, in the order data flows (docs/architecture.md, "Host tools"):
//!
//! `swarm-sim` (the 2D simulator, seeds, statistics) → `report` (generic CSV and SVG, a leaf)
//! → `viewer` (the replay page of a run) → `lab` (the emulated lab's experiments over
//! `hal-emu`) → `pages` (results as pages, figures and CSV files) → `host-sim` (`cimax`).
//!
//! Each crate imports only those before it; the compiler keeps the direction. This library
//! holds what only the tool needs: [`shard`], a long command split over processes
//! (`--shard I/N`), its part files, and `cimax merge`'s checks.

pub mod shard;
