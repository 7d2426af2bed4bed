//! The shapes of the paper's section 5: every formation of [`formations`] run [`RUNS`] times
//! on X = 0 ([`decide`]), their directions counted on the axes ([`Tally`]) into the section's
//! tables ([`ShapesSection`]) and histograms ([`ShapeHistograms`], which `pages::figures` draws
//! and writes as CSV).

use protocol::direction::Opposite;

use serde::{Deserialize, Serialize};

use crate::Error;
use hal_emu::world::field::Field;
use swarm_sim::progress::Progress;
use swarm_sim::scenario::LATTICE_SPACING;
use swarm_sim::seeds::derive;
use swarm_sim::shapes::{
    Decisions, Formation, ShapeHistograms, Tally, decide, formations, histogram,
};
use swarm_sim::sim::RunConfig;

/// Runs per formation on the page.
pub const RUNS: u32 = 300;
/// Bins of the histograms over the circle (10° each).
pub const BINS: usize = 36;
/// A direction is on an axis within this many degrees of it.
pub const TOLERANCE_DEG: f64 = 10.0;
/// The page's claim threshold: the claim holds if at least this fraction is on the axes.
pub const CLAIM: f64 = 0.9;

/// The four sets of directions of one formation's runs, in radians.
struct Directions {
    swarm: Vec<f64>,
    swarm_preferred: Vec<f64>,
    agents: Vec<f64>,
    agents_preferred: Vec<f64>,
}

impl Directions {
    /// The four sets counted on the axes: agents' preferences, agents' decisions, mean of the
    /// preferences, swarm's direction.
    fn tallies(&self, tol: f64) -> [Tally; 4] {
        [
            &self.agents_preferred,
            &self.agents,
            &self.swarm_preferred,
            &self.swarm,
        ]
        .map(|v| Tally::of(v.iter().copied(), tol))
    }

    fn of(runs: &[Decisions]) -> Directions {
        let all = |f: fn(&Decisions) -> &Vec<f32>| -> Vec<f64> {
            runs.iter()
                .flat_map(|d| f(d).iter().map(|&b| f64::from(b)))
                .collect()
        };
        Directions {
            swarm: runs.iter().filter_map(|d| d.swarm).collect(),
            swarm_preferred: runs.iter().filter_map(Decisions::preferred_mean).collect(),
            agents: all(|d| &d.agents),
            agents_preferred: all(|d| &d.preferred),
        }
    }
}

/// One row of a page table: the formation, then the four fractions on the axes.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShapeRow {
    /// The formation's name.
    pub name: String,
    /// Agents' preferences before diffusion.
    pub agents_preferred: String,
    /// Agents' decisions.
    pub agents: String,
    /// The circular mean of the preferences before diffusion.
    pub swarm_preferred: String,
    /// The swarm's decided direction.
    pub swarm: String,
}

impl ShapeRow {
    /// The row of `name` from its [`Directions::tallies`], each the share `count` picks.
    fn of(name: &str, t: &[Tally; 4], count: fn(&Tally) -> usize) -> ShapeRow {
        let [a, b, c, e] = t.map(|t| pct(t.frac(count(&t))));
        ShapeRow {
            name: name.to_owned(),
            agents_preferred: a,
            agents: b,
            swarm_preferred: c,
            swarm: e,
        }
    }
}

/// One formation on the page.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FormationNote {
    /// The formation's name.
    pub name: String,
    /// Number of agents.
    pub agents: usize,
    /// Extent in R.
    pub extent: String,
    /// Mean number of neighbours (a random disk: over the runs' placements).
    pub degree: String,
    /// Runs whose swarm moved (the decided bearings did not cancel).
    pub moved: u32,
}

/// What the page's section shows (`templates/reproduction/shapes.md.j2`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShapesSection {
    /// Runs per formation.
    pub runs: u32,
    /// The diffusion rate, per cent.
    pub diffusion: String,
    /// The tolerance in degrees.
    pub tolerance: String,
    /// The claim threshold, per cent.
    pub claim: String,
    /// Spacing of the line and the cross, in R.
    pub spacing: String,
    /// The fraction of a uniform distribution within the tolerance of 2 axes, and of 4.
    pub uniform: [String; 2],
    /// The formations.
    pub formations: Vec<FormationNote>,
    /// Within the tolerance of 0° or 180°.
    pub on_line: Vec<ShapeRow>,
    /// Within the tolerance of the four axes.
    pub on_cross: Vec<ShapeRow>,
    /// Within the tolerance of the four diagonals.
    pub diagonal: Vec<ShapeRow>,
    /// Key numbers for the text, per cent, by formation and quantity ([`Key`]).
    pub key: Key,
    /// The line's agents' preferences (before diffusion) lie on its axis ([`CLAIM`]).
    pub line_preferred_holds: bool,
    /// The cross's agents' preferences lie on its four axes.
    pub cross_preferred_holds: bool,
    /// The line's agents' decisions lie on its axis.
    pub line_agents_hold: bool,
    /// The cross's agents' decisions lie on its four axes.
    pub cross_agents_hold: bool,
    /// The line swarm's direction lies on its axis.
    pub line_swarm_holds: bool,
    /// The cross swarm's direction lies on its four axes.
    pub cross_swarm_holds: bool,
    /// The mean of the line's preferences lies on its axis.
    pub line_swarm_preferred_holds: bool,
    /// The mean of the cross's preferences lies on its four axes.
    pub cross_swarm_preferred_holds: bool,
    /// The figure's file name.
    pub figure: String,
    /// The line and the cross again with the other rule for an exactly opposite opinion
    /// ([`Opposite::Keep`]): their agents' decisions and their swarm's direction on their axes.
    pub keep: Vec<ShapeRow>,
    /// Whether the line's swarm moves along its axis in at least [`CLAIM`] of the runs, with
    /// the counter-clockwise rule and with [`Opposite::Keep`].
    pub line_holds_by_rule: [bool; 2],
    /// The same for the cross and its four arms.
    pub cross_holds_by_rule: [bool; 2],
    /// The CSV file's name.
    pub csv: String,
}

/// The numbers the section's text quotes.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Key {
    /// The line: its agents' preferences, agents' decisions, mean of preferences and swarm's
    /// direction on 0° or 180°.
    pub line: Option<ShapeRow>,
    /// The cross: the same on its four axes.
    pub cross: Option<ShapeRow>,
    /// The cross: the same on the four diagonals.
    pub cross_diagonal: Option<ShapeRow>,
    /// The lattice disk on 0° or 180°.
    pub lattice: Option<ShapeRow>,
    /// The random disk on 0° or 180°.
    pub random: Option<ShapeRow>,
}

fn pct(v: f64) -> String {
    format!("{:.0} %", 100.0 * v)
}

/// What the shapes' runs give: the page's section and the figure's histograms.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShapesResult {
    /// The page's section.
    pub section: ShapesSection,
    /// One formation's histograms each, for the figure and the CSV file.
    pub hists: Vec<ShapeHistograms>,
    /// The diffusion rate, per cent, as the figure names it.
    pub diffusion: String,
}

/// Runs every formation of [`formations`] [`RUNS`] times on X = 0 with `cfg` (formation `k`
/// uses seed `derive(seed, [k])`), and the line and the cross again with the other rule for an
/// exactly opposite opinion; writes nothing (`pages::figures::write_shapes` does).
///
/// # Errors
/// If a run fails.
pub fn compute(cfg: RunConfig, seed: u64, progress: &Progress) -> Result<ShapesResult, Error> {
    let field = Field::default();
    let tol = TOLERANCE_DEG.to_radians();
    let mut tables = Tables::default();
    for (k, f) in formations().iter().enumerate() {
        let s = derive(seed, &[k as u64]);
        let runs = decide(f, &field, cfg, RUNS, s, progress)?;
        tables.add(f, &runs, s, tol)?;
    }
    let (keep, keep_holds) = with_keep(cfg, seed, tol, progress)?;
    let diffusion = format!("{:.0}", 100.0 * f64::from(cfg.params.diffusion));
    let hists = std::mem::take(&mut tables.hists);
    Ok(ShapesResult {
        section: tables.section(diffusion.clone(), keep, keep_holds),
        hists,
        diffusion,
    })
}

/// What [`compute`] gathers formation by formation: the histograms of the figure, the notes
/// and rows of the tables, and per formation whether its directions hold the claim on its own
/// axes (agents before diffusion, agents, swarm before diffusion, swarm).
#[derive(Default)]
struct Tables {
    hists: Vec<ShapeHistograms>,
    notes: Vec<FormationNote>,
    on_line: Vec<ShapeRow>,
    on_cross: Vec<ShapeRow>,
    diagonal: Vec<ShapeRow>,
    holds: std::collections::HashMap<&'static str, [bool; 4]>,
}

impl Tables {
    /// Formation `f`'s runs (from seed `s`), counted with tolerance `tol`.
    fn add(&mut self, f: &Formation, runs: &[Decisions], s: u64, tol: f64) -> Result<(), Error> {
        let d = Directions::of(runs);
        let t = d.tallies(tol);
        let row = |count: fn(&Tally) -> usize| ShapeRow::of(f.name(), &t, count);
        self.on_line.push(row(|t| t.on_line));
        self.on_cross.push(row(|t| t.on_cross));
        self.diagonal.push(row(|t| t.diagonal));
        let axes: fn(&Tally) -> usize = match f {
            Formation::Cross { .. } => |t| t.on_cross,
            _ => |t| t.on_line,
        };
        self.holds
            .insert(f.name(), t.map(|t| t.frac(axes(&t)) >= CLAIM));
        let swarm0 = f.swarm(derive(s, &[0]))?;
        let degree = match f {
            Formation::RandomDisk { .. } => {
                let mut sum = 0.0;
                for r in 0..RUNS {
                    sum += f.swarm(derive(s, &[r.into()]))?.mean_degree();
                }
                sum / f64::from(RUNS)
            }
            _ => swarm0.mean_degree(),
        };
        // One decimal, without a trailing ".0" beyond 10 R (45, 22.5, 6.0).
        let extent = match format!("{:.1}", f.extent()) {
            e if f.extent() >= 10.0 => e.trim_end_matches(".0").to_owned(),
            e => e,
        };
        self.notes.push(FormationNote {
            name: f.name().to_owned(),
            agents: f.agents(),
            extent: extent.clone(),
            degree: format!("{degree:.1}"),
            moved: d.swarm.len() as u32,
        });
        self.hists.push(ShapeHistograms {
            name: f.name().to_owned(),
            size: f.agents(),
            extent,
            offsets: swarm0.offsets().iter().map(|o| (o.x, o.y)).collect(),
            swarm: histogram(d.swarm.iter().copied(), BINS),
            swarm_preferred: histogram(d.swarm_preferred.iter().copied(), BINS),
            agents: histogram(d.agents.iter().copied(), BINS),
            agents_preferred: histogram(d.agents_preferred.iter().copied(), BINS),
        });
        Ok(())
    }

    /// The page's section: these tables, with diffusion `diffusion` (%), and the line and the
    /// cross run again with [`Opposite::Keep`] (`keep`, and whether each holds the claim).
    fn section(
        self,
        diffusion: String,
        keep: Vec<ShapeRow>,
        keep_holds: (bool, bool),
    ) -> ShapesSection {
        let h = |name: &str, i: usize| self.holds.get(name).is_some_and(|v| v[i]);
        let find = |rows: &[ShapeRow], name: &str| rows.iter().find(|r| r.name == name).cloned();
        let key = Key {
            line: find(&self.on_line, "line"),
            cross: find(&self.on_cross, "cross"),
            cross_diagonal: find(&self.diagonal, "cross"),
            lattice: find(&self.on_line, "lattice disk"),
            random: find(&self.on_line, "random disk"),
        };
        ShapesSection {
            runs: RUNS,
            diffusion,
            tolerance: format!("{TOLERANCE_DEG:.0}"),
            claim: pct(CLAIM),
            spacing: LATTICE_SPACING.to_string(),
            uniform: [2.0, 4.0].map(|a| pct(a * 2.0 * TOLERANCE_DEG / 360.0)),
            line_preferred_holds: h("line", 0),
            cross_preferred_holds: h("cross", 0),
            line_agents_hold: h("line", 1),
            cross_agents_hold: h("cross", 1),
            line_swarm_preferred_holds: h("line", 2),
            cross_swarm_preferred_holds: h("cross", 2),
            line_swarm_holds: h("line", 3),
            cross_swarm_holds: h("cross", 3),
            figure: FIGURE.to_owned(),
            csv: CSV.to_owned(),
            line_holds_by_rule: [h("line", 3), keep_holds.0],
            cross_holds_by_rule: [h("cross", 3), keep_holds.1],
            keep,
            formations: self.notes,
            on_line: self.on_line,
            on_cross: self.on_cross,
            diagonal: self.diagonal,
            key,
        }
    }
}

/// The line and the cross (the formations whose agents hear exactly opposite bearings) run
/// again, with the same seeds, with [`Opposite::Keep`]: their rows on their own axes, and
/// whether each swarm (line, cross) moves along them in at least [`CLAIM`] of the runs.
fn with_keep(
    cfg: RunConfig,
    seed: u64,
    tol: f64,
    progress: &Progress,
) -> Result<(Vec<ShapeRow>, (bool, bool)), Error> {
    let cfg = RunConfig {
        opposite: Opposite::Keep,
        ..cfg
    };
    let field = Field::default();
    let mut rows = Vec::new();
    let mut holds = (false, false);
    for (k, f) in formations().iter().enumerate() {
        let axes: fn(&Tally) -> usize = match f {
            Formation::Cross { .. } => |t| t.on_cross,
            Formation::Line { .. } => |t| t.on_line,
            _ => continue,
        };
        let runs = decide(f, &field, cfg, RUNS, derive(seed, &[k as u64]), progress)?;
        let t = Directions::of(&runs).tallies(tol);
        let h = t[3].frac(axes(&t[3])) >= CLAIM;
        match f {
            Formation::Cross { .. } => holds.1 = h,
            _ => holds.0 = h,
        }
        rows.push(ShapeRow::of(f.name(), &t, axes));
    }
    Ok((rows, holds))
}

/// Formations `with_keep` runs again (the line and the cross).
pub const KEEP_FORMATIONS: u32 = 2;

/// The figure's file name under `docs/figures/` (the section names it).
pub const FIGURE: &str = "shapes-directions.svg";
/// The CSV file's name under `docs/figures/`.
pub const CSV: &str = "shapes-directions.csv";

#[cfg(test)]
mod tests {
    use super::*;
    use swarm_sim::scenario::Scenario;

    fn cfg() -> RunConfig {
        Scenario::builtin("sharp").unwrap().run
    }

    #[test]
    fn the_section_is_computed_from_the_runs() {
        let r = compute(cfg(), 3, &Progress::hidden()).unwrap();
        let sec = &r.section;
        assert_eq!(sec.formations.len(), 4);
        assert_eq!(sec.uniform, ["11 %".to_owned(), "22 %".to_owned()]);
        assert_eq!(sec.key.line.as_ref().unwrap().agents_preferred, "100 %");
        assert_eq!(sec.key.cross.as_ref().unwrap().agents_preferred, "100 %");
        assert!(sec.line_preferred_holds && sec.cross_preferred_holds);
        assert!(sec.line_swarm_preferred_holds);
        assert_eq!(r.hists.len(), 4);
    }
}
