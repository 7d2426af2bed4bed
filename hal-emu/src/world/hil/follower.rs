//! A robot in the loop whose clock follows the arena's ([`Follower`], link version 2,
//! `docs/hil.md` "Time"): a QEMU process booted (or a socket connected) and greeted before the
//! run, reached over a blocking socket, its frames decoded by a thread of its own into a channel that the run's
//! [`Lockstep`](super::lockstep::Lockstep) reads only while the run's tasks wait. No tokio:
//! the run is on the timeline's own executor, and time moves only when every follower has
//! said it is idle.

use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration as WallDuration, Instant as WallInstant};

use firmware::hil::{LINK_FRAME_MAX, LINK_VERSION, LinkDecoder, LinkError, LinkMsg};

use super::error::HilError;
use super::qemu::qemu_args;

/// What the reader thread hands over.
#[derive(Debug)]
pub(crate) enum FromRobot {
    /// A message.
    Msg(LinkMsg),
    /// A `Hello` of another link version.
    Version(u8),
    /// The stream ended (the process died, or closed its end).
    Ended,
}

/// Lines of QEMU's output kept for a failure's message.
const LOG_LINES: usize = 3;

/// A QEMU robot, booted, connected and greeted, whose clock can follow the host's.
#[derive(Debug)]
pub struct Follower {
    /// Its transport, for messages (`qemu`, `tcp:HOST:PORT`).
    pub(crate) name: String,
    stream: TcpStream,
    child: Option<Child>,
    pub(crate) from: Receiver<FromRobot>,
    log: Arc<Mutex<VecDeque<String>>>,
    /// Bad link frames seen by the reader.
    errors: Arc<AtomicU64>,
    /// Bytes sent.
    pub(crate) sent: u64,
    /// The id it said hello with.
    pub(crate) hello_id: u16,
    /// Wall time from starting QEMU to its `Hello`.
    pub(crate) hello: WallDuration,
}

impl Follower {
    /// Boots QEMU on `image` and greets the robot: it must speak [`LINK_VERSION`], have
    /// `sectors` receivers and be able to follow the host's clock. Waits at most `hello` for
    /// its `Hello` (and 10 s for QEMU to connect).
    ///
    /// # Errors
    /// Why not, with QEMU's last words; the process is killed then.
    pub fn boot(image: &Path, sectors: u8, hello: WallDuration) -> Result<Self, HilError> {
        if !image.is_file() {
            return Err(HilError::NoImage {
                image: image.to_path_buf(),
            });
        }
        let listener = TcpListener::bind("127.0.0.1:0").map_err(HilError::NoSocket)?;
        let port = listener.local_addr().map_err(HilError::NoSocket)?.port();
        let mut child = Command::new("qemu-system-arm")
            .args(qemu_args(image, port))
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(HilError::Spawn)?;
        let log = Arc::new(Mutex::new(VecDeque::new()));
        let outs: [Option<Box<dyn Read + Send>>; 2] = [
            child.stdout.take().map(|o| Box::new(o) as _),
            child.stderr.take().map(|o| Box::new(o) as _),
        ];
        for out in outs.into_iter().flatten() {
            let log = log.clone();
            std::thread::spawn(move || keep_log(out, &log));
        }
        let mut f = Follower {
            name: "qemu".into(),
            stream: match accept(&listener, WallDuration::from_secs(10)) {
                Ok(s) => s,
                Err(e) => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(e.with_output(output(&log)));
                }
            },
            child: Some(child),
            from: channel().1,
            log,
            errors: Arc::default(),
            sent: 0,
            hello_id: 0,
            hello: WallDuration::ZERO,
        };
        let t0 = WallInstant::now();
        f.start_reader()?;
        f.greet(sectors, hello)
            .map_err(|e| e.with_output(f.output()))?;
        f.hello = t0.elapsed();
        Ok(f)
    }

    /// Connects to a robot on a TCP socket (`HOST:PORT`, within 10 s) and greets it, as
    /// [`boot`](Self::boot) does a QEMU robot.
    ///
    /// # Errors
    /// Why not (no connection, no hello, another version or sectors, a robot that cannot
    /// follow the host's clock).
    pub fn connect(addr: &str, sectors: u8, hello: WallDuration) -> Result<Self, HilError> {
        let mut f = Self::dial(addr)?;
        let t0 = WallInstant::now();
        f.greet(sectors, hello)?;
        f.hello = t0.elapsed();
        Ok(f)
    }

    /// Asks the robot on the TCP socket `addr` (`HOST:PORT`) whether it can follow the host's
    /// clock (its `Hello` says so; docs/hil.md, "Time"), then hangs up: `cimax arena --hil
    /// tcp:...` without `--hil-clock` runs it on the clock it says.
    ///
    /// # Errors
    /// Why it could not tell (no connection, no hello within `hello`, another version).
    pub fn follows_host_clock(addr: &str, hello: WallDuration) -> Result<bool, HilError> {
        let mut f = Self::dial(addr).map_err(|e| HilError::Unreachable(Box::new(e)))?;
        f.hello(hello).map(|(_, _, host_clock)| host_clock)
    }

    /// Connects to `addr` (within 10 s) and starts reading.
    fn dial(addr: &str) -> Result<Self, HilError> {
        use std::net::ToSocketAddrs;
        let tcp = |source| HilError::Tcp {
            addr: addr.to_string(),
            source,
        };
        let to =
            addr.to_socket_addrs()
                .map_err(tcp)?
                .next()
                .ok_or_else(|| HilError::NoAddress {
                    addr: addr.to_string(),
                })?;
        let stream = TcpStream::connect_timeout(&to, WallDuration::from_secs(10)).map_err(tcp)?;
        let mut f = Follower {
            name: format!("tcp:{addr}"),
            stream,
            child: None,
            from: channel().1,
            log: Arc::default(),
            errors: Arc::default(),
            sent: 0,
            hello_id: 0,
            hello: WallDuration::ZERO,
        };
        f.start_reader()?;
        Ok(f)
    }

    /// Starts the thread that decodes what the robot sends into [`Follower::from`].
    fn start_reader(&mut self) -> Result<(), HilError> {
        let _ = self.stream.set_nodelay(true);
        let stream = self.stream.try_clone().map_err(HilError::Socket)?;
        let (tx, rx) = channel();
        self.from = rx;
        let errors = self.errors.clone();
        std::thread::spawn(move || read_link(stream, &tx, &errors));
        Ok(())
    }

    /// Sends a 0x00 and asks who it is; waits for its `Hello` and checks it.
    fn greet(&mut self, sectors: u8, within: WallDuration) -> Result<(), HilError> {
        let (id, k, host_clock) = self.hello(within)?;
        if k != sectors {
            return Err(HilError::Sectors {
                has: k,
                over: self.name.clone(),
                want: sectors,
            });
        }
        if !host_clock {
            return Err(HilError::NoHostClock);
        }
        self.hello_id = id;
        Ok(())
    }

    /// Sends a 0x00 and asks who it is: its `Hello`'s id, sectors and whether it can follow
    /// the host's clock, within `within`.
    fn hello(&mut self, within: WallDuration) -> Result<(u16, u8, bool), HilError> {
        let mut bytes = vec![0u8];
        bytes.extend_from_slice(&frame(&LinkMsg::Hello {
            version: LINK_VERSION,
            id: 0,
            sectors: 0,
            host_clock: true,
        }));
        self.write(&bytes)?;
        let deadline = WallInstant::now() + within;
        loop {
            let left = deadline.saturating_duration_since(WallInstant::now());
            match self.from.recv_timeout(left) {
                Ok(FromRobot::Msg(LinkMsg::Hello {
                    id,
                    sectors,
                    host_clock,
                    ..
                })) => return Ok((id, sectors, host_clock)),
                Ok(FromRobot::Version(v)) => {
                    return Err(HilError::Version {
                        version: v,
                        over: self.name.clone(),
                    });
                }
                Ok(FromRobot::Msg(_)) => {}
                Ok(FromRobot::Ended) | Err(RecvTimeoutError::Disconnected) => {
                    return Err(HilError::EndedBeforeHello {
                        over: self.name.clone(),
                    });
                }
                Err(RecvTimeoutError::Timeout) => {
                    return Err(HilError::NoHello {
                        over: self.name.clone(),
                        within,
                    });
                }
            }
        }
    }

    /// Writes `bytes` to the robot.
    ///
    /// # Errors
    /// The link ended.
    pub(crate) fn write(&mut self, bytes: &[u8]) -> Result<(), HilError> {
        self.stream
            .write_all(bytes)
            .map_err(|source| HilError::Write {
                over: self.name.clone(),
                source,
            })?;
        self.sent += bytes.len() as u64;
        Ok(())
    }

    /// Bad link frames from it so far.
    pub(crate) fn link_errors(&self) -> u64 {
        self.errors.load(Ordering::Relaxed)
    }

    /// The last lines QEMU printed (none for a robot on a socket).
    pub(crate) fn output(&self) -> Vec<String> {
        output(&self.log)
    }
}

impl Drop for Follower {
    /// Kills and reaps QEMU: no process is left behind.
    fn drop(&mut self) {
        let _ = self.stream.shutdown(std::net::Shutdown::Both);
        if let Some(mut c) = self.child.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// One link frame of `msg`.
pub(crate) fn frame(msg: &LinkMsg) -> Vec<u8> {
    let mut buf = [0u8; LINK_FRAME_MAX];
    firmware::hil::encode(msg, &mut buf).map_or_else(|_| Vec::new(), <[u8]>::to_vec)
}

/// Accepts one connection within `within`.
fn accept(listener: &TcpListener, within: WallDuration) -> Result<TcpStream, HilError> {
    listener.set_nonblocking(true).map_err(HilError::Qemu)?;
    let deadline = WallInstant::now() + within;
    loop {
        match listener.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).map_err(HilError::Qemu)?;
                return Ok(s);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                if WallInstant::now() >= deadline {
                    return Err(HilError::UartTimeout { after: within });
                }
                std::thread::sleep(WallDuration::from_millis(2));
            }
            Err(e) => return Err(HilError::Qemu(e)),
        }
    }
}

/// The reader thread: decodes the robot's frames into `to` until the stream ends.
fn read_link(mut stream: TcpStream, to: &Sender<FromRobot>, errors: &AtomicU64) {
    let mut decoder = LinkDecoder::new();
    let mut buf = [0u8; 512];
    loop {
        let n = match stream.read(&mut buf) {
            Ok(0) | Err(_) => {
                let _ = to.send(FromRobot::Ended);
                return;
            }
            Ok(n) => n,
        };
        for &b in &buf[..n] {
            let out = match decoder.push(b) {
                None => continue,
                Some(Ok(m)) => FromRobot::Msg(m),
                Some(Err(LinkError::UnknownVersion(v))) => FromRobot::Version(v),
                Some(Err(_)) => {
                    errors.fetch_add(1, Ordering::Relaxed);
                    continue;
                }
            };
            if to.send(out).is_err() {
                return;
            }
        }
    }
}

/// Keeps the last [`LOG_LINES`] lines of `out`.
fn keep_log(out: Box<dyn Read + Send>, log: &Mutex<VecDeque<String>>) {
    for line in BufReader::new(out).lines() {
        let Ok(line) = line else { return };
        let mut l = log.lock().unwrap_or_else(PoisonError::into_inner);
        if l.len() == LOG_LINES {
            l.pop_front();
        }
        l.push_back(line);
    }
}

/// The lines kept in `log`, oldest first.
fn output(log: &Mutex<VecDeque<String>>) -> Vec<String> {
    let l = log.lock().unwrap_or_else(PoisonError::into_inner);
    l.iter().cloned().collect()
}
