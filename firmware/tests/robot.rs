//! The robot program on fake hardware, under tokio's paused clock: virtual time, so an hour of
//! robot life takes milliseconds, and every run with the same seed is identical.
//!
//! The robot under test (id 1) sits in a line between two scripted neighbours (robots 0 on
//! its left and 2 on its right) that send frames on a fixed schedule. It reads darkness; the lit neighbour's side is the diverse one, so it must
//! decide for that side, and show it on the LEDs.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::future::pending;

use embassy_futures::select::{Either, select};
use firmware::embedded_io_async::{self, ErrorKind as IoKind, Read, Write};
use firmware::hal::{Clock, ErrorKind, ErrorType, LedColor, Leds, Sensor};
use firmware::protocol::frame::{Deframer, FrameError, KEYED_MAX_HOPS, encode, encode_keyed};
use firmware::protocol::{Hop, Instant, Level, Message, Sector, SwarmKey, Tag};
use firmware::{Config, Hardware, Robot, SetupError, Stats};
use rand_pcg::Pcg32;

mod common;
use common::TokioClock;

const L: Option<Sector> = Some(Sector::LEFT);
const R: Option<Sector> = Some(Sector::RIGHT);

/// Two negotiation periods of the longest cycles (10 × 70 s each), and a little more.
const TWO_PERIODS_MS: u64 = 2 * 10 * 70_000 + 1_000;

// ---------------------------------------------------------------------------------------------
// Fake hardware

/// What a scripted receiver delivers at a given time.
type Step = (u64, Result<Vec<u8>, IoKind>);

/// A receiver that delivers a script, then stays silent (or reports the end of its stream).
struct ScriptRx {
    clock: TokioClock,
    steps: VecDeque<Step>,
    close_at_end: bool,
}

impl ScriptRx {
    fn new(clock: TokioClock, mut steps: Vec<Step>) -> Self {
        steps.sort_by_key(|s| s.0);
        ScriptRx {
            clock,
            steps: steps.into(),
            close_at_end: false,
        }
    }
}

impl embedded_io_async::ErrorType for ScriptRx {
    type Error = IoKind;
}

impl Read for ScriptRx {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, IoKind> {
        let Some(&(at, _)) = self.steps.front() else {
            if self.close_at_end {
                return Ok(0);
            }
            return pending().await;
        };
        self.clock.sleep_until(Instant::from_millis(at)).await;
        let Some((_, step)) = self.steps.front_mut() else {
            return Ok(0);
        };
        match step {
            Ok(bytes) => {
                let n = bytes.len().min(buf.len());
                buf[..n].copy_from_slice(&bytes[..n]);
                bytes.drain(..n);
                if bytes.is_empty() {
                    self.steps.pop_front();
                }
                Ok(n)
            }
            Err(kind) => {
                let kind = *kind;
                self.steps.pop_front();
                Err(kind)
            }
        }
    }
}

/// A transmitter that records what was sent and when, or hangs for ever.
struct RecordingTx {
    clock: TokioClock,
    sent: Vec<(u64, Vec<u8>)>,
    hang: bool,
}

impl embedded_io_async::ErrorType for RecordingTx {
    type Error = Infallible;
}

impl Write for RecordingTx {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        if self.hang {
            return pending().await;
        }
        self.sent.push((self.clock.now().as_millis(), buf.to_vec()));
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// How a fake sensor or LED set misbehaves.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Works,
    /// Every other call fails.
    Flaky,
    /// Every call fails.
    Broken,
    /// Every call hangs for ever.
    Hangs,
}

impl Mode {
    /// Whether call number `n` fails; hangs if the device hangs.
    async fn fails(self, n: u32) -> bool {
        match self {
            Mode::Works => false,
            Mode::Flaky => n.is_multiple_of(2),
            Mode::Broken => true,
            Mode::Hangs => pending().await,
        }
    }
}

struct FakeSensor {
    light: Level,
    mode: Mode,
    calls: u32,
}

impl ErrorType for FakeSensor {
    type Error = ErrorKind;
}

impl Sensor for FakeSensor {
    async fn ambient_light(&mut self) -> Result<Level, ErrorKind> {
        self.calls += 1;
        if self.mode.fails(self.calls).await {
            return Err(ErrorKind::Bus);
        }
        Ok(self.light)
    }

    async fn oxygen(&mut self) -> Result<Level, ErrorKind> {
        Err(ErrorKind::NotReady)
    }
}

struct FakeLeds {
    clock: TokioClock,
    mode: Mode,
    calls: u32,
    shown: Vec<(u64, LedColor)>,
}

impl ErrorType for FakeLeds {
    type Error = ErrorKind;
}

impl Leds for FakeLeds {
    async fn show(&mut self, color: LedColor) -> Result<(), ErrorKind> {
        self.calls += 1;
        if self.mode.fails(self.calls).await {
            return Err(ErrorKind::Timeout);
        }
        self.shown.push((self.clock.now().as_millis(), color));
        Ok(())
    }
}

type FakeHardware = Hardware<RecordingTx, [ScriptRx; 2], FakeSensor, FakeLeds, TokioClock>;

// ---------------------------------------------------------------------------------------------
// Scripted neighbours

/// The robot under test's id, hence its tag.
const ID: u16 = 1;

/// The hop robot `tag` adds with `reading` and `pref`.
fn hop(tag: u16, reading: u8, pref: Option<Sector>) -> Hop {
    Hop {
        reading: Level(reading),
        pref,
        tag: Tag::from_id(tag),
    }
}

/// The tag of the neighbour on `side`: robot 0 on the left, robot 2 on the right.
fn neighbour_tag(side: Sector) -> u16 {
    if side == Sector::LEFT { ID - 1 } else { ID + 1 }
}

/// A neighbour that sends `msg` every `period` ms from `first` on, until `until`, framed with
/// `key` (plain frames if `None`).
fn neighbour(first: u64, period: u64, until: u64, msg: &[Hop], key: Option<SwarmKey>) -> Vec<Step> {
    let msg = Message::from_hops(msg).unwrap();
    let frame = match key {
        Some(k) => encode_keyed(&msg, &k),
        None => encode(&msg),
    };
    let frame = frame.unwrap().to_vec();
    (first..until)
        .step_by(period as usize)
        .map(|t| (t, Ok(frame.clone())))
        .collect()
}

/// The lit neighbour initiates with its reading and no preference yet; the dark one relays
/// with a preference for the lit side.
fn lit(side: Sector) -> Vec<Hop> {
    vec![hop(neighbour_tag(side), 1, None)]
}

fn dark_toward(side: Sector, pref: Option<Sector>) -> Vec<Hop> {
    vec![hop(neighbour_tag(side), 0, pref)]
}

/// A dark robot between a lit neighbour on `lit_side` and a dark one on the other.
fn scene(lit_side: Sector, seed: u64) -> (Robot<Pcg32, 2>, FakeHardware) {
    keyed_scene(lit_side, seed, None, None)
}

/// [`scene`] with a swarm key for the robot and another (or the same, or none) for the frames
/// its neighbours send.
fn keyed_scene(
    lit_side: Sector,
    seed: u64,
    robot_key: Option<SwarmKey>,
    neighbour_key: Option<SwarmKey>,
) -> (Robot<Pcg32, 2>, FakeHardware) {
    let clock = TokioClock::new();
    let until = TWO_PERIODS_MS;
    let (left, right) = if lit_side == Sector::LEFT {
        (lit(Sector::LEFT), dark_toward(Sector::RIGHT, L))
    } else {
        (dark_toward(Sector::LEFT, R), lit(Sector::RIGHT))
    };
    // Different periods, so the neighbours drift through the robot's own cycle.
    let left = ScriptRx::new(clock, neighbour(7_300, 47_000, until, &left, neighbour_key));
    let right = ScriptRx::new(
        clock,
        neighbour(29_100, 61_000, until, &right, neighbour_key),
    );
    let hw = Hardware::line(
        RecordingTx {
            clock,
            sent: Vec::new(),
            hang: false,
        },
        left,
        right,
        FakeSensor {
            light: Level(0),
            mode: Mode::Works,
            calls: 0,
        },
        FakeLeds {
            clock,
            mode: Mode::Works,
            calls: 0,
            shown: Vec::new(),
        },
        clock,
    );
    let config = Config {
        id: ID,
        key: robot_key,
        ..Config::robots()
    };
    let robot = Robot::new(config, clock.now(), Pcg32::new(seed, 0xda3e_39cb_94b9_5bdb)).unwrap();
    (robot, hw)
}

/// Runs the robot for `ms` of virtual time, then stops it.
async fn run_for(robot: &mut Robot<Pcg32, 2>, hw: &mut FakeHardware, ms: u64) {
    let stop = tokio::time::sleep(std::time::Duration::from_millis(ms));
    match select(robot.run(hw), stop).await {
        Either::First(never) => match never {},
        Either::Second(()) => {}
    }
}

/// Every message the robot transmitted, decoded.
fn sent_messages(hw: &FakeHardware) -> Vec<(u64, Message)> {
    sent_messages_with(hw, Deframer::new())
}

/// Every message the robot transmitted, decoded by `d`.
fn sent_messages_with(hw: &FakeHardware, mut d: Deframer) -> Vec<(u64, Message)> {
    let mut out = Vec::new();
    for (t, bytes) in &hw.transmitter.sent {
        for r in d.frames(bytes) {
            out.push((*t, r.expect("the robot only sends good frames")));
        }
    }
    assert_eq!(d.stats().errors(), 0);
    out
}

fn expect_decided(robot: &Robot<Pcg32, 2>, hw: &FakeHardware, side: Option<Sector>, seed: u64) {
    let color = LedColor::for_decision(side);
    assert_eq!(
        robot.decision(),
        side,
        "replay with seed {seed}: {:?}",
        robot.stats()
    );
    assert!(
        robot.stats().decisions >= 2,
        "seed {seed}: {:?}",
        robot.stats()
    );
    assert_eq!(robot.shown(), Some(color), "seed {seed}");
    assert_eq!(
        hw.leds.shown.last().map(|s| s.1),
        Some(color),
        "seed {seed}"
    );
    // The first decision falls after one negotiation period: 10 cycles of 40 to 70 s.
    let first = hw.leds.shown[0].0;
    assert!(
        (400_000..=700_000).contains(&first),
        "seed {seed}: first decision at {first} ms"
    );
}

// ---------------------------------------------------------------------------------------------
// Tests

#[tokio::test(start_paused = true)]
async fn decides_for_the_lit_neighbours_side_and_shows_it() {
    for seed in 0..8 {
        for (lit_side, expected) in [(Sector::LEFT, L), (Sector::RIGHT, R)] {
            let (mut robot, mut hw) = scene(lit_side, seed);
            run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
            expect_decided(&robot, &hw, expected, seed);
            let s = robot.stats();
            assert!(s.messages > 30, "seed {seed}: {s:?}");
            assert_eq!(
                (s.frame_errors, s.rx_errors, s.tx_errors),
                (0, 0, 0),
                "seed {seed}"
            );
            assert_eq!((s.sensor_errors, s.led_errors), (0, 0), "seed {seed}");
            assert!(
                robot.node().wave_stats().ignored > 0,
                "some arrive while refractory"
            );
        }
    }
}

#[tokio::test(start_paused = true)]
async fn relays_what_it_hears_with_its_own_hop_and_initiates() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 1);
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let sent = sent_messages(&hw);
    assert_eq!(sent.len() as u32, robot.stats().transmitted);
    let relays_of_lit = sent
        .iter()
        .filter(|(_, m)| m.hops() == [hop(0, 1, None), hop(ID, 0, L)])
        .count();
    assert!(relays_of_lit > 5, "{sent:?}");
    let initiations = sent.iter().filter(|(_, m)| m.len() == 1).count() as u32;
    assert_eq!(initiations, robot.node().wave_stats().initiated);
    // A relay goes out one relay delay (1 s) after the neighbour's frame arrived.
    let lit_times: Vec<u64> = (7_300..TWO_PERIODS_MS).step_by(47_000).collect();
    for (t, m) in &sent {
        if m.hops() == [hop(0, 1, None), hop(ID, 0, L)] {
            assert!(lit_times.contains(&(t - 1_000)), "relay at {t} ms");
        }
    }
}

#[tokio::test(start_paused = true)]
async fn same_seed_same_run() {
    let trace = |seed| async move {
        let (mut robot, mut hw) = scene(Sector::RIGHT, seed);
        run_for(&mut robot, &mut hw, 600_000).await;
        hw.transmitter.sent
    };
    assert_eq!(trace(5).await, trace(5).await);
    assert_ne!(trace(5).await, trace(6).await);
}

#[tokio::test(start_paused = true)]
async fn survives_garbage_corrupt_frames_and_receiver_errors() {
    use rand_core::RngCore;
    for seed in 0..8 {
        let (mut robot, mut hw) = scene(Sector::LEFT, seed);
        let mut noise = Pcg32::new(seed, 77);
        let mut good = 0;
        for rx in &mut hw.receivers {
            let mut extra = Vec::new();
            for (t, step) in &rx.steps {
                let Ok(frame) = step else { continue };
                good += 1;
                // Noise (with plenty of `s`) between frames.
                let mut junk = vec![0u8; 1 + (noise.next_u32() % 60) as usize];
                noise.fill_bytes(&mut junk);
                for b in junk.iter_mut().step_by(5) {
                    *b = b's';
                }
                extra.push((t + 3_000, Ok(junk)));
                // A copy of the frame with a flipped bit.
                let mut bad = frame.clone();
                let i = 2 + (noise.next_u32() as usize % (bad.len() - 4));
                bad[i] ^= 1 << (noise.next_u32() % 8);
                extra.push((t + 11_000, Ok(bad)));
                extra.push((t + 13_000, Err(IoKind::InvalidData)));
            }
            let mut steps: Vec<Step> = rx.steps.drain(..).chain(extra).collect();
            steps.sort_by_key(|s| s.0);
            rx.steps = steps.into();
        }
        run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
        expect_decided(&robot, &hw, L, seed);
        let s = *robot.stats();
        assert!(s.frame_errors >= good / 2, "seed {seed}: {s:?}");
        assert_eq!(
            s.rx_errors, good,
            "seed {seed}: every receiver error counted"
        );
        assert!(
            s.messages >= good,
            "seed {seed}: every good frame got through: {s:?}"
        );
    }
}

#[tokio::test(start_paused = true)]
async fn keeps_going_with_a_flaky_or_broken_sensor() {
    for mode in [Mode::Flaky, Mode::Broken] {
        let (mut robot, mut hw) = scene(Sector::RIGHT, 3);
        hw.sensor.mode = mode;
        run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
        // A broken sensor leaves the reading at its default, darkness: the same decision.
        expect_decided(&robot, &hw, R, 3);
        let s = robot.stats();
        let expected = if mode == Mode::Broken {
            hw.sensor.calls
        } else {
            hw.sensor.calls / 2
        };
        assert_eq!(s.sensor_errors, expected, "{mode:?}: {s:?}");
        assert!(s.sensor_errors > 600, "sampled every second: {s:?}");
    }
}

#[tokio::test(start_paused = true)]
async fn a_flaky_sensor_keeps_the_last_good_reading() {
    let (mut robot, mut hw) = scene(Sector::RIGHT, 3);
    hw.sensor.mode = Mode::Flaky;
    hw.sensor.light = Level(9);
    run_for(&mut robot, &mut hw, 10_000).await;
    assert_eq!(robot.node().reading(), Level(9));
}

#[tokio::test(start_paused = true)]
async fn never_blocks_on_hung_devices() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 2);
    hw.sensor.mode = Mode::Hangs;
    hw.leds.mode = Mode::Hangs;
    hw.transmitter.hang = true;
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let s = *robot.stats();
    // Deadlines were kept: decisions taken, neighbours heard, every device call timed out.
    assert!(s.decisions >= 2, "{s:?}");
    assert_eq!(robot.decision(), L, "{s:?}");
    assert!(s.messages > 30, "{s:?}");
    assert_eq!(s.transmitted, 0);
    assert!(s.tx_errors > 20, "{s:?}");
    assert_eq!(s.led_errors, s.decisions, "{s:?}");
    // One read per sample period plus the I/O timeout each: about 1400 s / 1.5 s.
    assert!(s.sensor_errors > 900, "{s:?}");
    assert_eq!(robot.shown(), None);
}

#[tokio::test(start_paused = true)]
async fn failing_leds_are_counted_and_retried() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 4);
    hw.leds.mode = Mode::Flaky;
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let s = robot.stats();
    assert_eq!(s.led_errors, hw.leds.calls / 2, "{s:?}");
    assert!(!hw.leds.shown.is_empty());
}

#[tokio::test(start_paused = true)]
async fn closed_receivers_are_dropped_and_the_robot_keeps_time() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 0);
    for rx in &mut hw.receivers {
        rx.steps.clear();
        rx.close_at_end = true;
    }
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let s: Stats = *robot.stats();
    assert_eq!(s.rx_closed, 2, "{s:?}");
    assert!(s.decisions >= 2, "{s:?}");
    // Alone, with no evidence: undecided, LEDs off.
    assert_eq!(robot.decision(), None);
    assert_eq!(hw.leds.shown.last().map(|s| s.1), Some(LedColor::Off));
    assert!(s.transmitted >= 20, "it still initiates its waves: {s:?}");
}

#[tokio::test(start_paused = true)]
async fn can_be_stopped_and_resumed() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 6);
    for _ in 0..14 {
        run_for(&mut robot, &mut hw, TWO_PERIODS_MS / 14 + 1).await;
    }
    expect_decided(&robot, &hw, L, 6);
}

#[test]
fn bad_setups_are_refused() {
    let rng = || Pcg32::new(0, 0);
    let mut c = Config::robots();
    c.params.sectors = 3;
    assert_eq!(
        Robot::<_, 2>::new(c, Instant::ZERO, rng()).err(),
        Some(SetupError::Receivers {
            sectors: 3,
            receivers: 2
        })
    );
    let mut c = Config::robots();
    c.params.sectors = 9;
    assert!(matches!(
        Robot::<_, 9>::new(c, Instant::ZERO, rng()),
        Err(SetupError::Params(_))
    ));
    for zero in [
        |c: &mut Config| c.sample_period = firmware::protocol::Duration::ZERO,
        |c: &mut Config| c.io_timeout = firmware::protocol::Duration::ZERO,
        |c: &mut Config| c.rx_error_backoff = firmware::protocol::Duration::ZERO,
    ] {
        let mut c = Config::robots();
        zero(&mut c);
        assert_eq!(
            Robot::<_, 2>::new(c, Instant::ZERO, rng()).err(),
            Some(SetupError::ZeroDuration)
        );
    }
    assert!(Robot::<_, 2>::new(Config::robots(), Instant::ZERO, rng()).is_ok());
}

#[test]
fn the_tag_is_the_id_modulo_sixteen() {
    for (id, tag) in [(0, 0), (1, 1), (15, 15), (16, 0), (17, 1), (u16::MAX, 15)] {
        let c = Config {
            id,
            ..Config::robots()
        };
        let robot = Robot::<_, 2>::new(c, Instant::ZERO, Pcg32::new(0, 0)).unwrap();
        assert_eq!(robot.node().tag(), Tag::new(tag).unwrap(), "id {id}");
    }
}

#[tokio::test(start_paused = true)]
async fn echoes_and_replays_of_its_own_messages_are_dropped() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 3);
    // Besides the lit neighbour's initiations, the left receiver hears an old message that
    // passed through this robot (its relay of robot 2, replayed) at times it can accept one.
    let mut steps = neighbour(7_300, 47_000, TWO_PERIODS_MS, &lit(Sector::LEFT), None);
    let echo = [hop(2, 0, L), hop(ID, 0, L), hop(0, 1, R)];
    steps.extend(neighbour(30_000, 47_000, TWO_PERIODS_MS, &echo, None));
    hw.receivers[Sector::LEFT.index() as usize] = ScriptRx::new(hw.clock, steps);
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    expect_decided(&robot, &hw, L, 3);
    let dropped = robot.node().stats().own_tag;
    assert!(dropped > 20, "{dropped}");
    for (_, m) in sent_messages(&hw) {
        let own = m
            .hops()
            .iter()
            .filter(|h| h.tag == Tag::from_id(ID))
            .count();
        assert_eq!(own, 1, "its own hop, once: {m:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Authenticated frames

const SWARM: SwarmKey = SwarmKey::new([0x42; 16]);
const FOREIGN: SwarmKey = SwarmKey::new([0x24; 16]);

#[tokio::test(start_paused = true)]
async fn a_keyed_robot_hears_its_swarm_and_sends_only_keyed_frames() {
    for seed in 0..4 {
        for (lit_side, expected) in [(Sector::LEFT, L), (Sector::RIGHT, R)] {
            let (mut robot, mut hw) = keyed_scene(lit_side, seed, Some(SWARM), Some(SWARM));
            run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
            expect_decided(&robot, &hw, expected, seed);
            let s = *robot.stats();
            assert!(s.messages > 30, "seed {seed}: {s:?}");
            assert_eq!((s.frame_errors, s.bad_mac, s.tx_errors), (0, 0, 0), "{s:?}");
            // Everything it sent carries the swarm's MAC: a keyed deframer takes all of it, a
            // plain one or one with another key none.
            let sent = sent_messages_with(&hw, Deframer::with_key(SWARM));
            assert_eq!(sent.len() as u32, s.transmitted);
            for other in [Deframer::new(), Deframer::with_key(FOREIGN)] {
                let mut d = other;
                for (_, bytes) in &hw.transmitter.sent {
                    assert!(d.frames(bytes).all(|r| r.is_err()));
                }
                assert_eq!(d.stats().frames, 0);
            }
        }
    }
}

#[tokio::test(start_paused = true)]
async fn a_keyed_robot_drops_and_counts_frames_without_its_key() {
    for neighbour_key in [None, Some(FOREIGN)] {
        let (mut robot, mut hw) = keyed_scene(Sector::LEFT, 1, Some(SWARM), neighbour_key);
        let delivered: u32 = hw.receivers.iter().map(|rx| rx.steps.len() as u32).sum();
        run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
        let s = *robot.stats();
        // Nothing got through: every frame was dropped for its MAC and counted.
        assert_eq!(s.messages, 0, "{neighbour_key:?}: {s:?}");
        assert_eq!(robot.node().stats().accepted, 0);
        assert_eq!(s.bad_mac, delivered, "{neighbour_key:?}: {s:?}");
        assert_eq!(s.frame_errors, s.bad_mac);
        // Deaf to the lit neighbour, it has no evidence: undecided, LEDs off.
        assert!(s.decisions >= 2, "{s:?}");
        assert_eq!(robot.decision(), None);
        assert_eq!(hw.leds.shown.last().map(|s| s.1), Some(LedColor::Off));
    }
    // A plain robot does not understand the keyed swarm either (but counts no bad MAC).
    let (mut robot, mut hw) = keyed_scene(Sector::LEFT, 1, None, Some(SWARM));
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let s = *robot.stats();
    assert_eq!((s.messages, s.bad_mac), (0, 0), "{s:?}");
    assert!(s.frame_errors > 30, "{s:?}");
}

#[tokio::test(start_paused = true)]
async fn a_keyed_robot_relays_at_most_eleven_hops() {
    let (mut robot, mut hw) = keyed_scene(Sector::LEFT, 2, Some(SWARM), Some(SWARM));
    assert_eq!(
        robot.config().params.max_hops,
        12,
        "the configuration as given"
    );
    assert_eq!(usize::from(robot.node().params().max_hops), KEYED_MAX_HOPS);
    // The left neighbour now sends full keyed messages: 11 hops, readings 1..=11.
    let long: Vec<Hop> = (1..=KEYED_MAX_HOPS as u8)
        .map(|r| hop(u16::from(r) + 1, r, None))
        .collect();
    hw.receivers[Sector::LEFT.index() as usize] = ScriptRx::new(
        hw.clock,
        neighbour(7_300, 47_000, 600_000, &long, Some(SWARM)),
    );
    run_for(&mut robot, &mut hw, 600_000).await;
    let sent = sent_messages_with(&hw, Deframer::with_key(SWARM));
    let relays: Vec<&Message> = sent
        .iter()
        .map(|(_, m)| m)
        // Relays of the left neighbour (the right one's are two hops long).
        .filter(|m| m.len() > 2)
        .collect();
    assert!(relays.len() > 5, "{sent:?}");
    for m in relays {
        // The oldest hops made room for the robot's own and its two-sector ray (9 bytes): a
        // keyed payload holds 23 bytes, 1 + 2 × 6 + 9 = 22 (a seventh hop does not fit).
        assert_eq!(m.len(), 6);
        assert_eq!(m.encoded_len(), protocol::frame::KEYED_PAYLOAD_MAX - 1);
        assert_eq!(m.hops()[0].reading, Level(7));
        assert_eq!(m.hops()[5].reading, Level(0));
        assert_eq!(m.ray().map(|r| r.sector), Some(Sector::LEFT));
    }
    assert!(robot.node().stats().hops_evicted > 5);
    assert_eq!(robot.stats().tx_errors, 0);
}

#[test]
fn a_keyed_frame_error_is_a_bad_mac() {
    let msg = Message::from_hops(&[hop(0, 1, None)]).unwrap();
    let f = encode(&msg).unwrap();
    let mut d = Deframer::with_key(SWARM);
    assert_eq!(d.frames(&f).collect::<Vec<_>>(), [Err(FrameError::BadMac)]);
}

/// Records the main loop's rounds ([`firmware::Observer::progress`]).
#[derive(Default)]
struct Rounds(Vec<Instant>);

impl firmware::Observer for Rounds {
    fn event(&mut self, _: Instant, _: &firmware::protocol::Event) {}

    fn progress(&mut self, now: Instant) {
        self.0.push(now);
    }
}

/// The largest gap between two rounds of the main loop over a run of `ms` (from the start).
async fn longest_gap(robot: &mut Robot<Pcg32, 2>, hw: &mut FakeHardware, ms: u64) -> u64 {
    let start = hw.clock.now();
    let mut rounds = Rounds::default();
    let stop = tokio::time::sleep(std::time::Duration::from_millis(ms));
    match select(robot.run_observed(hw, &mut rounds), stop).await {
        Either::First(never) => match never {},
        Either::Second(()) => {}
    }
    assert!(rounds.0.windows(2).all(|w| w[0] <= w[1]));
    let mut times = vec![start];
    times.extend(&rounds.0);
    times
        .windows(2)
        .map(|w| w[1].saturating_since(w[0]).as_millis())
        .max()
        .unwrap_or(u64::MAX)
}

/// A watchdog fed on `progress` needs a bound on the gap between rounds: one sample period
/// plus the I/O timeouts of one round (sensor, transmissions, LEDs), even with every device
/// hung. The Nucleo image's IWDG timeout (8 s) is well above it.
#[tokio::test(start_paused = true)]
async fn the_main_loop_comes_round_at_least_every_few_seconds() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 3);
    let healthy = longest_gap(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    assert!(
        healthy <= 1_000,
        "a healthy robot's longest round gap {healthy} ms"
    );

    let (mut robot, mut hw) = scene(Sector::LEFT, 3);
    hw.sensor.mode = Mode::Hangs;
    hw.leds.mode = Mode::Hangs;
    hw.transmitter.hang = true;
    let hung = longest_gap(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    assert!(hung > 1_000, "hung devices cost their timeouts: {hung} ms");
    // Measured 2,500 ms: a second of sleep, then the sensor's and one frame's 500 ms timeouts
    // (and the LEDs' when a decision is shown).
    assert!(
        hung <= 3_000,
        "with hung devices the longest round gap is {hung} ms"
    );
}

#[tokio::test(start_paused = true)]
async fn a_failing_receiver_rests_between_reads_and_the_other_still_hears() {
    let (mut robot, mut hw) = scene(Sector::LEFT, 5);
    // The right receiver fails every 5 ms for the whole run.
    let errors: Vec<Step> = (0..TWO_PERIODS_MS)
        .step_by(5)
        .map(|t| (t, Err(IoKind::Other)))
        .collect();
    let scripted = errors.len() as u64;
    hw.receivers[Sector::RIGHT.index() as usize] = ScriptRx::new(hw.clock, errors);
    let left_frames = hw.receivers[Sector::LEFT.index() as usize].steps.len() as u32;
    run_for(&mut robot, &mut hw, TWO_PERIODS_MS).await;
    let s = *robot.stats();
    // Read again only after each back-off (100 ms): one error per back-off, not per 5 ms.
    let backoff = Config::robots().rx_error_backoff.as_millis();
    let rests = TWO_PERIODS_MS / backoff;
    let errors = u64::from(s.rx_errors);
    assert!(errors <= rests + 1 && errors >= rests * 9 / 10, "{s:?}");
    assert!(errors < scripted / 10, "{errors} of {scripted}");
    // The left receiver is read all along: every frame of the lit neighbour is heard, and
    // followed.
    assert!(left_frames > 25);
    assert_eq!(s.messages, left_frames, "{s:?}");
    expect_decided(&robot, &hw, L, 5);
}

#[tokio::test(start_paused = true)]
async fn an_array_of_streams_is_read_as_one_lowest_sector_first() {
    use firmware::hal::Receivers;
    let clock = TokioClock::new();
    let at = |t: u64, bytes: &[u8]| (t, Ok(bytes.to_vec()));
    let mut rx = [
        ScriptRx::new(clock, vec![at(10, b"right"), at(30, b"r2")]),
        ScriptRx::new(
            clock,
            vec![at(10, b"left"), at(20, b"l2"), (40, Err(IoKind::Other))],
        ),
    ];
    rx[0].close_at_end = true;
    let mut buf = [0u8; 32];
    let mut got = Vec::new();
    for k in 0..6 {
        // After its end the right stream is not asked for again, as the robot does.
        let asked = if k < 5 { 0b11 } else { 0b10 };
        let (i, r) = rx.read(asked, &mut buf).await;
        got.push((clock.now().as_millis(), i, r.map(|n| buf[..n].to_vec())));
    }
    let ok = |t: u64, i: usize, b: &[u8]| (t, i, Ok(b.to_vec()));
    assert_eq!(
        got,
        [
            // Both have bytes at 10 ms: the right (sector 0) first.
            ok(10, 0, b"right"),
            ok(10, 1, b"left"),
            ok(20, 1, b"l2"),
            ok(30, 0, b"r2"),
            // The right stream ended; the left fails at 40 ms.
            ok(30, 0, b""),
            (40, 1, Err(IoKind::Other)),
        ]
    );
    // Only the sectors asked for are read; each gets half of a buffer: 16 bytes.
    let mut rx = [
        ScriptRx::new(clock, vec![at(50, b"not asked")]),
        ScriptRx::new(clock, vec![at(60, &[7; 20])]),
    ];
    let (i, r) = rx.read(0b10, &mut buf).await;
    assert_eq!((clock.now().as_millis(), i, r), (60, 1, Ok(16)));
    assert_eq!(buf[..16], [7; 16]);
    assert_eq!(rx[0].steps.len(), 1, "the right one was not read");
    // A buffer with room for one byte reads the lowest sector only.
    let mut one = [0u8; 1];
    assert_eq!(rx.read(0b11, &mut one).await, (0, Ok(1)));
    assert_eq!(one, [b'n']);
}
