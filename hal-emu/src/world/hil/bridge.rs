//! The bridge of one robot in the loop into the run: it opens the robot's link, checks its
//! `Hello`, sends the run's `Setup`, then carries the robot's light into the medium and back,
//! its sensor's readings, its LEDs and heartbeats, until the run ends or the robot fails.

use embedded_io_async::Write;
use firmware::hil::robot::led_decision;
use firmware::hil::{CHUNK_MAX, LINK_FRAME_MAX, LinkDecoder, LinkError, LinkMsg, Setup};
use firmware::{Clock, Config, LedColor, Leds, Quantity, Sensor};
use protocol::{Duration, Instant};
use serde::Serialize;
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender, unbounded_channel};
use tokio::task::JoinHandle;

use super::ends::LinkEnds;
use super::error::HilError;
use super::link::open;
use super::transport::Transport;
use crate::board::clock::EmuClock;
use crate::board::leds::EmuLeds;
use crate::board::light::{EmuReceivers, EmuTransmitter, bit};
use crate::board::sensor::EmuSensor;
use firmware::hal::Receivers as _;

/// What the bridge of one robot needs from the run.
pub(crate) struct Bridge {
    pub(crate) robot: usize,
    pub(crate) transport: Transport,
    pub(crate) clock: EmuClock,
    pub(crate) transmitter: Option<EmuTransmitter>,
    pub(crate) receivers: Option<EmuReceivers>,
    pub(crate) sensor: EmuSensor,
    pub(crate) leds: EmuLeds,
    pub(crate) config: Config,
    pub(crate) setup: Setup,
    pub(crate) timeouts: HilTimeouts,
}

/// How long the host waits for a robot in the loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HilTimeouts {
    /// From connecting to its `Hello`.
    pub hello: Duration,
    /// Longest silence (no frame at all) once it runs; for a robot on the arena's clock, the
    /// longest wait (wall time) for its `Idle` after a `Sync`.
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
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
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
    /// True if it ran on the arena's clock (lockstep): `round_trips` counts its `Sync`s and
    /// their `Idle`s then, with no wall time measured.
    pub lockstep: bool,
    /// Heartbeats it answered: round trips measured (on the arena's clock: `Sync`s answered).
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

/// Why a bridge failed: the error names the transport; the arena adds the robot.
type Failure = HilError;

/// Sends one message on the link.
fn send(
    to: &UnboundedSender<Vec<u8>>,
    msg: &LinkMsg,
    report: &mut HilReport,
) -> Result<(), Failure> {
    let mut buf = [0u8; LINK_FRAME_MAX];
    let f = firmware::hil::encode(msg, &mut buf).map_err(|error| HilError::Encode {
        msg: Box::new(msg.clone()),
        error,
    })?;
    // The writer stops when the robot's end closes: the same failure as reading the end of
    // its stream, whichever of the two the bridge sees first.
    to.send(f.to_vec()).map_err(|_| HilError::SendEnded)?;
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
        let ends = open(&self.transport, self.clock.clone(), self.config).await;
        let mut ends = ends.map_err(|e| HilError::NotOpened(Box::new(e)))?;
        let out = self
            .serve(&mut ends, &mut report, t0, stop)
            .await
            .map_err(|e| e.with_output(ends.output()));
        ends.close().await;
        out.map(|()| report)
    }

    /// The robot's side of the run: its hello, its setup, then its light, messages, readings
    /// and heartbeats until `stop` fires (`Ok`) or the robot fails.
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
        let mut pending = self.greet(ends, &mut decoder, report, t0).await?;
        // 2. Its sensor's first readings, then the run's setup, and at once a heartbeat: its
        // answer says the robot runs the setup (what it sent before is stale: a board that ran
        // already may still be sending the last run's light and LEDs).
        if self.config.key.is_some() {
            // Link version 3 carries the key only to a robot on the arena's clock.
            return Err(HilError::NoKey {
                over: self.transport.to_string(),
            });
        }
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
                    return Err(HilError::Disconnected {
                        over: self.transport.to_string(),
                    });
                }
                Input::Bytes(Some(bytes)) => {
                    self.on_bytes(bytes, now, &mut decoder, &mut live, &air, report)
                        .await?;
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
            self.due(now, &to, &mut live, report).await?;
        }
    }

    /// Waits for the robot's `Hello` and checks its sectors: the bytes that came after it.
    async fn greet(
        &self,
        ends: &mut LinkEnds,
        decoder: &mut LinkDecoder,
        report: &mut HilReport,
        t0: Instant,
    ) -> Result<Vec<u8>, Failure> {
        let (id, sectors, pending) = self.await_hello(&mut ends.from_robot, decoder, t0).await?;
        report.hello_id = id;
        report.hello_ms = self.clock.now().saturating_since(t0).as_millis();
        if sectors != self.config.params.sectors {
            return Err(HilError::Sectors {
                has: sectors,
                over: self.transport.to_string(),
                want: self.config.params.sectors,
            });
        }
        Ok(pending)
    }

    /// Bytes from the robot, arrived at `now`: each message they complete is handled.
    async fn on_bytes(
        &mut self,
        bytes: Vec<u8>,
        now: Instant,
        decoder: &mut LinkDecoder,
        live: &mut Live,
        air: &UnboundedSender<Vec<u8>>,
        report: &mut HilReport,
    ) -> Result<(), Failure> {
        report.bytes_received += bytes.len() as u64;
        for b in bytes {
            match decoder.push(b) {
                None => {}
                Some(Err(_)) => report.link_errors += 1,
                Some(Ok(msg)) => {
                    report.frames_received += 1;
                    live.last_heard = now;
                    self.on_message(msg, live, report, air).await?;
                }
            }
        }
        Ok(())
    }

    /// What is due at `now`: the sensor's readings every sample period, a heartbeat every
    /// beat; fails if the robot has been silent too long.
    async fn due(
        &mut self,
        now: Instant,
        to: &UnboundedSender<Vec<u8>>,
        live: &mut Live,
        report: &mut HilReport,
    ) -> Result<(), Failure> {
        if now >= live.next_sample {
            self.readings(to, report).await?;
            live.next_sample = now + self.config.sample_period;
        }
        if now >= live.next_beat {
            send(to, &LinkMsg::Heartbeat(live.beat), report)?;
            live.ping = Some((live.beat, tokio::time::Instant::now()));
            live.beat = live.beat.wrapping_add(1);
            live.next_beat = now + firmware::hil::robot::BEAT;
        }
        let silent = now.saturating_since(live.last_heard);
        if silent > self.timeouts.silence {
            return Err(HilError::HeartbeatStopped {
                over: self.transport.to_string(),
                silent,
            });
        }
        Ok(())
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
                    return Err(HilError::NoHello {
                        over: self.transport.to_string(),
                        within: std::time::Duration::from_millis(self.timeouts.hello.as_millis()),
                    });
                }
            };
            let Some(bytes) = got else {
                return Err(HilError::EndedBeforeHello {
                    over: self.transport.to_string(),
                });
            };
            for (i, &b) in bytes.iter().enumerate() {
                match decoder.push(b) {
                    Some(Ok(LinkMsg::Hello { id, sectors, .. })) => {
                        return Ok((id, sectors, bytes[i + 1..].to_vec()));
                    }
                    Some(Err(LinkError::UnknownVersion(version))) => {
                        return Err(HilError::Version {
                            version,
                            over: self.transport.to_string(),
                        });
                    }
                    _ => {}
                }
            }
        }
    }

    /// Starts the robot's light: a task handing what reaches its receivers to the returned
    /// channel, with the sector, and one putting the frames sent into the returned one on air,
    /// one at a time as from the robot's own transmitter. The tasks end when the guard is
    /// dropped.
    fn start_light(&mut self) -> (Heard, UnboundedSender<Vec<u8>>, AbortAll) {
        let (heard_tx, heard) = unbounded_channel::<(usize, Vec<u8>)>();
        let mut tasks = Vec::new();
        if let Some(rx) = self.receivers.take() {
            tasks.push(tokio::task::spawn_local(hear(rx, heard_tx)));
        }
        let (air, air_rx) = unbounded_channel::<Vec<u8>>();
        if let Some(transmitter) = self.transmitter.take() {
            tasks.push(tokio::task::spawn_local(put_on_air(transmitter, air_rx)));
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
                return Err(HilError::Refused {
                    over: self.transport.to_string(),
                    why: refusal(code),
                    code,
                });
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
                return Err(HilError::Rebooted {
                    over: self.transport.to_string(),
                });
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
            return Err(HilError::Dark {
                over: self.transport.to_string(),
                ran,
            });
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

/// Why a robot refused its setup, from [`LinkMsg::Refused`]'s code.
pub(super) fn refusal(code: u8) -> &'static str {
    match code {
        1 => "bad protocol parameters",
        2 => "its receivers and the sectors differ",
        3 => "a zero duration",
        4 => "a swarm key without keyed framing",
        firmware::hil::robot::REFUSED_HOST_CLOCK => "it cannot follow the host's clock",
        _ => "another reason",
    }
}

/// Hands what reaches `rx` (every sector, until its stream ends) to `to`, with the sector.
pub(super) async fn hear(mut rx: EmuReceivers, to: UnboundedSender<(usize, Vec<u8>)>) {
    let mut buf = [0u8; CHUNK_MAX];
    let mut open = u8::MAX;
    while open != 0 {
        let (sector, got) = rx.read(open, &mut buf).await;
        match got {
            Ok(n @ 1..) => {
                if to.send((sector, buf[..n].to_vec())).is_err() {
                    return;
                }
            }
            _ => open &= !bit(sector),
        }
    }
}

/// Puts each frame from `frames` on air through `transmitter`, one at a time as from the
/// robot's own transmitter.
pub(super) async fn put_on_air(
    mut transmitter: EmuTransmitter,
    mut frames: UnboundedReceiver<Vec<u8>>,
) {
    while let Some(f) = frames.recv().await {
        let _ = transmitter.write(&f).await;
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
        host_clock: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
