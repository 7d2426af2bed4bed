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

/// One robot of a run in the loop.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HilRobot {
    /// Its place (index into the arena's positions).
    pub robot: usize,
    /// How to reach it.
    pub transport: Transport,
}
