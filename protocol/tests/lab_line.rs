//! Four robots in a line, wired directly (no emulator): the paper's six light patterns and the
//! alternating experiment, decided by the real nodes through real frames.

use protocol::lab::{LabPattern, PAPER};
use protocol::line::{Happening, Line};
use protocol::{
    Deframer, Duration, FusedNode, Instant, Level, Message, Params, Reception, Sector, Tag,
    WaveState, encode,
};
use rand_pcg::Pcg32;

const L: Option<Sector> = Some(Sector::LEFT);
const R: Option<Sector> = Some(Sector::RIGHT);

/// The lab pattern `lights` (one of the paper's six, [`PAPER`]).
fn paper(lights: &str) -> LabPattern {
    LabPattern::find(lights).expect("one of the paper's patterns")
}

/// Lit robots read 1, dark ones 0.
fn readings(pattern: &LabPattern) -> [Level; 4] {
    pattern.levels(Level(1), Level(0))
}

fn line(pattern: &LabPattern, seed: u64) -> Line<Pcg32, 4> {
    let rngs = core::array::from_fn(|i| Pcg32::new(seed, 2 * i as u64 + 1));
    Line::new(Params::robots(), readings(pattern), rngs).unwrap()
}

/// Two negotiation periods of the longest cycles: every robot has decided at least twice.
const TWO_PERIODS: Instant = Instant::from_secs(2 * 10 * 70 + 1);

#[test]
fn six_lab_patterns_give_the_papers_decisions() {
    for seed in 0..20 {
        for p in PAPER {
            let (pattern, expected) = (p.lights, p.expected());
            let mut l = line(&p, seed);
            l.run_until(TWO_PERIODS, |_, _, _| {});
            assert_eq!(
                l.decisions(),
                expected,
                "pattern {pattern}, replay with seed {seed}"
            );
            for n in l.nodes() {
                assert!(n.periods() >= 2);
            }
        }
    }
}

#[test]
fn the_first_decisions_are_already_right() {
    for seed in 0..20 {
        for p in PAPER {
            let (pattern, expected) = (p.lights, p.expected());
            let mut l = line(&p, seed);
            let mut first = [None; 4];
            l.run_until(TWO_PERIODS, |_, i, h| {
                if let Happening::Event(protocol::Event::Decided {
                    period: 1,
                    decision,
                    ..
                }) = h
                {
                    first[i] = Some(decision);
                }
            });
            assert_eq!(
                first,
                expected.map(Some),
                "pattern {pattern}, replay with seed {seed}"
            );
        }
    }
}

#[test]
fn mirrored_pattern_makes_the_swarm_switch() {
    for seed in 0..10 {
        let mut l = line(&paper("1000"), seed);
        l.run_until(TWO_PERIODS, |_, _, _| {});
        assert_eq!(l.decisions(), [L; 4], "seed {seed}");
        l.set_readings(readings(&paper("0001")));
        // One period may straddle the switch; the next one is all after it.
        l.run_until(TWO_PERIODS + Duration::from_secs(2 * 10 * 70), |_, _, _| {});
        assert_eq!(l.decisions(), [R; 4], "replay with seed {seed}");
    }
}

/// What the [`Wired`] line reports: unlike [`Line`], it shows every reception too.
#[derive(Debug)]
enum Seen<'a> {
    /// Robot `by` broadcast `m`.
    Sent { by: usize, m: &'a Message },
    /// Robot `by` was handed a message robot `from` sent; `state` is its wave state once
    /// everything due at that instant was done, just before the message.
    Heard {
        by: usize,
        from: usize,
        state: WaveState,
        got: Reception,
    },
}

/// `N` robots wired as [`Line`] wires them (same framing, tags, RNGs, order of service), but
/// the test sees what every robot made of every message and in which state it was.
/// `the_wired_line_runs_as_line_does` checks that it sends exactly what [`Line`] sends.
struct Wired<const N: usize> {
    nodes: [FusedNode; N],
    deframers: [[Deframer; 2]; N],
    rngs: [Pcg32; N],
}

impl<const N: usize> Wired<N> {
    fn new(params: Params, readings: [Level; N], mut rngs: [Pcg32; N]) -> Self {
        let nodes = core::array::from_fn(|i| {
            let tag = Tag::from_id(i as u16);
            let mut n = FusedNode::new(params, tag, Instant::ZERO, &mut rngs[i]).unwrap();
            n.handle_reading(readings[i]);
            n
        });
        Wired {
            nodes,
            deframers: core::array::from_fn(|_| [Deframer::new(), Deframer::new()]),
            rngs,
        }
    }

    fn run_until(&mut self, end: Instant, mut observe: impl FnMut(Instant, Seen<'_>)) {
        loop {
            let next = (0..N).map(|i| (self.nodes[i].poll_timeout(), i)).min();
            let Some((t, first)) = next.filter(|&(t, _)| t <= end) else {
                return;
            };
            self.nodes[first].handle_timeout(t, &mut self.rngs[first]);
            let mut dirty = [false; N];
            dirty[first] = true;
            while let Some(i) = dirty.iter().position(|&d| d) {
                dirty[i] = false;
                while self.nodes[i].poll_event().is_some() {}
                while let Some(m) = self.nodes[i].poll_transmit() {
                    observe(t, Seen::Sent { by: i, m: &m });
                    let frame = encode(&m).unwrap();
                    let left = i.checked_sub(1).map(|j| (j, Sector::RIGHT));
                    let right = (i + 1 < N).then_some((i + 1, Sector::LEFT));
                    for (j, from) in left.into_iter().chain(right) {
                        let side = usize::from(from == Sector::RIGHT);
                        for msg in self.deframers[j][side].frames(&frame).flatten() {
                            // `handle_message` does this first itself; done here, the state
                            // read is the one the message meets.
                            self.nodes[j].handle_timeout(t, &mut self.rngs[j]);
                            let state = self.nodes[j].state();
                            let got =
                                self.nodes[j].handle_message(t, from, &msg, &mut self.rngs[j]);
                            observe(
                                t,
                                Seen::Heard {
                                    by: j,
                                    from: i,
                                    state,
                                    got,
                                },
                            );
                        }
                        dirty[j] = true;
                    }
                }
            }
        }
    }
}

/// Four robots with distinct readings, as in the lab.
fn wired(params: Params, seed: u64) -> Wired<4> {
    let rngs = core::array::from_fn(|i| Pcg32::new(seed, i as u64));
    Wired::new(params, [10, 20, 30, 40].map(Level), rngs)
}

#[test]
fn the_wired_line_runs_as_line_does() {
    for seed in [99, 7] {
        let end = Instant::from_secs(1800);
        let mut want = Vec::new();
        let rngs = core::array::from_fn(|i| Pcg32::new(seed, i as u64));
        let mut l: Line<Pcg32, 4> =
            Line::new(Params::robots(), [10, 20, 30, 40].map(Level), rngs).unwrap();
        l.run_until(end, |t, i, h| {
            if let Happening::Sent(m) = h {
                want.push((t, i, m.clone()));
            }
        });
        let mut got = Vec::new();
        let mut w = wired(Params::robots(), seed);
        w.run_until(end, |t, s| {
            if let Seen::Sent { by, m } = s {
                got.push((t, by, m.clone()));
            }
        });
        assert!(want.len() > 100);
        assert_eq!(got, want, "seed {seed}");
    }
}

#[test]
fn an_initiator_is_never_reactivated_by_its_own_wave() {
    // With a hop capacity of 1 every relay carries the relaying robot's hop alone: the
    // neighbours' relays of a robot's wave (its echoes) never hold its tag, so the own-tag rule
    // cannot stop them. Only the refractory time can.
    let mut params = Params::robots();
    params.max_hops = 1;
    for seed in [99, 3, 17] {
        let mut w = wired(params, seed);
        // The harness follows every wave: an initiation starts one, a relay carries on the one
        // the robot accepted. Per robot: the wave of its last transmission, the wave it accepted
        // and will relay, and every wave it took part in (with the wave's initiator).
        let mut waves = 0usize;
        let mut initiator = Vec::new();
        let mut sending = [usize::MAX; 4];
        let mut accepted: [Option<usize>; 4] = [None; 4];
        let mut joined: [Vec<usize>; 4] = Default::default();
        let (mut echoes, mut initiator_echoes, mut initiations) = (0, 0, 0);
        w.run_until(Instant::from_secs(3600), |t, s| match s {
            Seen::Sent { by, m } => {
                assert_eq!(m.len(), 1);
                let wave = accepted[by].take().unwrap_or_else(|| {
                    initiations += 1;
                    initiator.push(by);
                    waves += 1;
                    waves - 1
                });
                sending[by] = wave;
                joined[by].push(wave);
            }
            Seen::Heard {
                by,
                from,
                state,
                got,
            } => {
                let wave = sending[from];
                if joined[by].contains(&wave) {
                    // A neighbour relaying a wave this robot sent on: its own wave, back.
                    echoes += 1;
                    if initiator[wave] == by {
                        initiator_echoes += 1;
                    }
                    assert_eq!(
                        (state, got),
                        (WaveState::Refractory, Reception::Ignored),
                        "robot {by} hears wave {wave} (started by robot {}) again from robot \
                         {from} at {t:?}, seed {seed}",
                        initiator[wave]
                    );
                }
                if got == Reception::Accepted {
                    accepted[by] = Some(wave);
                }
            }
        });
        assert!(initiations > 150, "{initiations}");
        // End robots' initiations echo once, middle ones' twice.
        assert!(initiator_echoes > initiations, "{initiator_echoes}");
        assert!(
            echoes > initiator_echoes,
            "relaying robots hear their echo too"
        );
        for n in &w.nodes {
            assert_eq!(n.stats().own_tag, 0, "the own-tag rule had no part in it");
            assert!(n.wave_stats().ignored > 0);
        }
    }
}

#[test]
fn own_tag_drops_happen_only_while_refractory() {
    // Distinct readings per robot: a message carrying one robot's reading twice means that
    // robot joined the same wave twice.
    for seed in [99, 3, 17] {
        let mut w = wired(Params::robots(), seed);
        let mut drops = [0u32; 4];
        let mut sent = 0;
        w.run_until(Instant::from_secs(3600), |t, s| match s {
            Seen::Sent { m, .. } => {
                sent += 1;
                let mut seen = [false; 256];
                for hop in m.hops() {
                    let r = usize::from(hop.reading.0);
                    assert!(!seen[r], "a robot appears twice in {m:?}");
                    seen[r] = true;
                    // Robot i has tag i: tags identify the robots just as well.
                    let t = usize::from(hop.tag.index());
                    assert_eq!(r, 10 * (t + 1), "robot {t}'s tag on another's hop: {m:?}");
                }
            }
            Seen::Heard { by, state, got, .. } => {
                if got == Reception::OwnTag {
                    drops[by] += 1;
                    assert_eq!(
                        state,
                        WaveState::Refractory,
                        "robot {by} dropped a message by its tag at {t:?}, seed {seed}"
                    );
                }
            }
        });
        assert!(sent > 200, "{sent}");
        for (i, n) in w.nodes.iter().enumerate() {
            // The counter counts exactly these drops, and there are some: the echoes of its own
            // relays and initiations.
            assert_eq!(n.stats().own_tag, drops[i], "robot {i}, seed {seed}");
            assert!(drops[i] > 20, "robot {i}: {drops:?}");
        }
        for d in w.deframers.iter().flatten() {
            assert_eq!(d.stats().errors(), 0);
        }
    }
}

#[test]
fn same_seed_same_run() {
    let trace = |seed| {
        let mut l = line(&paper("1100"), seed);
        let mut out = String::new();
        l.run_until(Instant::from_secs(1500), |t, i, h| {
            out += &format!("{} {i} {h:?}\n", t.as_millis());
        });
        out
    };
    assert_eq!(trace(5), trace(5));
    assert_ne!(trace(5), trace(6));
}

#[test]
fn noisy_sensors_still_give_the_papers_decisions_every_period() {
    use rand::Rng;
    // Lit 200, dark 30, each reading off by up to ±10, re-drawn every second: a uniform side
    // has a small but positive diversity, so preferences must not flip on one message.
    for seed in 0..10 {
        for p in PAPER {
            let (pattern, expected) = (p.lights, p.expected());
            let mut l = line(&p, seed);
            let mut noise = Pcg32::new(seed, 1000);
            let mut decided = [0u32; 4];
            let mut t = 0;
            while t < 3 * 10 * 70 + 1 {
                let lit = p.lit();
                l.set_readings(
                    lit.map(|b| {
                        Level((if b { 200 } else { 30 }) + noise.random_range(0..=20) - 10)
                    }),
                );
                t += 1;
                l.run_until(Instant::from_secs(t), |_, i, h| {
                    if let Happening::Event(protocol::Event::Decided {
                        decision, period, ..
                    }) = h
                    {
                        assert_eq!(
                            decision, expected[i],
                            "pattern {pattern}, robot {i}, period {period}, replay with seed {seed}"
                        );
                        decided[i] += 1;
                    }
                });
            }
            assert!(decided.iter().all(|&d| d >= 3), "{decided:?}");
        }
    }
}
