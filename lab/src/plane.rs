//! The robot program on a plane: `cimax arena --field ...` and `cimax arena sweep`.
//!
//! Robots on a line, the paper's hexagonal lattice or a random disk, each with K receivers,
//! run the unchanged robot program (`firmware::Robot`) over the emulated light medium
//! (`hal-emu`). What they sense is one of the 2D simulator's fields ([`hal_emu::world::field`], the
//! scenarios of `cimax swarm`), read where each robot is; every negotiation period the swarm
//! moves rigidly by the scenario's step (0.33 R) along the circular mean of the sectors its
//! LEDs show ([`hal_emu::world::arena::swarm_heading`]). A run succeeds by the scenario's criterion
//! (sharp: the centre of mass within 0.33 R of the border; gradient: at x >= 2.33) within the
//! given number of moves, as in the paper's Figs. 6 and 9.

use hal_emu::world::arena::{Motion, Move};
use hal_emu::{ArenaConfig, Environment, MediumParams, Point2};
use nalgebra::Vector2;
use protocol::{MAX_TAGS, Params};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

use swarm_sim::experiment::SweepPoint;
use swarm_sim::geometry::{PlacementError, Shape, Swarm};
use swarm_sim::progress::Progress;
use swarm_sim::scenario::{MAX_EXTENT, Placement, Scenario, Success};

/// How the robots are placed on the plane: as the 2D simulator places a swarm
/// ([`Placement`]), or in a way only the arena has (a line, a file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// [`Placement::Lattice`]: the nodes of a triangular lattice of spacing 0.75 R nearest the
    /// centre (61: the paper's disk of 6 R). [`Placement::Random`]: uniformly at random in a
    /// disk with the density of the paper's (61 robots in 6 R), redrawn until connected
    /// (`--shape disk`).
    Placed(Placement),
    /// In a line along x, 0.75 R apart.
    Line,
    /// Where a file says (`--positions FILE`, [`read_positions`]).
    File,
}

impl Layout {
    /// Its name in the arena's summaries and figure titles: `Line`, `Lattice`, `Disk`, `File`.
    pub fn label(self) -> &'static str {
        match self {
            Layout::Placed(Placement::Lattice) => "Lattice",
            Layout::Placed(Placement::Random) => "Disk",
            Layout::Line => "Line",
            Layout::File => "File",
        }
    }
}

/// Spacing of the line and the lattice, in R: 61 lattice robots fill the paper's 6 R disk.
pub const SPACING: f64 = swarm_sim::scenario::LATTICE_SPACING;

/// One plane experiment.
#[derive(Clone, Debug)]
pub struct PlaneSpec {
    /// The field, the success criterion and the step, from a `cimax swarm` scenario.
    pub scenario: Scenario,
    /// How the robots are placed.
    pub placement: Layout,
    /// Number of robots.
    pub robots: usize,
    /// Receive sectors per robot (2 to 8).
    pub sectors: u8,
    /// Where the centre of mass starts, in R along x.
    pub x_init: f64,
    /// Negotiation periods (moves) per run.
    pub moves: u32,
    /// The light medium (its `range` is R in metres).
    pub medium: MediumParams,
    /// Protocol parameters (`sectors` is set from `sectors`).
    pub params: Params,
    /// Positions relative to the swarm, in R, for [`Layout::File`] (recentred on their
    /// centre of mass).
    pub file_positions: Vec<Vector2<f64>>,
    /// What the light sensors report (`--readings`).
    pub readings: hal_emu::Readings,
    /// Robots in the loop (`--hil`): places taken by robots running the real image elsewhere.
    pub hil: Vec<hal_emu::world::hil::HilRobot>,
    /// How often the robots read their sensors, if not the robot program's default (`--cycle`
    /// scales it).
    pub sample_period: Option<protocol::Duration>,
}

impl PlaneSpec {
    /// The experiment in a few words: robots, placement, sectors, field, start and moves.
    pub fn summary(&self) -> String {
        format!(
            "{} robots ({}, K = {}) on field {} from x = {}, {} moves",
            self.robots,
            self.placement.label(),
            self.sectors,
            self.scenario.name,
            self.x_init,
            self.moves
        )
    }
}

/// Reads robot positions, in R: one robot per line, `x y` or `x,y`; empty lines and lines
/// starting with `#` are skipped. The positions are recentred on their centre of mass.
///
/// # Errors
/// A [`PositionsError`] naming the line and what is wrong with it (not two finite numbers, a
/// coordinate beyond [`MAX_EXTENT`], two robots in one place, a robot farther than 1 R, the
/// light's range, from every other), or that there are fewer than two robots or more than 1000.
pub fn read_positions(text: &str, source: &str) -> Result<Vec<Vector2<f64>>, PositionsError> {
    let file = || source.to_string();
    // Each robot with its line, for the errors.
    let mut out: Vec<(usize, Vector2<f64>)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let [x, y] = fields.as_slice() else {
            return Err(PositionsError::NotTwo {
                file: file(),
                line: i + 1,
                text: line.to_string(),
            });
        };
        let num = |f: &str| match f.parse::<f64>() {
            Ok(v) if v.is_finite() && v.abs() <= MAX_EXTENT => Ok(v),
            Ok(v) if v.is_finite() => Err(PositionsError::TooFar {
                file: file(),
                line: i + 1,
                field: f.to_string(),
            }),
            _ => Err(PositionsError::NotFinite {
                file: file(),
                line: i + 1,
                field: f.to_string(),
            }),
        };
        let p = Vector2::new(num(x)?, num(y)?);
        if let Some((j, _)) = out.iter().find(|(_, q)| *q == p) {
            return Err(PositionsError::SamePlace {
                file: file(),
                line: i + 1,
                at: p,
                other: *j,
            });
        }
        out.push((i + 1, p));
    }
    if !(2..=1000).contains(&out.len()) {
        return Err(PositionsError::Count {
            file: file(),
            robots: out.len(),
        });
    }
    for (line, p) in &out {
        let nearest = out
            .iter()
            .filter(|(l, _)| l != line)
            .map(|(_, q)| (q - p).norm())
            .fold(f64::INFINITY, f64::min);
        if nearest > 1.0 {
            return Err(PositionsError::OutOfRange {
                file: file(),
                line: *line,
                at: *p,
                nearest,
            });
        }
    }
    let centre = out.iter().fold(Vector2::zeros(), |s, (_, p)| s + p) / out.len() as f64;
    Ok(out.into_iter().map(|(_, p)| p - centre).collect())
}

/// Why [`read_positions`] refused a positions file; each names the file (and the line).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PositionsError {
    /// A line that is not two fields.
    #[error("{file}:{line}: expected two numbers `x y` (in R), got {text:?}")]
    NotTwo {
        /// The file, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The line's text, trimmed.
        text: String,
    },
    /// A coordinate beyond [`MAX_EXTENT`].
    #[error("{file}:{line}: {field} is too far: at most {MAX_EXTENT} R from the origin")]
    TooFar {
        /// The file, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The coordinate as written.
        field: String,
    },
    /// A coordinate that is no finite number.
    #[error("{file}:{line}: {field:?} is not a finite number")]
    NotFinite {
        /// The file, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The coordinate as written.
        field: String,
    },
    /// Two robots in one place.
    #[error("{file}:{line}: two robots in one place: ({}, {}) is also on line {other}", at.x, at.y)]
    SamePlace {
        /// The file, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The place.
        at: Vector2<f64>,
        /// The other robot's line.
        other: usize,
    },
    /// Fewer than 2 robots or more than 1000.
    #[error("{file}: {robots} robots; 2 to 1000 are needed")]
    Count {
        /// The file, as named.
        file: String,
        /// Its robots.
        robots: usize,
    },
    /// A robot farther than 1 R (the light's range) from every other.
    #[error(
        "{file}:{line}: the robot at ({}, {}) is out of everyone's range: the nearest is \
         {nearest:.2} R away, the light carries 1 R",
        at.x,
        at.y
    )]
    OutOfRange {
        /// The file, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// The robot's place.
        at: Vector2<f64>,
        /// The distance to the nearest robot, R.
        nearest: f64,
    },
}

/// What one run did.
#[derive(Clone, Debug, Serialize)]
pub struct PlaneRun {
    /// The run's seed.
    pub seed: u64,
    /// True if the criterion was met within the moves.
    pub success: bool,
    /// The first move after which the criterion held, if any.
    pub moves_to_success: Option<u32>,
    /// Per negotiation period: the fraction of robots whose LEDs show the sector nearest the
    /// swarm's decision.
    pub consensus: Vec<f64>,
    /// The centre of mass at the end, in R.
    pub final_position: [f64; 2],
    /// The LEDs at the end: `R` (sector 0, +x) and `L` with two sectors, else the sector's
    /// digit; `-` off.
    pub leds: String,
    /// Emulated seconds.
    pub emulated_s: f64,
    /// Wall seconds.
    pub wall_s: f64,
    /// Each robot in the loop's link (`--hil`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub hil: Vec<hal_emu::world::hil::HilReport>,
}

/// Why a plane experiment could not be set up.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneError {
    /// No connected placement.
    Placement(PlacementError),
    /// The emulator refused the configuration.
    Arena(String),
    /// A sweep over a scenario without a success criterion.
    NoCriterion(String),
}

impl std::fmt::Display for PlaneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlaneError::Placement(e) => write!(f, "placing the robots: {e}"),
            PlaneError::Arena(e) => write!(f, "emulator: {e}"),
            PlaneError::NoCriterion(s) => write!(f, "scenario {s} has no success criterion"),
        }
    }
}

impl std::error::Error for PlaneError {}

/// The robots' positions relative to the centre of mass, in R.
///
/// # Errors
/// [`PlacementError`] if a random disk cannot be made connected.
pub fn positions(spec: &PlaneSpec, seed: u64) -> Result<Vec<Vector2<f64>>, PlacementError> {
    let n = spec.robots;
    let shape = match spec.placement {
        Layout::Line => {
            let mid = (n as f64 - 1.0) / 2.0;
            return Ok((0..n)
                .map(|i| Vector2::new((i as f64 - mid) * SPACING, 0.0))
                .collect());
        }
        Layout::File => return Ok(spec.file_positions.clone()),
        Layout::Placed(Placement::Lattice) => Shape::Lattice { spacing: SPACING },
        // The paper's density: 61 robots in a disk of diameter 6 R.
        Layout::Placed(Placement::Random) => Shape::Disk { diameter: 6.0 }.scaled_for(61, n),
    };
    let mut rng = Pcg64Mcg::seed_from_u64(swarm_sim::seeds::derive(seed, &[7]));
    Ok(Swarm::place(n, shape, 1.0, &mut rng)?.offsets().to_vec())
}

/// Robot ids whose tags (`id mod 16`) differ between robots close to each other: each robot in
/// turn takes the tag whose nearest holder is farthest away (greedy), so that robots sharing a
/// tag are as far apart as the swarm allows (on the lattice at least 3 spacings). Robots
/// within a message's reach should not share a tag (`docs/protocol.md` §5.1).
pub fn spread_ids(positions: &[Vector2<f64>]) -> Vec<u16> {
    let mut tags: Vec<u16> = Vec::with_capacity(positions.len());
    for p in positions {
        let nearest = |t: u16| {
            tags.iter()
                .zip(positions)
                .filter(|(tag, _)| **tag == t)
                .map(|(_, q)| (p - q).norm())
                .fold(f64::INFINITY, f64::min)
        };
        // The first tag whose nearest holder is farthest (an unused tag first).
        let tag = (0..MAX_TAGS as u16)
            .map(|t| (t, nearest(t)))
            .fold(
                (0, f64::NEG_INFINITY),
                |best, c| if c.1 > best.1 { c } else { best },
            )
            .0;
        tags.push(tag);
    }
    // Distinct ids with these tags: the k-th robot with tag t gets 16 k + t.
    let mut count = [0u16; MAX_TAGS];
    tags.iter()
        .map(|&t| {
            let k = &mut count[usize::from(t)];
            *k += 1;
            (*k - 1) * MAX_TAGS as u16 + t
        })
        .collect()
}

/// The arena configuration of one run with `seed`.
///
/// # Errors
/// [`PlaneError::Placement`] if the robots cannot be placed.
pub fn config(spec: &PlaneSpec, seed: u64) -> Result<ArenaConfig, PlaneError> {
    let rel = positions(spec, seed).map_err(PlaneError::Placement)?;
    let range = spec.medium.range;
    let metres = rel.iter().map(|v| Point2::from(v * range)).collect();
    let mut params = spec.params;
    params.sectors = spec.sectors;
    let period = params.nominal_period();
    let mut c = ArenaConfig::line(
        Vec::new(),
        1.0,
        period.saturating_mul(u64::from(spec.moves)),
        seed,
    );
    c.positions = metres;
    c.ids = Some(spread_ids(&rel));
    c.robot.params = params;
    c.medium = spec.medium;
    c.env = Environment::plane(
        spec.scenario.field.clone(),
        rel.iter().map(|v| Point2::from(*v)).collect(),
        Vector2::new(spec.x_init, 0.0),
    );
    let (base, gain, noise) = sensor_scale(&spec.scenario);
    if let Some(f) = c.env.field.as_mut() {
        f.base = base;
        f.gain = gain;
    }
    c.env.noise = noise;
    c.env.readings = spec.readings;
    c.motion = Some(Motion {
        period,
        step: spec.scenario.run.step,
    });
    c.hil = spec.hil.clone();
    if let Some(p) = spec.sample_period {
        c.robot.sample_period = p;
    }
    Ok(c)
}

/// How the sensor reads the scenario's field: `(base, gain, noise)`, the level of X being
/// `base + gain · X` and the noise ± `noise` levels. The field's range where a swarm can go
/// (|x|, |y| ≤ 10 R) maps into 30..=255 with at most 34 levels per unit of X (the sharp border's
/// 0 and 5 read 30 and 200, the lab's dark and lit); the paper's noise of width `noise` in X
/// becomes ± `gain · noise / 2` levels. A steeper gain would saturate the gradient's ramp
/// (2.5 per R) 2.6 R into it, where the swarm must go, and stall it there.
pub fn sensor_scale(scenario: &Scenario) -> (f64, f64, u8) {
    let (lo, hi) = scenario.field.range_over((-10.0, 10.0), (-10.0, 10.0));
    let gain = if hi > lo {
        (225.0 / (hi - lo)).min(34.0)
    } else {
        34.0
    };
    let noise = (gain * scenario.run.noise / 2.0).round().clamp(0.0, 255.0) as u8;
    (30.0 - gain * lo, gain, noise)
}

/// The centre after each move, and the first move after which `success` held.
fn judge(moves: &[Move], step: f64, success: &Success) -> (Option<u32>, Point2<f64>) {
    let mut first = None;
    let mut last = moves.first().map_or(Point2::origin(), |m| m.centre);
    for (k, m) in moves.iter().enumerate() {
        let after = match m.heading {
            Some(h) => m.centre + Vector2::new(h.cos(), h.sin()) * step,
            None => m.centre,
        };
        if first.is_none() && success.met(after) {
            first = Some(k as u32 + 1);
        }
        last = after;
    }
    (first, last)
}

/// Runs one experiment with `seed`.
///
/// # Errors
/// A [`PlaneError`] if it cannot be set up.
pub fn run(spec: &PlaneSpec, seed: u64) -> Result<PlaneRun, PlaneError> {
    Ok(run_traced(spec, seed, false)?.0)
}

/// Runs one experiment with `seed`, with its configuration and, if `trace`, its trace.
///
/// # Errors
/// A [`PlaneError`] if it cannot be set up.
pub fn run_traced(
    spec: &PlaneSpec,
    seed: u64,
    trace: bool,
) -> Result<(PlaneRun, ArenaConfig, Vec<hal_emu::TraceEvent>), PlaneError> {
    let mut cfg = config(spec, seed)?;
    cfg.trace = trace;
    let mut report = hal_emu::run(&cfg).map_err(|e| PlaneError::Arena(e.to_string()))?;
    let events = std::mem::take(&mut report.trace);
    // A field without a criterion (the cloud) is reported, never a success.
    let never = Success::BeyondX { x: f64::INFINITY };
    let success = spec.scenario.success.unwrap_or(never);
    let (first, end) = judge(&report.moves, spec.scenario.run.step, &success);
    let leds = hal_emu::judge::leds_str(&report.leds_at(protocol::Instant::MAX));
    let run = PlaneRun {
        seed,
        success: first.is_some(),
        moves_to_success: first,
        consensus: report.moves.iter().map(|m| m.consensus).collect(),
        final_position: [end.x, end.y],
        leds,
        emulated_s: report.emulated.as_secs_f64(),
        wall_s: report.wall.as_secs_f64(),
        hil: report.hil,
    };
    Ok((run, cfg, events))
}

/// The viewer's header of a plane run: the set-up, the goal and the verdict.
pub fn viewer_header(
    spec: &PlaneSpec,
    cfg: &ArenaConfig,
    run: &PlaneRun,
    trace: &[hal_emu::TraceEvent],
) -> viewer::Header {
    let mut h = viewer::header_of(cfg, trace);
    h.title = format!("cimax arena: {}, seed {}", spec.summary(), run.seed);
    if let Some(f) = h.field.as_mut() {
        f.label = format!("field {} (X)", spec.scenario.name);
    }
    h.goal = viewer::goal_of(spec.scenario.success);
    h.verdict = Some(viewer::move_verdict(
        h.goal.as_ref(),
        run.moves_to_success,
        spec.moves,
        "moves",
        run.final_position,
        run.leds.clone(),
    ));
    h
}

/// The sweep of `cimax arena sweep`: `base` started at each of `xs` (its `x_init` replaced),
/// `runs` runs each with seeds `seed`, `seed + 1`, ..., in parallel; per position the success
/// rate and the mean moves to success. The result does not depend on the number of threads.
/// Unit `p * runs + k` is run `k` at `xs[p]` ([`sweep_run`]), put together by
/// [`sweep_points`].
///
/// # Errors
/// A [`PlaneError`] if a run cannot be set up.
pub fn sweep(
    base: &PlaneSpec,
    xs: &[f64],
    runs: u64,
    seed: u64,
    progress: &Progress,
) -> Result<Vec<SweepPoint>, PlaneError> {
    use rayon::prelude::*;
    let units = xs.len() as u64 * runs;
    let done: Vec<SweepRun> = (0..units)
        .into_par_iter()
        .map(|k| {
            let r = sweep_run(base, xs, runs, seed, k);
            progress.inc();
            r
        })
        .collect::<Result<_, _>>()?;
    Ok(sweep_points(xs, runs, &done))
}

/// What a sweep keeps of a run ([`PlaneRun`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SweepRun {
    /// The criterion was met within the moves.
    pub success: bool,
    /// The first move after which it held.
    pub moves_to_success: Option<u32>,
}

/// Unit `k` of [`sweep`]: run `k % runs` (seed `seed + k % runs`) from `xs[k / runs]`.
///
/// # Errors
/// A [`PlaneError`] if the run cannot be set up or `k` is beyond the sweep.
pub fn sweep_run(
    base: &PlaneSpec,
    xs: &[f64],
    runs: u64,
    seed: u64,
    k: u64,
) -> Result<SweepRun, PlaneError> {
    let runs = runs.max(1);
    let x = usize::try_from(k / runs)
        .ok()
        .and_then(|p| xs.get(p))
        .ok_or_else(|| PlaneError::Arena(format!("sweep unit {k} is beyond the sweep")))?;
    let spec = PlaneSpec {
        x_init: *x,
        ..base.clone()
    };
    let r = run(&spec, seed.wrapping_add(k % runs))?;
    Ok(SweepRun {
        success: r.success,
        moves_to_success: r.moves_to_success,
    })
}

/// The points of a sweep from its units' runs ([`sweep_run`], in unit order).
pub fn sweep_points(xs: &[f64], runs: u64, done: &[SweepRun]) -> Vec<SweepPoint> {
    xs.iter()
        .enumerate()
        .map(|(p, &x)| {
            let from = (p as u64).saturating_mul(runs);
            let mine = usize::try_from(from)
                .ok()
                .and_then(|a| done.get(a..a.saturating_add(runs as usize)))
                .unwrap_or_default();
            let moves: Vec<f64> = mine
                .iter()
                .filter_map(|r| r.moves_to_success.map(f64::from))
                .collect();
            SweepPoint {
                x_init: x,
                runs: mine.len() as u32,
                successes: mine.iter().filter(|r| r.success).count() as u32,
                mean_success_periods: swarm_sim::stats::mean(&moves),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_files_are_read_and_their_errors_name_the_line() {
        let p = read_positions("# a triangle\n0 0\n\n0.75,0\n0.375 0.65\n", "t.txt").unwrap();
        assert_eq!(p.len(), 3);
        assert!((p.iter().fold(Vector2::zeros(), |s, q| s + q)).norm() < 1e-12);
        let e = read_positions("0 0\n1 x\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.txt:2:") && e.contains("\"x\""), "{e}");
        let e = read_positions("0 0\n1 2 3\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.txt:2:"), "{e}");
        let e = read_positions("0 inf\n1 2\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.txt:1:"), "{e}");
        let e = read_positions("0 0\n1e300 0\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.txt:2: 1e300 is too far"), "{e}");
        let e = read_positions("0 0\n0.5 0\n# again\n0 0\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "t.txt:4: two robots in one place: (0, 0) is also on line 1"
        );
        let e = read_positions("0 0\n0.5 0\n50 0\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.txt:3: the robot at (50, 0) is out of everyone's range"),
            "{e}"
        );
        assert!(
            read_positions("0 0\n", "t.txt")
                .unwrap_err()
                .to_string()
                .contains("1 robots")
        );
    }

    #[test]
    fn the_sharp_border_reads_as_the_lab_and_the_gradient_does_not_saturate() {
        let sharp = Scenario::load("sharp").unwrap();
        assert_eq!(sensor_scale(&sharp), (30.0, 34.0, 17));
        let gradient = Scenario::load("gradient").unwrap();
        let (base, gain, noise) = sensor_scale(&gradient);
        // X reaches 25 at x = 10 R: 30 + 9 × 25 = 255.
        assert_eq!((base, gain, noise), (30.0, 9.0, 5));
    }

    #[test]
    fn spread_ids_keep_equal_tags_apart_on_the_lattice() {
        let p = swarm_sim::geometry::lattice(61, SPACING);
        let ids = spread_ids(&p);
        let mut closest = f64::INFINITY;
        for i in 0..p.len() {
            for j in 0..i {
                if ids[i] % 16 == ids[j] % 16 {
                    closest = closest.min((p[i] - p[j]).norm() / SPACING);
                }
            }
        }
        assert!(closest >= 3.0, "{closest}");
        // Ids stay distinct.
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), ids.len());
    }

    #[test]
    fn the_centre_moves_by_a_step_along_each_heading() {
        let m = |x: f64, h: Option<f64>| Move {
            t: protocol::Instant::ZERO,
            centre: Point2::new(x, 0.0),
            heading: h,
            consensus: 1.0,
        };
        let near = Success::NearX {
            x: 0.0,
            within: 0.33,
        };
        // From -0.9: -0.57 after the first move, -0.24 after the second (success), then no
        // decision, no move.
        let moves = [m(-0.9, Some(0.0)), m(-0.57, Some(0.0)), m(-0.24, None)];
        let (first, end) = judge(&moves, 0.33, &near);
        assert_eq!(first, Some(2));
        assert!((end.x + 0.24).abs() < 1e-12, "{end}");
        let (first, _) = judge(&moves[..1], 0.33, &near);
        assert_eq!(first, None);
    }
}
