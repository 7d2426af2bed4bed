//! Why a run could not start or has no valid result.

use firmware::SetupError;

use crate::world::adversary::AdversaryError;
use crate::world::hil::HilError;
use crate::world::medium::{MediumError, NoSuchNode};

use crate::board::clock::TaskEnd;

/// Why a run could not start.
#[derive(Debug, Clone, PartialEq)]
pub enum ArenaError {
    /// The robot program refused its configuration.
    Setup(SetupError),
    /// The medium's parameters make no sense.
    Medium(MediumError),
    /// A kill, restart or per-robot configuration names a robot that does not exist.
    NoSuchRobot(usize),
    /// An adversary's parameters make no sense.
    Adversary(AdversaryError),
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
    /// The robot's index (its position in [`ArenaConfig::positions`](super::ArenaConfig::positions)).
    pub robot: usize,
    /// The run's seed ([`ArenaConfig::seed`](super::ArenaConfig::seed)): it replays the failure.
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
    pub(super) fn from_join(robot: usize, seed: u64, e: TaskEnd) -> Self {
        let (panicked, message) = match e {
            TaskEnd::Panicked(m) => (true, m),
            TaskEnd::Cancelled => (false, "its task was cancelled".to_string()),
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

/// Why a robot's life ended before its stop: it could not boot, or (a robot in the loop) its
/// link failed. The arena makes it a [`RobotFailure`].
#[derive(Debug, thiserror::Error)]
pub(super) enum LifeError {
    /// The robot program has no build for this many receivers.
    #[error("{0} sectors: the robot program has 2 to 8 receivers")]
    Sectors(u8),
    /// The medium has no place for the robot.
    #[error(transparent)]
    Attach(#[from] NoSuchNode),
    /// The medium gave another number of receivers than the robot has.
    #[error("the medium gave {got} receivers for {want} sectors")]
    Receivers {
        /// The receivers given.
        got: usize,
        /// The robot's sectors.
        want: usize,
    },
    /// The robot program refused its configuration.
    #[error("robot configuration: {0}")]
    Setup(#[source] SetupError),
    /// The robot in the loop failed.
    #[error(transparent)]
    Hil(#[from] HilError),
    /// The bridge of a robot in the loop went on after its stop.
    #[error("the bridge outlived its stop")]
    BridgeOutlived,
}
