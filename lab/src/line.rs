//! The lab experiment on a line (paper section 4): robots in a line under light patterns,
//! each pattern an [`Experiment`] over many seeds, run in parallel ([`run_all`]) and judged by
//! their LEDs (`hal_emu::judge`). `cimax arena` builds the experiments from its options and
//! prints the runs; the fault campaign ([`crate::campaign`]) runs lab patterns under faults.

use hal_emu::judge::{LabRun, judge, pattern_str};
use hal_emu::world::arena::RobotFailure;
use hal_emu::{ArenaConfig, ArenaError};
use protocol::Instant;
use rayon::prelude::*;
use swarm_sim::progress::Progress;

/// One experiment: a list of runs sharing a label and an expected outcome.
#[derive(Clone, Debug)]
pub struct Experiment {
    /// The pattern, or e.g. `1000>0001` where it changes.
    pub label: String,
    /// One configuration per seed.
    pub configs: Vec<ArenaConfig>,
}

/// The options that replay a run of `cfg` alone: its first pattern (`--lights`) and, if the
/// pattern changes, when and to what (`--switch-at`, `--then`).
pub fn replay_lights(cfg: &ArenaConfig) -> String {
    let mut out = String::new();
    for (i, (t, p)) in cfg.env.schedule.iter().enumerate() {
        if i == 0 {
            out += &format!("--lights {}", pattern_str(p));
        } else {
            let ms = t.saturating_since(Instant::ZERO).as_millis();
            let at = format!("{}.{:03}", ms / 1000, ms % 1000);
            let at = at.trim_end_matches('0').trim_end_matches('.');
            out += &format!(" --switch-at {at} --then {}", pattern_str(p));
        }
    }
    out
}

/// How `hal_emu` says that a robot in the loop's link did not open (its `RobotFailure`'s
/// message).
const LINK_NOT_OPEN: &str = "its link did not open";

/// The runs of a list of experiments: judged, or crashed (a robot stopped on its own).
#[derive(Debug, Default)]
pub struct Runs {
    /// The judged runs, each with its experiment's index.
    pub judged: Vec<(usize, LabRun)>,
    /// The runs in which a robot stopped on its own, without LEDs to judge (they failed): the
    /// experiment's index, the configuration's index in it, and the robot's failure.
    pub crashed: Vec<(usize, usize, RobotFailure)>,
}

/// Runs every configuration of every experiment in parallel (one at a time with robots in the
/// loop, in real time): the runs and the wall time in seconds.
///
/// # Errors
/// A set-up error ([`ArenaError`]), among them a robot in the loop whose link never opened
/// (nothing listening, no such serial port) and an interrupted run; a robot that stops on its
/// own is a crashed run, not an error.
pub fn run_all(experiments: &[Experiment]) -> Result<(Runs, f64), ArenaError> {
    let jobs: Vec<(usize, usize, &ArenaConfig)> = experiments
        .iter()
        .enumerate()
        .flat_map(|(i, e)| e.configs.iter().enumerate().map(move |(k, c)| (i, k, c)))
        .collect();
    let real_time = jobs.iter().any(|(_, _, c)| c.real_time());
    let secs = |c: &ArenaConfig| c.duration.as_millis().div_ceil(1000);
    let bar = if real_time {
        // Robots in the loop: the bar moves with the seconds, even for one run.
        let total = jobs.iter().map(|(_, _, c)| secs(c)).sum();
        Progress::seconds(total, "arena (real time)")
    } else if jobs.len() > 1 {
        Progress::new(jobs.len() as u64, "arena", false)
    } else {
        Progress::hidden()
    };
    let wall = std::time::Instant::now();
    // Each run is independent and seeded: the results do not depend on the thread count.
    let one = |c: &ArenaConfig| {
        let r = judge(c);
        bar.inc();
        r
    };
    // Runs with robots in the loop go in real time, one at a time (the robots are one board,
    // or QEMU processes that need the cores); the others in parallel.
    let results: Vec<Result<LabRun, ArenaError>> = if real_time {
        jobs.iter()
            .map(|(_, _, c)| bar.while_running(secs(c), || judge(c)))
            .collect()
    } else {
        jobs.par_iter().map(|(_, _, c)| one(c)).collect()
    };
    bar.finish();
    let wall_s = wall.elapsed().as_secs_f64();
    let mut runs = Runs::default();
    // Runs in which a robot stopped on its own (a panic): failed, without LEDs to judge. A robot
    // in the loop whose link never opened (nothing listening, no such serial port) is a set-up
    // error, not a failed run.
    for ((i, k, _), r) in jobs.iter().zip(results) {
        match r {
            Ok(r) => runs.judged.push((*i, r)),
            Err(ArenaError::Robot(f)) if !f.panicked && f.message.starts_with(LINK_NOT_OPEN) => {
                return Err(ArenaError::Hil(format!("robot {}: {}", f.robot, f.message)));
            }
            Err(ArenaError::Robot(f)) => runs.crashed.push((*i, *k, f)),
            Err(e) => return Err(e),
        }
    }
    Ok((runs, wall_s))
}
