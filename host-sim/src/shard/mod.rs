//! Splitting a long command over many processes or machines (`--shard I/N`) and putting the
//! pieces back together (`cimax merge`).
//!
//! A command that shards numbers its work in units (one run, say) in a fixed order; the whole
//! job is `0..total`. Unsharded, it computes every unit ([`compute`]) and writes its outputs
//! from the list of results. With `--shard I/N` it computes only its share ([`spec`]) and
//! writes that as one part file ([`part`]); `cimax merge` reads all the parts, checks them
//! ([`merge`]) and hands the command the same list of results, which it writes with the same
//! function, so that the outputs are the very same bytes.
//!
//! Where to start: [`ShardSpec`] (which units are whose), [`run_shard`] (one shard's run),
//! [`merge::merge`] (the checks). What it never does: write a half part under its final name,
//! panic on a part's bytes, or depend on the order the parts are given in.

pub mod merge;
pub mod part;
pub mod spec;

use std::fmt::Display;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;

pub use part::{Job, PartError};
pub use spec::ShardSpec;
use swarm_sim::progress::Progress;

/// How long a job took and on how many threads: measured for an unsharded run, the shards'
/// wall times added up (and their most threads) for a merged one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Wall time, s.
    pub wall_s: f64,
    /// Worker threads.
    pub threads: usize,
}

/// Computes `f` for each of `units`, in parallel, and returns the results in the order of
/// `units`; `progress` steps once per unit.
///
/// # Errors
/// The first error of a unit, in unit order.
pub fn compute<U, E, F>(units: &[u64], progress: &Progress, f: F) -> Result<Vec<U>, E>
where
    U: Send,
    E: Send,
    F: Fn(u64) -> Result<U, E> + Sync,
{
    let out = units
        .par_iter()
        .map(|&k| {
            let r = f(k);
            progress.inc();
            r
        })
        .collect();
    progress.finish();
    out
}

/// Runs shard `shard` of `job` (`total` units, unit `k` computed by `f`) and writes its part
/// into `dir`: says on stderr what its share is, shows progress with the time left (unless
/// `quiet`), and returns the part's path.
///
/// # Errors
/// A unit's error, or the part not written.
pub fn run_shard<U, E, F>(
    job: Job,
    total: u64,
    shard: ShardSpec,
    dir: &Path,
    quiet: bool,
    f: F,
) -> Result<PathBuf, ShardError<E>>
where
    U: Serialize + Send,
    E: Send + Display,
    F: Fn(u64) -> Result<U, E> + Sync,
{
    let wall = std::time::Instant::now();
    let units: Vec<u64> = shard.units(total).collect();
    announce(&job, total, shard, dir, units.len(), "runs");
    let progress = Progress::logged(units.len() as u64, &format!("shard {shard}"), quiet);
    let results = compute(&units, &progress, f).map_err(ShardError::Unit)?;
    Ok(write_shard(job, total, shard, dir, units, results, wall)?)
}

/// Runs shard `shard` of `job` as [`run_shard`] does, but its units one after another in unit
/// order, each free to use every thread itself: for units that are whole stages, which run
/// their own runs in parallel and time themselves (as `swarm reproduce`'s do). Its share and
/// progress are counted in units: `shard 2/3: 23 of 68 units of ...`.
///
/// # Errors
/// The first unit's error, or the part not written.
pub fn run_shard_in_order<U, E, F>(
    job: Job,
    total: u64,
    shard: ShardSpec,
    dir: &Path,
    quiet: bool,
    mut f: F,
) -> Result<PathBuf, ShardError<E>>
where
    U: Serialize,
    E: Display,
    F: FnMut(u64) -> Result<U, E>,
{
    let wall = std::time::Instant::now();
    let units: Vec<u64> = shard.units(total).collect();
    announce(&job, total, shard, dir, units.len(), "units");
    let label = format!("shard {shard}");
    let progress = Progress::logged_counting(units.len() as u64, &label, "units", quiet);
    let mut results = Vec::with_capacity(units.len());
    for &k in &units {
        results.push(f(k).map_err(ShardError::Unit)?);
        progress.inc();
    }
    progress.finish();
    Ok(write_shard(job, total, shard, dir, units, results, wall)?)
}

/// Says on stderr which share of the job the shard runs, and where its part goes.
fn announce(job: &Job, total: u64, shard: ShardSpec, dir: &Path, share: usize, noun: &str) {
    eprintln!(
        "shard {shard}: {share} of {total} {noun} of {}, into {}",
        job.command,
        dir.join(shard.file_name()).display()
    );
}

/// Writes the part of shard `shard` of `job` into `dir`: `results` of `units`, in the same
/// order, and the time since `wall`, with this process's threads.
fn write_shard<U: Serialize>(
    job: Job,
    total: u64,
    shard: ShardSpec,
    dir: &Path,
    units: Vec<u64>,
    results: Vec<U>,
    wall: std::time::Instant,
) -> Result<PathBuf, PartError> {
    let header = part::Header {
        format: part::FORMAT.into(),
        version: part::VERSION,
        cimax: part::CIMAX.into(),
        job,
        shard,
        units: total,
    };
    let numbered: Vec<(u64, U)> = units.into_iter().zip(results).collect();
    part::write_part(
        dir,
        &header,
        &numbered,
        wall.elapsed().as_secs_f64(),
        rayon::current_num_threads(),
    )
}

/// Why a shard did not write its part: one of its units failed (that unit's error), or the
/// part could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ShardError<E> {
    /// A unit's error.
    #[error("{0}")]
    Unit(E),
    /// The part could not be written.
    #[error(transparent)]
    Part(#[from] PartError),
}
