//! A robot's lives in a run: each boots the robot on its board in the world ([`life`]) and runs
//! the unchanged robot program until told to stop, or bridges a robot in the loop into the
//! world; its protocol events go into the trace ([`Tracer`]). Every life draws from RNGs seeded
//! from the run's seed, its robot and its number ([`rng`]).

use std::cell::{Cell, RefCell};
use std::rc::Rc;
use std::task::{Poll, Waker};

use embassy_futures::select::{Either, select};
use firmware::{Clock, Config, Hardware, Observer, Robot, SetupError, Stats};
use protocol::fused::NodeStats;
use protocol::fused::Rule;
use protocol::wave::WaveStats;
use protocol::{Event, FusedNode, Instant, Sector, Variance, WaveState};
use rand_pcg::Pcg32;

use super::camera::LedLog;
use super::error::LifeError;
use crate::board::clock::EmuClock;
use crate::board::leds::EmuLeds;
use crate::board::sensor::EmuSensor;
use crate::world::env::SwarmEnv;
use crate::world::hil::{
    Bridge, HilReport, HilRobot, HilTimeouts, Lockstep, Transport, serve_lockstep, setup_of,
    setup_seed,
};
use crate::world::medium::{Medium, SharedMedium, TraceEvent};

/// What the robots' hardware shares in one run: the world their boards live in, and what each
/// robot's boot needs of the run's configuration.
pub(super) struct Shared {
    pub(super) medium: SharedMedium,
    pub(super) clock: EmuClock,
    /// The environment, and where the swarm is over a plane field.
    pub(super) surroundings: Rc<SwarmEnv>,
    pub(super) leds: Rc<LedLog>,
    pub(super) config: Config,
    pub(super) configs: Vec<Option<Config>>,
    pub(super) ids: Option<Vec<u16>>,
    pub(super) seed: u64,
    /// Robots in the loop, and how long to wait for them.
    pub(super) hil: Vec<HilRobot>,
    pub(super) hil_timeouts: HilTimeouts,
    /// Told when a robot in the loop fails: the run ends there.
    pub(super) failed: Rc<tokio::sync::Notify>,
    /// What the robots in the loop's bridges reported, as they ended.
    pub(super) hil_reports: RefCell<Vec<HilReport>>,
    /// The robots in the loop on the arena's clock, if any.
    pub(super) lockstep: Option<Rc<Lockstep>>,
}

/// Puts a robot's protocol events into the trace.
struct Tracer {
    shared: Rc<Shared>,
    robot: usize,
}

impl Observer for Tracer {
    fn event_at<Rl: Rule>(&mut self, now: Instant, event: &Event, node: &FusedNode<Variance, Rl>) {
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

/// Tells a robot's life to stop: a flag and the life's waker. The life polls it on every wake
/// of the robot, so it is a look at a cell (a oneshot channel cost a tenth of a 1000-robot run).
#[derive(Debug, Default)]
pub(super) struct Stop {
    stopped: Cell<bool>,
    waker: RefCell<Option<Waker>>,
}

impl Stop {
    /// Stops the life (now or when it is next polled).
    pub(super) fn signal(&self) {
        self.stopped.set(true);
        if let Some(w) = self.waker.borrow_mut().take() {
            w.wake();
        }
    }

    /// Returns once [`signal`](Self::signal)led.
    async fn wait(&self) {
        std::future::poll_fn(|cx| {
            if self.stopped.get() {
                return Poll::Ready(());
            }
            let mut slot = self.waker.borrow_mut();
            match &*slot {
                Some(w) if w.will_wake(cx.waker()) => {}
                _ => *slot = Some(cx.waker().clone()),
            }
            Poll::Pending
        })
        .await;
    }
}

/// A seeded RNG for one purpose of one robot's life: runs are reproducible and independent.
pub(super) fn rng(seed: u64, purpose: u64, robot: usize, life: u32) -> Pcg32 {
    Pcg32::new(
        seed,
        (purpose << 48) | ((robot as u64) << 16) | u64::from(life),
    )
}

pub(super) const RNG_MEDIUM: u64 = 1;
const RNG_PROTOCOL: u64 = 2;
const RNG_SENSOR: u64 = 3;
pub(super) const RNG_ADVERSARY: u64 = 4;

/// One life of one robot: boot, run the unchanged robot program until told to stop. `Err`
/// says why the robot could not boot ([`run`](super::run) checked the configuration, so it
/// should not).
pub(super) async fn life(
    shared: Rc<Shared>,
    robot: usize,
    life: u32,
    stop: Rc<Stop>,
) -> Result<Counters, LifeError> {
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
        s => Err(LifeError::Sectors(s)),
    }
}

/// [`life`] of a robot with `N` receivers: the same robot program for every `N`.
async fn life_of<const N: usize>(
    shared: Rc<Shared>,
    robot: usize,
    life: u32,
    stop: Rc<Stop>,
) -> Result<Counters, LifeError> {
    let (tx, rx) = Medium::attach(&shared.medium, robot)?;
    // Receivers come indexed by sector (with two: right, left).
    if rx.sectors() != N {
        return Err(LifeError::Receivers {
            got: rx.sectors(),
            want: N,
        });
    }
    let clock = shared.clock.clone();
    let sensor = EmuSensor::new(
        shared.surroundings.clone(),
        robot,
        clock.clone(),
        rng(shared.seed, RNG_SENSOR, robot, life),
    );
    let leds = EmuLeds::new(shared.leds.clone(), robot);
    let mut hw = Hardware {
        transmitter: tx,
        receivers: rx,
        sensor,
        leds,
        clock: clock.clone(),
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
    .map_err(LifeError::Setup)?;
    let mut tracer = Tracer {
        shared: shared.clone(),
        robot,
    };
    select(r.run_observed(&mut hw, &mut tracer), stop.wait()).await;
    Ok((*r.stats(), *r.node().wave_stats(), *r.node().stats()))
}

/// Robot `robot`'s configuration: `configs[robot]` if given, else `shared`.
pub(super) fn config_of(shared: Config, configs: &[Option<Config>], robot: usize) -> Config {
    configs.get(robot).copied().flatten().unwrap_or(shared)
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
    transport: Transport,
    stop: Rc<Stop>,
) -> Result<Counters, LifeError> {
    let (tx, rx) = Medium::attach(&shared.medium, robot)?;
    let clock = shared.clock.clone();
    let config = Config {
        id: id_of(&shared, robot),
        ..config_of(shared.config, &shared.configs, robot)
    };
    let seed = rand_core::RngCore::next_u64(&mut rng(shared.seed, RNG_PROTOCOL, robot, life));
    let bridge = Bridge {
        robot,
        transport,
        clock: clock.clone(),
        transmitter: Some(tx),
        receivers: Some(rx),
        sensor: EmuSensor::new(
            shared.surroundings.clone(),
            robot,
            clock,
            rng(shared.seed, RNG_SENSOR, robot, life),
        ),
        leds: EmuLeds::new(shared.leds.clone(), robot),
        config,
        setup: setup_of(&config, setup_seed(seed)),
        timeouts: shared.hil_timeouts,
    };
    // The bridge takes its stop as a oneshot (it selects on it among its link's inputs).
    let (stop_tx, stop_rx) = tokio::sync::oneshot::channel();
    let relay = async {
        stop.wait().await;
        let _ = stop_tx.send(());
        std::future::pending::<()>().await;
    };
    let run = async {
        match shared.lockstep.clone().filter(|l| l.has(robot)) {
            Some(l) => serve_lockstep(bridge, l, stop_rx).await,
            None => bridge.run(stop_rx).await,
        }
    };
    let report = match select(run, relay).await {
        Either::First(r) => r?,
        Either::Second(()) => return Err(LifeError::BridgeOutlived),
    };
    shared.hil_reports.borrow_mut().push(report);
    Ok(Default::default())
}

/// What a robot's life leaves: its counters, its wave counters and its protocol counters.
pub(super) type Counters = (Stats, WaveStats, NodeStats);

/// Checks that the robot program accepts `config` with as many receivers as it has sectors.
pub(super) fn check_robot(config: Config) -> Result<(), SetupError> {
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
