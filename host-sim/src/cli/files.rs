//! One place for output paths: every file or folder a command writes is checked before any
//! work ([`check_file`], [`check_dir`]), written to a temporary file beside it and moved in
//! only when all the command's files are written ([`Staged`]), and named in every error.
//!
//! The rule for missing folders, the same for every option: the parents of an output are
//! created (`--csv new/x.csv` makes `new/`); an existing file where a folder is needed, or a
//! folder where a file is needed, is refused before any work.

use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// The closest existing ancestor of `p` (`p` itself if it exists), `.` if none.
fn existing_ancestor(p: &Path) -> PathBuf {
    let mut a = p;
    loop {
        if a.as_os_str().is_empty() {
            return PathBuf::from(".");
        }
        if a.exists() {
            return a.to_path_buf();
        }
        match a.parent() {
            Some(up) => a = up,
            None => return PathBuf::from("."),
        }
    }
}

/// `Ok` if `dir`, or the parents created for it, can be a folder: its closest existing
/// ancestor is a folder.
fn check_ancestors(option: &str, p: &Path, dir: &Path) -> Result<(), String> {
    let a = existing_ancestor(dir);
    if a.is_dir() {
        Ok(())
    } else {
        Err(format!(
            "{option} {}: {} is a file, not a folder",
            p.display(),
            a.display()
        ))
    }
}

/// Checks output file `p` of `option` (`--csv`) before any work: not a folder, and its folder
/// is one or can be created.
///
/// # Errors
/// A message naming the option, the path and the problem.
pub fn check_file(option: &str, p: &Path) -> Result<(), String> {
    if p.as_os_str().is_empty() {
        return Err(format!("{option}: an empty path"));
    }
    if p.is_dir() {
        return Err(format!(
            "{option} {}: is a folder; a file is needed",
            p.display()
        ));
    }
    check_ancestors(option, p, p.parent().unwrap_or(Path::new("")))
}

/// Checks output folder `p` of `option` (`--out-dir`) before any work: a folder, or one that
/// can be created.
///
/// # Errors
/// A message naming the option, the path and the problem.
pub fn check_dir(option: &str, p: &Path) -> Result<(), String> {
    if p.as_os_str().is_empty() {
        return Err(format!("{option}: an empty path"));
    }
    if p.exists() && !p.is_dir() {
        return Err(format!(
            "{option} {}: is a file; a folder is needed",
            p.display()
        ));
    }
    check_ancestors(option, p, p)
}

/// Refuses two outputs on one path, or an output on an input: `(option, path)` pairs.
///
/// # Errors
/// A message naming both options and the path.
pub fn check_distinct(paths: &[(&str, &Path)]) -> Result<(), String> {
    for (i, (a, p)) in paths.iter().enumerate() {
        for (b, q) in &paths[..i] {
            if same(p, q) {
                return Err(format!("{b} and {a} name the same file, {}", p.display()));
            }
        }
    }
    Ok(())
}

/// True if `a` and `b` are the same file (by their canonical paths where they exist).
fn same(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// A temporary file in `dir`, created with the mode a plain `File::create` gives (0666 less
/// the umask), not tempfile's private 0600: it becomes the output.
fn temp_in(dir: &Path) -> std::io::Result<NamedTempFile> {
    let mut b = tempfile::Builder::new();
    b.prefix(".cimax-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        b.permissions(std::fs::Permissions::from_mode(0o666));
    }
    b.tempfile_in(dir)
}

/// The checkout's `docs/` folder ([`report::default_docs_dir`]), the default of
/// the commands that regenerate its pages, if the working folder is inside that checkout;
/// outside it the command must be told where to write (`option`).
///
/// # Errors
/// Outside the checkout: a message naming the checkout and `option`.
pub fn checkout_docs(option: &str) -> Result<PathBuf, String> {
    let docs = report::default_docs_dir();
    let root = docs.parent().unwrap_or(&docs).to_path_buf();
    let here = std::env::current_dir()
        .and_then(|d| d.canonicalize())
        .map_err(|e| format!("the working folder: {e}"))?;
    if here.starts_with(&root) {
        Ok(docs)
    } else {
        Err(format!(
            "the default output is the docs/ folder of the checkout cimax was built from ({}); \
             {} is outside it: give {option}",
            docs.display(),
            here.display()
        ))
    }
}

/// Output files written beside their places and moved in together ([`Staged::commit`]); on
/// drop without a commit, the temporary files are removed and nothing is moved in.
#[derive(Default)]
pub struct Staged {
    files: Vec<(NamedTempFile, PathBuf)>,
}

impl Staged {
    /// No files yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes `path` (created parents included) through `write`, which is handed the path of
    /// a temporary file beside it to write instead.
    ///
    /// # Errors
    /// `path` and what went wrong: its folder not made, the temporary file, `write`'s error.
    pub fn write_with<E: std::fmt::Display>(
        &mut self,
        path: &Path,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<(), String> {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
        std::fs::create_dir_all(dir).map_err(|e| err(&e))?;
        let tmp = temp_in(dir).map_err(|e| err(&e))?;
        write(tmp.path()).map_err(|e| {
            // The writer names the temporary file; the user knows the real one.
            let said = e.to_string();
            let said = said.replace(&format!("{}: ", tmp.path().display()), "");
            err(&said.replace(
                &tmp.path().display().to_string(),
                &path.display().to_string(),
            ))
        })?;
        self.files.push((tmp, path.to_path_buf()));
        Ok(())
    }

    /// Writes `bytes` to `path` ([`Staged::write_with`]).
    ///
    /// # Errors
    /// As [`Staged::write_with`].
    pub fn write(&mut self, path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), String> {
        self.write_with(path, |tmp| std::fs::write(tmp, bytes.as_ref()))
    }

    /// Moves every file in, in the order written.
    ///
    /// # Errors
    /// The first file not moved in, by its path.
    pub fn commit(self) -> Result<(), String> {
        for (tmp, path) in self.files {
            tmp.persist(&path)
                .map_err(|e| format!("{}: {}", path.display(), e.error))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_checked_and_files_move_in_only_on_commit() {
        let dir = std::env::temp_dir().join(format!("cimax-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let afile = dir.join("afile");
        std::fs::write(&afile, "x").unwrap();
        assert_eq!(
            check_dir("--out-dir", &afile).unwrap_err(),
            format!(
                "--out-dir {}: is a file; a folder is needed",
                afile.display()
            )
        );
        assert!(
            check_file("--csv", &dir)
                .unwrap_err()
                .contains("is a folder")
        );
        let under = afile.join("x.csv");
        assert!(
            check_file("--csv", &under)
                .unwrap_err()
                .contains("is a file, not a folder")
        );
        assert!(check_file("--csv", &dir.join("new/deeper/x.csv")).is_ok());
        assert!(check_distinct(&[("--trace", &afile), ("--svg", &afile)]).is_err());

        let out = dir.join("sub/out.txt");
        let mut staged = Staged::new();
        staged.write(&out, "hello").unwrap();
        let failed = staged.write_with(&dir.join("sub/bad.txt"), |_| Err("no luck"));
        assert_eq!(
            failed.unwrap_err(),
            format!("{}: no luck", dir.join("sub/bad.txt").display())
        );
        assert!(!out.exists(), "nothing moved in before the commit");
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "hello");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&out).unwrap().permissions().mode();
            assert_ne!(
                mode & 0o044,
                0,
                "readable by others as File::create makes it: {mode:o}"
            );
        }
        let left: Vec<_> = std::fs::read_dir(dir.join("sub")).unwrap().collect();
        assert_eq!(left.len(), 1, "no temporary file left");

        let mut dropped = Staged::new();
        dropped.write(&dir.join("sub/never.txt"), "x").unwrap();
        drop(dropped);
        assert!(!dir.join("sub/never.txt").exists());
        assert_eq!(std::fs::read_dir(dir.join("sub")).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
