//! QEMU as a robot in the loop: a fresh `qemu-system-arm -machine mps2-an386` process per run,
//! booting the one-robot HIL image, its UART0 a TCP client of ours; its output is kept for a
//! failure's message.

use std::path::Path;
use std::process::Stdio;

use super::ends::{LinkEnds, keep_log};
use super::error::HilError;

/// Boots QEMU on `image` for `ends` (the process and the tasks keeping its output go into
/// `ends`, so that they are ended with it) and waits for it to connect its UART.
///
/// # Errors
/// No image, no QEMU, or no connection within 10 s (with QEMU's last words).
pub(super) async fn start(
    ends: &mut LinkEnds,
    image: &Path,
) -> Result<tokio::net::TcpStream, HilError> {
    if !image.is_file() {
        return Err(HilError::NoImage {
            image: image.to_path_buf(),
        });
    }
    // QEMU connects UART0 to a socket of ours; its stdout and stderr (the image's
    // semihosting log, QEMU's complaints) are kept for the failure message.
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .map_err(HilError::NoSocket)?;
    let port = listener.local_addr().map_err(HilError::NoSocket)?.port();
    let mut child = tokio::process::Command::new("qemu-system-arm")
        .args(qemu_args(image, port))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .kill_on_drop(true)
        .spawn()
        .map_err(HilError::Spawn)?;
    let outs: [Option<Box<dyn tokio::io::AsyncRead + Unpin>>; 2] = [
        child.stdout.take().map(|o| Box::new(o) as _),
        child.stderr.take().map(|o| Box::new(o) as _),
    ];
    for out in outs.into_iter().flatten() {
        ends.tasks
            .push(tokio::task::spawn_local(keep_log(out, ends.log.clone())));
    }
    ends.child = Some(child);
    let after = std::time::Duration::from_secs(10);
    match tokio::time::timeout(after, listener.accept()).await {
        Ok(Ok((s, _))) => Ok(s),
        Ok(Err(e)) => Err(HilError::Qemu(e)),
        Err(_) => Err(HilError::UartTimeout { after }.with_output(ends.output())),
    }
}

/// The QEMU command line of a robot in the loop: mps2-an386 in real time (no `-icount`), its
/// UART0 a TCP client of the host's `port` on 127.0.0.1, semihosting (the image's log) on
/// stdout. (Semihosting writes to QEMU's stdout whatever `-semihosting-config` says, so the
/// link cannot share it.)
pub fn qemu_args(image: &Path, port: u16) -> Vec<std::ffi::OsString> {
    // nodelay: QEMU writes the UART byte by byte, and Nagle's algorithm held them back up to
    // 40 ms (the heartbeat's round trip was 21 ms on average, 39 ms at worst).
    let serial = format!("tcp:127.0.0.1:{port},nodelay=on");
    let mut a: Vec<std::ffi::OsString> = [
        "-machine",
        "mps2-an386",
        "-cpu",
        "cortex-m4",
        "-display",
        "none",
        "-monitor",
        "none",
        "-serial",
        serial.as_str(),
        "-semihosting-config",
        "enable=on,target=native",
        "-kernel",
    ]
    .iter()
    .map(Into::into)
    .collect();
    a.push(image.as_os_str().to_owned());
    a
}
