//! What defines a run: [`ArenaConfig`].

use firmware::Config;
use nalgebra::Point2;
use protocol::{Duration, Instant};

use super::lives;
use super::motion::Motion;
use crate::world::adversary::Adversary;
use crate::world::env::Environment;
use crate::world::hil::{HilRobot, HilTimeouts};
use crate::world::medium::MediumParams;

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
    /// absent: [`judge`](crate::judge::judge) judges the others as a line of their own.
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
        self.hil.iter().any(HilRobot::own_clock)
    }

    /// True if robots in the loop follow the arena's clock over their links (lockstep,
    /// [`crate::world::hil::Lockstep`]).
    pub fn lockstep(&self) -> bool {
        self.hil.iter().any(HilRobot::follows)
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
        lives::config_of(self.robot, &self.configs, robot)
    }
}
