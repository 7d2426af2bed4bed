//! How the paper's results depend on what the paper does not fix: the cycle length, the
//! negotiation period, the diffusion rate, the noise, the gradient's slope and the swarm's
//! extent. Each knob is varied alone from a built-in scenario; every other setting stays.

use nalgebra::Point2;
use protocol::Duration;
use rayon::prelude::*;

use crate::experiment::{Error, SweepPoint, run, sweep};
use crate::geometry::{Shape, lattice};
use crate::progress::Progress;
use crate::scenario::Scenario;
use crate::seeds::derive;
use crate::stats;
use hal_emu::world::field::Along;

/// A setting the paper leaves open, and the value to give it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Knob {
    /// The cycle t_p^max, seconds.
    Cycle(u64),
    /// Cycles per negotiation period, half gathering and half deciding (even, ≥ 2).
    Period(u16),
    /// The diffusion rate (fraction of the angle turned toward a neighbour's opinion).
    Diffusion(f32),
    /// The width of the uniform noise.
    Noise(f64),
    /// The slope of every rising segment of an x profile (per R).
    Slope(f64),
    /// The swarm's diameter in R, agents at the same density (a disk of that diameter, or
    /// the lattice nodes within it).
    Extent(f64),
}

/// Why a knob cannot be set on a scenario.
#[derive(Debug, thiserror::Error)]
pub enum KnobError {
    /// A negotiation period must be an even number of cycles (half gathering, half deciding).
    #[error("a period of {0} cycles is not even")]
    OddPeriod(u16),
    /// The scenario's field has no ramp along x.
    #[error("scenario {0} has no slope to change")]
    NoSlope(String),
    /// A rectangle of agents has no diameter.
    #[error("the extent knob needs a disk or lattice swarm")]
    ExtentOfRectangle,
}

impl Knob {
    /// `scn` with this knob set.
    ///
    /// # Errors
    /// If the value makes no valid scenario (checked again when a run starts).
    pub fn apply(self, scn: &Scenario) -> Result<Scenario, Error> {
        let mut s = scn.clone();
        match self {
            Knob::Cycle(secs) => s.run.params.wave.cycle = Duration::from_secs(secs),
            Knob::Period(cycles) => {
                if cycles < 2 || cycles % 2 != 0 {
                    return Err(KnobError::OddPeriod(cycles).into());
                }
                s.run.params.gather_cycles = cycles / 2;
                s.run.params.decide_cycles = cycles / 2;
            }
            Knob::Diffusion(d) => s.run.params.diffusion = d,
            Knob::Noise(w) => s.run.noise = w,
            Knob::Slope(k) => {
                let mut found = false;
                for layer in &mut s.field.layers {
                    if layer.along == Along::X {
                        for g in &mut layer.segments {
                            if g.slope != 0.0 {
                                g.slope = k;
                                found = true;
                            }
                        }
                    }
                }
                if !found {
                    return Err(KnobError::NoSlope(scn.name.clone()).into());
                }
            }
            Knob::Extent(d) => match scn.shape {
                Shape::Lattice { spacing } => {
                    let r = 0.5 * d + 1e-9;
                    let big = lattice(4 * scn.agents.max(1) + 64, spacing);
                    s.agents = big.iter().filter(|v| v.norm() <= r).count();
                }
                Shape::Disk { diameter } => {
                    let k = d / diameter;
                    s.agents = ((scn.agents as f64) * k * k).round() as usize;
                    s.shape = Shape::Disk { diameter: d };
                }
                Shape::Rectangle { .. } => {
                    return Err(KnobError::ExtentOfRectangle.into());
                }
            },
        }
        s.run.check()?;
        Ok(s)
    }
}

/// Success from `x` (y = 0) with the knob at each value: `runs` runs per value, stopped at
/// success; value `k` uses seed `derive(seed, [k])`.
///
/// # Errors
/// The first run's error.
pub fn success_against(
    scn: &Scenario,
    knobs: &[Knob],
    x: f64,
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<SweepPoint>, Error> {
    knobs
        .iter()
        .enumerate()
        .map(|(k, knob)| {
            let s = knob.apply(scn)?;
            let pts = sweep(&s, s.run, &[x], runs, derive(seed, &[k as u64]), progress)?;
            Ok(pts[0])
        })
        .collect()
}

/// The observer's average diversity in one negotiation period with the swarm's centre at
/// `at`: mean and standard error over `runs` runs (run `r` uses seed `derive(seed, [r])`).
///
/// # Errors
/// The first run's error.
pub fn diversity_at(
    scn: &Scenario,
    at: Point2<f64>,
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<(f64, f64), Error> {
    let v: Vec<f64> = (0..runs)
        .into_par_iter()
        .map(|r| {
            let out = run(scn, scn.run, at, 1, derive(seed, &[u64::from(r)]), false)?;
            progress.inc();
            Ok(out.periods[0].diversity)
        })
        .collect::<Result<_, Error>>()?;
    let m = stats::mean(&v).unwrap_or(f64::NAN);
    let se = stats::standard_error(&v).unwrap_or(0.0);
    Ok((m, se))
}

/// How strongly the swarm's first move points toward +x from each `(x, 0)`: the mean over
/// `runs` one-period runs of cos(decided direction), 0 for a run without one, with its
/// standard error. Point `p`, run `r` use seed `derive(seed, [p, r])`.
///
/// # Errors
/// The first run's error.
pub fn heading_against_x(
    scn: &Scenario,
    xs: &[f64],
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<(f64, f64, f64)>, Error> {
    let n = xs.len() * runs as usize;
    let cos: Vec<f64> = (0..n)
        .into_par_iter()
        .map(|k| {
            let (p, r) = (k / runs as usize, k % runs as usize);
            let s = derive(seed, &[p as u64, r as u64]);
            let out =
                crate::experiment::run_moves(scn, scn.run, Point2::new(xs[p], 0.0), 1, s, false)?;
            progress.inc();
            Ok(out.periods[0].direction.map_or(0.0, f64::cos))
        })
        .collect::<Result<_, Error>>()?;
    Ok(xs
        .iter()
        .enumerate()
        .map(|(p, &x)| {
            let c = &cos[p * runs as usize..(p + 1) * runs as usize];
            let m = stats::mean(c).unwrap_or(f64::NAN);
            let se = stats::standard_error(c).unwrap_or(0.0);
            (x, m, se)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn builtin(name: &str) -> Scenario {
        Scenario::builtin(name).unwrap()
    }

    #[test]
    fn each_knob_changes_only_its_setting() {
        let g = builtin("gradient")
            .placed(crate::scenario::Placement::Lattice)
            .unwrap();
        let s = Knob::Slope(4.0).apply(&g).unwrap();
        assert_eq!(s.field.mean(Point2::new(1.0, 0.0)), 4.0);
        assert_eq!(g.field.mean(Point2::new(1.0, 0.0)), 2.5);
        assert_eq!(s.run.params, g.run.params);
        let s = Knob::Period(10).apply(&g).unwrap();
        assert_eq!(
            (s.run.params.gather_cycles, s.run.params.decide_cycles),
            (5, 5)
        );
        assert!(Knob::Period(3).apply(&g).is_err());
        assert!(Knob::Slope(1.0).apply(&builtin("sharp")).is_err());
        let s = Knob::Cycle(20).apply(&g).unwrap();
        assert_eq!(s.run.period_secs(), 40);
        // The 3 R lattice is the 61 agents; within 2.5 R there are fewer, at the same spacing.
        assert_eq!(Knob::Extent(6.0).apply(&g).unwrap().agents, 61);
        let small = Knob::Extent(5.0).apply(&g).unwrap();
        assert!((37..61).contains(&small.agents), "{}", small.agents);
        let r = builtin("gradient")
            .placed(crate::scenario::Placement::Random)
            .unwrap();
        let small = Knob::Extent(5.0).apply(&r).unwrap();
        assert_eq!(small.agents, 42);
        assert_eq!(small.shape, Shape::Disk { diameter: 5.0 });
    }
}
