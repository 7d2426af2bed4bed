//! SVG figures with plotters' SVG backend: pure Rust, no system fonts or libraries (text is
//! written as SVG `<text>` and laid out by the viewer).
//!
//! Only what does not know the experiments: plain x–y figures ([`xy_figure`], [`Line`]), the
//! legend strip every figure puts between its title and its plots ([`Key`], [`Entry`],
//! [`legend_height`], [`draw_legend`]) and the field's colours ([`palette`]). The figures of the
//! experiments are drawn with them in `pages::figures`.

mod legend;
pub mod palette;
mod xy;

pub use legend::{Entry, Key, draw_legend, legend_height};
pub use xy::{Line, xy_figure};

/// Any failure while drawing or writing a figure.
pub type PlotError = Box<dyn std::error::Error + Send + Sync>;

/// The font of every figure's text.
pub const FONT: &str = "sans-serif";
