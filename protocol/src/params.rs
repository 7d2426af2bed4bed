//! Every parameter of the protocol in one place, with the paper's defaults and validation.

use core::fmt;

use crate::direction::MAX_SECTORS;
use crate::message::MAX_HOPS;
use crate::time::Duration;

/// When, within its cycle, a robot initiates its wave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum InitiationPoint {
    /// At the end of each cycle, whose length is drawn anew every cycle: what the aMussels did
    /// ("randomized the time when they initiated a message ... at the beginning of every cycle";
    /// the effective cycle varied between 40 and 70 s).
    EndOfCycle,
    /// At a uniformly random time in `(0, L]` of each cycle of length `L` (the paper's Alg. 1:
    /// "timer ← random integer ∈ (0, t_p^max]"). With no spread every agent started at the same
    /// instant shares the cycle boundaries, which the three-phase variant needs for its phases.
    Uniform,
}

/// Timing of the wave paradigm (paper section 2.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WaveParams {
    /// Mean cycle length `t_p^max`.
    pub cycle: Duration,
    /// Each cycle's length is drawn uniformly from `cycle ± cycle_spread`.
    pub cycle_spread: Duration,
    /// Where in the cycle the initiation falls.
    pub initiation: InitiationPoint,
    /// Delay between receiving a message and relaying it (`t_delay`, 1 s).
    pub relay_delay: Duration,
    /// Time after transmitting during which every message is ignored.
    pub refractory: Duration,
    /// Granularity of every random draw (1 s makes them "random integers" as in Alg. 1).
    pub tick: Duration,
}

/// When a robot of the fused variant decides, i.e. shows a decision on its LEDs
/// (`docs/protocol.md` §5.4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecisionRule {
    /// At the end of every negotiation period of [`Params::negotiation_cycles`] cycles, as the
    /// paper's robots did ("every aMussel initiated at least 10 messages").
    #[default]
    Fixed,
    /// As soon as the evidence is settled: the robot has heard every side it can hear or a
    /// whole cycle has passed, the votes it holds give one direction that the robots it holds
    /// without a vote cannot overturn, and every side confirmed that direction with a later ray.
    /// At the latest at the end of a negotiation period, by the fixed rule (the cap).
    Adaptive,
}

/// All protocol parameters. [`Params::robots`] (also `Default`) is the aMussel lab; [`Params::simulation_2d`]
/// the paper's 2D simulations.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Params {
    /// Wave timing.
    pub wave: WaveParams,
    /// Receive sectors K (2 for robots in a line, up to [`MAX_SECTORS`]); fused variant only.
    pub sectors: u8,
    /// Fused variant: cycles per negotiation period (10 on the robots).
    pub negotiation_cycles: u16,
    /// Three-phase variant: cycles of information gathering per negotiation period.
    pub gather_cycles: u16,
    /// Three-phase variant: cycles of opinion diffusion per negotiation period.
    pub decide_cycles: u16,
    /// Three-phase variant: fraction of the shorter arc an opinion moves toward a received one.
    pub diffusion: f32,
    /// Fused variant: the most hops a message this robot relays keeps (its oldest hops are
    /// dropped to make room): the frame's capacity. [`MAX_HOPS`] (12) for plain frames;
    /// authenticated frames hold [`crate::frame::KEYED_MAX_HOPS`] (11), and the firmware
    /// lowers it to that when a swarm key is set.
    pub max_hops: u8,
    /// Fused variant: when a robot decides ([`DecisionRule::Fixed`] on the robots, as in the
    /// paper).
    pub decide: DecisionRule,
}

impl Params {
    /// The longest cycle a robot can draw (cycle + spread): within it every neighbour in range
    /// initiates at least once.
    pub fn longest_cycle(&self) -> Duration {
        self.wave.cycle + self.wave.cycle_spread
    }

    /// A negotiation period of mean cycles (fused variant): on a plane, the time between two
    /// moves of the swarm.
    pub fn nominal_period(&self) -> Duration {
        self.wave
            .cycle
            .saturating_mul(u64::from(self.negotiation_cycles))
    }

    /// How long a lab run lasts unless told otherwise (`cimax arena` and its campaign): three
    /// negotiation periods of the longest cycle, plus 1 s, so that every robot decides at
    /// least twice.
    pub fn lab_run(&self) -> Duration {
        self.longest_cycle()
            .saturating_mul(3 * u64::from(self.negotiation_cycles))
            + Duration::from_secs(1)
    }

    /// The aMussel lab experiment: from the paper's Table 1 a cycle of 55 ± 15 s (initiated at
    /// its end), refractory 4 s and a negotiation period of 10 cycles; from section 2.1 the
    /// relay delay `t_delay` = 1 s; K = 2 sectors for robots in a line.
    pub const fn robots() -> Self {
        Params {
            wave: WaveParams {
                cycle: Duration::from_secs(55),
                cycle_spread: Duration::from_secs(15),
                initiation: InitiationPoint::EndOfCycle,
                relay_delay: Duration::from_secs(1),
                refractory: Duration::from_secs(4),
                tick: Duration::from_millis(1),
            },
            sectors: 2,
            negotiation_cycles: 10,
            gather_cycles: 1,
            decide_cycles: 1,
            diffusion: 0.1,
            max_hops: MAX_HOPS as u8,
            decide: DecisionRule::Fixed,
        }
    }

    /// The paper's 2D simulations (section 3): 1 s steps, refractory 10 s (the wave figure),
    /// negotiation period of 2 cycles (one gathering, one diffusion), 10 % diffusion.
    ///
    /// The paper does not give `t_p^max`. It must let waves flood the swarm without colliding
    /// (`shared/paper-notes.md`: on the order of N × (refractory + hops across)); 1000 s suits
    /// 61 agents. The 2D simulator shows the effect of changing it.
    pub const fn simulation_2d() -> Self {
        Params {
            wave: WaveParams {
                cycle: Duration::from_secs(1000),
                cycle_spread: Duration::ZERO,
                initiation: InitiationPoint::Uniform,
                relay_delay: Duration::from_secs(1),
                refractory: Duration::from_secs(10),
                tick: Duration::from_secs(1),
            },
            sectors: 8,
            negotiation_cycles: 2,
            gather_cycles: 1,
            decide_cycles: 1,
            diffusion: 0.1,
            max_hops: MAX_HOPS as u8,
            decide: DecisionRule::Fixed,
        }
    }

    /// Checks that the parameters make sense together.
    ///
    /// # Errors
    /// The first problem found, as a [`ParamError`] whose `Display` names it.
    pub fn validate(&self) -> Result<(), ParamError> {
        let w = &self.wave;
        if w.cycle == Duration::ZERO {
            return Err(ParamError::ZeroCycle);
        }
        if w.tick == Duration::ZERO {
            return Err(ParamError::ZeroTick);
        }
        if w.cycle_spread >= w.cycle {
            return Err(ParamError::SpreadNotBelowCycle);
        }
        if w.relay_delay == Duration::ZERO {
            return Err(ParamError::ZeroRelayDelay);
        }
        if w.refractory <= w.relay_delay {
            return Err(ParamError::RefractoryNotAboveRelayDelay);
        }
        let shortest = w.cycle - w.cycle_spread;
        if w.relay_delay + w.refractory >= shortest {
            return Err(ParamError::RefractoryNotBelowCycle);
        }
        if shortest < w.tick {
            return Err(ParamError::CycleBelowTick);
        }
        if !(2..=MAX_SECTORS as u8).contains(&self.sectors) {
            return Err(ParamError::BadSectorCount);
        }
        if self.negotiation_cycles == 0 || self.gather_cycles == 0 || self.decide_cycles == 0 {
            return Err(ParamError::ZeroPeriod);
        }
        if !(self.diffusion > 0.0 && self.diffusion <= 1.0) {
            return Err(ParamError::BadDiffusion);
        }
        if !(1..=MAX_HOPS).contains(&usize::from(self.max_hops)) {
            return Err(ParamError::BadHopCapacity);
        }
        Ok(())
    }
}

impl Default for Params {
    fn default() -> Self {
        Params::robots()
    }
}

/// A parameter set that makes no sense.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamError {
    /// The cycle length is zero.
    ZeroCycle,
    /// The tick (granularity of random draws) is zero.
    ZeroTick,
    /// The cycle spread is not below the cycle: a cycle could have no length.
    SpreadNotBelowCycle,
    /// The relay delay is zero.
    ZeroRelayDelay,
    /// A robot would be re-activated by the relay of the neighbour it just activated.
    RefractoryNotAboveRelayDelay,
    /// Relay delay plus refractory time is not below the shortest cycle.
    RefractoryNotBelowCycle,
    /// The shortest cycle is shorter than one tick.
    CycleBelowTick,
    /// The number of sectors is not in `2..=8`.
    BadSectorCount,
    /// A negotiation period or phase of zero cycles.
    ZeroPeriod,
    /// The diffusion fraction is not in `(0, 1]`.
    BadDiffusion,
    /// `max_hops` is not in `1..=MAX_HOPS`.
    BadHopCapacity,
    /// `decide` names another rule than the node's type runs
    /// ([`FusedNode::with_rule`](crate::FusedNode::with_rule)).
    RuleMismatch,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParamError::ZeroCycle => "the cycle length must be positive",
            ParamError::ZeroTick => "the tick must be positive",
            ParamError::SpreadNotBelowCycle => "the cycle spread must be smaller than the cycle",
            ParamError::ZeroRelayDelay => "the relay delay must be positive",
            ParamError::RefractoryNotAboveRelayDelay => {
                "the refractory time must be longer than the relay delay, or waves bounce back"
            }
            ParamError::RefractoryNotBelowCycle => {
                "relay delay plus refractory time must be shorter than the shortest cycle"
            }
            ParamError::CycleBelowTick => "the shortest cycle must be at least one tick",
            ParamError::BadSectorCount => "the number of sectors must be between 2 and 8",
            ParamError::ZeroPeriod => "negotiation periods and phases must last at least one cycle",
            ParamError::BadDiffusion => "the diffusion fraction must be in (0, 1]",
            ParamError::BadHopCapacity => "the hops per message must be between 1 and 12",
            ParamError::RuleMismatch => "the decision rule differs from the one the node runs",
        })
    }
}

impl core::error::Error for ParamError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_the_papers() {
        let p = Params::default();
        assert_eq!(p.validate(), Ok(()));
        assert_eq!(p.wave.cycle, Duration::from_secs(55));
        assert_eq!(p.wave.cycle_spread, Duration::from_secs(15));
        assert_eq!(p.wave.refractory, Duration::from_secs(4));
        assert_eq!(p.negotiation_cycles, 10);
        assert_eq!(usize::from(p.max_hops), MAX_HOPS);
        assert_eq!(Params::simulation_2d().validate(), Ok(()));
    }

    #[test]
    fn nonsense_is_named() {
        let check = |f: fn(&mut Params), e: ParamError| {
            let mut p = Params::robots();
            f(&mut p);
            assert_eq!(p.validate(), Err(e));
        };
        check(|p| p.wave.cycle = Duration::ZERO, ParamError::ZeroCycle);
        check(
            |p| p.wave.cycle_spread = p.wave.cycle,
            ParamError::SpreadNotBelowCycle,
        );
        check(
            |p| p.wave.refractory = Duration::from_secs(40),
            ParamError::RefractoryNotBelowCycle,
        );
        check(
            |p| p.wave.refractory = Duration::from_secs(1),
            ParamError::RefractoryNotAboveRelayDelay,
        );
        check(
            |p| p.wave.relay_delay = Duration::ZERO,
            ParamError::ZeroRelayDelay,
        );
        check(|p| p.wave.tick = Duration::ZERO, ParamError::ZeroTick);
        check(|p| p.sectors = 1, ParamError::BadSectorCount);
        check(|p| p.sectors = 9, ParamError::BadSectorCount);
        check(|p| p.negotiation_cycles = 0, ParamError::ZeroPeriod);
        check(|p| p.diffusion = 0.0, ParamError::BadDiffusion);
        check(|p| p.diffusion = f32::NAN, ParamError::BadDiffusion);
        check(|p| p.max_hops = 0, ParamError::BadHopCapacity);
        check(|p| p.max_hops = 13, ParamError::BadHopCapacity);

        use std::string::ToString;
        assert!(
            ParamError::RefractoryNotBelowCycle
                .to_string()
                .contains("refractory")
        );
    }
}
