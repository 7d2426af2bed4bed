//! The discussion's claim about the swarm's shape (paper section 5): on a field of independent
//! random values, "if agents are distributed e.g. in a line, the preferred direction can only be
//! along the linear distribution of the swarm", and "a swarm shaped as a perfect cross will
//! theoretically move like the king on a chess board, solely up-down-left-right".
//!
//! Three formations of comparable size are run for one negotiation period each on the field
//! X = 0 everywhere, so that every reading is the simulator's noise alone (independent uniform
//! values): the page's lattice disk, a line along x and a cross of two perpendicular lines
//! ([`Formation`]). Each run records the swarm's decided direction (the circular mean,
//! [`Period::direction`](crate::swarm::sim::Period)) and every agent's decided bearing
//! ([`Agent::decision`](crate::swarm::sim::Agent)); [`Tally`] counts how many fall within a
//! tolerance of the line's two or the cross's four axes.

use protocol::direction::Opposite;
use std::f64::consts::{PI, TAU};
use std::path::Path;

use nalgebra::{Point2, Vector2};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use rayon::prelude::*;
use serde::Serialize;

use crate::pages::figures as shapes_plot;
use crate::progress::Progress;
use crate::seeds::derive;
use crate::stats::circular_mean;
use crate::swarm::experiment::Error;
use crate::swarm::field::Field;
use crate::swarm::geometry::{Shape, Swarm, lattice};
use crate::swarm::scenario::LATTICE_SPACING;
use crate::swarm::sim::{RunConfig, Sim};

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

/// Runs per formation on the page.
pub const RUNS: u32 = 300;
/// Bins of the histograms over the circle (10° each).
pub const BINS: usize = 36;
/// A direction is on an axis within this many degrees of it.
pub const TOLERANCE_DEG: f64 = 10.0;
/// The page's claim threshold: the claim holds if at least this fraction is on the axes.
pub const CLAIM: f64 = 0.9;

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

/// One formation's histograms (counts per bin, [`histogram`]) for the figure and the CSV file.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeHistograms {
    /// The formation's name.
    pub name: &'static str,
    /// Number of agents.
    pub size: usize,
    /// Its extent in R, formatted.
    pub extent: String,
    /// Agents' offsets (x, y) in R (one placement for a random disk).
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

/// The four sets of directions of one formation's runs, in radians.
struct Directions {
    swarm: Vec<f64>,
    swarm_preferred: Vec<f64>,
    agents: Vec<f64>,
    agents_preferred: Vec<f64>,
}

impl Directions {
    /// The four sets counted on the axes: agents' preferences, agents' decisions, mean of the
    /// preferences, swarm's direction.
    fn tallies(&self, tol: f64) -> [Tally; 4] {
        [
            &self.agents_preferred,
            &self.agents,
            &self.swarm_preferred,
            &self.swarm,
        ]
        .map(|v| Tally::of(v.iter().copied(), tol))
    }

    fn of(runs: &[Decisions]) -> Directions {
        let all = |f: fn(&Decisions) -> &Vec<f32>| -> Vec<f64> {
            runs.iter()
                .flat_map(|d| f(d).iter().map(|&b| f64::from(b)))
                .collect()
        };
        Directions {
            swarm: runs.iter().filter_map(|d| d.swarm).collect(),
            swarm_preferred: runs.iter().filter_map(Decisions::preferred_mean).collect(),
            agents: all(|d| &d.agents),
            agents_preferred: all(|d| &d.preferred),
        }
    }
}

/// One row of a page table: the formation, then the four fractions on the axes.
#[derive(Clone, Debug, Serialize)]
pub struct ShapeRow {
    /// The formation's name.
    pub name: &'static str,
    /// Agents' preferences before diffusion.
    pub agents_preferred: String,
    /// Agents' decisions.
    pub agents: String,
    /// The circular mean of the preferences before diffusion.
    pub swarm_preferred: String,
    /// The swarm's decided direction.
    pub swarm: String,
}

impl ShapeRow {
    /// The row of `name` from its [`Directions::tallies`], each the share `count` picks.
    fn of(name: &'static str, t: &[Tally; 4], count: fn(&Tally) -> usize) -> ShapeRow {
        let [a, b, c, e] = t.map(|t| pct(t.frac(count(&t))));
        ShapeRow {
            name,
            agents_preferred: a,
            agents: b,
            swarm_preferred: c,
            swarm: e,
        }
    }
}

/// One formation on the page.
#[derive(Clone, Debug, Serialize)]
pub struct FormationNote {
    /// The formation's name.
    pub name: &'static str,
    /// Number of agents.
    pub agents: usize,
    /// Extent in R.
    pub extent: String,
    /// Mean number of neighbours (a random disk: over the runs' placements).
    pub degree: String,
    /// Runs whose swarm moved (the decided bearings did not cancel).
    pub moved: u32,
}

/// What the page's section shows (`templates/reproduction/shapes.md.j2`).
#[derive(Clone, Debug, Serialize)]
pub struct ShapesSection {
    /// Runs per formation.
    pub runs: u32,
    /// The diffusion rate, per cent.
    pub diffusion: String,
    /// The tolerance in degrees.
    pub tolerance: String,
    /// The claim threshold, per cent.
    pub claim: String,
    /// Spacing of the line and the cross, in R.
    pub spacing: String,
    /// The fraction of a uniform distribution within the tolerance of 2 axes, and of 4.
    pub uniform: [String; 2],
    /// The formations.
    pub formations: Vec<FormationNote>,
    /// Within the tolerance of 0° or 180°.
    pub on_line: Vec<ShapeRow>,
    /// Within the tolerance of the four axes.
    pub on_cross: Vec<ShapeRow>,
    /// Within the tolerance of the four diagonals.
    pub diagonal: Vec<ShapeRow>,
    /// Key numbers for the text, per cent, by formation and quantity ([`Key`]).
    pub key: Key,
    /// The line's agents' preferences (before diffusion) lie on its axis ([`CLAIM`]).
    pub line_preferred_holds: bool,
    /// The cross's agents' preferences lie on its four axes.
    pub cross_preferred_holds: bool,
    /// The line's agents' decisions lie on its axis.
    pub line_agents_hold: bool,
    /// The cross's agents' decisions lie on its four axes.
    pub cross_agents_hold: bool,
    /// The line swarm's direction lies on its axis.
    pub line_swarm_holds: bool,
    /// The cross swarm's direction lies on its four axes.
    pub cross_swarm_holds: bool,
    /// The mean of the line's preferences lies on its axis.
    pub line_swarm_preferred_holds: bool,
    /// The mean of the cross's preferences lies on its four axes.
    pub cross_swarm_preferred_holds: bool,
    /// The figure's file name.
    pub figure: &'static str,
    /// The line and the cross again with the other rule for an exactly opposite opinion
    /// ([`Opposite::Keep`]): their agents' decisions and their swarm's direction on their axes.
    pub keep: Vec<ShapeRow>,
    /// Whether the line's swarm moves along its axis in at least [`CLAIM`] of the runs, with
    /// the counter-clockwise rule and with [`Opposite::Keep`].
    pub line_holds_by_rule: [bool; 2],
    /// The same for the cross and its four arms.
    pub cross_holds_by_rule: [bool; 2],
    /// The CSV file's name.
    pub csv: &'static str,
}

/// The numbers the section's text quotes.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Key {
    /// The line: its agents' preferences, agents' decisions, mean of preferences and swarm's
    /// direction on 0° or 180°.
    pub line: Option<ShapeRow>,
    /// The cross: the same on its four axes.
    pub cross: Option<ShapeRow>,
    /// The cross: the same on the four diagonals.
    pub cross_diagonal: Option<ShapeRow>,
    /// The lattice disk on 0° or 180°.
    pub lattice: Option<ShapeRow>,
    /// The random disk on 0° or 180°.
    pub random: Option<ShapeRow>,
}

fn pct(v: f64) -> String {
    format!("{:.0} %", 100.0 * v)
}

/// Runs every formation of [`formations`] [`RUNS`] times on X = 0 with `cfg` (formation `k`
/// uses seed `derive(seed, [k])`), writes `figs/shapes-directions.svg` and `.csv`, and returns
/// the page's section.
///
/// # Errors
/// If a run fails or a file cannot be written.
pub fn reproduce(
    figs: &Path,
    cfg: RunConfig,
    seed: u64,
    progress: &Progress,
) -> Result<ShapesSection, Error> {
    let field = Field::default();
    let tol = TOLERANCE_DEG.to_radians();
    let mut tables = Tables::default();
    for (k, f) in formations().iter().enumerate() {
        let s = derive(seed, &[k as u64]);
        let runs = decide(f, &field, cfg, RUNS, s, progress)?;
        tables.add(f, &runs, s, tol)?;
    }
    let (keep, keep_holds) = with_keep(cfg, seed, tol, progress)?;
    let diffusion = format!("{:.0}", 100.0 * f64::from(cfg.params.diffusion));
    shapes_plot::write_shapes_csv(&figs.join(CSV), &tables.hists)?;
    shapes_plot::shapes_figure(&figs.join(FIGURE), &tables.hists, RUNS, &diffusion)?;
    Ok(tables.section(diffusion, keep, keep_holds))
}

/// What [`reproduce`] gathers formation by formation: the histograms of the figure, the notes
/// and rows of the tables, and per formation whether its directions hold the claim on its own
/// axes (agents before diffusion, agents, swarm before diffusion, swarm).
#[derive(Default)]
struct Tables {
    hists: Vec<ShapeHistograms>,
    notes: Vec<FormationNote>,
    on_line: Vec<ShapeRow>,
    on_cross: Vec<ShapeRow>,
    diagonal: Vec<ShapeRow>,
    holds: std::collections::HashMap<&'static str, [bool; 4]>,
}

impl Tables {
    /// Formation `f`'s runs (from seed `s`), counted with tolerance `tol`.
    fn add(&mut self, f: &Formation, runs: &[Decisions], s: u64, tol: f64) -> Result<(), Error> {
        let d = Directions::of(runs);
        let t = d.tallies(tol);
        let row = |count: fn(&Tally) -> usize| ShapeRow::of(f.name(), &t, count);
        self.on_line.push(row(|t| t.on_line));
        self.on_cross.push(row(|t| t.on_cross));
        self.diagonal.push(row(|t| t.diagonal));
        let axes: fn(&Tally) -> usize = match f {
            Formation::Cross { .. } => |t| t.on_cross,
            _ => |t| t.on_line,
        };
        self.holds
            .insert(f.name(), t.map(|t| t.frac(axes(&t)) >= CLAIM));
        let swarm0 = f.swarm(derive(s, &[0]))?;
        let degree = match f {
            Formation::RandomDisk { .. } => {
                let mut sum = 0.0;
                for r in 0..RUNS {
                    sum += f.swarm(derive(s, &[r.into()]))?.mean_degree();
                }
                sum / f64::from(RUNS)
            }
            _ => swarm0.mean_degree(),
        };
        // One decimal, without a trailing ".0" beyond 10 R (45, 22.5, 6.0).
        let extent = match format!("{:.1}", f.extent()) {
            e if f.extent() >= 10.0 => e.trim_end_matches(".0").to_owned(),
            e => e,
        };
        self.notes.push(FormationNote {
            name: f.name(),
            agents: f.agents(),
            extent: extent.clone(),
            degree: format!("{degree:.1}"),
            moved: d.swarm.len() as u32,
        });
        self.hists.push(ShapeHistograms {
            name: f.name(),
            size: f.agents(),
            extent,
            offsets: swarm0.offsets().iter().map(|o| (o.x, o.y)).collect(),
            swarm: histogram(d.swarm.iter().copied(), BINS),
            swarm_preferred: histogram(d.swarm_preferred.iter().copied(), BINS),
            agents: histogram(d.agents.iter().copied(), BINS),
            agents_preferred: histogram(d.agents_preferred.iter().copied(), BINS),
        });
        Ok(())
    }

    /// The page's section: these tables, with diffusion `diffusion` (%), and the line and the
    /// cross run again with [`Opposite::Keep`] (`keep`, and whether each holds the claim).
    fn section(
        self,
        diffusion: String,
        keep: Vec<ShapeRow>,
        keep_holds: (bool, bool),
    ) -> ShapesSection {
        let h = |name: &str, i: usize| self.holds.get(name).is_some_and(|v| v[i]);
        let find = |rows: &[ShapeRow], name: &str| rows.iter().find(|r| r.name == name).cloned();
        let key = Key {
            line: find(&self.on_line, "line"),
            cross: find(&self.on_cross, "cross"),
            cross_diagonal: find(&self.diagonal, "cross"),
            lattice: find(&self.on_line, "lattice disk"),
            random: find(&self.on_line, "random disk"),
        };
        ShapesSection {
            runs: RUNS,
            diffusion,
            tolerance: format!("{TOLERANCE_DEG:.0}"),
            claim: pct(CLAIM),
            spacing: LATTICE_SPACING.to_string(),
            uniform: [2.0, 4.0].map(|a| pct(a * 2.0 * TOLERANCE_DEG / 360.0)),
            line_preferred_holds: h("line", 0),
            cross_preferred_holds: h("cross", 0),
            line_agents_hold: h("line", 1),
            cross_agents_hold: h("cross", 1),
            line_swarm_preferred_holds: h("line", 2),
            cross_swarm_preferred_holds: h("cross", 2),
            line_swarm_holds: h("line", 3),
            cross_swarm_holds: h("cross", 3),
            figure: FIGURE,
            csv: CSV,
            line_holds_by_rule: [h("line", 3), keep_holds.0],
            cross_holds_by_rule: [h("cross", 3), keep_holds.1],
            keep,
            formations: self.notes,
            on_line: self.on_line,
            on_cross: self.on_cross,
            diagonal: self.diagonal,
            key,
        }
    }
}

/// The line and the cross (the formations whose agents hear exactly opposite bearings) run
/// again, with the same seeds, with [`Opposite::Keep`]: their rows on their own axes, and
/// whether each swarm (line, cross) moves along them in at least [`CLAIM`] of the runs.
fn with_keep(
    cfg: RunConfig,
    seed: u64,
    tol: f64,
    progress: &Progress,
) -> Result<(Vec<ShapeRow>, (bool, bool)), Error> {
    let cfg = RunConfig {
        opposite: Opposite::Keep,
        ..cfg
    };
    let field = Field::default();
    let mut rows = Vec::new();
    let mut holds = (false, false);
    for (k, f) in formations().iter().enumerate() {
        let axes: fn(&Tally) -> usize = match f {
            Formation::Cross { .. } => |t| t.on_cross,
            Formation::Line { .. } => |t| t.on_line,
            _ => continue,
        };
        let runs = decide(f, &field, cfg, RUNS, derive(seed, &[k as u64]), progress)?;
        let t = Directions::of(&runs).tallies(tol);
        let h = t[3].frac(axes(&t[3])) >= CLAIM;
        match f {
            Formation::Cross { .. } => holds.1 = h,
            _ => holds.0 = h,
        }
        rows.push(ShapeRow::of(f.name(), &t, axes));
    }
    Ok((rows, holds))
}

/// Formations [`with_keep`] runs again (the line and the cross).
pub const KEEP_FORMATIONS: u32 = 2;

/// The figure's file name under `docs/figures/`.
pub const FIGURE: &str = "shapes-directions.svg";
/// The CSV file's name under `docs/figures/`.
pub const CSV: &str = "shapes-directions.csv";

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swarm::scenario::Scenario;
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
        // The mean of a line's preferences (0 or π, 61 of them) is exactly its axis.
        for d in runs(&LINE, 20) {
            assert!(off_axis(d.preferred_mean().unwrap(), 2) < 1e-6);
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

    #[test]
    fn the_section_is_computed_from_the_runs() {
        let dir = std::env::temp_dir().join(format!("cimax-shapes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let sec = reproduce(&dir, cfg(), 3, &Progress::hidden()).unwrap();
        assert_eq!(sec.formations.len(), 4);
        assert_eq!(sec.uniform, ["11 %".to_owned(), "22 %".to_owned()]);
        assert_eq!(sec.key.line.as_ref().unwrap().agents_preferred, "100 %");
        assert_eq!(sec.key.cross.as_ref().unwrap().agents_preferred, "100 %");
        assert!(sec.line_preferred_holds && sec.cross_preferred_holds);
        assert!(sec.line_swarm_preferred_holds);
        let csv = std::fs::read_to_string(dir.join(CSV)).unwrap();
        assert_eq!(csv.lines().count(), 1 + 4 * 4 * BINS);
        assert!(dir.join(FIGURE).exists());
        let md = crate::report::page::render(
            "reproduction/shapes.md.j2",
            serde_json::json!({ "shapes": sec }),
        )
        .unwrap();
        assert!(md.contains("| line | 61 | 45 |"), "{md}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
