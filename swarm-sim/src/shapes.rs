//! The discussion's claim about the swarm's shape (paper section 5): on a field of independent
//! random values, "if agents are distributed e.g. in a line, the preferred direction can only be
//! along the linear distribution of the swarm", and "a swarm shaped as a perfect cross will
//! theoretically move like the king on a chess board, solely up-down-left-right".
//!
//! Three formations of comparable size are run for one negotiation period each on the field
//! X = 0 everywhere, so that every reading is the simulator's noise alone (independent uniform
//! values): the page's lattice disk, a line along x and a cross of two perpendicular lines
//! ([`Formation`]). Each run records the swarm's decided direction (the circular mean,
//! [`Period::direction`](crate::sim::Period)) and every agent's decided bearing
//! ([`Agent::decision`](crate::sim::Agent)); [`Tally`] counts how many fall within a
//! tolerance of the line's two or the cross's four axes. The page's runs and section are
//! `reproduce::shapes`; its figure and CSV file `pages::figures`.

use std::f64::consts::{PI, TAU};

use nalgebra::{Point2, Vector2};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::experiment::Error;
use crate::geometry::{Shape, Swarm, lattice};
use crate::progress::Progress;
use crate::scenario::LATTICE_SPACING;
use crate::seeds::derive;
use crate::sim::{RunConfig, Sim};
use crate::stats::circular_mean;
use hal_emu::world::field::Field;

/// A swarm's formation: where its agents sit, in R (the perception range is 1 R).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Formation {
    /// The `agents` nodes of a triangular lattice of this spacing nearest the centre
    /// ([`lattice`]): 61 at 0.75 R fill the paper's disk of 6 R, the page's placement. Every
    /// neighbour lies at a multiple of 60°, so its agents hear from six directions only.
    Lattice {
        /// Number of agents.
        agents: usize,
        /// Distance between neighbouring nodes, in R.
        spacing: f64,
    },
    /// `agents` agents scattered uniformly in a disk, redrawn until connected
    /// ([`Swarm::place`]), a fresh placement per run: bearings in every direction.
    RandomDisk {
        /// Number of agents.
        agents: usize,
        /// The disk's diameter, in R.
        diameter: f64,
    },
    /// `agents` agents on the x axis, `spacing` apart, centred on the origin.
    Line {
        /// Number of agents.
        agents: usize,
        /// Distance between neighbours, in R.
        spacing: f64,
    },
    /// A centre agent and four arms of `arm` agents each along +x, +y, −x and −y, `spacing`
    /// apart: `4 arm + 1` agents.
    Cross {
        /// Agents per arm, the centre not counted.
        arm: usize,
        /// Distance between neighbours along an arm, in R.
        spacing: f64,
    },
}

impl Formation {
    /// The formation's name on the page and in the CSV file.
    pub fn name(&self) -> &'static str {
        match self {
            Formation::Lattice { .. } => "lattice disk",
            Formation::RandomDisk { .. } => "random disk",
            Formation::Line { .. } => "line",
            Formation::Cross { .. } => "cross",
        }
    }

    /// Number of agents.
    pub fn agents(&self) -> usize {
        match *self {
            Formation::Lattice { agents, .. }
            | Formation::RandomDisk { agents, .. }
            | Formation::Line { agents, .. } => agents,
            Formation::Cross { arm, .. } => 4 * arm + 1,
        }
    }

    /// The largest distance between two agents' positions (a random disk: its diameter), in R.
    pub fn extent(&self) -> f64 {
        match *self {
            Formation::RandomDisk { diameter, .. } => diameter,
            Formation::Lattice { .. } | Formation::Line { .. } | Formation::Cross { .. } => {
                let o = self.offsets().unwrap_or_default();
                o.iter()
                    .flat_map(|a| o.iter().map(move |b| (a - b).norm()))
                    .fold(0.0, f64::max)
            }
        }
    }

    /// The agents' offsets from the centre; `None` for a random disk, which is drawn per run.
    pub fn offsets(&self) -> Option<Vec<Vector2<f64>>> {
        Some(match *self {
            Formation::RandomDisk { .. } => return None,
            Formation::Lattice { agents, spacing } => lattice(agents, spacing),
            Formation::Line { agents, spacing } => {
                let mid = 0.5 * agents.saturating_sub(1) as f64;
                (0..agents)
                    .map(|i| Vector2::new(spacing * (i as f64 - mid), 0.0))
                    .collect()
            }
            Formation::Cross { arm, spacing } => {
                let mut v = vec![Vector2::zeros()];
                for d in [
                    Vector2::new(1.0, 0.0),
                    Vector2::new(0.0, 1.0),
                    Vector2::new(-1.0, 0.0),
                    Vector2::new(0.0, -1.0),
                ] {
                    v.extend((1..=arm).map(|k| d * (spacing * k as f64)));
                }
                v
            }
        })
    }

    /// The swarm of run `seed` with a perception range of 1 R (`seed` only places a random
    /// disk).
    ///
    /// # Errors
    /// If a random disk has no connected placement.
    pub fn swarm(&self, seed: u64) -> Result<Swarm, Error> {
        match (*self, self.offsets()) {
            (_, Some(o)) => Ok(Swarm::from_offsets(o, 1.0)),
            (Formation::RandomDisk { agents, diameter }, None) => {
                let mut rng = Pcg64Mcg::seed_from_u64(derive(seed, &[3]));
                Ok(Swarm::place(
                    agents,
                    Shape::Disk { diameter },
                    1.0,
                    &mut rng,
                )?)
            }
            (_, None) => Err("a formation without offsets".into()),
        }
    }
}

/// What one negotiation period decided, and what the agents preferred before diffusion.
#[derive(Clone, Debug, PartialEq)]
pub struct Decisions {
    /// The swarm's direction (circular mean of the agents' decided bearings), radians in
    /// `(−π, π]`; `None` if no agent decided or the bearings cancelled.
    pub swarm: Option<f64>,
    /// Every deciding agent's bearing at the end of the period, radians in `[0, 2π)`.
    pub agents: Vec<f32>,
    /// Every agent's preferred bearing at the end of the gathering phase (the evaluation,
    /// before any opinion was diffused), radians in `[0, 2π)`, for the agents with one.
    pub preferred: Vec<f32>,
}

impl Decisions {
    /// The circular mean of the preferred bearings before diffusion: the direction a swarm
    /// whose agents kept their own preference would take (`None` as for
    /// [`swarm`](Self::swarm)).
    pub fn preferred_mean(&self) -> Option<f64> {
        circular_mean(self.preferred.iter().map(|&b| f64::from(b)))
    }
}

/// `runs` single negotiation periods of `formation` on `field` with the centre at the origin;
/// run `r` uses seed `derive(seed, [r])`. The agents' preferences are read at the end of the
/// gathering phase: every agent evaluates at that second, and no opinion wave can start before
/// the next (an initiation lies 1 to `cycle` ticks into its cycle).
///
/// # Errors
/// If `cfg` does not validate or a random disk cannot be placed.
pub fn decide(
    formation: &Formation,
    field: &Field,
    cfg: RunConfig,
    runs: u32,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<Decisions>, Error> {
    let fixed = formation.offsets().map(|o| Swarm::from_offsets(o, 1.0));
    let gather_s = u64::from(cfg.params.gather_cycles) * cfg.params.wave.cycle.as_millis() / 1000;
    (0..runs)
        .into_par_iter()
        .map(|r| {
            let s = derive(seed, &[r.into()]);
            let placed;
            let swarm = match &fixed {
                Some(f) => f,
                None => {
                    placed = formation.swarm(s)?;
                    &placed
                }
            };
            let mut sim = Sim::new(swarm, field, cfg, Point2::origin(), s)?;
            // Only the preferences and decisions are read.
            sim.without_diversity();
            sim.run_until(gather_s);
            let preferred = sim.agents().iter().filter_map(|a| a.preferred()).collect();
            let p = sim.run_period()?;
            progress.inc();
            Ok(Decisions {
                swarm: p.direction,
                agents: sim.agents().iter().filter_map(|a| a.decision()).collect(),
                preferred,
            })
        })
        .collect()
}

/// The angle from `theta` (radians) to the nearest of `axes` directions evenly spaced from 0
/// (2: 0 and π; 4: 0, π/2, π, 3π/2), in `[0, π / axes]`.
pub fn off_axis(theta: f64, axes: u32) -> f64 {
    let p = TAU / f64::from(axes.max(1));
    let d = theta.rem_euclid(p);
    d.min(p - d)
}

/// Counts of directions near the axes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    /// Directions counted.
    pub n: usize,
    /// Within the tolerance of 0 or π (a line along x).
    pub on_line: usize,
    /// Within the tolerance of 0, π/2, π or 3π/2 (the cross's arms).
    pub on_cross: usize,
    /// Within the tolerance of a diagonal, π/4 + k π/2.
    pub diagonal: usize,
}

impl Tally {
    /// Counts `thetas` (radians) within `tol` radians of the axes.
    pub fn of(thetas: impl IntoIterator<Item = f64>, tol: f64) -> Tally {
        let mut t = Tally::default();
        for th in thetas {
            t.n += 1;
            t.on_line += usize::from(off_axis(th, 2) <= tol);
            t.on_cross += usize::from(off_axis(th, 4) <= tol);
            t.diagonal += usize::from(off_axis(th - 0.25 * PI, 4) <= tol);
        }
        t
    }

    /// `count / n` (0 without directions).
    pub fn frac(&self, count: usize) -> f64 {
        count as f64 / self.n.max(1) as f64
    }
}

/// Histogram of `thetas` (radians) in `bins` equal bins over the circle, bin `k` centred on
/// `k × 360° / bins` (so that the axes fall in the middle of a bin).
pub fn histogram(thetas: impl IntoIterator<Item = f64>, bins: usize) -> Vec<usize> {
    let w = TAU / bins.max(1) as f64;
    let last = bins.max(1) - 1;
    let mut h = vec![0; last + 1];
    for th in thetas {
        let k = ((th + 0.5 * w).rem_euclid(TAU) / w).floor() as usize;
        h[k.min(last)] += 1;
    }
    h
}

/// The page's formations, 61 agents each, neighbours 0.75 R apart along a line: the lattice
/// disk of the page, a random disk of 6 R, a line 45 R long and a cross of arms 11.25 R long.
pub fn formations() -> [Formation; 4] {
    let spacing = LATTICE_SPACING;
    [
        Formation::Lattice {
            agents: 61,
            spacing,
        },
        Formation::RandomDisk {
            agents: 61,
            diameter: 6.0,
        },
        Formation::Line {
            agents: 61,
            spacing,
        },
        Formation::Cross { arm: 15, spacing },
    ]
}

/// One formation's histograms (counts per bin, [`histogram`]), for the page's figure and
/// CSV file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeHistograms {
    /// The formation's name.
    pub name: String,
    /// Number of agents.
    pub size: usize,
    /// Its extent in R, formatted.
    pub extent: String,
    /// Agents' offsets (x, y) in R (one placement for a random disk).
    #[serde(with = "crate::json")]
    pub offsets: Vec<(f64, f64)>,
    /// The swarm's decided direction, one per run that moved.
    pub swarm: Vec<usize>,
    /// The circular mean of the preferences before diffusion, one per run.
    pub swarm_preferred: Vec<usize>,
    /// Every agent's decided bearing.
    pub agents: Vec<usize>,
    /// Every agent's preferred bearing before diffusion.
    pub agents_preferred: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;
    use nalgebra::Vector2;

    fn cfg() -> RunConfig {
        Scenario::builtin("sharp").unwrap().run
    }

    const LINE: Formation = Formation::Line {
        agents: 61,
        spacing: LATTICE_SPACING,
    };
    const CROSS: Formation = Formation::Cross {
        arm: 15,
        spacing: LATTICE_SPACING,
    };

    fn runs(f: &Formation, n: u32) -> Vec<Decisions> {
        decide(f, &Field::default(), cfg(), n, 11, &Progress::hidden()).unwrap()
    }

    #[test]
    fn the_line_and_the_cross_hear_only_along_their_lines() {
        for (f, axes, extent) in [(LINE, 2, 45.0), (CROSS, 4, 22.5)] {
            let s = f.swarm(0).unwrap();
            assert_eq!(s.len(), 61);
            assert!(s.is_connected());
            assert!((f.extent() - extent).abs() < 1e-9, "{}", f.extent());
            let c: Vector2<f64> = s.offsets().iter().sum();
            assert!(c.norm() < 1e-9, "centred");
            for i in 0..s.len() {
                for l in s.neighbours(i) {
                    assert!(off_axis(f64::from(l.bearing), axes) < 1e-6);
                }
            }
        }
        // The line: two neighbours but at the ends; the cross: its centre hears four.
        let line = LINE.swarm(0).unwrap();
        assert_eq!(line.neighbours(0).len(), 1);
        assert_eq!(line.neighbours(30).len(), 2);
        assert_eq!(CROSS.swarm(0).unwrap().neighbours(0).len(), 4);
        let lat = formations()[0].swarm(0).unwrap();
        assert_eq!(lat.len(), 61);
        assert!((formations()[0].extent() - 6.0).abs() < 1e-9);
        // A random disk is drawn per run, from the run's seed.
        let r = formations()[1];
        assert!(r.offsets().is_none());
        assert_eq!(r.swarm(5).unwrap().offsets(), r.swarm(5).unwrap().offsets());
        assert_ne!(r.swarm(5).unwrap().offsets(), r.swarm(6).unwrap().offsets());
    }

    #[test]
    fn agents_prefer_exactly_their_shapes_axes_and_diffusion_leaves_them() {
        for (f, axes) in [(LINE, 2), (CROSS, 4)] {
            let out = runs(&f, 20);
            let mut off = 0;
            for d in &out {
                // Every agent hears noise from its neighbours and prefers one of them.
                assert_eq!(d.preferred.len(), 61, "{}", f.name());
                for &b in &d.preferred {
                    assert!(off_axis(f64::from(b), axes) < 1e-6, "{} {b}", f.name());
                }
                off += d
                    .agents
                    .iter()
                    .filter(|&&b| off_axis(f64::from(b), axes) > 10f64.to_radians())
                    .count();
            }
            // The paper's 10 % diffusion turns many decisions more than 10° off the axes.
            assert!(off > 20 * 61 / 4, "{}: {off}", f.name());
        }
        // The mean of a line's preferences (0 or π, 61 of them) is its axis, up to the f32
        // rounding of π (8.7e-8 rad): at most 61 of those over a lead of one preference.
        for d in runs(&LINE, 20) {
            let off = off_axis(d.preferred_mean().unwrap(), 2);
            assert!(off < 61.0 * 8.8e-8, "{off}");
        }
        // A cross's mean is not: up and right average to a diagonal in some runs.
        let cross = runs(&CROSS, 40);
        let t = Tally::of(cross.iter().filter_map(Decisions::preferred_mean), 0.2);
        assert_eq!(t.n, 40);
        assert!(t.diagonal > 0 && t.on_cross < 40, "{t:?}");
    }

    #[test]
    fn a_random_disk_prefers_every_direction_alike() {
        let out = runs(&formations()[1], 20);
        let t = Tally::of(
            out.iter()
                .flat_map(|d| d.preferred.iter().map(|&b| f64::from(b))),
            10f64.to_radians(),
        );
        assert!(t.n > 1000);
        let f = t.frac(t.on_line);
        assert!((0.07..0.16).contains(&f), "{f} (uniform: 0.11)");
        // The lattice's agents prefer only its six neighbour directions.
        for d in runs(&formations()[0], 5) {
            for &b in &d.preferred {
                assert!(off_axis(f64::from(b), 6) < 1e-6, "{b}");
            }
        }
    }

    #[test]
    fn axes_bins_and_means() {
        assert!((off_axis(PI / 2.0, 2) - PI / 2.0).abs() < 1e-12);
        assert!(off_axis(PI / 2.0, 4) < 1e-12);
        assert!((off_axis(-0.1, 2) - 0.1).abs() < 1e-12);
        assert!((off_axis(PI + 0.1, 4) - 0.1).abs() < 1e-12);
        let deg = |d: f64| d.to_radians();
        // Bin 0 is centred on 0°: it holds −5° up to 5°.
        let h = histogram([0.0, deg(359.0), deg(4.9), deg(5.1), deg(-90.0)], 36);
        assert_eq!((h[0], h[1], h[27]), (3, 1, 1));
        assert_eq!(h.iter().sum::<usize>(), 5);
        let t = Tally::of([0.0, PI, deg(90.0), deg(45.0), deg(12.0)], deg(10.0));
        assert_eq!((t.n, t.on_line, t.on_cross, t.diagonal), (5, 2, 3, 1));
        assert!((circular_mean([0.0, deg(90.0)]).unwrap() - deg(45.0)).abs() < 1e-12);
        assert_eq!(circular_mean([0.0, PI]), None);
        assert_eq!(circular_mean([]), None);
    }
}
