//! Helpers the integration tests of `host-sim` share: running the `cimax` binary, and a scratch
//! directory per test process. Each test file that needs them says `mod common;`.

// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `cimax` binary of this build with `args` and returns what it did.
pub fn cimax(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cimax"))
        .args(args)
        .output()
        .expect("cimax runs")
}

/// A scratch directory for `what`, `cimax-WHAT-PID` in the system's temporary directory (not
/// created): one per test process, so parallel test runs do not share files.
pub fn scratch(what: &str) -> PathBuf {
    std::env::temp_dir().join(format!("cimax-{what}-{}", std::process::id()))
}

/// A rayon pool of `threads` worker threads, to check that results do not depend on their
/// number.
pub fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// Runs `cimax ARGS...` in `dir` (created).
pub fn cimax_in(dir: &Path, args: &[&str]) -> Output {
    std::fs::create_dir_all(dir).unwrap();
    Command::new(env!("CARGO_BIN_EXE_cimax"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("cimax runs")
}

/// Bytes as text (lossy), for messages and searches.
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every file under `dir`, by its path relative to `dir`, with its bytes.
pub fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_path_buf();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// `cimax merge PARTS... --out out`, run in `dir`.
pub fn merge_in(dir: &Path, parts: &[&PathBuf]) -> Output {
    let mut args: Vec<&str> = vec!["merge"];
    args.extend(parts.iter().map(|p| p.to_str().unwrap()));
    args.extend(["--out", "out"]);
    cimax_in(dir, &args)
}

/// A merge in `dir` that must fail: exit code 2, `message` on stderr, and `dir/out` left as it
/// was.
pub fn refused(dir: &Path, parts: &[&PathBuf], message: &str) {
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("keep.txt"), "mine").unwrap();
    let m = merge_in(dir, parts);
    assert_eq!(m.status.code(), Some(2), "{}", text(&m.stdout));
    assert!(text(&m.stderr).contains(message), "{}", text(&m.stderr));
    assert!(m.stdout.is_empty(), "{}", text(&m.stdout));
    let left: Vec<PathBuf> = files(&out).into_keys().collect();
    assert_eq!(left, [PathBuf::from("keep.txt")], "nothing written");
}
