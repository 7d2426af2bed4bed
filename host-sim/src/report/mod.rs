//! What the experiments' results become: CSV files ([`csv_files`]), SVG figures ([`plot`], and
//! the arena's: [`reliability_plot`], [`lab_timeline`]) and the Markdown pages rendered from
//! templates ([`page`]). Shared by the arena and the swarm
//! simulator; it runs no experiment itself.

use std::path::{Path, PathBuf};

pub mod csv_files;
pub mod lab_timeline;
pub mod page;
pub mod plot;
pub mod reliability_plot;
pub mod shapes_plot;
pub mod timecourse_plot;
pub mod waves_plot;

pub use csv_files::{
    CycleRow, write_cycle_csv, write_field_csv, write_radial_csv, write_run_csv, write_sweep_csv,
};

/// The default `docs` directory of the workspace this binary was built in.
pub fn default_docs_dir() -> PathBuf {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("docs");
    docs.canonicalize().unwrap_or(docs)
}
