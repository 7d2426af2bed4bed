//! The paper's claims (its 2D simulations of section 3, and the claims of sections 2, 4 and 5
//! the page can test), each typed once: where in the paper it is, the quantity, the value or
//! range, the tolerance and kind by which ours is judged ([`super::verdict`]), and the figures
//! it is drawn on ([`super::marks`]). The summary table of `docs/reproduction.md`, the verdicts
//! and the paper's marks on the figures all read [`CLAIMS`].

use crate::paper::{Fig, Sec};

mod types;

pub use types::{Claim, Ends, Figure, Id, Kind, Value};

/// Every claim the reproduction tests, in the order of the summary table.
pub const CLAIMS: &[Claim] = &[
    Claim {
        id: Id::SharpNear,
        source: "§3.1, Fig. 6",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpSweep],
        quotes: &[
            "For initial distances smaller than |x_{init}| < 2.5\\,R the success rates are 1",
        ],
        quantity: "Sharp border (Fig. 6): success for \\|x_init\\| < 2.5 R",
        paper: "1.0",
        value: Value::At(1.0),
        over: Some((-2.5, 2.5)),
        ends: Ends::Open,
        kind: Kind::Rate,
        drawn: &[(Figure::Sweep("sharp"), "paper: 1.0 for |x_init| < 2.5 R")],
    },
    Claim {
        id: Id::SharpFar,
        source: "§3.1, Fig. 6",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpSweep],
        quotes: &[
            "For distances further away the swarm randomly moves around and by chance perceives the respective other domain",
        ],
        quantity: "Sharp border: success beyond 2.5 R",
        paper: "falls (random walk until the swarm perceives the border)",
        value: Value::Words,
        over: Some((-5.0, -2.5)),
        ends: Ends::Open,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::SharpTime,
        source: "§3.1, Fig. 6",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpSweep],
        quotes: &["the corresponding success time decreases linearly"],
        quantity: "Sharp border: mean success time from −2.5 … −0.5",
        paper: "decreases linearly toward the border",
        value: Value::Words,
        over: Some((-2.5, -0.5)),
        ends: Ends::Closed,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::SharpStart,
        source: "§3.1, Fig. 5b",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpRun],
        quotes: &["Initially the diversity is small (t=0, \\overline{V_k}=0.2)"],
        quantity: "Sharp border (Fig. 5b): average diversity at t = 0, from x = −2.5",
        paper: "≈ 0.2",
        value: Value::At(0.2),
        over: None,
        ends: Ends::Open,
        kind: Kind::Level { rel: 0.1 },
        drawn: &[(Figure::Course("sharp"), "paper: start ≈ 0.2")],
    },
    Claim {
        id: Id::GradientStart,
        source: "§3.2, Fig. 8b",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientRun],
        quotes: &["It increases from \\overline{V_k}\\approx0.3"],
        quantity: "Gradient (Fig. 8b): average diversity at t = 0, from x = −2.5",
        paper: "≈ 0.3",
        value: Value::At(0.3),
        over: None,
        ends: Ends::Open,
        kind: Kind::Level { rel: 0.1 },
        drawn: &[(Figure::Course("gradient"), "paper: start ≈ 0.3")],
    },
    Claim {
        id: Id::SharpArrival,
        source: "§3.1, Fig. 5",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpRun],
        quotes: &["increases until t=8 where it reaches a plateau"],
        quantity: "Sharp border (Fig. 5): periods from x = −2.5 until the swarm arrives",
        paper: "≈ 8 (one run)",
        value: Value::At(8.0),
        over: None,
        ends: Ends::Open,
        kind: Kind::Level { rel: 0.1 },
        drawn: &[],
    },
    Claim {
        id: Id::GradientArrival,
        source: "§3.2, Fig. 8",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientRun],
        quotes: &["until at t=15 (when it starts moving randomly) it reaches a plateau"],
        quantity: "Gradient (Fig. 8): periods from x = −2.5 until the swarm arrives",
        paper: "≈ 15 (one run)",
        value: Value::At(15.0),
        over: None,
        ends: Ends::Open,
        kind: Kind::Level { rel: 0.1 },
        drawn: &[],
    },
    Claim {
        id: Id::SharpPlateau,
        source: "§3.1, Fig. 5b",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpRun],
        quotes: &["it reaches a plateau around \\overline{V_k}=4.5"],
        quantity: "Sharp border (Fig. 5b): diversity plateau at the border",
        paper: "≈ 4.5",
        value: Value::At(4.5),
        over: None,
        ends: Ends::Open,
        kind: Kind::Level { rel: 0.1 },
        drawn: &[(Figure::Course("sharp"), "paper: plateau ≈ 4.5 (Fig. 5b)")],
    },
    Claim {
        id: Id::GradientPlateau,
        source: "§3.2, Fig. 8b and its caption",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientRun],
        quotes: &[
            "it saturates and fluctuates around \\overline{V_k}=8",
            "it reaches a plateau where it fluctuates around \\overline{V_k}=20",
        ],
        quantity: "Gradient (Fig. 8b): diversity plateau",
        paper: "≈ 8 (caption), ≈ 20 (text)",
        value: Value::Either(&[(8.0, "caption of Fig. 8"), (20.0, "text")]),
        over: None,
        ends: Ends::Open,
        kind: Kind::Tuned,
        drawn: &[
            (
                Figure::Course("gradient"),
                "paper: plateau ≈ 8 (caption of Fig. 8)",
            ),
            (Figure::Course("gradient"), "paper: plateau ≈ 20 (text)"),
        ],
    },
    Claim {
        id: Id::SharpMapNear,
        source: "§3.1, Fig. 7",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpMap],
        quotes: &["For distances from the border |d|<2.5, the swarm moves towards the border"],
        quantity: "Sharp map (Fig. 7): arrows toward the border, 0 < \\|x\\| ≤ 2.5",
        paper: "all",
        value: Value::Words,
        over: Some((-2.5, 2.5)),
        ends: Ends::Open,
        kind: Kind::Direction { toward: true },
        drawn: &[(
            Figure::Map("sharp"),
            "paper: |x| = 2.5 R, toward the border inside, random beyond",
        )],
    },
    Claim {
        id: Id::SharpMapFar,
        source: "§3.1, Fig. 7",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpMap],
        quotes: &["For distances from the border |d|>2.5 the preferred direction is random"],
        quantity: "Sharp map: arrows toward the border, \\|x\\| > 2.5",
        paper: "random",
        value: Value::Words,
        over: Some((-2.5, 2.5)),
        ends: Ends::Open,
        kind: Kind::Direction { toward: false },
        drawn: &[],
    },
    Claim {
        id: Id::GradientMid,
        source: "§3.2 and §5, Fig. 9",
        secs: &[Sec::Gradient, Sec::Discussion],
        figs: &[Fig::GradientSweep],
        quotes: &[
            "For -2\\lesssim x_{init} < 2.33 the swarm succeeds in the majority of conducted simulations",
            "the success rates vary between 85\\% to 100\\%",
        ],
        quantity: "Gradient (Fig. 9): success for −2 ≤ x_init < 2.33",
        paper: "85–100 %",
        value: Value::Range(0.85, 1.0),
        over: Some((-2.0, 2.33)),
        ends: Ends::LowClosed,
        kind: Kind::Rate,
        drawn: &[(
            Figure::Sweep("gradient"),
            "paper: 85–100 % for −2 ≤ x_init < 2.33",
        )],
    },
    Claim {
        id: Id::GradientFar,
        source: "§3.2, Fig. 9",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientSweep],
        quotes: &["at x_{init}=-4 they reach 25\\%"],
        quantity: "Gradient: success at x_init = −4",
        paper: "≈ 25 %",
        value: Value::At(0.25),
        over: Some((-4.0, -4.0)),
        ends: Ends::Closed,
        kind: Kind::Rate,
        drawn: &[(Figure::Sweep("gradient"), "paper: 25 % at x_init = −4")],
    },
    Claim {
        id: Id::GradientFall,
        source: "§3.2, Fig. 9",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientSweep],
        quotes: &[
            "At x_{init}\\lesssim -2 for decreasing distance from the border the success rates decrease significantly",
        ],
        quantity: "Gradient: success beyond x_init = −2",
        paper: "falls (\"decrease significantly\")",
        value: Value::Words,
        over: Some((-5.0, -2.0)),
        ends: Ends::Open,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::GradientTime,
        source: "§3.2, Fig. 9",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientSweep],
        quotes: &[
            "the success times increase with decreasing distance from the border between the two domains",
        ],
        quantity: "Gradient: mean success time from −2 to the border (x = 0), against the distance from it",
        paper: "\"increase with decreasing distance from the border\" (as written)",
        value: Value::Words,
        over: Some((-2.0, 0.0)),
        ends: Ends::LowClosed,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::GradientMapNear,
        source: "§3.2, Fig. 10",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientMap],
        quotes: &[
            "For -2\\gtrsim x\\gtrsim 2 the swarm is attracted to the gradient domain and moves towards the right",
        ],
        quantity: "Gradient map (Fig. 10): arrows toward +x, −2.2 ≤ x ≤ 2.2",
        paper: "all",
        value: Value::Words,
        over: Some((-2.2, 2.2)),
        ends: Ends::Closed,
        kind: Kind::Direction { toward: true },
        drawn: &[(
            Figure::Map("gradient"),
            "paper: x = −2.2 and 2.2, toward +x between, random beyond",
        )],
    },
    Claim {
        id: Id::GradientMapLeft,
        source: "§3.2, Fig. 10",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientMap],
        quotes: &[
            "For x<-2.2 the swarm moves randomly as it does not perceive the linear gradient",
        ],
        quantity: "Gradient map: arrows toward +x, x < −2.2",
        paper: "random",
        value: Value::Words,
        over: Some((f64::NEG_INFINITY, -2.2)),
        ends: Ends::Open,
        kind: Kind::Direction { toward: false },
        drawn: &[],
    },
    Claim {
        id: Id::GradientMapFar,
        source: "§3.2, Fig. 10",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientMap],
        quotes: &["For x\\gtrsim 2 the swarm moves randomly"],
        quantity: "Gradient map: arrows toward +x, x > 2.2",
        paper: "random",
        value: Value::Words,
        over: Some((2.2, f64::INFINITY)),
        ends: Ends::Open,
        kind: Kind::Direction { toward: false },
        drawn: &[],
    },
    Claim {
        id: Id::SharpEdge,
        source: "§3.1, Fig. 7",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpMap],
        quotes: &["For |x|\\gtrsim2.5 the swarm moves randomly"],
        quantity: "Sharp border: farthest start from which the first move heads for the border",
        paper: "≈ 2.5 R",
        value: Value::At(2.5),
        over: None,
        ends: Ends::Open,
        kind: Kind::Distance { tol: 0.25 },
        drawn: &[(Figure::Extent, " paper: 2.5 R")],
    },
    Claim {
        id: Id::GradientEdge,
        source: "§3.2, Fig. 10",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientMap],
        quotes: &["For x<-2.2 the swarm moves randomly"],
        quantity: "Gradient: farthest start from which the first move heads for the border",
        paper: "≈ 2.2 R",
        value: Value::At(2.2),
        over: None,
        ends: Ends::Open,
        kind: Kind::Distance { tol: 0.25 },
        drawn: &[(Figure::Extent, " paper: 2.2 R")],
    },
    Claim {
        id: Id::CloudLimit,
        source: "§3.3, text and caption of Fig. 11",
        secs: &[Sec::Cloud],
        figs: &[Fig::Cloud],
        quotes: &[
            "For radial distances from the center of the cloud of d\\gtrsim7 the swarm moves randomly",
            "larger than d\\gtrsim 7.5 the swarm is too far from it to perceive it",
        ],
        quantity: "Cloud (Fig. 11, the text's): distance beyond which the swarm no longer heads for it",
        paper: "≈ 7 (text), ≈ 7.5 (caption)",
        value: Value::Either(&[(7.0, "text"), (7.5, "caption")]),
        over: None,
        ends: Ends::Open,
        kind: Kind::Distance { tol: 0.25 },
        drawn: &[
            (Figure::Map("cloud"), "paper (text): d = 7, random beyond"),
            (
                Figure::Map("cloud"),
                "paper (caption): d = 7.5, random beyond",
            ),
            (
                Figure::Profile("cloud"),
                "paper (text): d = 7, random beyond",
            ),
            (
                Figure::Profile("cloud"),
                "paper (caption): d = 7.5, random beyond",
            ),
        ],
    },
    Claim {
        id: Id::CloudOutward,
        source: "§3.3, text",
        secs: &[Sec::Cloud],
        figs: &[Fig::Cloud],
        quotes: &["whereas for d\\lesssim 4 it moves radially away from it towards its border"],
        quantity: "Cloud (the text's): inside, the swarm heads out toward its border",
        paper: "for d ≲ 4",
        value: Value::At(4.0),
        over: None,
        ends: Ends::Open,
        kind: Kind::Distance { tol: 0.25 },
        drawn: &[
            (
                Figure::Map("cloud"),
                "paper (text): d = 4, heads out inside",
            ),
            (
                Figure::Profile("cloud"),
                "paper (text): d = 4, heads out inside",
            ),
        ],
    },
    Claim {
        id: Id::CloudToward,
        source: "§3.3, text",
        secs: &[Sec::Cloud],
        figs: &[Fig::Cloud],
        quotes: &[
            "For 7\\gtrsim d\\gtrsim 4 the swarm moves towards the circular domain",
            "it proceeds to move towards its border where it measures the largest average diversity",
        ],
        quantity: "Cloud (the text's): from d ≈ 4 to 7 the swarm moves toward it",
        paper: "toward the cloud for 7 ≳ d ≳ 4",
        value: Value::Range(4.0, 7.0),
        over: Some((4.0, 7.0)),
        ends: Ends::Open,
        kind: Kind::Profile,
        drawn: &[],
    },
    Claim {
        id: Id::CaptionLimit,
        source: "§3.3, caption of Fig. 11",
        secs: &[Sec::Cloud],
        figs: &[Fig::Cloud],
        quotes: &["larger than d\\gtrsim 7.5 the swarm is too far from it to perceive it"],
        quantity: "Cloud (the caption's, radius 5): distance beyond which the swarm no longer heads for it",
        paper: "≈ 7.5 (caption)",
        value: Value::At(7.5),
        over: None,
        ends: Ends::Open,
        kind: Kind::Distance { tol: 0.25 },
        drawn: &[
            (
                Figure::Map("cloud-caption"),
                "paper (caption): d = 7.5, random beyond",
            ),
            (
                Figure::Profile("cloud-caption"),
                "paper (caption): d = 7.5, random beyond",
            ),
        ],
    },
    Claim {
        id: Id::ShapesLine,
        source: "§5 (discussion)",
        secs: &[Sec::Discussion],
        figs: &[],
        quotes: &["the preferred direction can only be along the linear distribution of the swarm"],
        quantity: "Random field: a line's swarm moves along its axis",
        paper: "only along the line",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::OpenRule,
        drawn: &[],
    },
    Claim {
        id: Id::ShapesCross,
        source: "§5 (discussion)",
        secs: &[Sec::Discussion],
        figs: &[],
        quotes: &[
            "will theoretically move like the king on a chess board, solely up-down-left-right",
        ],
        quantity: "Random field: a cross's swarm moves along its four arms",
        paper: "\"like the king on a chess board, solely up-down-left-right\"",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::OpenRule,
        drawn: &[],
    },
    Claim {
        id: Id::SharpWalk,
        source: "§3.1, text of Fig. 5",
        secs: &[Sec::Sharp],
        figs: &[Fig::SharpRun],
        quotes: &["effectively performing a one-dimensional random walk"],
        quantity: "Sharp border: after arriving, the swarm walks along the border",
        paper: "\"a one-dimensional random walk\"",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Walk { dims: 1 },
        drawn: &[],
    },
    Claim {
        id: Id::GradientWalk,
        source: "§3.2, text of Fig. 10",
        secs: &[Sec::Gradient],
        figs: &[Fig::GradientMap],
        quotes: &["the swarm diffuses in both dimensions given that x\\geq2.3"],
        quantity: "Gradient: on the ramp the swarm diffuses in both dimensions",
        paper: "\"diffuses in both dimensions\"",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Walk { dims: 2 },
        drawn: &[],
    },
    Claim {
        id: Id::Steeper,
        source: "§5 (discussion), from Figs. 6 and 9",
        secs: &[Sec::Discussion],
        figs: &[Fig::SharpSweep, Fig::GradientSweep],
        quotes: &[
            "the artificial swarms using this algorithm perform better the steeper a gradient in measured quantity is",
        ],
        quantity: "The steeper the gradient, the better the swarm performs",
        paper: "shorter times on the sharp border than on the gradient",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::CaptionToward,
        source: "§3.3, caption of Fig. 11",
        secs: &[Sec::Cloud],
        figs: &[Fig::Cloud],
        quotes: &[
            "For d\\lesssim7.5 the swarm consistently moves towards the border between the two domains",
        ],
        quantity: "Cloud (the caption's, radius 5): the swarm moves toward the border",
        paper: "for d ≲ 7.5",
        value: Value::At(7.5),
        over: Some((0.0, 7.5)),
        ends: Ends::Open,
        kind: Kind::Profile,
        drawn: &[],
    },
    Claim {
        id: Id::Refractory,
        source: "§2.1, text beside Fig. 2",
        secs: &[Sec::Waves],
        figs: &[Fig::Waves],
        quotes: &[
            "The refractory state assures that a signal will neither 'flood' a swarm, i.e. signals will not (re)activate the initial sender, nor periodically propagate through the swarm e.g. as a spiraling wave",
        ],
        quantity: "The refractory state keeps a wave from flooding the swarm and from coming back periodically",
        paper: "signals neither flood the swarm (re-activate the sender) nor propagate periodically (e.g. a spiral wave)",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Mechanism,
        drawn: &[],
    },
    Claim {
        id: Id::Initiations,
        source: "§2.1",
        secs: &[Sec::Waves],
        figs: &[],
        quotes: &[
            "each agent initiates the sending of a signal at least once within a time period",
        ],
        quantity: "Every agent initiates at least once per cycle",
        paper: "at least once per cycle: every agent-cycle",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Rate,
        drawn: &[],
    },
    Claim {
        id: Id::Indecision,
        source: "§5 (discussion)",
        secs: &[Sec::Discussion],
        figs: &[Fig::Lights],
        quotes: &[
            "The chances of reaching an indecision point, when two aMussels decide to move left and two aMussels decide to move right",
            "decrease with increasing number of members of a swarm",
        ],
        quantity: "Indecision points (as many agents decide left as right) get rarer as the swarm grows",
        paper: "rarer with more members; negligible for a large 2D swarm",
        value: Value::Words,
        over: None,
        ends: Ends::Open,
        kind: Kind::Trend,
        drawn: &[],
    },
    Claim {
        id: Id::Lab,
        source: "§4",
        secs: &[Sec::Experiments],
        figs: &[Fig::Lights],
        quotes: &[
            "For each light configuration the experiment was independently repeated five times with a success rate of 100 \\%",
            "We conducted this experiment five independent times with all experiments successful",
        ],
        quantity: "Four robots in a line: every light configuration, and the alternating experiment, decided right",
        paper: "100 % (5 runs per configuration, 5 alternating)",
        value: Value::At(1.0),
        over: None,
        ends: Ends::Open,
        kind: Kind::Rate,
        drawn: &[],
    },
];

/// The claim `id`.
pub fn claim(id: Id) -> &'static Claim {
    CLAIMS
        .iter()
        .find(|c| c.id == id)
        .unwrap_or_else(|| unreachable!("every Id has a row in CLAIMS (test)"))
}

impl Claim {
    /// The paper's numbers of this claim with where each is from (none for a claim in words).
    pub fn values(&self) -> Vec<(f64, &'static str)> {
        match self.value {
            Value::At(v) => vec![(v, self.source)],
            Value::Range(lo, hi) => vec![(lo, self.source), (hi, self.source)],
            Value::Either(vs) => vs.to_vec(),
            Value::Words => Vec::new(),
        }
    }

    /// The tolerance of a level (relative: 0.1 is 10 %) or a distance (R); 0 for other kinds.
    pub fn tolerance(&self) -> f64 {
        match self.kind {
            Kind::Level { rel } => rel,
            Kind::Distance { tol } => tol,
            _ => 0.0,
        }
    }

    /// Whether `x` lies in the claim's range (every `x` for a claim without one).
    pub fn covers(&self, x: f64) -> bool {
        const EPS: f64 = 1e-9;
        let Some((lo, hi)) = self.over else {
            return true;
        };
        match self.ends {
            Ends::Open => x > lo + EPS && x < hi - EPS,
            Ends::LowClosed => x > lo - EPS && x < hi - EPS,
            Ends::Closed => x > lo - EPS && x < hi + EPS,
        }
    }

    /// The paper's value as a band: one value, a range, or the span of its values.
    pub fn band(&self) -> Option<(f64, f64)> {
        let vs = self.values();
        let lo = vs.iter().map(|v| v.0).reduce(f64::min)?;
        let hi = vs.iter().map(|v| v.0).reduce(f64::max)?;
        Some((lo, hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper;

    /// The numbers written in `text` (digits with an optional decimal part), in order.
    fn numbers(text: &str) -> Vec<f64> {
        let mut out = Vec::new();
        let mut cur = String::new();
        for c in text.chars().chain([' ']) {
            if c.is_ascii_digit() || (c == '.' && !cur.is_empty() && !cur.contains('.')) {
                cur.push(c);
            } else if !cur.is_empty() {
                out.extend(cur.trim_end_matches('.').parse::<f64>().ok());
                cur.clear();
            }
        }
        out
    }

    /// The figure numbers `text` cites ("Fig. 5b", "Figs. 6 and 9", "Figs. 8–10").
    fn cited_figures(text: &str) -> Vec<u8> {
        let mut out = Vec::new();
        for (k, _) in text.match_indices("Fig") {
            let rest = text[k..]
                .trim_start_matches("Figs")
                .trim_start_matches("Fig");
            let Some(rest) = rest.strip_prefix('.') else {
                continue;
            };
            // The list after it: numbers with panel letters, joined by ",", "and", "–".
            let list: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || " ,–".contains(*c))
                .collect();
            let list = list.split(" (").next().unwrap_or("");
            for w in list.split([' ', ',', '–']) {
                let digits: String = w.chars().take_while(char::is_ascii_digit).collect();
                if let Ok(n) = digits.parse() {
                    out.push(n);
                } else if !w.is_empty() && w != "and" {
                    break;
                }
            }
        }
        out
    }

    /// The section numbers `text` cites ("§3.2").
    fn cited_sections(text: &str) -> Vec<String> {
        text.match_indices('§')
            .map(|(k, _)| {
                text[k + '§'.len_utf8()..]
                    .chars()
                    .take_while(|c| c.is_ascii_digit() || *c == '.')
                    .collect::<String>()
                    .trim_end_matches('.')
                    .to_owned()
            })
            .collect()
    }

    #[test]
    fn every_quote_is_the_paper_s_text_in_the_claim_s_section() {
        for c in CLAIMS {
            assert!(!c.secs.is_empty() && !c.quotes.is_empty(), "{:?}", c.id);
            for q in c.quotes {
                let found = c.secs.iter().any(|&s| {
                    paper::section_text(paper::LATEX, s)
                        .is_some_and(|t| paper::plain(t).contains(q))
                });
                assert!(found, "{:?}: {q:?} is not in {:?}", c.id, c.secs);
            }
        }
    }

    #[test]
    fn every_number_of_the_paper_s_value_is_in_its_words() {
        for c in CLAIMS {
            let said: Vec<f64> = c.quotes.iter().flat_map(|q| numbers(q)).collect();
            let values: Vec<f64> = match c.value {
                Value::At(v) => vec![v],
                Value::Range(lo, hi) => vec![lo, hi],
                Value::Either(vs) => vs.iter().map(|v| v.0).collect(),
                Value::Words => vec![],
            };
            for v in values {
                // A rate is written as a percentage.
                let ok = said
                    .iter()
                    .any(|&n| (n - v).abs() < 1e-9 || (n - 100.0 * v).abs() < 1e-9);
                assert!(ok, "{:?}: {v} is not in {:?}", c.id, c.quotes);
            }
        }
    }

    #[test]
    fn every_figure_and_section_a_claim_cites_is_the_paper_s() {
        for c in CLAIMS {
            let mut texts = vec![c.source, c.quantity, c.paper];
            texts.extend(c.drawn.iter().map(|d| d.1));
            if let Value::Either(vs) = c.value {
                texts.extend(vs.iter().map(|v| v.1));
            }
            let figs: Vec<u8> = c.figs.iter().map(|f| f.number()).collect();
            let secs: Vec<&str> = c.secs.iter().map(|s| s.number()).collect();
            for t in texts {
                for n in cited_figures(t) {
                    assert!(
                        figs.contains(&n),
                        "{:?}: Fig. {n} in {t:?}, not of {:?}",
                        c.id,
                        c.figs
                    );
                }
                for n in cited_sections(t) {
                    assert!(secs.contains(&n.as_str()), "{:?}: §{n} in {t:?}", c.id);
                }
            }
        }
        assert_eq!(cited_figures("Figs. 6 and 9, Fig. 5b (one run)"), [6, 9, 5]);
        assert_eq!(cited_sections("§3.2 and §5, Fig. 9"), ["3.2", "5"]);
    }

    #[test]
    fn ranges_keep_the_ends_the_paper_states() {
        let near = claim(Id::SharpNear);
        assert!(near.covers(2.0) && !near.covers(-2.5) && !near.covers(2.5));
        let mid = claim(Id::GradientMid);
        assert!(mid.covers(-2.0) && !mid.covers(2.33) && mid.covers(2.0));
        assert!(claim(Id::GradientFar).covers(-4.0) && !claim(Id::GradientFar).covers(-3.5));
    }

    #[test]
    fn every_claim_is_typed_once_and_found_by_its_id() {
        for (k, c) in CLAIMS.iter().enumerate() {
            assert_eq!(claim(c.id), c);
            assert!(
                CLAIMS[k + 1..].iter().all(|d| d.id != c.id),
                "{:?} twice",
                c.id
            );
            assert!(c.drawn.iter().all(|(_, label)| label.contains("paper")));
            // A claim with a number states it in the table's paper column.
            for (v, _) in c.values() {
                let shown = if c.paper.contains('%') { v * 100.0 } else { v };
                assert!(
                    c.paper.contains(&format!("{shown}")),
                    "{:?}: {} does not show {shown}",
                    c.id,
                    c.paper
                );
            }
        }
    }
}
