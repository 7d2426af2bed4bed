//! The environment the robots sense: a light pattern per robot, changing at scheduled times, or
//! a scalar field over the plane ([`PlaneField`]) sampled where each robot is as the swarm moves.
//! Part of the world: [`SwarmEnv`], the environment where the swarm is, is the board's
//! [`Surroundings`], what each robot's sensor ([`crate::board::sensor::EmuSensor`]) reads.

use std::cell::Cell;
use std::rc::Rc;

use nalgebra::{Point2, Vector2};
use protocol::{Instant, Level};
use rand::Rng;
use rand_pcg::Pcg32;

use crate::board::sensor::Surroundings;

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
    /// A field over the plane instead of the light pattern, if set: each robot reads it where
    /// it is (`schedule`, `lit` and `dark` are then not used).
    pub field: Option<PlaneField>,
    /// What the ambient-light sensor reports: noisy levels (the default), the paper's binary
    /// readings (Fig. 12(d): g = 1 lit, 0 dark), a coarser sensor, or a scaled and offset one.
    pub readings: Readings,
}

/// What a robot's ambient-light sensor reports ([`Environment::light`]): the same light seen
/// through sensors of another unit, gain, offset or resolution. CIMAX compares diversities, so
/// none of these may change a decision (`docs/protocol.md` §5.6).
///
/// The oxygen reading is a noisy level either way (the lab experiment used light only).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Readings {
    /// A level: [`Environment::lit`] or [`Environment::dark`] (or the field's level), off by the
    /// environment's noise.
    #[default]
    Levels,
    /// The paper's binary readings (Fig. 12(d), g ∈ {0, 1}): `Level(1)` for a lit robot and
    /// `Level(0)` for a dark one, without noise (no draw from the robot's RNG). Over a
    /// [`PlaneField`], 1 where the field's noiseless level is at least halfway between
    /// [`Environment::dark`] and [`Environment::lit`] ([`Environment::binary_threshold`]).
    Binary,
    /// A coarser sensor of `N` levels (`2..=256`): the noisy level `x` of [`Readings::Levels`]
    /// read as `⌊x · N / 256⌋`, `0..N` (16 levels: lit 200 reads 12, dark 30 reads 1).
    Quantised(u16),
    /// A sensor of another gain and offset: the noisy level `x` read as
    /// `round(gain · x + offset)`, saturated to `0..=255`.
    Scaled {
        /// Levels of this sensor per level of the default one (`> 0`).
        gain: f64,
        /// Added after the gain.
        offset: f64,
    },
}

impl Readings {
    /// What a sensor of this kind reports for the noisy level `x` (not for [`Readings::Binary`],
    /// which reads lit or dark without noise: `x` unchanged).
    pub fn read(self, x: Level) -> Level {
        match self {
            Readings::Levels | Readings::Binary => x,
            Readings::Quantised(n) => {
                Level((u32::from(x.0) * u32::from(n.clamp(2, 256)) / 256) as u8)
            }
            Readings::Scaled { gain, offset } => {
                // `as` saturates and maps NaN to 0.
                Level((gain * f64::from(x.0) + offset).round().clamp(0.0, 255.0) as u8)
            }
        }
    }
}

impl core::fmt::Display for Readings {
    /// The `--readings` spelling: `full`, `binary`, `levels:N`, `gain:G,offset:B`.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Readings::Levels => write!(f, "full"),
            Readings::Binary => write!(f, "binary"),
            Readings::Quantised(n) => write!(f, "levels:{n}"),
            Readings::Scaled { gain, offset } => write!(f, "gain:{gain},offset:{offset}"),
        }
    }
}

/// A `--readings` value that does not parse: says what was expected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadingsError(pub String);

impl core::fmt::Display for ReadingsError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ReadingsError {}

impl core::str::FromStr for Readings {
    type Err = ReadingsError;

    /// `full`, `binary`, `levels:N` (N in 2..=256) or `gain:G,offset:B` (G > 0, both finite;
    /// either part may be left out: gain 1, offset 0).
    fn from_str(s: &str) -> Result<Readings, ReadingsError> {
        let err = |why: &str| {
            ReadingsError(format!(
                "{s:?}: {why} (expected full, binary, levels:N with N in 2..=256, or gain:G,offset:B)"
            ))
        };
        match s.trim() {
            "full" => return Ok(Readings::Levels),
            "binary" => return Ok(Readings::Binary),
            _ => {}
        }
        if let Some(n) = s.trim().strip_prefix("levels:") {
            let n: u16 = n
                .trim()
                .parse()
                .map_err(|_| err("the number of levels is not a whole number"))?;
            if !(2..=256).contains(&n) {
                return Err(err("a sensor has 2 to 256 levels"));
            }
            return Ok(Readings::Quantised(n));
        }
        let (mut gain, mut offset) = (1.0, 0.0);
        for part in s.split(',') {
            let (key, value) = part
                .split_once(':')
                .ok_or_else(|| err("unknown kind of readings"))?;
            let v: f64 = value
                .trim()
                .parse()
                .map_err(|_| err("gain and offset must be numbers"))?;
            if !v.is_finite() {
                return Err(err("gain and offset must be finite"));
            }
            match key.trim() {
                "gain" if v > 0.0 => gain = v,
                "gain" => return Err(err("the gain must be above 0")),
                "offset" => offset = v,
                _ => return Err(err("unknown kind of readings")),
            }
        }
        Ok(Readings::Scaled { gain, offset })
    }
}

/// A scalar field over the plane as the robots' sensors read it (the swarm simulator's fields,
/// [`crate::world::field`]).
///
/// Robot `i` at `positions[i]` (in R, the light's range) reads the field's mean at
/// `positions[i] + offset`, where `offset` is the swarm's displacement (`start` at first, then
/// moved by the arena as the swarm decides, [`crate::world::arena::Motion`]), mapped to a sensor level by `level = base + gain × X`, rounded and
/// saturated to `0..=255`, plus the environment's noise. With the defaults (base 30, gain 34)
/// the sharp border's 0 and 5 read as 30 and 200, the lab's dark and lit, and the paper's
/// noise of width 1 is about ±17 levels.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneField {
    /// The field.
    pub field: crate::world::field::Field,
    /// Each robot's position relative to the swarm, in R.
    pub positions: Vec<Point2<f64>>,
    /// The swarm's displacement at the start, in R.
    pub start: Vector2<f64>,
    /// Level of X = 0.
    pub base: f64,
    /// Levels per unit of X.
    pub gain: f64,
}

impl PlaneField {
    /// `field` read by robots at `positions` (in R), the swarm displaced by `start`; base 30,
    /// gain 34.
    pub fn new(
        field: crate::world::field::Field,
        positions: Vec<Point2<f64>>,
        start: Vector2<f64>,
    ) -> Self {
        PlaneField {
            field,
            positions,
            start,
            base: 30.0,
            gain: 34.0,
        }
    }

    /// Where robot `i` is with the swarm displaced by `offset`, in R (the origin for a robot
    /// beyond `positions`).
    pub fn position(&self, i: usize, offset: Vector2<f64>) -> Point2<f64> {
        self.positions
            .get(i)
            .copied()
            .unwrap_or_else(Point2::origin)
            + offset
    }

    /// The swarm's centre of mass with the swarm displaced by `offset`, in R.
    pub fn centre(&self, offset: Vector2<f64>) -> Point2<f64> {
        let n = self.positions.len().max(1) as f64;
        let sum = self
            .positions
            .iter()
            .fold(Vector2::zeros(), |s, p| s + p.coords);
        Point2::from(sum / n) + offset
    }

    /// The noiseless level robot `i` reads with the swarm displaced by `offset`.
    pub fn level(&self, i: usize, offset: Vector2<f64>) -> u8 {
        let x = self.base + self.gain * self.field.mean(self.position(i, offset));
        // `as` saturates and maps NaN to 0.
        x.round().clamp(0.0, 255.0) as u8
    }
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
            field: None,
            readings: Readings::Levels,
        }
    }

    /// `field` over the plane, read by robots at `positions` (in R) with the swarm displaced by
    /// `start`, noise ±17 levels (the paper's noise of width 1 at the default gain).
    pub fn plane(
        field: crate::world::field::Field,
        positions: Vec<Point2<f64>>,
        start: Vector2<f64>,
    ) -> Self {
        Environment {
            schedule: vec![(Instant::ZERO, Vec::new())],
            noise: 17,
            field: Some(PlaneField::new(field, positions, start)),
            ..Environment::constant(Vec::new())
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

    /// What robot `robot`'s ambient-light sensor reports at `t` under the light pattern
    /// ([`Readings`]): `lit` or `dark` with noise drawn from `rng` as the sensor reads it, or
    /// 1 or 0.
    pub fn light(&self, robot: usize, t: Instant, rng: &mut Pcg32) -> Level {
        let lit = self.is_lit(robot, t);
        match self.readings {
            Readings::Binary => Level(u8::from(lit)),
            r => r.read(self.noisy(if lit { self.lit } else { self.dark }, rng)),
        }
    }

    /// What a sensor whose noiseless level is `level` (a [`PlaneField`]'s) reports
    /// ([`Readings`]): `level` with noise drawn from `rng` as the sensor reads it, or 1 if it
    /// is at least [`Self::binary_threshold`] and 0 below.
    pub fn field_light(&self, level: u8, rng: &mut Pcg32) -> Level {
        match self.readings {
            Readings::Binary => Level(u8::from(level >= self.binary_threshold())),
            r => r.read(self.noisy(level, rng)),
        }
    }

    /// The level from which a field reads as lit with [`Readings::Binary`]: halfway between
    /// `dark` and `lit`, rounded up (115 with the defaults, between the sharp border's 30 and
    /// 200).
    pub fn binary_threshold(&self) -> u8 {
        let (a, b) = (self.dark.min(self.lit), self.dark.max(self.lit));
        a + (b - a).div_ceil(2)
    }

    /// `level` off by a uniform draw in `-noise..=noise` from `rng`, saturated to `0..=255`.
    pub(crate) fn noisy(&self, level: u8, rng: &mut Pcg32) -> Level {
        let n = i16::from(self.noise);
        let off = if n > 0 { rng.random_range(-n..=n) } else { 0 };
        Level((i16::from(level) + off).clamp(0, 255) as u8)
    }
}

/// The environment where the swarm is, as one run's sensors read it (the board's
/// [`Surroundings`]): the light pattern of the time, or over a [`PlaneField`] the field where
/// each robot is with the swarm displaced by an offset shared with whatever moves the swarm
/// (the arena's motion).
#[derive(Debug)]
pub struct SwarmEnv {
    env: Rc<Environment>,
    offset: Rc<Cell<Vector2<f64>>>,
}

impl SwarmEnv {
    /// `env` with the swarm at its start (a [`PlaneField`]'s `start`, or nowhere in particular).
    pub fn new(env: Rc<Environment>) -> Self {
        let start = env.field.as_ref().map_or(Vector2::zeros(), |f| f.start);
        SwarmEnv {
            env,
            offset: Rc::new(Cell::new(start)),
        }
    }

    /// The environment.
    pub fn env(&self) -> &Environment {
        &self.env
    }

    /// The swarm's displacement over the plane field now.
    pub fn offset(&self) -> Vector2<f64> {
        self.offset.get()
    }

    /// Moves the swarm: displaced by `offset` from now on.
    pub fn set_offset(&self, offset: Vector2<f64>) {
        self.offset.set(offset);
    }
}

impl Surroundings for SwarmEnv {
    fn ambient_light(&self, robot: usize, now: Instant, rng: &mut Pcg32) -> Level {
        if let Some(f) = &self.env.field {
            let level = f.level(robot, self.offset.get());
            return self.env.field_light(level, rng);
        }
        self.env.light(robot, now, rng)
    }

    fn oxygen(&self, _robot: usize, rng: &mut Pcg32) -> Level {
        self.env.noisy(self.env.oxygen, rng)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::board::clock::EmuClock;
    use crate::board::sensor::EmuSensor;
    use firmware::{Clock as _, Sensor as _};

    #[tokio::test(flavor = "current_thread", start_paused = true)]
    async fn binary_readings_reach_the_robot_as_zero_or_one() {
        let mut env = Environment::constant(vec![false, true]);
        env.schedule
            .push((Instant::from_secs(60), vec![true, false]));
        env.readings = Readings::Binary;
        let env: Rc<dyn Surroundings> = Rc::new(SwarmEnv::new(Rc::new(env)));
        let clock = EmuClock::new(tokio::time::Instant::now());
        let mut sensors: Vec<EmuSensor> = (0..2)
            .map(|r| EmuSensor::new(env.clone(), r, clock.clone(), Pcg32::new(r as u64, 1)))
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
    fn binary_readings_are_zero_or_one_and_follow_the_pattern() {
        let mut e = Environment::constant(vec![true, false, false, true]);
        e.schedule
            .push((Instant::from_secs(100), vec![false, true, true, false]));
        e.readings = Readings::Binary;
        let mut rng = Pcg32::new(1, 1);
        for s in (0..200).step_by(7) {
            let t = Instant::from_secs(s);
            for robot in 0..5 {
                let g = e.light(robot, t, &mut rng).0;
                assert!(g <= 1, "g = {g}");
                assert_eq!(g == 1, e.is_lit(robot, t), "robot {robot} at {s} s");
            }
        }
        // No noise is drawn: the robot's RNG is untouched.
        assert_eq!(rng, Pcg32::new(1, 1));
        // Levels (the default) stay levels, with noise.
        e.readings = Readings::Levels;
        let l = e.light(0, Instant::ZERO, &mut rng).0;
        assert!((190..=210).contains(&l), "{l}");
        assert_ne!(rng, Pcg32::new(1, 1));
    }

    #[test]
    fn coarse_and_scaled_sensors_read_the_noisy_level() {
        let mut rng = Pcg32::new(1, 2);
        let mut e = Environment::constant(vec![true, false]);
        e.noise = 0;
        e.readings = Readings::Quantised(16);
        assert_eq!(e.light(0, Instant::ZERO, &mut rng), Level(12));
        assert_eq!(e.light(1, Instant::ZERO, &mut rng), Level(1));
        e.readings = Readings::Quantised(4);
        assert_eq!(e.light(0, Instant::ZERO, &mut rng), Level(3));
        assert_eq!(e.light(1, Instant::ZERO, &mut rng), Level(0));
        e.readings = Readings::Scaled {
            gain: 0.5,
            offset: 100.0,
        };
        assert_eq!(e.light(0, Instant::ZERO, &mut rng), Level(200));
        assert_eq!(e.light(1, Instant::ZERO, &mut rng), Level(115));
        // Saturation at the top.
        e.readings = Readings::Scaled {
            gain: 2.0,
            offset: 0.0,
        };
        assert_eq!(e.light(0, Instant::ZERO, &mut rng), Level(255));
    }

    #[test]
    fn readings_parse_and_print_back() {
        for (text, r) in [
            ("full", Readings::Levels),
            ("binary", Readings::Binary),
            ("levels:16", Readings::Quantised(16)),
            (
                "gain:0.5,offset:100",
                Readings::Scaled {
                    gain: 0.5,
                    offset: 100.0,
                },
            ),
        ] {
            let got: Readings = text.parse().unwrap();
            assert_eq!(got, r, "{text}");
            assert_eq!(got.to_string().parse::<Readings>().unwrap(), r);
        }
        for bad in [
            "",
            "bin",
            "levels:1",
            "levels:257",
            "levels:x",
            "gain:0",
            "gain:-1",
            "gain:x",
            "offset:inf",
            "gain:2,foo:1",
        ] {
            let e = bad.parse::<Readings>().unwrap_err();
            assert!(
                e.to_string().contains("expected full, binary"),
                "{bad}: {e}"
            );
        }
    }

    #[test]
    fn binary_readings_threshold_a_field_halfway() {
        let mut e = Environment::constant(Vec::new());
        e.readings = Readings::Binary;
        assert_eq!(e.binary_threshold(), 115);
        let mut rng = Pcg32::new(1, 1);
        assert_eq!(e.field_light(200, &mut rng), Level(1));
        assert_eq!(e.field_light(115, &mut rng), Level(1));
        assert_eq!(e.field_light(114, &mut rng), Level(0));
        assert_eq!(e.field_light(30, &mut rng), Level(0));
        (e.lit, e.dark) = (0, 255);
        assert_eq!(e.binary_threshold(), 128);
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
