//! The types of the claims' table ([`super::CLAIMS`]): which claim ([`Id`]), how it is judged
//! ([`Kind`]), the paper's value ([`Value`]) and range ends ([`Ends`]), the figure it is drawn
//! on ([`Figure`]), and the row itself ([`Claim`]).

use crate::paper::{Fig, Sec};

/// Which claim a row is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Id {
    /// Sharp border: success 1.0 within 2.5 R.
    SharpNear,
    /// Sharp border: success falls beyond 2.5 R.
    SharpFar,
    /// Sharp border: mean success time falls linearly toward the border.
    SharpTime,
    /// Sharp border: the average diversity at t = 0.
    SharpStart,
    /// Gradient: the average diversity at t = 0.
    GradientStart,
    /// Sharp border: periods until the swarm arrives (one run).
    SharpArrival,
    /// Gradient: periods until the swarm's diversity saturates (one run).
    GradientArrival,
    /// Sharp border: the diversity plateau.
    SharpPlateau,
    /// Gradient: the diversity plateau.
    GradientPlateau,
    /// Sharp map: every arrow within 2.5 R points at the border.
    SharpMapNear,
    /// Sharp map: random beyond 2.5 R.
    SharpMapFar,
    /// Gradient: success 85–100 % for −2 ≤ x < 2.33.
    GradientMid,
    /// Gradient: success 25 % at x = −4.
    GradientFar,
    /// Gradient: success falls beyond x = −2.
    GradientFall,
    /// Gradient: the mean success time against the start, as the text words it.
    GradientTime,
    /// Gradient map: every arrow between −2.2 and 2.2 points to +x.
    GradientMapNear,
    /// Gradient map: random beyond 2.2.
    GradientMapFar,
    /// Gradient map: random for x < −2.2.
    GradientMapLeft,
    /// Sharp border: the farthest start from which the first move heads for the border.
    SharpEdge,
    /// Gradient: the same.
    GradientEdge,
    /// The text's cloud: the distance beyond which the swarm no longer heads for it.
    CloudLimit,
    /// The text's cloud: inside, the swarm heads out toward its border.
    CloudOutward,
    /// The text's cloud: between d ≈ 4 and 7 the swarm moves toward it.
    CloudToward,
    /// The caption's cloud: the distance beyond which the swarm no longer heads for it.
    CaptionLimit,
    /// The discussion: on a random field a line's swarm moves along its axis.
    ShapesLine,
    /// The discussion: on a random field a cross's swarm moves along its four arms.
    ShapesCross,
    /// Sharp border: after arrival the swarm walks along the border (a 1D random walk).
    SharpWalk,
    /// Gradient: on the ramp the swarm diffuses in both dimensions.
    GradientWalk,
    /// The conclusion: the steeper the gradient, the better the swarm performs.
    Steeper,
    /// The caption's cloud: for d ≲ 7.5 the swarm moves toward the border.
    CaptionToward,
    /// The refractory state keeps a wave from flooding the swarm.
    Refractory,
    /// Every agent initiates at least once per cycle (§2.1).
    Initiations,
    /// Indecision points get rarer as the swarm grows (§5).
    Indecision,
    /// The robots' lab experiment (§4), from the lab suite's file.
    Lab,
}

/// How a claim is judged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// A success rate: the value or range widened by two binomial standard errors.
    Rate,
    /// A level (a mean over runs) within a relative tolerance.
    Level {
        /// 0.1: within 10 %.
        rel: f64,
    },
    /// A distance within an absolute tolerance (R), found on a grid finer than it.
    Distance {
        /// ± R.
        tol: f64,
    },
    /// A trend along x: the slope's 95 % interval on the claimed side of zero, and a second
    /// condition (linearity, or a fall against the level elsewhere).
    Trend,
    /// Directions: the share of arrows inside a ±45° cone around the target.
    Direction {
        /// True: every arrow points at the target (at least 95 % in the cone); false: random
        /// (a quarter in the cone, as uniform directions give).
        toward: bool,
    },
    /// A value we tuned a free parameter of our set-up to.
    Tuned,
    /// The outcome may turn on a rule the paper does not give: run with both choices.
    OpenRule,
    /// The walk after arrival: the mean squared displacement grows along one axis only
    /// (`dims` 1) or along both (`dims` 2).
    Walk {
        /// 1: along the border; 2: in both dimensions.
        dims: u8,
    },
    /// A radial profile's mean alignment toward a target at least 0.5 at every distance of
    /// the claim's range.
    Profile,
    /// A mechanism: without it the effect appears, with it it does not.
    Mechanism,
}

/// The paper's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// One number.
    At(f64),
    /// A range.
    Range(f64, f64),
    /// Different numbers in different places of the paper (text, caption), with where.
    Either(&'static [(f64, &'static str)]),
    /// No number: a shape or a trend, in words.
    Words,
}

/// Which ends of a claim's range belong to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ends {
    /// Neither: `lo < x < hi`.
    Open,
    /// The low end: `lo ≤ x < hi`.
    LowClosed,
    /// Both: `lo ≤ x ≤ hi` (a single point when they are equal).
    Closed,
}

/// A figure of the reproduction a claim is drawn on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// The success sweep of a built-in scenario (Figs. 6, 9).
    Sweep(&'static str),
    /// The direction map of a built-in scenario (Figs. 7, 10, 11).
    Map(&'static str),
    /// The averaged time course (Figs. 5b, 8b).
    Course(&'static str),
    /// A cloud's radial heading profile.
    Profile(&'static str),
    /// The heading of the first move against the start, both fields.
    Extent,
}

/// One claim of the paper.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Claim {
    /// Which claim.
    pub id: Id,
    /// Where in the paper: section, figure, caption or text.
    pub source: &'static str,
    /// The sections the claim is made in: every `§` of `source` is one of these, and each
    /// quote is in one of them (tests against the LaTeX source, [`crate::paper`]).
    pub secs: &'static [Sec],
    /// The figures it is about: every figure number of the claim's text is one of these.
    pub figs: &'static [Fig],
    /// The paper's own words the claim rests on (LaTeX as [`crate::paper::plain`] reads it): each
    /// is found in the claim's sections, and every number of the paper's value is in one.
    pub quotes: &'static [&'static str],
    /// What is measured (the table's first column).
    pub quantity: &'static str,
    /// The paper's value as the table shows it.
    pub paper: &'static str,
    /// The paper's value as a number, where it has one.
    pub value: Value,
    /// The x or distance range (R) the claim covers, if it covers one.
    pub over: Option<(f64, f64)>,
    /// Which ends of `over` belong to it.
    pub ends: Ends,
    /// How ours is judged.
    pub kind: Kind,
    /// Where it is drawn, and the mark's legend.
    pub drawn: &'static [(Figure, &'static str)],
}
