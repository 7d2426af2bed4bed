//! The board's top-cap LEDs: [`EmuLeds`] implements the firmware's [`Leds`] and nothing else.
//! Each colour a robot shows goes to the [`Camera`], whatever sees the LEDs: in a run, the
//! world's record of every LED change with its time, as a camera over the arena would see it,
//! which the run's report and the swarm's motion read.

use std::fmt;
use std::rc::Rc;

use firmware::hal::ErrorType;
use firmware::{ErrorKind, LedColor, Leds};

/// What sees a robot's LEDs, as the board sees it: the world's LED record implements it
/// (`world::arena`'s camera, which adds the time and traces each change).
pub trait Camera: fmt::Debug {
    /// Robot `robot` shows `color` from now on.
    fn shown(&self, robot: usize, color: LedColor);
}

/// The top-cap LEDs of one emulated robot: each colour shown goes to the [`Camera`].
#[derive(Debug)]
pub struct EmuLeds {
    camera: Rc<dyn Camera>,
    robot: usize,
}

impl EmuLeds {
    /// Robot `robot`'s LEDs, seen by `camera`.
    pub(crate) fn new(camera: Rc<dyn Camera>, robot: usize) -> Self {
        EmuLeds { camera, robot }
    }
}

impl ErrorType for EmuLeds {
    type Error = ErrorKind;
}

impl Leds for EmuLeds {
    async fn show(&mut self, color: LedColor) -> Result<(), ErrorKind> {
        #[cfg(test)]
        fault::faulty_led_driver(self.robot);
        self.camera.shown(self.robot, color);
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
