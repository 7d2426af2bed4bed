//! Why a robot in the loop could not be reached, greeted or kept in the run ([`HilError`]),
//! and why `cimax arena --hil` could not read its robots ([`SpecError`]).

use std::io;
use std::path::PathBuf;
use std::time::Duration as WallDuration;

use firmware::hil::{LINK_VERSION, LinkError, LinkMsg};
use protocol::{Duration, Instant};

/// Why a robot in the loop failed: its link could not be opened, it said something the host
/// cannot accept, or it went silent. The message names its transport (`over`); the arena adds
/// the robot.
#[derive(Debug, thiserror::Error)]
pub enum HilError {
    /// There is no HIL image to boot QEMU on.
    #[error("no HIL image at {} (build it with `cargo hil-image`, docs/hil.md)", image.display())]
    NoImage {
        /// Where it should be.
        image: PathBuf,
    },
    /// No local socket for QEMU's UART to connect to.
    #[error("qemu: no local socket: {0}")]
    NoSocket(#[source] io::Error),
    /// `qemu-system-arm` could not be started.
    #[error("qemu-system-arm: {0} (is QEMU installed?)")]
    Spawn(#[source] io::Error),
    /// QEMU's connection failed.
    #[error("qemu: {0}")]
    Qemu(#[source] io::Error),
    /// The socket to a robot could not be shared with its reader.
    #[error("qemu: socket: {0}")]
    Socket(#[source] io::Error),
    /// QEMU did not connect its UART in time.
    #[error("qemu did not connect its UART within {} s", after.as_secs())]
    UartTimeout {
        /// How long the host waited.
        after: WallDuration,
    },
    /// A robot on a TCP socket could not be reached.
    #[error("tcp:{addr}: {source}")]
    Tcp {
        /// Its `HOST:PORT`.
        addr: String,
        /// Why.
        source: io::Error,
    },
    /// A robot's `HOST:PORT` names no address.
    #[error("tcp:{addr}: no address")]
    NoAddress {
        /// Its `HOST:PORT`.
        addr: String,
    },
    /// A robot on a TCP socket did not accept the connection in time.
    #[error("tcp:{addr}: no connection within {} s", after.as_secs())]
    ConnectTimeout {
        /// Its `HOST:PORT`.
        addr: String,
        /// How long the host waited.
        after: WallDuration,
    },
    /// A board's serial port could not be opened.
    #[error("serial:{port}: {source}")]
    Serial {
        /// The port's path.
        port: String,
        /// Why.
        source: serialport::Error,
    },
    /// The robot's link did not open (asking whether it follows the host's clock).
    #[error("its link did not open ({0})")]
    Unreachable(#[source] Box<HilError>),
    /// The robot's link did not open (at the start of its bridge).
    #[error("its link did not open: {0}")]
    NotOpened(#[source] Box<HilError>),
    /// A failure, with the last lines the robot's process (QEMU) printed.
    #[error("{error}{}", last_words(output))]
    WithOutput {
        /// The failure.
        #[source]
        error: Box<HilError>,
        /// QEMU's last lines of output, oldest first (none: nothing is added).
        output: Vec<String>,
    },
    /// The robot has another number of receivers than the arena's robots.
    #[error("has {has} receivers (said hello over {over}); the arena's robots have {want}")]
    Sectors {
        /// Its receivers.
        has: u8,
        /// Its transport.
        over: String,
        /// The arena's robots' receivers.
        want: u8,
    },
    /// The robot's image cannot follow the host's clock.
    #[error(
        "its image cannot follow the host's clock (its Hello says so): rebuild it with \
         `cargo hil-image`, or run it with --hil-clock wall"
    )]
    NoHostClock,
    /// The robot speaks another link version.
    #[error("speaks link version {version} over {over}; this host speaks {LINK_VERSION}")]
    Version {
        /// Its link version.
        version: u8,
        /// Its transport.
        over: String,
    },
    /// The robot's link ended before its `Hello`.
    #[error("its {over} link ended before it said hello")]
    EndedBeforeHello {
        /// Its transport.
        over: String,
    },
    /// The robot said no `Hello` in time.
    #[error("never said hello over {over} within {} s", within.as_secs())]
    NoHello {
        /// Its transport.
        over: String,
        /// How long the host waited.
        within: WallDuration,
    },
    /// Writing to the robot failed: its link ended.
    #[error("its {over} link ended (writing: {source})")]
    Write {
        /// Its transport.
        over: String,
        /// Why.
        source: io::Error,
    },
    /// The robot's link ended during the run.
    #[error("its {over} link ended (disconnected)")]
    Disconnected {
        /// Its transport.
        over: String,
    },
    /// The robot's link ended while the host was sending.
    #[error("its link ended (disconnected) while the host was sending")]
    SendEnded,
    /// A message could not be encoded as a link frame.
    #[error("encoding {msg:?}: {error:?}")]
    Encode {
        /// The message.
        msg: Box<LinkMsg>,
        /// Why.
        error: LinkError,
    },
    /// A robot on its own clock cannot be given the run's swarm key.
    #[error(
        "cannot take the run's swarm key over {over} on its own clock: link version 3 gives \
         it only to robots on the arena's clock"
    )]
    NoKey {
        /// Its transport.
        over: String,
    },
    /// The robot refused the run's setup.
    #[error("refused the run's setup over {over}: {why} (code {code})")]
    Refused {
        /// Its transport.
        over: String,
        /// What the code means.
        why: &'static str,
        /// The refusal's code.
        code: u8,
    },
    /// The robot (on its own clock) stopped answering heartbeats.
    #[error("stopped its heartbeat over {over}: nothing for {} ms", silent.as_millis())]
    HeartbeatStopped {
        /// Its transport.
        over: String,
        /// How long it has been silent.
        silent: Duration,
    },
    /// The robot said `Hello` again during the run.
    #[error("said hello again over {over}: it rebooted during the run")]
    Rebooted {
        /// Its transport.
        over: String,
    },
    /// The robot sent no light during the run.
    #[error(
        "sent no light over {over} in {} s: its robot program is not running",
        ran.as_millis() / 1000
    )]
    Dark {
        /// Its transport.
        over: String,
        /// How long the run lasted.
        ran: Duration,
    },
    /// The robot is not one of the run's robots on the arena's clock.
    #[error("is no robot on the arena's clock")]
    NotInLockstep,
    /// The robot is on a socket: the arena cannot boot it.
    #[error("is on a socket: the arena cannot boot it")]
    CannotBoot,
    /// The robot's transport cannot follow the arena's clock.
    #[error("{transport} cannot follow the arena's clock")]
    CannotFollow {
        /// Its transport.
        transport: String,
    },
    /// The thread booting the robot panicked.
    #[error("its boot thread panicked")]
    BootPanicked,
    /// The run's time does not fit the link's clock.
    #[error("the run outlasts the link's clock (u32 milliseconds)")]
    ClockOverflow,
    /// The host twin's link ended.
    #[error("its loopback link ended (the robot stopped)")]
    LoopbackEnded,
    /// The host twin is gone.
    #[error("its loopback robot is gone")]
    LoopbackGone,
    /// The robot's QEMU is gone.
    #[error("its QEMU is gone")]
    QemuGone,
    /// The robot (on the arena's clock) said no `Idle` in time.
    #[error(
        "stopped answering over {over}: no Idle within {} ms of Sync({} ms)",
        patience.as_millis(),
        now.as_millis()
    )]
    Silent {
        /// Its transport.
        over: String,
        /// How long the host waited (wall time).
        patience: WallDuration,
        /// The `Sync`'s instant.
        now: Instant,
    },
    /// The robot said it was idle at another instant than the arena's.
    #[error("said it was idle at {said} ms over {over}; the arena is at {} ms", now.as_millis())]
    IdleAt {
        /// Its instant, milliseconds.
        said: u32,
        /// Its transport.
        over: String,
        /// The arena's instant.
        now: Instant,
    },
    /// The robot sent too many messages for one `Sync`.
    #[error(
        "floods the link over {over}: more than {most} messages for Sync({} ms)",
        now.as_millis()
    )]
    Flood {
        /// Its transport.
        over: String,
        /// The most messages a follower may send for one `Sync` ([`FLOOD`](super::FLOOD)).
        most: usize,
        /// The `Sync`'s instant.
        now: Instant,
    },
    /// The host twin did not say `Idle` once nothing could run.
    #[error(
        "did not say Idle for Sync({} ms) over loopback once nothing could run",
        now.as_millis()
    )]
    NoIdle {
        /// The `Sync`'s instant.
        now: Instant,
    },
    /// The lockstep ended before the robot's bridge.
    #[error("its lockstep ended")]
    LockstepEnded,
}

impl HilError {
    /// This failure with the last lines `output` of the robot's process (nothing is added if
    /// there are none).
    pub(crate) fn with_output(self, output: Vec<String>) -> Self {
        if output.is_empty() {
            self
        } else {
            HilError::WithOutput {
                error: Box::new(self),
                output,
            }
        }
    }
}

/// `; its output ends: ...` with the lines `output`, or nothing.
pub(crate) fn last_words(output: &[String]) -> String {
    if output.is_empty() {
        String::new()
    } else {
        format!("; its output ends: {}", output.join(" | "))
    }
}

/// Why `cimax arena --hil` could not read a robot in the loop (`qemu:N`, `serial:PATH[@BAUD]`,
/// `tcp:HOST:PORT`, `loopback:N`).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SpecError {
    /// `qemu:N` or `loopback:N` with N not from 1 to 64.
    #[error("{what}:N needs N from 1 to 64, not {n:?}")]
    Count {
        /// `qemu` or `loopback`.
        what: &'static str,
        /// What was given for N.
        n: String,
    },
    /// `serial:PATH@BAUD` with no baud rate.
    #[error("serial:PATH@BAUD: {baud:?} is no baud rate")]
    Baud {
        /// What was given for BAUD.
        baud: String,
    },
    /// `serial:` with no path.
    #[error("serial:PATH needs a path, e.g. serial:/dev/ttyACM0")]
    NoPath,
    /// `tcp:` with no host and port.
    #[error("tcp:HOST:PORT: {addr:?} is no host and port")]
    Address {
        /// What was given.
        addr: String,
    },
    /// None of the kinds.
    #[error(
        "{spec:?}: a robot in the loop is qemu:N, serial:PATH[@BAUD], tcp:HOST:PORT or loopback:N"
    )]
    Unknown {
        /// What was given.
        spec: String,
    },
}
