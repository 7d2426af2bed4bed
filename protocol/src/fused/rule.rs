//! The decision rule behind a small trait, as quinn-proto keeps congestion control behind its
//! `Controller`: [`FusedNode`](super::FusedNode) runs the waves, scores directions and keeps
//! the rays ([`Core`]); a [`Rule`] decides when to show what, what the robot votes in the rays
//! it sends, and any extra initiations. Each rule is one file of this module ([`Fixed`](super::Fixed),
//! [`Adaptive`](super::Adaptive)); [`AnyRule`](super::AnyRule) (`any.rs`) picks one from
//! [`Params::decide`](crate::Params) at run time. A third rule is one new file, a
//! [`DecisionRule`] variant and an arm in `AnyRule`.

use rand_core::RngCore;

use super::Core;
use crate::direction::Sector;
use crate::message::{Level, Ray, Tag};
use crate::params::{DecisionRule, Params};
use crate::time::Instant;

/// What just happened, for [`Rule::react`]. The node calls it once the core has done its part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// A message was handled; `Some(sector)` if a ray was taken from that sector.
    Reception(Option<Sector>),
    /// [`Rule::begin_timeout`] asked to react, and the wave's due actions are done.
    Timeout,
    /// The robot just initiated a wave.
    Initiated,
    /// One of the robot's cycles ended (after the period's end, if it was one).
    CycleEnded,
}

/// How a rule treats the rays and diversities the core keeps. The fixed rule's is the
/// [`Default`] (all `false`): the paper's averages and the loosest ray-taking.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayPolicy {
    /// A side's diversity is its latest ray's (set, not averaged), and a ray taken while the
    /// robot is busy is scored too.
    pub latest_ray_scores: bool,
    /// Without a ray from a side, a message's hops stand for it (a ray built from them).
    pub hops_stand_for_side: bool,
    /// Rays are taken strictly: a robot followed on another side is refused however old that
    /// ray, and the followed robot's shorter ray within the switch time.
    pub strict: bool,
}

/// A decision rule: the hooks [`FusedNode`](super::FusedNode) calls. Every hook but
/// [`end_of_period`](Self::end_of_period) and [`ray_to_send`](Self::ray_to_send) does nothing
/// by default. A hook must draw randomness only from the `rng` it is given, and read time only
/// from `now`: the node stays sans-IO and a seed replays a run bit for bit.
pub trait Rule {
    /// The rule, for a node starting at `now` with `params` (already valid).
    fn start(params: &Params, now: Instant) -> Self;

    /// The [`DecisionRule`] this is (`Params::decide` of a node that runs it).
    fn decides(&self) -> DecisionRule;

    /// How rays and diversities are kept under this rule.
    fn policy(&self) -> RayPolicy {
        RayPolicy::default()
    }

    /// The next instant the rule needs [`begin_timeout`](Self::begin_timeout) called at
    /// (`Instant::MAX`: never).
    fn poll_timeout(&self) -> Instant {
        Instant::MAX
    }

    /// A new sensor reading, before the core takes it.
    fn on_reading(&mut self, _core: &Core, _reading: Level) {}

    /// A message arrived from `from` (a sector below K), whatever becomes of it.
    fn heard_from(&mut self, _from: Sector) {}

    /// The start of the node's `handle_timeout` at `now`, before the wave's due actions.
    /// Returns true to be called with [`Cause::Timeout`] once they are done.
    fn begin_timeout(&mut self, _core: &Core, _now: Instant) -> bool {
        false
    }

    /// After something happened ([`Cause`]): settle a decision, ask for news, etc.
    fn react(&mut self, _core: &mut Core, _now: Instant, _cause: Cause, _rng: &mut impl RngCore) {}

    /// The end of a negotiation period.
    fn end_of_period(&mut self, core: &mut Core, now: Instant);

    /// The sector whose ray the initiation going out now carries, if the rule asked for this
    /// one (else the core's round robin over the shortest sides).
    fn initiation_sector(&mut self) -> Option<Sector> {
        None
    }

    /// The robot sends its ray of `sector`: the vote that ray carries, and whether a ray the
    /// robot starts itself (nothing held from `sector`) is [closed](Ray::closed).
    fn ray_to_send(&mut self, core: &Core, sector: Sector) -> (Option<Sector>, bool);

    /// True if `ray` from `sender`, heard from `from`, is a stale ray coming back (refused).
    fn is_replay(
        &self,
        _core: &Core,
        _now: Instant,
        _from: Sector,
        _ray: &Ray,
        _sender: Tag,
    ) -> bool {
        false
    }

    /// `ray` from `sender` is taken for `from`; `core` still holds the ray it replaces.
    fn ray_taken(&mut self, _core: &Core, _now: Instant, _from: Sector, _ray: &Ray, _sender: Tag) {}
}
