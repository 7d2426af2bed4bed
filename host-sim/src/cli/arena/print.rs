//! What `cimax arena` on a line prints: the table, the `--json` report, the robots in the
//! loop's links, and the failed or crashed runs with the commands that replay them.

use firmware::LedColor;
use hal_emu::judge::{LabRun, leds_str, pattern_str};
use hal_emu::world::arena::RobotFailure;
use hal_emu::world::hil::HilReport;
use hal_emu::{ArenaConfig, Readings};
use protocol::{Instant, Params};
use serde::Serialize;

use super::ArenaArgs;
use crate::cli::out::{Fail, StdoutError, outln};
use lab::line::{Experiment, replay_lights};

/// One run in the `--json` report.
#[derive(Serialize)]
pub(super) struct JsonRun {
    lights: String,
    expected: Option<String>,
    leds: String,
    /// Whether the LEDs were as expected; `null` for a pattern without a verdict (not judged).
    success: Option<bool>,
    consensus_s: Option<f64>,
    /// Robots that flickered: changed their LEDs after showing their side, before the lights
    /// changed (`hal_emu::judge::LabRun::flickers`).
    flickers: usize,
    seed: u64,
    emulated_s: f64,
    wall_s: f64,
    /// Why the run has no result (a robot panicked); absent for a judged run.
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
    /// Each robot in the loop's link (`--hil`): transport, frames each way, link errors.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    hil: Vec<HilReport>,
    /// Where the pattern changes (`--switch-at --then`, the suite's alternating runs): every
    /// pattern in turn, from when, with its verdict; absent for one pattern (`lights`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    patterns: Vec<JsonPattern>,
}

/// One pattern of a run whose pattern changes.
#[derive(Clone, Serialize)]
pub(super) struct JsonPattern {
    /// When it starts, seconds.
    at_s: f64,
    lights: String,
    /// The LEDs it asks for; `null` without a verdict.
    expected: Option<String>,
}

/// The patterns of a run of `cfg` if it has more than one, else none.
pub(super) fn patterns_of(cfg: &ArenaConfig) -> Vec<JsonPattern> {
    if cfg.env.schedule.len() < 2 {
        return Vec::new();
    }
    let absent = hal_emu::judge::absent(cfg);
    cfg.env
        .schedule
        .iter()
        .map(|(t, p)| JsonPattern {
            at_s: t.saturating_since(Instant::ZERO).as_secs_f64(),
            lights: pattern_str(p),
            expected: hal_emu::judge::expected_without(p, &absent).map(|e| leds_str(&e)),
        })
        .collect()
}

/// The `--json` summary.
#[derive(Serialize)]
pub(super) struct JsonSummary {
    pub(super) runs: usize,
    pub(super) successes: usize,
    /// Runs of a pattern without a verdict (`--lights 1010`): neither successes nor failures.
    pub(super) not_judged: usize,
    pub(super) emulated_s: f64,
    pub(super) wall_s: f64,
}

/// The `--json` report: every run and the summary.
#[derive(Serialize)]
struct JsonReport {
    runs: Vec<JsonRun>,
    summary: JsonSummary,
}

/// Prints the `--json` report.
pub(super) fn print_json(
    experiments: &[Experiment],
    runs: &[(usize, LabRun)],
    crashed: &[(usize, Crashed)],
    summary: JsonSummary,
) -> Result<(), Fail> {
    let report = JsonReport {
        runs: runs
            .iter()
            .map(|(i, r)| JsonRun {
                lights: pattern_str(&r.lights),
                expected: r.expected.as_deref().map(leds_str),
                leds: leds_str(&r.leds),
                success: r.expected.is_some().then_some(r.success),
                consensus_s: r.consensus_s,
                flickers: r.flickers,
                seed: r.seed,
                emulated_s: r.report.emulated.as_secs_f64(),
                wall_s: r.report.wall.as_secs_f64(),
                error: None,
                hil: r.report.hil.clone(),
                patterns: experiments[*i]
                    .configs
                    .iter()
                    .find(|c| c.seed == r.seed)
                    .map(patterns_of)
                    .unwrap_or_default(),
            })
            .chain(crashed.iter().map(|(_, c)| c.json()))
            .collect(),
        summary,
    };
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    outln!("{text}")?;
    Ok(())
}

/// One line per robot in the loop: its link over all runs.
pub(super) fn print_hil(runs: &[(usize, LabRun)]) -> Result<(), StdoutError> {
    let mut places: std::collections::BTreeMap<usize, (String, HilReport, usize)> =
        std::collections::BTreeMap::new();
    for (_, r) in runs {
        for h in &r.report.hil {
            let e = places
                .entry(h.robot)
                .or_insert_with(|| (h.transport.clone(), HilReport::default(), 0));
            e.1.frames_sent += h.frames_sent;
            e.1.frames_received += h.frames_received;
            e.1.link_errors += h.link_errors;
            e.1.tx += h.tx;
            e.1.hello_ms = e.1.hello_ms.max(h.hello_ms);
            e.1.bytes_sent += h.bytes_sent;
            e.1.bytes_received += h.bytes_received;
            // The mean over runs, weighted by round trips.
            let trips = e.1.round_trips + h.round_trips;
            if let Some(mean) = (e.1.rtt_mean_us * e.1.round_trips + h.rtt_mean_us * h.round_trips)
                .checked_div(trips)
            {
                e.1.rtt_mean_us = mean;
            }
            e.1.round_trips = trips;
            e.1.rtt_max_us = e.1.rtt_max_us.max(h.rtt_max_us);
            e.1.lockstep |= h.lockstep;
            e.2 += 1;
        }
    }
    for (robot, (transport, h, n)) in places {
        let timing = if h.lockstep {
            format!(
                "on the arena's clock, {} lockstep rounds (Sync and Idle)",
                h.round_trips
            )
        } else {
            format!(
                "heartbeat round trip {:.2} ms mean, {:.2} ms max",
                h.rtt_mean_us as f64 / 1000.0,
                h.rtt_max_us as f64 / 1000.0
            )
        };
        outln!(
            "robot {robot} in the loop over {transport}: {n} runs, {} link frames ({} B) sent to it, {} ({} B) received with {} light frames, {} link errors; hello within {} ms, {timing}",
            h.frames_sent,
            h.bytes_sent,
            h.frames_received,
            h.bytes_received,
            h.tx,
            h.link_errors,
            h.hello_ms,
        )?;
    }
    Ok(())
}

/// The command that replays one run: `cimax arena`, its patterns (`lights`,
/// [`replay_lights`]), its seed, one run, and the command line's other options (`extra`,
/// [`super::replay::replay_options`]).
pub(super) fn replay_command(lights: &str, seed: u64, extra: &str) -> String {
    format!("cimax arena {lights} --seed {seed} --runs 1{extra}")
}

/// One line on stderr per failed or crashed run (each failed run with the `--lights` options
/// that replay it, [`replay_lights`]), with the command that replays it.
pub(super) fn print_failures(
    extra: &str,
    failures: &[(&LabRun, String, Option<String>)],
    crashed: &[(usize, Crashed)],
) {
    for (r, lights, earlier) in failures {
        let flicker = r
            .flicker
            .map(|(t, robot)| {
                format!("; robot {robot}'s LEDs changed at {t:.0} s, after it showed its side")
            })
            .unwrap_or_default();
        let flicker = match earlier {
            Some(why) => format!("{flicker}; {why}"),
            None => flicker,
        };
        eprintln!(
            "FAILED {} seed {}: LEDs {}, expected {}{flicker} (replay: {})",
            pattern_str(&r.lights),
            r.seed,
            leds_str(&r.leds),
            r.expected.as_deref().map(leds_str).unwrap_or_default(),
            replay_command(lights, r.seed, extra)
        );
    }
    for (_, c) in crashed {
        eprintln!("{}", c.failed_line(extra));
    }
}

/// Why a run of `cfg` failed before its last pattern, if it did: the first earlier pattern
/// whose verdict the LEDs did not show when it changed (a switch before the first decision
/// leaves them off).
pub(super) fn earlier_pattern_failed(cfg: &ArenaConfig, run: &LabRun) -> Option<String> {
    let absent = hal_emu::judge::absent(cfg);
    cfg.env.schedule.windows(2).find_map(|w| {
        let ((_, p), (to, _)) = (&w[0], &w[1]);
        let expected = hal_emu::judge::expected_without(p, &absent)?;
        let leds = run.report.leds_at(*to - protocol::Duration::from_millis(1));
        if leds == expected {
            return None;
        }
        let at = to.saturating_since(Instant::ZERO).as_secs_f64();
        let leds = leds_str(&leds);
        let why = if leds.chars().all(|c| c == '-') {
            " (a switch before the first decision: no robot had decided yet)"
        } else {
            ""
        };
        Some(format!(
            "but pattern {} showed LEDs {leds} when it changed at {at} s, expected {}{why}",
            pattern_str(p),
            leds_str(&expected)
        ))
    })
}

/// A run in which a robot stopped on its own ([`hal_emu::ArenaError::Robot`]: its task panicked, or it
/// could not boot). It has no LEDs worth judging: it failed.
pub(super) struct Crashed {
    /// The pattern at the end of the run (what a judged run reports as its lights).
    lights: Vec<bool>,
    /// The LEDs the run should have ended with, if its pattern has a verdict.
    expected: Option<Vec<LedColor>>,
    /// Which robot, why, and the seed.
    failure: RobotFailure,
    /// The options that replay it ([`replay_lights`]).
    replay: String,
    /// Its patterns, if it changes ([`patterns_of`]).
    patterns: Vec<JsonPattern>,
}

impl Crashed {
    pub(super) fn new(cfg: &ArenaConfig, failure: RobotFailure) -> Self {
        let (lights, expected) = hal_emu::judge::crash_verdict(cfg);
        Crashed {
            lights,
            expected,
            failure,
            replay: replay_lights(cfg),
            patterns: patterns_of(cfg),
        }
    }

    /// The `FAILED` line on stderr, like a judged run's, with the command that replays it.
    fn failed_line(&self, extra: &str) -> String {
        let (lights, seed) = (pattern_str(&self.lights), self.failure.seed);
        format!(
            "FAILED {lights} seed {seed}: {}, expected {} (replay: {})",
            self.failure.what(),
            self.expected.as_deref().map(leds_str).unwrap_or_default(),
            replay_command(&self.replay, seed, extra),
        )
    }

    /// The run in the `--json` report: no LEDs, not a success, and the error.
    fn json(&self) -> JsonRun {
        JsonRun {
            lights: pattern_str(&self.lights),
            expected: self.expected.as_deref().map(leds_str),
            leds: String::new(),
            success: Some(false),
            consensus_s: None,
            flickers: 0,
            seed: self.failure.seed,
            emulated_s: 0.0,
            wall_s: 0.0,
            error: Some(self.failure.what()),
            hil: Vec::new(),
            patterns: self.patterns.clone(),
        }
    }
}

/// What the LEDs of a run of `cfg` should show: the verdict of its pattern, or of each pattern
/// in turn where the pattern changes (`LLLL>RRRR`); `(none)` for a pattern without a verdict.
pub(super) fn expected_str(cfg: &ArenaConfig) -> String {
    let absent = hal_emu::judge::absent(cfg);
    cfg.env
        .schedule
        .iter()
        .map(|(_, p)| {
            hal_emu::judge::expected_without(p, &absent).map_or("(none)".into(), |e| leds_str(&e))
        })
        .collect::<Vec<_>>()
        .join(">")
}

/// The table of every experiment: expected LEDs, the LEDs of each run, success, mean time to
/// consensus and speed.
pub(super) fn print_table(
    args: &ArenaArgs,
    experiments: &[Experiment],
    runs: &[(usize, LabRun)],
    crashed: &[(usize, Crashed)],
) -> Result<(), StdoutError> {
    let cycle_s = args
        .cycle
        .unwrap_or(Params::robots().wave.cycle.as_secs_f64());
    outln!(
        "CIMAX lab arena: robots in a line running the robot program over the emulated light medium{}",
        match args.readings() {
            Readings::Binary => "; binary readings (g = 1 lit, 0 dark)".to_string(),
            Readings::Levels => String::new(),
            r => format!("; readings {r}"),
        }
    )?;
    outln!(
        "{:<12} {:<10} {:<36} {:>8} {:>24} {:>9}",
        "pattern",
        "expected",
        "LEDs per run",
        "success",
        "consensus s (cycles)",
        "speed"
    )?;
    for (i, e) in experiments.iter().enumerate() {
        let rs: Vec<&LabRun> = runs
            .iter()
            .filter(|(j, _)| *j == i)
            .map(|(_, r)| r)
            .collect();
        let crashes: Vec<&Crashed> = crashed
            .iter()
            .filter(|(j, _)| *j == i)
            .map(|(_, c)| c)
            .collect();
        let ok = rs.iter().filter(|r| r.success).count();
        let times: Vec<f64> = rs.iter().filter_map(|r| r.consensus_s).collect();
        let mean = swarm_sim::stats::mean(&times);
        let speed: f64 = rs
            .iter()
            .map(|r| r.report.emulated.as_secs_f64())
            .sum::<f64>()
            / rs.iter()
                .map(|r| r.report.wall.as_secs_f64())
                .sum::<f64>()
                .max(1e-9);
        let mut leds: Vec<String> = rs.iter().map(|r| leds_str(&r.leds)).collect();
        leds.extend(crashes.iter().map(|_| "crashed".to_string()));
        let exp = e
            .configs
            .first()
            .map_or_else(|| "(none)".into(), expected_str);
        // A crashed run is a failure whatever its pattern.
        let success = if crashes.is_empty() && rs.iter().all(|r| r.expected.is_none()) {
            "n/a".to_string()
        } else {
            let n = rs.len() + crashes.len();
            format!("{:.0}%", 100.0 * ok as f64 / n.max(1) as f64)
        };
        let consensus = mean.map_or("-".into(), |m| format!("{m:.0} ({:.1})", m / cycle_s));
        outln!(
            "{:<12} {:<10} {:<36} {:>8} {:>24} {:>8.0}x",
            e.label,
            exp,
            leds.join(" "),
            success,
            consensus,
            speed
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_emu::judge::parse_pattern;
    use protocol::Duration;

    #[test]
    fn a_run_in_which_a_robot_panicked_is_reported_failed_with_its_replay() {
        // What `judge` returns when robot 1's task panics (hal-emu's arena tests inject one);
        // `main` keeps it as a crashed run instead of stopping every run.
        let mut cfg = ArenaConfig::line(
            parse_pattern("1100").unwrap(),
            1.0,
            Duration::from_secs(2101),
            42,
        );
        cfg.env
            .schedule
            .push((Instant::from_secs(2101), parse_pattern("0011").unwrap()));
        cfg.duration = Duration::from_secs(4202);
        let c = Crashed::new(
            &cfg,
            RobotFailure {
                robot: 1,
                seed: 42,
                panicked: true,
                message: "attempt to subtract with overflow".into(),
            },
        );
        assert_eq!(
            c.failed_line(" --decide adaptive"),
            "FAILED 0011 seed 42: robot 1 panicked: attempt to subtract with overflow, expected \
             RRLL (replay: cimax arena --lights 1100 --switch-at 2101 --then 0011 --seed 42 --runs 1 \
             --decide adaptive)"
        );
        let json = serde_json::to_value(c.json()).unwrap();
        assert_eq!(json["success"], false);
        assert_eq!(json["seed"], 42);
        assert_eq!(
            json["error"],
            "robot 1 panicked: attempt to subtract with overflow"
        );
        // A judged run's JSON has no `error` key.
        let mut judged = c.json();
        judged.error = None;
        assert!(serde_json::to_value(judged).unwrap().get("error").is_none());
    }
}
