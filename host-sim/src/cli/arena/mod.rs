//! `cimax arena`: the paper's lab experiment (section 4) in the emulated arena, and its
//! subcommands.
//!
//! Virtual robots run the unchanged robot program (`firmware::Robot::run`) on emulated
//! hardware (`hal-emu`): a modulated-light medium with airtime, collisions, loss and byte
//! errors, and light patterns on their sensors. A run is judged by the LEDs, as a person
//! watching the robots would.
//!
//! This module holds the options ([`ArenaArgs`]) and dispatches: robots in a line under light
//! patterns ([`line`](mod@line)), robots on a plane over a field and `cimax arena bench` ([`plane`]),
//! `cimax arena sweep` ([`sweep`]), the fault campaign ([`campaign`]). The experiments themselves are the
//! library's [`lab`] and `hal_emu::judge`; [`options`] turns the options into
//! their configurations.

mod campaign;
mod conform;
mod line;
mod options;
mod plane;
mod print;
mod replay;
mod sweep;

use std::path::PathBuf;
use std::process::ExitCode;

use crate::cli::out::finish;
use clap::{Args, Subcommand};
use hal_emu::Readings;
use hal_emu::world::hil::HilSpec;
use lab::campaign::Decide;
use lab::plane::Layout;
use protocol::SwarmKey;
use swarm_sim::scenario::MAX_EXTENT;

pub use campaign::CampaignArgs;
pub(crate) use campaign::{COMMAND as CAMPAIGN_COMMAND, merge as merge_campaign};
pub use plane::BenchArgs;
pub use sweep::SweepArgs;
pub(crate) use sweep::{COMMAND as SWEEP_COMMAND, merge as merge_sweep};

/// Subcommands of `cimax arena`.
#[derive(Subcommand, Debug, Clone)]
pub enum ArenaCommand {
    /// Fault-injection campaign: every scenario over many seeds, with bars to meet; writes
    /// docs/reliability.md and exits 1 if a bar is missed.
    Campaign(CampaignArgs),
    /// Robots on a plane over a field: success rate and moves to success against the initial
    /// position, beside the 2D simulator's and the paper's (Figs. 6 and 9).
    Sweep(SweepArgs),
    /// Speed of the robot program over the emulated medium: robot-seconds per wall second for
    /// 4, 64 and 1000 robots on a plane, one negotiation period, one core.
    Bench(BenchArgs),
    /// The robot program built for the host and for Cortex-M, run for run: each run of a suite
    /// with the robots in the loop in this process, then as QEMU robots on the arena's clock;
    /// their LED changes and times must be the same (docs/hil.md, "Conformance").
    Conform(conform::ConformArgs),
}

/// The longest emulated run (or phase) `cimax arena` makes, in seconds: 11.6 days of robot time,
/// where the paper's runs last 2101 s. The LED log, the `--trace` and the wall time grow with it;
/// without a bound a huge `--duration` or `--cycle` would run for ever or exhaust memory.
pub const MAX_RUN_SECS: u64 = 1_000_000;

/// The most metres `--spacing` and `--range` take (a kilometre: light crosses a lab).
pub const MAX_METRES: f64 = 1000.0;

/// Options of `cimax arena`. With none, the paper's suite ([`paper_suite`](hal_emu::judge::paper_suite)): six patterns and
/// the alternating experiment from each to its mirror image, five runs each.
#[derive(Args, Debug, Clone)]
#[command(args_conflicts_with_subcommands = true, allow_negative_numbers = true)]
pub struct ArenaArgs {
    /// Number of robots: in a line with light patterns 2 to 64 (default: the pattern's length,
    /// else 4); with --field 2 to 1000 (default 61).
    #[arg(long, value_parser = crate::cli::values::whole::<u16>(2, 1000))]
    pub robots: Option<u16>,
    /// With --field: how the robots are placed (a line, the paper's hexagonal lattice 0.75 R
    /// apart, or a random disk of the paper's density).
    #[arg(long, value_parser = plane::shape_parser(), default_value = "lattice", requires = "field")]
    pub shape: Layout,
    /// With --field --shape file: the robots' positions, one `x y` per line, in R.
    #[arg(long, value_name = "FILE", requires = "field")]
    pub positions: Option<PathBuf>,
    /// With --field: receive sectors (receivers) per robot, 2 to 8.
    #[arg(long, default_value_t = 6, value_parser = crate::cli::values::whole::<u8>(2, 8), requires = "field")]
    pub sectors: u8,
    /// Robots on a plane over a field instead of light patterns: a `cimax swarm` scenario
    /// (sharp, gradient, cloud) or its TOML file. The swarm moves as it decides.
    #[arg(long)]
    pub field: Option<String>,
    /// With --field: where the centre of mass starts, in R along x.
    #[arg(long, default_value_t = -2.0, requires = "field", value_parser = crate::cli::values::number(-MAX_EXTENT, MAX_EXTENT, "a position in R"))]
    pub x_init: f64,
    /// With --field: negotiation periods (moves of 0.33 R) per run.
    #[arg(long, default_value_t = 50, value_parser = crate::cli::values::whole::<u32>(1, 1000), requires = "field")]
    pub moves: u32,
    /// Metres between neighbours (the light carries --range metres).
    #[arg(long, default_value_t = 1.0, value_parser = crate::cli::values::positive(MAX_METRES, "a number of metres"))]
    pub spacing: f64,
    /// Range of the light, metres.
    #[arg(long, default_value_t = hal_emu::MediumParams::LAB_RANGE, value_parser = crate::cli::values::positive(MAX_METRES, "a number of metres"))]
    pub range: f64,
    /// One light pattern instead of the paper's suite, one character per robot, 1 = lit.
    #[arg(long)]
    pub lights: Option<String>,
    /// Change the pattern at this time (seconds, to the millisecond, at most 1,000,000)...
    #[arg(long, requires = "then", value_parser = crate::cli::values::number(0.0, MAX_RUN_SECS as f64, "a number of seconds"))]
    pub switch_at: Option<f64>,
    /// ...to this pattern.
    #[arg(long, requires = "switch_at")]
    pub then: Option<String>,
    /// Base seed: run k uses seed + k. Failing runs print their seed.
    #[arg(long, default_value_t = 1, value_parser = crate::cli::values::whole::<u64>(0, u64::MAX))]
    pub seed: u64,
    /// Runs per pattern.
    #[arg(long, default_value_t = 5, value_parser = crate::cli::values::whole::<u64>(1, 100_000))]
    pub runs: u64,
    /// Emulated seconds per run (per phase in the alternating experiment), 1 to 1,000,000;
    /// default three negotiation periods of the longest cycle.
    #[arg(long, value_parser = crate::cli::values::whole::<u64>(1, MAX_RUN_SECS))]
    pub duration: Option<u64>,
    /// What the light sensors report: `full` (levels of 200 lit and 30 dark with noise ±10,
    /// or the field's level), `binary` (the paper's g in {0, 1}: 1 lit, 0 dark, without noise),
    /// `levels:N` (a coarser sensor of N levels, 2 to 256) or `gain:G,offset:B` (a sensor of
    /// another gain and offset, saturating at 0 and 255). None of these may change a decision.
    #[arg(long, value_name = "KIND", default_value_t = Readings::Levels, conflicts_with = "binary_readings")]
    pub readings: Readings,
    /// The same as `--readings binary`.
    #[arg(long)]
    pub binary_readings: bool,
    /// Probability that a frame is lost at a receiver.
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::number(0.0, 1.0, "a probability"))]
    pub loss: f64,
    /// Probability that a received byte is corrupted.
    #[arg(long, default_value_t = 0.0, value_parser = crate::cli::values::number(0.0, 1.0, "a probability"))]
    pub byte_error_rate: f64,
    /// Turn collisions of overlapping frames off.
    #[arg(long)]
    pub no_collisions: bool,
    /// Bits per second on air (the board's 9600 Bd IrDA SIR link; 10 bits per byte).
    #[arg(long, default_value_t = firmware::LIGHT_BITRATE, value_parser = crate::cli::values::whole::<u32>(1, u64::from(u32::MAX)))]
    pub bitrate: u32,
    /// Mean cycle length, seconds (the paper's 55).
    #[arg(long, value_parser = crate::cli::values::positive(MAX_RUN_SECS as f64, "a number of seconds"))]
    pub cycle: Option<f64>,
    /// Cycle spread, seconds (the paper's ±15).
    #[arg(long, value_parser = crate::cli::values::number(0.0, MAX_RUN_SECS as f64, "a number of seconds"))]
    pub cycle_spread: Option<f64>,
    /// Refractory time, seconds (the paper's 4).
    #[arg(long, value_parser = crate::cli::values::number(0.0, MAX_RUN_SECS as f64, "a number of seconds"))]
    pub refractory: Option<f64>,
    /// Negotiation period, cycles (the paper's 10).
    #[arg(long, value_parser = crate::cli::values::whole::<u16>(1, u64::from(u16::MAX)))]
    pub negotiation: Option<u16>,
    /// When a robot decides: at the end of each negotiation period (the paper's), or as soon as
    /// its evidence settles, at the latest at a period's end (docs/protocol.md §5.4).
    #[arg(long, value_enum, default_value_t = Decide::Fixed)]
    pub decide: Decide,
    /// Kill a robot: ROBOT@SECONDS (robots count from 0); repeatable.
    #[arg(long, value_parser = parse_at)]
    pub kill: Vec<(usize, u64)>,
    /// Restart a killed robot with fresh state: ROBOT@SECONDS; repeatable.
    #[arg(long, value_parser = parse_at)]
    pub restart: Vec<(usize, u64)>,
    /// Print a machine-readable JSON report on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write every frame sent, received or dropped, LED change and event as JSON lines
    /// (the first run only). Missing folders of --trace, --svg and --html are created; the
    /// files are moved in only when all are written.
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Draw a timeline per robot of frames and LED colour as SVG (the first run only).
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write the first run as one self-contained HTML page that replays it: waves, frames,
    /// LEDs, moves, consensus (docs/viewer.md). A failing run opens where it went wrong.
    #[arg(long, value_name = "FILE")]
    pub html: Option<PathBuf>,
    /// Swarm key, 32 hex digits (128 bits): every robot authenticates its frames and drops
    /// those without a valid MAC (docs/protocol.md, "Authenticated frames").
    #[arg(long, value_name = "HEX")]
    pub key: Option<SwarmKey>,
    /// Robots in the loop (docs/hil.md): `qemu:N` (N QEMU processes, each booting the
    /// one-robot HIL image), `serial:PATH[@BAUD]` (a board, 115200 Bd by default),
    /// `tcp:HOST:PORT` (anything speaking the link on a socket) or `loopback:N` (the robot
    /// program in this process, over the link). Repeatable. They take the first places of the
    /// line or plane (--hil-at picks others); the others stay virtual. QEMU robots run on the
    /// arena's clock (--hil-clock); with a board, or a socket robot on its own clock, the run
    /// goes in real time: shrink it with --cycle.
    #[arg(long, value_name = "SPEC")]
    pub hil: Vec<HilSpec>,
    /// Whose clock the robots in the loop run on (docs/hil.md, "Time"): `virtual`, the arena's,
    /// in lockstep (deterministic, faster than real time; the default for qemu: and
    /// loopback:), or `wall`, their own (the only one for serial:; the run goes in real time).
    /// Without it, a tcp: robot is asked before the run and runs on the clock its Hello says
    /// it can follow.
    #[arg(long, value_enum, value_name = "CLOCK", requires = "hil")]
    pub hil_clock: Option<HilClockArg>,
    /// The places of the robots in the loop, in the order of --hil: I,J,... (from 0).
    #[arg(long, value_name = "I,J,...", value_delimiter = ',', requires = "hil")]
    pub hil_at: Vec<usize>,
    /// The image --hil qemu:N boots (default: the HIL image `cargo hil-image` builds,
    /// firmware/qemu/target/thumbv7em-none-eabihf/release/hil, or hil6 for 6 sectors, under
    /// the working folder if it is there, else under the checkout cimax was built from).
    #[arg(long, value_name = "ELF", requires = "hil")]
    pub hil_image: Option<PathBuf>,
    /// `campaign`: the fault-injection campaign ([`campaign`]); `sweep` and `bench` on a plane.
    #[command(subcommand)]
    pub command: Option<Box<ArenaCommand>>,
}

/// `--hil-clock`: whose clock the robots in the loop run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum HilClockArg {
    /// The arena's, in lockstep.
    Virtual,
    /// Their own: the run goes in real time.
    Wall,
}

impl ArenaArgs {
    /// What the sensors report: `--readings`, binary with `--binary-readings`.
    pub fn readings(&self) -> Readings {
        if self.binary_readings {
            Readings::Binary
        } else {
            self.readings
        }
    }
}

fn parse_at(s: &str) -> Result<(usize, u64), String> {
    let (r, t) = s
        .split_once('@')
        .ok_or_else(|| format!("{s:?}: expected ROBOT@SECONDS, e.g. 3@600"))?;
    let r = r
        .trim()
        .parse()
        .map_err(|_| format!("{s:?}: {r:?} is not a robot number"))?;
    let t = t
        .trim()
        .parse()
        .map_err(|_| format!("{s:?}: {t:?} is not a whole number of seconds"))?;
    Ok((r, t))
}

/// Runs `cimax arena` (`matches`: its command line, which failed runs' replays repeat); the exit code is non-zero if any run with a verdict failed or an option
/// was bad.
pub fn main(args: &ArenaArgs, matches: &clap::ArgMatches) -> ExitCode {
    match args.command.as_deref() {
        Some(ArenaCommand::Campaign(c)) => finish("cimax arena campaign", campaign::main(c)),
        Some(ArenaCommand::Sweep(s)) => finish("cimax arena sweep", sweep::sweep_main(s)),
        Some(ArenaCommand::Bench(b)) => finish("cimax arena bench", plane::bench_main(b)),
        Some(ArenaCommand::Conform(c)) => finish("cimax arena conform", conform::main(c)),
        None if args.field.is_some() => finish("cimax arena", plane::main(args)),
        None => finish("cimax arena", line::main(args, matches)),
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::line::{build, run_all};
    use super::plane::plane_spec;
    use super::print::expected_str;
    use super::*;
    use clap::Parser as _;
    use hal_emu::judge::leds_str;
    use lab::line::replay_lights;

    /// `cimax arena` as the tool parses it (also the replay tests').
    #[derive(clap::Parser)]
    pub(super) struct Cli {
        #[command(subcommand)]
        pub(super) command: Cmd,
    }

    #[derive(clap::Subcommand)]
    pub(super) enum Cmd {
        Arena(ArenaArgs),
    }

    /// The options of `cimax arena ARGS...`.
    fn args(a: &[&str]) -> ArenaArgs {
        let cli = Cli::try_parse_from(["cimax", "arena"].iter().chain(a)).unwrap();
        let Cmd::Arena(args) = cli.command;
        args
    }

    #[test]
    fn the_default_suite_runs_every_pattern_and_its_mirror() {
        let experiments = build(&args(&[])).unwrap();
        let labels: Vec<&str> = experiments.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "1000",
                "0111",
                "0001",
                "1110",
                "1100",
                "0011",
                "1000>0001",
                "0111>1110",
                "0001>1000",
                "1110>0111",
                "1100>0011",
                "0011>1100"
            ]
        );
        let expected: Vec<String> = experiments
            .iter()
            .map(|e| expected_str(&e.configs[0]))
            .collect();
        assert_eq!(
            expected[6..],
            [
                "LLLL>RRRR",
                "LLLL>RRRR",
                "RRRR>LLLL",
                "RRRR>LLLL",
                "RRLL>RRLL",
                "RRLL>RRLL"
            ]
        );
        for e in &experiments {
            assert_eq!(e.configs.len(), 5, "{}", e.label);
            let seeds: Vec<u64> = e.configs.iter().map(|c| c.seed).collect();
            assert_eq!(seeds, [1, 2, 3, 4, 5]);
            for c in &e.configs {
                assert_eq!(c.env.readings, Readings::Levels);
                let phases = if e.label.contains('>') { 2 } else { 1 };
                assert_eq!(c.duration.as_millis(), phases * 2_101_000, "{}", e.label);
            }
        }
        // A failing run of an alternating experiment replays with its change.
        let last = &experiments[11].configs[2];
        assert_eq!(
            replay_lights(last),
            "--lights 0011 --switch-at 2101 --then 1100"
        );
        assert_eq!(replay_lights(&experiments[0].configs[0]), "--lights 1000");
        // One pattern with a change of its own: as before, no suite.
        let one = build(&args(&[
            "--lights",
            "10",
            "--switch-at",
            "60",
            "--then",
            "01",
        ]))
        .unwrap();
        assert_eq!(one.len(), 1);
        assert_eq!(one[0].label, "10>01");
        assert_eq!(
            replay_lights(&one[0].configs[0]),
            "--lights 10 --switch-at 60 --then 01"
        );
    }

    #[test]
    fn binary_readings_reach_every_run_and_its_replay() {
        let a = args(&["--binary-readings", "--runs", "1"]);
        let experiments = build(&a).unwrap();
        assert!(
            experiments
                .iter()
                .flat_map(|e| &e.configs)
                .all(|c| c.env.readings == Readings::Binary)
        );
        // The same as `--readings binary`; on a plane too.
        assert_eq!(
            build(&args(&["--readings", "binary", "--runs", "1"])).unwrap()[0].configs[0]
                .env
                .readings,
            Readings::Binary
        );
        assert_eq!(
            plane_spec(&args(&["--field", "sharp", "--binary-readings"]))
                .unwrap()
                .readings,
            Readings::Binary
        );
        let scaled = args(&["--readings", "gain:0.5,offset:100", "--runs", "1"]);
        assert_eq!(
            build(&scaled).unwrap()[0].configs[0]
                .env
                .readings
                .to_string(),
            "gain:0.5,offset:100"
        );
        // The whole suite with binary readings, one run each: every verdict holds.
        let ((runs, crashed), _) = run_all(&experiments).unwrap();
        assert!(crashed.is_empty());
        for (i, r) in &runs {
            assert!(
                r.success,
                "{} seed {}: LEDs {}",
                experiments[*i].label,
                r.seed,
                leds_str(&r.leds)
            );
        }
        let end = |label: &str| {
            let i = experiments.iter().position(|e| e.label == label).unwrap();
            runs.iter()
                .find(|(j, _)| *j == i)
                .map(|(_, r)| leds_str(&r.leds))
                .unwrap()
        };
        assert_eq!(end("1100>0011"), "RRLL");
        assert_eq!(end("0001>1000"), "LLLL");
        assert_eq!(end("0111>1110"), "RRRR");
    }
}
