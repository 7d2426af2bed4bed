//! The environment the robots sense: a light pattern per robot, changing at scheduled times.

use firmware::{ErrorKind, Sensor, hal::ErrorType};
use protocol::{Instant, Level};
use rand::Rng;
use rand_pcg::Pcg32;
use std::cell::RefCell;
use std::rc::Rc;

/// Light patterns over time, and how they read on the sensors.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    /// `(from, pattern)`, sorted by time; `pattern[i]` is true if robot `i` is lit. The first
    /// entry should be at time zero.
    pub schedule: Vec<(Instant, Vec<bool>)>,
    /// Sensor level of a lit robot.
    pub lit: u8,
    /// Sensor level of a dark robot.
    pub dark: u8,
    /// Sensor noise: each reading is off by a uniform amount in `-noise..=noise`.
    pub noise: u8,
    /// The oxygen level every robot reads (the lab experiment used light only).
    pub oxygen: u8,
}

impl Environment {
    /// A constant pattern with the default levels (lit 200, dark 30, noise ±10).
    pub fn constant(pattern: Vec<bool>) -> Self {
        Environment {
            schedule: vec![(Instant::ZERO, pattern)],
            lit: 200,
            dark: 30,
            noise: 10,
            oxygen: 128,
        }
    }

    /// The pattern in force at `t`.
    pub fn pattern_at(&self, t: Instant) -> Option<&[bool]> {
        self.schedule
            .iter()
            .rev()
            .find(|(from, _)| *from <= t)
            .or(self.schedule.first())
            .map(|(_, p)| p.as_slice())
    }

    /// Whether robot `robot` is lit at `t` (a robot beyond the pattern is dark).
    pub fn is_lit(&self, robot: usize, t: Instant) -> bool {
        self.pattern_at(t)
            .and_then(|p| p.get(robot).copied())
            .unwrap_or(false)
    }

    fn noisy(&self, level: u8, rng: &mut Pcg32) -> Level {
        let n = i16::from(self.noise);
        let off = if n > 0 { rng.random_range(-n..=n) } else { 0 };
        Level((i16::from(level) + off).clamp(0, 255) as u8)
    }
}

/// One robot's sensor in the emulated environment.
#[derive(Debug)]
pub struct EmuSensor {
    env: Rc<Environment>,
    robot: usize,
    clock: crate::EmuClock,
    rng: Pcg32,
    /// Reads that fail from now on (to test a failing sensor); shared so a test can flip it.
    pub failing: Rc<RefCell<bool>>,
}

impl EmuSensor {
    /// The sensor of robot `robot`, with its own noise RNG.
    pub fn new(env: Rc<Environment>, robot: usize, clock: crate::EmuClock, rng: Pcg32) -> Self {
        EmuSensor {
            env,
            robot,
            clock,
            rng,
            failing: Rc::new(RefCell::new(false)),
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_picks_the_pattern_in_force() {
        let mut e = Environment::constant(vec![true, false]);
        e.schedule
            .push((Instant::from_secs(100), vec![false, true]));
        assert!(e.is_lit(0, Instant::from_secs(99)));
        assert!(!e.is_lit(0, Instant::from_secs(100)));
        assert!(e.is_lit(1, Instant::from_secs(500)));
        assert!(!e.is_lit(7, Instant::ZERO));
    }

    #[test]
    fn noise_stays_in_bounds() {
        let e = Environment::constant(vec![true]);
        let mut rng = Pcg32::new(1, 1);
        for _ in 0..1000 {
            let l = e.noisy(250, &mut rng).0;
            assert!((240..=255).contains(&l));
        }
    }
}
