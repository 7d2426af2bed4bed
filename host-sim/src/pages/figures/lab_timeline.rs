//! The timeline of one lab run (`cimax arena --svg`): per robot, its LED colour as a band, its
//! wave state above it, frames sent as ticks and frames received as dots (red when garbled or
//! dropped).

use firmware::LedColor;
use hal_emu::judge::{LabRun, pattern_str};
use hal_emu::{ArenaConfig, TraceEvent};
use plotters::prelude::*;

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
        (30.0 + self.lane * r as f64).round() as i32
    }
}

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
        left: 70.0,
        width: 1200.0,
        lane: 40.0,
        end_ms: end_s * 1000.0,
    };
    let h = (40.0 + lanes.lane * n as f64) as u32;
    {
        let root = SVGBackend::with_string(out, (1200, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let title = format!(
            "pattern {} seed {}: wave state (orange active, red refractory), frames sent (ticks), \
             LED colour (green left, blue right, grey off), frames received (dots; red = garbled \
             or dropped); {end_s:.0} s",
            pattern_str(&run.lights),
            run.seed
        );
        root.draw(&Text::new(title, (70, 4), ("sans-serif", 11)))?;
        led_lanes(&root, &lanes, cfg, run)?;
        wave_bands(&root, &lanes, run, n)?;
        frame_marks(&root, &lanes, run)?;
        root.present()?;
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
            ("sans-serif", 11),
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
