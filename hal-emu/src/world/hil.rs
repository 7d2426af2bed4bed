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

use std::fmt;
use std::path::PathBuf;
use std::process::Stdio;
use std::str::FromStr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use embedded_io_async::{ErrorKind, ErrorType, Read, Write};
use firmware::hil::robot::{Link, led_decision};
use firmware::hil::{
    CHUNK_MAX, LINK_FRAME_MAX, LINK_VERSION, LinkDecoder, LinkError, LinkMsg, Setup,
};
use firmware::{Clock, Config, LedColor, Leds, Quantity, Sensor};
use protocol::{Duration, Instant};
use rand_pcg::Pcg32;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};
use tokio::task::JoinHandle;

use crate::board::leds::EmuLeds;
use crate::board::light::{EmuReceiver, EmuTransmitter};
use crate::board::sensor::EmuSensor;
use crate::world::clock::EmuClock;

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

/// The robots in the loop of a run, as `cimax arena --hil` names them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum HilSpec {
    /// `qemu:N`: N QEMU robots.
    Qemu(usize),
    /// `serial:PATH[@BAUD]`: one board (115200 Bd by default).
    Serial(PathBuf, u32),
    /// `tcp:HOST:PORT`: one robot on a socket.
    Tcp(String),
    /// `loopback:N`: N robots in this process, over the link.
    Loopback(usize),
}

/// The default baud rate of `serial:PATH`: the Nucleo image's USART2.
pub const DEFAULT_BAUD: u32 = 115_200;

impl HilSpec {
    /// How many robots it brings.
    pub fn robots(&self) -> usize {
        match self {
            HilSpec::Qemu(n) | HilSpec::Loopback(n) => *n,
            HilSpec::Serial(..) | HilSpec::Tcp(_) => 1,
        }
    }

    /// Each robot's transport; QEMU robots boot `image`.
    pub fn transports(&self, image: &std::path::Path) -> Vec<Transport> {
        match self {
            HilSpec::Qemu(n) => vec![Transport::Qemu(image.to_path_buf()); *n],
            HilSpec::Loopback(n) => vec![Transport::InProcess; *n],
            HilSpec::Serial(p, b) => vec![Transport::Serial(p.clone(), *b)],
            HilSpec::Tcp(a) => vec![Transport::Tcp(a.clone())],
        }
    }
}

impl FromStr for HilSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let count = |n: &str, what: &str| -> Result<usize, String> {
            match n.parse::<usize>() {
                Ok(k @ 1..=64) => Ok(k),
                _ => Err(format!("{what}:N needs N from 1 to 64, not {n:?}")),
            }
        };
        if let Some(n) = s.strip_prefix("qemu:") {
            return count(n, "qemu").map(HilSpec::Qemu);
        }
        if let Some(n) = s.strip_prefix("loopback:") {
            return count(n, "loopback").map(HilSpec::Loopback);
        }
        if let Some(rest) = s.strip_prefix("serial:") {
            let (path, baud) = match rest.rsplit_once('@') {
                Some((p, b)) => {
                    let baud = b
                        .parse::<u32>()
                        .ok()
                        .filter(|&b| b > 0)
                        .ok_or_else(|| format!("serial:PATH@BAUD: {b:?} is no baud rate"))?;
                    (p, baud)
                }
                None => (rest, DEFAULT_BAUD),
            };
            if path.is_empty() {
                return Err("serial:PATH needs a path, e.g. serial:/dev/ttyACM0".into());
            }
            return Ok(HilSpec::Serial(PathBuf::from(path), baud));
        }
        if let Some(addr) = s.strip_prefix("tcp:") {
            let ok = addr
                .rsplit_once(':')
                .is_some_and(|(h, p)| !h.is_empty() && p.parse::<u16>().is_ok());
            if !ok {
                return Err(format!("tcp:HOST:PORT: {addr:?} is no host and port"));
            }
            return Ok(HilSpec::Tcp(addr.to_string()));
        }
        Err(format!(
            "{s:?}: a robot in the loop is qemu:N, serial:PATH[@BAUD], tcp:HOST:PORT or loopback:N"
        ))
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

/// How long the host waits for a robot in the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HilTimeouts {
    /// From connecting to its `Hello`.
    pub hello: Duration,
    /// Longest silence (no frame at all) once it runs.
    pub silence: Duration,
}

impl Default for HilTimeouts {
    /// 15 s to boot (QEMU, or a board reset by opening its port), 5 s of silence (ten
    /// heartbeats).
    fn default() -> Self {
        HilTimeouts {
            hello: Duration::from_secs(15),
            silence: Duration::from_secs(5),
        }
    }
}

/// What a run reports about one robot in the loop.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct HilReport {
    /// Its place.
    pub robot: usize,
    /// Its transport (`qemu`, `serial:PATH@BAUD`, `tcp:HOST:PORT`, `loopback`).
    pub transport: String,
    /// The id it said hello with.
    pub hello_id: u16,
    /// Link frames the host sent it.
    pub frames_sent: u64,
    /// Link frames the host received from it (good ones).
    pub frames_received: u64,
    /// Bad link frames from it (every `LinkError`).
    pub link_errors: u64,
    /// Light frames it transmitted (`Tx` messages).
    pub tx: u64,
    /// Light bytes its receivers were sent (`Rx`).
    pub rx_bytes: u64,
    /// Milliseconds from connecting to its `Hello`.
    pub hello_ms: u64,
    /// Bytes the host sent it, frames and delimiters included.
    pub bytes_sent: u64,
    /// Bytes the host received from it.
    pub bytes_received: u64,
    /// Heartbeats it answered: round trips measured.
    pub round_trips: u64,
    /// The mean round trip of a heartbeat (host → robot → host), microseconds of the run's
    /// clock (zero in virtual time).
    pub rtt_mean_us: u64,
    /// The longest round trip, microseconds.
    pub rtt_max_us: u64,
    /// Light frames and LED changes it sent before it answered the first heartbeat after its
    /// setup (a board that ran already, finishing its last run), ignored.
    pub stale: u64,
}

/// The two directions of one link, as channels of byte chunks, and whatever keeps the other
/// end alive (a child process, reader and writer tasks or threads). Dropping it kills the child
/// and stops the tasks; [`LinkEnds::close`] also reaps the child.
pub struct LinkEnds {
    /// Bytes from the robot.
    pub from_robot: UnboundedReceiver<Vec<u8>>,
    /// Bytes to the robot.
    pub to_robot: UnboundedSender<Vec<u8>>,
    child: Option<tokio::process::Child>,
    tasks: Vec<JoinHandle<()>>,
    stop: Arc<AtomicBool>,
    log: Log,
    /// A serial port's reader and writer threads.
    threads: Vec<std::thread::JoinHandle<()>>,
}

impl LinkEnds {
    fn new(from_robot: UnboundedReceiver<Vec<u8>>, to_robot: UnboundedSender<Vec<u8>>) -> Self {
        LinkEnds {
            from_robot,
            to_robot,
            child: None,
            tasks: Vec::new(),
            stop: Arc::new(AtomicBool::new(false)),
            log: Log::default(),
            threads: Vec::new(),
        }
    }

    /// Carries the link over socket `s`: its bytes into `to_host`, `from_host` into it.
    fn attach(
        &mut self,
        s: tokio::net::TcpStream,
        to_host: UnboundedSender<Vec<u8>>,
        from_host: UnboundedReceiver<Vec<u8>>,
    ) {
        let _ = s.set_nodelay(true);
        let (r, w) = s.into_split();
        self.tasks
            .push(tokio::task::spawn_local(pump_in(r, to_host)));
        self.tasks
            .push(tokio::task::spawn_local(pump_out(w, from_host)));
    }

    /// `; its output ends: ...` with the last lines its process printed, or nothing.
    pub fn last_words(&self) -> String {
        let l = self.log.borrow();
        if l.is_empty() {
            String::new()
        } else {
            let lines: Vec<&str> = l.iter().map(String::as_str).collect();
            format!("; its output ends: {}", lines.join(" | "))
        }
    }

    /// Ends the link: stops the tasks and threads, kills the child process and waits for it.
    pub async fn close(mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for t in self.tasks.drain(..) {
            t.abort();
        }
        if let Some(mut c) = self.child.take() {
            let _ = c.start_kill();
            let _ = c.wait().await;
        }
        // A serial port's threads end within their 50 ms read timeout once the channel to the
        // robot is closed; wait for them, so that the port is free for the next run (it is
        // opened exclusively).
        let (closed, _) = unbounded_channel();
        drop(std::mem::replace(&mut self.to_robot, closed));
        let threads = std::mem::take(&mut self.threads);
        // Only serial ports have threads (waiting on the blocking pool would let a paused
        // clock jump, and in-process robots run on one).
        if !threads.is_empty() {
            let _ = tokio::task::spawn_blocking(move || {
                for t in threads {
                    let _ = t.join();
                }
            })
            .await;
        }
    }
}

impl Drop for LinkEnds {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        for t in &self.tasks {
            t.abort();
        }
        // `kill_on_drop` kills a child left here; tokio reaps it in the background.
    }
}

/// Opens the link to one robot (its place `robot`, for the in-process one; `base` is the
/// configuration an in-process robot's image would have).
///
/// # Errors
/// Why the transport could not be opened (no QEMU, no such port, connection refused).
pub async fn open(
    transport: &Transport,
    clock: EmuClock,
    base: Config,
) -> Result<LinkEnds, String> {
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
            let s = tokio::time::timeout(
                std::time::Duration::from_secs(10),
                tokio::net::TcpStream::connect(addr.as_str()),
            )
            .await
            .map_err(|_| format!("tcp:{addr}: no connection within 10 s"))?
            .map_err(|e| format!("tcp:{addr}: {e}"))?;
            ends.attach(s, to_host, from_host);
        }
        Transport::Qemu(image) => {
            if !image.is_file() {
                return Err(format!(
                    "no HIL image at {} (build it with `cargo hil-image`, docs/hil.md)",
                    image.display()
                ));
            }
            // QEMU connects UART0 to a socket of ours; its stdout and stderr (the image's
            // semihosting log, QEMU's complaints) are kept for the failure message.
            let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
                .await
                .map_err(|e| format!("qemu: no local socket: {e}"))?;
            let port = listener
                .local_addr()
                .map_err(|e| format!("qemu: no local socket: {e}"))?
                .port();
            let mut child = tokio::process::Command::new("qemu-system-arm")
                .args(qemu_args(image, port))
                .stdin(Stdio::null())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .kill_on_drop(true)
                .spawn()
                .map_err(|e| format!("qemu-system-arm: {e} (is QEMU installed?)"))?;
            let outs: [Option<Box<dyn tokio::io::AsyncRead + Unpin>>; 2] = [
                child.stdout.take().map(|o| Box::new(o) as _),
                child.stderr.take().map(|o| Box::new(o) as _),
            ];
            for out in outs.into_iter().flatten() {
                ends.tasks
                    .push(tokio::task::spawn_local(keep_log(out, ends.log.clone())));
            }
            ends.child = Some(child);
            let accepted =
                tokio::time::timeout(std::time::Duration::from_secs(10), listener.accept());
            let (s, _) = match accepted.await {
                Ok(Ok(s)) => s,
                Ok(Err(e)) => return Err(format!("qemu: {e}")),
                Err(_) => {
                    return Err(format!(
                        "qemu did not connect its UART within 10 s{}",
                        ends.last_words()
                    ));
                }
            };
            ends.attach(s, to_host, from_host);
        }
        Transport::Serial(path, baud) => {
            ends.threads = serial(path, *baud, to_host, from_host, ends.stop.clone())?;
        }
    }
    // Either end sends a 0x00 first, so that the other starts with an empty buffer; then the
    // host asks who the robot is (a board that runs already says hello only when asked).
    let _ = ends.to_robot.send(vec![0]);
    let mut buf = [0u8; LINK_FRAME_MAX];
    let ask = LinkMsg::Hello {
        version: LINK_VERSION,
        id: 0,
        sectors: 0,
    };
    if let Ok(f) = firmware::hil::encode(&ask, &mut buf) {
        let _ = ends.to_robot.send(f.to_vec());
    }
    Ok(ends)
}

/// The QEMU command line of a robot in the loop: mps2-an386 in real time (no `-icount`), its
/// UART0 a TCP client of the host's `port` on 127.0.0.1, semihosting (the image's log) on
/// stdout. (Semihosting writes to QEMU's stdout whatever `-semihosting-config` says, so the
/// link cannot share it.)
pub fn qemu_args(image: &std::path::Path, port: u16) -> Vec<std::ffi::OsString> {
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

/// Keeps the last [`LOG_LINES`] lines a child process printed.
async fn keep_log(out: Box<dyn tokio::io::AsyncRead + Unpin>, log: Log) {
    use tokio::io::AsyncBufReadExt;
    let mut lines = tokio::io::BufReader::new(out).lines();
    while let Ok(Some(line)) = lines.next_line().await {
        let mut l = log.borrow_mut();
        if l.len() == LOG_LINES {
            l.pop_front();
        }
        l.push_back(line);
    }
}

/// Lines of a child's output kept for a failure's message.
const LOG_LINES: usize = 3;

/// The last lines a child printed.
type Log = std::rc::Rc<std::cell::RefCell<std::collections::VecDeque<String>>>;

/// Copies a byte stream into a channel until either ends.
async fn pump_in<R: tokio::io::AsyncRead + Unpin>(mut r: R, to: UnboundedSender<Vec<u8>>) {
    let mut buf = [0u8; 256];
    loop {
        match r.read(&mut buf).await {
            Ok(0) | Err(_) => return,
            Ok(n) => {
                if to.send(buf[..n].to_vec()).is_err() {
                    return;
                }
            }
        }
    }
}

/// Copies a channel into a byte stream until either ends.
async fn pump_out<W: tokio::io::AsyncWrite + Unpin>(
    mut w: W,
    mut from: UnboundedReceiver<Vec<u8>>,
) {
    while let Some(b) = from.recv().await {
        if w.write_all(&b).await.is_err() || w.flush().await.is_err() {
            return;
        }
    }
}

/// A serial port, read and written by two threads (the port is blocking I/O).
fn serial(
    path: &std::path::Path,
    baud: u32,
    to_host: UnboundedSender<Vec<u8>>,
    mut from_host: UnboundedReceiver<Vec<u8>>,
    stop: Arc<AtomicBool>,
) -> Result<Vec<std::thread::JoinHandle<()>>, String> {
    let name = path.to_string_lossy().into_owned();
    let mut port = serialport::new(&name, baud)
        .timeout(std::time::Duration::from_millis(50))
        .open()
        .map_err(|e| format!("serial:{name}: {e}"))?;
    let mut writer = port
        .try_clone()
        .map_err(|e| format!("serial:{name}: {e}"))?;
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

/// The robot program in this process, over the link (`firmware::hil::robot::run`), with as
/// many receivers as `base` has sectors.
async fn in_process(
    to_host: UnboundedSender<Vec<u8>>,
    from_host: UnboundedReceiver<Vec<u8>>,
    clock: EmuClock,
    base: Config,
) {
    async fn with<const N: usize>(
        to_host: UnboundedSender<Vec<u8>>,
        from_host: UnboundedReceiver<Vec<u8>>,
        clock: EmuClock,
        base: Config,
    ) {
        let link = Link::<_, N>::new(ChanWriter(to_host));
        // A channel of byte chunks read as a stream: what a light receiver is.
        let reader = EmuReceiver::new(from_host);
        let _ = firmware::hil::robot::run(
            &link,
            reader,
            &clock,
            base,
            |seed| Pcg32::new(u64::from(seed), firmware::hil::robot::RNG_STREAM),
            &mut (),
        )
        .await;
    }
    match base.params.sectors {
        2 => with::<2>(to_host, from_host, clock, base).await,
        3 => with::<3>(to_host, from_host, clock, base).await,
        4 => with::<4>(to_host, from_host, clock, base).await,
        5 => with::<5>(to_host, from_host, clock, base).await,
        6 => with::<6>(to_host, from_host, clock, base).await,
        7 => with::<7>(to_host, from_host, clock, base).await,
        _ => with::<8>(to_host, from_host, clock, base).await,
    }
}

/// A channel's sending end as an [`embedded_io_async::Write`].
struct ChanWriter(UnboundedSender<Vec<u8>>);

impl ErrorType for ChanWriter {
    type Error = ErrorKind;
}

impl Write for ChanWriter {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, ErrorKind> {
        self.0
            .send(buf.to_vec())
            .map_err(|_| ErrorKind::BrokenPipe)?;
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), ErrorKind> {
        Ok(())
    }
}

/// What the bridge of one robot needs from the run.
pub(crate) struct Bridge {
    pub(crate) robot: usize,
    pub(crate) transport: Transport,
    pub(crate) clock: EmuClock,
    pub(crate) transmitter: Option<EmuTransmitter>,
    pub(crate) receivers: Vec<EmuReceiver>,
    pub(crate) sensor: EmuSensor,
    pub(crate) leds: EmuLeds,
    pub(crate) config: Config,
    pub(crate) setup: Setup,
    pub(crate) timeouts: HilTimeouts,
}

/// Why a bridge failed: the message names the transport; the arena adds the robot.
type Failure = String;

/// Sends one message on the link.
fn send(
    to: &UnboundedSender<Vec<u8>>,
    msg: &LinkMsg,
    report: &mut HilReport,
) -> Result<(), Failure> {
    let mut buf = [0u8; LINK_FRAME_MAX];
    let f = firmware::hil::encode(msg, &mut buf).map_err(|e| format!("encoding {msg:?}: {e:?}"))?;
    // The writer stops when the robot's end closes: the same failure as reading the end of
    // its stream, whichever of the two the bridge sees first.
    to.send(f.to_vec())
        .map_err(|_| "its link ended (disconnected) while the host was sending".to_string())?;
    report.frames_sent += 1;
    report.bytes_sent += f.len() as u64;
    Ok(())
}

/// What one of the bridge's sources gave.
enum Input {
    Bytes(Option<Vec<u8>>),
    Heard(usize, Vec<u8>),
    Tick,
    Stop,
}

impl Bridge {
    /// Runs the robot's link until `stop` fires (`Ok`, with its report) or the robot fails.
    pub(crate) async fn run(
        mut self,
        stop: tokio::sync::oneshot::Receiver<()>,
    ) -> Result<HilReport, Failure> {
        let mut report = HilReport {
            robot: self.robot,
            transport: self.transport.to_string(),
            ..HilReport::default()
        };
        let t0 = self.clock.now();
        let ends = open(&self.transport, self.clock, self.config).await;
        let mut ends = ends.map_err(|e| format!("its link did not open: {e}"))?;
        let out = self
            .serve(&mut ends, &mut report, t0, stop)
            .await
            .map_err(|e| e + &ends.last_words());
        ends.close().await;
        out.map(|()| report)
    }

    async fn serve(
        &mut self,
        ends: &mut LinkEnds,
        report: &mut HilReport,
        t0: Instant,
        mut stop: tokio::sync::oneshot::Receiver<()>,
    ) -> Result<(), Failure> {
        let mut decoder = LinkDecoder::new();
        let to = ends.to_robot.clone();
        // 1. Hello, checked; what came after it is the run's.
        let (id, sectors, mut pending) = self
            .await_hello(&mut ends.from_robot, &mut decoder, t0)
            .await?;
        report.hello_id = id;
        report.hello_ms = self.clock.now().saturating_since(t0).as_millis();
        if sectors != self.config.params.sectors {
            return Err(format!(
                "has {sectors} receivers (said hello over {}); the arena's robots have {}",
                self.transport, self.config.params.sectors
            ));
        }
        // 2. Its sensor's first readings, then the run's setup, and at once a heartbeat: its
        // answer says the robot runs the setup (what it sent before is stale: a board that ran
        // already may still be sending the last run's light and LEDs).
        self.readings(&to, report).await?;
        send(&to, &LinkMsg::Setup(self.setup), report)?;

        // 3. The run: its light, its messages, readings and heartbeats.
        let (mut heard, air, _light) = self.start_light();
        let mut live = Live::new(self.clock.now(), self.config.sample_period);
        live.next_beat = self.clock.now();
        loop {
            let input = if pending.is_empty() {
                tokio::select! {
                    b = ends.from_robot.recv() => Input::Bytes(b),
                    Some((s, b)) = heard.recv() => Input::Heard(s, b),
                    () = self.clock.sleep_until(live.wake()) => Input::Tick,
                    _ = &mut stop => Input::Stop,
                }
            } else {
                Input::Bytes(Some(std::mem::take(&mut pending)))
            };
            let now = self.clock.now();
            match input {
                Input::Stop => return self.check_at_end(now.saturating_since(t0), report),
                Input::Bytes(None) => {
                    return Err(format!("its {} link ended (disconnected)", self.transport));
                }
                Input::Bytes(Some(bytes)) => {
                    report.bytes_received += bytes.len() as u64;
                    for b in bytes {
                        match decoder.push(b) {
                            None => {}
                            Some(Err(_)) => report.link_errors += 1,
                            Some(Ok(msg)) => {
                                report.frames_received += 1;
                                live.last_heard = now;
                                self.on_message(msg, &mut live, report, &air).await?;
                            }
                        }
                    }
                }
                Input::Heard(sector, bytes) => {
                    report.rx_bytes += bytes.len() as u64;
                    let Ok(sector) = u8::try_from(sector) else {
                        continue;
                    };
                    for c in bytes.chunks(CHUNK_MAX) {
                        let bytes = heapless::Vec::from_slice(c).unwrap_or_default();
                        send(&to, &LinkMsg::Rx { sector, bytes }, report)?;
                    }
                }
                Input::Tick => {}
            }
            if now >= live.next_sample {
                self.readings(&to, report).await?;
                live.next_sample = now + self.config.sample_period;
            }
            if now >= live.next_beat {
                send(&to, &LinkMsg::Heartbeat(live.beat), report)?;
                live.ping = Some((live.beat, tokio::time::Instant::now()));
                live.beat = live.beat.wrapping_add(1);
                live.next_beat = now + firmware::hil::robot::BEAT;
            }
            let silent = now.saturating_since(live.last_heard);
            if silent > self.timeouts.silence {
                return Err(format!(
                    "stopped its heartbeat over {}: nothing for {} ms",
                    self.transport,
                    silent.as_millis()
                ));
            }
        }
    }

    /// Waits for the robot's `Hello` (at most [`HilTimeouts::hello`] from `t0`): its id and
    /// sectors, and the bytes that came after it in the same read.
    async fn await_hello(
        &self,
        from: &mut UnboundedReceiver<Vec<u8>>,
        decoder: &mut LinkDecoder,
        t0: Instant,
    ) -> Result<(u16, u8, Vec<u8>), Failure> {
        let deadline = t0 + self.timeouts.hello;
        loop {
            let got = tokio::select! {
                b = from.recv() => b,
                () = self.clock.sleep_until(deadline) => {
                    return Err(format!(
                        "never said hello over {} within {} s",
                        self.transport,
                        self.timeouts.hello.as_millis() / 1000
                    ));
                }
            };
            let Some(bytes) = got else {
                return Err(format!(
                    "its {} link ended before it said hello",
                    self.transport
                ));
            };
            for (i, &b) in bytes.iter().enumerate() {
                match decoder.push(b) {
                    Some(Ok(LinkMsg::Hello { id, sectors, .. })) => {
                        return Ok((id, sectors, bytes[i + 1..].to_vec()));
                    }
                    Some(Err(LinkError::UnknownVersion(v))) => {
                        return Err(format!(
                            "speaks link version {v} over {}; this host speaks {LINK_VERSION}",
                            self.transport
                        ));
                    }
                    _ => {}
                }
            }
        }
    }

    /// Starts the robot's light: a task per receiver handing what reaches it to the returned
    /// channel, and one putting the frames sent into the returned one on air, one at a time
    /// as from the robot's own transmitter. The tasks end when the guard is dropped.
    fn start_light(&mut self) -> (Heard, UnboundedSender<Vec<u8>>, AbortAll) {
        let (heard_tx, heard) = unbounded_channel::<(usize, Vec<u8>)>();
        let mut tasks = Vec::new();
        for (sector, mut rx) in std::mem::take(&mut self.receivers).into_iter().enumerate() {
            let tx = heard_tx.clone();
            tasks.push(tokio::task::spawn_local(async move {
                let mut buf = [0u8; CHUNK_MAX];
                while let Ok(n @ 1..) = rx.read(&mut buf).await {
                    if tx.send((sector, buf[..n].to_vec())).is_err() {
                        return;
                    }
                }
            }));
        }
        let (air, mut air_rx) = unbounded_channel::<Vec<u8>>();
        if let Some(mut transmitter) = self.transmitter.take() {
            tasks.push(tokio::task::spawn_local(async move {
                while let Some(f) = air_rx.recv().await {
                    let _ = transmitter.write(&f).await;
                }
            }));
        }
        (heard, air, AbortAll(tasks))
    }

    /// One message from the robot during the run.
    async fn on_message(
        &mut self,
        msg: LinkMsg,
        live: &mut Live,
        report: &mut HilReport,
        air: &UnboundedSender<Vec<u8>>,
    ) -> Result<(), Failure> {
        match msg {
            // From before its setup: the last run's.
            LinkMsg::Tx(_) | LinkMsg::Led(_) if !live.beating => report.stale += 1,
            LinkMsg::Tx(chunk) => {
                report.tx += 1;
                let _ = air.send(chunk.to_vec());
            }
            LinkMsg::Led(code) => {
                let sectors = self.config.params.sectors;
                let color = LedColor::for_decision_of(led_decision(code), sectors);
                let _ = self.leds.show(color).await;
            }
            LinkMsg::Refused(code) => {
                let why = match code {
                    1 => "bad protocol parameters",
                    2 => "its receivers and the sectors differ",
                    3 => "a zero duration",
                    4 => "a swarm key without keyed framing",
                    _ => "another reason",
                };
                return Err(format!(
                    "refused the run's setup over {}: {why} (code {code})",
                    self.transport
                ));
            }
            LinkMsg::Heartbeat(seq) => {
                live.beating = true;
                if let Some((sent, at)) = live.ping
                    && sent == seq
                {
                    let us = u64::try_from(at.elapsed().as_micros()).unwrap_or(u64::MAX);
                    live.rtt_sum += us;
                    report.round_trips += 1;
                    report.rtt_max_us = report.rtt_max_us.max(us);
                    report.rtt_mean_us = live.rtt_sum / report.round_trips;
                    live.ping = None;
                }
            }
            // Hellos still in flight when it got the setup are fine; a Hello after it started
            // answering heartbeats means it rebooted.
            LinkMsg::Hello { .. } if live.beating => {
                return Err(format!(
                    "said hello again over {}: it rebooted during the run",
                    self.transport
                ));
            }
            _ => {}
        }
        Ok(())
    }

    /// At the end of a run that lasted `ran`: a robot program that runs initiates a wave every
    /// cycle, so one that sent no light in three cycles' time is not running (a safety net
    /// beside `Refused`, for images that cannot say so).
    fn check_at_end(&self, ran: Duration, report: &HilReport) -> Result<(), Failure> {
        let cycles = self.config.params.longest_cycle().saturating_mul(3);
        if report.tx == 0 && ran > cycles {
            return Err(format!(
                "sent no light over {} in {} s: its robot program is not running",
                self.transport,
                ran.as_millis() / 1000
            ));
        }
        Ok(())
    }

    /// Sends what its sensor reads now, both quantities (a failed read sends nothing).
    async fn readings(
        &mut self,
        to: &UnboundedSender<Vec<u8>>,
        report: &mut HilReport,
    ) -> Result<(), Failure> {
        for (q, quantity) in [(0u8, Quantity::AmbientLight), (1, Quantity::Oxygen)] {
            if let Ok(level) = self.sensor.read(quantity).await {
                send(
                    to,
                    &LinkMsg::Reading {
                        quantity: q,
                        level: level.0,
                    },
                    report,
                )?;
            }
        }
        Ok(())
    }
}

/// What the robot's receivers heard: `(sector, bytes)`.
type Heard = UnboundedReceiver<(usize, Vec<u8>)>;

/// The bridge's state during a run.
struct Live {
    /// When the robot last sent a good frame.
    last_heard: Instant,
    next_beat: Instant,
    next_sample: Instant,
    /// The next heartbeat's number.
    beat: u32,
    /// True once it answered a heartbeat (a `Hello` after that is a reboot).
    beating: bool,
    /// The heartbeat under way and when it left.
    ping: Option<(u32, tokio::time::Instant)>,
    /// The sum of the round trips so far, microseconds.
    rtt_sum: u64,
}

impl Live {
    fn new(now: Instant, sample_period: Duration) -> Self {
        Live {
            last_heard: now,
            next_beat: now + firmware::hil::robot::BEAT,
            next_sample: now + sample_period,
            beat: 0,
            beating: false,
            ping: None,
            rtt_sum: 0,
        }
    }

    /// The next time something is due.
    fn wake(&self) -> Instant {
        self.next_beat.min(self.next_sample)
    }
}

/// Aborts its tasks when dropped.
struct AbortAll(Vec<JoinHandle<()>>);

impl Drop for AbortAll {
    fn drop(&mut self) {
        for t in &self.0 {
            t.abort();
        }
    }
}

/// The seed of a robot's `Setup` from its 64-bit one.
pub(crate) fn setup_seed(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

/// A robot's `Setup` from its configuration (id included) and seed.
pub(crate) fn setup_of(config: &Config, seed: u32) -> Setup {
    let ms = |d: Duration| u32::try_from(d.as_millis()).unwrap_or(u32::MAX);
    let w = &config.params.wave;
    Setup {
        id: config.id,
        seed,
        cycle_ms: ms(w.cycle),
        spread_ms: ms(w.cycle_spread),
        relay_ms: ms(w.relay_delay),
        refractory_ms: ms(w.refractory),
        negotiation: config.params.negotiation_cycles,
        adaptive: config.params.decide == protocol::params::DecisionRule::Adaptive,
        sample_ms: ms(config.sample_period),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_refuse_with_a_reason() {
        assert_eq!("qemu:4".parse(), Ok(HilSpec::Qemu(4)));
        assert_eq!("loopback:2".parse(), Ok(HilSpec::Loopback(2)));
        assert_eq!(
            "serial:/dev/ttyACM0".parse(),
            Ok(HilSpec::Serial("/dev/ttyACM0".into(), DEFAULT_BAUD))
        );
        assert_eq!(
            "serial:/dev/ttyACM0@9600".parse(),
            Ok(HilSpec::Serial("/dev/ttyACM0".into(), 9600))
        );
        assert_eq!(
            "tcp:127.0.0.1:4000".parse(),
            Ok(HilSpec::Tcp("127.0.0.1:4000".into()))
        );
        for (bad, why) in [
            ("qemu:0", "N from 1 to 64"),
            ("qemu:x", "N from 1 to 64"),
            ("serial:", "needs a path"),
            ("serial:/dev/x@fast", "no baud rate"),
            ("tcp:4000", "no host and port"),
            ("udp:1", "qemu:N, serial:PATH"),
        ] {
            let e = bad.parse::<HilSpec>().unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    #[test]
    fn a_setup_carries_the_configuration_back() {
        let mut c = Config::robots();
        c.id = 3;
        c.params.wave.cycle = Duration::from_millis(2000);
        c.params.decide = protocol::params::DecisionRule::Adaptive;
        let s = setup_of(&c, 99);
        let back = firmware::hil::robot::configure(Config::robots(), &s);
        assert_eq!(back, c);
    }
}
