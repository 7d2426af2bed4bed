//! Opening a link to a robot in the loop over its transport ([`open`]): a TCP socket (here),
//! QEMU (`qemu.rs`), a serial port (`serial.rs`) or the robot program in this process
//! (`in_process.rs`).

use firmware::Config;
use tokio::sync::mpsc::unbounded_channel;

use super::ends::LinkEnds;
use super::error::HilError;
use super::in_process::in_process;
use super::qemu;
use super::serial::serial;
use super::transport::Transport;
use crate::board::clock::EmuClock;

/// Opens the link to one robot over `transport`, and asks the robot who it is (an in-process
/// robot runs on `clock`, with `base` as the configuration its image would have).
///
/// # Errors
/// Why the transport could not be opened (no QEMU, no such port, connection refused).
pub async fn open(
    transport: &Transport,
    clock: EmuClock,
    base: Config,
) -> Result<LinkEnds, HilError> {
    let (to_host, from_robot) = unbounded_channel::<Vec<u8>>();
    let (to_robot, from_host) = unbounded_channel::<Vec<u8>>();
    let mut ends = LinkEnds::new(from_robot, to_robot);
    match transport {
        Transport::InProcess => {
            ends.tasks.push(tokio::task::spawn_local(in_process(
                to_host, from_host, clock, base,
            )));
        }
        Transport::Tcp(addr) => {
            let s = connect(addr).await?;
            ends.attach(s, to_host, from_host);
        }
        Transport::Qemu(image) => {
            let s = qemu::start(&mut ends, image).await?;
            ends.attach(s, to_host, from_host);
        }
        Transport::Serial(path, baud) => {
            ends.threads = serial(path, *baud, to_host, from_host, ends.stop.clone())?;
        }
    }
    ends.ask_hello();
    Ok(ends)
}

/// Connects to a robot on a TCP socket (`HOST:PORT`), within 10 s.
async fn connect(addr: &str) -> Result<tokio::net::TcpStream, HilError> {
    let after = std::time::Duration::from_secs(10);
    tokio::time::timeout(after, tokio::net::TcpStream::connect(addr))
        .await
        .map_err(|_| HilError::ConnectTimeout {
            addr: addr.to_string(),
            after,
        })?
        .map_err(|source| HilError::Tcp {
            addr: addr.to_string(),
            source,
        })
}
