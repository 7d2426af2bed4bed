//! How the arena reaches a robot in the loop ([`Transport`]), and which place it takes
//! ([`HilRobot`]).

use std::fmt;
use std::path::PathBuf;

/// How the arena reaches one robot in the loop.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Transport {
    /// A fresh `qemu-system-arm -machine mps2-an386` process per run, booting this image (the
    /// one-robot HIL image, `cargo hil-image`), its UART0 on the process's stdin and stdout.
    Qemu(PathBuf),
    /// A board on a serial port at this baud rate (the Nucleo's ST-LINK virtual COM port).
    Serial(PathBuf, u32),
    /// Anything that speaks the link on a TCP socket (`HOST:PORT`), e.g. QEMU started by hand
    /// with `-serial tcp::PORT,server=on`.
    Tcp(String),
    /// The unchanged robot program (`firmware::hil::robot::run`) in this process, over a
    /// channel: the link and the bridge without QEMU.
    InProcess,
}

impl Transport {
    /// True if the robot runs on the arena's own (virtual) clock.
    pub fn virtual_time(&self) -> bool {
        matches!(self, Transport::InProcess)
    }
}

impl fmt::Display for Transport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Transport::Qemu(_) => f.write_str("qemu"),
            Transport::Serial(p, baud) => write!(f, "serial:{}@{baud}", p.display()),
            Transport::Tcp(a) => write!(f, "tcp:{a}"),
            Transport::InProcess => f.write_str("loopback"),
        }
    }
}

/// Whose clock a robot in the loop runs on (`cimax arena --hil-clock`, docs/hil.md "Time").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HilClock {
    /// The arena's: in lockstep with the run's virtual time, deterministic and faster than
    /// real time (QEMU robots, and their host twins in this process).
    #[default]
    Virtual,
    /// Its own: the run goes in wall-clock time (a board on a serial port).
    Wall,
}

/// One robot of a run in the loop.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HilRobot {
    /// Its place (index into the arena's positions).
    pub robot: usize,
    /// How to reach it.
    pub transport: Transport,
    /// Whose clock it runs on.
    pub clock: HilClock,
}

impl HilRobot {
    /// True if it runs in lockstep with the arena's clock over its link (a QEMU robot, one on
    /// a socket, or the host twin in this process, on the arena's clock). An in-process robot
    /// with [`HilClock::Wall`] shares the arena's clock directly instead (the wall-clock bridge
    /// in virtual time, for tests).
    pub fn follows(&self) -> bool {
        self.clock == HilClock::Virtual
            && matches!(
                self.transport,
                Transport::Qemu(_) | Transport::Tcp(_) | Transport::InProcess
            )
    }

    /// True if it runs on a clock of its own (the run then goes in real time).
    pub fn own_clock(&self) -> bool {
        !self.transport.virtual_time() && !self.follows()
    }
}
