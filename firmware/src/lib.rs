//! # The aMussel robot program
//!
//! This crate turns [`protocol::FusedNode`] (fused CIMAX, sans-IO) into a robot:
//!
//! - [`hal`]: the hardware seam. The light transmitter is an [`embedded_io_async::Write`]
//!   byte stream, the receivers one [`Receivers`] (an array of
//!   [`Read`](embedded_io_async::Read) byte streams, one per sector, is one); the
//!   environmental [`Sensor`], the top-cap [`Leds`] and the [`Clock`] are small traits in the
//!   embedded-hal-async style. Boards and the emulator (`hal-emu`) implement these and nothing
//!   else.
//! - [`robot`]: [`Robot::run`], the one generic `async fn` every board runs: sample the sensor,
//!   deframe each receiver into the protocol with its direction, transmit what the protocol
//!   polls out, sleep until the next deadline, show each decision on the LEDs.
//! - [`identity`]: a robot's id from the chip's unique ID and its random seed from the
//!   hardware RNG mixed with that ID (pure functions, tested on the host).
//! - [`hil`]: the hardware-in-the-loop link's codec (version 1, `docs/hil.md`): the messages a
//!   robot and the host exchange over one byte stream, framed with COBS and a CRC.
//! - [`wired`]: hardware made of memory (pipes, fixed sensor, LED state), for the QEMU board's
//!   virtual robots and for tests.
//!
//! The real board is a binary of this package: `src/bin/nucleo_l476.rs` (STM32L476RG,
//! embassy-stm32, defmt over RTT; feature `board-nucleo-l476`). The QEMU board (`mps2-an386`,
//! four virtual robots in one image on [`wired`], semihosting) is a package of its own,
//! `firmware/qemu/` (its own workspace, built and run with `cargo qemu` from the repository
//! root), and the emulator `hal-emu` is a third board on the host. `docs/firmware.md` has the
//! pin map and how to build, flash and run.
//!
//! ## What it never does
//! - allocate: `no_std`, no heap; the robot's future has a size fixed at compile time;
//! - read a global clock or global state: time comes from the [`Clock`], everything a robot
//!   knows lives in its [`Robot`];
//! - panic on input or block for ever: bad frames and device failures are counted in
//!   [`Stats`] and logged, and every device call but a receiver's read has a timeout.
//!
//! ## Features
//! - `defmt`: log with defmt and derive `defmt::Format` (the real board);
//! - `log`: log through the `log` facade (the emulator, the QEMU board);
//! - `embassy-time`: `hal::EmbassyClock`, the [`Clock`] over embassy-time;
//! - `board-nucleo-l476`: the Nucleo binary (thumb targets only);
//! - `keyed`: authenticated frames with a swarm key ([`Config::key`]; `protocol/keyed`).

#![cfg_attr(not(test), no_std)]
#![forbid(unsafe_code)]

#[macro_use]
mod fmt;

pub mod hal;
pub mod hil;
pub mod identity;
pub mod robot;
pub mod wired;

pub use embedded_io_async;
pub use protocol;

/// The light link's bit rate, bits per second: the Nucleo image's IrDA SIR USARTs, the
/// emulated medium's default (`hal_emu::MediumParams`) and `cimax arena --bitrate`'s.
pub const LIGHT_BITRATE: u32 = 9_600;
/// Bits on air per byte of the light link: start, 8 data, stop (UART framing, IrDA SIR).
pub const LIGHT_BITS_PER_BYTE: u32 = 10;

pub use hal::{Clock, ErrorKind, LedColor, Leds, Quantity, Receivers, Sensor};
pub use robot::{Config, Hardware, Observer, Robot, SetupError, Stats};
