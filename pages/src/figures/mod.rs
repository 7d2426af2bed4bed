//! The experiments' SVG figures, drawn with `report::plot`'s helpers (legend strip, field
//! colours, x–y figures).
//!
//! One file per kind of figure: a run's trajectory ([`run_figure`]), a sweep against the
//! initial position ([`sweep_figure`]), a preferred-direction map ([`direction_figure`]) over the
//! field's colouring (`field.rs`), the cloud's radial profile ([`radial_figure`]), the averaged
//! time courses ([`time_course_figure`]), the shapes' direction histograms ([`shapes_figure`])
//! and the wave's snapshots ([`waves_figure`]), each of the last two with its CSV file; and the
//! arena's: the fault campaign's charts ([`success_chart`], [`rules_chart`]) and the timeline of
//! one lab run ([`draw_timeline`]).

mod direction;
mod field;
mod lab_timeline;
mod radial;
mod reliability;
mod run;
mod shapes;
mod sweep;
pub(crate) mod timecourse;
mod waves;

pub use direction::{MapMark, MapMarks, MapShape, direction_figure};
pub use lab_timeline::{Drawn, draw_timeline};
pub use radial::radial_figure;
pub use reliability::{rules_chart, success_chart};
pub use run::run_figure;
pub use shapes::{shapes_figure, write_shapes, write_shapes_csv};
pub use sweep::{SweepMark, sweep_figure};
pub use timecourse::{PaperMark, time_course_figure};
pub use waves::{waves_figure, write_waves_csv};
