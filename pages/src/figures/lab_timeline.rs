//! The timeline of one lab run (`cimax arena --svg`): per robot, its LED colour as a band, its
//! wave state above it, frames sent as ticks and frames received as dots (red when garbled or
//! dropped); a time axis with labelled ticks below, and a legend. Readable at 1:1: text is at
//! least 11 px ([`FONT`]; plotters' SVG writes a font of size s as 0.81 s px).

use firmware::LedColor;
use hal_emu::judge::{LabRun, pattern_str};
use hal_emu::{ArenaConfig, TraceEvent};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Where the timeline draws: pixel coordinates on a plotters SVG canvas, one lane per robot.
struct Lanes {
    left: f64,
    width: f64,
    lane: f64,
    end_ms: f64,
}

impl Lanes {
    /// The x pixel of time `t_ms`.
    fn x(&self, t_ms: u64) -> i32 {
        (self.left + (self.width - self.left - 10.0) * (t_ms as f64 / self.end_ms)).round() as i32
    }

    /// The top pixel of robot `r`'s lane.
    fn y(&self, r: usize) -> i32 {
        (TOP + self.lane * r as f64).round() as i32
    }
}

/// The font size of labels: 12.1 px in the SVG.
const FONT: u32 = 15;
/// Where the first lane starts, below the title.
const TOP: f64 = 34.0;
/// The height of the time axis and of the legend below the lanes.
const AXIS: f64 = 46.0;
const LEGEND: f64 = 50.0;

/// The SVG canvas the timeline draws on.
type Canvas<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
/// What drawing the timeline returns.
pub type Drawn = Result<(), Box<dyn std::error::Error>>;

/// Draws the timeline of `run` (a run of `cfg`, traced) into `out` as SVG, with plotters (as
/// every other figure of `cimax`).
///
/// # Errors
/// Any failure to draw; `out` then holds what was drawn so far.
pub fn draw_timeline(cfg: &ArenaConfig, run: &LabRun, out: &mut String) -> Drawn {
    let n = cfg.positions.len();
    let end_s = cfg.duration.as_secs_f64().max(1.0);
    let lanes = Lanes {
        left: 80.0,
        width: 1200.0,
        lane: 40.0,
        end_ms: end_s * 1000.0,
    };
    let h = (TOP + lanes.lane * n as f64 + AXIS + LEGEND) as u32;
    {
        let root = SVGBackend::with_string(out, (1200, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let title = format!(
            "cimax arena: pattern {} (at the end), seed {}, {end_s:.0} s; per robot its wave \
             state, frames and LED colour",
            pattern_str(&run.lights),
            run.seed
        );
        root.draw(&Text::new(title, (8, 8), ("sans-serif", FONT + 1)))?;
        led_lanes(&root, &lanes, cfg, run)?;
        wave_bands(&root, &lanes, run, n)?;
        frame_marks(&root, &lanes, run)?;
        let below = lanes.y(n) + 4;
        time_axis(&root, &lanes, end_s, below)?;
        legend(&root, below + AXIS as i32)?;
        root.present()?;
    }
    Ok(())
}

/// The seconds between ticks of an axis `end_s` long: 1, 2 or 5 times a power of ten, at
/// most 12 ticks.
fn tick_step(end_s: f64) -> f64 {
    let mut step = 1.0;
    loop {
        for m in [1.0, 2.0, 5.0] {
            if end_s / (m * step) <= 12.0 {
                return m * step;
            }
        }
        step *= 10.0;
    }
}

/// The time axis at pixel row `y`: a line, a tick and label every [`tick_step`] seconds, and
/// its name.
fn time_axis(root: &Canvas<'_>, lanes: &Lanes, end_s: f64, y: i32) -> Drawn {
    let ink = RGBColor(0x33, 0x33, 0x33);
    let end_ms = (end_s * 1000.0) as u64;
    root.draw(&PathElement::new(
        vec![(lanes.x(0), y), (lanes.x(end_ms), y)],
        ink,
    ))?;
    let step = tick_step(end_s);
    let centred = ("sans-serif", FONT)
        .into_font()
        .color(&ink)
        .pos(Pos::new(HPos::Center, VPos::Top));
    let mut k = 0.0;
    while k * step <= end_s + 1e-9 {
        let x = lanes.x((k * step * 1000.0).round() as u64);
        root.draw(&PathElement::new(vec![(x, y), (x, y + 5)], ink))?;
        root.draw(&Text::new(
            format!("{}", k * step),
            (x, y + 7),
            centred.clone(),
        ))?;
        k += 1.0;
    }
    root.draw(&Text::new("time (s)", (4, y + 7), ("sans-serif", FONT)))?;
    Ok(())
}

/// The legend at pixel row `y`: each mark and colour with what it means, in two rows.
fn legend(root: &Canvas<'_>, y: i32) -> Drawn {
    let items: [(&str, RGBColor, u8); 8] = [
        ("LED left (L)", RGBColor(0x2e, 0x9d, 0x4a), 0),
        ("LED right (R)", RGBColor(0x2b, 0x6c, 0xd6), 0),
        ("LED off", RGBColor(0xd8, 0xd8, 0xd8), 0),
        ("wave: active", RGBColor(0xf0, 0xa0, 0x30), 1),
        ("wave: refractory", RGBColor(0xe0, 0x60, 0x60), 1),
        ("frame sent", BLACK, 2),
        ("frame received", RGBColor(0x55, 0x55, 0x55), 3),
        ("received garbled, or dropped", RED, 3),
    ];
    for (i, (label, colour, mark)) in items.iter().enumerate() {
        let (x, y) = (80 + 280 * (i as i32 % 4), y + 22 * (i as i32 / 4));
        match mark {
            0 => root.draw(&Rectangle::new(
                [(x, y + 3), (x + 22, y + 15)],
                colour.filled(),
            ))?,
            1 => root.draw(&Rectangle::new(
                [(x, y + 6), (x + 22, y + 11)],
                colour.filled(),
            ))?,
            2 => root.draw(&PathElement::new(
                vec![(x + 11, y + 3), (x + 11, y + 14)],
                *colour,
            ))?,
            _ => root.draw(&Circle::new((x + 11, y + 9), 3, colour.filled()))?,
        }
        root.draw(&Text::new(*label, (x + 30, y + 2), ("sans-serif", FONT)))?;
    }
    Ok(())
}

/// The LED colour of each robot over time, one lane per robot, with its label.
fn led_lanes(root: &Canvas<'_>, lanes: &Lanes, cfg: &ArenaConfig, run: &LabRun) -> Drawn {
    for r in 0..cfg.positions.len() {
        let y = lanes.y(r);
        root.draw(&Text::new(
            format!("robot {r}"),
            (4, y + 8),
            ("sans-serif", FONT),
        ))?;
        let mut segs: Vec<(u64, LedColor)> = vec![(0, LedColor::Off)];
        segs.extend(
            run.report
                .leds
                .iter()
                .filter(|c| c.robot == r)
                .map(|c| (c.t.as_millis(), c.color)),
        );
        for (i, &(t, c)) in segs.iter().enumerate() {
            let t2 = segs.get(i + 1).map_or(cfg.duration.as_millis(), |s| s.0);
            let fill = match c {
                LedColor::Green => RGBColor(0x2e, 0x9d, 0x4a),
                LedColor::Blue => RGBColor(0x2b, 0x6c, 0xd6),
                LedColor::Off => RGBColor(0xd8, 0xd8, 0xd8),
                LedColor::Sector(_) => RGBColor(0x8a, 0x4f, 0xd6),
            };
            let (x0, x1) = (lanes.x(t), lanes.x(t2).max(lanes.x(t) + 1));
            root.draw(&Rectangle::new([(x0, y + 10), (x1, y + 22)], fill.filled()))?;
        }
    }
    Ok(())
}

/// Wave states as a thin band above the LEDs: orange active, red refractory.
fn wave_bands(root: &Canvas<'_>, lanes: &Lanes, run: &LabRun, n: usize) -> Drawn {
    let mut since: Vec<Option<(u64, &str)>> = vec![None; n];
    for e in &run.report.trace {
        if let TraceEvent::State { t_ms, robot, state } = e
            && let Some(slot) = since.get_mut(*robot)
        {
            if let Some((t0, st)) = slot.take() {
                let fill = if st == "active" {
                    RGBColor(0xf0, 0xa0, 0x30)
                } else {
                    RGBColor(0xe0, 0x60, 0x60)
                };
                let y = lanes.y(*robot);
                let (x0, x1) = (lanes.x(t0), lanes.x(*t_ms).max(lanes.x(t0) + 1));
                root.draw(&Rectangle::new([(x0, y + 3), (x1, y + 8)], fill.filled()))?;
            }
            if *state != "inactive" {
                *slot = Some((*t_ms, state));
            }
        }
    }
    Ok(())
}

/// Frames sent (ticks), received (dots) and dropped (red rings), per robot.
fn frame_marks(root: &Canvas<'_>, lanes: &Lanes, run: &LabRun) -> Drawn {
    let grey = RGBColor(0x55, 0x55, 0x55);
    for e in &run.report.trace {
        match e {
            TraceEvent::Sent { t_ms, robot, .. } => {
                let (x, y) = (lanes.x(*t_ms), lanes.y(*robot));
                root.draw(&PathElement::new(vec![(x, y + 2), (x, y + 9)], BLACK))?;
            }
            TraceEvent::Received {
                t_ms,
                robot,
                garbled,
                corrupted,
                ..
            } => {
                let c = if *garbled || *corrupted > 0 {
                    RED
                } else {
                    grey
                };
                let at = (lanes.x(*t_ms), lanes.y(*robot) + 26);
                root.draw(&Circle::new(at, 1, c.filled()))?;
            }
            TraceEvent::Dropped { t_ms, robot, .. } => {
                let at = (lanes.x(*t_ms), lanes.y(*robot) + 26);
                root.draw(&Circle::new(at, 2, RED))?;
            }
            _ => {}
        }
    }
    Ok(())
}
