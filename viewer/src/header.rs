//! A replay's set-up: what the page draws beneath the events.

use hal_emu::judge::{expected_without, leds_str, pattern_str};
use hal_emu::world::field::Field;
use hal_emu::{ArenaConfig, Point2, TraceEvent};
use serde::{Deserialize, Serialize};

use super::REPLAY_VERSION;

/// What kind of run a replay shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Robots on a line under lamps (`cimax arena`).
    Line,
    /// Robots on a plane over a field, moving as they decide (`cimax arena --field`).
    Plane,
    /// Agents of the 2D simulator (`cimax swarm run`).
    Swarm,
}

/// A light pattern from a time on, with the LEDs it should end in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PatternAt {
    /// From when, ms.
    pub t_ms: u64,
    /// One character per robot, `1` lit.
    pub lights: String,
    /// The LEDs expected under it (`L`, `R`, `-`), if it has a verdict.
    pub expected: Option<String>,
}

/// A field sampled on a grid, for the heat map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Heatmap {
    /// The centre of the first cell, in R.
    pub x0: f64,
    /// The centre of the first cell, in R.
    pub y0: f64,
    /// Cell size, in R.
    pub step: f64,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Row-major values (`ny` rows of `nx`), the field's noiseless mean.
    pub values: Vec<f32>,
    /// What the values are.
    pub label: String,
}

/// Where the swarm should go (planes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Goal {
    /// The line x = `x`, in R.
    pub x: f64,
    /// Success within this distance of the line, or (`None`) at or beyond it.
    pub within: Option<f64>,
    /// The criterion in words.
    pub text: String,
}

/// How the run was judged.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// True if it passed.
    pub success: bool,
    /// The LEDs at the end (`L`, `R`, `-`, or the sector's digit).
    pub leds: String,
    /// The LEDs expected at the end, if the run has such a verdict.
    pub expected: Option<String>,
    /// The verdict in words.
    pub text: String,
}

/// A run's set-up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// [`REPLAY_VERSION`].
    pub version: u32,
    /// What kind of run.
    pub kind: Kind,
    /// One line saying what ran (the page's title).
    pub title: String,
    /// The seed that replays it.
    pub seed: u64,
    /// How long it ran, ms.
    pub duration_ms: u64,
    /// Receive sectors per robot (sector `s` faces `s · 360°/K`; with two, 0 right, 1 left).
    pub sectors: u8,
    /// Each robot's id (its tag is `id mod 16`).
    pub ids: Vec<u16>,
    /// Each robot's position relative to the swarm's centre of mass, in R (the radio range).
    pub positions: Vec<[f64; 2]>,
    /// The centre of mass at the start, in R.
    pub start: [f64; 2],
    /// Airtime of one byte, ms.
    pub airtime_ms_per_byte: f64,
    /// The lamps (lines): each pattern from its time on.
    pub lights: Vec<PatternAt>,
    /// The field (planes).
    pub field: Option<Heatmap>,
    /// Where the swarm should go (planes).
    pub goal: Option<Goal>,
    /// How the run was judged.
    pub verdict: Option<Verdict>,
}

impl Header {
    /// A header with nothing in it yet.
    pub fn empty(kind: Kind) -> Self {
        Header {
            version: REPLAY_VERSION,
            kind,
            title: String::new(),
            seed: 0,
            duration_ms: 0,
            sectors: 2,
            ids: Vec::new(),
            positions: Vec::new(),
            start: [0.0, 0.0],
            airtime_ms_per_byte: 0.0,
            lights: Vec::new(),
            field: None,
            goal: None,
            verdict: None,
        }
    }
}

/// The header of an arena run of `cfg` whose trace is `trace`: robots, lamps and expected
/// LEDs (lines) or the field over where the swarm went (planes). Title, goal and verdict are
/// the caller's.
pub fn header_of(cfg: &ArenaConfig, trace: &[TraceEvent]) -> Header {
    let n = cfg.positions.len();
    let range = cfg.medium.range.max(f64::MIN_POSITIVE);
    let mut h = Header::empty(Kind::Line);
    h.seed = cfg.seed;
    h.duration_ms = cfg.duration.as_millis();
    h.sectors = cfg.robot.params.sectors;
    h.ids = cfg
        .ids
        .clone()
        .unwrap_or_else(|| (0..n).map(|i| i as u16).collect());
    h.airtime_ms_per_byte =
        1000.0 * f64::from(cfg.medium.bits_per_byte) / f64::from(cfg.medium.bitrate.max(1));
    let metres: Vec<[f64; 2]> = cfg
        .positions
        .iter()
        .map(|p| [p.x / range, p.y / range])
        .collect();
    let centre = mean(&metres);
    h.positions = metres
        .iter()
        .map(|p| [p[0] - centre[0], p[1] - centre[1]])
        .collect();
    h.start = centre;
    if let Some(plane) = &cfg.env.field {
        h.kind = Kind::Plane;
        let c = plane.centre(plane.start);
        h.start = [c.x, c.y];
        let rel: Vec<[f64; 2]> = plane.positions.iter().map(|p| [p.x, p.y]).collect();
        let m = mean(&rel);
        h.positions = rel.iter().map(|p| [p[0] - m[0], p[1] - m[1]]).collect();
        let mut centres = vec![h.start];
        for e in trace {
            if let TraceEvent::Moved {
                centre,
                heading: Some(a),
                step,
                ..
            } = e
            {
                centres.push(*centre);
                centres.push([centre[0] + step * a.cos(), centre[1] + step * a.sin()]);
            }
        }
        let reach = h
            .positions
            .iter()
            .map(|p| p[0].hypot(p[1]))
            .fold(0.0, f64::max);
        h.field = Some(heatmap(&plane.field, &centres, reach + 1.0, "X"));
    } else {
        let absent = hal_emu::judge::absent(cfg);
        h.lights = cfg
            .env
            .schedule
            .iter()
            .map(|(t, p)| PatternAt {
                t_ms: t.as_millis(),
                lights: pattern_str(p),
                expected: expected_without(p, &absent).map(|l| leds_str(&l)),
            })
            .collect();
    }
    h
}

/// `field` on a grid of about 120 cells across, covering `centres` with `margin` R around
/// them (values rounded to 1/1000).
pub fn heatmap(field: &Field, centres: &[[f64; 2]], margin: f64, label: &str) -> Heatmap {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for c in centres {
        for a in 0..2 {
            lo[a] = lo[a].min(c[a] - margin);
            hi[a] = hi[a].max(c[a] + margin);
        }
    }
    if !lo[0].is_finite() {
        (lo, hi) = ([-margin; 2], [margin; 2]);
    }
    let step = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 120.0).max(1e-3);
    let nx = ((hi[0] - lo[0]) / step).ceil() as usize + 1;
    let ny = ((hi[1] - lo[1]) / step).ceil() as usize + 1;
    let mut values = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let p = Point2::new(lo[0] + i as f64 * step, lo[1] + j as f64 * step);
            values.push(((field.mean(p) * 1000.0).round() / 1000.0) as f32);
        }
    }
    Heatmap {
        x0: lo[0],
        y0: lo[1],
        step,
        nx,
        ny,
        values,
        label: label.into(),
    }
}

/// The mean of points.
fn mean(p: &[[f64; 2]]) -> [f64; 2] {
    let n = p.len().max(1) as f64;
    let s = p.iter().fold([0.0, 0.0], |s, q| [s[0] + q[0], s[1] + q[1]]);
    [s[0] / n, s[1] / n]
}

/// The goal of a scenario's success criterion.
pub fn goal_of(success: Option<swarm_sim::scenario::Success>) -> Option<Goal> {
    use swarm_sim::scenario::Success;
    success.map(|s| match s {
        Success::NearX { x, within } => Goal {
            x,
            within: Some(within),
            text: s.to_string(),
        },
        Success::BeyondX { x } => Goal {
            x,
            within: None,
            text: s.to_string(),
        },
    })
}

/// The verdict of a run that moves toward `goal`: met after `after` of at most `limit` moves
/// (or periods, `unit`), ending at `end`, with `leds` at the end.
pub fn move_verdict(
    goal: Option<&Goal>,
    after: Option<u32>,
    limit: u32,
    unit: &str,
    end: [f64; 2],
    leds: String,
) -> Verdict {
    let [x, y] = end;
    let text = match (after, goal) {
        (Some(m), Some(g)) => format!(
            "passed: {} after {m} {unit}; at the end ({x:.2}, {y:.2})",
            g.text
        ),
        (None, Some(g)) => format!(
            "FAILED: not {} within {limit} {unit}; at the end ({x:.2}, {y:.2})",
            g.text
        ),
        (_, None) => format!("no criterion for this field; at the end ({x:.2}, {y:.2})"),
    };
    Verdict {
        success: after.is_some(),
        leds,
        expected: None,
        text,
    }
}
