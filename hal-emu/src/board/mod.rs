//! The board: hal-emu is just another board. Like `firmware/src/bin/nucleo_l476.rs` and the
//! QEMU board, it implements the firmware's hardware traits ([`firmware::hal`]) and nothing
//! else, so the unchanged robot program runs on it:
//!
//! - [`light`]: the light transmitter and the per-sector receivers
//!   ([`embedded_io_async::Write`] and [`Read`](embedded_io_async::Read)), over the world's
//!   light medium;
//! - [`sensor`]: the environmental [`Sensor`](firmware::Sensor), reading the world's
//!   environment;
//! - [`leds`]: the top-cap [`Leds`](firmware::Leds), recorded as a camera would;
//! - the [`Clock`](firmware::Clock) is the world's ([`crate::world::clock::EmuClock`]): every
//!   robot of a run shares virtual time.
//!
//! The world ([`crate::world`]) hands these out when a robot boots
//! ([`Medium::attach`](crate::world::medium::Medium::attach), the run's boot of a robot).

pub mod leds;
pub mod light;
pub mod sensor;
