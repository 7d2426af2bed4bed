//! A link's two ends on the host ([`LinkEnds`]): channels of byte chunks to and from the
//! robot, and whatever carries them (tasks pumping a socket, a child process, a serial port's
//! threads), ended together.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use firmware::hil::{LINK_FRAME_MAX, LINK_VERSION, LinkMsg};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};
use tokio::task::JoinHandle;

/// The two directions of one link, as channels of byte chunks, and whatever keeps the other
/// end alive (a child process, reader and writer tasks or threads). Dropping it kills the child
/// and stops the tasks; [`LinkEnds::close`] also reaps the child.
pub struct LinkEnds {
    /// Bytes from the robot.
    pub from_robot: UnboundedReceiver<Vec<u8>>,
    /// Bytes to the robot.
    pub to_robot: UnboundedSender<Vec<u8>>,
    /// A QEMU process.
    pub(super) child: Option<tokio::process::Child>,
    /// Tasks carrying the link, or running the in-process robot.
    pub(super) tasks: Vec<JoinHandle<()>>,
    /// Tells a serial port's threads to stop.
    pub(super) stop: Arc<AtomicBool>,
    /// The last lines the child printed.
    pub(super) log: Log,
    /// A serial port's reader and writer threads.
    pub(super) threads: Vec<std::thread::JoinHandle<()>>,
}

impl LinkEnds {
    pub(super) fn new(
        from_robot: UnboundedReceiver<Vec<u8>>,
        to_robot: UnboundedSender<Vec<u8>>,
    ) -> Self {
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
    pub(super) fn attach(
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

    /// Starts the conversation: either end sends a 0x00 first, so that the other starts with
    /// an empty buffer; then the host asks who the robot is (a board that runs already says
    /// hello only when asked).
    pub(super) fn ask_hello(&self) {
        let _ = self.to_robot.send(vec![0]);
        let mut buf = [0u8; LINK_FRAME_MAX];
        let ask = LinkMsg::Hello {
            version: LINK_VERSION,
            id: 0,
            sectors: 0,
            host_clock: false,
        };
        if let Ok(f) = firmware::hil::encode(&ask, &mut buf) {
            let _ = self.to_robot.send(f.to_vec());
        }
    }

    /// `; its output ends: ...` with the last lines its process printed, or nothing.
    pub fn last_words(&self) -> String {
        super::error::last_words(&self.output())
    }

    /// The last lines its process printed, oldest first.
    pub(crate) fn output(&self) -> Vec<String> {
        self.log.borrow().iter().cloned().collect()
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

/// Keeps the last [`LOG_LINES`] lines a child process printed.
pub(super) async fn keep_log(out: Box<dyn tokio::io::AsyncRead + Unpin>, log: Log) {
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
pub(super) type Log = std::rc::Rc<std::cell::RefCell<std::collections::VecDeque<String>>>;
