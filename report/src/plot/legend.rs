//! The legend strip between a figure's title and its plots: entries in rows, each a key and
//! its text, so that no entry can cover data.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::palette::level_colour;
use super::{FONT, PlotError};

/// What a legend entry shows beside its text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Key {
    /// A filled box: a bar series.
    Bar(RGBColor),
    /// A pale box with a border: a shaded band.
    Band(RGBColor),
    /// A solid line.
    Line(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A hollow circle: one value at one point.
    Marker(RGBColor),
    /// An arrow: a swarm's preferred direction.
    Arrow,
    /// A dot: no direction.
    Dot,
    /// The field's colour ramp from low X to high X; `true` when high X is pale yellow.
    Ramp(bool),
}

/// A legend entry: its key and its text.
pub type Entry = (Key, String);

/// Height of one row of a legend strip, px.
const LEGEND_ROW: i32 = 20;
/// Width of a legend key, px.
const KEY_W: i32 = 24;
/// Font size of legend text, px.
const LEGEND_FONT: u32 = 13;

/// A generous estimate of the width of `text` in the legend font (SVG text is laid out by the
/// viewer: 0.6 em per character covers sans-serif).
fn text_width(text: &str) -> i32 {
    (text.chars().count() as f64 * 0.6 * f64::from(LEGEND_FONT)).ceil() as i32
}

/// Where each entry of a legend strip `width` px wide goes, (x, row), filling rows left to
/// right; and the number of rows.
fn legend_layout(width: i32, entries: &[Entry]) -> (Vec<(i32, i32)>, i32) {
    let (mut x, mut row) = (10, 0);
    let mut out = Vec::with_capacity(entries.len());
    for (_, text) in entries {
        let w = KEY_W + 6 + text_width(text) + 20;
        if x > 10 && x + w > width - 10 {
            row += 1;
            x = 10;
        }
        out.push((x, row));
        x += w;
    }
    (out, if entries.is_empty() { 0 } else { row + 1 })
}

/// Height of the legend strip of `entries` across `width` px (0 without entries).
pub fn legend_height(width: u32, entries: &[Entry]) -> u32 {
    let (_, rows) = legend_layout(width as i32, entries);
    if rows == 0 {
        0
    } else {
        (rows * LEGEND_ROW + 8) as u32
    }
}

/// Draws the key of a legend entry with its left end at `x` on the centre line `y` (px).
fn draw_key(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    key: Key,
    x: i32,
    y: i32,
) -> Result<(), PlotError> {
    match key {
        Key::Bar(c) => area.draw(&Rectangle::new(
            [(x, y - 6), (x + KEY_W, y + 6)],
            c.filled(),
        ))?,
        Key::Band(c) => {
            area.draw(&Rectangle::new(
                [(x, y - 6), (x + KEY_W, y + 6)],
                c.mix(0.2).filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x, y - 6), (x + KEY_W, y + 6)],
                c.stroke_width(1),
            ))?;
        }
        Key::Line(c) => area.draw(&PathElement::new(
            vec![(x, y), (x + KEY_W, y)],
            c.stroke_width(2),
        ))?,
        Key::Dashed(c) => {
            for (a, b) in [(0, 7), (11, 18), (22, KEY_W)] {
                area.draw(&PathElement::new(
                    vec![(x + a, y), (x + b, y)],
                    c.stroke_width(2),
                ))?;
            }
        }
        Key::Marker(c) => area.draw(&Circle::new((x + KEY_W / 2, y), 5, c.stroke_width(2)))?,
        Key::Arrow => {
            let style = BLACK.stroke_width(2);
            area.draw(&PathElement::new(vec![(x, y), (x + KEY_W, y)], style))?;
            area.draw(&PathElement::new(
                vec![
                    (x + KEY_W - 6, y - 4),
                    (x + KEY_W, y),
                    (x + KEY_W - 6, y + 4),
                ],
                style,
            ))?;
        }
        Key::Dot => area.draw(&Circle::new((x + KEY_W / 2, y), 2, BLACK.filled()))?,
        Key::Ramp(high_is_yellow) => {
            for i in 0..KEY_W {
                let l = (f64::from(i) * 23.0 / f64::from(KEY_W - 1)).round() as u8;
                area.draw(&Rectangle::new(
                    [(x + i, y - 6), (x + i + 1, y + 6)],
                    level_colour(l, high_is_yellow).filled(),
                ))?;
            }
        }
    }
    Ok(())
}

/// Draws `entries` in rows across `area`, a strip outside every plot, so that no entry can
/// cover data.
pub fn draw_legend(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    entries: &[Entry],
) -> Result<(), PlotError> {
    let (w, _) = area.dim_in_pixel();
    let (pos, _) = legend_layout(w as i32, entries);
    let font =
        TextStyle::from((FONT, LEGEND_FONT).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for ((key, text), (x, row)) in entries.iter().zip(pos) {
        let y = 4 + row * LEGEND_ROW + LEGEND_ROW / 2;
        draw_key(area, *key, x, y)?;
        area.draw(&Text::new(text.clone(), (x + KEY_W + 6, y), font.clone()))?;
    }
    Ok(())
}
