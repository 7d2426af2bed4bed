//! The board: hal-emu is just another board. Like `firmware/src/bin/nucleo_l476.rs` and the
//! QEMU board, it implements the firmware's hardware traits ([`firmware::hal`]) and nothing
//! else, so the unchanged robot program runs on it:
//!
//! - [`light`]: the light transmitter and the per-sector receivers
//!   ([`embedded_io_async::Write`] and [`Read`](embedded_io_async::Read));
//! - [`sensor`]: the environmental [`Sensor`](firmware::Sensor);
//! - [`leds`]: the top-cap [`Leds`](firmware::Leds);
//! - [`clock`]: the [`Clock`](firmware::Clock), virtual time on a [`timeline`], one value
//!   shared by every robot of a run and by the world around them;
//! - [`timeline`]: the deadlines of a virtual-time run, one queue (a wheel of
//!   milliseconds, a heap beyond) driven by one tokio timer, or running the run's tasks
//!   itself ([`exec`]).
//!
//! ## Layering
//! The board is the bottom layer of hal-emu: it imports nothing of [`crate::world`]. What a
//! device needs of its surroundings the board states as a small trait of its own, and the
//! world implements it: the light the transmitter sends into ([`light::Air`], the world's
//! medium), what the sensor reads ([`sensor::Surroundings`], the world's environment), what
//! sees the LEDs ([`leds::Camera`], the world's LED record). The world builds a robot's board
//! when the robot boots ([`Medium::attach`](crate::world::medium::Medium::attach) hands out its
//! light; the run makes its sensor and LEDs).

pub mod clock;
pub mod exec;
pub mod leds;
pub mod light;
pub mod sensor;
pub mod timeline;
