//! What a run produced: [`RunReport`].

use firmware::{LedColor, Stats};
use protocol::fused::NodeStats;
use protocol::wave::WaveStats;
use protocol::{Duration, Instant};

use super::camera::{LedChange, leds_at};
use super::motion::Move;
use crate::world::hil::HilReport;
use crate::world::medium::{MediumStats, TraceEvent};

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Every LED change, in time order.
    pub leds: Vec<LedChange>,
    /// Each robot's LEDs at the end.
    pub final_leds: Vec<LedColor>,
    /// The trace, if asked for.
    pub trace: Vec<TraceEvent>,
    /// The medium's frame counts.
    pub medium: MediumStats,
    /// Each robot's counters (of its last life).
    pub robots: Vec<Stats>,
    /// Each robot's wave counters (of its last life): waves initiated, relayed, initiations
    /// skipped while busy.
    pub waves: Vec<WaveStats>,
    /// Each robot's protocol counters (of its last life): messages scored, rays, negotiation
    /// periods and those in which it initiated fewer waves than cycles.
    pub nodes: Vec<NodeStats>,
    /// Emulated time.
    pub emulated: Duration,
    /// Wall time the run took.
    pub wall: std::time::Duration,
    /// The swarm's moves, with [`ArenaConfig::motion`](super::ArenaConfig::motion).
    pub moves: Vec<Move>,
    /// Each robot in the loop's link ([`ArenaConfig::hil`](super::ArenaConfig::hil)), by place.
    pub hil: Vec<HilReport>,
}

impl RunReport {
    /// The LEDs of every robot at `t` (the last change at or before `t`).
    pub fn leds_at(&self, t: Instant) -> Vec<LedColor> {
        leds_at(&self.leds, self.robots.len(), t)
    }

    /// The earliest time from which every robot's LEDs showed `expected` without a change
    /// until `until`: the last LED change at or before `until`, if the LEDs then show
    /// `expected`.
    pub fn consensus_since(&self, expected: &[LedColor], until: Instant) -> Option<Instant> {
        if self.leds_at(until) != expected {
            return None;
        }
        let last = self.leds.iter().rev().find(|c| c.t <= until).map(|c| c.t);
        Some(last.unwrap_or(Instant::ZERO))
    }
}
