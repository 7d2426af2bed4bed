//! Emulated aMussel hardware (skeleton).
//!
//! This crate will implement the firmware's hardware traits over tokio channels and a simulated
//! light medium, so virtual robots run the unchanged robot program on a PC. Nothing is
//! implemented yet: see the arena issue and `docs/architecture.md`.

#![forbid(unsafe_code)]
