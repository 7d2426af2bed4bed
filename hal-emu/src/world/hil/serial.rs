//! A board on a serial port as a robot in the loop (the Nucleo's ST-LINK virtual COM port).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender};

use super::error::HilError;

/// A serial port, read and written by two threads (the port is blocking I/O).
pub(super) fn serial(
    path: &std::path::Path,
    baud: u32,
    to_host: UnboundedSender<Vec<u8>>,
    mut from_host: UnboundedReceiver<Vec<u8>>,
    stop: Arc<AtomicBool>,
) -> Result<Vec<std::thread::JoinHandle<()>>, HilError> {
    let name = path.to_string_lossy().into_owned();
    let failed = |source| HilError::Serial {
        port: name.clone(),
        source,
    };
    let mut port = serialport::new(&name, baud)
        .timeout(std::time::Duration::from_millis(50))
        .open()
        .map_err(failed)?;
    let mut writer = port.try_clone().map_err(failed)?;
    let stop_r = stop.clone();
    let reader = std::thread::spawn(move || {
        let mut buf = [0u8; 256];
        while !stop_r.load(Ordering::Relaxed) {
            match port.read(&mut buf) {
                Ok(0) => return,
                Ok(n) => {
                    if to_host.send(buf[..n].to_vec()).is_err() {
                        return;
                    }
                }
                Err(e) if e.kind() == std::io::ErrorKind::TimedOut => {}
                Err(_) => return,
            }
        }
    });
    let writer = std::thread::spawn(move || {
        while let Some(b) = from_host.blocking_recv() {
            if stop.load(Ordering::Relaxed) || writer.write_all(&b).is_err() {
                return;
            }
        }
    });
    Ok(vec![reader, writer])
}
