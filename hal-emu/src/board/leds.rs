//! The board's top-cap LEDs: each change a robot shows is recorded with its time, as a camera
//! over the arena would see it, and traced. [`EmuLeds`] implements the firmware's [`Leds`] and
//! nothing else; `LedLog` is the record all robots of one run write into, which the run's
//! report ([`crate::world::arena::RunReport::leds`]) and the swarm's motion read.

use std::cell::RefCell;
use std::rc::Rc;

use firmware::hal::ErrorType;
use firmware::{Clock, ErrorKind, LedColor, Leds};

use crate::world::arena::{LedChange, leds_at};
use crate::world::clock::EmuClock;
use crate::world::medium::{SharedMedium, TraceEvent};
use protocol::Instant;

/// Trace names of the LEDs of robots with more than two sectors.
const SECTOR_NAMES: [&str; 8] = [
    "sector 0", "sector 1", "sector 2", "sector 3", "sector 4", "sector 5", "sector 6", "sector 7",
];

/// Every LED change of every robot of one run, in time order; each change also goes into the
/// medium's trace.
#[derive(Debug)]
pub(crate) struct LedLog {
    clock: EmuClock,
    medium: SharedMedium,
    changes: RefCell<Vec<LedChange>>,
}

impl LedLog {
    /// An empty record on the run's clock, tracing into `medium`.
    pub(crate) fn new(clock: EmuClock, medium: SharedMedium) -> Self {
        LedLog {
            clock,
            medium,
            changes: RefCell::new(Vec::new()),
        }
    }

    /// Every change so far.
    pub(crate) fn changes(&self) -> Vec<LedChange> {
        self.changes.borrow().clone()
    }

    /// Every robot's LEDs now (`n` robots).
    pub(crate) fn now(&self, n: usize) -> Vec<LedColor> {
        leds_at(&self.changes.borrow(), n, Instant::MAX)
    }

    /// Robot `robot` shows `color` from now on: recorded (and traced) if it is a change.
    pub(crate) fn record(&self, robot: usize, color: LedColor) {
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

/// The top-cap LEDs of one emulated robot: each change is recorded with its time.
#[derive(Debug)]
pub struct EmuLeds {
    log: Rc<LedLog>,
    robot: usize,
}

impl EmuLeds {
    /// Robot `robot`'s LEDs, recording into `log`.
    pub(crate) fn new(log: Rc<LedLog>, robot: usize) -> Self {
        EmuLeds { log, robot }
    }
}

impl ErrorType for EmuLeds {
    type Error = ErrorKind;
}

impl Leds for EmuLeds {
    async fn show(&mut self, color: LedColor) -> Result<(), ErrorKind> {
        #[cfg(test)]
        fault::faulty_led_driver(self.robot);
        self.log.record(self.robot, color);
        Ok(())
    }
}

/// A test-only fault in the LED driver, for the run's tests of a robot that panics.
#[cfg(test)]
pub(crate) mod fault {
    use std::cell::Cell;

    thread_local! {
        /// The robot whose LED driver panics in this test thread's runs, if any.
        static FAULTY_LEDS: Cell<Option<usize>> = const { Cell::new(None) };
    }

    /// The test-only fault: robot `robot`'s LED driver panics when the robot program shows a
    /// decision, inside the robot's task as a panic in real driver code would be. Runs are on
    /// the calling thread (a current-thread runtime), so the setting stays with its test.
    pub(crate) fn faulty_led_driver(robot: usize) {
        if FAULTY_LEDS.get() == Some(robot) {
            panic!("injected fault: robot {robot}'s LED driver");
        }
    }

    /// Runs `f` with robot `robot`'s LED driver faulty.
    pub(crate) fn with_faulty_leds<T>(robot: usize, f: impl FnOnce() -> T) -> T {
        FAULTY_LEDS.set(Some(robot));
        let out = f();
        FAULTY_LEDS.set(None);
        out
    }
}
