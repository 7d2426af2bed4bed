//! `cimax merge PARTS... --out DIR`: the parts of a sharded command (`--shard I/N`) put back
//! together, and written as the command would have written them unsharded.
//!
//! [`host_sim::shard::merge::merge`] checks the parts (one job, complete, no overlap); then the
//! job's command writes its outputs from the merged results with the very function its
//! unsharded run uses. A command that shards adds one entry to [`COMMANDS`].

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use host_sim::shard::merge::{Merged, merge};

use super::out::{Exit, finish};
use super::{arena, swarm};

/// Options of `cimax merge`.
#[derive(clap::Args, Debug, Clone)]
pub struct MergeArgs {
    /// The part files (`part-I-of-N.jsonl`, as `--shard I/N` writes them), in any order.
    #[arg(required = true, value_name = "PARTS")]
    pub parts: Vec<PathBuf>,
    /// The directory to write the command's outputs into, created if missing (its `--out`; for `arena campaign`
    /// the page goes to DIR/reliability.md with its figures in DIR/figures/, for `swarm
    /// reproduce` to DIR/reproduction.md and DIR/figures/, as its `--docs DIR`).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// A sharded command's merge: the outputs of the merged job into the directory, and the
/// command's exit code.
type MergeFn = fn(&Merged, &Path) -> Exit;

/// The commands whose parts `cimax merge` reads, by the `job.command` of their headers.
const COMMANDS: [(&str, MergeFn); 4] = [
    (arena::SWEEP_COMMAND, arena::merge_sweep),
    (arena::CAMPAIGN_COMMAND, arena::merge_campaign),
    (swarm::SWEEP_COMMAND, swarm::merge_sweep),
    (swarm::REPRODUCE_COMMAND, swarm::merge_reproduce),
];

/// Runs `cimax merge`: the merged command's exit code, or 2 (and nothing written) if the parts
/// do not merge.
pub fn main(a: &MergeArgs) -> ExitCode {
    finish("cimax merge", run(a))
}

/// `cimax merge`, its failures as values.
fn run(a: &MergeArgs) -> Exit {
    super::files::check_dir("--out", &a.out)?;
    let merged = merge(&a.parts).map_err(|e| e.to_string())?;
    let command = merged.job.command.as_str();
    let Some((_, write)) = COMMANDS.iter().find(|(c, _)| *c == command) else {
        let known: Vec<&str> = COMMANDS.iter().map(|(c, _)| *c).collect();
        return Err(format!(
            "{}: parts of {command:?}, which this cimax does not merge (it merges {})",
            merged
                .parts
                .first()
                .map_or(String::new(), |p| p.display().to_string()),
            known.join(", ")
        )
        .into());
    };
    write(&merged, &a.out)
}
