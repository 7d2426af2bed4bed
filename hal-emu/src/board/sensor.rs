//! The board's environmental sensor: what one robot reads of the world's
//! [`Environment`] (a light pattern, or a field over the plane where the swarm is), with the
//! environment's noise drawn from the robot's own RNG. It implements the firmware's
//! [`Sensor`] and nothing else.

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use firmware::{ErrorKind, Sensor, hal::ErrorType};
use nalgebra::Vector2;
use protocol::Level;
use rand_pcg::Pcg32;

use crate::world::clock::EmuClock;
use crate::world::env::Environment;

/// One robot's sensor in the emulated environment.
#[derive(Debug)]
pub struct EmuSensor {
    env: Rc<Environment>,
    robot: usize,
    clock: EmuClock,
    rng: Pcg32,
    /// Reads that fail from now on (to test a failing sensor); shared so a test can flip it.
    pub failing: Rc<RefCell<bool>>,
    /// The swarm's displacement over a [`PlaneField`](crate::world::env::PlaneField), shared with whatever moves the swarm.
    offset: Rc<Cell<Vector2<f64>>>,
}

impl EmuSensor {
    /// The sensor of robot `robot`, with its own noise RNG; over a [`PlaneField`](crate::world::env::PlaneField) the swarm
    /// stays at the field's `start`.
    pub fn new(env: Rc<Environment>, robot: usize, clock: EmuClock, rng: Pcg32) -> Self {
        let start = env.field.as_ref().map_or(Vector2::zeros(), |f| f.start);
        EmuSensor {
            env,
            robot,
            clock,
            rng,
            failing: Rc::new(RefCell::new(false)),
            offset: Rc::new(Cell::new(start)),
        }
    }

    /// The same sensor, reading a [`PlaneField`](crate::world::env::PlaneField) where `offset` (shared with the arena's
    /// motion) says the swarm is.
    pub fn moving_with(mut self, offset: Rc<Cell<Vector2<f64>>>) -> Self {
        self.offset = offset;
        self
    }
}

impl ErrorType for EmuSensor {
    type Error = ErrorKind;
}

impl Sensor for EmuSensor {
    async fn ambient_light(&mut self) -> Result<Level, ErrorKind> {
        if *self.failing.borrow() {
            return Err(ErrorKind::Bus);
        }
        if let Some(f) = &self.env.field {
            let level = f.level(self.robot, self.offset.get());
            return Ok(self.env.noisy(level, &mut self.rng));
        }
        let t = firmware::Clock::now(&self.clock);
        let base = if self.env.is_lit(self.robot, t) {
            self.env.lit
        } else {
            self.env.dark
        };
        Ok(self.env.noisy(base, &mut self.rng))
    }

    async fn oxygen(&mut self) -> Result<Level, ErrorKind> {
        if *self.failing.borrow() {
            return Err(ErrorKind::Bus);
        }
        Ok(self.env.noisy(self.env.oxygen, &mut self.rng))
    }
}
