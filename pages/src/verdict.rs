//! How one of our numbers is judged against a claim of the paper: one small function per kind
//! of claim ([`rate`], [`level`], [`distance`], [`trend`], [`direction`], [`walk`],
//! [`profile`], [`mechanism`]), each returning a
//! [`Verdict`].
//!
//! The rule is the same for every kind: a claim has a **reproduced band** (its value or range,
//! widened by its tolerance); ours is **reproduced** inside the band, **partly** when it lies
//! outside by at most two standard errors of our own estimate, and **not reproduced** beyond.
//! A success rate has no tolerance but sampling: it is reproduced when it is within two
//! standard errors of the paper's value or range (ours and the paper's 50 runs combined: a
//! two-sided test at about 5 %), and not reproduced beyond; so no verdict stretches more than
//! two standard errors past what the paper says.

use serde::Serialize;

/// The verdict on one claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Ours is inside the claim's band.
    Reproduced,
    /// Ours is outside the band by at most two of our standard errors.
    Partly,
    /// Ours is farther from the band.
    NotReproduced,
    /// Ours was tuned to the paper's value (a free parameter of the set-up).
    ByConstruction,
    /// The outcome turns on a rule the paper does not give; the row shows both choices.
    DependsOnUnspecifiedRule,
}

impl Verdict {
    /// Every verdict, in the order the page counts them.
    pub const ALL: [Verdict; 5] = [
        Verdict::Reproduced,
        Verdict::Partly,
        Verdict::NotReproduced,
        Verdict::ByConstruction,
        Verdict::DependsOnUnspecifiedRule,
    ];

    /// The words the page shows.
    pub fn words(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::NotReproduced => "not reproduced",
            Verdict::ByConstruction => "by construction",
            Verdict::DependsOnUnspecifiedRule => "depends on an unspecified rule",
        }
    }

    /// The weaker of the verdicts of the same claim under two placements: a claim the paper
    /// makes without naming a placement must hold under both. From strong to weak: reproduced
    /// (or by construction), partly, depends on an unspecified rule, not reproduced (a
    /// placement on which the claim fails outright decides, whatever the open rule).
    pub fn both(self, other: Verdict) -> Verdict {
        let rank = |v: Verdict| match v {
            Verdict::Reproduced | Verdict::ByConstruction => 0,
            Verdict::Partly => 1,
            Verdict::DependsOnUnspecifiedRule => 2,
            Verdict::NotReproduced => 3,
        };
        if rank(other) > rank(self) {
            other
        } else {
            self
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.words())
    }
}

/// A claim run under both choices of a rule the paper leaves open: reproduced if it holds under
/// both, not if under neither, and otherwise it depends on the rule.
pub fn open_rule(holds: [bool; 2]) -> Verdict {
    match holds {
        [true, true] => Verdict::Reproduced,
        [false, false] => Verdict::NotReproduced,
        _ => Verdict::DependsOnUnspecifiedRule,
    }
}

/// Ours against the band `[lo, hi]`: inside, at most two standard errors `se` outside, or
/// farther.
pub fn banded(ours: f64, (lo, hi): (f64, f64), se: f64) -> Verdict {
    let off = (lo - ours).max(ours - hi).max(0.0);
    if !ours.is_finite() {
        Verdict::NotReproduced
    } else if off <= 1e-9 {
        Verdict::Reproduced
    } else if off <= 2.0 * se + 1e-9 {
        Verdict::Partly
    } else {
        Verdict::NotReproduced
    }
}

/// The binomial standard error of a rate `p` over `runs` runs, at least one run's worth (at a
/// rate of 0 or 1 it would vanish).
pub fn rate_se(p: f64, runs: u32) -> f64 {
    let n = f64::from(runs.max(1));
    (p * (1.0 - p) / n).sqrt().max(1.0 / n)
}

/// Runs per point of the paper's sweeps: "Each data is the result of 50 independent
/// simulations" (the captions of its sweep figures; a test finds the words in the LaTeX).
pub const PAPER_RUNS: u32 = 50;

/// A success rate of `successes` in `runs` against the paper's `[lo, hi]` (lo = hi for one
/// value), measured over `paper_runs` runs (`None`: an exact value, such as the share of
/// uniform directions). Reproduced within two standard errors of the band, ours and the
/// paper's sampling combined (binomial, each at least one run's worth); not reproduced beyond.
pub fn rate(successes: u32, runs: u32, (lo, hi): (f64, f64), paper_runs: Option<u32>) -> Verdict {
    let ours = f64::from(successes) / f64::from(runs.max(1));
    let near = ours.clamp(lo, hi);
    let paper_se = paper_runs.map_or(0.0, |n| rate_se(near, n));
    let se = (rate_se(ours, runs).powi(2) + paper_se.powi(2)).sqrt();
    if (ours - near).abs() <= 2.0 * se + 1e-9 {
        Verdict::Reproduced
    } else {
        Verdict::NotReproduced
    }
}

/// A level (a mean over runs, with standard error `se`) against the paper's `paper`, within
/// the relative tolerance `rel` (0.1: 10 %).
pub fn level(ours: f64, se: f64, paper: f64, rel: f64) -> Verdict {
    let tol = (paper * rel).abs();
    banded(ours, (paper - tol, paper + tol), se)
}

/// A distance `(d, s.e.)` (interpolated on a grid finer than `tol`) against the paper's
/// `[lo, hi]` (lo = hi for one value) within `tol`; none found is not reproduced.
pub fn distance(ours: Option<(f64, f64)>, (lo, hi): (f64, f64), tol: f64) -> Verdict {
    ours.map_or(Verdict::NotReproduced, |(d, se)| {
        banded(d, (lo - tol, hi + tol), se)
    })
}

/// What a trend claim says about the sign of the slope.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sign {
    /// The quantity grows with x.
    Rises,
    /// The quantity shrinks with x.
    Falls,
}

/// A trend: the fitted slope's 95 % interval (`slope ± ci`) lies wholly on the claimed side of
/// zero, and the claim's second condition `also` holds (linearity, or a fall beyond the level
/// measured elsewhere). Reproduced if both, partly if only the slope, not otherwise.
pub fn trend(slope: f64, ci: f64, sign: Sign, also: bool) -> Verdict {
    let signed = match sign {
        Sign::Rises => slope - ci > 0.0,
        Sign::Falls => slope + ci < 0.0,
    };
    match (signed, also) {
        (true, true) => Verdict::Reproduced,
        (true, false) => Verdict::Partly,
        _ => Verdict::NotReproduced,
    }
}

/// A walk after arrival from the growth per period of the mean squared displacement along the
/// two axes (`(slope, 95 % half-width)`, least squares against the lag), by one test at the
/// 95 % level for both claims, no round factor: the interval of the difference of the two
/// growths (half-width √(h₁² + h₂²)). Along one axis (`dims` 1): the second axis's growth has
/// its interval above zero and exceeds the first's (the difference's interval above zero);
/// in both dimensions (`dims` 2): both intervals above zero and the difference's interval
/// containing zero (a diffusion in two dimensions is the same along both). Reproduced or not:
/// there is no band to be near.
pub fn walk(across: (f64, f64), along: (f64, f64), dims: u8) -> Verdict {
    let grows = |s: (f64, f64)| s.0 - s.1 > 0.0;
    let diff = (along.0 - across.0, across.1.hypot(along.1));
    let holds = match dims {
        1 => grows(along) && grows(diff),
        _ => grows(across) && grows(along) && diff.0.abs() <= diff.1,
    };
    if holds {
        Verdict::Reproduced
    } else {
        Verdict::NotReproduced
    }
}

/// A profile's mean alignments `(value, s.e.)` toward the claimed target, every one of which
/// should be at least `level`: the worst point decides ([`banded`] on `[level, 1]`).
pub fn profile(points: &[(f64, f64)], level: f64) -> Verdict {
    points
        .iter()
        .map(|&(m, se)| banded(m, (level, 1.0), se))
        .max_by_key(|v| Verdict::ALL.iter().position(|w| w == v))
        .unwrap_or(Verdict::NotReproduced)
}

/// A mechanism: reproduced if the effect shows without it and not with it.
pub fn mechanism(without: bool, with: bool) -> Verdict {
    if without && !with {
        Verdict::Reproduced
    } else {
        Verdict::NotReproduced
    }
}

/// What a direction claim says the arrows do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Heading {
    /// Every arrow points at the target: at least `share` of them inside the cone.
    Toward {
        /// The least share inside the cone.
        share: f64,
    },
    /// The arrows point anywhere: a share inside the cone of `cone / 180°`, as uniform
    /// directions would give.
    Random,
}

/// The half-angle of the cone around the target direction inside which an arrow counts as
/// pointing at it, degrees.
pub const CONE_DEG: f64 = 45.0;

/// The least share of the arrows inside the cone for a claim that every arrow points at the
/// target.
pub const TOWARD_SHARE: f64 = 0.95;

/// `inside` of `n` arrows inside the ±[`CONE_DEG`] cone, against the claim `heading`. Toward:
/// the band is `[share, 1]`; random: the band is the uniform share (1/4) widened by two
/// binomial standard errors.
pub fn direction(inside: usize, n: usize, heading: Heading) -> Verdict {
    let runs = u32::try_from(n).unwrap_or(u32::MAX);
    let k = u32::try_from(inside).unwrap_or(u32::MAX);
    let f = f64::from(k) / f64::from(runs.max(1));
    match heading {
        Heading::Toward { share } => banded(f, (share, 1.0), rate_se(f, runs)),
        Heading::Random => rate(k, runs, (CONE_DEG / 180.0, CONE_DEG / 180.0), None),
    }
}

#[cfg(test)]
mod tests {
    use super::Verdict::*;
    use super::*;

    #[test]
    fn partly_is_at_most_two_of_our_standard_errors_beyond_the_band() {
        assert_eq!(banded(1.0, (0.0, 1.0), 0.1), Reproduced);
        assert_eq!(banded(1.2, (0.0, 1.0), 0.1), Partly);
        assert_eq!(banded(1.21, (0.0, 1.0), 0.1), NotReproduced);
        assert_eq!(banded(-0.15, (0.0, 1.0), 0.1), Partly);
        assert_eq!(banded(f64::NAN, (0.0, 1.0), 0.1), NotReproduced);
    }

    #[test]
    fn a_walk_along_one_axis_is_not_one_in_two() {
        let flat = (0.0003, 0.0004);
        let grows = (0.1, 0.003);
        assert_eq!(walk(flat, grows, 1), Reproduced);
        assert_eq!(walk(flat, grows, 2), NotReproduced);
        // Both grow, at rates the intervals cannot tell apart: two dimensions.
        assert_eq!(walk((0.098, 0.004), grows, 2), Reproduced);
        // Both grow, one five times faster (the gradient's walk): not the same in both.
        assert_eq!(walk((0.02, 0.001), grows, 2), NotReproduced);
        // By the same test the gradient's walk is one along y.
        assert_eq!(walk((0.02, 0.001), grows, 1), Reproduced);
        assert_eq!(walk((0.098, 0.004), grows, 1), NotReproduced);
        assert_eq!(walk(flat, (0.0, 0.01), 1), NotReproduced);
    }

    #[test]
    fn a_profile_is_judged_by_its_worst_point() {
        assert_eq!(profile(&[(0.9, 0.01), (0.6, 0.05)], 0.5), Reproduced);
        assert_eq!(profile(&[(0.9, 0.01), (0.45, 0.05)], 0.5), Partly);
        assert_eq!(profile(&[(0.9, 0.01), (-0.5, 0.05)], 0.5), NotReproduced);
        assert_eq!(mechanism(true, false), Reproduced);
        assert_eq!(mechanism(true, true), NotReproduced);
    }

    #[test]
    fn rates_are_reproduced_within_two_combined_standard_errors_and_never_partly() {
        let paper = Some(PAPER_RUNS);
        // A claimed 1.0 over 50 runs each: 47 of 50 (0.94) is 0.06 off; ours 0.034, the
        // paper's one run's worth 0.02: combined 0.039, two of them 0.079.
        assert_eq!(rate(47, 50, (1.0, 1.0), paper), Reproduced);
        // 45 of 50 (0.90): 0.10 off, combined s.e. 0.047: beyond two.
        assert_eq!(rate(45, 50, (1.0, 1.0), paper), NotReproduced);
        // 25 %: 8 of 50 (0.16) is 0.09 off; combined s.e. 0.079.
        assert_eq!(rate(8, 50, (0.25, 0.25), paper), Reproduced);
        assert_eq!(rate(1, 50, (0.25, 0.25), paper), NotReproduced);
        // A range: inside; 20 runs below 85–100 %: 0.65 is 0.20 off, combined s.e. 0.12.
        assert_eq!(rate(45, 50, (0.85, 1.0), paper), Reproduced);
        assert_eq!(rate(13, 20, (0.85, 1.0), paper), Reproduced);
        // 0.55 is 0.30 off: not, where the old rule (two s.e. of the paper's, then two of
        // ours: about four in all) said partly.
        assert_eq!(rate(11, 20, (0.85, 1.0), paper), NotReproduced);
        assert_eq!(rate(10, 20, (0.85, 1.0), paper), NotReproduced);
        // An exact value (uniform directions) has no sampling of its own.
        assert_eq!(rate(10, 42, (0.25, 0.25), None), Reproduced);
    }

    #[test]
    fn the_paper_ran_fifty_runs_per_point() {
        let text = crate::paper::plain(crate::paper::LATEX);
        assert!(text.contains("Each data is the result of 50 independent simulations"));
        assert!(text.contains("For each distance we conducted 50 independent simulations"));
        assert_eq!(PAPER_RUNS, 50);
    }

    #[test]
    fn levels_and_distances_have_their_tolerances() {
        assert_eq!(level(4.6, 0.05, 4.5, 0.1), Reproduced);
        // The sharp plateau: 5.1 with a small s.e. is far outside 4.05–4.95.
        assert_eq!(level(5.1, 0.03, 4.5, 0.1), NotReproduced);
        assert_eq!(level(5.1, 0.1, 4.5, 0.1), Partly);
        assert_eq!(distance(Some((7.0, 0.1)), (7.0, 7.5), 0.25), Reproduced);
        assert_eq!(distance(Some((3.6, 0.1)), (4.0, 4.0), 0.25), Partly);
        assert_eq!(distance(Some((3.0, 0.1)), (4.0, 4.0), 0.25), NotReproduced);
        assert_eq!(distance(None, (4.0, 4.0), 0.25), NotReproduced);
    }

    #[test]
    fn trends_need_the_whole_interval_on_the_claimed_side() {
        assert_eq!(trend(-3.2, 0.5, Sign::Falls, true), Reproduced);
        assert_eq!(trend(-3.2, 0.5, Sign::Falls, false), Partly);
        assert_eq!(trend(-0.2, 0.5, Sign::Falls, true), NotReproduced);
        assert_eq!(trend(0.3, 0.1, Sign::Rises, true), Reproduced);
    }

    #[test]
    fn directions_count_the_cone() {
        assert_eq!(
            direction(70, 70, Heading::Toward { share: 0.95 }),
            Reproduced
        );
        // 60 of 63 = 0.952.
        assert_eq!(
            direction(60, 63, Heading::Toward { share: 0.95 }),
            Reproduced
        );
        assert_eq!(
            direction(48, 63, Heading::Toward { share: 0.95 }),
            NotReproduced
        );
        // Uniform directions put a quarter in a ±45° cone.
        assert_eq!(direction(10, 42, Heading::Random), Reproduced);
        assert_eq!(direction(30, 42, Heading::Random), NotReproduced);
    }

    #[test]
    fn both_placements_give_the_weaker_verdict() {
        assert_eq!(Reproduced.both(Reproduced), Reproduced);
        assert_eq!(Reproduced.both(NotReproduced), NotReproduced);
        assert_eq!(Reproduced.both(Partly), Partly);
        assert_eq!(NotReproduced.both(Partly), NotReproduced);
        assert_eq!(NotReproduced.both(NotReproduced), NotReproduced);
        assert_eq!(DependsOnUnspecifiedRule.both(NotReproduced), NotReproduced);
        assert_eq!(
            Reproduced.both(DependsOnUnspecifiedRule),
            DependsOnUnspecifiedRule
        );
        assert_eq!(open_rule([true, false]), DependsOnUnspecifiedRule);
        assert_eq!(open_rule([false, false]), NotReproduced);
        assert_eq!(open_rule([true, true]), Reproduced);
        assert_eq!(
            DependsOnUnspecifiedRule.words(),
            "depends on an unspecified rule"
        );
    }
}
