//! Robots in the loop: the host's end of the link of `docs/hil.md`.
//!
//! A robot in the loop runs the real robot program somewhere else (a QEMU process, a board on
//! a serial port, anything behind a TCP socket) and talks to the arena over one byte stream
//! (`firmware::hil`). Here it takes the place of a virtual robot in the medium: what its
//! transmitter sends (`Tx`) goes on air through the medium like any robot's frame (airtime,
//! collisions, loss, byte errors); what reaches its receivers goes back as `Rx`; its sensor
//! reads the arena's environment (`Reading`, every sample period); its `Led` messages go into
//! the LED record the judge reads. [`Transport`] says how to reach it; [`HilReport`] is what
//! the run reports about its link.
//!
//! A run with a robot in the loop runs in real time (the robot has its own clock), except when
//! every such robot runs in this process ([`Transport::InProcess`]: the unchanged
//! `firmware::hil::robot::run` over a channel, on the run's virtual clock), which tests the
//! link without QEMU, deterministically.
//!
//! The bridge fails its run, naming the robot and its transport, if the robot says no `Hello`
//! within [`HilTimeouts::hello`], speaks another link version or has other sectors, says
//! `Hello` again (it rebooted) or goes silent for [`HilTimeouts::silence`], or its stream
//! ends. Child processes are killed and reaped on every path ([`LinkEnds`]'s drop).
//!
//! Its parts, each using only those listed before it:
//!
//! - `transport.rs`: how to reach a robot in the loop ([`Transport`], [`HilRobot`]);
//! - `spec.rs`: the robots in the loop as `cimax arena --hil` names them ([`HilSpec`]);
//! - `error.rs`: why a robot in the loop failed ([`HilError`]) or could not be named
//!   ([`SpecError`]);
//! - `ends.rs`: a link's two ends on the host, as channels of bytes ([`LinkEnds`]);
//! - `qemu.rs`, `serial.rs`, `in_process.rs`: the transports other than a plain socket;
//! - `link.rs`: opening a link over its transport ([`open`]);
//! - `bridge.rs`: the bridge of one robot into the medium during a run, what it waits for
//!   ([`HilTimeouts`]) and what it reports ([`HilReport`]).

mod bridge;
mod ends;
mod error;
mod follower;
mod in_process;
mod link;
mod lockstep;
mod qemu;
mod serial;
mod spec;
mod transport;
mod twin;

pub(crate) use bridge::{Bridge, setup_of, setup_seed};
pub use bridge::{HilReport, HilTimeouts};
pub use ends::LinkEnds;
pub use error::{HilError, SpecError};
pub use follower::Follower;
pub use link::open;
pub(crate) use lockstep::Boot;
pub(crate) use lockstep::serve as serve_lockstep;
pub use lockstep::{FLOOD, Lockstep};
pub use qemu::qemu_args;
pub use spec::{DEFAULT_BAUD, HilSpec};
pub use transport::{HilClock, HilRobot, Transport};
