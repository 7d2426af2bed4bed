//! Input pieces shared by the state-machine targets (`fused_node`, `three_phase`): the RNG
//! seed, the parameters, the start instant and how time moves between two inputs.

use arbitrary::Unstructured;
use protocol::params::DecisionRule;
use protocol::{Duration, InitiationPoint, Instant, MAX_HOPS, Params, WaveParams};

use crate::input::{Writer, get};

/// Forward jumps are bounded by this many shortest cycles, so that one input's work stays
/// bounded: a late `handle_timeout` replays every transition it missed, one cycle at a time
/// (`docs/protocol.md` §3, "a late caller gets the same schedule"). Backward jumps and start
/// instants are not bounded.
pub const FORWARD_CYCLES: u64 = 16;

/// Which parameters a run uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamsChoice {
    /// [`Params::robots`].
    Robots,
    /// [`Params::simulation_2d`].
    Simulation2d,
    /// [`Params::robots`] with `2 + sectors % 7` sectors, `1 + negotiation % 4` cycles per
    /// period (decisions come quickly) and `1 + max_hops % 12` hops kept by a relay.
    Quick {
        /// Sector count, before the mapping.
        sectors: u8,
        /// Negotiation cycles, before the mapping.
        negotiation: u8,
        /// Relay capacity, before the mapping.
        max_hops: u8,
    },
    /// Every field from the input, valid or not (the node must then refuse them exactly as
    /// [`Params::validate`] does).
    Custom(Custom),
}

/// Raw parameter fields; durations in milliseconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Custom {
    /// `wave.cycle`.
    pub cycle: u16,
    /// `wave.cycle_spread`.
    pub spread: u16,
    /// `wave.relay_delay`.
    pub relay: u16,
    /// `wave.refractory`.
    pub refractory: u16,
    /// `wave.tick`.
    pub tick: u8,
    /// `wave.initiation` is `Uniform` (else `EndOfCycle`).
    pub uniform: bool,
    /// `sectors`.
    pub sectors: u8,
    /// `negotiation_cycles`.
    pub negotiation: u8,
    /// `gather_cycles`.
    pub gather: u8,
    /// `decide_cycles`.
    pub decide: u8,
    /// `diffusion`.
    pub diffusion: f32,
    /// `max_hops`.
    pub max_hops: u8,
}

impl ParamsChoice {
    /// The parameters.
    pub fn params(self) -> Params {
        match self {
            ParamsChoice::Robots => Params::robots(),
            ParamsChoice::Simulation2d => Params::simulation_2d(),
            ParamsChoice::Quick {
                sectors,
                negotiation,
                max_hops,
            } => Params {
                sectors: 2 + sectors % 7,
                negotiation_cycles: 1 + u16::from(negotiation % 4),
                max_hops: 1 + max_hops % MAX_HOPS as u8,
                ..Params::robots()
            },
            ParamsChoice::Custom(c) => Params {
                wave: WaveParams {
                    cycle: Duration::from_millis(c.cycle.into()),
                    cycle_spread: Duration::from_millis(c.spread.into()),
                    initiation: if c.uniform {
                        InitiationPoint::Uniform
                    } else {
                        InitiationPoint::EndOfCycle
                    },
                    relay_delay: Duration::from_millis(c.relay.into()),
                    refractory: Duration::from_millis(c.refractory.into()),
                    tick: Duration::from_millis(c.tick.into()),
                },
                sectors: c.sectors,
                negotiation_cycles: c.negotiation.into(),
                gather_cycles: c.gather.into(),
                decide_cycles: c.decide.into(),
                diffusion: c.diffusion,
                max_hops: c.max_hops,
                // The model (`fused_node.rs`) knows the fixed rule only; the adaptive rule is
                // not fuzzed yet (README, "Targets").
                decide: DecisionRule::Fixed,
            },
        }
    }

    fn read(u: &mut Unstructured<'_>) -> Self {
        match get::<u8>(u) % 4 {
            0 => ParamsChoice::Robots,
            1 => ParamsChoice::Simulation2d,
            2 => ParamsChoice::Quick {
                sectors: get(u),
                negotiation: get(u),
                max_hops: get(u),
            },
            _ => ParamsChoice::Custom(Custom {
                cycle: get(u),
                spread: get(u),
                relay: get(u),
                refractory: get(u),
                tick: get(u),
                uniform: get(u),
                sectors: get(u),
                negotiation: get(u),
                gather: get(u),
                decide: get(u),
                diffusion: f32::from_bits(get(u)),
                max_hops: get(u),
            }),
        }
    }

    fn write(self, w: &mut Writer) {
        match self {
            ParamsChoice::Robots => w.u8(0),
            ParamsChoice::Simulation2d => w.u8(1),
            ParamsChoice::Quick {
                sectors,
                negotiation,
                max_hops,
            } => w.u8(2).u8(sectors).u8(negotiation).u8(max_hops),
            ParamsChoice::Custom(c) => w
                .u8(3)
                .u16(c.cycle)
                .u16(c.spread)
                .u16(c.relay)
                .u16(c.refractory)
                .u8(c.tick)
                .bool(c.uniform)
                .u8(c.sectors)
                .u8(c.negotiation)
                .u8(c.gather)
                .u8(c.decide)
                .f32(c.diffusion)
                .u8(c.max_hops),
        };
    }
}

/// The instant a run starts at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Start {
    /// The epoch.
    Zero,
    /// Up to 2³² ms (7 weeks) after it.
    Soon(u32),
    /// Anywhere.
    Any(u64),
    /// Up to 2³² ms before the end of time ([`Instant::MAX`], which the protocol uses as
    /// "never").
    NearEnd(u32),
}

impl Start {
    /// The instant.
    pub fn instant(self) -> Instant {
        match self {
            Start::Zero => Instant::ZERO,
            Start::Soon(ms) => Instant::from_millis(ms.into()),
            Start::Any(ms) => Instant::from_millis(ms),
            Start::NearEnd(ms) => Instant::from_millis(u64::MAX - u64::from(ms)),
        }
    }

    fn read(u: &mut Unstructured<'_>) -> Self {
        match get::<u8>(u) % 4 {
            0 => Start::Zero,
            1 => Start::Soon(get(u)),
            2 => Start::Any(get(u)),
            _ => Start::NearEnd(get(u)),
        }
    }

    fn write(self, w: &mut Writer) {
        match self {
            Start::Zero => w.u8(0),
            Start::Soon(ms) => w.u8(1).u32(ms),
            Start::Any(ms) => w.u8(2).u64(ms),
            Start::NearEnd(ms) => w.u8(3).u32(ms),
        };
    }
}

/// What a run starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// `rand_pcg::Pcg32::new(state, stream)`.
    pub rng_state: u64,
    /// See `rng_state`.
    pub rng_stream: u64,
    /// The parameters.
    pub params: ParamsChoice,
    /// The start instant.
    pub start: Start,
}

impl Setup {
    /// Reads a setup.
    pub fn read(u: &mut Unstructured<'_>) -> Self {
        Setup {
            rng_state: get(u),
            rng_stream: get(u),
            params: ParamsChoice::read(u),
            start: Start::read(u),
        }
    }

    /// Writes a setup for [`read`](Self::read).
    pub fn write(&self, w: &mut Writer) {
        w.u64(self.rng_state).u64(self.rng_stream);
        self.params.write(w);
        self.start.write(w);
    }

    /// A seeded generator.
    pub fn rng(&self) -> rand_pcg::Pcg32 {
        rand_pcg::Pcg32::new(self.rng_state, self.rng_stream)
    }

    /// The largest forward jump: [`FORWARD_CYCLES`] shortest cycles.
    pub fn max_forward(&self) -> Duration {
        let w = self.params.params().wave;
        (w.cycle - w.cycle_spread).saturating_mul(FORWARD_CYCLES)
    }

    /// The longest cycle: no deadline lies further ahead of the latest instant seen.
    pub fn longest_cycle(&self) -> Duration {
        let w = self.params.params().wave;
        w.cycle + w.cycle_spread
    }
}

/// How `now` moves before an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeStep {
    /// It stays.
    Same,
    /// Forward by this many ms modulo one more than [`Setup::max_forward`].
    Forward(u32),
    /// Backward by this many ms, saturating at the epoch.
    Backward(u64),
    /// To the node's `poll_timeout()`, if that is later and not "never".
    Deadline,
    /// Forward by a few ms.
    Nudge(u8),
}

impl TimeStep {
    /// Reads a step.
    pub fn read(u: &mut Unstructured<'_>) -> Self {
        match get::<u8>(u) % 5 {
            0 => TimeStep::Same,
            1 => TimeStep::Forward(get(u)),
            2 => TimeStep::Backward(get(u)),
            3 => TimeStep::Deadline,
            _ => TimeStep::Nudge(get(u)),
        }
    }

    /// Writes a step for [`read`](Self::read).
    pub fn write(self, w: &mut Writer) {
        match self {
            TimeStep::Same => w.u8(0),
            TimeStep::Forward(ms) => w.u8(1).u32(ms),
            TimeStep::Backward(ms) => w.u8(2).u64(ms),
            TimeStep::Deadline => w.u8(3),
            TimeStep::Nudge(ms) => w.u8(4).u8(ms),
        };
    }

    /// The new `now`.
    pub fn apply(self, now: Instant, deadline: Instant, max_forward: Duration) -> Instant {
        match self {
            TimeStep::Same => now,
            TimeStep::Forward(ms) => {
                now + Duration::from_millis(u64::from(ms) % (max_forward.as_millis() + 1))
            }
            TimeStep::Backward(ms) => now - Duration::from_millis(ms),
            TimeStep::Deadline if deadline > now && deadline != Instant::MAX => deadline,
            TimeStep::Deadline => now,
            TimeStep::Nudge(ms) => now + Duration::from_millis(ms.into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setups_read_back() {
        for params in [
            ParamsChoice::Robots,
            ParamsChoice::Simulation2d,
            ParamsChoice::Quick {
                sectors: 5,
                negotiation: 2,
                max_hops: 10,
            },
            ParamsChoice::Custom(Custom {
                cycle: 200,
                spread: 20,
                relay: 10,
                refractory: 40,
                tick: 1,
                uniform: true,
                sectors: 3,
                negotiation: 2,
                gather: 1,
                decide: 2,
                diffusion: 0.5,
                max_hops: 11,
            }),
        ] {
            for start in [
                Start::Zero,
                Start::Soon(7),
                Start::Any(u64::MAX / 3),
                Start::NearEnd(9),
            ] {
                let s = Setup {
                    rng_state: 1,
                    rng_stream: 2,
                    params,
                    start,
                };
                let mut w = Writer::new();
                s.write(&mut w);
                let bytes = w.finish();
                assert_eq!(Setup::read(&mut Unstructured::new(&bytes)), s);
            }
        }
    }

    #[test]
    fn time_steps_move_now() {
        let t = Instant::from_secs(100);
        let d = Instant::from_secs(150);
        let max = Duration::from_secs(10);
        assert_eq!(TimeStep::Same.apply(t, d, max), t);
        assert_eq!(
            TimeStep::Forward(12_000).apply(t, d, max),
            Instant::from_millis(101_999)
        );
        assert_eq!(TimeStep::Backward(u64::MAX).apply(t, d, max), Instant::ZERO);
        assert_eq!(TimeStep::Deadline.apply(t, d, max), d);
        assert_eq!(TimeStep::Deadline.apply(t, Instant::MAX, max), t);
        assert_eq!(TimeStep::Deadline.apply(d, t, max), d);
        assert_eq!(TimeStep::Nudge(5).apply(Instant::MAX, d, max), Instant::MAX);
    }
}
