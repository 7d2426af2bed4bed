//! `three_phase`: the 2D-simulation agent [`ThreePhaseAgent`] driven by arbitrary inputs, as
//! `fused_node` drives the robot.
//!
//! Input: a [`Setup`], a flag choosing the agent's size (`<Variance, 4, 3>`: 4 readings per
//! message, 3 bearing slots, so that full messages and full slots come quickly; or the default
//! `<Variance, 32, 16>`), then up to [`MAX_STEPS`] steps: a reading, a message (`Readings` or
//! `Opinion`) from a bearing, or a bare `handle_timeout`, each moving time first. Readings,
//! bearings and opinions are small integers or any `f32` bit pattern (NaN, infinities, −0).
//!
//! Checks after every call (`docs/protocol.md` §6, §9):
//!
//! - nothing panics; `new` refuses exactly what `Params::validate` refuses;
//! - `poll_transmit` / `poll_event` run dry within 2 / 8 items; `Readings` hold 1..=N readings;
//! - `preferred()`, `decision()` and every bearing in a message or event are `None` or finite in
//!   `[0, 2π)`; `weights()` holds at most S directions, each heard at least once with a weight
//!   that is not negative and not NaN; `diversity()` is never negative, and not NaN while every
//!   reading fed was finite;
//! - `poll_timeout()` as for `fused_node`;
//! - a message of the other phase (or empty `Readings`) returns `false`, counts `wrong_phase`
//!   and leaves the wave node alone; an accepted one leaves the agent active; an ignored one is
//!   counted in `ignored`; an accepted `Readings` has a slot for its bearing unless `slots_full`
//!   counted it with all S slots taken; an accepted opinion moves the preference exactly as
//!   `wrap_positive` / `turn_toward` say (when no phase ended in the call);
//! - with every output of a call seen: an initiation in gathering carries just the own reading,
//!   a relay is the accepted readings plus the own (oldest dropped when full); opinions carry
//!   the preference; `State` events chain valid transitions; `Evaluated` and `Decided`
//!   alternate with `phase()`, number the periods, and match `diversity()` and `decision()`;
//! - the same seed and inputs give the same outputs (bit for bit; the input is run twice).

use core::f32::consts::TAU;

use arbitrary::Unstructured;
use protocol::direction::{turn_toward, wrap_positive};
use protocol::three_phase::{AgentStats, Phase, SimEvent};
use protocol::wave::WaveStats;
use protocol::{Instant, Params, SimMessage, ThreePhaseAgent, Variance, WaveState};

use crate::input::{Writer, get, list};
use crate::scenario::{Setup, TimeStep};

/// Steps read at most.
pub const MAX_STEPS: usize = 256;
/// Readings per message read at most (then truncated to the agent's N).
pub const MAX_READINGS: usize = 40;
/// The outbox depth.
pub const OUTBOX: usize = 2;
/// The event queue depth.
pub const EVENT_QUEUE: usize = 8;

/// A number from the input: a small integer (a realistic reading or a bearing in 256ths of a
/// turn) or any bit pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Num {
    /// `f32::from(x)` as a reading, `x · 2π / 256` as a bearing.
    Small(u8),
    /// `f32::from_bits(x)`.
    Bits(u32),
}

impl Num {
    /// As a reading.
    pub fn reading(self) -> f32 {
        match self {
            Num::Small(x) => f32::from(x),
            Num::Bits(b) => f32::from_bits(b),
        }
    }

    /// As a bearing.
    pub fn bearing(self) -> f32 {
        match self {
            Num::Small(x) => f32::from(x) * TAU / 256.0,
            Num::Bits(b) => f32::from_bits(b),
        }
    }

    fn read(u: &mut Unstructured<'_>) -> Self {
        if get::<bool>(u) {
            Num::Bits(get(u))
        } else {
            Num::Small(get(u))
        }
    }

    fn write(self, w: &mut Writer) {
        match self {
            Num::Small(x) => w.bool(false).u8(x),
            Num::Bits(b) => w.bool(true).u32(b),
        };
    }
}

/// A message as the input spells it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Msg {
    /// `SimMessage::Readings` (truncated to N).
    Readings(Vec<Num>),
    /// `SimMessage::Opinion` (a bearing).
    Opinion(Option<Num>),
}

/// What a step does after moving time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Action {
    /// `handle_reading`.
    Reading(Num),
    /// `handle_message`.
    Message {
        /// The bearing it came from.
        bearing: Num,
        /// The message.
        msg: Msg,
        /// How time moves first.
        time: TimeStep,
    },
    /// `handle_timeout`.
    Timeout(TimeStep),
}

/// One step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    /// What it does.
    pub action: Action,
    /// Leave the outputs queued (not drained) after it.
    pub hold: bool,
}

impl Step {
    /// A step that drains its outputs.
    pub fn drain(action: Action) -> Self {
        Step {
            action,
            hold: false,
        }
    }

    fn read(u: &mut Unstructured<'_>) -> Self {
        let action = match get::<u8>(u) % 3 {
            0 => Action::Reading(Num::read(u)),
            1 => Action::Message {
                bearing: Num::read(u),
                msg: if get::<bool>(u) {
                    Msg::Opinion(get::<bool>(u).then(|| Num::read(u)))
                } else {
                    Msg::Readings(list(u, MAX_READINGS, Num::read))
                },
                time: TimeStep::read(u),
            },
            _ => Action::Timeout(TimeStep::read(u)),
        };
        Step {
            action,
            hold: get(u),
        }
    }

    fn write(&self, w: &mut Writer) {
        match &self.action {
            Action::Reading(x) => {
                w.u8(0);
                x.write(w);
            }
            Action::Message { bearing, msg, time } => {
                w.u8(1);
                bearing.write(w);
                match msg {
                    Msg::Opinion(o) => {
                        w.bool(true).bool(o.is_some());
                        if let Some(o) = o {
                            o.write(w);
                        }
                    }
                    Msg::Readings(r) => {
                        w.bool(false);
                        for x in r {
                            w.item();
                            x.write(w);
                        }
                        w.end();
                    }
                }
                time.write(w);
            }
            Action::Timeout(time) => {
                w.u8(2);
                time.write(w);
            }
        }
        w.bool(self.hold);
    }
}

/// A parsed input.
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// Seed, parameters, start.
    pub setup: Setup,
    /// Use the small agent `<Variance, 4, 3>`.
    pub small: bool,
    /// The steps.
    pub steps: Vec<Step>,
}

impl Input {
    /// Reads an input.
    pub fn read(data: &[u8]) -> Self {
        let mut u = Unstructured::new(data);
        let setup = Setup::read(&mut u);
        let small = get(&mut u);
        let steps = list(&mut u, MAX_STEPS, Step::read);
        Input {
            setup,
            small,
            steps,
        }
    }

    /// The bytes [`read`](Self::read) turns into this input.
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        self.setup.write(&mut w);
        w.bool(self.small);
        for s in &self.steps {
            w.item();
            s.write(&mut w);
        }
        w.end().finish()
    }
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let input = Input::read(data);
    let (first, second) = if input.small {
        (run::<4, 3>(&input), run::<4, 3>(&input))
    } else {
        (run::<32, 16>(&input), run::<32, 16>(&input))
    };
    assert!(
        first == second,
        "one seed and the same inputs gave two runs"
    );
}

fn bits(x: Option<f32>) -> Option<u32> {
    x.map(f32::to_bits)
}

fn bearing_ok(b: Option<f32>) -> bool {
    b.is_none_or(|b| b.is_finite() && (0.0..TAU).contains(&b))
}

/// Runs an input with every check; returns a bit-exact record of what it observed.
pub fn run<const N: usize, const S: usize>(input: &Input) -> Vec<u64> {
    let setup = &input.setup;
    let params = setup.params.params();
    let start = setup.start.instant();
    let mut rng = setup.rng();
    let agent = match ThreePhaseAgent::<Variance, N, S>::new(params, start, &mut rng) {
        Ok(a) => {
            assert_eq!(params.validate(), Ok(()));
            a
        }
        Err(e) => {
            assert_eq!(params.validate(), Err(e), "new refused {params:?}");
            return Vec::new();
        }
    };
    assert_eq!(agent.phase(), Phase::Gathering);
    assert_eq!(agent.state(), WaveState::Inactive);
    assert_eq!((agent.preferred(), agent.decision()), (None, None));
    let t = agent.poll_timeout();
    assert!(t > start || t == Instant::MAX, "first deadline {t:?}");
    assert!(t <= start + setup.longest_cycle(), "first deadline {t:?}");
    let mut r = Run {
        agent,
        rng,
        params,
        setup: *setup,
        now: start,
        latest: start,
        pending: None,
        clean: true,
        all_finite: true,
        reading: None,
        trace: Vec::new(),
    };
    for s in &input.steps {
        r.step(s);
    }
    r.trace
}

struct Run<const N: usize, const S: usize> {
    agent: ThreePhaseAgent<Variance, N, S>,
    rng: rand_pcg::Pcg32,
    params: Params,
    setup: Setup,
    now: Instant,
    latest: Instant,
    /// Model of the message waiting to be relayed.
    pending: Option<SimMessage<N>>,
    /// No output was left queued by a held step.
    clean: bool,
    /// Every reading fed so far was finite.
    all_finite: bool,
    /// The last reading given to `handle_reading`, if any.
    reading: Option<f32>,
    trace: Vec<u64>,
}

struct Before {
    phase: Phase,
    state: WaveState,
    preferred: Option<f32>,
    decision: Option<f32>,
    diversity: f32,
    periods: u32,
    stats: AgentStats,
    wave: WaveStats,
    timeout: Instant,
}

enum Call<'a, const N: usize> {
    Timeout,
    Message {
        bearing: f32,
        msg: &'a SimMessage<N>,
        accepted: bool,
    },
}

fn delta(after: u32, before: u32, what: &str) -> u32 {
    assert!(after >= before, "{what} went back: {before} -> {after}");
    after - before
}

impl<const N: usize, const S: usize> Run<N, S> {
    fn step(&mut self, step: &Step) {
        match &step.action {
            Action::Reading(x) => {
                let x = x.reading();
                self.all_finite &= x.is_finite();
                self.reading = Some(x);
                self.agent.handle_reading(x);
            }
            Action::Timeout(time) => {
                self.advance(*time);
                let before = self.before();
                self.agent.handle_timeout(self.now, &mut self.rng);
                self.after(before, Call::Timeout, step.hold);
            }
            Action::Message { bearing, msg, time } => {
                self.advance(*time);
                let msg = match msg {
                    Msg::Readings(r) => {
                        let v: heapless::Vec<f32, N> =
                            r.iter().map(|x| x.reading()).take(N).collect();
                        self.all_finite &= v.iter().all(|x| x.is_finite());
                        SimMessage::Readings(v)
                    }
                    Msg::Opinion(o) => SimMessage::Opinion(o.map(Num::bearing)),
                };
                let bearing = bearing.bearing();
                let before = self.before();
                let accepted = self
                    .agent
                    .handle_message(self.now, bearing, &msg, &mut self.rng);
                self.trace.push(u64::from(accepted));
                self.after(
                    before,
                    Call::Message {
                        bearing,
                        msg: &msg,
                        accepted,
                    },
                    step.hold,
                );
            }
        }
    }

    fn advance(&mut self, time: TimeStep) {
        let deadline = self.agent.poll_timeout();
        self.now = time.apply(self.now, deadline, self.setup.max_forward());
        self.latest = self.latest.max(self.now);
    }

    fn before(&self) -> Before {
        let a = &self.agent;
        Before {
            phase: a.phase(),
            state: a.state(),
            preferred: a.preferred(),
            decision: a.decision(),
            diversity: a.diversity(),
            periods: a.periods(),
            stats: *a.stats(),
            wave: *a.wave_stats(),
            timeout: a.poll_timeout(),
        }
    }

    fn record(&mut self, m: &SimMessage<N>) {
        match m {
            SimMessage::Readings(r) => {
                self.trace.push(1 << 32 | r.len() as u64);
                self.trace.extend(r.iter().map(|x| u64::from(x.to_bits())));
            }
            SimMessage::Opinion(o) => self.trace.push(2 << 32 | opt_bits(*o)),
        }
    }

    fn after(&mut self, before: Before, call: Call<'_, N>, hold: bool) {
        let now = self.now;
        let a = &self.agent;
        let phase = a.phase();
        let state = a.state();
        let preferred = a.preferred();
        let decision = a.decision();
        let diversity = a.diversity();
        let stats = *a.stats();
        let wave = *a.wave_stats();

        // Values.
        assert!(bearing_ok(preferred), "preferred {preferred:?}");
        assert!(bearing_ok(decision), "decision {decision:?}");
        assert!(
            diversity >= 0.0 || diversity.is_nan(),
            "diversity {diversity}"
        );
        if self.all_finite {
            assert!(!diversity.is_nan(), "diversity NaN from finite readings");
        }
        let heard: Vec<(f32, f32, u32)> = a.weights().collect();
        assert!(heard.len() <= S, "{} directions", heard.len());
        for &(b, w, n) in &heard {
            assert!(n >= 1 && w >= 0.0, "{heard:?}");
            assert!(b.is_nan() || (0.0..TAU).contains(&b), "{heard:?}");
        }
        let d_periods = delta(a.periods(), before.periods, "periods");
        let d_init = delta(wave.initiated, before.wave.initiated, "initiated");
        let d_relayed = delta(wave.relayed, before.wave.relayed, "relayed");
        let d_ignored = delta(wave.ignored, before.wave.ignored, "ignored");
        delta(
            wave.skipped_initiations,
            before.wave.skipped_initiations,
            "skipped",
        );
        let d_accepted = delta(stats.accepted, before.stats.accepted, "accepted");
        let d_wrong = delta(stats.wrong_phase, before.stats.wrong_phase, "wrong_phase");
        let d_full = delta(stats.slots_full, before.stats.slots_full, "slots_full");
        let d_lost = delta(stats.lost, before.stats.lost, "lost");
        assert!(d_relayed <= 1 && d_accepted <= 1 && d_wrong <= 1 && d_full <= 1);
        // No evaluation and no period end in this call: the preference only moves by messages.
        let quiet = d_periods == 0 && phase == before.phase;

        // The deadline.
        let t = a.poll_timeout();
        self.trace.push(t.as_millis());
        assert!(
            t > now || t == Instant::MAX,
            "deadline {t:?} not after {now:?}"
        );
        assert!(
            t <= self.latest + self.setup.longest_cycle(),
            "deadline {t:?} more than a cycle after {:?}",
            self.latest
        );
        if now < before.timeout {
            assert_eq!((d_init, d_relayed, d_periods), (0, 0, 0));
            assert_eq!(phase, before.phase);
            if let Call::Timeout = call {
                assert_eq!(state, before.state);
                assert_eq!(stats, before.stats);
                assert_eq!(wave, before.wave);
                assert_eq!(t, before.timeout);
            }
        }

        // The reception.
        let mut accepted_msg = None;
        match call {
            Call::Timeout => assert_eq!((d_accepted, d_wrong, d_full), (0, 0, 0)),
            Call::Message {
                bearing,
                msg,
                accepted,
            } => {
                let in_phase = match (phase, msg) {
                    (Phase::Gathering, SimMessage::Readings(r)) => !r.is_empty(),
                    (Phase::Deciding, SimMessage::Opinion(_)) => true,
                    _ => false,
                };
                if !in_phase {
                    assert!(!accepted, "accepted in the wrong phase");
                    assert_eq!((d_wrong, d_accepted, d_ignored, d_full), (1, 0, 0, 0));
                } else if accepted {
                    assert_eq!((d_wrong, d_accepted, d_ignored), (0, 1, 0));
                    assert_eq!(state, WaveState::Active);
                    assert!(t <= now + self.params.wave.relay_delay, "relay at {t:?}");
                    match msg {
                        SimMessage::Readings(_) => {
                            let key = wrap_positive(bearing);
                            let found = heard.iter().any(|&(b, _, _)| {
                                b.to_bits() == key.to_bits() || (b.is_nan() && key.is_nan())
                            });
                            if d_full == 1 {
                                assert!(!found && heard.len() == S, "slots_full with {heard:?}");
                            } else {
                                assert!(found, "no slot for {bearing} in {heard:?}");
                            }
                        }
                        SimMessage::Opinion(o) => {
                            assert_eq!(d_full, 0);
                            if quiet {
                                let expected = match (*o, before.preferred) {
                                    (Some(o), None) if o.is_finite() => Some(wrap_positive(o)),
                                    (Some(o), Some(p)) if o.is_finite() => {
                                        Some(turn_toward(p, o, self.params.diffusion))
                                    }
                                    _ => before.preferred,
                                };
                                assert_eq!(bits(preferred), bits(expected), "opinion {o:?}");
                            }
                        }
                    }
                    accepted_msg = Some(msg.clone());
                } else {
                    assert_eq!((d_wrong, d_accepted, d_ignored, d_full), (0, 0, 1, 0));
                    assert_ne!(state, WaveState::Inactive, "ignored while inactive");
                }
            }
        }
        if quiet && accepted_msg.is_none() {
            assert_eq!(bits(preferred), bits(before.preferred));
        }

        // Transmissions.
        if !hold {
            let mut got = Vec::new();
            while let Some(m) = self.agent.poll_transmit() {
                got.push(m);
                assert!(got.len() <= OUTBOX, "poll_transmit does not run dry");
            }
            for m in &got {
                match m {
                    SimMessage::Readings(r) => assert!((1..=N).contains(&r.len()), "{m:?}"),
                    SimMessage::Opinion(o) => assert!(bearing_ok(*o), "{m:?}"),
                }
            }
            if self.clean && d_lost == 0 {
                if quiet {
                    // A relay whose message a phase change discarded (in an earlier call) sends
                    // nothing.
                    let relays = if self.pending.is_some() { d_relayed } else { 0 };
                    assert_eq!(got.len(), (d_init + relays) as usize, "{got:?}");
                }
                for m in &got {
                    match m {
                        SimMessage::Readings(r) if r.len() >= 2 => {
                            let Some(SimMessage::Readings(mut expected)) = self.pending.clone()
                            else {
                                panic!("relayed {m:?} with {:?} pending", self.pending);
                            };
                            if expected.is_full() {
                                expected.remove(0);
                            }
                            let own = self.reading.unwrap_or(r[r.len() - 1]);
                            let _ = expected.push(own);
                            let same = expected.len() == r.len()
                                && expected
                                    .iter()
                                    .zip(r.iter())
                                    .all(|(x, y)| x.to_bits() == y.to_bits());
                            assert!(same, "relay {m:?} of {:?}", self.pending);
                        }
                        SimMessage::Readings(r) => {
                            if let Some(own) = self.reading {
                                assert_eq!(r[0].to_bits(), own.to_bits(), "initiation {m:?}");
                            }
                        }
                        SimMessage::Opinion(o) => {
                            if quiet {
                                assert_eq!(bits(*o), bits(before.preferred), "{m:?}");
                            }
                        }
                    }
                }
            }
            for m in &got {
                self.record(m);
            }
        }
        if d_relayed > 0 || !quiet {
            self.pending = None;
        }
        if let Some(m) = accepted_msg {
            self.pending = Some(m);
        }

        // Events.
        if hold {
            self.clean = false;
            return;
        }
        let mut got = Vec::new();
        while let Some(e) = self.agent.poll_event() {
            got.push(e);
            assert!(got.len() <= EVENT_QUEUE, "poll_event does not run dry");
        }
        for e in &got {
            match *e {
                SimEvent::State(_) => {}
                SimEvent::Evaluated {
                    preferred,
                    diversity,
                } => assert!(
                    bearing_ok(preferred) && (diversity >= 0.0 || diversity.is_nan()),
                    "{e:?}"
                ),
                SimEvent::Decided { bearing, .. } => assert!(bearing_ok(bearing), "{e:?}"),
            }
        }
        if self.clean && d_lost == 0 {
            let mut s = before.state;
            let mut p = before.phase;
            let mut period = before.periods;
            let mut last_decision = bits(before.decision);
            let mut last_diversity = before.diversity.to_bits();
            let (mut refractory, mut active) = (0, 0);
            for e in &got {
                match *e {
                    SimEvent::State(next) => {
                        let ok = matches!(
                            (s, next),
                            (WaveState::Inactive, WaveState::Active)
                                | (WaveState::Active, WaveState::Refractory)
                                | (WaveState::Inactive, WaveState::Refractory)
                                | (WaveState::Refractory, WaveState::Inactive)
                        );
                        assert!(ok, "{s:?} -> {next:?} in {got:?}");
                        refractory += u32::from(next == WaveState::Refractory);
                        active += u32::from(next == WaveState::Active);
                        s = next;
                    }
                    SimEvent::Evaluated { diversity, .. } => {
                        assert_eq!(p, Phase::Gathering, "{got:?}");
                        p = Phase::Deciding;
                        last_diversity = diversity.to_bits();
                    }
                    SimEvent::Decided { period: n, bearing } => {
                        assert_eq!(p, Phase::Deciding, "{got:?}");
                        p = Phase::Gathering;
                        period += 1;
                        assert_eq!(n, period);
                        last_decision = bits(bearing);
                    }
                }
            }
            assert_eq!(s, state, "events end in {s:?}: {got:?}");
            assert_eq!(p, phase, "events end in {p:?}: {got:?}");
            assert_eq!(period, self.agent.periods());
            assert_eq!(last_decision, bits(decision));
            assert_eq!(last_diversity, diversity.to_bits());
            assert_eq!(refractory, d_init + d_relayed);
            assert_eq!(active, d_accepted);
        }
        self.clean = true;
        for e in &got {
            self.trace.push(event_word(e));
        }
    }
}

fn opt_bits(x: Option<f32>) -> u64 {
    x.map_or(u64::MAX, |x| u64::from(x.to_bits()))
}

fn event_word(e: &SimEvent) -> u64 {
    match *e {
        SimEvent::State(s) => 3 << 32 | s as u64,
        SimEvent::Evaluated {
            preferred,
            diversity,
        } => (4 << 32 | u64::from(diversity.to_bits())) ^ opt_bits(preferred).rotate_left(17),
        SimEvent::Decided { period, bearing } => {
            (5 << 32 | u64::from(period)) ^ opt_bits(bearing).rotate_left(29)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{ParamsChoice, Start};

    #[test]
    fn inputs_read_back_and_a_run_decides() {
        let mut steps = vec![
            Step::drain(Action::Reading(Num::Small(0))),
            Step::drain(Action::Message {
                bearing: Num::Small(0),
                msg: Msg::Readings(vec![Num::Small(5), Num::Small(5)]),
                time: TimeStep::Forward(1_000),
            }),
            Step::drain(Action::Message {
                bearing: Num::Bits(f32::NAN.to_bits()),
                msg: Msg::Opinion(Some(Num::Small(64))),
                time: TimeStep::Nudge(1),
            }),
        ];
        steps.extend((0..12).map(|_| Step::drain(Action::Timeout(TimeStep::Deadline))));
        let input = Input {
            setup: Setup {
                rng_state: 1,
                rng_stream: 2,
                params: ParamsChoice::Simulation2d,
                start: Start::Zero,
            },
            small: true,
            steps,
        };
        assert_eq!(Input::read(&input.write()), input);
        let trace = run::<4, 3>(&input);
        assert_eq!(trace[0], 1, "the first message is accepted");
        check(&input.write());
    }
}
