//! The units of work of `swarm reproduce`: one per stage (one progress bar, one seed or a
//! fixed set of seeds), each computed on its own ([`crate::compute()`]) from the options alone,
//! in the fixed order of [`UNITS`]. A unit's name ([`Unit::name`]) is how part files and logs
//! name it.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::Error;
use swarm_sim::scenario::Placement;

/// One of the paper's two fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Field {
    /// The sharp border (`sharp`).
    Sharp,
    /// The gradient (`gradient`).
    Gradient,
}

impl Field {
    /// Both, in the page's order.
    pub const BOTH: [Field; 2] = [Field::Sharp, Field::Gradient];

    /// 0 for the sharp border, 1 for the gradient: the index of the page's arrays and seeds.
    pub fn index(self) -> usize {
        self as usize
    }

    fn name(self) -> &'static str {
        ["sharp", "gradient"][self.index()]
    }
}

/// Which placement a unit runs with: the page's ([`crate::Options::placement`]) or the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    /// The page's placement.
    Main,
    /// The other one.
    Other,
}

impl Side {
    /// Both, main first.
    pub const BOTH: [Side; 2] = [Side::Main, Side::Other];

    /// 0 for the main placement, 1 for the other.
    pub fn index(self) -> usize {
        self as usize
    }

    fn name(self) -> &'static str {
        ["main", "other"][self.index()]
    }
}

/// The scenario of a direction map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Scene {
    /// `sharp`.
    Sharp,
    /// `gradient`.
    Gradient,
    /// `cloud`, the text's cloud.
    Cloud,
}

impl Scene {
    /// 0, 1, 2 as listed: the index of the page's maps and their seeds.
    pub fn index(self) -> usize {
        self as usize
    }

    fn name(self) -> &'static str {
        ["sharp", "gradient", "cloud"][self.index()]
    }
}

/// One unit of work of `swarm reproduce`. Those with an index count from 0 over a list of the
/// stage's module: plateau cycles 250, 500, 1000, 2000 s; steepness cases the sharp border,
/// then slopes 1, 2.5, 5, 10, 20; knobs cycle, period, diffusion, noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Unit {
    /// Figs. 5 and 8: the first successful of up to [`crate::RUN_TRIES`] runs.
    Run(Field),
    /// Figs. 6 and 9: a sweep of starts.
    Sweep(Field, Side),
    /// Figs. 7, 10, 11: a direction map, with the page's placement or the other.
    Map(Scene, Side),
    /// The text's cloud's radial profile, with the page's placement or the other.
    CloudProfile(Side),
    /// The caption's cloud's direction map.
    CaptionMap,
    /// The caption's cloud's radial profile, with the page's placement or the other.
    CaptionProfile(Side),
    /// Figs. 5b and 8b averaged, with the page's placement or the other; the runs are tapped
    /// as they run (what "Settling the open rows" reads off them,
    /// [`crate::results::CourseDigest`]).
    Course(Field, Side),
    /// The averaged courses with one sensor reading per period.
    Sensor(Field),
    /// The sharp plateau at one cycle (the page's own cycle with the main placement is the
    /// courses' runs: that unit runs nothing).
    Plateau(Side, u8),
    /// The first move's heading along the way to the line.
    Heading(Field),
    /// The starting diversity against the agents across.
    Start(Field, Side),
    /// Steeper ramps: one case, with the page's placement or the other.
    Steep(u8, Side),
    /// The refractory time, off and on.
    Refractory,
    /// The cycle length (sharp).
    Cycle,
    /// Sensitivity to one knob.
    Knob(u8),
    /// Sensitivity to the gradient's slope.
    Slope,
    /// The swarm's extent against the perception edges (the other placement: the page's
    /// extent only).
    Extent(Side),
    /// The discussion's shapes on a random field.
    Shapes,
    /// Beyond the paper: success with the entropy.
    BeyondSuccess,
    /// Beyond the paper: both measures along the gradient.
    BeyondAlong,
    /// Beyond the paper: two quantities.
    BeyondTwo,
    /// One wave (Fig. 2).
    Waves,
    /// The simulator's speed (wall-clock figures).
    Speed,
    /// The NumPy peer's work (`scripts/numpy_peer.py`) on one thread (wall-clock figure).
    PeerWork,
    /// Neighbour counts of random placements.
    Placements,
    /// Indecision points against the swarm's size.
    Indecision(Side),
}

use Field::{Gradient as G, Sharp as S};
use Side::{Main as M, Other as O};

/// Every unit, in the order the unsharded command computes them.
pub const UNITS: [Unit; 68] = [
    Unit::Run(S),
    Unit::Run(G),
    Unit::Sweep(S, M),
    Unit::Sweep(S, O),
    Unit::Sweep(G, M),
    Unit::Sweep(G, O),
    Unit::Map(Scene::Sharp, M),
    Unit::Map(Scene::Gradient, M),
    Unit::Map(Scene::Cloud, M),
    Unit::Map(Scene::Sharp, O),
    Unit::Map(Scene::Gradient, O),
    Unit::Map(Scene::Cloud, O),
    Unit::CloudProfile(M),
    Unit::CloudProfile(O),
    Unit::CaptionMap,
    Unit::CaptionProfile(M),
    Unit::CaptionProfile(O),
    Unit::Course(S, M),
    Unit::Course(S, O),
    Unit::Course(G, M),
    Unit::Course(G, O),
    Unit::Sensor(S),
    Unit::Sensor(G),
    Unit::Plateau(M, 0),
    Unit::Plateau(M, 1),
    Unit::Plateau(M, 2),
    Unit::Plateau(M, 3),
    Unit::Plateau(O, 0),
    Unit::Plateau(O, 1),
    Unit::Plateau(O, 2),
    Unit::Plateau(O, 3),
    Unit::Heading(S),
    Unit::Heading(G),
    Unit::Start(S, M),
    Unit::Start(S, O),
    Unit::Start(G, M),
    Unit::Start(G, O),
    Unit::Steep(0, M),
    Unit::Steep(1, M),
    Unit::Steep(2, M),
    Unit::Steep(3, M),
    Unit::Steep(4, M),
    Unit::Steep(5, M),
    Unit::Steep(0, O),
    Unit::Steep(1, O),
    Unit::Steep(2, O),
    Unit::Steep(3, O),
    Unit::Steep(4, O),
    Unit::Steep(5, O),
    Unit::Refractory,
    Unit::Cycle,
    Unit::Knob(0),
    Unit::Knob(1),
    Unit::Knob(2),
    Unit::Knob(3),
    Unit::Slope,
    Unit::Extent(M),
    Unit::Extent(O),
    Unit::Shapes,
    Unit::BeyondSuccess,
    Unit::BeyondAlong,
    Unit::BeyondTwo,
    Unit::Indecision(M),
    Unit::Indecision(O),
    Unit::PeerWork,
    Unit::Waves,
    Unit::Speed,
    Unit::Placements,
];

/// Every unit of `swarm reproduce`, in a fixed order ([`UNITS`]).
pub fn units() -> &'static [Unit] {
    &UNITS
}

impl Unit {
    /// The unit's name: `run/sharp`, `sweep/gradient/other`, `map/cloud`, `plateau/main/2`,
    /// `steep/0`, `knob/3`, `cloud-profile`, …; [`FromStr`] reads it back.
    pub fn name(self) -> String {
        match self {
            Unit::Run(f) => format!("run/{}", f.name()),
            Unit::Sweep(f, s) => format!("sweep/{}/{}", f.name(), s.name()),
            Unit::Map(m, s) => format!("map/{}/{}", m.name(), s.name()),
            Unit::Course(f, s) => format!("course/{}/{}", f.name(), s.name()),
            Unit::Sensor(f) => format!("sensor/{}", f.name()),
            Unit::Plateau(s, k) => format!("plateau/{}/{k}", s.name()),
            Unit::Heading(f) => format!("heading/{}", f.name()),
            Unit::Start(f, s) => format!("start/{}/{}", f.name(), s.name()),
            Unit::Steep(k, s) => format!("steep/{k}/{}", s.name()),
            Unit::Knob(k) => format!("knob/{k}"),
            Unit::CloudProfile(s) => format!("cloud-profile/{}", s.name()),
            Unit::CaptionMap => "caption-map".into(),
            Unit::CaptionProfile(s) => format!("caption-profile/{}", s.name()),
            Unit::Refractory => "refractory".into(),
            Unit::Cycle => "cycle".into(),
            Unit::Slope => "slope".into(),
            Unit::Extent(s) => format!("extent/{}", s.name()),
            Unit::Shapes => "shapes".into(),
            Unit::BeyondSuccess => "beyond-success".into(),
            Unit::BeyondAlong => "beyond-along".into(),
            Unit::BeyondTwo => "beyond-two".into(),
            Unit::Waves => "waves".into(),
            Unit::Speed => "speed".into(),
            Unit::PeerWork => "peer-work".into(),
            Unit::Placements => "placements".into(),
            Unit::Indecision(s) => format!("indecision/{}", s.name()),
        }
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl FromStr for Unit {
    type Err = Error;

    /// The unit of [`UNITS`] with this [`Unit::name`].
    fn from_str(s: &str) -> Result<Unit, Error> {
        UNITS
            .iter()
            .copied()
            .find(|u| u.name() == s)
            .ok_or_else(|| Error::NoUnit(s.to_owned()))
    }
}

impl Serialize for Unit {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

impl<'de> Deserialize<'de> for Unit {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Unit, D::Error> {
        String::deserialize(d)?
            .parse()
            .map_err(serde::de::Error::custom)
    }
}

/// The placement of `side` when the page's is `main`.
pub fn placement(main: Placement, side: Side) -> Placement {
    match side {
        Side::Main => main,
        Side::Other => main.other(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_unit_has_its_own_name_and_reads_back() {
        let mut names: Vec<String> = UNITS.iter().map(|u| u.name()).collect();
        for u in UNITS {
            assert_eq!(u.name().parse::<Unit>().unwrap(), u);
        }
        names.sort();
        names.dedup();
        assert_eq!(names.len(), UNITS.len());
        let e = "plateau/main/4".parse::<Unit>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "no unit of swarm reproduce is named \"plateau/main/4\""
        );
    }
}
