//! `cimax`: the CIMAX command-line tool.
//!
//! - `cimax arena` runs the paper's four-robot lab experiment (section 4), see [`cli::arena`].
//! - `cimax swarm run|sweep|field|reproduce|bench` are the paper's 2D simulations (section 3),
//!   over the `swarm-sim` crate, see [`cli::swarm`].
//! - `cimax view TRACE -o PAGE.html` makes the replay viewer's page of a saved trace
//!   ([`viewer`]).
//! - `cimax merge PARTS... --out DIR` puts the parts of a sharded `arena sweep`, `arena
//!   campaign` or `swarm sweep` (`--shard I/N`) together, see [`cli::merge`].
//!
//! This file only parses the command line and dispatches: `cimax swarm` runs in `cli/swarm.rs`,
//! `cimax arena` in `cli/arena/`.

mod cli;

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use cli::arena;
use cli::swarm::SwarmCommand;

/// The most worker threads `--threads` asks for (each has a stack; more than the cores only
/// costs memory).
const MAX_THREADS: u64 = 1024;

#[derive(Parser, Debug)]
#[command(
    name = "cimax",
    version,
    about = "CIMAX swarm tools: the lab arena and the paper's 2D swarm simulations",
    allow_negative_numbers = true
)]
struct Cli {
    /// Worker threads for runs in parallel, 1 to 1024 (default: all cores). Results do not
    /// depend on it.
    #[arg(long, global = true, value_parser = crate::cli::values::whole::<usize>(1, MAX_THREADS))]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The lab experiment in the emulated arena: robots in a line running the robot program
    /// over an emulated light medium; with no options the paper's six patterns and the
    /// alternating experiment from each to its mirror image, five runs each, judged by the LEDs.
    Arena(Box<arena::ArenaArgs>),
    /// The paper's 2D simulations (section 3): a swarm of agents running the three-phase CIMAX.
    Swarm {
        #[command(subcommand)]
        command: SwarmCommand,
    },
    /// The replay viewer's page of a saved `cimax arena --trace` (docs/viewer.md): one HTML
    /// file that opens offline.
    View {
        /// The trace (JSON lines, as `cimax arena --trace` writes them).
        trace: std::path::PathBuf,
        /// The page to write (its folder is created); `-` writes it to standard output.
        #[arg(short, long, value_name = "FILE.html")]
        output: std::path::PathBuf,
    },
    /// The parts of a command run with `--shard I/N` (`arena sweep`, `arena campaign`, `swarm
    /// sweep`) put together: checks that they are one job, complete and without overlap, then
    /// writes and prints what the command unsharded would.
    Merge(cli::merge::MergeArgs),
}

/// `cimax view`: the page of a saved trace.
fn view(trace: &std::path::Path, output: &std::path::Path) -> cli::out::Exit {
    let to_stdout = output.as_os_str() == "-";
    if !to_stdout {
        cli::files::check_file("--output", output)?;
        cli::files::check_distinct(&[("the trace", trace), ("--output", output)])?;
    }
    let text = std::fs::read_to_string(trace).map_err(|e| format!("{}: {e}", trace.display()))?;
    let source = trace.display().to_string();
    let (header, events) = viewer::read_trace(&text, &source).map_err(|e| {
        // A trace of events only, as `arena campaign --trace` wrote them before they had the
        // set-up line.
        let first: Option<serde_json::Value> = text
            .lines()
            .next()
            .and_then(|l| serde_json::from_str(l).ok());
        match first {
            Some(v) if v.get("event").is_some() => format!(
                "{source}: events without the run's set-up (an `arena campaign --trace` of an \
                 older cimax); `cimax view` reads traces that start with it, as `cimax arena \
                 --trace` and `cimax arena campaign --trace` write them now"
            ),
            _ => e.to_string(),
        }
    })?;
    if to_stdout {
        let page = viewer::page(&viewer::Replay::from_trace(header, &events))
            .map_err(|e| e.to_string())?;
        cli::out::text(&page)?;
    } else {
        let mut staged = cli::files::Staged::new();
        staged.write_with(output, |p| viewer::write_page(p, header, &events))?;
        staged.commit()?;
    }
    Ok(ExitCode::SUCCESS)
}

/// Exit codes: 0 success; 1 a failed experiment (a run that failed its verdict, a missed bar)
/// or standard output that cannot be written; 2 a usage, input or set-up error (clap's own
/// errors included); 130 interrupted. A closed standard output (`cimax arena | head`) ends
/// quietly with 0, as `cat` does.
fn main() -> ExitCode {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some(n) = cli.threads
        && let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
    {
        eprintln!("error: cannot start {n} threads: {e}");
        return ExitCode::from(2);
    }
    match cli.command {
        Command::Arena(args) => {
            let m = matches.subcommand_matches("arena").unwrap_or(&matches);
            arena::main(&args, m)
        }
        Command::Swarm { command } => {
            let res = cli::swarm::run(command).map(|()| ExitCode::SUCCESS);
            cli::out::finish("error", res.map_err(cli::out::Fail::from))
        }
        Command::View { trace, output } => cli::out::finish("cimax view", view(&trace, &output)),
        Command::Merge(args) => cli::merge::main(&args),
    }
}
