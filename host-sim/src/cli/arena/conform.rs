//! `cimax arena conform`: the same robot program, built for the host and for Cortex-M, on the
//! same seeds (issue 35, docs/hil.md "Conformance"). Each run of a suite goes twice: with the
//! robots in the loop as host twins (`loopback`: the very program the HIL image runs,
//! `firmware::hil::robot::run`, built for the host, on the same lockstep), then as QEMU robots
//! on the arena's clock. The LED changes of the two, with their times, must be the same; where
//! they are not, the first difference is printed.

use std::process::ExitCode;

use clap::{Args, Parser};
use hal_emu::judge::{LabRun, judge};
use hal_emu::world::arena::LedChange;
use hal_emu::world::hil::{HilClock, Transport};
use hal_emu::{ArenaConfig, ArenaError};

use super::ArenaArgs;
use super::line::build;
use crate::cli::out::{Exit, Fail, outln};
use lab::line::Experiment;

/// Options of `cimax arena conform`.
#[derive(Args, Debug, Clone)]
pub struct ConformArgs {
    /// The `cimax arena` options of the suite to run twice, as for `cimax arena` (default: the
    /// paper's suite, one run per experiment, `--hil qemu:4`). The robots in the loop must be
    /// QEMU robots on the arena's clock.
    #[arg(
        trailing_var_arg = true,
        allow_hyphen_values = true,
        value_name = "ARENA OPTIONS"
    )]
    pub arena: Vec<String>,
}

/// `cimax arena`'s options, parsed on their own.
#[derive(Parser, Debug)]
#[command(name = "cimax arena conform")]
struct Arena {
    #[command(flatten)]
    args: ArenaArgs,
}

/// The arena options of `c`, with the defaults: `--runs 1`, `--hil qemu:4`.
fn options(c: &ConformArgs) -> Result<ArenaArgs, clap::Error> {
    let has = |flag: &str| {
        c.arena
            .iter()
            .any(|a| a == flag || a.starts_with(&format!("{flag}=")))
    };
    let mut argv = vec!["cimax arena conform".to_string()];
    if !has("--runs") {
        argv.extend(["--runs".into(), "1".into()]);
    }
    if !has("--hil") {
        argv.extend(["--hil".into(), "qemu:4".into()]);
    }
    argv.extend(c.arena.iter().cloned());
    Arena::try_parse_from(argv).map(|a| a.args)
}

/// `e`'s runs with the robots in the loop in this process (the host build).
fn on_the_host(e: &Experiment) -> Vec<ArenaConfig> {
    e.configs
        .iter()
        .map(|c| {
            let mut c = c.clone();
            for h in &mut c.hil {
                h.transport = Transport::InProcess;
                h.clock = HilClock::Virtual;
            }
            c
        })
        .collect()
}

/// The first place where two LED logs differ: `(time s, robot, host's, QEMU's)`, each side's
/// change at that place (or `-` if its log ended).
fn first_difference(
    host: &[LedChange],
    qemu: &[LedChange],
) -> Option<(f64, usize, String, String)> {
    let show = |c: Option<&LedChange>| {
        c.map_or_else(
            || "-".to_string(),
            |c| format!("{:?} at {:.3} s", c.color, c.t.as_millis() as f64 / 1000.0),
        )
    };
    let i = (0..host.len().max(qemu.len())).find(|&i| host.get(i) != qemu.get(i))?;
    let (a, b) = (host.get(i), qemu.get(i));
    let first = [a, b]
        .into_iter()
        .flatten()
        .min_by_key(|c| (c.t, c.robot))?;
    Some((
        first.t.as_millis() as f64 / 1000.0,
        first.robot,
        show(a),
        show(b),
    ))
}

/// What one run gave: its LED log, or why it has none.
fn leds(r: Result<LabRun, ArenaError>) -> Result<Vec<LedChange>, String> {
    r.map(|r| r.report.leds).map_err(|e| e.to_string())
}

/// Runs `cimax arena conform`: exit 0 if every pair of runs is the same, 1 if one differs, 2 on
/// bad options.
pub(super) fn main(c: &ConformArgs) -> Exit {
    let args = match options(c) {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return Ok(ExitCode::from(2));
        }
    };
    let experiments = build(&args)?;
    let follows = experiments
        .iter()
        .flat_map(|e| &e.configs)
        .all(|c| !c.hil.is_empty() && c.hil.iter().all(|h| h.follows()));
    if !follows {
        return Err(Fail::Input(
            "the robots in the loop must be QEMU robots on the arena's clock (--hil qemu:N, \
             --hil-clock virtual)"
                .into(),
        ));
    }
    outln!("experiment      seed  LED changes  host build = Cortex-M build")?;
    let (mut same, mut all) = (0, 0);
    for e in &experiments {
        for (host, qemu) in on_the_host(e).iter().zip(&e.configs) {
            all += 1;
            let (a, b) = (leds(judge(host)), leds(judge(qemu)));
            let verdict = match (&a, &b) {
                (Ok(a), Ok(b)) => match first_difference(a, b) {
                    None => {
                        same += 1;
                        format!("{:>11}  identical", a.len())
                    }
                    Some((t, robot, x, y)) => format!(
                        "{:>11}  DIFFER first at {t:.3} s, robot {robot}: host {x}, QEMU {y}",
                        a.len()
                    ),
                },
                (Err(x), _) => format!("{:>11}  host build failed: {x}", "-"),
                (_, Err(y)) => format!("{:>11}  Cortex-M build failed: {y}", "-"),
            };
            outln!("{:<15} {:>4}  {verdict}", e.label, qemu.seed)?;
        }
    }
    outln!("{same} of {all} runs identical (LED changes and their times)")?;
    Ok(if same == all {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
