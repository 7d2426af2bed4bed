//! The 2D simulation engine: the `protocol` crate's [`ThreePhaseAgent`]s stepped in whole
//! seconds over a rigid swarm that moves after every negotiation period.
//!
//! There is no second implementation of CIMAX here: this module only delivers messages, feeds
//! readings and moves the swarm. Per simulated second `t` at which anything happens:
//!
//! 1. every agent with a relay or a timer (its cycle's end, its initiation) due at `t` is served,
//!    by increasing index ([`ThreePhaseAgent::handle_timeout`]); what it transmits is collected.
//!    The end of a refractory time alone is left to the agent's next call (the call ends it
//!    first, with the same outcome), unless the states are kept current for the recorder and
//!    the wave figure ([`Sim::keep_states`]);
//! 2. each transmission (senders by increasing index) is delivered at `t` to every neighbour
//!    within the perception range, with the bearing `atan2(sender − receiver)`
//!    ([`ThreePhaseAgent::handle_message`]). An agent activated at `t` relays at `t + 1`, so a
//!    wave advances one hop per second;
//! 3. at the end of a negotiation period (every agent shares the cycle boundaries: created at
//!    second 0, no cycle spread) the swarm's direction is the circular mean of the agents'
//!    decided bearings (agents without a decision abstain; if all abstain, or the bearings cancel
//!    exactly, the swarm stays put) and the swarm moves `step` along it.
//!
//! Time jumps from one due second to the next (the agents' timers in a timing wheel, one
//! bucket per second over the next 4096 seconds and a heap beyond; their relays, and their rests
//! when served, in two queues), so the idle part of a long cycle costs little.
//!
//! **Readings.** An agent samples X once per activation: when it may initiate (served at one of
//! its timers while not active) and when a message reaches it while it is inactive. The sample is
//! `field(position) + ξ`, with ξ uniform in `(−noise/2, noise/2)` drawn fresh from the run's noise
//! generator. The same sample is scored on reception and appended when relaying.

use std::fmt;

use crate::calendar::{Schedule, secs};
use hal_emu::TraceEvent;
use nalgebra::{Point2, Vector2};
use protocol::direction::Opposite;
use protocol::three_phase::{Sent, SimEvent, SimMessage, ThreePhaseAgent};
use protocol::{Instant, ParamError, Params, Sector, WaveNode, WaveState};
use rand::SeedableRng;
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

use crate::geometry::Swarm;
use crate::measure::Measure;
use crate::reading::Reading;
use crate::stats::Resultant;
use crate::tap::Tap;
use hal_emu::world::field::Field;

/// The most readings a message carries (a full message drops its oldest).
pub const MESSAGE_READINGS: usize = 32;

/// The agent the simulator steps: the run's [`Measure`] as the diversity (the variance unless
/// the scenario says otherwise), up to [`MESSAGE_READINGS`] readings per message, up to 16
/// distinct bearings per period, one quantity per reading.
pub type Agent = AgentOf<f32>;

/// The agent of a run whose readings are `R` (one quantity or several).
pub type AgentOf<R> = ThreePhaseAgent<<R as Reading>::Measure, MESSAGE_READINGS, 16, R>;

/// A message between agents.
pub type Message = SimMessage<MESSAGE_READINGS>;

/// What a run needs besides the geometry and the field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunConfig {
    /// Protocol parameters (`Params::simulation_2d()` unless a scenario changes them).
    pub params: Params,
    /// Move per negotiation period, in R (the paper: 0.33).
    pub step: f64,
    /// Width of the noise: ξ uniform in `(−noise/2, noise/2)` (the paper: 1).
    pub noise: f64,
    /// The agents' diversity measure (the paper: the variance).
    pub diversity: Measure,
    /// What an agent does with an opinion exactly opposite its own (the paper does not say;
    /// counter-clockwise unless a run says otherwise).
    pub opposite: Opposite,
    /// When an agent's sensor is read (the paper's noise is "time dependent" and says no
    /// more; a fresh sample per activation unless a run says otherwise).
    pub sensor: Sensor,
}

/// When an agent's sensor is read: the sensor model the paper leaves open.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sensor {
    /// A fresh sample whenever the agent becomes active (initiates or is activated by a
    /// message): the sample it scores and relays.
    #[default]
    PerActivation,
    /// One sample per agent and negotiation period, drawn as the period starts (agents by
    /// index) and used for every activation in it.
    PerPeriod,
}

/// The longest negotiation period a run accepts, in seconds (11.6 days; the paper's period is
/// 2000 s and the longest in docs/reproduction.md 10,000 s). Any number of periods a `u32` can
/// count then ends before 2^32 × 10^6 s ≈ 4.3 × 10^15 s, within the protocol's clock
/// (milliseconds in a `u64`, 1.8 × 10^16 s): no period's end overflows.
pub const MAX_PERIOD_SECS: u64 = 1_000_000;

/// Why a run cannot start or go on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimError {
    /// The protocol parameters do not validate.
    Params(ParamError),
    /// A negotiation period, `(gather_cycles + decide_cycles) × cycle`, longer than
    /// [`MAX_PERIOD_SECS`].
    PeriodTooLong {
        /// Gathering cycles per period.
        gather_cycles: u16,
        /// Deciding cycles per period.
        decide_cycles: u16,
        /// The cycle, whole seconds.
        cycle_s: u64,
    },
    /// The run has counted `u32::MAX` periods: it cannot count another.
    TooManyPeriods,
    /// The run's readings need this many fields (quantities) but were given another number.
    Fields {
        /// Fields needed.
        needed: usize,
        /// Fields given.
        given: usize,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SimError::Params(e) => e.fmt(f),
            SimError::PeriodTooLong {
                gather_cycles,
                decide_cycles,
                cycle_s,
            } => {
                let cycles = u128::from(gather_cycles) + u128::from(decide_cycles);
                write!(
                    f,
                    "a negotiation period of (gather_cycles + decide_cycles) × cycle = \
                     ({gather_cycles} + {decide_cycles}) × {cycle_s} s = {} s is longer than \
                     the limit of {MAX_PERIOD_SECS} s",
                    cycles * u128::from(cycle_s)
                )
            }
            SimError::TooManyPeriods => {
                write!(f, "a run cannot count more than {} periods", u32::MAX)
            }
            SimError::Fields { needed, given } => {
                write!(
                    f,
                    "a run of {needed} quantities needs {needed} fields, not {given}"
                )
            }
        }
    }
}

impl std::error::Error for SimError {}

impl From<ParamError> for SimError {
    fn from(e: ParamError) -> Self {
        SimError::Params(e)
    }
}

impl RunConfig {
    /// The paper's move per negotiation period, in R.
    pub const PAPER_STEP: f64 = 0.33;
    /// The paper's noise width: ξ uniform in (−0.5, 0.5).
    pub const PAPER_NOISE: f64 = 1.0;

    /// The paper's run with protocol parameters `params`: a step of [`Self::PAPER_STEP`], noise
    /// of width [`Self::PAPER_NOISE`], the variance, and the defaults for what the paper leaves
    /// open (an exactly opposite opinion turns counter-clockwise; a fresh sample per
    /// activation). What a scenario file gives for the keys it leaves out.
    pub fn paper(params: Params) -> RunConfig {
        RunConfig {
            params,
            step: Self::PAPER_STEP,
            noise: Self::PAPER_NOISE,
            diversity: Measure::Variance,
            opposite: Opposite::default(),
            sensor: Sensor::default(),
        }
    }

    /// Length of one negotiation period in seconds, `(gather_cycles + decide_cycles) × cycle`
    /// with the cycle rounded up to whole seconds; `u64::MAX` if that does not fit (a
    /// configuration [`check`](Self::check) accepts has at most [`MAX_PERIOD_SECS`]).
    pub fn period_secs(&self) -> u64 {
        self.checked_period_secs().unwrap_or(u64::MAX)
    }

    /// [`period_secs`](Self::period_secs), `None` if it does not fit in a `u64`.
    pub fn checked_period_secs(&self) -> Option<u64> {
        let p = &self.params;
        let cycles = u64::from(p.gather_cycles) + u64::from(p.decide_cycles);
        cycles.checked_mul(p.wave.cycle.as_millis().div_ceil(1000))
    }

    /// Checks that a run can use this configuration: the protocol parameters validate and a
    /// negotiation period is at most [`MAX_PERIOD_SECS`].
    ///
    /// # Errors
    /// The [`SimError`] saying which.
    pub fn check(&self) -> Result<(), SimError> {
        self.params.validate()?;
        match self.checked_period_secs() {
            Some(s) if s <= MAX_PERIOD_SECS => Ok(()),
            _ => Err(SimError::PeriodTooLong {
                gather_cycles: self.params.gather_cycles,
                decide_cycles: self.params.decide_cycles,
                cycle_s: self.params.wave.cycle.as_millis().div_ceil(1000),
            }),
        }
    }
}

/// What happened in one negotiation period.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Period {
    /// Periods completed, counting this one (1 for the first).
    pub index: u32,
    /// Simulated second at which the period ended.
    pub end_s: u64,
    /// Centre of mass during the period.
    #[serde(with = "crate::json")]
    pub from: Point2<f64>,
    /// Centre of mass after the move.
    #[serde(with = "crate::json")]
    pub to: Point2<f64>,
    /// Direction moved (radians), if any.
    #[serde(with = "crate::json")]
    pub direction: Option<f64>,
    /// Length of the mean resultant of the decided bearings (1 = unanimous, 0 = no agreement).
    #[serde(with = "crate::json")]
    pub consensus: f64,
    /// Agents that had a decision.
    pub decided: u32,
    /// The observer's average diversity: the mean over agents of `V_k` from this period's
    /// gathering phase.
    #[serde(with = "crate::json")]
    pub diversity: f64,
}

/// The index and the end (second) of the period after `periods` periods of `cfg`.
///
/// # Errors
/// [`SimError::TooManyPeriods`] if either does not fit.
pub(crate) fn next_period(cfg: &RunConfig, periods: u32) -> Result<(u32, u64), SimError> {
    let index = periods.checked_add(1).ok_or(SimError::TooManyPeriods)?;
    let end = cfg
        .checked_period_secs()
        .and_then(|p| p.checked_mul(u64::from(index)))
        .ok_or(SimError::TooManyPeriods)?;
    Ok((index, end))
}

impl Period {
    /// Period `index`, ended at second `end_s` with the swarm's centre at `from`, from the
    /// agents' decided bearings and diversities (in agent order): the swarm moves `step`
    /// along the circular mean of the decisions, if they have one. Both engines end a period
    /// so.
    pub(crate) fn ending(
        index: u32,
        end_s: u64,
        from: Point2<f64>,
        step: f64,
        agents: impl Iterator<Item = (Option<f32>, f32)> + Clone,
    ) -> Period {
        let n = agents.clone().count().max(1) as f64;
        let diversity: f64 = agents.clone().fold(0.0, |d, (_, v)| d + f64::from(v));
        let resultant = Resultant::of(agents.filter_map(|(b, _)| b).map(f64::from));
        let direction = resultant.direction();
        Period {
            index,
            end_s,
            from,
            to: direction.map_or(from, |d| from + step * Vector2::new(d.cos(), d.sin())),
            direction,
            consensus: resultant.length(),
            decided: resultant.n,
            diversity: diversity / n,
        }
    }
}

/// One run of the simulation: the agents, where the swarm is and the clock.
pub struct Sim<'a, R: Reading = f32> {
    swarm: &'a Swarm,
    /// One field per quantity of `R`.
    fields: Vec<&'a Field>,
    cfg: RunConfig,
    agents: Vec<AgentOf<R>>,
    centre: Point2<f64>,
    periods: u32,
    /// When each agent has something due.
    schedule: Schedule,
    /// Per agent, the first instant (milliseconds) at which it hears a message, as of its last
    /// call: 0 while inactive, the end of its refractory time while refractory, `u64::MAX`
    /// while active.
    /// Read at every delivery, so kept apart from the agents, which are large. Rests are not
    /// served unless the states are kept current ([`Sim::keep_states`]): an agent whose
    /// refractory time is over rests in its next call.
    hears: Vec<u64>,
    proto_rng: Pcg64Mcg,
    noise_rng: Pcg64Mcg,
    due: Vec<u32>,
    /// Seconds from a message heard to its relay (the relay delay, a part of a second
    /// counting as a second, as [`secs`] counts).
    relay_secs: u64,
    /// This second's transmissions: the sender and its message (the sender keeps it).
    tx: Vec<(u32, Sent)>,
    calls: u64,
    /// The fields' means at every agent's position (agent-major, `R::QUANTITIES` per agent):
    /// positions change only when the swarm moves, so the fields are evaluated once per agent
    /// and period, not once per reading.
    means: Vec<f64>,
    /// The run's events for the replay viewer, if asked for ([`Sim::record`]).
    trace: Option<Recorder>,
    /// The observer's diversities of the accepted messages, if asked for ([`Sim::tap`]).
    tap: Option<Tap>,
    /// Each agent's reading of the current period ([`Sensor::PerPeriod`]; empty otherwise).
    held: Vec<R>,
}

/// The first instant (milliseconds) at which an agent with wave node `w` hears a message
/// ([`Sim`]'s `hears`): at second `t` it hears if `t`'s instant is not before it (a rest due
/// during a second is over by its end, as [`secs`] counts).
#[inline]
fn hears_from(w: &WaveNode) -> u64 {
    match w.state() {
        WaveState::Inactive => 0,
        WaveState::Active => u64::MAX,
        WaveState::Refractory => w.rest_due().map_or(u64::MAX, |at| at.as_millis()),
    }
}

/// What [`Sim::record`] keeps: the events, and each agent's scores per sector before its
/// last timeout and at its last evaluation (they go with its decision at the period's end).
#[derive(Default)]
struct Recorder {
    events: Vec<TraceEvent>,
    heard: Vec<Vec<Option<f32>>>,
    scores: Vec<Vec<Option<f32>>>,
}

/// The sectors a bearing is binned into for the viewer (its LED colours).
pub const TRACE_SECTORS: u8 = 8;

impl<'a> Sim<'a> {
    /// A run of `swarm` in `field` with its centre of mass at `centre`; every agent starts its
    /// first cycle (gathering) at second 0. All randomness of the run (cycle draws, noise) comes
    /// from `seed`.
    ///
    /// # Errors
    /// A [`SimError`] if the configuration fails [`RunConfig::check`]: the protocol parameters
    /// do not validate, or a negotiation period is longer than [`MAX_PERIOD_SECS`].
    pub fn new(
        swarm: &'a Swarm,
        field: &'a Field,
        cfg: RunConfig,
        centre: Point2<f64>,
        seed: u64,
    ) -> Result<Self, SimError> {
        Sim::with_fields(swarm, vec![field], cfg, centre, seed)
    }
}

impl<'a, R: Reading> Sim<'a, R> {
    /// [`Sim::new`] for readings of `R::QUANTITIES` quantities, one field each (the first is
    /// X, sampled first at every reading).
    ///
    /// # Errors
    /// As [`Sim::new`], and [`SimError::Fields`] unless `fields` has one field per quantity.
    pub fn with_fields(
        swarm: &'a Swarm,
        fields: Vec<&'a Field>,
        cfg: RunConfig,
        centre: Point2<f64>,
        seed: u64,
    ) -> Result<Self, SimError> {
        if fields.len() != R::QUANTITIES {
            return Err(SimError::Fields {
                needed: R::QUANTITIES,
                given: fields.len(),
            });
        }
        cfg.check()?;
        let mut proto_rng = Pcg64Mcg::seed_from_u64(crate::seeds::derive(seed, &[1]));
        let noise_rng = Pcg64Mcg::seed_from_u64(crate::seeds::derive(seed, &[2]));
        let n = swarm.len();
        let mut agents = Vec::with_capacity(n);
        for _ in 0..n {
            let mut agent = AgentOf::<R>::with_diversity(
                cfg.params,
                R::measure(cfg.diversity),
                Instant::ZERO,
                &mut proto_rng,
            )?;
            agent.set_opposite(cfg.opposite);
            // Only a recording run looks at the events ([`Sim::record`]).
            agent.set_events(false);
            agents.push(agent);
        }
        let hears = agents.iter().map(|a| hears_from(a.wave())).collect();
        let mut sim = Sim {
            swarm,
            fields,
            cfg,
            agents,
            centre,
            periods: 0,
            schedule: Schedule::new(n),
            hears,
            proto_rng,
            noise_rng,
            due: Vec::new(),
            relay_secs: cfg.params.wave.relay_delay.as_millis().div_ceil(1000),
            tx: Vec::new(),
            calls: 0,
            means: Vec::with_capacity(n * R::QUANTITIES),
            trace: None,
            tap: None,
            held: Vec::new(),
        };
        sim.place_means();
        for i in 0..n {
            sim.schedule.start(i, sim.agents[i].wave());
        }
        Ok(sim)
    }

    /// The centre of mass.
    pub fn centre(&self) -> Point2<f64> {
        self.centre
    }

    /// Negotiation periods completed.
    pub fn periods(&self) -> u32 {
        self.periods
    }

    /// The agents, by index.
    pub fn agents(&self) -> &[AgentOf<R>] {
        &self.agents
    }

    /// Calls made into the agents so far (`handle_timeout` and `handle_message`).
    pub fn calls(&self) -> u64 {
        self.calls
    }

    /// The run's configuration.
    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }

    /// Serves every agent at the end of its refractory time, so that each agent's state
    /// ([`Sim::agents`]) is current at every second; otherwise an agent whose refractory time
    /// is over rests in its next call, and the run is the same. Call it before the run starts.
    pub fn keep_states(&mut self) {
        self.schedule.serve_rests();
    }

    /// Records the run's events from now on for the replay viewer ([`take_trace`](Self::take_trace)):
    /// wave states, transmissions (each of length 1: a hop takes a second), each
    /// agent's preferred and decided bearing binned into [`TRACE_SECTORS`] sectors, and the
    /// moves. Costs memory; a run without it records nothing.
    pub fn record(&mut self) {
        // Every state change at its second.
        self.keep_states();
        let n = self.agents.len();
        for a in &mut self.agents {
            a.set_events(true);
        }
        self.trace.get_or_insert_with(|| Recorder {
            events: Vec::new(),
            heard: vec![Vec::new(); n],
            scores: vec![Vec::new(); n],
        });
    }

    /// The events recorded so far.
    pub fn take_trace(&mut self) -> Vec<TraceEvent> {
        self.trace
            .as_mut()
            .map(|r| std::mem::take(&mut r.events))
            .unwrap_or_default()
    }

    /// Stops accumulating the observer's diversity ([`ThreePhaseAgent::set_pooling`]): every
    /// later period's [`Period::diversity`] is 0; the run is otherwise the same, draw for draw.
    /// For runs whose diversity nobody reads (a sweep's).
    pub fn without_diversity(&mut self) {
        for a in &mut self.agents {
            a.set_pooling(false);
        }
    }

    /// Observes the messages the agents score from now on ([`Tap`]); changes nothing in the
    /// run.
    pub fn tap(&mut self) {
        self.tap = Some(Tap::default());
    }

    /// What the tap saw since the last call (empty if [`Sim::tap`] was not called).
    pub fn take_tap(&mut self) -> Tap {
        self.tap.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Keeps what agent `i` heard so far, per sector the best direction's score, if recording:
    /// an evaluation at its next timeout clears the agent's own table before it is seen.
    fn note_scores(&mut self, i: usize) {
        let Some(rec) = self.trace.as_mut() else {
            return;
        };
        let mut scores = vec![None::<f32>; usize::from(TRACE_SECTORS)];
        for (b, w, _) in self.agents[i].weights() {
            let s = &mut scores[usize::from(Sector::from_bearing(b, TRACE_SECTORS).index())];
            *s = Some(s.map_or(w, |x| x.max(w)));
        }
        rec.heard[i] = scores;
    }

    /// Takes agent `i`'s events at second `t`, recording them if asked.
    #[inline]
    fn drain_events(&mut self, i: usize, t: u64) {
        if self.trace.is_some() {
            self.record_events(i, t);
        }
        // Otherwise events are off ([`ThreePhaseAgent::set_events`]): none is queued.
    }

    /// [`drain_events`](Self::drain_events) of a recording run.
    fn record_events(&mut self, i: usize, t: u64) {
        while let Some(e) = self.agents[i].poll_event() {
            let Some(rec) = self.trace.as_mut() else {
                continue;
            };
            let trace = &mut rec.events;
            let t_ms = t * 1000;
            let sector = |b: Option<f32>| b.map(|b| Sector::from_bearing(b, TRACE_SECTORS).index());
            match e {
                SimEvent::State(s) => trace.push(TraceEvent::State {
                    t_ms,
                    robot: i,
                    state: match s {
                        WaveState::Inactive => "inactive",
                        WaveState::Active => "active",
                        WaveState::Refractory => "refractory",
                    }
                    .into(),
                }),
                SimEvent::Evaluated { preferred, .. } => {
                    // The scores it evaluated ([`Self::note_scores`] kept them).
                    rec.scores[i] = std::mem::take(&mut rec.heard[i]);
                    trace.push(TraceEvent::Preference {
                        t_ms,
                        robot: i,
                        preference: sector(preferred)
                            .map_or("none".into(), |s| format!("sector {s}")),
                    });
                }
                SimEvent::Decided { period, bearing } => {
                    trace.push(TraceEvent::Decided {
                        t_ms,
                        robot: i,
                        period,
                        decision: sector(bearing),
                        votes: Vec::new(),
                        scores: rec.scores[i].clone(),
                        reading: self.means[i * R::QUANTITIES] as f32,
                    });
                    trace.push(TraceEvent::Led {
                        t_ms,
                        robot: i,
                        color: sector(bearing)
                            .map_or("off".into(), |s| format!("sector {s}").into()),
                    });
                }
            }
        }
    }

    /// Evaluates the field at every agent's position (after the swarm moved).
    fn place_means(&mut self) {
        let (swarm, centre) = (self.swarm, self.centre);
        self.means.clear();
        for i in 0..swarm.len() {
            let at = swarm.position(i, centre);
            self.means.extend(self.fields.iter().map(|f| f.mean(at)));
        }
    }

    /// A fresh reading for agent `i` at the current position.
    fn draw(&mut self, i: usize) -> R {
        let q = R::QUANTITIES;
        R::sample(
            &self.means[i * q..(i + 1) * q],
            self.cfg.noise,
            &mut self.noise_rng,
        )
    }

    /// Agent `i`'s reading as it becomes active or may initiate: fresh, or the period's under
    /// [`Sensor::PerPeriod`].
    #[inline]
    fn reading(&mut self, i: usize) -> R {
        match self.held.get(i) {
            Some(&r) => r,
            None => self.draw(i),
        }
    }

    /// Under [`Sensor::PerPeriod`], every agent's reading for the period about to start.
    fn hold_readings(&mut self) {
        if self.cfg.sensor == Sensor::PerPeriod {
            self.held.clear();
            for i in 0..self.agents.len() {
                let r = self.draw(i);
                self.held.push(r);
            }
        }
    }

    /// Runs every due second up to and including `until`.
    fn advance_to(&mut self, until: u64) {
        while let Some(t) = self.schedule.next_due(until) {
            self.second(t);
        }
    }

    /// Serves everything due at second `t`, then delivers what was sent.
    fn second(&mut self, t: u64) {
        let now = Instant::from_secs(t);
        self.serve_due(t, now);
        self.deliver(t, now);
    }

    /// Serves every agent due at second `t` (by increasing index) and collects what they
    /// transmit into `tx`.
    fn serve_due(&mut self, t: u64, now: Instant) {
        let mut due = std::mem::take(&mut self.due);
        // By increasing index.
        self.schedule.take(t, &mut due);
        for &i in &due {
            let i = i as usize;
            // Nothing is ever overdue, and an agent with nothing due now (`> now`: its second
            // is not `t`) would be a stale entry: there are none.
            let Some(a) = self.agents.get(i) else {
                continue;
            };
            let due_now = a.poll_timeout() <= now;
            debug_assert!(due_now, "agent {i} queued at {t} with nothing due");
            if !due_now {
                continue;
            }
            // A reading for the agent's own wave: it initiates only at one of its timers, and
            // only if it is not active (a rest or a relay uses none: the relay carries the
            // reading drawn as the agent heard the message).
            let own =
                (self.hears[i] != u64::MAX && a.wave().timers_at() <= now).then(|| self.reading(i));
            self.note_scores(i);
            let a = &mut self.agents[i];
            if let Some(x) = own {
                a.handle_reading(x);
            }
            a.handle_timeout(now, &mut self.proto_rng);
            self.hears[i] = hears_from(a.wave());
            self.calls += 1;
            while let Some(b) = a.poll_transmit_sent() {
                self.tx.push((i as u32, b));
                if let Some(rec) = self.trace.as_mut() {
                    rec.events.push(TraceEvent::Sent {
                        t_ms: t * 1000,
                        robot: i,
                        // One unit: the viewer shows a message for its one-second hop.
                        len: 1,
                    });
                }
            }
            self.schedule.track(i, a.wave(), now);
            self.drain_events(i, t);
        }
        due.clear();
        self.due = due;
    }

    /// Delivers what was transmitted at second `t` (`tx`, senders by increasing index) to
    /// every neighbour within range. The messages are read where their senders keep them
    /// ([`ThreePhaseAgent::sent`]): a sender is refractory now, so no delivery calls it.
    fn deliver(&mut self, t: u64, now: Instant) {
        let mut tx = std::mem::take(&mut self.tx);
        for &(s, b) in &tx {
            let s = s as usize;
            for l in self.swarm.neighbours(s) {
                let r = l.agent as usize;
                if now.as_millis() < self.hears[r] {
                    // An active or refractory agent ignores every message (the wave rule; most
                    // deliveries are such: a wave comes back to the agents it came from). Not
                    // calling it changes nothing but its `ignored`/`wrong_phase` counters,
                    // which then count only messages heard while inactive.
                    debug_assert!(!self.agents[r].clone().handle_message(
                        now,
                        l.bearing,
                        self.agents[s].sent(b),
                        &mut self.proto_rng.clone()
                    ));
                    continue;
                }
                let own = self.reading(r);
                // The sender and the receiver: two agents (no agent is its own neighbour).
                let Ok([from, to]) = self.agents.get_disjoint_mut([s, r]) else {
                    debug_assert!(false, "agent {s} is its own neighbour");
                    continue;
                };
                to.handle_reading(own);
                let m = from.sent(b);
                let accepted = to.handle_message(now, l.bearing, m, &mut self.proto_rng);
                // It was inactive or at the end of its refractory time (which the call ended):
                // now active, or inactive if the message was of the other phase.
                self.hears[r] = if accepted { u64::MAX } else { 0 };
                debug_assert_eq!(self.hears[r], hears_from(to.wave()));
                self.calls += 1;
                debug_assert!(to.poll_transmit().is_none());
                if !accepted {
                    // Every agent due at `t` was served above, so a refused message changed
                    // nothing but a counter: no event, the same timeout (most deliveries reach
                    // an agent that is already active or refractory).
                    debug_assert!(to.poll_event().is_none());
                    debug_assert!(secs(to.poll_timeout()) > t);
                    continue;
                }
                // Its relay: a relay delay after `now`, a whole second.
                self.schedule.track_heard(r, to.wave(), t + self.relay_secs);
                if let (Some(tap), SimMessage::Readings(rs)) = (self.tap.as_mut(), m) {
                    let own = std::iter::once(own.first());
                    tap.add(rs.iter().map(R::first).chain(own));
                }
                self.drain_events(r, t);
            }
        }
        tx.clear();
        self.tx = tx;
    }

    /// Runs one negotiation period, then moves the swarm along the decided direction.
    ///
    /// # Errors
    /// [`SimError::TooManyPeriods`] once the run has counted `u32::MAX` periods (the period's
    /// end cannot overflow: [`Sim::new`] checked the period's length).
    pub fn run_period(&mut self) -> Result<Period, SimError> {
        let (index, end) = next_period(&self.cfg, self.periods)?;
        self.hold_readings();
        self.advance_to(end);
        self.periods = index;
        let p = Period::ending(
            index,
            end,
            self.centre,
            self.cfg.step,
            self.agents.iter().map(|a| (a.decision(), a.diversity())),
        );
        if let Some(rec) = self.trace.as_mut() {
            rec.events.push(TraceEvent::Moved {
                t_ms: end * 1000,
                centre: [p.from.x, p.from.y],
                heading: p.direction,
                step: if p.direction.is_some() {
                    self.cfg.step
                } else {
                    0.0
                },
                consensus: p.consensus,
            });
        }
        if p.direction.is_some() {
            self.centre = p.to;
            self.place_means();
        }
        Ok(p)
    }

    /// Runs every due second up to and including second `t` and returns the calls made. The
    /// swarm does not move: for measurements inside the first period only (a period ending
    /// meanwhile is not counted by [`run_period`](Self::run_period)).
    pub fn run_until(&mut self, t: u64) -> u64 {
        let before = self.calls;
        self.advance_to(t);
        self.calls - before
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;

    fn cfg() -> RunConfig {
        RunConfig {
            params: Params::simulation_2d(),
            step: 0.33,
            noise: 1.0,
            diversity: Measure::Variance,
            opposite: Opposite::default(),
            sensor: Sensor::default(),
        }
    }

    #[test]
    fn a_sensor_read_once_per_period_changes_the_readings_not_the_default_run() {
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        let swarm = Swarm::place(30, Shape::Disk { diameter: 4.0 }, 1.0, &mut rng).unwrap();
        let field = crate::scenario::Scenario::builtin("sharp").unwrap().field;
        let run = |sensor| {
            let cfg = RunConfig { sensor, ..cfg() };
            let mut sim = Sim::new(&swarm, &field, cfg, Point2::new(-0.5, 0.0), 9).unwrap();
            (0..2)
                .map(|_| sim.run_period().unwrap())
                .collect::<Vec<_>>()
        };
        let fresh = run(Sensor::PerActivation);
        let held = run(Sensor::PerPeriod);
        assert_eq!(fresh, run(Sensor::default()));
        assert_ne!(fresh, held);
        assert_eq!(held, run(Sensor::PerPeriod));
    }

    /// Rests left to the agents' next calls give the run that serving every rest at its
    /// second gives (the state the recorder and the wave figure read), bit for bit.
    #[test]
    fn a_run_is_the_same_whether_rests_are_served_or_left_to_the_next_call() {
        let field = crate::scenario::Scenario::builtin("sharp").unwrap().field;
        for seed in 0..12u64 {
            let mut rng = Pcg64Mcg::seed_from_u64(seed);
            let swarm = Swarm::place(61, Shape::Disk { diameter: 6.0 }, 1.0, &mut rng).unwrap();
            let sensor = [Sensor::PerActivation, Sensor::PerPeriod][seed as usize % 2];
            let run = |served: bool| {
                let cfg = RunConfig { sensor, ..cfg() };
                let start = Point2::new(-1.0 + 0.2 * seed as f64, 0.5);
                let mut sim = Sim::new(&swarm, &field, cfg, start, seed).unwrap();
                if served {
                    sim.keep_states();
                }
                sim.tap();
                let periods: Vec<Period> = (0..3).map(|_| sim.run_period().unwrap()).collect();
                let agents: Vec<_> = sim
                    .agents()
                    .iter()
                    .map(|a| (a.decision(), a.preferred(), *a.stats(), a.diversity()))
                    .collect();
                let taps = sim.take_tap();
                (periods, agents, taps)
            };
            let (served, lazy) = (run(true), run(false));
            assert_eq!(served.0, lazy.0, "seed {seed}: periods");
            assert_eq!(served.1, lazy.1, "seed {seed}: agents");
            assert_eq!(served.2, lazy.2, "seed {seed}: observer");
        }
    }

    #[test]
    fn a_uniform_field_gives_small_diversity_and_the_swarm_moves_one_step() {
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let swarm = Swarm::place(61, Shape::Disk { diameter: 6.0 }, 1.0, &mut rng).unwrap();
        let field = Field::default();
        let mut sim = Sim::new(&swarm, &field, cfg(), Point2::origin(), 9).unwrap();
        let p = sim.run_period().unwrap();
        assert_eq!(p.index, 1);
        assert_eq!(p.end_s, 2000);
        // Uniform noise of width 1 has variance 1/12.
        assert!((0.03..0.12).contains(&p.diversity), "{}", p.diversity);
        assert!(p.decided > 50);
        assert!(((p.to - p.from).norm() - 0.33).abs() < 1e-9);
    }

    #[test]
    fn a_period_too_long_to_count_is_refused_before_the_run() {
        let swarm = Swarm::from_offsets(vec![Vector2::zeros(), Vector2::new(0.5, 0.0)], 1.0);
        let field = Field::default();
        // (1 + 1) × 500,000 s: the longest period there is.
        let mut c = cfg();
        c.params.wave.cycle = protocol::Duration::from_secs(MAX_PERIOD_SECS / 2);
        assert_eq!(c.checked_period_secs(), Some(MAX_PERIOD_SECS));
        assert!(Sim::new(&swarm, &field, c, Point2::origin(), 1).is_ok());
        // One second more per cycle, then periods whose product overflows u64: the old
        // `cycles * cycle` wrapped (or panicked) here.
        for (cycle_s, gather, decide) in [
            (MAX_PERIOD_SECS / 2 + 1, 1, 1),
            (u64::MAX / 1000, 1, 1),
            (u64::MAX / 1000, u16::MAX, u16::MAX),
        ] {
            let mut c = cfg();
            c.params.wave.cycle = protocol::Duration::from_secs(cycle_s);
            c.params.gather_cycles = gather;
            c.params.decide_cycles = decide;
            let e = Sim::new(&swarm, &field, c, Point2::origin(), 1)
                .err()
                .expect("refused");
            assert!(matches!(e, SimError::PeriodTooLong { .. }), "{e}");
            assert!(e.to_string().contains("limit of 1000000 s"), "{e}");
        }
        assert_eq!(
            RunConfig {
                params: Params {
                    gather_cycles: u16::MAX,
                    ..Params::simulation_2d()
                },
                ..cfg()
            }
            .period_secs(),
            (u64::from(u16::MAX) + 1) * 1000
        );
        let mut c = cfg();
        c.params.wave.cycle = protocol::Duration::from_secs(u64::MAX / 1000);
        c.params.gather_cycles = u16::MAX;
        assert_eq!(c.checked_period_secs(), None);
        assert_eq!(c.period_secs(), u64::MAX);
    }

    #[test]
    fn waves_flood_the_swarm_when_they_rarely_collide() {
        let mut rng = Pcg64Mcg::seed_from_u64(6);
        let swarm = Swarm::place(61, Shape::Disk { diameter: 6.0 }, 1.0, &mut rng).unwrap();
        let field = Field::default();
        let mut c = cfg();
        c.params.wave.cycle = protocol::Duration::from_secs(20_000);
        let mut sim = Sim::new(&swarm, &field, c, Point2::origin(), 1).unwrap();
        sim.run_until(20_000);
        let accepted: u32 = sim.agents().iter().map(|a| a.stats().accepted).sum();
        // 61 waves; an agent is activated by every wave but its own (unless two overlap).
        assert!(accepted > 61 * 55, "accepted {accepted}");
        assert!(accepted <= 61 * 60, "accepted {accepted}");
    }

    #[test]
    fn one_hop_per_second_with_the_receivers_bearing() {
        // Three agents on a line 0.8 apart: 0 hears 1 from the east, 2 hears 1 from the west.
        let swarm = Swarm::from_offsets(
            vec![
                Vector2::new(-0.8, 0.0),
                Vector2::new(0.0, 0.0),
                Vector2::new(0.8, 0.0),
            ],
            1.0,
        );
        let field = Field::default();
        let mut sim = Sim::new(&swarm, &field, cfg(), Point2::origin(), 3).unwrap();
        sim.run_until(1000);
        // Each of the 3 waves reaches both other agents: 0 and 2 only through 1, one hop later.
        let accepted: Vec<u32> = sim.agents().iter().map(|a| a.stats().accepted).collect();
        assert_eq!(accepted, vec![2, 2, 2]);
        // With readings all equal to 0 ± 0.5 no bearing is heavier in expectation, but every
        // preference is one of the exact bearings of an agent's neighbours.
        let pref: Vec<Option<f32>> = sim.agents().iter().map(|a| a.preferred()).collect();
        assert!(pref[0].is_none_or(|p| p.abs() < 1e-6), "{pref:?}");
        assert!(
            pref[2].is_none_or(|p| (p - std::f32::consts::PI).abs() < 1e-6),
            "{pref:?}"
        );
    }
}
