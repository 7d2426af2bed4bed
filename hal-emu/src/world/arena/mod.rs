//! A whole emulated run, the world's orchestrator: it builds the medium, the environment and
//! the adversaries from an [`ArenaConfig`], boots each robot on its board ([`crate::board`])
//! running the unchanged robot program, carries out scheduled kills and restarts, moves the
//! swarm over a plane field, and reports the LED changes a camera would have seen.
//!
//! Its line of robots ([`ArenaConfig::line`]) is one of three in the workspace, the deepest:
//! the same robot program as `firmware::wired::run_line` (wired in memory, no airtime, what the
//! QEMU board runs), here through the modelled medium; `protocol::line` drives the protocol core
//! alone. Each tests what the others leave out (see `protocol::line`).
//!
//! Where to read on: [`run`] checks the configuration, then plays the run in steps (the world,
//! the robots, the schedule, the report). Its parts:
//!
//! - `config.rs`: what defines a run ([`ArenaConfig`]);
//! - `lives.rs`: one life of one robot: its board (light from the medium, sensor, LEDs) and
//!   the robot program on it, or a robot in the loop's bridge; its seeded RNGs; its trace;
//! - `schedule.rs`: kills, restarts and pattern changes in time order, carried out on the
//!   robots' lives;
//! - `motion.rs`: the swarm's moves over a plane field ([`Motion`], [`swarm_heading`]);
//! - `camera.rs`: the LED record ([`LedChange`]), the board's camera;
//! - `report.rs` and `error.rs`: what a run gives ([`RunReport`]) or why it has no result
//!   ([`ArenaError`], [`RobotFailure`]).

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration as StdDuration;

use embassy_futures::select::{Either, select};
use firmware::SetupError;
use protocol::{Duration, Instant};

use crate::board::clock::EmuClock;
use crate::board::timeline::{self, Timeline};
use crate::world::adversary;
use crate::world::env::SwarmEnv;
use crate::world::hil::{Boot, Follower, HilError, Lockstep, Transport};
use crate::world::medium::Medium;

mod camera;
mod config;
mod error;
mod lives;
mod motion;
mod report;
mod schedule;

pub use camera::LedChange;
pub use config::ArenaConfig;
pub use error::{ArenaError, RobotFailure};
pub use motion::{Motion, Move, swarm_heading};
pub use report::RunReport;

use lives::{RNG_ADVERSARY, RNG_MEDIUM, Shared, check_robot, rng};
use schedule::{Control, Robots, controls};

/// Runs one emulated experiment to its end, in virtual time on the calling thread (with
/// robots in the loop, on a fresh current-thread tokio runtime).
///
/// # Errors
/// An [`ArenaError`] if the configuration is unusable; nothing is run then. If a robot's task
/// panics (or a robot cannot boot), the run goes on to its end and then fails with
/// [`ArenaError::Robot`], naming the first such robot, the panic's message and the seed.
pub fn run(cfg: &ArenaConfig) -> Result<RunReport, ArenaError> {
    check(cfg)?;
    let controls = controls(cfg);
    let wall = std::time::Instant::now();
    let report = if cfg.hil.is_empty() {
        // Virtual time on the run's own executor (`board::exec`): tokio's order of events
        // without its runtime, which cost a sixth of a 1000-robot run.
        let (clock, timeline) = EmuClock::virtual_run();
        timeline.block_on(play(
            cfg,
            controls,
            Time::Own(clock, timeline.clone()),
            None,
        ))
    } else if cfg.lockstep() {
        // QEMU robots on the arena's clock: booted and greeted first, then the run on the own
        // executor, time waiting for them (`world::hil::lockstep`).
        let patience = StdDuration::from_millis(cfg.hil_timeouts.silence.as_millis());
        let lockstep = Rc::new(boot_followers(cfg, patience)?);
        let (clock, timeline) = EmuClock::virtual_run();
        timeline.set_gate(lockstep.clone());
        let time = Time::Own(clock, timeline.clone());
        let out = timeline.block_on(play(cfg, controls, time, Some(lockstep)));
        // The gate holds the followers (and what holds the timeline): gone with the run, and
        // their QEMU processes with them.
        drop(timeline.take_gate());
        out
    } else {
        // Robots in the loop: their links are tokio's. Virtual time on its paused clock,
        // unless a robot in the loop has a clock of its own: then real time, with I/O (its
        // link) and signals (Ctrl-C stops the run and its QEMU processes).
        let real_time = cfg.real_time();
        let runtime = runtime(real_time)?;
        let local = tokio::task::LocalSet::new();
        let time = if real_time { Time::Real } else { Time::Paused };
        local.block_on(&runtime, play(cfg, controls, time, None))
    };
    let mut report = report.map_err(|f| f.map_or(ArenaError::Interrupted, ArenaError::Robot))?;
    report.wall = wall.elapsed();
    report.final_leds = report.leds_at(Instant::ZERO + report.emulated);
    Ok(report)
}

/// What moves a run's time.
enum Time {
    /// The run's own executor and its timeline ([`EmuClock::virtual_run`]).
    Own(EmuClock, Rc<Timeline>),
    /// A timeline driven by tokio's paused clock.
    Paused,
    /// tokio's clock in real time.
    Real,
}

/// Checks that `cfg` can run: the robots' configurations, the medium, the robots in the
/// loop, the adversaries, and that every robot it names exists.
fn check(cfg: &ArenaConfig) -> Result<(), ArenaError> {
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
    let named = cfg.kills.iter().chain(&cfg.restarts).map(|&(_, r)| r);
    if let Some(r) = named
        .chain(cfg.dead_at_start.iter().copied())
        .find(|&r| r >= n)
    {
        return Err(ArenaError::NoSuchRobot(r));
    }
    Ok(())
}

/// Checks the robots in the loop: places that exist, each taken once, no kills or restarts of
/// robots on their own clocks, and a swarm key only for robots on the arena's clock (link
/// version 3 gives it to them alone).
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
        let restarts = cfg.restarts.iter().any(|&(_, r)| r == h.robot);
        let scheduled = restarts
            || cfg.kills.iter().any(|&(_, r)| r == h.robot)
            || cfg.dead_at_start.contains(&h.robot);
        // On the arena's clock, a kill ends its link (and its QEMU process), a restart boots
        // it afresh; a board on its own clock, or one behind a socket, cannot be rebooted.
        let bootable = h.follows() && !matches!(h.transport, Transport::Tcp(_));
        if scheduled && !(bootable || h.follows() && !restarts) {
            return Err(ArenaError::Hil(format!(
                "robot {} is in the loop over {}: it cannot be {} (only robots on the \
                 arena's clock can, and only QEMU robots and host twins restarted)",
                h.robot,
                h.transport,
                if restarts { "restarted" } else { "killed" }
            )));
        }
        if cfg.lockstep() && !h.follows() {
            return Err(ArenaError::Hil(format!(
                "robot {} ({}) runs on its own or a shared clock, and QEMU robots on the \
                 arena's clock cannot share a run with it (use --hil-clock wall for all)",
                h.robot, h.transport
            )));
        }
        if cfg.config_of(h.robot).key.is_some() && !h.follows() {
            return Err(ArenaError::Hil(format!(
                "robot {} ({}) runs on its own clock: link version 3 gives the swarm key only \
                 to robots on the arena's clock",
                h.robot, h.transport
            )));
        }
    }
    Ok(())
}

/// A fresh current-thread runtime: in virtual time (paused clock), or in real time with I/O
/// and signals.
fn runtime(real_time: bool) -> Result<tokio::runtime::Runtime, ArenaError> {
    if real_time {
        tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
    } else {
        tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .start_paused(true)
            .build()
    }
    .map_err(|e| ArenaError::Runtime(e.to_string()))
}

/// The run on the runtime: builds the world, boots the robots, carries out the schedule to
/// the end (or to a robot in the loop's failure, or an interruption), stops every robot and
/// reports. `Err(None)`: interrupted; `Err(Some(_))`: a robot stopped on its own.
async fn play(
    cfg: &ArenaConfig,
    controls: Vec<(Instant, Control)>,
    time: Time,
    lockstep: Option<Rc<Lockstep>>,
) -> Result<RunReport, Option<RobotFailure>> {
    let n = cfg.positions.len();
    let real_time = matches!(time, Time::Real);
    let shared = world(cfg, time, lockstep);
    let moves = Rc::new(RefCell::new(Vec::new()));
    if let Some(motion) = cfg.motion {
        shared
            .clock
            .spawn(motion::mover(shared.clone(), motion, moves.clone()));
    }
    let mut robots = Robots::new(shared.clone(), n);
    for robot in 0..n {
        if !cfg.dead_at_start.contains(&robot) {
            robots.boot(robot);
        }
    }
    // A robot in the loop that fails ends the run (its failure is the run's result), and
    // so does Ctrl-C in real time.
    let end = Instant::ZERO + cfg.duration;
    let failed = shared.failed.clone();
    let interrupt = async {
        if real_time {
            stop_signal().await;
        } else {
            std::future::pending::<()>().await;
        }
    };
    let interrupted = matches!(
        select(
            robots.follow(controls, end),
            select(failed.notified(), interrupt)
        )
        .await,
        Either::Second(Either::Second(()))
    );
    robots.stop_all().await;
    if interrupted {
        return Err(None);
    }
    if let Some(f) = robots.failure {
        return Err(Some(f));
    }
    Ok(report(
        &shared,
        &robots,
        moves.borrow().clone(),
        cfg.duration,
    ))
}

/// The world of a run: the medium with the robots' places and the adversaries (their tasks
/// spawned), the environment, the LED record, and what the robots' boots need.
fn world(cfg: &ArenaConfig, time: Time, lockstep: Option<Rc<Lockstep>>) -> Rc<Shared> {
    let clock = match time {
        Time::Own(clock, timeline) => {
            clock.spawn(timeline::drive_virtual(timeline));
            clock
        }
        Time::Paused => {
            let (clock, driver) = EmuClock::on_timeline();
            tokio::task::spawn_local(driver);
            clock
        }
        Time::Real => EmuClock::new(tokio::time::Instant::now()),
    };
    if let Some(l) = &lockstep {
        // Host twins of QEMU robots: the image's own configuration (its id is the setup's).
        let base = firmware::Config {
            id: 0,
            ..firmware::Config::robots()
        };
        for h in cfg.hil.iter().filter(|h| h.follows()) {
            if h.transport == Transport::InProcess {
                l.add_twin(h.robot, &clock, base, cfg.dead_at_start.contains(&h.robot));
            }
        }
    }
    let medium = Medium::new(
        cfg.medium,
        clock.clone(),
        rng(cfg.seed, RNG_MEDIUM, 0, 0),
        &cfg.positions,
        cfg.robot.params.sectors,
        cfg.trace,
    );
    for (k, a) in cfg.adversaries.iter().enumerate() {
        adversary::spawn(
            &medium,
            clock.clone(),
            a,
            rng(cfg.seed, RNG_ADVERSARY, k, 0),
        );
    }
    Rc::new(Shared {
        medium: medium.clone(),
        clock: clock.clone(),
        surroundings: Rc::new(SwarmEnv::new(Rc::new(cfg.env.clone()))),
        leds: Rc::new(camera::LedLog::new(clock, medium.clone())),
        config: cfg.robot,
        configs: cfg.configs.clone(),
        ids: cfg.ids.clone(),
        seed: cfg.seed,
        hil: cfg.hil.clone(),
        hil_timeouts: cfg.hil_timeouts,
        failed: Rc::new(tokio::sync::Notify::new()),
        hil_reports: RefCell::new(Vec::new()),
        lockstep,
    })
}

/// The lockstep of `cfg`'s robots on the arena's clock, each given `patience` to answer: its
/// QEMU robots booted and those on sockets connected, all at once, and each greeted
/// ([`Follower::boot`], [`Follower::connect`]); robots dead from the start boot at their first
/// restart. Host twins are added when the run starts (they need its executor).
fn boot_followers(cfg: &ArenaConfig, patience: StdDuration) -> Result<Lockstep, ArenaError> {
    let hello = StdDuration::from_millis(cfg.hil_timeouts.hello.as_millis());
    let sectors = cfg.robot.params.sectors;
    /// A follower's place, transport, how it boots again, and its boot (none if dead now).
    type Booted = (usize, String, Boot, Option<Result<Follower, HilError>>);
    let booted: Vec<Booted> = std::thread::scope(|scope| {
        let boots: Vec<_> = cfg
            .hil
            .iter()
            .filter(|h| h.follows() && h.transport != Transport::InProcess)
            .map(|h| {
                let dead = cfg.dead_at_start.contains(&h.robot);
                let boot = move || match &h.transport {
                    Transport::Qemu(image) => Follower::boot(image, sectors, hello),
                    Transport::Tcp(addr) => Follower::connect(addr, sectors, hello),
                    t => Err(HilError::CannotFollow {
                        transport: t.to_string(),
                    }),
                };
                (h.robot, &h.transport, (!dead).then(|| scope.spawn(boot)))
            })
            .collect();
        boots
            .into_iter()
            .map(|(robot, t, b)| {
                let out = b.map(|b| b.join().unwrap_or_else(|_| Err(HilError::BootPanicked)));
                let again = match t {
                    Transport::Qemu(image) => Boot::Qemu {
                        image: image.clone(),
                        sectors,
                        hello,
                    },
                    _ => Boot::Socket,
                };
                (robot, t.to_string(), again, out)
            })
            .collect()
    });
    let lockstep = Lockstep::new(patience);
    for (robot, t, again, f) in booted {
        // The others are dropped (killed) on an error.
        let f = f
            .transpose()
            .map_err(|e| ArenaError::Hil(format!("robot {robot} ({t}): {e}")))?;
        lockstep.add(robot, f, again);
    }
    Ok(lockstep)
}

/// The report of a run that ended well, `emulated` long (its wall time and final LEDs are
/// filled in by [`run`]).
fn report(shared: &Shared, robots: &Robots, moves: Vec<Move>, emulated: Duration) -> RunReport {
    let leds = shared.leds.changes();
    let mut m = shared.medium.borrow_mut();
    RunReport {
        moves,
        final_leds: Vec::new(),
        leds,
        trace: m.take_trace(),
        medium: m.stats(),
        robots: robots.stats.iter().map(|c| c.0).collect(),
        waves: robots.stats.iter().map(|c| c.1).collect(),
        nodes: robots.stats.iter().map(|c| c.2).collect(),
        emulated,
        wall: std::time::Duration::ZERO,
        hil: {
            let mut h = shared.hil_reports.borrow().clone();
            h.sort_by_key(|r| r.robot);
            h
        },
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::leds::fault::with_faulty_leds;
    use crate::world::medium::TraceEvent;
    use firmware::Config;

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
