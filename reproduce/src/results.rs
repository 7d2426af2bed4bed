//! What the units of `swarm reproduce` measured ([`UnitResult`], one per [`Unit`]) and the
//! set of them the page is written from ([`Results`]). A [`UnitResult`] goes through JSON
//! without loss (serde, every float bit for bit: [`swarm_sim::json`]), so the results of
//! a sharded run can be merged from part files and written as if computed here.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::shapes::ShapesResult;
use crate::units::{Field, Side, UNITS, Unit};
use swarm_sim::experiment::{Arrow, BenchResult, RadialPoint, RunOutput, SweepPoint};
use swarm_sim::probe::{Msd, Plateaus, Split, StartRun};
use swarm_sim::timecourse::TimeCourse;
use swarm_sim::waves::Wave;

// The units' result types are kept here, so that the files that compute and write them
// depend on this one and it on none of them.

/// A run figure's run: the first of up to [`RUN_TRIES`](crate::RUN_TRIES) that succeeded (or the first), and
/// which try it was.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunFigure {
    /// Tries before it (0: the first).
    pub tries: u64,
    /// The run.
    pub out: RunOutput,
}

/// One cycle length of the cycle-length experiment.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CycleRun {
    /// The cycle length t_p^max, seconds.
    pub cycle_s: u64,
    /// Waves heard per agent per cycle.
    #[serde(with = "swarm_sim::json")]
    pub waves_heard: f64,
    /// Agents that initiated a wave in that first cycle, over the same runs.
    pub initiating: u64,
    /// Agents over those runs (agent-cycles).
    pub agent_cycles: u64,
    /// Success from each start of [`CYCLE_XS`](crate::CYCLE_XS).
    pub points: Vec<SweepPoint>,
}

/// Neighbour counts of random placements of the sharp scenario's swarm.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PlacementStats {
    /// Mean degree with the redraw-until-connected rule ([`Swarm::place`](swarm_sim::geometry::Swarm::place)).
    #[serde(with = "swarm_sim::json")]
    pub redrawn_degree: f64,
    /// Mean degree of plain uniform scattering.
    #[serde(with = "swarm_sim::json")]
    pub plain_degree: f64,
    /// Fraction of plain scatterings that are disconnected.
    #[serde(with = "swarm_sim::json")]
    pub plain_disconnected: f64,
}

/// Both measures along the gradient and at its success line against the slope.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Along {
    /// Per measure, `(x, mean, s.e.)` per point of [`PROFILE_XS`](crate::beyond::PROFILE_XS).
    #[serde(with = "swarm_sim::json")]
    pub prof: Vec<Vec<(f64, f64, f64)>>,
    /// Per slope of [`SLOPES`](crate::beyond::SLOPES), both measures at the success line.
    #[serde(with = "swarm_sim::json")]
    pub by_slope: Vec<[f64; 2]>,
    /// The gradient's success line.
    #[serde(with = "swarm_sim::json")]
    pub line_x: f64,
}

/// The gradient against its slope: per slope of [`SLOPES`](crate::sensitivity::SLOPES), success from [`SENS_X`](crate::sensitivity::SENS_X) and the
/// diversity at the success line.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SlopeRuns {
    /// Success per slope.
    pub success: Vec<SweepPoint>,
    /// `(slope, mean, s.e.)` of the diversity at the success line, per slope.
    #[serde(with = "swarm_sim::json")]
    pub diversity: Vec<(f64, f64, f64)>,
}

impl Along {
    /// The mean of measure `m` at profile point `x` (NaN if none is there).
    pub fn at(&self, m: usize, x: f64) -> f64 {
        self.prof[m]
            .iter()
            .find(|q| (q.0 - x).abs() < 1e-9)
            .map_or(f64::NAN, |q| q.1)
    }
}

/// One field and extent: the heading of the first move against the start.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ExtentRun {
    /// The swarm's agents.
    pub agents: usize,
    /// `(x, mean cos, s.e.)` by increasing x.
    #[serde(with = "swarm_sim::json")]
    pub profile: Vec<(f64, f64, f64)>,
}

/// One refractory time on the swarm of the paper's Fig. 2.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RefractoryRun {
    /// t_ref, seconds.
    pub refractory_s: u64,
    /// What the protocol does with it.
    pub answer: String,
    /// Where the protocol runs it: whether every agent sent exactly once.
    pub once: Option<bool>,
    /// The model's transmissions per second from the initiation to [`HORIZON`](crate::settle::refractory::HORIZON).
    pub sends: Vec<u32>,
}

/// Each refractory time of [`REFRACTORY`](crate::settle::refractory::REFRACTORY) on the swarm of the paper's Fig. 2.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RefractoryRuns {
    /// The swarm's agents.
    pub agents: usize,
    /// The relay delay, seconds.
    pub relay_s: u64,
    /// One per refractory time.
    pub runs: Vec<RefractoryRun>,
}

/// One field's levels under one sensor model: `(mean, s.e.)` each.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Levels {
    /// The first period's diversity.
    #[serde(with = "swarm_sim::json")]
    pub start: (f64, f64),
    /// Periods until arrival, over the runs that arrived.
    #[serde(with = "swarm_sim::json")]
    pub arrival: (f64, f64),
    /// The plateau (mean over agents of `V_k` after arrival).
    #[serde(with = "swarm_sim::json")]
    pub plateau: (f64, f64),
    /// Runs that arrived.
    pub arrived: usize,
    /// Runs in all.
    pub runs: usize,
}

/// The runs of one field's averaged course, either placement, tapped as they run: what
/// "Settling the open rows" reads off them.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CourseDigest {
    /// Their plateaus, three ways.
    pub plateaus: Plateaus,
    /// Their levels, one sensor reading per activation.
    pub levels: Levels,
    /// Where their periods went on the way to the line.
    pub way: Way,
    /// The walk after arrival.
    pub msd: Vec<Msd>,
}

/// Where a field's averaged courses' runs spent their periods on the way to the line.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Way {
    /// `(bin's centre, mean periods there)` per step from the start.
    #[serde(with = "swarm_sim::json")]
    pub spent: Vec<(f64, f64)>,
    /// Arrival periods of the runs that arrived.
    #[serde(with = "swarm_sim::json")]
    pub arrivals: Vec<f64>,
}

/// One run's periods to the criterion and to the common line (`None`: not met).
pub type Times = (Option<u32>, Option<u32>);

/// One unit's result: what it measured, and how long it took where it ran.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct UnitResult {
    /// The unit.
    pub unit: Unit,
    /// Wall time of the unit, seconds (it varies from run to run; only the page's timing
    /// lines read it).
    pub wall_s: f64,
    /// Rayon's threads where it ran.
    pub threads: usize,
    /// What it measured.
    outcome: Outcome,
}

impl UnitResult {
    /// The result of `unit`, measured in `wall_s` seconds on `threads` threads.
    pub fn new(unit: Unit, wall_s: f64, threads: usize, outcome: Outcome) -> UnitResult {
        UnitResult {
            unit,
            wall_s,
            threads,
            outcome,
        }
    }
}

/// What a unit measured, by kind of unit.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// [`Unit::Run`].
    Run(RunFigure),
    /// [`Unit::Sweep`].
    Sweep(Vec<SweepPoint>),
    /// [`Unit::Map`], [`Unit::CaptionMap`].
    Map(Vec<Arrow>),
    /// [`Unit::CloudProfile`], [`Unit::CaptionProfile`].
    Profile(Vec<RadialPoint>),
    /// [`Unit::Course`]: the course and what its runs, tapped as they ran, give.
    Course(TimeCourse, Box<CourseDigest>),
    /// [`Unit::Sensor`].
    Sensor(Levels),
    /// [`Unit::Plateau`] (`None`: the courses' own cycle and placement, not run again).
    Plateau(Option<Plateaus>),
    /// [`Unit::Heading`]: `(x, mean cos, s.e.)` per start.
    Heading(#[serde(with = "swarm_sim::json")] Vec<(f64, f64, f64)>),
    /// [`Unit::Start`].
    Start(Vec<StartRun>),
    /// [`Unit::Steep`].
    Steep(Vec<Times>),
    /// [`Unit::Refractory`].
    Refractory(RefractoryRuns),
    /// [`Unit::Cycle`].
    Cycle(Vec<CycleRun>),
    /// [`Unit::Knob`]: per case, one point per value.
    Knob(Vec<Vec<SweepPoint>>),
    /// [`Unit::Slope`].
    Slope(SlopeRuns),
    /// [`Unit::Extent`].
    Extent(Vec<ExtentRun>),
    /// [`Unit::Shapes`].
    Shapes(Box<ShapesResult>),
    /// [`Unit::BeyondSuccess`]: per field, one point per measure.
    BeyondSuccess(Vec<Vec<SweepPoint>>),
    /// [`Unit::BeyondAlong`].
    BeyondAlong(Along),
    /// [`Unit::BeyondTwo`]: one point per measure.
    BeyondTwo(Vec<SweepPoint>),
    /// [`Unit::Waves`].
    Waves(Wave),
    /// [`Unit::Speed`].
    Speed(Vec<BenchResult>),
    /// [`Unit::PeerWork`]: wall seconds per run.
    PeerWork(#[serde(with = "swarm_sim::json")] f64),
    /// [`Unit::Placements`].
    Placements(PlacementStats),
    /// [`Unit::Indecision`]: one split per run, sizes in order.
    Indecision(Vec<Split>),
}

impl Outcome {
    /// Whether this is the kind of result `unit` gives.
    fn fits(&self, unit: Unit) -> bool {
        use Outcome as O;
        matches!(
            (unit, self),
            (Unit::Run(_), O::Run(_))
                | (Unit::Sweep(..), O::Sweep(_))
                | (Unit::Map(..) | Unit::CaptionMap, O::Map(_))
                | (
                    Unit::CloudProfile(_) | Unit::CaptionProfile(_),
                    O::Profile(_)
                )
                | (Unit::Course(..), O::Course(..))
                | (Unit::Sensor(_), O::Sensor(_))
                | (Unit::Plateau(..), O::Plateau(_))
                | (Unit::Heading(_), O::Heading(_))
                | (Unit::Start(..), O::Start(_))
                | (Unit::Steep(..), O::Steep(_))
                | (Unit::Refractory, O::Refractory(_))
                | (Unit::Cycle, O::Cycle(_))
                | (Unit::Knob(_), O::Knob(_))
                | (Unit::Slope, O::Slope(_))
                | (Unit::Extent(_), O::Extent(_))
                | (Unit::Shapes, O::Shapes(_))
                | (Unit::BeyondSuccess, O::BeyondSuccess(_))
                | (Unit::BeyondAlong, O::BeyondAlong(_))
                | (Unit::BeyondTwo, O::BeyondTwo(_))
                | (Unit::Waves, O::Waves(_))
                | (Unit::Speed, O::Speed(_))
                | (Unit::PeerWork, O::PeerWork(_))
                | (Unit::Placements, O::Placements(_))
                | (Unit::Indecision(_), O::Indecision(_))
        )
    }
}

/// The units' results the page is written from (`pages::reproduction::write`): empty at first, filled
/// unit by unit ([`Results::insert`]), complete when no unit is [`Results::missing`].
#[derive(Clone, Debug, Default)]
pub struct Results {
    by_unit: BTreeMap<Unit, UnitResult>,
    /// The page's wall time when its units ran side by side in one command
    /// ([`Results::set_wall_s`]); otherwise the units' added up.
    wall_s: Option<f64>,
}

/// Typed access to one kind of result: `$name(unit)` is the result of `unit` if it is a
/// `$variant`.
macro_rules! getter {
    ($name:ident, $variant:ident, $ty:ty) => {
        #[doc = concat!("The result of `unit`, a [`Outcome::", stringify!($variant), "`].")]
        pub fn $name(&self, unit: Unit) -> Result<&$ty, Error> {
            match &self.get(unit)?.outcome {
                Outcome::$variant(v) => Ok(v),
                _ => Err(Error::WrongKind(unit, stringify!($variant))),
            }
        }
    };
}

impl Results {
    /// Adds one unit's result.
    ///
    /// # Errors
    /// If the unit already has a result, or the result is not of the unit's kind.
    pub fn insert(&mut self, r: UnitResult) -> Result<(), Error> {
        if !r.outcome.fits(r.unit) {
            return Err(Error::NotOfKind(r.unit));
        }
        if self.by_unit.contains_key(&r.unit) {
            return Err(Error::SecondResult(r.unit));
        }
        self.by_unit.insert(r.unit, r);
        Ok(())
    }

    /// The units of [`UNITS`] without a result yet, in order.
    pub fn missing(&self) -> Vec<Unit> {
        UNITS
            .iter()
            .copied()
            .filter(|u| !self.by_unit.contains_key(u))
            .collect()
    }

    /// The results, in unit order.
    pub fn iter(&self) -> impl Iterator<Item = &UnitResult> {
        self.by_unit.values()
    }

    /// The page's "whole page in … s": the time set by [`Results::set_wall_s`], or else the
    /// sum of the units' wall times (a merge of shards, each run one unit after another).
    pub fn wall_s(&self) -> f64 {
        self.wall_s
            .unwrap_or_else(|| self.by_unit.values().map(|r| r.wall_s).sum())
    }

    /// Sets the page's wall time: the units ran side by side, so their own times overlap and
    /// their sum is not the page's.
    pub fn set_wall_s(&mut self, s: f64) {
        self.wall_s = Some(s);
    }

    /// The most threads any unit ran on.
    pub fn threads(&self) -> usize {
        self.by_unit.values().map(|r| r.threads).max().unwrap_or(0)
    }

    /// The result of `unit`.
    ///
    /// # Errors
    /// If it has none.
    fn get(&self, unit: Unit) -> Result<&UnitResult, Error> {
        self.by_unit.get(&unit).ok_or(Error::NoResult(unit))
    }

    getter!(run, Run, RunFigure);
    getter!(sweep, Sweep, Vec<SweepPoint>);
    getter!(map, Map, Vec<Arrow>);
    getter!(profile, Profile, Vec<RadialPoint>);

    /// The averaged course of `unit` (a [`Unit::Course`], either placement).
    ///
    /// # Errors
    /// If it has no result, or `unit` is not a course.
    pub fn course(&self, unit: Unit) -> Result<&TimeCourse, Error> {
        match &self.get(unit)?.outcome {
            Outcome::Course(c, _) => Ok(c),
            _ => Err(Error::WrongKind(unit, "Course")),
        }
    }

    /// What the tapped runs of field `f`'s averaged course with `side`'s placement give.
    ///
    /// # Errors
    /// If that course has no result.
    pub fn tapped(&self, f: Field, side: Side) -> Result<&CourseDigest, Error> {
        let unit = Unit::Course(f, side);
        match &self.get(unit)?.outcome {
            Outcome::Course(_, d) => Ok(d),
            _ => Err(Error::WrongKind(unit, "Course")),
        }
    }

    getter!(sensor, Sensor, Levels);
    getter!(plateau, Plateau, Option<Plateaus>);
    getter!(heading, Heading, Vec<(f64, f64, f64)>);
    getter!(start, Start, Vec<StartRun>);
    getter!(steep, Steep, Vec<Times>);
    getter!(refractory, Refractory, RefractoryRuns);
    getter!(cycle, Cycle, Vec<CycleRun>);
    getter!(knob, Knob, Vec<Vec<SweepPoint>>);
    getter!(slope, Slope, SlopeRuns);
    getter!(extent, Extent, Vec<ExtentRun>);
    getter!(shapes, Shapes, ShapesResult);
    getter!(beyond_success, BeyondSuccess, Vec<Vec<SweepPoint>>);
    getter!(beyond_along, BeyondAlong, Along);
    getter!(beyond_two, BeyondTwo, Vec<SweepPoint>);
    getter!(waves, Waves, Wave);
    getter!(speed, Speed, Vec<BenchResult>);
    getter!(peer_work, PeerWork, f64);
    getter!(placements, Placements, PlacementStats);
    getter!(indecision, Indecision, Vec<Split>);
}
