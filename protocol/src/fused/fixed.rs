//! [`DecisionRule::Fixed`], the paper's rule: a robot votes its preference in every ray it
//! sends and decides by majority at the end of every negotiation period, nothing in between.

use super::Core;
use super::rule::Rule;
use crate::direction::Sector;
use crate::params::{DecisionRule, Params};
use crate::time::Instant;

/// The fixed rule. It keeps no state of its own.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fixed;

impl Rule for Fixed {
    fn start(_params: &Params, _now: Instant) -> Self {
        Fixed
    }

    fn decides(&self) -> DecisionRule {
        DecisionRule::Fixed
    }

    /// Decides by the votes held (rays not refreshed within the period forgotten first), then
    /// shrinks the diversities to their one-message prior (module docs of [`super`]).
    fn end_of_period(&mut self, core: &mut Core, now: Instant) {
        core.expire_rays(now);
        core.count_period();
        core.decide_by_votes();
        core.weights.shrink_to_prior();
    }

    /// The preference, always; rays are never closed.
    fn ray_to_send(&mut self, core: &Core, _sector: Sector) -> (Option<Sector>, bool) {
        (core.pref, false)
    }
}
