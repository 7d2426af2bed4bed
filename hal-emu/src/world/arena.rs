//! A whole emulated run, the world's orchestrator: it builds the medium, the environment and
//! the adversaries from an [`ArenaConfig`], boots each robot on its board ([`crate::board`])
//! running the unchanged robot program, carries out scheduled kills and restarts, moves the
//! swarm over a plane field, and reports the LED changes a camera would have seen.
//!
//! Its line of robots ([`ArenaConfig::line`]) is one of three in the workspace, the deepest:
//! the same robot program as `firmware::wired::run_line` (wired in memory, no airtime, what the
//! QEMU board runs), here through the modelled medium; `protocol::line` drives the protocol core
//! alone. Each tests what the others leave out (see `protocol::line`).

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use embassy_futures::select::{Either, select};
use firmware::{Clock, Config, Hardware, LedColor, Observer, Robot, SetupError, Stats};
use nalgebra::{Point2, Vector2};
use protocol::fused::NodeStats;
use protocol::wave::WaveStats;
use protocol::{Duration, Event, FusedNode, Instant, Sector, WaveState};
use rand_pcg::Pcg32;
use tokio::sync::oneshot;

use crate::board::leds::{EmuLeds, LedLog};
use crate::board::sensor::EmuSensor;
use crate::world::adversary::{self, Adversary};
use crate::world::clock::EmuClock;
use crate::world::env::Environment;
use crate::world::hil::{Bridge, HilReport, HilRobot, HilTimeouts, setup_of, setup_seed};
use crate::world::medium::{Medium, MediumParams, MediumStats, SharedMedium, TraceEvent};

/// Everything that defines a run.
#[derive(Clone, Debug)]
pub struct ArenaConfig {
    /// Robot positions, metres.
    pub positions: Vec<Point2<f64>>,
    /// The robot program's configuration. Its `id` is set per robot: robot `i` gets `ids[i]`,
    /// or `i` without `ids`, hence the tag `id mod 16` on the wire. Each robot has
    /// `robot.params.sectors` receivers (2 to 8), receiver `s` facing sector `s` of the swarm's
    /// common frame.
    pub robot: Config,
    /// Per-robot configurations: robot `i` runs `configs[i]` where it is `Some`, and
    /// [`robot`](Self::robot) otherwise (and beyond the end of the list, so an empty list means
    /// one configuration for all). The `id` is still set per robot as for the shared one, and
    /// every robot must have the shared one's `params.sectors` (the medium gives every robot as
    /// many receivers). For robots that differ, e.g. a keyed swarm with an outsider without the
    /// key: [`with_config`](Self::with_config).
    pub configs: Vec<Option<Config>>,
    /// Robot ids, if not `0..n` (on a plane, ids whose tags differ between neighbours).
    pub ids: Option<Vec<u16>>,
    /// How the swarm moves as it decides, if it does (robots on a plane over a field).
    pub motion: Option<Motion>,
    /// The light medium.
    pub medium: MediumParams,
    /// What the sensors read.
    pub env: Environment,
    /// `(time, robot)`: the robot dies (stops, hears nothing, LEDs off).
    pub kills: Vec<(Instant, usize)>,
    /// `(time, robot)`: the robot boots again with fresh state.
    pub restarts: Vec<(Instant, usize)>,
    /// Robots dead from the start (boot them with a restart). One that is never restarted is
    /// absent: [`lab::judge`](crate::judge::judge) judges the others as a line of their own.
    pub dead_at_start: Vec<usize>,
    /// Rogue transmitters and replayers sharing the robots' light (node numbers after the
    /// robots', in this order).
    pub adversaries: Vec<Adversary>,
    /// Emulated time to run.
    pub duration: Duration,
    /// The one seed every random thing is drawn from.
    pub seed: u64,
    /// Keep a full trace of frames, LEDs and events.
    pub trace: bool,
    /// Robots in the loop ([`crate::world::hil`]): these places are taken by robots running the real
    /// image elsewhere (QEMU, a board, a socket), reached over the link of `docs/hil.md`. With
    /// any that is not in this process the run goes in real time.
    pub hil: Vec<HilRobot>,
    /// How long the host waits for a robot in the loop to say hello, and how much silence it
    /// takes.
    pub hil_timeouts: HilTimeouts,
}

impl ArenaConfig {
    /// `pattern.len()` robots in a line along x, `spacing` metres apart, with the lab's
    /// parameters and the default medium.
    pub fn line(pattern: Vec<bool>, spacing: f64, duration: Duration, seed: u64) -> Self {
        let positions = (0..pattern.len())
            .map(|i| Point2::new(i as f64 * spacing, 0.0))
            .collect();
        ArenaConfig {
            positions,
            robot: Config::robots(),
            medium: MediumParams::default(),
            env: Environment::constant(pattern),
            kills: Vec::new(),
            restarts: Vec::new(),
            dead_at_start: Vec::new(),
            adversaries: Vec::new(),
            duration,
            seed,
            trace: false,
            configs: Vec::new(),
            ids: None,
            motion: None,
            hil: Vec::new(),
            hil_timeouts: HilTimeouts::default(),
        }
    }

    /// True if the run goes in real time: a robot in the loop runs on its own clock.
    pub fn real_time(&self) -> bool {
        self.hil.iter().any(|h| !h.transport.virtual_time())
    }

    /// The same run with robot `robot` running `config` instead of the shared
    /// [`robot`](Self::robot) configuration ([`configs`](Self::configs)).
    #[must_use]
    pub fn with_config(mut self, robot: usize, config: Config) -> Self {
        if self.configs.len() <= robot {
            self.configs.resize(robot + 1, None);
        }
        self.configs[robot] = Some(config);
        self
    }

    /// The configuration robot `robot` runs, before its `id` is set: its own
    /// ([`configs`](Self::configs)) or the shared one.
    pub fn config_of(&self, robot: usize) -> Config {
        config_of(self.robot, &self.configs, robot)
    }
}

/// Robot `robot`'s configuration: `configs[robot]` if given, else `shared`.
fn config_of(shared: Config, configs: &[Option<Config>], robot: usize) -> Config {
    configs.get(robot).copied().flatten().unwrap_or(shared)
}

/// The swarm's motion over a [`PlaneField`](crate::world::env::PlaneField), as in the paper's 2D
/// simulations: every `period` (a negotiation period) the swarm moves rigidly by `step` R along
/// its decision, the circular mean of the sectors the robots' LEDs show ([`swarm_heading`]).
/// Relative positions do not change, so neither does what the robots hear: only what they
/// sense.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Time between moves.
    pub period: Duration,
    /// Length of a move, in R.
    pub step: f64,
}

/// One move of the swarm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// When.
    pub t: Instant,
    /// The centre of mass before the move, in R.
    pub centre: Point2<f64>,
    /// The swarm's heading (radians), if any robot had decided.
    pub heading: Option<f64>,
    /// Fraction of all robots whose LEDs show the sector nearest the heading.
    pub consensus: f64,
}

/// The swarm's decision from its LEDs: the circular mean of the directions of the sectors the
/// decided robots show (`sectors` per robot), or `None` if none has decided or they cancel
/// out. Also the fraction of all robots showing the sector nearest that heading.
pub fn swarm_heading(leds: &[LedColor], sectors: u8) -> (Option<f64>, f64) {
    let (mut x, mut y, mut n) = (0.0, 0.0, 0.0f64);
    for s in leds.iter().filter_map(|c| c.decision()) {
        let b = f64::from(s.bearing(sectors));
        x += b.cos();
        y += b.sin();
        n += 1.0;
    }
    // Bearings are `f32`: opposite sectors cancel to within a rounding, not exactly.
    if x.hypot(y) < 1e-5 * n.max(1.0) {
        return (None, 0.0);
    }
    let heading = y.atan2(x);
    let nearest = Sector::from_bearing(heading as f32, sectors);
    let agree = leds
        .iter()
        .filter(|c| c.decision() == Some(nearest))
        .count();
    (Some(heading), agree as f64 / leds.len().max(1) as f64)
}
/// Why a run could not start.
#[derive(Debug, Clone, PartialEq)]
pub enum ArenaError {
    /// The robot program refused its configuration.
    Setup(SetupError),
    /// The medium's parameters make no sense.
    Medium(String),
    /// A kill, restart or per-robot configuration names a robot that does not exist.
    NoSuchRobot(usize),
    /// An adversary's parameters make no sense.
    Adversary(String),
    /// The tokio runtime could not be built.
    Runtime(String),
    /// A robot in the loop cannot be: its place does not exist or is taken twice, or the run
    /// asks what the link cannot carry (kills and restarts of it, a swarm key).
    Hil(String),
    /// A run in real time was interrupted (Ctrl-C, SIGTERM or SIGHUP) before its end; robots
    /// in the loop were stopped, QEMU processes killed and reaped.
    Interrupted,
    /// A robot stopped before the end of the run: its task panicked (a bug in the robot
    /// program or the emulator) or it could not boot. The run then has no valid result (its
    /// LEDs and counters would be those of a swarm that lost a robot without anyone killing
    /// it), so it fails; the failure's seed replays it.
    Robot(RobotFailure),
}

/// A robot that stopped before the end of its run ([`ArenaError::Robot`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RobotFailure {
    /// The robot's index (its position in [`ArenaConfig::positions`]).
    pub robot: usize,
    /// The run's seed ([`ArenaConfig::seed`]): it replays the failure.
    pub seed: u64,
    /// True if the robot's task panicked; false if the robot could not boot, or (a robot in the
    /// loop) its link failed.
    pub panicked: bool,
    /// The panic's message, or why the robot could not boot or its link failed.
    pub message: String,
}

impl std::fmt::Display for RobotFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = if self.panicked { "panicked" } else { "failed" };
        write!(
            f,
            "robot {} {what} (seed {}): {}",
            self.robot, self.seed, self.message
        )
    }
}

impl RobotFailure {
    /// What stopped the robot, without the seed: `robot 2 panicked: MESSAGE`.
    pub fn what(&self) -> String {
        let how = if self.panicked { "panicked" } else { "failed" };
        format!("robot {} {how}: {}", self.robot, self.message)
    }

    /// The failure of robot `robot`'s task in the run with `seed`, from how it ended.
    fn from_join(robot: usize, seed: u64, e: tokio::task::JoinError) -> Self {
        let panicked = e.is_panic();
        let message = if panicked {
            let payload = e.into_panic();
            payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".to_string())
        } else {
            "its task was cancelled".to_string()
        };
        RobotFailure {
            robot,
            seed,
            panicked,
            message,
        }
    }
}

impl std::fmt::Display for ArenaError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArenaError::Setup(e) => write!(f, "robot configuration: {e}"),
            ArenaError::Medium(e) => write!(f, "medium: {e}"),
            ArenaError::NoSuchRobot(i) => {
                write!(f, "there is no robot {i} to kill, restart or configure")
            }
            ArenaError::Adversary(e) => write!(f, "adversary: {e}"),
            ArenaError::Runtime(e) => write!(f, "runtime: {e}"),
            ArenaError::Hil(e) => write!(f, "robots in the loop: {e}"),
            ArenaError::Interrupted => f.write_str("interrupted"),
            ArenaError::Robot(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ArenaError {}

/// One LED change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LedChange {
    /// When.
    pub t: Instant,
    /// Which robot.
    pub robot: usize,
    /// What it shows from then on.
    pub color: LedColor,
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Every LED change, in time order.
    pub leds: Vec<LedChange>,
    /// Each robot's LEDs at the end.
    pub final_leds: Vec<LedColor>,
    /// The trace, if asked for.
    pub trace: Vec<TraceEvent>,
    /// The medium's frame counts.
    pub medium: MediumStats,
    /// Each robot's counters (of its last life).
    pub robots: Vec<Stats>,
    /// Each robot's wave counters (of its last life): waves initiated, relayed, initiations
    /// skipped while busy.
    pub waves: Vec<WaveStats>,
    /// Each robot's protocol counters (of its last life): messages scored, rays, negotiation
    /// periods and those in which it initiated fewer waves than cycles.
    pub nodes: Vec<NodeStats>,
    /// Emulated time.
    pub emulated: Duration,
    /// Wall time the run took.
    pub wall: std::time::Duration,
    /// The swarm's moves, with [`ArenaConfig::motion`].
    pub moves: Vec<Move>,
    /// Each robot in the loop's link ([`ArenaConfig::hil`]), by place.
    pub hil: Vec<HilReport>,
}

impl RunReport {
    /// The LEDs of every robot at `t` (the last change at or before `t`).
    pub fn leds_at(&self, t: Instant) -> Vec<LedColor> {
        leds_at(&self.leds, self.robots.len(), t)
    }

    /// The earliest time from which every robot's LEDs showed `expected` without a change
    /// until `until`: the last LED change at or before `until`, if the LEDs then show
    /// `expected`.
    pub fn consensus_since(&self, expected: &[LedColor], until: Instant) -> Option<Instant> {
        if self.leds_at(until) != expected {
            return None;
        }
        let last = self.leds.iter().rev().find(|c| c.t <= until).map(|c| c.t);
        Some(last.unwrap_or(Instant::ZERO))
    }
}

/// The LEDs of `n` robots at `t`: the last of `changes` (in time order) at or before `t` for
/// each robot, off before its first.
pub(crate) fn leds_at(changes: &[LedChange], n: usize, t: Instant) -> Vec<LedColor> {
    let mut out = vec![LedColor::Off; n];
    for c in changes.iter().take_while(|c| c.t <= t) {
        if let Some(o) = out.get_mut(c.robot) {
            *o = c.color;
        }
    }
    out
}

/// What the robots' hardware shares in one run.
struct Shared {
    medium: SharedMedium,
    clock: EmuClock,
    env: Rc<Environment>,
    leds: Rc<LedLog>,
    config: Config,
    configs: Vec<Option<Config>>,
    ids: Option<Vec<u16>>,
    seed: u64,
    /// The swarm's displacement over a plane field.
    offset: Rc<Cell<Vector2<f64>>>,
    /// Robots in the loop, and how long to wait for them.
    hil: Vec<HilRobot>,
    hil_timeouts: HilTimeouts,
    /// Told when a robot in the loop fails: the run ends there.
    failed: Rc<tokio::sync::Notify>,
    /// What the robots in the loop's bridges reported, as they ended.
    hil_reports: RefCell<Vec<HilReport>>,
}

/// Puts a robot's protocol events into the trace.
struct Tracer {
    shared: Rc<Shared>,
    robot: usize,
}

impl Observer for Tracer {
    fn event_at(&mut self, now: Instant, event: &Event, node: &FusedNode) {
        if let Event::Decided {
            period,
            decision,
            votes,
            ..
        } = event
        {
            let k = node.params().sectors;
            let e = TraceEvent::Decided {
                t_ms: now.as_millis(),
                robot: self.robot,
                period: *period,
                decision: decision.map(Sector::index),
                votes: votes.iter().take(usize::from(k)).copied().collect(),
                scores: (0..k)
                    .map(|s| Sector::new(s).and_then(|s| node.weight(s)))
                    .collect(),
                reading: f32::from(node.reading().0),
            };
            self.shared.medium.borrow_mut().log(e);
            return;
        }
        self.event(now, event);
    }

    fn event(&mut self, now: Instant, event: &Event) {
        let t_ms = now.as_millis();
        let robot = self.robot;
        let e = match event {
            Event::State(s) => TraceEvent::State {
                t_ms,
                robot,
                state: match s {
                    WaveState::Inactive => "inactive",
                    WaveState::Active => "active",
                    WaveState::Refractory => "refractory",
                }
                .into(),
            },
            Event::Preference(p) => TraceEvent::Preference {
                t_ms,
                robot,
                preference: match *p {
                    Some(Sector::LEFT) => "left".into(),
                    Some(Sector::RIGHT) => "right".into(),
                    Some(s) => format!("sector {}", s.index()),
                    None => "none".into(),
                },
            },
            Event::Decided { .. } => return,
        };
        self.shared.medium.borrow_mut().log(e);
    }
}

/// A seeded RNG for one purpose of one robot's life: runs are reproducible and independent.
fn rng(seed: u64, purpose: u64, robot: usize, life: u32) -> Pcg32 {
    Pcg32::new(
        seed,
        (purpose << 48) | ((robot as u64) << 16) | u64::from(life),
    )
}

const RNG_MEDIUM: u64 = 1;
const RNG_PROTOCOL: u64 = 2;
const RNG_SENSOR: u64 = 3;
const RNG_ADVERSARY: u64 = 4;

/// One life of one robot: boot, run the unchanged robot program until told to stop. `Err`
/// says why the robot could not boot (`run` checked the configuration, so it should not).
async fn life(
    shared: Rc<Shared>,
    robot: usize,
    life: u32,
    stop: oneshot::Receiver<()>,
) -> Result<Counters, String> {
    if let Some(h) = shared.hil.iter().find(|h| h.robot == robot) {
        let transport = h.transport.clone();
        let out = in_the_loop(shared.clone(), robot, life, transport, stop).await;
        if out.is_err() {
            shared.failed.notify_one();
        }
        return out;
    }
    match shared.config.params.sectors {
        2 => life_of::<2>(shared, robot, life, stop).await,
        3 => life_of::<3>(shared, robot, life, stop).await,
        4 => life_of::<4>(shared, robot, life, stop).await,
        5 => life_of::<5>(shared, robot, life, stop).await,
        6 => life_of::<6>(shared, robot, life, stop).await,
        7 => life_of::<7>(shared, robot, life, stop).await,
        8 => life_of::<8>(shared, robot, life, stop).await,
        s => Err(format!(
            "{s} sectors: the robot program has 2 to 8 receivers"
        )),
    }
}

/// [`life`] of a robot with `N` receivers: the same robot program for every `N`.
async fn life_of<const N: usize>(
    shared: Rc<Shared>,
    robot: usize,
    life: u32,
    stop: oneshot::Receiver<()>,
) -> Result<Counters, String> {
    let (tx, rx) = Medium::attach(&shared.medium, robot).map_err(|e| e.to_string())?;
    // Receivers come indexed by sector (with two: right, left).
    let receivers = <[_; N]>::try_from(rx)
        .map_err(|rx| format!("the medium gave {} receivers for {N} sectors", rx.len()))?;
    let clock = shared.clock;
    let sensor = EmuSensor::new(
        shared.env.clone(),
        robot,
        clock,
        rng(shared.seed, RNG_SENSOR, robot, life),
    )
    .moving_with(shared.offset.clone());
    let leds = EmuLeds::new(shared.leds.clone(), robot);
    let mut hw = Hardware {
        transmitter: tx,
        receivers,
        sensor,
        leds,
        clock,
    };
    let config = Config {
        id: id_of(&shared, robot),
        ..config_of(shared.config, &shared.configs, robot)
    };
    let mut r = Robot::<Pcg32, N>::new(
        config,
        clock.now(),
        rng(shared.seed, RNG_PROTOCOL, robot, life),
    )
    .map_err(|e| format!("robot configuration: {e}"))?;
    let mut tracer = Tracer {
        shared: shared.clone(),
        robot,
    };
    select(r.run_observed(&mut hw, &mut tracer), stop).await;
    Ok((*r.stats(), *r.node().wave_stats(), *r.node().stats()))
}

/// The id robot `robot` has in the run.
fn id_of(shared: &Shared, robot: usize) -> u16 {
    shared
        .ids
        .as_ref()
        .and_then(|ids| ids.get(robot).copied())
        .unwrap_or(robot as u16)
}

/// A robot in the loop's life: its place in the medium, sensor and LEDs bridged over its link
/// ([`Bridge`]). Its counters are the robot's own business: the report has its link's.
async fn in_the_loop(
    shared: Rc<Shared>,
    robot: usize,
    life: u32,
    transport: crate::world::hil::Transport,
    stop: oneshot::Receiver<()>,
) -> Result<Counters, String> {
    let (tx, rx) = Medium::attach(&shared.medium, robot).map_err(|e| e.to_string())?;
    let clock = shared.clock;
    let config = Config {
        id: id_of(&shared, robot),
        ..config_of(shared.config, &shared.configs, robot)
    };
    let seed = rand_core::RngCore::next_u64(&mut rng(shared.seed, RNG_PROTOCOL, robot, life));
    let bridge = Bridge {
        robot,
        transport,
        clock,
        transmitter: Some(tx),
        receivers: rx,
        sensor: EmuSensor::new(
            shared.env.clone(),
            robot,
            clock,
            rng(shared.seed, RNG_SENSOR, robot, life),
        )
        .moving_with(shared.offset.clone()),
        leds: EmuLeds::new(shared.leds.clone(), robot),
        config,
        setup: setup_of(&config, setup_seed(seed)),
        timeouts: shared.hil_timeouts,
    };
    let report = bridge.run(stop).await?;
    shared.hil_reports.borrow_mut().push(report);
    Ok(Default::default())
}

/// What a robot's life leaves: its counters, its wave counters and its protocol counters.
type Counters = (Stats, WaveStats, NodeStats);

/// Checks that the robot program accepts `config` with as many receivers as it has sectors.
fn check_robot(config: Config) -> Result<(), SetupError> {
    fn with<const N: usize>(config: Config) -> Result<(), SetupError> {
        Robot::<Pcg32, N>::new(config, Instant::ZERO, rng(0, 0, 0, 0)).map(|_| ())
    }
    match config.params.sectors {
        2 => with::<2>(config),
        3 => with::<3>(config),
        4 => with::<4>(config),
        5 => with::<5>(config),
        6 => with::<6>(config),
        7 => with::<7>(config),
        _ => with::<8>(config),
    }
}

/// Waits for Ctrl-C (SIGINT), SIGTERM or SIGHUP: a run in real time then ends at once and
/// kills and reaps its QEMU processes (nothing can for SIGKILL). Waits for ever if no signal
/// can be listened for.
async fn stop_signal() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        let (Ok(mut term), Ok(mut hup)) = (
            signal(SignalKind::terminate()),
            signal(SignalKind::hangup()),
        ) else {
            return std::future::pending().await;
        };
        tokio::select! {
            r = tokio::signal::ctrl_c() => if r.is_err() { std::future::pending::<()>().await },
            _ = term.recv() => {}
            _ = hup.recv() => {}
        }
    }
    #[cfg(not(unix))]
    if tokio::signal::ctrl_c().await.is_err() {
        std::future::pending::<()>().await;
    }
}

/// Checks the robots in the loop: places that exist, each taken once, no kills or restarts of
/// them, no swarm key (link version 1 carries none).
fn check_hil(cfg: &ArenaConfig) -> Result<(), ArenaError> {
    let n = cfg.positions.len();
    let mut seen = std::collections::BTreeSet::new();
    for h in &cfg.hil {
        if h.robot >= n {
            return Err(ArenaError::Hil(format!(
                "there is no place {} (robots are 0..{})",
                h.robot,
                n.saturating_sub(1)
            )));
        }
        if !seen.insert(h.robot) {
            return Err(ArenaError::Hil(format!("place {} is taken twice", h.robot)));
        }
        let scheduled = cfg
            .kills
            .iter()
            .chain(&cfg.restarts)
            .any(|&(_, r)| r == h.robot)
            || cfg.dead_at_start.contains(&h.robot);
        if scheduled {
            return Err(ArenaError::Hil(format!(
                "robot {} is in the loop: it cannot be killed or restarted",
                h.robot
            )));
        }
        if cfg.config_of(h.robot).key.is_some() {
            return Err(ArenaError::Hil(
                "link version 1 carries no swarm key: robots in the loop send plain frames".into(),
            ));
        }
    }
    Ok(())
}

/// Moves the swarm every `motion.period` along the heading of the LEDs, for ever.
async fn mover(shared: Rc<Shared>, motion: Motion, moves: Rc<RefCell<Vec<Move>>>) {
    let Some(plane) = shared.env.field.clone() else {
        return;
    };
    let sectors = shared.config.params.sectors;
    let n = plane.positions.len();
    let mut t = Instant::ZERO;
    loop {
        t += motion.period;
        shared.clock.sleep_until(t).await;
        let leds = shared.leds.now(n);
        let (heading, consensus) = swarm_heading(&leds, sectors);
        let offset = shared.offset.get();
        let centre = plane.centre(offset);
        moves.borrow_mut().push(Move {
            t,
            centre,
            heading,
            consensus,
        });
        shared.medium.borrow_mut().log(TraceEvent::Moved {
            t_ms: t.as_millis(),
            centre: [centre.x, centre.y],
            heading,
            step: if heading.is_some() { motion.step } else { 0.0 },
            consensus,
        });
        if let Some(h) = heading {
            shared
                .offset
                .set(offset + Vector2::new(h.cos(), h.sin()) * motion.step);
        }
    }
}

enum Control {
    Kill(usize),
    Restart(usize),
    Pattern(String),
}

/// Runs one emulated experiment to its end, on a fresh current-thread runtime with a paused
/// clock.
///
/// # Errors
/// An [`ArenaError`] if the configuration is unusable; nothing is run then. If a robot's task
/// panics (or a robot cannot boot), the run goes on to its end and then fails with
/// [`ArenaError::Robot`], naming the first such robot, the panic's message and the seed.
pub fn run(cfg: &ArenaConfig) -> Result<RunReport, ArenaError> {
    let n = cfg.positions.len();
    check_robot(cfg.robot).map_err(ArenaError::Setup)?;
    if cfg.configs.len() > n {
        return Err(ArenaError::NoSuchRobot(cfg.configs.len() - 1));
    }
    for own in cfg.configs.iter().flatten() {
        let sectors = cfg.robot.params.sectors;
        if own.params.sectors != sectors {
            // The medium gives every robot `sectors` receivers.
            return Err(ArenaError::Setup(SetupError::Receivers {
                sectors: own.params.sectors,
                receivers: usize::from(sectors),
            }));
        }
        check_robot(*own).map_err(ArenaError::Setup)?;
    }
    cfg.medium.validate().map_err(ArenaError::Medium)?;
    check_hil(cfg)?;
    for a in &cfg.adversaries {
        a.validate().map_err(ArenaError::Adversary)?;
    }
    let mut controls: Vec<(Instant, Control)> = Vec::new();
    for &(t, r) in &cfg.kills {
        controls.push((t, Control::Kill(r)));
    }
    for &(t, r) in &cfg.restarts {
        controls.push((t, Control::Restart(r)));
    }
    let named = cfg.kills.iter().chain(&cfg.restarts).map(|&(_, r)| r);
    if let Some(r) = named
        .chain(cfg.dead_at_start.iter().copied())
        .find(|&r| r >= n)
    {
        return Err(ArenaError::NoSuchRobot(r));
    }
    for (t, p) in cfg.env.schedule.iter().skip(1) {
        let lights = p.iter().map(|&b| if b { '1' } else { '0' }).collect();
        controls.push((*t, Control::Pattern(lights)));
    }
    // Stable: simultaneous controls keep their listed order.
    controls.sort_by_key(|(t, _)| *t);

    // Virtual time, unless a robot in the loop has a clock of its own: then real time, with
    // I/O (its link) and signals (Ctrl-C stops the run and its QEMU processes).
    let real_time = cfg.real_time();
    let runtime = if real_time {
        tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
    } else {
        tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .start_paused(true)
            .build()
    }
    .map_err(|e| ArenaError::Runtime(e.to_string()))?;
    let wall = std::time::Instant::now();
    let local = tokio::task::LocalSet::new();
    let report = local.block_on(&runtime, async {
        let clock = EmuClock::new(tokio::time::Instant::now());
        let medium = Medium::new(
            cfg.medium,
            clock,
            rng(cfg.seed, RNG_MEDIUM, 0, 0),
            &cfg.positions,
            cfg.robot.params.sectors,
            cfg.trace,
        );
        for (k, a) in cfg.adversaries.iter().enumerate() {
            adversary::spawn(&medium, clock, a, rng(cfg.seed, RNG_ADVERSARY, k, 0));
        }
        let shared = Rc::new(Shared {
            medium: medium.clone(),
            clock,
            env: Rc::new(cfg.env.clone()),
            leds: Rc::new(LedLog::new(clock, medium.clone())),
            config: cfg.robot,
            configs: cfg.configs.clone(),
            ids: cfg.ids.clone(),
            seed: cfg.seed,
            offset: Rc::new(Cell::new(
                cfg.env.field.as_ref().map_or(Vector2::zeros(), |f| f.start),
            )),
            hil: cfg.hil.clone(),
            hil_timeouts: cfg.hil_timeouts,
            failed: Rc::new(tokio::sync::Notify::new()),
            hil_reports: RefCell::new(Vec::new()),
        });
        let moves = Rc::new(RefCell::new(Vec::new()));
        if let Some(motion) = cfg.motion {
            tokio::task::spawn_local(mover(shared.clone(), motion, moves.clone()));
        }
        let mut lives: Vec<u32> = vec![0; n];
        let mut stops: Vec<Option<oneshot::Sender<()>>> = (0..n).map(|_| None).collect();
        let mut handles: Vec<Option<tokio::task::JoinHandle<Result<Counters, String>>>> =
            (0..n).map(|_| None).collect();
        let mut stats = vec![(Stats::default(), WaveStats::default(), NodeStats::default()); n];
        // The first robot that stopped on its own (a panic, or no boot), if any: the run goes
        // on to its end (so that it stays the same run) and then fails.
        let mut failure: Option<RobotFailure> = None;
        // Waits for robot `r`'s task to end (it was told to stop) and keeps its counters.
        let ended = async |r: usize,
                           h: tokio::task::JoinHandle<Result<Counters, String>>,
                           stats: &mut Vec<Counters>,
                           failure: &mut Option<RobotFailure>| {
            let f = match h.await {
                Ok(Ok(s)) => {
                    stats[r] = s;
                    return;
                }
                Ok(Err(message)) => RobotFailure {
                    robot: r,
                    seed: cfg.seed,
                    panicked: false,
                    message,
                },
                Err(e) => RobotFailure::from_join(r, cfg.seed, e),
            };
            failure.get_or_insert(f);
        };
        let spawn = |robot: usize, lives: &mut Vec<u32>| {
            let (tx, rx) = oneshot::channel();
            let h = tokio::task::spawn_local(life(shared.clone(), robot, lives[robot], rx));
            lives[robot] += 1;
            (tx, h)
        };
        for robot in 0..n {
            if !cfg.dead_at_start.contains(&robot) {
                let (tx, h) = spawn(robot, &mut lives);
                stops[robot] = Some(tx);
                handles[robot] = Some(h);
            }
        }
        let end = cfg.duration;
        let mut interrupted = false;
        let schedule = async {
            for (t, c) in controls {
                if t > Instant::ZERO + end {
                    break;
                }
                clock.sleep_until(t).await;
                match c {
                    Control::Kill(r) => {
                        if let Some(s) = stops[r].take() {
                            let _ = s.send(());
                        }
                        if let Some(h) = handles[r].take() {
                            ended(r, h, &mut stats, &mut failure).await;
                        }
                        medium.borrow_mut().detach(r);
                        medium.borrow_mut().log(TraceEvent::Killed {
                            t_ms: t.as_millis(),
                            robot: r,
                        });
                        shared.leds.record(r, LedColor::Off);
                    }
                    Control::Restart(r) => {
                        if stops[r].is_none() {
                            medium.borrow_mut().log(TraceEvent::Restarted {
                                t_ms: t.as_millis(),
                                robot: r,
                            });
                            let (tx, h) = spawn(r, &mut lives);
                            stops[r] = Some(tx);
                            handles[r] = Some(h);
                        }
                    }
                    Control::Pattern(lights) => {
                        medium.borrow_mut().log(TraceEvent::Pattern {
                            t_ms: t.as_millis(),
                            lights,
                        });
                    }
                }
            }
            clock.sleep_until(Instant::ZERO + end).await;
        };
        // A robot in the loop that fails ends the run (its failure is the run's result), and
        // so does Ctrl-C in real time.
        let failed = shared.failed.clone();
        let interrupt = async {
            if real_time {
                stop_signal().await;
            } else {
                std::future::pending::<()>().await;
            }
        };
        if let Either::Second(Either::Second(())) =
            select(schedule, select(failed.notified(), interrupt)).await
        {
            interrupted = true;
        }
        for r in 0..n {
            if let Some(s) = stops[r].take() {
                let _ = s.send(());
            }
            if let Some(h) = handles[r].take() {
                ended(r, h, &mut stats, &mut failure).await;
            }
        }
        if interrupted {
            return Err(None);
        }
        if let Some(f) = failure {
            return Err(Some(f));
        }
        let leds = shared.leds.changes();
        let moves = moves.borrow().clone();
        let mut m = medium.borrow_mut();
        Ok(RunReport {
            moves,
            final_leds: Vec::new(),
            leds,
            trace: m.take_trace(),
            medium: m.stats(),
            robots: stats.iter().map(|c| c.0).collect(),
            waves: stats.iter().map(|c| c.1).collect(),
            nodes: stats.iter().map(|c| c.2).collect(),
            emulated: end,
            wall: std::time::Duration::ZERO,
            hil: {
                let mut h = shared.hil_reports.borrow().clone();
                h.sort_by_key(|r| r.robot);
                h
            },
        })
    });
    let mut report = report.map_err(|f| f.map_or(ArenaError::Interrupted, ArenaError::Robot))?;
    report.wall = wall.elapsed();
    report.final_leds = report.leds_at(Instant::ZERO + report.emulated);
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::leds::fault::with_faulty_leds;

    /// The paper's lab run of pattern 1000 (2101 s: three negotiation periods of 70 s cycles).
    fn lab(seed: u64) -> ArenaConfig {
        let pattern = vec![true, false, false, false];
        ArenaConfig::line(pattern, 1.0, Duration::from_secs(2101), seed)
    }

    #[test]
    fn a_robot_that_panics_fails_the_run_with_its_index_message_and_seed() {
        let cfg = lab(7);
        let ok = run(&cfg).expect("the run without the fault");
        assert!(ok.leds.iter().any(|c| c.robot == 2), "robot 2 decides");
        let e = with_faulty_leds(2, || run(&cfg)).expect_err("robot 2 panicked");
        let ArenaError::Robot(f) = &e else {
            panic!("not a robot failure: {e}");
        };
        assert_eq!(f.robot, 2);
        assert_eq!(f.seed, 7);
        assert!(f.panicked);
        assert_eq!(f.message, "injected fault: robot 2's LED driver");
        assert_eq!(
            e.to_string(),
            "robot 2 panicked (seed 7): injected fault: robot 2's LED driver"
        );
        assert_eq!(
            f.what(),
            "robot 2 panicked: injected fault: robot 2's LED driver"
        );
        // The lab's verdict does not turn it into a run with LEDs.
        let e = with_faulty_leds(2, || crate::judge::judge(&cfg)).expect_err("judged");
        assert!(matches!(
            e,
            ArenaError::Robot(RobotFailure { robot: 2, .. })
        ));
    }

    #[test]
    fn a_robot_that_panicked_and_is_then_killed_still_fails_the_run() {
        // Robot 1 panics at its first decision (before 800 s) and is killed at 1500 s: its
        // task is awaited at the kill, not at the end.
        let mut cfg = lab(3);
        cfg.kills = vec![(Instant::from_secs(1500), 1)];
        let ok = run(&cfg).expect("the run without the fault");
        let first = ok.leds.iter().find(|c| c.robot == 1).map(|c| c.t);
        assert!(
            first.is_some_and(|t| t < Instant::from_secs(1500)),
            "{first:?}"
        );
        let e = with_faulty_leds(1, || run(&cfg)).expect_err("robot 1 panicked");
        assert!(
            matches!(&e, ArenaError::Robot(f) if f.robot == 1 && f.seed == 3 && f.panicked),
            "{e}"
        );
    }

    #[test]
    fn robots_with_their_own_configs_share_one_world() {
        // Robot 0 has a swarm key, robot 1 none: each drops the other's frames, the keyed one
        // as bad MACs, the plain one as bad CRCs, and each puts its own frames on air.
        let key = protocol::SwarmKey::new(*b"sixteen byte key");
        let mut cfg = ArenaConfig::line(vec![true, false], 1.0, Duration::from_secs(700), 5);
        cfg.medium.collisions = false;
        cfg.trace = true;
        let keyed = Config {
            key: Some(key),
            ..cfg.robot
        };
        let cfg = cfg.with_config(0, keyed);
        assert_eq!(cfg.configs, vec![Some(keyed)]);
        assert_eq!(cfg.config_of(0).key, Some(key));
        assert_eq!(cfg.config_of(1).key, None, "the shared configuration");
        let r = run(&cfg).unwrap();
        let (k, p) = (&r.robots[0], &r.robots[1]);
        assert!(k.transmitted > 5 && p.transmitted > 5, "{:?}", r.robots);
        assert_eq!((k.messages, p.messages), (0, 0), "{:?}", r.robots);
        assert_eq!(k.bad_mac, k.frame_errors, "{:?}", r.robots);
        assert!(k.bad_mac > 5, "{:?}", r.robots);
        assert_eq!(p.bad_mac, 0, "a plain robot checks CRCs");
        assert!(p.frame_errors > 5, "{:?}", r.robots);
        // Initiations: 21 bytes keyed, 19 plain.
        let sent = |robot: usize| -> Vec<usize> {
            r.trace
                .iter()
                .filter_map(|e| match e {
                    TraceEvent::Sent { robot: r, len, .. } if *r == robot => Some(*len),
                    _ => None,
                })
                .collect()
        };
        assert!(
            sent(0).contains(&21) && !sent(0).contains(&19),
            "{:?}",
            sent(0)
        );
        assert!(
            sent(1).contains(&19) && !sent(1).contains(&21),
            "{:?}",
            sent(1)
        );

        // The same two robots with one key hear each other.
        let both = cfg.clone().with_config(1, keyed);
        let r = run(&both).unwrap();
        assert!(r.robots.iter().all(|s| s.messages > 5 && s.bad_mac == 0));

        // Different ids through `ids`, one configuration each: the run goes as well.
        let mut ids = cfg.clone();
        ids.ids = Some(vec![7, 9]);
        assert!(run(&ids).is_ok());

        // Every robot keeps the medium's receivers; a configuration for a robot that does not
        // exist is refused.
        let mut six = keyed;
        six.params.sectors = 6;
        let e = run(&cfg.clone().with_config(1, six)).unwrap_err();
        assert_eq!(
            e,
            ArenaError::Setup(SetupError::Receivers {
                sectors: 6,
                receivers: 2
            })
        );
        let e = run(&cfg.clone().with_config(2, keyed)).unwrap_err();
        assert_eq!(e, ArenaError::NoSuchRobot(2));
    }
}
