//! `fused_node`: the robot state machine [`FusedNode`] driven by an arbitrary sequence of inputs.
//!
//! Input: a [`Setup`] (RNG seed for `rand_pcg::Pcg32`, parameters, start instant), the robot's
//! tag (modulo 16), then up to [`MAX_STEPS`] steps: a sensor reading; a message from any sector (also sectors `≥ K`, and the
//! empty message); received bytes for a sector's [`Deframer`]; noise then a whole frame; or a
//! bare `handle_timeout`. Each step moves time first ([`TimeStep`]: forward, backward, to the
//! deadline). After each step the outputs are drained, unless the step says to hold them.
//!
//! After every `handle_*` call the harness checks, through the public API only, against a
//! small model of what `docs/protocol.md` §5 and §9 promise:
//!
//! - nothing panics; `new` refuses exactly what `Params::validate` refuses, and keeps the tag;
//! - `poll_transmit` and `poll_event` run dry within 2 and 8 items (§5.4), as many messages
//!   come out as were queued minus those counted lost, and a loss means the queue was full;
//! - every transmitted message encodes and frames back, has at most `max_hops` hops, a payload
//!   of at most 25 bytes (and `1 + 2·max_hops` unless one hop is left), the own tag last and a
//!   valid ray of K sectors with robots ≥ 1; an initiation is the robot's own hop with the ray of
//!   a side holding the fewest robots; a relay is the accepted message cut to `max_hops − 1`
//!   hops plus its own hop, cut again to what fits beside the ray of the side it came from,
//!   which is the held ray of that side extended by the robot (or the robot alone); the cuts
//!   are counted in `hops_evicted` (but see finding 5 of README.md);
//! - `poll_timeout()` is after `now` (or "never", `Instant::MAX`) and at most one longest cycle
//!   after the latest instant seen; an input before the deadline changes nothing due to time;
//! - receptions: `UnknownSector` exactly for sectors `≥ K`; then `OwnTag` exactly for a message
//!   holding a hop with the robot's own tag, which changes nothing but `own_tag` (no
//!   activation, no score, no vote, not counted as ignored); `Ignored` for the empty message or
//!   a node that is not inactive; `Accepted` leaves it active with its relay due within the
//!   relay delay; counters move by one accordingly;
//! - preference and decision are `None` or a sector below K; a preference, once set, is never
//!   cleared; after an accepted message it is the strictly heaviest sector by `weight()` if
//!   there is one, else unchanged; weights are finite, in `[0, 127.5²]`, and only below K;
//! - rays: a message heard (accepted or ignored) with a ray counts in `rays` or `rays_refused`
//!   exactly as the taking rules of §5.3 say, and the model holds what was taken; rays older
//!   than a negotiation period are forgotten at its end;
//! - `votes()` equals the own preference plus the votes of every ray held (this replaces the
//!   per-tag slots of the first format, which the node no longer keeps);
//! - with every event of a call seen: the `State` events chain valid transitions ending in
//!   `state()`, one `Refractory` per transmission and one `Active` per acceptance; `Decided`
//!   events number the periods, carry the model's votes and follow the decision by resultant
//!   scores and the tie rules of §5.3 ([`check_decision`]), and `changed` is right;
//! - the same seed and inputs give the same outputs (the input is run twice).

use arbitrary::Unstructured;
use protocol::frame::{self, Deframer, FrameError};
use protocol::fused::{NodeStats, Votes};
use protocol::message::{PAYLOAD_BUDGET, Ray, Tag};
use protocol::wave::WaveStats;
use protocol::{
    Event, FusedNode, Hop, Instant, Level, MAX_HOPS, MAX_SECTORS, Message, Params, Reception,
    Sector, WaveState,
};

use crate::input::{Writer, byte_list, get, list};
use crate::reference::{self, ArbRay, MAX_LEVEL_VARIANCE};
use crate::scenario::{Setup, TimeStep};

/// Steps read at most.
pub const MAX_STEPS: usize = 256;
/// Received bytes per step at most.
pub const MAX_BYTES: usize = 96;
/// The outbox depth of §5.4.
pub const OUTBOX: usize = 2;
/// The event queue depth of §5.4.
pub const EVENT_QUEUE: usize = 8;

/// What a step does after moving time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Action {
    /// `handle_reading`.
    Reading(u8),
    /// `handle_message` with this message (empty for no hops) from `sector % 8`.
    Message {
        /// Sector index, before the modulo.
        sector: u8,
        /// The hops.
        hops: Vec<Hop>,
        /// The message's ray, if any (set with `set_ray`, which may drop the oldest hops).
        ray: Option<Ray>,
        /// How time moves first.
        time: TimeStep,
    },
    /// Bytes received on `sector % 8`: its deframer's messages go to `handle_message`.
    Bytes {
        /// Sector index, before the modulo.
        sector: u8,
        /// The bytes.
        bytes: Vec<u8>,
        /// How time moves first.
        time: TimeStep,
    },
    /// Noise, then the frame of the message (if it has hops), on `sector % 8`.
    Framed {
        /// Sector index, before the modulo.
        sector: u8,
        /// Bytes before the frame.
        noise: Vec<u8>,
        /// The hops.
        hops: Vec<Hop>,
        /// The message's ray, if any.
        ray: Option<Ray>,
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
        let action = match get::<u8>(u) % 5 {
            0 => Action::Reading(get(u)),
            1 => Action::Message {
                sector: get(u),
                hops: reference::read_hops(u, MAX_HOPS),
                ray: read_ray(u),
                time: TimeStep::read(u),
            },
            2 => Action::Bytes {
                sector: get(u),
                bytes: byte_list(u, MAX_BYTES),
                time: TimeStep::read(u),
            },
            3 => Action::Framed {
                sector: get(u),
                noise: byte_list(u, MAX_BYTES),
                hops: reference::read_hops(u, MAX_HOPS),
                ray: read_ray(u),
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
            Action::Reading(r) => {
                w.u8(0).u8(*r);
            }
            Action::Message {
                sector,
                hops,
                ray,
                time,
            } => {
                w.u8(1).u8(*sector);
                reference::write_hops(w, hops);
                write_ray(w, *ray);
                time.write(w);
            }
            Action::Bytes {
                sector,
                bytes,
                time,
            } => {
                w.u8(2).u8(*sector).byte_list(bytes);
                time.write(w);
            }
            Action::Framed {
                sector,
                noise,
                hops,
                ray,
                time,
            } => {
                w.u8(3).u8(*sector).byte_list(noise);
                reference::write_hops(w, hops);
                write_ray(w, *ray);
                time.write(w);
            }
            Action::Timeout(time) => {
                w.u8(4);
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
    /// The robot's tag, before the modulo.
    pub tag: u8,
    /// The steps.
    pub steps: Vec<Step>,
}

impl Input {
    /// Reads an input.
    pub fn read(data: &[u8]) -> Self {
        let mut u = Unstructured::new(data);
        let setup = Setup::read(&mut u);
        let tag = get(&mut u);
        let steps = list(&mut u, MAX_STEPS, Step::read);
        Input { setup, tag, steps }
    }

    /// The bytes [`read`](Self::read) turns into this input.
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        self.setup.write(&mut w);
        w.u8(self.tag);
        for s in &self.steps {
            w.item();
            s.write(&mut w);
        }
        w.end().finish()
    }
}

/// Everything observable a run produced, for the determinism check.
#[derive(Clone, Debug, PartialEq)]
pub enum Out {
    /// A deframer result.
    Deframed(Result<Message, FrameError>),
    /// What `handle_message` returned.
    Reception(Reception),
    /// A message from `poll_transmit`.
    Transmit(Message),
    /// An event from `poll_event`.
    Event(Event),
    /// `poll_timeout()` after a call.
    Deadline(Instant),
}

/// The check of this target.
/// Reads an optional ray (a `bool`, then a [`reference::ArbRay`]).
fn read_ray(u: &mut Unstructured<'_>) -> Option<Ray> {
    get::<bool>(u)
        .then(|| u.arbitrary::<ArbRay>().ok())
        .flatten()
        .map(|r| r.0)
}

/// Writes an optional ray for [`read_ray`].
fn write_ray(w: &mut Writer, ray: Option<Ray>) {
    match ray {
        Some(r) => {
            w.bool(true);
            ArbRay(r).write(w);
        }
        None => {
            w.bool(false);
        }
    }
}

/// The message of a step: the hops (none: the empty message) with the ray set.
fn message_of(hops: &[Hop], ray: Option<Ray>) -> Message {
    let mut m = reference::message(hops);
    if !m.is_empty() {
        m.set_ray(ray);
    }
    m
}

pub fn check(data: &[u8]) {
    let input = Input::read(data);
    let first = run(&input);
    let second = run(&input);
    assert!(
        first == second,
        "one seed and the same inputs gave two runs"
    );
}

/// Runs an input with every check; returns what it observed.
pub fn run(input: &Input) -> Vec<Out> {
    let setup = &input.setup;
    let params = setup.params.params();
    let start = setup.start.instant();
    let mut rng = setup.rng();
    let tag = reference::tag(input.tag);
    let node = match FusedNode::new(params, tag, start, &mut rng) {
        Ok(n) => {
            assert_eq!(params.validate(), Ok(()));
            n
        }
        Err(e) => {
            assert_eq!(params.validate(), Err(e), "new refused {params:?}");
            return Vec::new();
        }
    };
    assert_eq!(node.tag(), tag);
    assert_eq!(node.state(), WaveState::Inactive);
    assert_eq!((node.preference(), node.decision()), (None, None));
    assert_eq!(node.periods(), 0);
    assert_eq!(node.votes(), [0; MAX_SECTORS]);
    let t = node.poll_timeout();
    assert!(t > start || t == Instant::MAX, "first deadline {t:?}");
    assert!(t <= start + setup.longest_cycle(), "first deadline {t:?}");

    let mut r = Run {
        node,
        rng,
        params,
        k: usize::from(params.sectors),
        tag,
        setup: *setup,
        deframers: core::array::from_fn(|_| Deframer::new()),
        now: start,
        latest: start,
        held: NOTHING_HELD,
        pending: None,
        implausible_ray: false,
        outbox: 0,
        events_clean: true,
        trace: Vec::new(),
    };
    for s in &input.steps {
        r.step(s);
    }
    r.trace
}

/// Cycles after which a robot may take a direction's ray from another neighbour than the one
/// it follows (`SENDER_SWITCH_CYCLES` of `fused.rs`, private there; `docs/protocol.md` §5.3).
pub const SENDER_SWITCH_CYCLES: u64 = 3;

/// Scores closer than this to the best are a tie as far as the model can tell: the node sums
/// `f32` products with a cosine table rounded to 2⁻²⁰, the model `f64` products with `cos`;
/// for any votes the node can hold (under 2¹² per sector) the two differ by less than 0.005.
pub const SCORE_TOLERANCE: f64 = 0.01;

/// A ray the model holds for a sector: the ray, when it was taken, and from whom.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeldRay {
    /// The ray as received.
    pub ray: Ray,
    /// When it was taken.
    pub at: Instant,
    /// The tag of its message's last hop.
    pub sender: Tag,
}

/// The model of the rays a node holds, one slot per sector.
pub type Held = [Option<HeldRay>; MAX_SECTORS];
const NOTHING_HELD: Held = [None; MAX_SECTORS];

/// The votes counted: the votes of every ray held (each robot on that side once), plus the own
/// preference, for sectors below K only.
pub fn votes_of(held: &Held, pref: Option<Sector>, k: usize) -> Votes {
    let mut v = [0u16; MAX_SECTORS];
    for h in held.iter().flatten() {
        for (t, &x) in v.iter_mut().zip(&h.ray.votes).take(k) {
            *t = t.saturating_add(u16::from(x));
        }
    }
    if let Some(i) = pref.map(|p| usize::from(p.index())).filter(|&i| i < k) {
        v[i] += 1;
    }
    v
}

/// Each sector's score (§5.3): the votes projected on its direction,
/// `Σ_t votes[t] · cos(2π (s − t) / K)`, computed in `f64` from `cos`.
pub fn scores_of(votes: &Votes, k: usize) -> Vec<f64> {
    (0..k)
        .map(|s| {
            (0..k)
                .map(|t| {
                    let d = (s as f64 - t as f64) / k as f64;
                    // Rounded to 1e-9 so that the cosines of K = 2 and 4 are exactly 0 and ±1
                    // (`cos(π/2)` is 6e-17 in f64, which broke exact ties: finding 8).
                    let c = ((core::f64::consts::TAU * d).cos() * 1e9).round() / 1e9;
                    f64::from(votes[t]) * c
                })
                .sum()
        })
        .collect()
}

/// The decision rule of §5.3, checked: no vote gives no decision; else the sector of the
/// highest score; a tie goes to the own preference if it is among the best, else to the
/// previous decision if it is, else no decision. With K = 2 or 4 every cosine is 0 or ±1 and
/// the scores are exact, so the whole rule is checked; with other K, scores within
/// [`SCORE_TOLERANCE`] of the best may be a tie, and the decision must be one of them (or none).
pub fn check_decision(
    votes: &Votes,
    k: usize,
    pref: Option<Sector>,
    previous: Option<Sector>,
    decision: Option<Sector>,
) {
    let what = format!("votes {votes:?}, K {k}, pref {pref:?}, previous {previous:?}");
    if votes[..k].iter().all(|&v| v == 0) {
        assert_eq!(decision, None, "{what}");
        return;
    }
    let scores = scores_of(votes, k);
    let max = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let exact = k == 2 || k == 4;
    let tol = if exact { 0.0 } else { SCORE_TOLERANCE };
    let tops: Vec<Sector> = (0..k)
        .filter(|&i| scores[i] >= max - tol)
        .map(|i| reference::sector(i as u8))
        .collect();
    if let [only] = tops.as_slice() {
        assert_eq!(decision, Some(*only), "{what}");
    } else if exact {
        let expected = [pref, previous]
            .into_iter()
            .flatten()
            .find(|s| tops.contains(s));
        assert_eq!(decision, expected, "tie among {tops:?}: {what}");
    } else {
        assert!(
            decision.is_none_or(|d| tops.contains(&d)),
            "{decision:?} not among {tops:?}: {what}"
        );
    }
}

/// Checks the ray a transmission carries for `sector`: this robot's ray of that side, the ray
/// `held` extended by itself (its reading and preference), or itself alone if none is held.
/// The sums are exact (wire format 3): robots + 1 (a ray of 255 robots keeps its sums), the
/// reading added to the sum and its square to the sum of squares.
pub fn ray_matches(
    ray: &Ray,
    sector: Sector,
    k: usize,
    reading: Level,
    pref: Option<Sector>,
    held: Option<&HeldRay>,
) -> bool {
    if ray.sector != sector || usize::from(ray.sectors) != k || !reference::ray_is_valid(ray) {
        return false;
    }
    let mut votes = held.map_or([0; MAX_SECTORS], |h| h.ray.votes);
    if let Some(i) = pref.map(|p| usize::from(p.index())).filter(|&i| i < k) {
        votes[i] = votes[i].saturating_add(1);
    }
    let x = u32::from(reading.0);
    let Some(h) = held else {
        return ray.robots == 1
            && u32::from(ray.sum) == x
            && ray.sum_sq == x * x
            && ray.votes == votes;
    };
    let (robots, sum, sum_sq) = if h.ray.robots == u8::MAX {
        (h.ray.robots, u32::from(h.ray.sum), h.ray.sum_sq)
    } else {
        (
            h.ray.robots + 1,
            u32::from(h.ray.sum) + x,
            h.ray.sum_sq + x * x,
        )
    };
    ray.robots == robots
        && u32::from(ray.sum) == sum
        && ray.sum_sq == sum_sq
        && ray.votes == votes
        && ray.closed == h.ray.closed
}

/// True if a ray's sums are those of some 8-bit readings. Since wire format 3 every ray that
/// decodes is ([`reference::ray_is_valid`]); kept so that the check stays where it was.
pub fn ray_is_plausible(r: &Ray) -> bool {
    reference::ray_is_valid(r)
}

struct Run {
    node: FusedNode,
    rng: rand_pcg::Pcg32,
    params: Params,
    k: usize,
    tag: Tag,
    setup: Setup,
    deframers: [Deframer; MAX_SECTORS],
    now: Instant,
    latest: Instant,
    /// Model of the rays the node holds.
    held: Held,
    /// Model of the message waiting to be relayed, and where it came from.
    pending: Option<(Message, Sector)>,
    /// A ray whose moments no 8-bit readings have was delivered (see [`ray_is_plausible`]).
    implausible_ray: bool,
    /// Messages left in the outbox by held steps.
    outbox: usize,
    /// No event was left queued by a held step.
    events_clean: bool,
    trace: Vec<Out>,
}

/// What the checks compare with after a call.
struct Before {
    state: WaveState,
    pref: Option<Sector>,
    decision: Option<Sector>,
    periods: u32,
    stats: NodeStats,
    wave: WaveStats,
    timeout: Instant,
    held: Held,
    weights: [Option<f32>; MAX_SECTORS],
}

enum Call<'a> {
    Timeout,
    Message {
        from: Sector,
        msg: &'a Message,
        reception: Reception,
    },
}

fn delta(after: u32, before: u32, what: &str) -> u32 {
    assert!(after >= before, "{what} went back: {before} -> {after}");
    after - before
}

fn valid(s: Option<Sector>, k: usize) -> bool {
    s.is_none_or(|s| usize::from(s.index()) < k)
}

impl Run {
    fn step(&mut self, step: &Step) {
        let hold = step.hold;
        match &step.action {
            Action::Reading(r) => {
                self.node.handle_reading(Level(*r));
                assert_eq!(self.node.reading(), Level(*r));
            }
            Action::Timeout(time) => {
                self.advance(*time);
                let before = self.before();
                self.node.handle_timeout(self.now, &mut self.rng);
                self.after(before, Call::Timeout, hold);
            }
            Action::Message {
                sector,
                hops,
                ray,
                time,
            } => {
                self.advance(*time);
                self.deliver(reference::sector(*sector), &message_of(hops, *ray), hold);
            }
            Action::Bytes {
                sector,
                bytes,
                time,
            } => {
                self.advance(*time);
                let s = reference::sector(*sector);
                let got: Vec<_> = self.deframers[usize::from(s.index())]
                    .frames(bytes)
                    .collect();
                self.received(s, got, hold);
            }
            Action::Framed {
                sector,
                noise,
                hops,
                ray,
                time,
            } => {
                self.advance(*time);
                let s = reference::sector(*sector);
                let d = &mut self.deframers[usize::from(s.index())];
                let mut got: Vec<_> = d.frames(noise).collect();
                let msg = message_of(hops, *ray);
                match frame::encode(&msg) {
                    Ok(f) => {
                        let tail: Vec<_> = d.frames(&f).collect();
                        // §2.3: whatever came before, a whole frame is decoded.
                        assert!(tail.len() <= 2, "{tail:?}");
                        assert_eq!(tail.last(), Some(&Ok(msg.clone())), "{tail:?}");
                        got.extend(tail);
                        self.received(s, got, hold);
                    }
                    Err(e) => {
                        assert!(msg.is_empty(), "{e:?} for {msg:?}");
                        self.received(s, got, hold);
                        self.deliver(s, &msg, hold);
                    }
                }
            }
        }
    }

    fn advance(&mut self, time: TimeStep) {
        let deadline = self.node.poll_timeout();
        self.now = time.apply(self.now, deadline, self.setup.max_forward());
        self.latest = self.latest.max(self.now);
    }

    fn received(&mut self, from: Sector, got: Vec<Result<Message, FrameError>>, hold: bool) {
        for r in got {
            self.trace.push(Out::Deframed(r.clone()));
            if let Ok(m) = r {
                reference::check_decoded(&m);
                self.deliver(from, &m, hold);
            }
        }
    }

    fn deliver(&mut self, from: Sector, msg: &Message, hold: bool) {
        if msg.ray().is_some_and(|r| !ray_is_plausible(r)) {
            self.implausible_ray = true;
        }
        let before = self.before();
        let reception = self.node.handle_message(self.now, from, msg, &mut self.rng);
        self.trace.push(Out::Reception(reception));
        self.after(
            before,
            Call::Message {
                from,
                msg,
                reception,
            },
            hold,
        );
    }

    fn before(&self) -> Before {
        let n = &self.node;
        Before {
            state: n.state(),
            pref: n.preference(),
            decision: n.decision(),
            periods: n.periods(),
            stats: *n.stats(),
            wave: *n.wave_stats(),
            timeout: n.poll_timeout(),
            held: self.held,
            weights: core::array::from_fn(|i| n.weight(reference::sector(i as u8))),
        }
    }

    /// The strictly heaviest sector by `weight()`, above zero, if any.
    /// The sector the preference must name (docs/protocol.md §5.1): the largest average,
    /// above 0, ahead of every other by more than `TIE_TOLERANCE` relative (closer is a tie).
    fn heaviest(&self) -> Option<Sector> {
        let tol = protocol::fused::TIE_TOLERANCE;
        let w: Vec<(Sector, f32)> = (0..self.k as u8)
            .map(reference::sector)
            .filter_map(|s| self.node.weight(s).map(|w| (s, w)))
            .collect();
        let max = w.iter().map(|&(_, x)| x).fold(f32::NEG_INFINITY, f32::max);
        let mut tops = w
            .iter()
            .filter(|&&(_, x)| (max - x).abs() <= tol * max.abs().max(x.abs()));
        match (tops.next(), tops.next()) {
            (Some(&(s, x)), None) if x > 0.0 => Some(s),
            _ => None,
        }
    }

    fn after(&mut self, before: Before, call: Call<'_>, hold: bool) {
        let k = self.k;
        let now = self.now;
        let pref = self.node.preference();
        let decision = self.node.decision();
        let stats = *self.node.stats();
        let wave = *self.node.wave_stats();
        let state = self.node.state();

        // Values.
        assert!(valid(pref, k), "preference {pref:?} with K = {k}");
        assert!(valid(decision, k), "decision {decision:?} with K = {k}");
        if before.pref.is_some() {
            assert!(pref.is_some(), "a preference was cleared");
        }
        for i in 0..MAX_SECTORS as u8 {
            let w = self.node.weight(reference::sector(i));
            if usize::from(i) >= k {
                assert_eq!(w, None, "weight of sector {i} with K = {k}");
            } else if let Some(w) = w {
                // Rays carry the variance as u16 quarters: 16383.75 at most, and only
                // plausible rays keep it within what 8-bit readings allow.
                let max = if self.implausible_ray {
                    f32::from(u16::MAX) / 4.0
                } else {
                    MAX_LEVEL_VARIANCE
                };
                assert!((0.0..=max).contains(&w), "weight {w} of sector {i}");
            }
        }
        let d_periods = delta(self.node.periods(), before.periods, "periods");
        let d_init = delta(wave.initiated, before.wave.initiated, "initiated");
        let d_relayed = delta(wave.relayed, before.wave.relayed, "relayed");
        let d_ignored = delta(wave.ignored, before.wave.ignored, "ignored");
        delta(
            wave.skipped_initiations,
            before.wave.skipped_initiations,
            "skipped",
        );
        let d_accepted = delta(stats.accepted, before.stats.accepted, "accepted");
        let d_unknown = delta(stats.unknown_sector, before.stats.unknown_sector, "unknown");
        let d_own = delta(stats.own_tag, before.stats.own_tag, "own_tag");
        let d_evicted = delta(stats.hops_evicted, before.stats.hops_evicted, "evicted");
        let d_tlost = delta(stats.transmits_lost, before.stats.transmits_lost, "tlost");
        let d_elost = delta(stats.events_lost, before.stats.events_lost, "elost");
        let d_rays = delta(stats.rays, before.stats.rays, "rays");
        let d_refused = delta(
            stats.rays_refused,
            before.stats.rays_refused,
            "rays_refused",
        );
        assert!(d_relayed <= 1, "{d_relayed} relays in one call");
        assert!(d_accepted <= 1);

        // The deadline.
        let t = self.node.poll_timeout();
        self.trace.push(Out::Deadline(t));
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
            assert_eq!(
                (d_init, d_relayed, d_periods),
                (0, 0, 0),
                "before the deadline"
            );
            if let Call::Timeout = call {
                assert_eq!(state, before.state);
                assert_eq!(stats, before.stats);
                assert_eq!(wave, before.wave);
                assert_eq!(t, before.timeout);
            }
        }

        // Period ends forget the rays not refreshed within a period (before any message of
        // this call is noted).
        let period = self
            .setup
            .longest_cycle()
            .saturating_mul(u64::from(self.params.negotiation_cycles));
        if d_periods > 0 {
            let cutoff = now - period;
            for slot in &mut self.held {
                if slot.is_some_and(|h| h.at < cutoff) {
                    *slot = None;
                }
            }
        }
        // What a transmission of this call may have extended: the rays before the call or
        // after its period end (the cycle end and the relay come in either order).
        let held_after_expiry = self.held;

        // The reception.
        let mut accepted = None;
        let mut offered = None;
        match call {
            Call::Timeout => assert_eq!((d_accepted, d_unknown, d_own), (0, 0, 0)),
            Call::Message {
                from,
                msg,
                reception,
            } => {
                let known = usize::from(from.index()) < k;
                let own_tag = msg.has_tag(self.tag);
                let before_weight = before.weights[usize::from(from.index())];
                assert_eq!(own_tag, msg.hops().iter().any(|h| h.tag == self.tag));
                match reception {
                    Reception::UnknownSector => {
                        assert!(!known, "{from:?} is known with K = {k}");
                        assert_eq!((d_unknown, d_accepted, d_own), (1, 0, 0));
                    }
                    Reception::OwnTag => {
                        assert!(known && own_tag, "OwnTag for {msg:?}");
                        assert_eq!((d_unknown, d_accepted, d_own, d_ignored), (0, 0, 1, 0));
                        assert_eq!(
                            self.node.weight(from),
                            before_weight,
                            "scored a message with the own tag"
                        );
                        if now < before.timeout {
                            assert_eq!(state, before.state, "activated by the own tag");
                        }
                    }
                    Reception::Ignored => {
                        assert!(known && !own_tag);
                        offered = msg
                            .ray()
                            .zip(msg.hops().last())
                            .map(|(r, h)| (*r, h.tag, from));
                        assert_eq!((d_unknown, d_accepted, d_own), (0, 0, 0));
                        if msg.is_empty() {
                            assert_eq!(d_ignored, 0, "the empty message is not counted");
                        } else {
                            assert_eq!(d_ignored, 1);
                            assert_ne!(state, WaveState::Inactive, "ignored while inactive");
                        }
                    }
                    Reception::Accepted => {
                        assert!(known && !own_tag && !msg.is_empty());
                        offered = msg
                            .ray()
                            .zip(msg.hops().last())
                            .map(|(r, h)| (*r, h.tag, from));
                        assert_eq!((d_unknown, d_accepted, d_ignored, d_own), (0, 1, 0, 0));
                        assert_eq!(state, WaveState::Active);
                        assert!(t <= now + self.params.wave.relay_delay, "relay at {t:?}");
                        assert!(self.node.weight(from).is_some());
                        match self.heaviest() {
                            Some(best) => assert_eq!(pref, Some(best), "not the heaviest"),
                            None => assert_eq!(pref, before.pref, "changed without a reason"),
                        }
                        accepted = Some((msg.clone(), from));
                    }
                }
            }
        }
        if accepted.is_none() {
            assert_eq!(pref, before.pref, "preference changed without a message");
        }
        // The ray of a message heard (accepted or ignored) is taken or refused by the rules of
        // `FusedNode::take_ray`: it describes the side it came from, with K sectors; its sender
        // is not followed on another side (within the switch time); and it comes from the
        // neighbour followed on this side, reaches farther, or that one fell silent.
        match offered {
            None => assert_eq!((d_rays, d_refused), (0, 0), "a ray counted without a ray"),
            Some((ray, sender, from)) => {
                let switch = self
                    .setup
                    .longest_cycle()
                    .saturating_mul(SENDER_SWITCH_CYCLES);
                let i = usize::from(from.index());
                let fits = ray.sector == from && usize::from(ray.sectors) == k;
                let elsewhere = self.held.iter().enumerate().any(|(j, h)| {
                    j != i && h.is_some_and(|h| h.sender == sender && now - h.at <= switch)
                });
                let follows = self.held[i].is_none_or(|h| {
                    h.sender == sender || ray.robots > h.ray.robots || now - h.at > switch
                });
                let take = fits && !elsewhere && follows;
                assert_eq!(
                    (d_rays, d_refused),
                    if take { (1, 0) } else { (0, 1) },
                    "ray {ray:?} from {from:?} by {sender:?}, fits {fits}, elsewhere {elsewhere}, \
                     follows {follows}, held {:?}",
                    self.held
                );
                if take {
                    self.held[i] = Some(HeldRay {
                        ray,
                        at: now,
                        sender,
                    });
                }
            }
        }
        assert_eq!(self.node.votes(), votes_of(&self.held, pref, k), "votes");

        // Transmissions.
        let pushed = (d_init + d_relayed) as usize;
        let lost = d_tlost as usize;
        assert!(lost <= self.outbox + pushed);
        let queued = self.outbox + pushed - lost;
        assert!(queued <= OUTBOX, "{queued} messages queued");
        if lost > 0 {
            assert_eq!(
                queued, OUTBOX,
                "a message was dropped from a queue not full"
            );
        }
        let reading = self.node.reading();
        let tag = self.tag;
        let own = Hop {
            reading,
            pref: before.pref,
            tag,
        };
        let cap = usize::from(self.params.max_hops).max(1);
        // Payload budget of a transmission: 25 bytes, and that of `max_hops` plain hops.
        let budget = PAYLOAD_BUDGET.min(1 + 2 * cap);
        let ray_len = 7 + k;
        // Hops a transmission keeps beside its ray: as many as fit the budget, at least one.
        let room = (budget.saturating_sub(1 + ray_len) / 2).max(1);
        let ray_ok = |m: &Message, s: Sector| {
            let r = m.ray().expect("every transmission carries a ray");
            [&before.held, &held_after_expiry].iter().any(|held| {
                ray_matches(
                    r,
                    s,
                    k,
                    reading,
                    before.pref,
                    held[usize::from(s.index())].as_ref(),
                )
            })
        };
        // The relay this call made, if any, as the model expects its hops: the accepted
        // message without its ray, cut to `max_hops − 1` hops, the own hop appended, then as
        // many as fit beside the own ray of the side it came from; every dropped hop counted
        // in `hops_evicted` (finding 5 of README.md, fixed).
        let relayed = (d_relayed > 0).then(|| {
            let (m, from) = self
                .pending
                .clone()
                .expect("relayed without an accepted message");
            let mut hops = m.hops()[m.len().saturating_sub(cap - 1)..].to_vec();
            let cut = m.len() - hops.len();
            hops.push(own);
            let kept = hops[hops.len().saturating_sub(room)..].to_vec();
            let counted = cut + hops.len() - kept.len();
            assert_eq!(m.len() + 1 - kept.len(), counted);
            (kept, from, counted)
        });
        assert_eq!(
            d_evicted as usize,
            relayed.as_ref().map_or(0, |r| r.2),
            "hops_evicted (initiations drop none)"
        );
        // An initiation is the own hop, with the ray of a side holding the fewest robots.
        let fewest = |held: &Held| {
            (0..k)
                .map(|i| held[i].map_or(0, |h| h.ray.robots))
                .min()
                .unwrap_or(0)
        };
        let is_initiation = |m: &Message| {
            let Some(r) = m.ray() else { return false };
            m.hops() == [own]
                && [&before.held, &held_after_expiry].iter().any(|held| {
                    let i = usize::from(r.sector.index());
                    i < k
                        && held[i].map_or(0, |h| h.ray.robots) == fewest(held)
                        && ray_matches(r, r.sector, k, reading, before.pref, held[i].as_ref())
                })
        };
        let is_relay = |m: &Message| {
            relayed
                .as_ref()
                .is_some_and(|(hops, from, _)| m.hops() == hops.as_slice() && ray_ok(m, *from))
        };
        if hold {
            self.outbox = queued;
        } else {
            let mut got = Vec::new();
            while let Some(m) = self.node.poll_transmit() {
                got.push(m);
                assert!(got.len() <= OUTBOX, "poll_transmit does not run dry");
            }
            assert_eq!(got.len(), queued);
            for m in &got {
                // Every transmission encodes and fits its budget (one hop always stays), has
                // the own hop last and carries a valid ray of this robot's K sectors.
                reference::check_decoded(m);
                assert!(
                    m.len() <= cap,
                    "{} hops with max_hops {cap}: {m:?}",
                    m.len()
                );
                assert!(m.encoded_len() <= PAYLOAD_BUDGET);
                assert!(
                    m.encoded_len() <= budget || m.len() == 1,
                    "{m:?} over {budget} bytes"
                );
                assert_eq!(m.hops().last().map(|h| h.tag), Some(tag), "{m:?}");
                let r = m.ray().expect("a transmission without a ray");
                assert!(r.robots >= 1 && usize::from(r.sectors) == k, "{m:?}");
            }
            if self.outbox == 0 && lost == 0 {
                // Every message of this call is here, in order: each is the relay the model
                // expects or an initiation.
                assert_eq!(got.len(), pushed, "{got:?}");
                for m in &got {
                    assert!(
                        is_relay(m) || is_initiation(m),
                        "neither the relay {relayed:?} nor an initiation ({own:?}, held {:?} \
                         / {held_after_expiry:?}): {m:?}",
                        before.held
                    );
                }
                let relays = got.iter().filter(|m| is_relay(m)).count();
                assert!(relays >= d_relayed as usize, "{got:?}");
            }
            self.outbox = 0;
            self.trace.extend(got.into_iter().map(Out::Transmit));
        }
        if d_relayed > 0 {
            self.pending = None;
        }
        if let Some(m) = accepted {
            self.pending = Some(m);
        }

        // Events.
        if hold {
            self.events_clean = false;
            return;
        }
        let mut got = Vec::new();
        while let Some(e) = self.node.poll_event() {
            got.push(e);
            assert!(got.len() <= EVENT_QUEUE, "poll_event does not run dry");
        }
        if d_elost > 0 {
            assert_eq!(
                got.len(),
                EVENT_QUEUE,
                "an event was dropped from a queue not full"
            );
        }
        for e in &got {
            match *e {
                Event::State(_) => {}
                Event::Preference(p) => assert!(p.is_some() && valid(p, k), "{e:?}"),
                Event::Decided {
                    decision, votes, ..
                } => {
                    assert!(valid(decision, k), "{e:?}");
                    assert!(votes[k..].iter().all(|&v| v == 0), "{e:?}");
                    // A decision is a sector of (nearly, see SCORE_TOLERANCE) the best score.
                    if let Some(s) = decision {
                        let scores = scores_of(&votes, k);
                        let max = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                        assert!(votes[..k].iter().any(|&v| v > 0), "{e:?}");
                        assert!(
                            scores[usize::from(s.index())] >= max - SCORE_TOLERANCE,
                            "{e:?}: scores {scores:?}"
                        );
                    }
                }
            }
        }
        if self.events_clean && d_elost == 0 {
            // Every event of this call is here.
            let mut s = before.state;
            let (mut refractory, mut active, mut prefs) = (0, 0, 0);
            let mut period = before.periods;
            let mut previous = before.decision;
            for e in &got {
                match *e {
                    Event::State(next) => {
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
                    Event::Preference(p) => {
                        prefs += 1;
                        assert_eq!(p, pref);
                    }
                    Event::Decided {
                        period: p,
                        decision: d,
                        changed,
                        votes,
                    } => {
                        // Every period end of a call counts the rays left after expiry at
                        // `now`, before any ray of this call is taken.
                        period += 1;
                        assert_eq!(p, period);
                        assert_eq!(
                            votes,
                            votes_of(&held_after_expiry, before.pref, k),
                            "votes of {e:?}"
                        );
                        check_decision(&votes, k, before.pref, previous, d);
                        assert_eq!(changed, d != previous);
                        previous = d;
                    }
                }
            }
            assert_eq!(s, state, "events end in {s:?}: {got:?}");
            assert_eq!(refractory, d_init + d_relayed);
            assert_eq!(active, d_accepted);
            assert!(prefs <= 1);
            assert_eq!(prefs == 1, pref != before.pref);
            assert_eq!(period, self.node.periods());
            assert_eq!(previous, decision);
        }
        self.events_clean = true;
        self.trace.extend(got.into_iter().map(Out::Event));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::hop;
    use crate::scenario::{ParamsChoice, Start};

    #[test]
    fn decision_rule() {
        let r = Some(reference::sector(0));
        let l = Some(reference::sector(1));
        let mut v = [0u16; MAX_SECTORS];
        check_decision(&v, 2, r, l, None);
        v[0] = 2;
        v[1] = 2;
        check_decision(&v, 2, r, l, r);
        check_decision(&v, 2, None, l, l);
        check_decision(&v, 2, None, None, None);
        v[1] = 3;
        check_decision(&v, 2, r, None, l);
        // In the plane the resultant counts: with K = 8, two votes each for sectors 1 and 3
        // make sector 2 (no vote of its own) the best.
        let mut v = [0u16; MAX_SECTORS];
        v[1] = 2;
        v[3] = 2;
        check_decision(&v, 8, None, None, Some(reference::sector(2)));
        // K = 4: sectors 0 and 2 cancel, 1 wins alone.
        let v = [3, 1, 3, 0, 0, 0, 0, 0];
        check_decision(&v, 4, r, None, Some(reference::sector(1)));
    }

    #[test]
    fn rays_and_votes() {
        let ray = reference::ray_left_k2();
        let held = HeldRay {
            ray,
            at: Instant::ZERO,
            sender: reference::tag(3),
        };
        let mut h = NOTHING_HELD;
        h[1] = Some(held);
        assert_eq!(votes_of(&h, reference::sector(0).into(), 2)[..2], [3, 2]);
        let ext = ray.extended(Level(115), Some(reference::sector(0)));
        assert!(ray_matches(
            &ext,
            ray.sector,
            2,
            Level(115),
            Some(reference::sector(0)),
            Some(&held)
        ));
        assert!(!ray_matches(
            &ext,
            ray.sector,
            2,
            Level(115),
            None,
            Some(&held)
        ));
        let single = Ray::single(reference::sector(0), 2, Level(7), None).unwrap();
        assert!(ray_matches(
            &single,
            reference::sector(0),
            2,
            Level(7),
            None,
            None
        ));
        assert!(ray_is_plausible(&ray));
        assert!(!ray_is_plausible(&Ray {
            sum_sq: ray.sum_sq + 255 * u32::from(ray.sum) + 1,
            ..ray
        }));
    }

    #[test]
    fn inputs_read_back_and_a_run_decides() {
        let mut steps = vec![
            Step::drain(Action::Reading(1)),
            Step::drain(Action::Message {
                sector: 1,
                hops: vec![hop(0, None), hop(0, None)],
                ray: Some(reference::ray_left_k2()),
                time: TimeStep::Forward(3_000),
            }),
        ];
        steps.extend((0..60).map(|_| Step::drain(Action::Timeout(TimeStep::Deadline))));
        let input = Input {
            setup: Setup {
                rng_state: 5,
                rng_stream: 6,
                params: ParamsChoice::Quick {
                    sectors: 0,
                    negotiation: 0,
                    max_hops: 11,
                },
                start: Start::Zero,
            },
            tag: 3,
            steps,
        };
        assert_eq!(Input::read(&input.write()), input);
        let trace = run(&input);
        assert!(trace.contains(&Out::Reception(Reception::Accepted)));
        assert!(
            trace
                .iter()
                .any(|o| matches!(o, Out::Event(Event::Decided { period: 1, .. })))
        );
        check(&input.write());
    }
}
