//! [`AnyRule`]: the rule [`Params::decide`] names, chosen at run time. Its own file, so that
//! the rules depend on the [`Rule`] trait and this file on the rules, and no file on one that
//! depends on it.

use rand_core::RngCore;

use super::adaptive::Adaptive;
use super::fixed::Fixed;
use super::rule::{Cause, RayPolicy, Rule};
use super::state::Core;
use crate::direction::Sector;
use crate::message::{Level, Ray, Tag};
use crate::params::{DecisionRule, Params};
use crate::time::Instant;

/// The rule [`Params::decide`](crate::Params) names, chosen at run time: what the robot
/// program, the emulator and the CLI's `--decide` use. A build that runs one rule only can name
/// it instead ([`FusedNode::with_rule`](super::FusedNode::with_rule)).
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)] // one per robot, never moved in a hot path
pub enum AnyRule {
    /// [`DecisionRule::Fixed`].
    Fixed(Fixed),
    /// [`DecisionRule::Adaptive`].
    Adaptive(Adaptive),
}

/// Calls `$call` on whichever rule `$self` holds.
macro_rules! each {
    ($self:expr, $r:ident => $call:expr) => {
        match $self {
            AnyRule::Fixed($r) => $call,
            AnyRule::Adaptive($r) => $call,
        }
    };
}

impl Rule for AnyRule {
    fn start(params: &Params, now: Instant) -> Self {
        match params.decide {
            DecisionRule::Fixed => AnyRule::Fixed(Fixed::start(params, now)),
            DecisionRule::Adaptive => AnyRule::Adaptive(Adaptive::start(params, now)),
        }
    }
    fn decides(&self) -> DecisionRule {
        each!(self, r => r.decides())
    }
    fn policy(&self) -> RayPolicy {
        each!(self, r => r.policy())
    }
    fn poll_timeout(&self) -> Instant {
        each!(self, r => r.poll_timeout())
    }
    fn on_reading(&mut self, core: &Core, reading: Level) {
        each!(self, r => r.on_reading(core, reading))
    }
    fn heard_from(&mut self, from: Sector) {
        each!(self, r => r.heard_from(from))
    }
    fn begin_timeout(&mut self, core: &Core, now: Instant) -> bool {
        each!(self, r => r.begin_timeout(core, now))
    }
    fn react(&mut self, core: &mut Core, now: Instant, cause: Cause, rng: &mut impl RngCore) {
        each!(self, r => r.react(core, now, cause, rng))
    }
    fn end_of_period(&mut self, core: &mut Core, now: Instant) {
        each!(self, r => r.end_of_period(core, now))
    }
    fn initiation_sector(&mut self) -> Option<Sector> {
        each!(self, r => r.initiation_sector())
    }
    fn ray_to_send(&mut self, core: &Core, sector: Sector) -> (Option<Sector>, bool) {
        each!(self, r => r.ray_to_send(core, sector))
    }
    fn is_replay(&self, core: &Core, now: Instant, from: Sector, ray: &Ray, sender: Tag) -> bool {
        each!(self, r => r.is_replay(core, now, from, ray, sender))
    }
    fn ray_taken(&mut self, core: &Core, now: Instant, from: Sector, ray: &Ray, sender: Tag) {
        each!(self, r => r.ray_taken(core, now, from, ray, sender))
    }
}
