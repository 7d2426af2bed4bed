//! The board's environmental sensor: [`EmuSensor`] implements the firmware's [`Sensor`] and
//! nothing else. What it reads comes from its [`Surroundings`] (in a run, the world's
//! environment where the swarm is: a light pattern, or a field over the plane), with the
//! noise drawn from the robot's own RNG.

use std::fmt;
use std::rc::Rc;

use firmware::{Clock, ErrorKind, Sensor, hal::ErrorType};
use protocol::{Instant, Level};
use rand_pcg::Pcg32;

use crate::board::clock::EmuClock;

/// What is around a robot for its sensor to read, as the board sees it: the world's
/// environment implements it (`world::env`).
pub trait Surroundings: fmt::Debug {
    /// The ambient light robot `robot`'s sensor reports at `now`, noise drawn from `rng`.
    fn ambient_light(&self, robot: usize, now: Instant, rng: &mut Pcg32) -> Level;
    /// The oxygen level robot `robot`'s sensor reports, noise drawn from `rng`.
    fn oxygen(&self, robot: usize, rng: &mut Pcg32) -> Level;
}

/// One robot's sensor in the emulated environment.
#[derive(Debug)]
pub struct EmuSensor {
    surroundings: Rc<dyn Surroundings>,
    robot: usize,
    clock: EmuClock,
    rng: Pcg32,
}

impl EmuSensor {
    /// The sensor of robot `robot` in `surroundings`, with its own noise RNG.
    pub fn new(
        surroundings: Rc<dyn Surroundings>,
        robot: usize,
        clock: EmuClock,
        rng: Pcg32,
    ) -> Self {
        EmuSensor {
            surroundings,
            robot,
            clock,
            rng,
        }
    }
}

impl ErrorType for EmuSensor {
    type Error = ErrorKind;
}

impl Sensor for EmuSensor {
    async fn ambient_light(&mut self) -> Result<Level, ErrorKind> {
        let now = self.clock.now();
        Ok(self
            .surroundings
            .ambient_light(self.robot, now, &mut self.rng))
    }

    async fn oxygen(&mut self) -> Result<Level, ErrorKind> {
        Ok(self.surroundings.oxygen(self.robot, &mut self.rng))
    }
}
