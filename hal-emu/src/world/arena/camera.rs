//! The camera over the arena: every LED change of every robot of a run with its time
//! ([`LedChange`]), as a camera over the arena would see it. The run's LED log is the board's
//! [`Camera`]: each robot's LEDs ([`crate::board::leds::EmuLeds`]) show into it, and it traces
//! each change. The run's report and the swarm's motion read it.

use std::cell::RefCell;

use firmware::{Clock, LedColor};
use protocol::Instant;

use crate::board::clock::EmuClock;
use crate::board::leds::Camera;
use crate::world::medium::{SharedMedium, TraceEvent};

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

/// The LEDs of `n` robots at `t`: the last of `changes` (in time order) at or before `t` for
/// each robot, off before its first.
pub(super) fn leds_at(changes: &[LedChange], n: usize, t: Instant) -> Vec<LedColor> {
    let mut out = vec![LedColor::Off; n];
    for c in changes.iter().take_while(|c| c.t <= t) {
        if let Some(o) = out.get_mut(c.robot) {
            *o = c.color;
        }
    }
    out
}

/// Trace names of the LEDs of robots with more than two sectors.
const SECTOR_NAMES: [&str; 8] = [
    "sector 0", "sector 1", "sector 2", "sector 3", "sector 4", "sector 5", "sector 6", "sector 7",
];

/// Every LED change of every robot of one run, in time order; each change also goes into the
/// medium's trace. It is the board's [`Camera`]: every robot's LEDs show into it.
#[derive(Debug)]
pub(super) struct LedLog {
    clock: EmuClock,
    medium: SharedMedium,
    changes: RefCell<Vec<LedChange>>,
}

impl LedLog {
    /// An empty record on the run's clock, tracing into `medium`.
    pub(super) fn new(clock: EmuClock, medium: SharedMedium) -> Self {
        LedLog {
            clock,
            medium,
            changes: RefCell::new(Vec::new()),
        }
    }

    /// Every change so far.
    pub(super) fn changes(&self) -> Vec<LedChange> {
        self.changes.borrow().clone()
    }

    /// Every robot's LEDs now (`n` robots).
    pub(super) fn now(&self, n: usize) -> Vec<LedColor> {
        leds_at(&self.changes.borrow(), n, Instant::MAX)
    }

    /// Robot `robot` shows `color` from now on: recorded (and traced) if it is a change.
    pub(super) fn record(&self, robot: usize, color: LedColor) {
        let t = self.clock.now();
        let mut leds = self.changes.borrow_mut();
        let current = leds
            .iter()
            .rev()
            .find(|c| c.robot == robot)
            .map_or(LedColor::Off, |c| c.color);
        if current != color {
            leds.push(LedChange { t, robot, color });
            self.medium.borrow_mut().log(TraceEvent::Led {
                t_ms: t.as_millis(),
                robot,
                color: match color {
                    LedColor::Green => "green",
                    LedColor::Blue => "blue",
                    LedColor::Off => "off",
                    LedColor::Sector(i) => SECTOR_NAMES
                        .get(usize::from(i))
                        .copied()
                        .unwrap_or("sector ?"),
                }
                .into(),
            });
        }
    }
}

impl Camera for LedLog {
    fn shown(&self, robot: usize, color: LedColor) {
        self.record(robot, color);
    }
}
