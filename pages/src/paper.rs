//! The paper's figures and sections, each by its LaTeX label, numbered as the LaTeX source
//! (`pages/paper/cimax.tex`, the paper as its authors wrote it) numbers them: `figure` and
//! `figure*` share one counter, so the algorithm figure is Fig. 4 and the sharp border's run
//! Fig. 5; algorithm2e's pseudo-code blocks have their own counter. The pages name a figure
//! or a section only through these ([`Fig`], [`Sec`]; the templates through the `fig` and
//! `sec` globals of [`crate::page`]), and the tests below number the LaTeX source again and
//! check every one, so a figure number on a page cannot drift from the paper.

use std::collections::BTreeMap;
use std::fmt;

/// A figure of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Fig {
    /// The three states of an agent (WOSPP).
    StateCycle,
    /// One wave through 80 agents.
    Waves,
    /// A message gathering readings.
    Message,
    /// The algorithm's three parts.
    Algorithm,
    /// The sharp border: one run (a) and the diversity against time (b).
    SharpRun,
    /// The sharp border: success and mean success time against the start.
    SharpSweep,
    /// The sharp border: the direction map.
    SharpMap,
    /// The gradient: one run (a) and the diversity against time (b).
    GradientRun,
    /// The gradient: success and mean success time against the start.
    GradientSweep,
    /// The gradient: the direction map.
    GradientMap,
    /// The cloud: the direction map.
    Cloud,
    /// The robots' arena and set-up.
    Arena,
    /// The six light configurations of the robot experiments.
    Lights,
}

impl Fig {
    /// Every figure, in the paper's order.
    pub const ALL: [Fig; 13] = [
        Fig::StateCycle,
        Fig::Waves,
        Fig::Message,
        Fig::Algorithm,
        Fig::SharpRun,
        Fig::SharpSweep,
        Fig::SharpMap,
        Fig::GradientRun,
        Fig::GradientSweep,
        Fig::GradientMap,
        Fig::Cloud,
        Fig::Arena,
        Fig::Lights,
    ];

    /// Its `\label` in the LaTeX source.
    pub const fn label(self) -> &'static str {
        match self {
            Fig::StateCycle => "fig:state_cycle",
            Fig::Waves => "fig:scrollwave",
            Fig::Message => "fig:message",
            Fig::Algorithm => "fig:algorithm",
            Fig::SharpRun => "fig:discrete_transition",
            Fig::SharpSweep => "fig:discrete_transition_analysis",
            Fig::SharpMap => "fig:discrete_transition_vectorfield",
            Fig::GradientRun => "fig:smooth_transition",
            Fig::GradientSweep => "fig:smooth_transition_analysis",
            Fig::GradientMap => "fig:smooth_transition_vectorfield",
            Fig::Cloud => "fig:cloud_vectorfield",
            Fig::Arena => "fig:experiment",
            Fig::Lights => "fig:experiment_inkscape",
        }
    }

    /// Its number in the paper (checked against the LaTeX source by the tests).
    pub const fn number(self) -> u8 {
        match self {
            Fig::StateCycle => 1,
            Fig::Waves => 2,
            Fig::Message => 3,
            Fig::Algorithm => 4,
            Fig::SharpRun => 5,
            Fig::SharpSweep => 6,
            Fig::SharpMap => 7,
            Fig::GradientRun => 8,
            Fig::GradientSweep => 9,
            Fig::GradientMap => 10,
            Fig::Cloud => 11,
            Fig::Arena => 12,
            Fig::Lights => 13,
        }
    }

    /// The name the templates know it by (`{{ fig.sharp_sweep }}`).
    pub const fn key(self) -> &'static str {
        match self {
            Fig::StateCycle => "state_cycle",
            Fig::Waves => "waves",
            Fig::Message => "message",
            Fig::Algorithm => "algorithm",
            Fig::SharpRun => "sharp_run",
            Fig::SharpSweep => "sharp_sweep",
            Fig::SharpMap => "sharp_map",
            Fig::GradientRun => "gradient_run",
            Fig::GradientSweep => "gradient_sweep",
            Fig::GradientMap => "gradient_map",
            Fig::Cloud => "cloud",
            Fig::Arena => "arena",
            Fig::Lights => "lights",
        }
    }
}

impl fmt::Display for Fig {
    /// `Fig. 6`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Fig. {}", self.number())
    }
}

/// A section of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Sec {
    /// 1, the introduction.
    Intro,
    /// 2, the CIMAX algorithm.
    Cimax,
    /// 2.1, the communication paradigm (the waves).
    Waves,
    /// 2.2, the algorithm.
    Algorithm,
    /// 3, the simulations.
    Simulation,
    /// 3.1, the sharp border.
    Sharp,
    /// 3.2, the gradient.
    Gradient,
    /// 3.3, the cloud.
    Cloud,
    /// 4, the robot experiments.
    Experiments,
    /// 5, the discussion.
    Discussion,
}

impl Sec {
    /// Every section the pages cite, in the paper's order.
    pub const ALL: [Sec; 10] = [
        Sec::Intro,
        Sec::Cimax,
        Sec::Waves,
        Sec::Algorithm,
        Sec::Simulation,
        Sec::Sharp,
        Sec::Gradient,
        Sec::Cloud,
        Sec::Experiments,
        Sec::Discussion,
    ];

    /// Its `\label` in the LaTeX source.
    pub const fn label(self) -> &'static str {
        match self {
            Sec::Intro => "sec:intro",
            Sec::Cimax => "sec:methods",
            Sec::Waves => "sec:sub1methods",
            Sec::Algorithm => "sec:algorithm",
            Sec::Simulation => "sec:simulation",
            Sec::Sharp => "sec:simulation_sharp",
            Sec::Gradient => "sec:simulation_gradient",
            Sec::Cloud => "sec:simulation_cloud",
            Sec::Experiments => "sec:experiments",
            Sec::Discussion => "sec:discussion",
        }
    }

    /// Its number in the paper (checked against the LaTeX source by the tests).
    pub const fn number(self) -> &'static str {
        match self {
            Sec::Intro => "1",
            Sec::Cimax => "2",
            Sec::Waves => "2.1",
            Sec::Algorithm => "2.2",
            Sec::Simulation => "3",
            Sec::Sharp => "3.1",
            Sec::Gradient => "3.2",
            Sec::Cloud => "3.3",
            Sec::Experiments => "4",
            Sec::Discussion => "5",
        }
    }

    /// The name the templates know it by (`{{ sec.discussion }}`).
    pub const fn key(self) -> &'static str {
        match self {
            Sec::Intro => "intro",
            Sec::Cimax => "cimax",
            Sec::Waves => "waves",
            Sec::Algorithm => "algorithm",
            Sec::Simulation => "simulation",
            Sec::Sharp => "sharp",
            Sec::Gradient => "gradient",
            Sec::Cloud => "cloud",
            Sec::Experiments => "experiments",
            Sec::Discussion => "discussion",
        }
    }
}

impl fmt::Display for Sec {
    /// `§3.1`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "§{}", self.number())
    }
}

/// `{ key: "Fig. N" }` for every figure: the templates' `fig` global.
pub fn figure_names() -> BTreeMap<&'static str, String> {
    Fig::ALL.iter().map(|f| (f.key(), f.to_string())).collect()
}

/// `{ key: "§N" }` for every section: the templates' `sec` global.
pub fn section_names() -> BTreeMap<&'static str, String> {
    Sec::ALL.iter().map(|s| (s.key(), s.to_string())).collect()
}

/// The paper's LaTeX source, as its authors wrote it.
pub const LATEX: &str = include_str!("../paper/cimax.tex");

/// The paper's text with LaTeX's spacing undone: runs of white space as one space, `~` as a
/// space, and `$` dropped, so that a quote from the paper's text is found as it reads.
pub fn plain(latex: &str) -> String {
    let s: String = latex
        .chars()
        .filter(|&c| c != '$')
        .map(|c| if c == '~' { ' ' } else { c })
        .collect();
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The span of the paper's text (LaTeX source, from its `\section` or `\subsection` to the
/// next one) of section `sec`, or `None` if its label is not in the source.
pub fn section_text(latex: &str, sec: Sec) -> Option<&str> {
    let label = latex.find(&format!("\\label{{{}}}", sec.label()))?;
    let start = latex[..label]
        .rfind("\\section")
        .max(latex[..label].rfind("\\subsection"))?;
    // A section runs to the next heading of its level or above; a subsection to the next
    // heading of any level.
    let top = !sec.number().contains('.');
    let rest = &latex[label..];
    let next = ["\\section"]
        .into_iter()
        .chain((!top).then_some("\\subsection"))
        .filter_map(|h| rest.find(h))
        .min()
        .map_or(latex.len(), |k| label + k);
    Some(&latex[start..next])
}

/// Numbers the LaTeX source as LaTeX does: every `figure` and `figure*` environment in order
/// (one counter), each named by the first `\label` inside it; and every `\section` and
/// `\subsection` (not the starred ones), each named by the `\label` that follows it.
pub fn number_latex(latex: &str) -> (BTreeMap<String, u8>, BTreeMap<String, String>) {
    let mut figs = BTreeMap::new();
    let mut n = 0u8;
    for (at, _) in latex.match_indices("\\begin{figure") {
        // Saturating: a source with more than 255 figures numbers the rest 255, no panic.
        n = n.saturating_add(1);
        let body = &latex[at..];
        let end = body.find("\\end{figure").unwrap_or(body.len());
        if let Some(l) = first_label(&body[..end]) {
            figs.insert(l.to_owned(), n);
        }
    }
    let mut secs = BTreeMap::new();
    let (mut major, mut minor) = (0u32, 0u32);
    let mut rest = latex;
    while let Some(k) = next_heading(rest) {
        let head = &rest[k..];
        let sub = head.starts_with("\\subsection");
        let after = &head[if sub { 11 } else { 8 }..];
        rest = after;
        if after.starts_with('*') {
            continue;
        }
        let number = if sub {
            minor += 1;
            format!("{major}.{minor}")
        } else {
            major += 1;
            minor = 0;
            major.to_string()
        };
        let next = next_heading(after).unwrap_or(after.len());
        if let Some(l) = first_label(&after[..next]) {
            secs.insert(l.to_owned(), number);
        }
    }
    (figs, secs)
}

/// Where the next `\section` or `\subsection` of `s` starts.
fn next_heading(s: &str) -> Option<usize> {
    [s.find("\\section"), s.find("\\subsection")]
        .into_iter()
        .flatten()
        .min()
}

/// The first `\label{…}`'s name in `s`.
fn first_label(s: &str) -> Option<&str> {
    let at = s.find("\\label{")? + 7;
    let len = s[at..].find('}')?;
    Some(&s[at..at + len])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_figure_has_the_number_the_latex_source_gives_it() {
        let (figs, _) = number_latex(LATEX);
        assert_eq!(figs.len(), Fig::ALL.len(), "{figs:?}");
        for f in Fig::ALL {
            assert_eq!(figs.get(f.label()), Some(&f.number()), "{f:?}");
        }
        assert_eq!(Fig::Algorithm.to_string(), "Fig. 4");
        assert_eq!(Fig::SharpRun.to_string(), "Fig. 5");
    }

    #[test]
    fn every_section_has_the_number_the_latex_source_gives_it() {
        let (_, secs) = number_latex(LATEX);
        for s in Sec::ALL {
            assert_eq!(
                secs.get(s.label()).map(String::as_str),
                Some(s.number()),
                "{s:?}"
            );
        }
    }

    #[test]
    fn a_section_s_text_runs_to_the_next_heading() {
        let sharp = plain(section_text(LATEX, Sec::Sharp).unwrap());
        assert!(sharp.contains("increases until t=8"), "{sharp}");
        assert!(!sharp.contains("linearly increasing average levels"));
        let discussion = plain(section_text(LATEX, Sec::Discussion).unwrap());
        assert!(discussion.contains("the success rates vary between 85\\% to 100\\%"));
        let simulation = plain(section_text(LATEX, Sec::Simulation).unwrap());
        assert!(
            simulation.contains("increases until t=8"),
            "a section holds its subsections"
        );
    }

    #[test]
    fn a_renumbered_source_is_caught() {
        // One figure more before the sharp border's run: every number after it moves.
        let moved = LATEX.replacen(
            "\\begin{figure}[thpb]",
            "\\begin{figure}[thpb]\\label{fig:new}\\end{figure}\\begin{figure}[thpb]",
            1,
        );
        let (figs, _) = number_latex(&moved);
        assert_eq!(figs.get(Fig::SharpRun.label()), Some(&6));
    }
}
