//! Scenarios: the field, the swarm, the protocol parameters and what counts as success.
//!
//! The built-in scenarios `sharp`, `gradient`, `cloud` (the paper text's cloud) and
//! `cloud-caption` (the cloud of Fig. 11's caption) are TOML files compiled into the binary (`swarm-sim/scenarios/*.toml`); any other file in the same format can be passed to
//! `--scenario`. Every key but `[[field]]` is optional:
//!
//! ```toml
//! name = "two-steps"
//! description = "free text"
//! noise = 1.0            # ξ uniform in (−noise/2, noise/2), fresh at every reading
//! step = 0.33            # move per negotiation period, in R (R = 1)
//! periods = 50           # negotiation periods per run
//! start = [-2.5, 0.0]    # centre of mass for `swarm run`
//! diversity = "variance" # the paper's measure; or { kind = "entropy", bin = 0.5 }: Shannon
//!                        #   entropy (bits) of the readings binned at width `bin` (beyond the paper)
//!
//! [swarm]
//! agents = 61
//! shape = "disk"         # diameter = 6.0; "rectangle" with width and height; or "lattice"
//! diameter = 6.0         #   with spacing (≤ 1): the N triangular-lattice nodes nearest the centre
//!
//! [protocol]             # Params::simulation_2d() unless given; times in whole seconds
//! cycle = 1000
//! refractory = 10
//! relay_delay = 1
//! gather_cycles = 1
//! decide_cycles = 1
//! diffusion = 0.1
//!
//! [[field]]              # summed; along = "x", "y" or "radial" (with centre = [x, y])
//! along = "x"
//! segments = [           # from `from` on: level + slope · (s − from); sorted by `from`
//!     { from = -inf, level = 0.0 },
//!     { from = 0.0, level = 5.0 },
//! ]
//!
//! [[field2]]             # optional, beyond the paper: a second quantity (e.g. oxygen beside
//! along = "y"            #   light), same format; agents read both (each with its own noise
//! segments = [           #   draw) and score the sum of the per-quantity diversities
//!     { from = -inf, level = 0.0 },
//!     { from = 1.0, level = 5.0 },
//! ]
//!
//! [success]              # kind = "near_x" (|x − x0| < within) or "beyond_x" (x ≥ x0)
//! kind = "near_x"
//! x = 0.0
//! within = 0.33
//!
//! [sweep]                # initial x positions of `swarm sweep` (y = 0)
//! from = -5.0
//! to = 5.0
//! step = 0.5
//! runs = 50
//!
//! [grid]                 # swarm centres of `swarm field`: [from, to, step]
//! x = [-5.0, 5.0, 0.5]
//! y = [-3.0, 3.0, 1.0]
//! gather_cycles = 2      # the period used for each arrow
//! decide_cycles = 2
//! ```
//!
//! A file that does not parse or makes no sense gives a [`ScenarioError`] naming the line,
//! the column and the problem; reading and checking a file is `file.rs`.
//!
//! **Limits.** Sizes and counts are bounded so that a scenario can neither exhaust memory nor
//! overflow a product; a value beyond a limit is an error naming its key (`diameter = 100000:
//! at most 1000 R`):
//!
//! - `agents`: 2 to [`MAX_AGENTS`] (1,000,000);
//! - `diameter`, `width`, `height`: at most [`MAX_EXTENT`] (1000 R); a lattice's `spacing`: at
//!   most 1 R;
//! - `periods`: 1 to [`MAX_PERIODS`] (100,000); a negotiation period, `(gather_cycles +
//!   decide_cycles) × cycle` (of `[protocol]`, and of `[grid]`): at most
//!   [`MAX_PERIOD_SECS`](crate::sim::MAX_PERIOD_SECS) (1,000,000 s);
//! - `[sweep]`: 1 to 100,000 `runs` per position and at most [`MAX_RUNS`] (1,000,000) runs in
//!   all (positions × runs); `[grid]`: at most [`MAX_RUNS`] points (one run each); a range
//!   (`from`, `to`, `step`) has at most 100,001 values.

mod file;

use std::fmt;
use std::path::Path;

use nalgebra::Point2;

use crate::geometry::Shape;
use crate::sim::RunConfig;
use hal_emu::world::field::Field;

/// Spacing of `shape = "lattice"` (and of `--placement lattice`) unless given: 0.75 R, at which 61 agents
/// fill a disk of diameter 6 R with 5.1 neighbours on average (see [`Shape::Lattice`]).
pub const LATTICE_SPACING: f64 = 0.75;

/// How the agents of a scenario's swarm are placed (`--placement`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placement {
    /// Uniformly at random in the scenario's `shape` (disk or rectangle), redrawn until
    /// connected: 6.1 neighbours on average for the paper's 61 agents in a 6 R disk.
    Random,
    /// The N triangular-lattice nodes nearest the centre, spacing [`LATTICE_SPACING`] unless
    /// the scenario gives a lattice of its own: 5.1 neighbours on average for 61 agents, the
    /// paper's "on average five".
    Lattice,
}

/// The placement of `swarm run`, `sweep`, `field` and `reproduce` unless told otherwise.
pub const DEFAULT_PLACEMENT: Placement = Placement::Lattice;

impl Placement {
    /// Both placements.
    pub const ALL: [Placement; 2] = [Placement::Random, Placement::Lattice];

    /// The name `--placement` takes: `random` or `lattice`.
    pub fn name(self) -> &'static str {
        match self {
            Placement::Random => "random",
            Placement::Lattice => "lattice",
        }
    }

    /// The other placement.
    pub fn other(self) -> Placement {
        match self {
            Placement::Random => Placement::Lattice,
            Placement::Lattice => Placement::Random,
        }
    }
}

impl fmt::Display for Placement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Placement {
    type Err = PlacementError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Placement::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| PlacementError::Unknown(s.to_string()))
    }
}

/// Why a placement could not be read ([`Placement`]'s `FromStr`) or used
/// ([`Scenario::placed`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlacementError {
    /// No placement has this name.
    #[error("unknown placement {0:?}: random or lattice")]
    Unknown(String),
    /// Random placement of a scenario whose shape is a lattice.
    #[error(
        "scenario {scenario} sets shape = \"lattice\"; random placement needs a disk or rectangle"
    )]
    RandomOnLattice {
        /// The scenario's name.
        scenario: String,
    },
}

/// The most agents a swarm may have (`agents`, `cimax swarm bench --agents`).
pub const MAX_AGENTS: usize = 1_000_000;

/// The largest `diameter`, `width` or `height` of a swarm's shape, in R. 1000 R holds
/// [`MAX_AGENTS`] at the paper's density (61 agents in a disk of 6 R: 768 R for a million), and
/// the neighbour grid of a swarm that size has at most 1001 × 1001 cells one range wide
/// ([`crate::geometry::neighbour_lists`]): some 4 MB, where 100,000 R would need 10^10 cells.
pub const MAX_EXTENT: f64 = 1000.0;

/// The most negotiation periods of a run (`periods`, `cimax swarm run --periods`).
pub const MAX_PERIODS: u32 = 100_000;

/// The most runs per sweep position (`[sweep] runs`, `cimax swarm sweep --runs`).
pub const MAX_RUNS_PER_POINT: u32 = 100_000;

/// The most runs of one sweep (positions × runs per position) or grid (points): a million runs
/// take hours on a desktop and their results some megabytes; 10^10 would not fit in memory.
pub const MAX_RUNS: u64 = 1_000_000;

/// Checks that the runs of one command, the product of the counts in `what` (each with what
/// it counts), are at most [`MAX_RUNS`], and returns their number; the message says what
/// multiplied to how many.
///
/// # Errors
/// [`TooManyRuns`], whose message is such as
/// `21 positions × 100000 runs = 2100000 runs; at most 1000000`.
pub fn check_runs(what: &[(u64, &str)]) -> Result<u64, TooManyRuns> {
    let total = what
        .iter()
        .try_fold(1u64, |acc, &(n, _)| acc.checked_mul(n));
    match total {
        Some(t) if t <= MAX_RUNS => Ok(t),
        _ => Err(TooManyRuns {
            counts: what.iter().map(|&(n, w)| (n, w.to_string())).collect(),
        }),
    }
}

/// The runs of one command are more than [`MAX_RUNS`] ([`check_runs`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{} = {} runs; at most {MAX_RUNS}", self.product_text(), self.product())]
pub struct TooManyRuns {
    /// The counts that multiply to the runs, each with what it counts (`positions`, `runs`).
    pub counts: Vec<(u64, String)>,
}

impl TooManyRuns {
    /// The number of runs asked for.
    pub fn product(&self) -> u128 {
        self.counts.iter().map(|&(n, _)| u128::from(n)).product()
    }

    /// `21 positions × 100000 runs`.
    fn product_text(&self) -> String {
        let parts: Vec<String> = self
            .counts
            .iter()
            .map(|(n, w)| format!("{n} {w}"))
            .collect();
        parts.join(" × ")
    }
}

/// The built-in scenarios, by name.
pub const BUILTINS: [(&str, &str); 4] = [
    ("sharp", include_str!("../../scenarios/sharp.toml")),
    ("gradient", include_str!("../../scenarios/gradient.toml")),
    ("cloud", include_str!("../../scenarios/cloud.toml")),
    (
        "cloud-caption",
        include_str!("../../scenarios/cloud-caption.toml"),
    ),
];

/// When a run counts as a success (paper section 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Success {
    /// The centre of mass within `within` of the line `x = x` (sharp border: |x| < 0.33 R).
    NearX {
        /// The line.
        x: f64,
        /// Distance below which the run succeeds.
        within: f64,
    },
    /// The centre of mass at or beyond `x` (gradient: x ≥ 2.33).
    BeyondX {
        /// The line.
        x: f64,
    },
}

impl Success {
    /// True if a swarm centred at `c` has succeeded.
    pub fn met(&self, c: Point2<f64>) -> bool {
        match *self {
            Success::NearX { x, within } => (c.x - x).abs() < within,
            Success::BeyondX { x } => c.x >= x,
        }
    }

    /// False only if no centre within `reach` of `c` along x (so no centre within `reach` of
    /// `c` at all) meets the criterion: a swarm at `c` that moves at most `reach` from now on
    /// cannot succeed. Conservative: a `reach` or `c` that is not a number counts as reachable.
    pub fn reachable(&self, c: Point2<f64>, reach: f64) -> bool {
        let gap = match *self {
            Success::NearX { x, within } => (c.x - x).abs() - within,
            Success::BeyondX { x } => x - c.x,
        };
        gap.partial_cmp(&reach) != Some(std::cmp::Ordering::Greater)
    }
}

impl fmt::Display for Success {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Success::NearX { x: 0.0, within } => write!(f, "|x| < {within}"),
            Success::NearX { x, within } => write!(f, "|x − {x}| < {within}"),
            Success::BeyondX { x } => write!(f, "x ≥ {x}"),
        }
    }
}

/// The initial positions of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// Initial x of the centre of mass (y = 0).
    pub xs: Vec<f64>,
    /// Runs per position.
    pub runs: u32,
}

/// The grid of a preferred-direction map.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSpec {
    /// Column positions.
    pub xs: Vec<f64>,
    /// Row positions.
    pub ys: Vec<f64>,
    /// Gathering cycles of the period run at each point.
    pub gather_cycles: u16,
    /// Deciding cycles of the period run at each point.
    pub decide_cycles: u16,
}

/// A validated scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Short name (file names of outputs are derived from it).
    pub name: String,
    /// One line for plots and reports.
    pub description: String,
    /// The mean of X.
    pub field: Field,
    /// The mean of a second quantity read alongside X (`[[field2]]`, beyond the paper), if
    /// any: the agents then read both and score the sum of the two quantities' diversities.
    /// Maps and profiles of the field show X only.
    pub field2: Option<Field>,
    /// Number of agents.
    pub agents: usize,
    /// The outline the agents are scattered in.
    pub shape: Shape,
    /// Protocol parameters, step and noise.
    pub run: RunConfig,
    /// Negotiation periods per run.
    pub periods: u32,
    /// Where `swarm run` starts.
    pub start: Point2<f64>,
    /// Success criterion, if the scenario has one.
    pub success: Option<Success>,
    /// Sweep positions, if given.
    pub sweep: Option<SweepSpec>,
    /// Grid of the direction map, if given.
    pub grid: Option<GridSpec>,
}

/// A scenario that could not be read: where and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScenarioError {
    /// The file (or built-in) name.
    pub source: String,
    /// Line and column (1-based), when the problem has a place.
    pub at: Option<(usize, usize)>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            Some((l, c)) => write!(f, "{}:{l}:{c}: {}", self.source, self.message),
            None => write!(f, "{}: {}", self.source, self.message),
        }
    }
}

impl std::error::Error for ScenarioError {}

impl Scenario {
    /// The same scenario with its agents placed by `placement`: [`Placement::Lattice`] puts
    /// them on the triangular lattice of spacing [`LATTICE_SPACING`] (a scenario whose
    /// `shape` is already a lattice keeps its spacing); [`Placement::Random`] keeps the
    /// scenario's disk or rectangle. Name and description are unchanged.
    ///
    /// # Errors
    /// [`Placement::Random`] for a scenario with `shape = "lattice"`: it has no area to draw
    /// from.
    pub fn placed(&self, placement: Placement) -> Result<Scenario, PlacementError> {
        let mut s = self.clone();
        match (placement, self.shape) {
            (Placement::Lattice, Shape::Lattice { .. }) => {}
            (Placement::Lattice, _) => {
                s.shape = Shape::Lattice {
                    spacing: LATTICE_SPACING,
                };
            }
            (Placement::Random, Shape::Lattice { .. }) => {
                return Err(PlacementError::RandomOnLattice {
                    scenario: self.name.clone(),
                });
            }
            (Placement::Random, _) => {}
        }
        Ok(s)
    }

    /// The built-in scenario called `name`.
    pub fn builtin(name: &str) -> Option<Scenario> {
        BUILTINS
            .iter()
            .find(|(n, _)| *n == name)
            .and_then(|(n, text)| Scenario::from_toml(text, &format!("built-in {n}")).ok())
    }

    /// A built-in name or the path of a scenario file.
    ///
    /// # Errors
    /// A [`ScenarioError`] if the file cannot be read or is not a valid scenario.
    pub fn load(name_or_path: &str) -> Result<Scenario, ScenarioError> {
        if let Some(s) = Scenario::builtin(name_or_path) {
            return Ok(s);
        }
        let path = Path::new(name_or_path);
        let text = std::fs::read_to_string(path).map_err(|e| ScenarioError {
            source: name_or_path.to_string(),
            at: None,
            message: format!(
                "cannot read it ({e}); built-in scenarios are {}",
                BUILTINS.map(|(n, _)| n).join(", ")
            ),
        })?;
        Scenario::from_toml(&text, name_or_path)
    }

    /// Parses and validates a scenario; `source` names it in errors.
    ///
    /// # Errors
    /// A [`ScenarioError`] with the line and column of the first problem.
    pub fn from_toml(text: &str, source: &str) -> Result<Scenario, ScenarioError> {
        file::parse(text, source)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measure::Measure;
    use crate::sim::MAX_PERIOD_SECS;
    use protocol::Params;

    #[test]
    fn placement_puts_the_paper_swarm_on_the_lattice_or_keeps_its_disk() {
        assert_eq!(DEFAULT_PLACEMENT, Placement::Lattice);
        for p in Placement::ALL {
            assert_eq!(p.name().parse::<Placement>(), Ok(p));
            assert_eq!(p.other().other(), p);
        }
        assert!("grid".parse::<Placement>().is_err());
        let sharp = Scenario::builtin("sharp").unwrap();
        let lattice = sharp.placed(Placement::Lattice).unwrap();
        assert_eq!(
            lattice.shape,
            Shape::Lattice {
                spacing: LATTICE_SPACING
            }
        );
        assert_eq!(lattice.name, "sharp");
        assert_eq!(sharp.placed(Placement::Random).unwrap(), sharp);
        let mut own = sharp.clone();
        own.shape = Shape::Lattice { spacing: 0.9 };
        assert_eq!(own.placed(Placement::Lattice).unwrap(), own);
        assert!(own.placed(Placement::Random).is_err());
    }

    #[test]
    fn builtins_parse_and_match_the_paper() {
        for (n, _) in BUILTINS {
            assert!(Scenario::builtin(n).is_some(), "{n}");
        }
        let s = Scenario::builtin("sharp").unwrap();
        assert_eq!(s.agents, 61);
        assert_eq!(s.shape, Shape::Disk { diameter: 6.0 });
        assert_eq!(s.run.params, Params::simulation_2d());
        assert_eq!(s.periods, 50);
        assert_eq!(s.field.mean(Point2::new(-0.1, 0.0)), 0.0);
        assert_eq!(s.field.mean(Point2::new(0.0, 0.0)), 5.0);
        assert_eq!(s.sweep.as_ref().unwrap().xs.len(), 21);
        assert_eq!(s.sweep.as_ref().unwrap().runs, 50);
        let g = Scenario::builtin("gradient").unwrap();
        assert_eq!(g.field.mean(Point2::new(-3.0, 1.0)), 0.0);
        assert!((g.field.mean(Point2::new(2.0, 1.0)) - 5.0).abs() < 1e-12);
        let c = Scenario::builtin("cloud").unwrap();
        assert_eq!(c.field.mean(Point2::new(2.0, 2.0)), 0.0);
        assert!((c.field.mean(Point2::new(0.0, 3.75)) - 2.5).abs() < 1e-9);
        assert_eq!(c.field.mean(Point2::new(-8.0, 0.0)), 5.0);
    }

    #[test]
    fn the_diversity_key_picks_the_measure_and_names_itself_when_wrong() {
        let base = "[[field]]\nalong = \"x\"\nsegments = [{ from = -inf, level = 0.0 }]\n";
        let with = |d: &str| format!("diversity = {d}\n{base}");
        let ok = |d: &str| {
            Scenario::from_toml(&with(d), "d.toml")
                .unwrap()
                .run
                .diversity
        };
        assert_eq!(
            Scenario::from_toml(base, "d.toml").unwrap().run.diversity,
            Measure::Variance
        );
        assert_eq!(ok("\"variance\""), Measure::Variance);
        assert_eq!(ok("{ kind = \"variance\" }"), Measure::Variance);
        assert_eq!(
            ok("{ kind = \"entropy\", bin = 0.5 }"),
            Measure::entropy(0.5).unwrap()
        );
        assert_eq!(
            ok("{ kind = \"entropy\", bin = 2 }"),
            Measure::entropy(2.0).unwrap()
        );
        for (bad, says) in [
            ("\"entropy\"", "needs a bin width"),
            ("\"gini\"", "unknown diversity \"gini\""),
            ("{ kind = \"entropy\" }", "diversity.bin is missing"),
            (
                "{ kind = \"entropy\", bin = 0.0 }",
                "diversity.bin = 0 must be a positive",
            ),
            ("{ kind = \"entropy\", bin = -1.0 }", "must be a positive"),
            ("{ kind = \"entropy\", bin = nan }", "must be a positive"),
            ("{ kind = \"entropy\", bin = 1e300 }", "must be a positive"),
            ("{ kind = \"entropy\", bin = \"x\" }", "is not a number"),
            ("{ kind = \"variance\", bin = 1.0 }", "only for kind"),
            ("{ bin = 1.0 }", "diversity.kind is missing"),
            (
                "{ kind = \"entropy\", bin = 1.0, width = 2 }",
                "unknown key diversity.width",
            ),
            ("3", "neither a name nor a table"),
        ] {
            let e = err(&with(bad));
            assert_eq!(e.at.map(|a| a.0), Some(1), "{bad}: {e}");
            assert!(e.message.contains(says), "{bad}: {e}");
            assert!(e.message.contains("diversity must be"), "{bad}: {e}");
        }
    }

    #[test]
    fn a_second_field_is_a_second_quantity() {
        let base = "[[field]]\nalong = \"x\"\nsegments = [{ from = -inf, level = 0.0 }]\n";
        assert_eq!(Scenario::from_toml(base, "q.toml").unwrap().field2, None);
        let two = format!(
            "{base}[[field2]]\nalong = \"y\"\nsegments = [{{ from = -inf, level = 1.0 }}, {{ from = 2.0, level = 3.0 }}]\n"
        );
        let f2 = Scenario::from_toml(&two, "q.toml").unwrap().field2.unwrap();
        assert_eq!(f2.mean(Point2::new(0.0, 1.0)), 1.0);
        assert_eq!(f2.mean(Point2::new(0.0, 2.5)), 3.0);
        let e = err(&format!("field2 = []\n{base}"));
        assert!(e.message.contains("at least one layer"), "{e}");
    }

    #[test]
    fn the_caption_cloud_rises_from_0_to_5_over_its_radius_with_noise_in_0_1() {
        let c = Scenario::builtin("cloud-caption").unwrap();
        assert_eq!(c.name, "cloud-caption");
        assert_eq!(c.agents, 61);
        assert_eq!(c.run.noise, 1.0);
        // Mean of a reading: X + 0.5, the mean of a noise uniform in [0, 1).
        let at = |d: f64, phi: f64| c.field.mean(Point2::new(d * phi.cos(), d * phi.sin())) - 0.5;
        for phi in [0.0, 1.0, 2.5, 4.0] {
            assert_eq!(at(0.0, phi), 0.0);
            assert!((at(2.5, phi) - 2.5).abs() < 1e-12);
            assert!((at(4.999, phi) - 4.999).abs() < 1e-9);
            assert_eq!(at(5.0, phi), 5.0);
            assert_eq!(at(6.0, phi), 5.0);
            assert_eq!(at(20.0, phi), 5.0);
        }
        let grid = c.grid.as_ref().unwrap();
        assert_eq!((grid.xs.len(), grid.ys.len()), (21, 21));
        assert_eq!((grid.gather_cycles, grid.decide_cycles), (1, 1));
    }

    #[test]
    fn success_criteria() {
        let near = Success::NearX {
            x: 0.0,
            within: 0.33,
        };
        assert!(near.met(Point2::new(0.32, 7.0)));
        assert!(near.met(Point2::new(-0.32, -7.0)));
        assert!(!near.met(Point2::new(0.33, 0.0)));
        assert!(!near.met(Point2::new(-0.34, 0.0)));
        let beyond = Success::BeyondX { x: 2.33 };
        assert!(beyond.met(Point2::new(2.33, 0.0)));
        assert!(beyond.met(Point2::new(9.0, 0.0)));
        assert!(!beyond.met(Point2::new(2.32, 0.0)));
    }

    fn err(text: &str) -> ScenarioError {
        Scenario::from_toml(text, "bad.toml").unwrap_err()
    }

    const FIELD: &str = "[[field]]\nalong = \"x\"\nsegments = [{ from = 0.0, level = 1.0 }]\n";

    #[test]
    fn a_minimal_file_gets_the_papers_defaults() {
        let s = Scenario::from_toml(FIELD, "dir/mine.toml").unwrap();
        assert_eq!(s.name, "mine");
        assert_eq!(s.agents, 61);
        assert_eq!(s.run.step, 0.33);
        assert_eq!(s.success, None);
    }

    #[test]
    fn bad_files_name_the_line_and_the_problem() {
        let e = err(&format!("noise = 1.0\nnoyse = 2\n{FIELD}"));
        assert_eq!(e.at.map(|a| a.0), Some(2), "{e}");
        assert!(e.message.contains("noyse"), "{e}");

        let e = err(&format!(
            "{FIELD}[swarm]\nagents = 61\nshape = \"triangle\"\n"
        ));
        assert_eq!(e.at, Some((6, 9)), "{e}");
        assert!(e.message.contains("triangle"), "{e}");
        assert!(
            e.to_string().starts_with("bad.toml:6:9: unknown shape"),
            "{e}"
        );

        let e = err(&format!(
            "{FIELD}[swarm]\nshape = \"lattice\"\nspacing = 1.5\n"
        ));
        assert_eq!(e.at, Some((6, 11)), "{e}");
        assert!(e.message.contains("spacing"), "{e}");
        let e = err(&format!(
            "{FIELD}[swarm]\nshape = \"lattice\"\ndiameter = 6.0\n"
        ));
        assert!(e.message.contains("does not apply"), "{e}");
        let s = Scenario::from_toml(&format!("{FIELD}[swarm]\nshape = \"lattice\"\n"), "l.toml")
            .unwrap();
        assert_eq!(s.shape, Shape::Lattice { spacing: 0.75 });

        let e = err(
            "[[field]]\nalong = \"x\"\nsegments = [\n  { from = 1.0, level = 0.0 },\n  { from = 0.0, level = 5.0 },\n]\n",
        );
        assert_eq!(e.at.map(|a| a.0), Some(5), "{e}");
        assert!(e.message.contains("increasing"), "{e}");

        let e = err(&format!("{FIELD}[protocol]\ncycle = 5\n"));
        assert_eq!(e.at.map(|a| a.0), Some(4), "{e}");
        assert!(e.message.contains("refractory"), "{e}");

        let e = err(&format!("step = -1\n{FIELD}"));
        assert_eq!(e.at, Some((1, 8)), "{e}");
        assert!(e.message.contains("step"), "{e}");

        let e = err(&format!("{FIELD}[success]\nkind = \"near_x\"\nx = 0.0\n"));
        assert!(e.message.contains("within"), "{e}");

        let e = err(
            "[[field]]\nalong = \"x\"\nsegments = [{ from = -inf, level = 0.0, slope = 1.0 }]\n",
        );
        assert!(e.message.contains("flat"), "{e}");

        let e = err("start = [0.0, 0.0\n");
        assert!(e.at.is_some(), "{e}");

        let e = err("start = [0.0, 0.0]\n");
        assert!(e.message.contains("field"), "{e}");
    }

    #[test]
    fn sizes_and_counts_beyond_the_limits_name_their_key() {
        let shape = |body: &str| format!("{FIELD}[swarm]\n{body}");
        let e = err(&shape("diameter = 1e5\n"));
        assert_eq!(e.at, Some((5, 12)), "{e}");
        assert_eq!(e.message, "diameter = 100000: at most 1000 R");
        let e = err(&shape("diameter = 1e300\n"));
        assert_eq!(e.message, "diameter = 1e300: at most 1000 R");
        let e = err(&shape(
            "shape = \"rectangle\"\nwidth = 5000.0\nheight = 4.0\n",
        ));
        assert_eq!(e.message, "width = 5000: at most 1000 R");
        let e = err(&shape("shape = \"rectangle\"\nwidth = 9.0\nheight = 1e9\n"));
        assert_eq!(e.message, "height = 1000000000: at most 1000 R");
        let e = err(&shape("diameter = -1.0\n"));
        assert!(
            e.message.contains("the diameter must be a positive number"),
            "{e}"
        );
        let s = Scenario::from_toml(&shape("diameter = 1000.0\n"), "ok.toml").unwrap();
        assert_eq!(
            s.shape,
            Shape::Disk {
                diameter: MAX_EXTENT
            }
        );
        let e = err(&shape("agents = 1000001\n"));
        assert!(e.message.contains("1,000,000"), "{e}");

        // A negotiation period of (1 + 1) × cycle: at most 1,000,000 s.
        let protocol = |body: &str| format!("{FIELD}[protocol]\n{body}");
        let s = Scenario::from_toml(&protocol("cycle = 500000\n"), "ok.toml").unwrap();
        assert_eq!(s.run.period_secs(), MAX_PERIOD_SECS);
        let e = err(&protocol("cycle = 500001\n"));
        assert_eq!(e.at.map(|a| a.0), Some(4), "{e}");
        assert_eq!(
            e.message,
            "[protocol]: cycle = 500001 makes a negotiation period of (gather_cycles + \
             decide_cycles) × cycle = (1 + 1) × 500001 s = 1000002 s; at most 1000000 s"
        );
        // u64::MAX / 1000 s per cycle: `cycles * cycle` overflowed u64.
        let e = err(&protocol(
            "cycle = 18446744073709551\ngather_cycles = 65535\ndecide_cycles = 65535\n",
        ));
        assert!(
            e.message
                .contains("(65535 + 65535) × 18446744073709551 s = 2417814745741110849570 s"),
            "{e}"
        );
        let e = err(&format!(
            "{FIELD}[grid]\nx = [0.0, 1.0, 1.0]\ny = [0.0, 1.0, 1.0]\ngather_cycles = 60000\n"
        ));
        assert!(e.message.starts_with("[grid]: cycle = 1000 makes"), "{e}");

        // Runs: positions × runs of a sweep, points of a grid.
        let e = err(&format!(
            "{FIELD}[sweep]\nfrom = -5.0\nto = 5.0\nstep = 0.0001\nruns = 100\n"
        ));
        assert_eq!(e.at.map(|a| a.0), Some(4), "{e}");
        assert_eq!(
            e.message,
            "[sweep]: 100001 positions × 100 runs = 10000100 runs; at most 1000000"
        );
        let s = Scenario::from_toml(
            &format!("{FIELD}[sweep]\nfrom = -5.0\nto = 5.0\nstep = 0.001\nruns = 99\n"),
            "ok.toml",
        )
        .unwrap();
        assert_eq!(s.sweep.map(|w| w.xs.len() * w.runs as usize), Some(990_099));
        let e = err(&format!(
            "{FIELD}[grid]\nx = [-50.0, 50.0, 0.01]\ny = [-50.0, 50.0, 0.01]\n"
        ));
        assert_eq!(
            e.message,
            "[grid]: 10001 columns × 10001 rows = 100020001 runs; at most 1000000 (one per point)"
        );
    }
}
