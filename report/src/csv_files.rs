//! Writing CSV files with the `csv` crate ([`create`]) and the number formatting of their cells
//! and of the pages' text: a fixed number of decimals ([`fixed`]), or an empty cell ([`opt`]).
//! The experiments' own files are written by `pages::csv`.

use std::path::Path;

/// A CSV writer on `path` (parent directories created). `csv::Writer` buffers, and its errors
/// convert into `std::io::Error` with `?`.
pub fn create(path: &Path) -> std::io::Result<csv::Writer<std::fs::File>> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    Ok(csv::Writer::from_path(path)?)
}

/// `v` with `digits` decimal places.
pub fn fixed(v: f64, digits: usize) -> String {
    format!("{v:.digits$}")
}

/// `v` with `digits` decimal places, or an empty cell.
pub fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or(String::new(), |v| fixed(v, digits))
}
