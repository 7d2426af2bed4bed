//! Decisions do not depend on the sensor's unit, gain, offset or resolution (issue 19,
//! `docs/protocol.md` §5.6).
//!
//! A robot compares diversities (variances): mapping every reading `x ↦ a·x + b` (a > 0)
//! multiplies every variance by a² and so changes no comparison. The property: lines of robots
//! wired through real frames ([`protocol::line::Line`]), rays included, under both decision
//! rules, show the same decisions at the same times and in the same order when every reading
//! is scaled by any `a = p / q` with `p, q ∈ 1..=64` and offset by any `b` that does not
//! saturate. The test runs the two lines `q·v + b₁` and `p·v + b₂` over the same base pattern
//! `v` and the same seed.

use proptest::prelude::*;
use protocol::fused::Event;
use protocol::line::{Happening, Line};
use protocol::params::DecisionRule;
use protocol::{Instant, Level, Params, Sector};
use rand_pcg::Pcg32;

/// What a run shows: every decision with its time, robot, period, votes; and every
/// preference change with its time and robot.
type Trace = Vec<(Instant, usize, Event)>;

/// Runs `N` robots with `readings` for two negotiation periods of the longest cycles.
fn run<const N: usize>(decide: DecisionRule, readings: &[u8], seed: u64) -> Trace {
    let mut params = Params::robots();
    params.decide = decide;
    let levels: [Level; N] = core::array::from_fn(|i| Level(readings[i]));
    let rngs = core::array::from_fn(|i| Pcg32::new(seed, 2 * i as u64 + 1));
    let mut line = Line::new(params, levels, rngs).unwrap();
    let mut trace = Vec::new();
    line.run_until(Instant::from_secs(2 * 10 * 70 + 1), |t, i, h| {
        if let Happening::Event(e @ (Event::Decided { .. } | Event::Preference(_))) = h {
            trace.push((t, i, e));
        }
    });
    trace
}

fn run_any(decide: DecisionRule, readings: &[u8], seed: u64) -> Trace {
    match readings.len() {
        2 => run::<2>(decide, readings, seed),
        3 => run::<3>(decide, readings, seed),
        4 => run::<4>(decide, readings, seed),
        5 => run::<5>(decide, readings, seed),
        8 => run::<8>(decide, readings, seed),
        n => panic!("no line of {n} robots here"),
    }
}

/// A base pattern of levels `0..=top` on 2, 3, 4, 5 or 8 robots.
fn pattern() -> impl Strategy<Value = Vec<u8>> {
    (prop::sample::select(vec![2usize, 3, 4, 5, 8]), 1u8..=3)
        .prop_flat_map(|(n, top)| proptest::collection::vec(0..=top, n))
}

/// `a·v + b` for every level `v`.
fn map(v: &[u8], a: u8, b: u8) -> Vec<u8> {
    v.iter().map(|&x| x * a + b).collect()
}

fn decisions(t: &Trace) -> Vec<(Instant, usize, Option<Sector>)> {
    t.iter()
        .filter_map(|&(at, i, e)| match e {
            Event::Decided { decision, .. } => Some((at, i, decision)),
            _ => None,
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Any gain p/q in [1/64, 64], any offsets that do not saturate, both rules: the same
    /// trace of decisions (time, robot, period, decision, votes) and preferences.
    #[test]
    fn any_gain_and_offset_leave_every_decision_and_its_time(
        v in pattern(),
        p in 1u8..=64,
        q in 1u8..=64,
        b in any::<u8>(),
        c in any::<u8>(),
        seed in any::<u64>(),
        adaptive in any::<bool>(),
    ) {
        let top = *v.iter().max().unwrap();
        // Offsets that keep every reading within 0..=255.
        let b = (u16::from(b) % (256 - u16::from(q) * u16::from(top))) as u8;
        let c = (u16::from(c) % (256 - u16::from(p) * u16::from(top))) as u8;
        prop_assume!(u16::from(q) * u16::from(top) + u16::from(b) <= 255);
        prop_assume!(u16::from(p) * u16::from(top) + u16::from(c) <= 255);
        let decide = if adaptive { DecisionRule::Adaptive } else { DecisionRule::Fixed };
        let one = run_any(decide, &map(&v, q, b), seed);
        let other = run_any(decide, &map(&v, p, c), seed);
        prop_assert!(!decisions(&one).is_empty());
        prop_assert_eq!(
            &one, &other,
            "pattern {:?} as {:?} and as {:?}, {:?}, seed {}",
            v, map(&v, q, b), map(&v, p, c), decide, seed
        );
    }
}

/// The paper's lab readings (g ∈ {0, 1}) and the emulator's levels (30 dark, 200 lit: gain
/// 170, offset 30) give the same trace for each of the six lab patterns.
#[test]
fn binary_and_level_readings_of_the_lab_give_the_same_trace() {
    for decide in [DecisionRule::Fixed, DecisionRule::Adaptive] {
        for lights in ["1000", "0111", "0001", "1110", "1100", "0011"] {
            let v: Vec<u8> = lights.bytes().map(|c| c - b'0').collect();
            for seed in 0..5 {
                let binary = run_any(decide, &v, seed);
                let levels = run_any(decide, &map(&v, 170, 30), seed);
                assert!(!decisions(&binary).is_empty());
                assert_eq!(binary, levels, "{lights} {decide:?} seed {seed}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// `div_to_f32` rounds the exact quotient once: where both terms are exact in `f32`, it
    /// equals IEEE division; equal fractions give equal results whatever their terms; a
    /// power-of-two factor passes through exactly.
    #[test]
    fn div_to_f32_is_correctly_rounded(
        num in 1u64..(1 << 24),
        den in 1u32..(1 << 24),
        m in 1u32..(1 << 8),
        k in 0u32..30,
    ) {
        use protocol::message::div_to_f32;
        let v = div_to_f32(num, den);
        prop_assert_eq!(v, num as f32 / den as f32);
        prop_assert_eq!(div_to_f32(num * u64::from(m), den * m), v);
        prop_assert_eq!(div_to_f32(num << 32, 1), num as f32 * 2f32.powi(32));
        prop_assert_eq!(div_to_f32(num << k, den), v * (1u64 << k) as f32);
        prop_assert_eq!(div_to_f32(0, den), 0.0);
        prop_assert_eq!(div_to_f32(num, 0), 0.0);
    }

    /// A ray's variance under `x ↦ a·x + b`: exactly a² times the original for a power of two,
    /// and within one rounding (2⁻²³ relative) of it for any other gain (`docs/protocol.md`
    /// §5.6): the sums are exact, the variance is rounded once.
    #[test]
    fn a_rays_variance_scales_by_the_gain_squared(
        readings in proptest::collection::vec(0u8..=3, 1..=40),
        a in 1u8..=64,
        b in 0u8..=63,
    ) {
        use protocol::message::Ray;
        let ray = |f: &dyn Fn(u8) -> u8| {
            let mut r = Ray::single(Sector::LEFT, 2, Level(f(readings[0])), None).unwrap();
            for &x in &readings[1..] {
                r = r.extended(Level(f(x)), None);
            }
            r
        };
        let base = ray(&|x| x);
        let mapped = ray(&|x| x * a + b);
        prop_assert_eq!(mapped.scaled_variance(), u64::from(a).pow(2) * base.scaled_variance());
        let want = f64::from(base.variance()) * f64::from(a).powi(2);
        let got = f64::from(mapped.variance());
        prop_assert!((got - want).abs() <= want * 2f64.powi(-23), "{got} vs {want}");
        if a.is_power_of_two() {
            prop_assert_eq!(got, want);
        }
    }
}
