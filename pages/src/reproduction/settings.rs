//! The numbers the page's prose states about its set-up and its rules (`settings` in the view
//! model), each read from what the runs use — the scenarios, `Params`, the verdicts' rules —
//! or, for the paper's, from its claims ([`crate::claims`]) or a quote of its LaTeX source
//! ([`SAID`], checked by the tests): none is typed into a template (issue 38).

use serde::Serialize;

use super::*;
use crate::claims::{Id, Kind, claim};
use hal_emu::world::field::Segment;
use protocol::Params;

/// A number of the paper outside its claims: the words it rests on (LaTeX as
/// [`crate::paper::plain`] reads it) and the numbers in them the page uses.
struct Said {
    #[cfg_attr(not(test), allow(dead_code))]
    quote: &'static str,
    values: &'static [f64],
}

/// The swarm's disk (section 3).
const DISK: Said = Said {
    quote: "distributed in a circular area of diameter D=6R",
    values: &[6.0],
};
/// Where the sharp border's run starts (caption of its figure).
const START: Said = Said {
    quote: "with center of the swarm at x\\approx-2.5",
    values: &[-2.5],
};
/// The caption's cloud: its radius, its levels and its noise (caption of the cloud figure).
const CAPTION_RADIUS: Said = Said {
    quote: "extends radially with a radius of r=5",
    values: &[5.0],
};
const CAPTION_LEVELS: Said = Said {
    quote: "linearly decrease from a maximum of 5 down to 0",
    values: &[5.0, 0.0],
};
const CAPTION_NOISE: Said = Said {
    quote: "is added a noise between 0 and 1",
    values: &[0.0, 1.0],
};
/// The text's cloud: X outside, and the ramp (from d, to d, X inside).
const TEXT_OUTSIDE: Said = Said {
    quote: "fluctuates around a constant value X\\in[4.5,5.5] in the yellow domain",
    values: &[4.5, 5.5],
};
const TEXT_RAMP: Said = Said {
    quote: "between d\\in[3,4.5] the quantity X linearly decreases to X\\in[-0.5,0.5]",
    values: &[3.0, 4.5, -0.5, 0.5],
};

/// Every quote of the paper this module takes a number from.
#[cfg(test)]
const SAID: [&Said; 7] = [
    &DISK,
    &START,
    &CAPTION_RADIUS,
    &CAPTION_LEVELS,
    &CAPTION_NOISE,
    &TEXT_OUTSIDE,
    &TEXT_RAMP,
];

/// `x` as Rust prints it, with a true minus sign.
fn num(x: f64) -> String {
    x.to_string().replace('-', "−")
}

/// `x` to two decimals at most, as [`num`].
fn round2(x: f64) -> String {
    num((x * 100.0).round() / 100.0)
}

/// The mid-point of the interval `v[i]`, `v[i + 1]`.
fn mid(v: &[f64], i: usize) -> String {
    num((v[i] + v[i + 1]) / 2.0)
}

/// The `i`-th segment of `scn`'s `layer`-th field layer, if it has one.
fn segment(scn: &Scenario, layer: usize, i: usize) -> Option<&Segment> {
    scn.field.layers.get(layer)?.segments.get(i)
}

/// `f` of the `i`-th segment of `scn`'s `layer`-th layer, formatted ("–" without one).
fn seg(scn: &Scenario, layer: usize, i: usize, f: fn(&Segment) -> f64) -> String {
    segment(scn, layer, i).map_or("–".into(), |s| num(f(s)))
}

/// The distinct tolerances (times `scale`) of the claims whose kind `is`, joined by " or ".
fn tolerances(is: fn(&Kind) -> bool, scale: f64) -> String {
    let mut vs: Vec<String> = crate::claims::CLAIMS
        .iter()
        .filter(|c| is(&c.kind))
        .map(|c| num(c.tolerance() * scale))
        .collect();
    vs.sort();
    vs.dedup();
    vs.join(" or ")
}

/// The paper's value of claim `id` at `k` (of [`crate::claims::Claim::values`]).
fn paper(id: Id, k: usize) -> String {
    claim(id).values().get(k).map_or("–".into(), |v| num(v.0))
}

/// The page's set-up and rules as its prose states them.
#[derive(Serialize)]
pub(super) struct Settings {
    /// The diameter of the random placement's disk, R.
    disk: String,
    /// Half the noise's width: ξ uniform in (−half, half).
    noise_half: String,
    /// Cycles per negotiation period (gathering and deciding).
    period_cycles: u16,
    /// The longest run in cycles: periods × cycles per period.
    run_cycles: u64,
    /// Where `swarm run` starts the sharp border's and the gradient's swarms: x, R.
    starts: [String; 2],
    /// The sharp border: its x, X's mean left of it and right of it.
    sharp: [String; 3],
    /// The most variance a store can have with half its readings at each of the sharp
    /// border's two means: (half their difference)².
    sharp_bound: String,
    /// The gradient: where its ramp starts, X's mean before it.
    gradient: [String; 2],
    /// The text's cloud: X's mean inside, where the ramp starts and ends (d), X's mean beyond.
    cloud: [String; 4],
    /// The caption's cloud: X's mean at the centre, at the edge and beyond, the edge (d), and
    /// the reading's noise interval (the flat layer's offset ± half the noise).
    caption: [String; 5],
    /// The flat layer the caption's cloud adds (the noise's mean).
    caption_offset: String,
    /// The main placement's swarm radius (R); how far across the border (R) it reaches from
    /// the sharp border's start and from the gradient's; the most the gradient's mean reads
    /// there (slope × that distance).
    across: [String; 4],
    /// [`SHARP_NEAR`].
    sharp_near: String,
    /// The rings of the main placement's lattice (1, 6, 12, …) when its agents are a centred
    /// hexagonal number of them that fill the paper's disk exactly (its last ring at the
    /// disk's radius); `None` otherwise.
    hex_shells: Option<Vec<usize>>,
    /// The sharp border's success distance, R.
    near: String,
    /// The gradient's success line, x.
    line: String,
    /// The robots' shortest and longest cycle, s (`Params::robots()`).
    robot_cycle: [String; 2],
    /// The bands of the claims: a level's (%), a distance's (R).
    level_pct: String,
    distance: String,
    /// The cone of a direction claim, degrees, and the share of "all" arrows that must lie in
    /// it, %.
    cone_deg: String,
    toward_pct: String,
    /// The confidence of every interval and test, %.
    confidence_pct: String,
    /// The quantiles of the courses' bands, %.
    band: [String; 2],
    /// The periods the courses' tails average.
    tail: usize,
    /// The width of a bin of the shapes' direction histograms, degrees.
    bin_deg: String,
    /// The heading the perception edge falls through.
    edge_level: String,
    /// The paper's numbers the prose quotes.
    paper: PaperSaid,
}

/// The paper's numbers the prose quotes, from its claims and [`SAID`].
#[derive(Serialize)]
struct PaperSaid {
    /// The swarm's diameter and half of it, R.
    disk: [String; 2],
    /// The caption's cloud: radius, levels from and to, noise from and to.
    caption: [String; 5],
    /// The text's cloud: X outside, the ramp's outer and inner d, X inside.
    cloud: [String; 4],
    /// Where the sharp border's run starts, x, and the period it arrives at.
    start: String,
    arrival: String,
    /// The sharp border's success: the distance within which and the rate.
    near: [String; 2],
    /// The gradient's plateau: the caption's and the text's.
    plateaus: [String; 2],
    /// The perception edges, sharp and gradient, R.
    edges: [String; 2],
    /// The text's cloud: the limit; the toward range's outer and inner d; the outward d.
    cloud_claims: [String; 4],
    /// The caption's cloud's limit.
    caption_limit: String,
    /// The gradient's success: the x range of 85–100 % and that range; the x of 25 % and
    /// that rate.
    gradient_mid: [String; 3],
    gradient_far: [String; 2],
}

fn paper_said() -> PaperSaid {
    let toward = claim(Id::CloudToward).values();
    let at = |k: usize| toward.get(k).map_or("–".into(), |v| num(v.0));
    PaperSaid {
        disk: [num(DISK.values[0]), num(DISK.values[0] / 2.0)],
        caption: [
            num(CAPTION_RADIUS.values[0]),
            num(CAPTION_LEVELS.values[0]),
            num(CAPTION_LEVELS.values[1]),
            num(CAPTION_NOISE.values[0]),
            num(CAPTION_NOISE.values[1]),
        ],
        cloud: [
            mid(TEXT_OUTSIDE.values, 0),
            num(TEXT_RAMP.values[1]),
            num(TEXT_RAMP.values[0]),
            mid(TEXT_RAMP.values, 2),
        ],
        start: num(START.values[0]),
        arrival: paper(Id::SharpArrival, 0),
        near: [
            claim(Id::SharpNear).over.map_or("–".into(), |o| num(o.1)),
            claim(Id::SharpNear).paper.to_owned(),
        ],
        plateaus: [paper(Id::GradientPlateau, 0), paper(Id::GradientPlateau, 1)],
        edges: [paper(Id::SharpEdge, 0), paper(Id::GradientEdge, 0)],
        cloud_claims: [
            paper(Id::CloudLimit, 0),
            at(1),
            at(0),
            paper(Id::CloudOutward, 0),
        ],
        caption_limit: paper(Id::CaptionLimit, 0),
        gradient_mid: {
            let c = claim(Id::GradientMid);
            let (lo, hi) = c.over.unwrap_or((f64::NAN, f64::NAN));
            [num(lo), num(hi), c.paper.to_owned()]
        },
        gradient_far: [
            claim(Id::GradientFar).over.map_or("–".into(), |o| num(o.0)),
            claim(Id::GradientFar)
                .values()
                .first()
                .map_or("–".into(), |v| format!("{} %", num(100.0 * v.0))),
        ],
    }
}

/// The sharp border's "near" band of the page: |x| ≤ this, R.
pub(super) const SHARP_NEAR: f64 = 2.0;

/// The rings of a centred hexagonal lattice of `agents` nodes at [`LATTICE_SPACING`] (1, 6,
/// 12, …) if `agents` is such a number and its last ring lies at `radius`.
fn hex_shells(agents: usize, radius: f64) -> Option<Vec<usize>> {
    let mut shells = vec![1];
    while shells.iter().sum::<usize>() < agents {
        shells.push(6 * shells.len());
    }
    let rings = (shells.len() - 1) as f64;
    (shells.iter().sum::<usize>() == agents && (rings * LATTICE_SPACING - radius).abs() < 1e-9)
        .then_some(shells)
}

/// The periods at the end of a course its tail values average.
pub(super) const TAIL: usize = 10;

/// The settings of the page's runs: its three scenarios, placed by `main`.
///
/// # Errors
/// If the caption's cloud cannot be placed.
pub(super) fn settings(
    [sharp, gradient, cloud]: [&Scenario; 3],
    main: Placement,
) -> Result<Settings, Error> {
    let run = &sharp.run;
    let p = &run.params;
    let period_cycles = p.gather_cycles + p.decide_cycles;
    let caption = builtin_placed("cloud-caption", main)?;
    let offset = segment(&caption, 1, 0).map_or(0.0, |s| s.level);
    let robots = Params::robots().wave;
    let secs = |d: protocol::Duration| num(d.as_millis() as f64 / 1000.0);
    let line = match gradient.success {
        Some(swarm_sim::scenario::Success::BeyondX { x }) => num(x),
        _ => "–".into(),
    };
    let near = match sharp.success {
        Some(swarm_sim::scenario::Success::NearX { within, .. }) => num(within),
        _ => "–".into(),
    };
    let disk = match builtin_placed("sharp", Placement::Random)?.shape {
        swarm_sim::geometry::Shape::Disk { diameter } => num(diameter),
        _ => "–".into(),
    };
    let radius = marks::swarm_radius(sharp);
    let across = |scn: &Scenario| radius + scn.start.x - segment(scn, 0, 1).map_or(0.0, |s| s.from);
    let slope = segment(gradient, 0, 1).map_or(0.0, |s| s.slope);
    Ok(Settings {
        across: [
            round2(radius),
            round2(across(sharp)),
            round2(across(gradient)),
            round2(slope * across(gradient)),
        ],
        disk,
        noise_half: num(run.noise / 2.0),
        period_cycles,
        run_cycles: u64::from(sharp.periods) * u64::from(period_cycles),
        starts: [num(sharp.start.x), num(gradient.start.x)],
        sharp: [
            seg(sharp, 0, 1, |s| s.from),
            seg(sharp, 0, 0, |s| s.level),
            seg(sharp, 0, 1, |s| s.level),
        ],
        sharp_bound: {
            let (lo, hi) = (segment(sharp, 0, 0), segment(sharp, 0, 1));
            lo.zip(hi).map_or("–".into(), |(lo, hi)| {
                round2(((hi.level - lo.level) / 2.0).powi(2))
            })
        },
        gradient: [
            seg(gradient, 0, 1, |s| s.from),
            seg(gradient, 0, 0, |s| s.level),
        ],
        cloud: [
            seg(cloud, 0, 0, |s| s.level),
            seg(cloud, 0, 1, |s| s.from),
            seg(cloud, 0, 2, |s| s.from),
            seg(cloud, 0, 2, |s| s.level),
        ],
        caption: [
            seg(&caption, 0, 0, |s| s.level),
            seg(&caption, 0, 1, |s| s.level),
            seg(&caption, 0, 1, |s| s.from),
            num(offset - caption.run.noise / 2.0),
            num(offset + caption.run.noise / 2.0),
        ],
        caption_offset: num(offset),
        hex_shells: hex_shells(sharp.agents, DISK.values[0] / 2.0),
        near,
        sharp_near: num(SHARP_NEAR),
        line,
        robot_cycle: [
            secs(robots.cycle - robots.cycle_spread),
            secs(robots.cycle + robots.cycle_spread),
        ],
        level_pct: tolerances(|k| matches!(k, Kind::Level { .. }), 100.0),
        distance: tolerances(|k| matches!(k, Kind::Distance { .. }), 1.0),
        cone_deg: num(crate::verdict::CONE_DEG),
        toward_pct: num(100.0 * crate::verdict::TOWARD_SHARE),
        confidence_pct: num(100.0 * swarm_sim::stats::CONFIDENCE),
        band: swarm_sim::timecourse::BAND.map(|q| num(100.0 * q)),
        tail: TAIL,
        bin_deg: num(360.0 / reproduce::shapes::BINS as f64),
        edge_level: num(super::sensitivity::EDGE_LEVEL),
        paper: paper_said(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every quote is the paper's, and every number taken from it is in it.
    #[test]
    fn the_paper_says_every_number_taken_from_it() {
        let text = crate::paper::plain(crate::paper::LATEX);
        for s in SAID {
            assert!(text.contains(s.quote), "not in the paper: {}", s.quote);
            for v in s.values {
                assert!(s.quote.contains(&v.to_string()), "{v} not in {}", s.quote);
            }
        }
    }
}
