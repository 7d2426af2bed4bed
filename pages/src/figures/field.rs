//! The field under a figure: its mean X as coloured rectangles, pale yellow (low) to red
//! (high) as in the paper's figures.

use plotters::prelude::*;

use hal_emu::world::field::Field;
use report::plot::PlotError;
use report::plot::palette::level_colour;

type Rect = ((f64, f64), (f64, f64), u8);

/// The field as coloured rectangles over `[x0, x1] × [y0, y1]`: a grid of cells in 24 colour
/// levels, merged along rows and then between identical rows, so that a border is a handful of
/// rectangles, not thousands.
fn field_rects(field: &Field, x: (f64, f64), y: (f64, f64), cells: usize) -> (Vec<Rect>, f64, f64) {
    let (lo, hi) = field.range_over(x, y);
    let (dx, dy) = ((x.1 - x.0) / cells as f64, (y.1 - y.0) / cells as f64);
    let level = |v: f64| {
        if hi > lo {
            (((v - lo) / (hi - lo)) * 23.0).round() as u8
        } else {
            0
        }
    };
    let mut out: Vec<Rect> = Vec::new();
    let mut prev_row: Vec<(usize, usize, u8)> = Vec::new();
    let mut prev_start = 0usize;
    let flush = |runs: &[(usize, usize, u8)], r0: usize, r1: usize, out: &mut Vec<Rect>| {
        for &(c0, c1, l) in runs {
            out.push((
                (x.0 + c0 as f64 * dx, y.0 + r0 as f64 * dy),
                (x.0 + c1 as f64 * dx, y.0 + r1 as f64 * dy),
                l,
            ));
        }
    };
    for r in 0..cells {
        let yc = y.0 + (r as f64 + 0.5) * dy;
        let mut row: Vec<(usize, usize, u8)> = Vec::new();
        for c in 0..cells {
            let l = level(field.mean(nalgebra::Point2::new(x.0 + (c as f64 + 0.5) * dx, yc)));
            match row.last_mut() {
                Some(last) if last.2 == l => last.1 = c + 1,
                _ => row.push((c, c + 1, l)),
            }
        }
        if row != prev_row {
            flush(&prev_row, prev_start, r, &mut out);
            prev_row = row;
            prev_start = r;
        }
    }
    flush(&prev_row, prev_start, cells, &mut out);
    (out, lo, hi)
}

pub(super) fn draw_field<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    field: &Field,
    x: (f64, f64),
    y: (f64, f64),
    high_is_yellow: bool,
) -> Result<(f64, f64), PlotError>
where
    DB::ErrorType: 'static,
{
    let (rects, lo, hi) = field_rects(field, x, y, 120);
    chart
        .draw_series(
            rects
                .into_iter()
                .map(|(a, b, l)| Rectangle::new([a, b], level_colour(l, high_is_yellow).filled())),
        )
        .map_err(|e| e.to_string())?;
    Ok((lo, hi))
}

pub(super) fn square_range(
    xs: impl Iterator<Item = (f64, f64)> + Clone,
    pad: f64,
) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in xs {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let half = 0.5 * (x1 - x0).max(y1 - y0) + pad;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    ((cx - half, cx + half), (cy - half, cy + half))
}
