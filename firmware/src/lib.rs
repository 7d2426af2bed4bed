//! The aMussel robot program (skeleton).
//!
//! This crate will bind [`protocol::FusedNode`] to hardware traits (light transmitter and
//! receivers, ambient-light/oxygen sensor, top-cap LEDs, clock) and run it as embassy tasks on a
//! Cortex-M4F board and in QEMU; `hal-emu` will implement the same traits on a PC. Nothing is
//! implemented yet: see the firmware issue and `docs/architecture.md`.

#![no_std]
#![forbid(unsafe_code)]

pub use protocol;
