//! # host-sim: the CIMAX simulators
//!
//! The library behind the `cimax` command-line tool. `cimax swarm ...` is the paper's 2D
//! simulation (section 3): N agents running the `protocol` crate's three-phase CIMAX
//! ([`protocol::ThreePhaseAgent`]), stepped in whole seconds, in a swarm that moves rigidly after
//! every negotiation period.
//!
//! ## Where to start reading
//! - [`swarm`]: the 2D simulator. [`swarm::sim`] is the engine (message delivery, readings,
//!   the move) over [`swarm::geometry`] (placement and neighbour lists) and [`hal_emu::world::field`]
//!   (the environment); [`swarm::scenario`]: the built-in scenarios and the TOML scenario
//!   files; [`swarm::experiment`]: runs, sweeps, preferred-direction grids, spread over all
//!   cores.
//! - [`arena`]: the emulated lab over `hal-emu`: robots on a plane ([`arena::plane`]), the fault
//!   campaign ([`arena::campaign`]) and its stress sections ([`arena::stress`]). `cimax arena` itself (robots in a line under light patterns, judged by
//!   `hal_emu::judge`) is the binary's `cli/arena`, beside `cli/swarm.rs`.
//! - [`pages`]: the simulators' results as figures ([`pages::figures`]), CSV files
//!   ([`pages::csv`]) and pages: [`pages::reliability`] (`docs/reliability.md`) and
//!   [`pages::reproduction`], which runs every experiment for `docs/reproduction.md` (with
//!   [`pages::shapes`] and [`pages::waves`]); and what the pages say about the paper: its claims
//!   typed once ([`pages::claims`]), one verdict function per kind of claim
//!   ([`pages::verdict`]), the paper's marks on the figures ([`pages::marks`]).
//! - [`report`]: generic output, a leaf: CSV writing and number formatting
//!   ([`report::csv_files`]), the x–y figure, legend and palette ([`report::plot`]), and page
//!   rendering from the templates in `host-sim/templates/` ([`report::page`]).
//! - [`viewer`]: the replay viewer's page of a run (`--html`, `cimax view`).
//! - [`seeds`] and [`progress`]: the seed derivation and the progress bar both sides share.
//! - [`shard`]: a long command split over processes (`--shard I/N`), its part files, and
//!   `cimax merge`'s checks.
//!
//! Data flow: scenario → experiment (`swarm`, `arena`) → result structs → `pages` → JSON | CSV |
//! template → page | plot, written through `report`. `report` imports none of the others;
//! `swarm` and `arena` import neither `report` nor `pages`.
//!
//! ## What it never does
//! - implement CIMAX a second time: every decision is made by `protocol`'s state machines;
//! - depend on the number of threads: every run has its own seed ([`seeds`]), runs are
//!   independent, and results are collected in run order.

pub mod arena;
pub mod pages;
pub mod progress;
pub mod report;
pub mod seeds;
pub mod shard;
pub mod stats;
pub mod swarm;
pub mod viewer;
