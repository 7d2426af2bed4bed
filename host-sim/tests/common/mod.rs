//! Helpers the integration tests of `host-sim` share: running the `cimax` binary, and a scratch
//! directory per test process. Each test file that needs them says `mod common;`.

// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use std::path::PathBuf;
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
