//! The board's environmental sensor: what one robot reads of the world's
//! [`Environment`] (a light pattern, or a field over the plane where the swarm is), with the
//! environment's noise drawn from the robot's own RNG, or the paper's binary readings
//! ([`Readings`](crate::world::env::Readings)). It implements the firmware's [`Sensor`] and
//! nothing else.

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
            return Ok(self.env.field_light(level, &mut self.rng));
        }
        let t = firmware::Clock::now(&self.clock);
        Ok(self.env.light(self.robot, t, &mut self.rng))
    }

    async fn oxygen(&mut self) -> Result<Level, ErrorKind> {
        if *self.failing.borrow() {
            return Err(ErrorKind::Bus);
        }
        Ok(self.env.noisy(self.env.oxygen, &mut self.rng))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::env::Readings;
    use firmware::Clock as _;
    use protocol::Instant;
    use rand_pcg::Pcg32;

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn binary_readings_reach_the_robot_as_zero_or_one() {
        let mut env = Environment::constant(vec![false, true]);
        env.schedule
            .push((Instant::from_secs(60), vec![true, false]));
        env.readings = Readings::Binary;
        let env = Rc::new(env);
        let clock = EmuClock::new(tokio::time::Instant::now());
        let mut sensors: Vec<EmuSensor> = (0..2)
            .map(|r| EmuSensor::new(env.clone(), r, clock, Pcg32::new(r as u64, 1)))
            .collect();
        let mut seen = Vec::new();
        for _ in 0..4 {
            for s in &mut sensors {
                seen.push(s.ambient_light().await.unwrap().0);
            }
            clock
                .sleep_until(clock.now() + protocol::Duration::from_secs(30))
                .await;
        }
        // Dark-lit for the first minute, lit-dark after it.
        assert_eq!(seen, [0, 1, 0, 1, 1, 0, 1, 0]);
    }
}
