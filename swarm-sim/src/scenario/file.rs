//! Reading a scenario file: the TOML as written ([`Raw`] and its tables, with the spans of
//! their values), and the checks that turn it into a [`Scenario`] or a [`ScenarioError`] naming
//! the line, the column and the problem.

use std::ops::Range;
use std::path::Path;

use nalgebra::Point2;
use protocol::{Duration, Params};
use serde::Deserialize;
use toml::Spanned;

use super::{
    GridSpec, LATTICE_SPACING, MAX_AGENTS, MAX_EXTENT, MAX_PERIODS, MAX_RUNS_PER_POINT, Scenario,
    ScenarioError, Success, SweepSpec, check_runs,
};
use crate::geometry::Shape;
use crate::measure::Measure;
use crate::sim::{MAX_PERIOD_SECS, RunConfig, SimError};
use hal_emu::world::field::{Along, Field, Layer, Segment};

/// Parses and validates a scenario; `source` names it in errors
/// ([`Scenario::from_toml`]).
pub(super) fn parse(text: &str, source: &str) -> Result<Scenario, ScenarioError> {
    let cx = Ctx {
        text,
        source: source.to_string(),
    };
    let raw: Raw = toml::from_str(text).map_err(|e| ScenarioError {
        source: source.to_string(),
        at: e.span().map(|s| line_col(text, s.start)),
        message: e.message().trim().to_string(),
    })?;

    let (agents, shape) = cx.swarm(&raw)?;
    let params = cx.protocol(&raw)?;
    let diversity = cx.diversity(&raw)?;

    let noise = match &raw.noise {
        Some(v) if *v.get_ref() == 0.0 => 0.0,
        Some(v) => cx.positive(v, "noise")?,
        None => RunConfig::PAPER_NOISE,
    };
    let step = match &raw.step {
        Some(v) => cx.positive(v, "step")?,
        None => RunConfig::PAPER_STEP,
    };
    let periods = match &raw.periods {
        Some(v) if (1..=MAX_PERIODS).contains(v.get_ref()) => *v.get_ref(),
        Some(v) => return Err(cx.err(v.span(), "periods must be between 1 and 100,000")),
        None => 50,
    };
    let start = match &raw.start {
        Some(s) => {
            let [x, y] = *s.get_ref();
            if !(x.is_finite() && y.is_finite()) {
                return Err(cx.err(s.span(), "start must be two finite numbers"));
            }
            Point2::new(x, y)
        }
        None => Point2::new(-2.5, 0.0),
    };

    let layers = cx.layers(&raw.field)?;
    let field2 = match &raw.field2 {
        Some(f) => Some(Field {
            layers: cx.layers(f)?,
        }),
        None => None,
    };
    let success = cx.success(&raw)?;
    let sweep = cx.sweep(&raw)?;
    let grid = cx.grid(&raw, &params)?;

    let name = raw.name.unwrap_or_else(|| {
        Path::new(source)
            .file_stem()
            .map_or("scenario".into(), |s| s.to_string_lossy().into_owned())
    });
    Ok(Scenario {
        description: raw.description.unwrap_or_else(|| name.clone()),
        name,
        field: Field { layers },
        field2,
        agents,
        shape,
        run: RunConfig {
            step,
            noise,
            diversity,
            ..RunConfig::paper(params)
        },
        periods,
        start,
        success,
        sweep,
        grid,
    })
}

/// A number as a scenario file would write it: plain, or with an exponent when huge.
fn num(x: f64) -> String {
    if x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A scenario file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: Option<String>,
    description: Option<String>,
    noise: Option<Spanned<f64>>,
    step: Option<Spanned<f64>>,
    periods: Option<Spanned<u32>>,
    start: Option<Spanned<[f64; 2]>>,
    diversity: Option<Spanned<toml::Value>>,
    swarm: Option<Spanned<RawSwarm>>,
    protocol: Option<Spanned<RawProtocol>>,
    field: Spanned<Vec<RawLayer>>,
    field2: Option<Spanned<Vec<RawLayer>>>,
    success: Option<Spanned<RawSuccess>>,
    sweep: Option<Spanned<RawSweep>>,
    grid: Option<Spanned<RawGrid>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSwarm {
    agents: Option<Spanned<usize>>,
    shape: Option<Spanned<String>>,
    diameter: Option<Spanned<f64>>,
    width: Option<Spanned<f64>>,
    height: Option<Spanned<f64>>,
    spacing: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProtocol {
    cycle: Option<u64>,
    refractory: Option<u64>,
    relay_delay: Option<u64>,
    gather_cycles: Option<u16>,
    decide_cycles: Option<u16>,
    diffusion: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLayer {
    along: Spanned<String>,
    centre: Option<Spanned<[f64; 2]>>,
    segments: Spanned<Vec<RawSegment>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSegment {
    from: Spanned<f64>,
    level: Spanned<f64>,
    slope: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSuccess {
    kind: Spanned<String>,
    x: Option<Spanned<f64>>,
    within: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSweep {
    from: Spanned<f64>,
    to: Spanned<f64>,
    step: Spanned<f64>,
    runs: Option<Spanned<u32>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGrid {
    x: Spanned<[f64; 3]>,
    y: Spanned<[f64; 3]>,
    gather_cycles: Option<u16>,
    decide_cycles: Option<u16>,
}

/// Line and column (1-based, in characters) of byte `offset` in `text`.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

struct Ctx<'t> {
    text: &'t str,
    source: String,
}

impl Ctx<'_> {
    /// `[swarm]`: the number of agents and the shape they are placed in.
    fn swarm(&self, raw: &Raw) -> Result<(usize, Shape), ScenarioError> {
        let (mut agents, mut shape) = (61usize, Shape::Disk { diameter: 6.0 });
        if let Some(sw) = &raw.swarm {
            let sw = sw.get_ref();
            if let Some(a) = &sw.agents {
                agents = *a.get_ref();
                if !(2..=MAX_AGENTS).contains(&agents) {
                    return Err(self.err(a.span(), "agents must be between 2 and 1,000,000"));
                }
            }
            shape = self.shape(sw)?;
        }
        Ok((agents, shape))
    }

    /// `[swarm]`'s `shape` and the keys that size it (each only where it applies).
    fn shape(&self, sw: &RawSwarm) -> Result<Shape, ScenarioError> {
        let kind = sw.shape.as_ref().map_or("disk", |s| s.get_ref().as_str());
        let misplaced = |v: &Option<Spanned<f64>>, key: &str| {
            v.as_ref().map_or(Ok(()), |v| {
                Err(self.err(
                    v.span(),
                    format!("`{key}` does not apply to shape \"{kind}\""),
                ))
            })
        };
        match kind {
            "disk" => {
                misplaced(&sw.width, "width")?;
                misplaced(&sw.height, "height")?;
                misplaced(&sw.spacing, "spacing")?;
                Ok(Shape::Disk {
                    diameter: match &sw.diameter {
                        Some(d) => self.extent(d, "diameter", "the diameter")?,
                        None => 6.0,
                    },
                })
            }
            "rectangle" => {
                misplaced(&sw.diameter, "diameter")?;
                misplaced(&sw.spacing, "spacing")?;
                self.rectangle(sw)
            }
            "lattice" => {
                misplaced(&sw.diameter, "diameter")?;
                misplaced(&sw.width, "width")?;
                misplaced(&sw.height, "height")?;
                self.lattice(sw)
            }
            other => {
                let span = sw.shape.as_ref().map_or(0..0, |s| s.span());
                Err(self.err(
                    span,
                    format!(
                        "unknown shape \"{other}\", expected \"disk\", \"rectangle\" or \"lattice\""
                    ),
                ))
            }
        }
    }

    /// `shape = "rectangle"`: its `width` and `height`, both needed.
    fn rectangle(&self, sw: &RawSwarm) -> Result<Shape, ScenarioError> {
        let need = |v: &Option<Spanned<f64>>, key: &str| match v {
            Some(v) => self.extent(v, key, key),
            None => Err(ScenarioError {
                source: self.source.clone(),
                at: sw
                    .shape
                    .as_ref()
                    .map(|s| line_col(self.text, s.span().start)),
                message: format!("a rectangle needs `{key}`"),
            }),
        };
        Ok(Shape::Rectangle {
            width: need(&sw.width, "width")?,
            height: need(&sw.height, "height")?,
        })
    }

    /// `shape = "lattice"`: its `spacing` ([`LATTICE_SPACING`] unless given), at most the
    /// perception range so that the lattice is connected.
    fn lattice(&self, sw: &RawSwarm) -> Result<Shape, ScenarioError> {
        let spacing = match &sw.spacing {
            Some(v) => self.positive(v, "the spacing")?,
            None => LATTICE_SPACING,
        };
        if spacing > 1.0 {
            let span = sw.spacing.as_ref().map_or(0..0, |s| s.span());
            return Err(self.err(
                span,
                "the spacing must be at most the perception range (1) for a connected lattice",
            ));
        }
        Ok(Shape::Lattice { spacing })
    }

    /// `[protocol]`: `Params::simulation_2d()` with the file's changes, validated.
    fn protocol(&self, raw: &Raw) -> Result<Params, ScenarioError> {
        // Protocol.
        let mut params = Params::simulation_2d();
        if let Some(p) = &raw.protocol {
            let r = p.get_ref();
            if let Some(c) = r.cycle {
                params.wave.cycle = Duration::from_secs(c);
            }
            if let Some(c) = r.refractory {
                params.wave.refractory = Duration::from_secs(c);
            }
            if let Some(c) = r.relay_delay {
                params.wave.relay_delay = Duration::from_secs(c);
            }
            if let Some(c) = r.gather_cycles {
                params.gather_cycles = c;
            }
            if let Some(c) = r.decide_cycles {
                params.decide_cycles = c;
            }
            if let Some(d) = r.diffusion {
                params.diffusion = d;
            }
            params
                .validate()
                .map_err(|e| self.err(p.span(), format!("[protocol]: {e}")))?;
            period_fits(&params).map_err(|e| self.err(p.span(), format!("[protocol]: {e}")))?;
        }
        Ok(params)
    }

    /// `[[field]]`: the layers of the field.
    fn layers(&self, field: &Spanned<Vec<RawLayer>>) -> Result<Vec<Layer>, ScenarioError> {
        // Field.
        let mut layers = Vec::new();
        if field.get_ref().is_empty() {
            return Err(self.err(field.span(), "the field needs at least one layer"));
        }
        for l in field.get_ref() {
            let along = match (l.along.get_ref().as_str(), &l.centre) {
                ("x", None) => Along::X,
                ("y", None) => Along::Y,
                ("radial", c) => {
                    let [x, y] = c.as_ref().map_or([0.0, 0.0], |c| *c.get_ref());
                    if !(x.is_finite() && y.is_finite()) {
                        let span = c.as_ref().map_or(l.along.span(), |c| c.span());
                        return Err(self.err(span, "centre must be two finite numbers"));
                    }
                    Along::Radial {
                        centre: Point2::new(x, y),
                    }
                }
                ("x" | "y", Some(c)) => {
                    return Err(self.err(c.span(), "`centre` only applies to along = \"radial\""));
                }
                (other, _) => {
                    return Err(self.err(
                        l.along.span(),
                        format!("unknown along = \"{other}\", expected \"x\", \"y\" or \"radial\""),
                    ));
                }
            };
            let segs = l.segments.get_ref();
            if segs.is_empty() {
                return Err(self.err(l.segments.span(), "a layer needs at least one segment"));
            }
            let mut segments = Vec::new();
            for (k, s) in segs.iter().enumerate() {
                let from = *s.from.get_ref();
                if from.is_nan() || from == f64::INFINITY {
                    return Err(self.err(s.from.span(), "`from` must be a number or -inf"));
                }
                if k > 0 && from <= *segs[k - 1].from.get_ref() {
                    return Err(self.err(
                        s.from.span(),
                        format!(
                            "segments must start at increasing `from`: {from} follows {}",
                            segs[k - 1].from.get_ref()
                        ),
                    ));
                }
                let level = self.finite(&s.level, "level")?;
                let slope = match &s.slope {
                    Some(v) => self.finite(v, "slope")?,
                    None => 0.0,
                };
                if from == f64::NEG_INFINITY && slope != 0.0 {
                    let span = s.slope.as_ref().map_or(s.from.span(), |v| v.span());
                    return Err(self.err(span, "a segment from -inf must be flat (slope = 0)"));
                }
                segments.push(Segment { from, level, slope });
            }
            layers.push(Layer { along, segments });
        }
        Ok(layers)
    }

    /// `[success]`: the criterion, if any.
    fn success(&self, raw: &Raw) -> Result<Option<Success>, ScenarioError> {
        Ok(match &raw.success {
            None => None,
            Some(s) => {
                let r = s.get_ref();
                let x = match &r.x {
                    Some(v) => self.finite(v, "x")?,
                    None => return Err(self.err(s.span(), "[success] needs `x`")),
                };
                Some(match r.kind.get_ref().as_str() {
                    "near_x" => Success::NearX {
                        x,
                        within: match &r.within {
                            Some(v) => self.positive(v, "within")?,
                            None => return Err(self.err(s.span(), "near_x needs `within`")),
                        },
                    },
                    "beyond_x" => {
                        if let Some(w) = &r.within {
                            return Err(self.err(w.span(), "`within` does not apply to beyond_x"));
                        }
                        Success::BeyondX { x }
                    }
                    other => {
                        return Err(self.err(
                            r.kind.span(),
                            format!(
                                "unknown kind \"{other}\", expected \"near_x\" or \"beyond_x\""
                            ),
                        ));
                    }
                })
            }
        })
    }

    /// `[sweep]`: the initial positions and runs of a sweep, if any.
    fn sweep(&self, raw: &Raw) -> Result<Option<SweepSpec>, ScenarioError> {
        Ok(match &raw.sweep {
            None => None,
            Some(s) => {
                let r = s.get_ref();
                let from = self.finite(&r.from, "from")?;
                let to = self.finite(&r.to, "to")?;
                let runs = match &r.runs {
                    Some(v) if (1..=MAX_RUNS_PER_POINT).contains(v.get_ref()) => *v.get_ref(),
                    Some(v) => return Err(self.err(v.span(), "runs must be between 1 and 100,000")),
                    None => 50,
                };
                let xs = self.range(from, to, &r.step)?;
                check_runs(&[(xs.len() as u64, "positions"), (u64::from(runs), "runs")])
                    .map_err(|e| self.err(s.span(), format!("[sweep]: {e}")))?;
                Some(SweepSpec { xs, runs })
            }
        })
    }

    /// `[grid]`: the points and phases of a direction map, if any.
    fn grid(&self, raw: &Raw, params: &Params) -> Result<Option<GridSpec>, ScenarioError> {
        Ok(match &raw.grid {
            None => None,
            Some(g) => {
                let r = g.get_ref();
                let axis = |v: &Spanned<[f64; 3]>| {
                    let [a, b, s] = *v.get_ref();
                    self.range(a, b, &Spanned::new(v.span(), s))
                };
                let gather = r.gather_cycles.unwrap_or(params.gather_cycles);
                let decide = r.decide_cycles.unwrap_or(params.decide_cycles);
                if gather == 0 || decide == 0 {
                    return Err(self.err(g.span(), "[grid]: phases must last at least one cycle"));
                }
                let grid_params = Params {
                    gather_cycles: gather,
                    decide_cycles: decide,
                    ..*params
                };
                period_fits(&grid_params)
                    .map_err(|e| self.err(g.span(), format!("[grid]: {e}")))?;
                let (xs, ys) = (axis(&r.x)?, axis(&r.y)?);
                check_runs(&[(xs.len() as u64, "columns"), (ys.len() as u64, "rows")])
                    .map_err(|e| self.err(g.span(), format!("[grid]: {e} (one per point)")))?;
                Some(GridSpec {
                    xs,
                    ys,
                    gather_cycles: gather,
                    decide_cycles: decide,
                })
            }
        })
    }

    fn err(&self, span: Range<usize>, message: impl Into<String>) -> ScenarioError {
        ScenarioError {
            source: self.source.clone(),
            at: Some(line_col(self.text, span.start)),
            message: message.into(),
        }
    }

    fn positive(&self, v: &Spanned<f64>, what: &str) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                format!("{what} must be a positive number, not {x}"),
            ))
        }
    }

    /// A positive length (`what`) of at most [`MAX_EXTENT`], its key named `key` in errors.
    fn extent(&self, v: &Spanned<f64>, key: &str, what: &str) -> Result<f64, ScenarioError> {
        let x = self.positive(v, what)?;
        if x <= MAX_EXTENT {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                format!("{key} = {}: at most {MAX_EXTENT} R", num(x)),
            ))
        }
    }

    /// `diversity`: `"variance"`, `{ kind = "variance" }` or `{ kind = "entropy", bin = b }`
    /// with `b` finite and `> 0`.
    fn diversity(&self, raw: &Raw) -> Result<Measure, ScenarioError> {
        const FORMS: &str =
            "diversity must be \"variance\" or { kind = \"entropy\", bin = 0.5 } (bin > 0)";
        let Some(v) = &raw.diversity else {
            return Ok(Measure::Variance);
        };
        let bad = |why: String| Err(self.err(v.span(), format!("{why}; {FORMS}")));
        match v.get_ref() {
            toml::Value::String(s) if s == "variance" => Ok(Measure::Variance),
            toml::Value::String(s) if s == "entropy" => {
                bad("diversity = \"entropy\" needs a bin width".into())
            }
            toml::Value::String(s) => bad(format!("unknown diversity {s:?}")),
            toml::Value::Table(t) => {
                if let Some(k) = t.keys().find(|k| !matches!(k.as_str(), "kind" | "bin")) {
                    return bad(format!("unknown key diversity.{k}"));
                }
                let bin = match t.get("bin") {
                    None => None,
                    Some(toml::Value::Float(b)) => Some(*b),
                    Some(toml::Value::Integer(b)) => Some(*b as f64),
                    Some(b) => return bad(format!("diversity.bin = {b} is not a number")),
                };
                match (t.get("kind").and_then(toml::Value::as_str), bin) {
                    (Some("variance"), None) => Ok(Measure::Variance),
                    (Some("variance"), Some(_)) => {
                        bad("diversity.bin is only for kind = \"entropy\"".into())
                    }
                    (Some("entropy"), Some(b)) => match Measure::entropy(b as f32) {
                        Some(m) if b.is_finite() && b <= f64::from(f32::MAX) => Ok(m),
                        _ => bad(format!(
                            "diversity.bin = {} must be a positive number",
                            num(b)
                        )),
                    },
                    (Some("entropy"), None) => bad("diversity.bin is missing".into()),
                    (Some(k), _) => bad(format!("unknown diversity.kind {k:?}")),
                    (None, _) => bad("diversity.kind is missing".into()),
                }
            }
            other => bad(format!("diversity = {other} is neither a name nor a table")),
        }
    }

    fn finite(&self, v: &Spanned<f64>, what: &str) -> Result<f64, ScenarioError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), format!("{what} must be a finite number, not {x}")))
        }
    }

    fn range(&self, from: f64, to: f64, step: &Spanned<f64>) -> Result<Vec<f64>, ScenarioError> {
        let s = self.positive(step, "the step")?;
        let n = ((to - from) / s + 1e-9).floor();
        if !(from.is_finite() && to.is_finite() && (0.0..=100_000.0).contains(&n)) {
            return Err(self.err(
                step.span(),
                format!("from {from} to {to} by {s} is not a range of 1 to 100,001 values"),
            ));
        }
        Ok((0..=n as u64).map(|k| from + k as f64 * s).collect())
    }
}

/// Checks that a negotiation period of `params` is at most [`MAX_PERIOD_SECS`], naming the
/// keys it comes from.
fn period_fits(params: &Params) -> Result<(), PeriodError> {
    let run = RunConfig::paper(*params);
    match run.check() {
        Err(SimError::PeriodTooLong {
            gather_cycles,
            decide_cycles,
            cycle_s,
        }) => Err(PeriodError::TooLong {
            gather_cycles,
            decide_cycles,
            cycle_s,
        }),
        Err(e) => Err(PeriodError::Sim(e)),
        Ok(()) => Ok(()),
    }
}

/// Why [`period_fits`] refused a scenario's parameters.
#[derive(Debug, thiserror::Error)]
enum PeriodError {
    /// A negotiation period longer than [`MAX_PERIOD_SECS`], told by the keys it comes from.
    #[error(
        "cycle = {cycle_s} makes a negotiation period of (gather_cycles + decide_cycles) × \
         cycle = ({gather_cycles} + {decide_cycles}) × {cycle_s} s = {} s; at most \
         {MAX_PERIOD_SECS} s",
        (u128::from(*gather_cycles) + u128::from(*decide_cycles)) * u128::from(*cycle_s)
    )]
    TooLong {
        /// Gathering cycles per period.
        gather_cycles: u16,
        /// Deciding cycles per period.
        decide_cycles: u16,
        /// The cycle, whole seconds.
        cycle_s: u64,
    },
    /// Another reason the run cannot be.
    #[error(transparent)]
    Sim(SimError),
}
