//! SVG figures with plotters' SVG backend: pure Rust, no system fonts or libraries (text is
//! written as SVG `<text>` and laid out by the viewer).
//!
//! One file per kind of figure: a run's trajectory ([`run_figure`]), a sweep against the
//! initial position ([`sweep_figure`]), a preferred-direction map ([`direction_figure`]) and
//! plain x–y figures ([`xy_figure`], [`radial_figure`]); beside them the field's colouring
//! (`field.rs`) and the legend strip every figure puts between its title and its plots
//! ([`Key`], [`Entry`]).

mod direction;
mod field;
mod legend;
mod run;
mod sweep;
mod xy;

pub use direction::{MapMark, MapMarks, MapShape, direction_figure};
pub use legend::{Entry, Key};
pub use run::run_figure;
pub use sweep::{SweepMark, sweep_figure};
pub use xy::{Line, radial_figure, xy_figure};

/// Any failure while drawing or writing a figure.
pub type PlotError = Box<dyn std::error::Error + Send + Sync>;

/// The font of every figure's text.
const FONT: &str = "sans-serif";
