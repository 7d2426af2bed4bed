//! # report: generic output
//!
//! CSV files and the number formatting of their cells ([`csv_files`]), and SVG figures that
//! know nothing of the experiments ([`plot`]: x–y figures, legends, the field's colours). A
//! leaf: it depends on no crate of the workspace, runs no experiment, and names none. The
//! `pages` crate turns the simulators' results into files through it.

use std::path::{Path, PathBuf};

pub mod csv_files;
pub mod plot;

/// The default `docs` directory of the workspace this binary was built in.
pub fn default_docs_dir() -> PathBuf {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("docs");
    docs.canonicalize().unwrap_or(docs)
}
