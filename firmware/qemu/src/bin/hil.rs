//! The QEMU board's robot in the loop with two receivers (a robot in a line, the lab's): see [`hil_robot`].
//!
//! Build with `cargo hil-image` (from the repository root): the ELF is
//! `firmware/qemu/target/thumbv7em-none-eabihf/release/hil`.

#![no_std]
#![no_main]
#![deny(unsafe_code)]

#[path = "../exec.rs"]
mod exec;
#[path = "../hil_robot.rs"]
mod hil_robot;
#[path = "../semilog.rs"]
mod semilog;
#[path = "../tick.rs"]
mod tick;
#[path = "../uart.rs"]
mod uart;

#[cortex_m_rt::entry]
fn main() -> ! {
    hil_robot::main::<2>()
}
