//! The progress bar of long runs (sweeps, grids, the campaign), drawn on stderr only when it
//! is a terminal; and, for a shard of a job run in batch (`--shard`, a Slurm array task whose
//! stderr is a log file), a line with the time left every tenth of the way.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};

use indicatif::{HumanDuration, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar on stderr, shown only when stderr is a terminal; or progress lines
/// ([`Progress::logged`]).
pub struct Progress {
    bar: Option<ProgressBar>,
    /// Lines instead of a bar: the label, and the last tenth reported.
    log: Option<(String, AtomicU64)>,
    /// What it counts: `runs`, or `units` for a shard of whole stages.
    noun: &'static str,
}

impl Progress {
    /// A bar for `len` runs labelled `msg`, or nothing if stderr is not a terminal or `quiet`.
    pub fn new(len: u64, msg: &str, quiet: bool) -> Progress {
        Progress::counting(len, msg, "runs", quiet)
    }

    /// As [`Progress::new`], counting `noun` (`units`, say) instead of runs.
    fn counting(len: u64, msg: &str, noun: &'static str, quiet: bool) -> Progress {
        if quiet || !std::io::stderr().is_terminal() {
            return Progress::hidden();
        }
        let bar = ProgressBar::new(len);
        let template = format!("{{msg:>22}} [{{bar:40}}] {{pos}}/{{len}} {noun}, {{eta}} left");
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(msg.to_string());
        Progress {
            bar: Some(bar),
            log: None,
            noun,
        }
    }

    /// As [`Progress::new`] on a terminal; elsewhere (a batch job's log) a line on stderr each
    /// tenth of the way: `LABEL: 12 of 30 runs, 1 minute left`. Nothing if `quiet`.
    pub fn logged(len: u64, label: &str, quiet: bool) -> Progress {
        Progress::logged_counting(len, label, "runs", quiet)
    }

    /// As [`Progress::logged`], counting `noun` instead of runs: `LABEL: 6 of 19 units, 2
    /// minutes left`.
    pub fn logged_counting(len: u64, label: &str, noun: &'static str, quiet: bool) -> Progress {
        if quiet || std::io::stderr().is_terminal() {
            return Progress::counting(len, label, noun, quiet);
        }
        Progress {
            bar: Some(ProgressBar::with_draw_target(
                Some(len),
                ProgressDrawTarget::hidden(),
            )),
            log: Some((label.to_string(), AtomicU64::new(0))),
            noun,
        }
    }

    /// A bar over `secs` seconds of runs in real time (robots in the loop), labelled `msg`,
    /// moved on by [`Progress::while_running`]; nothing if stderr is not a terminal.
    pub fn seconds(secs: u64, msg: &str) -> Progress {
        Progress::counting(secs, msg, "s", false)
    }

    /// Runs `run`, which lasts about `secs` seconds of wall time, moving the bar on by the
    /// seconds as they pass (a thread ticks it five times a second), then to `secs` past
    /// where it was.
    pub fn while_running<T>(&self, secs: u64, run: impl FnOnce() -> T) -> T {
        let Some(b) = &self.bar else { return run() };
        let base = b.position();
        let done = std::sync::atomic::AtomicBool::new(false);
        let out = std::thread::scope(|s| {
            s.spawn(|| {
                let t0 = std::time::Instant::now();
                while !done.load(Ordering::Relaxed) {
                    std::thread::sleep(std::time::Duration::from_millis(200));
                    b.set_position(base + t0.elapsed().as_secs().min(secs));
                }
            });
            let out = run();
            done.store(true, Ordering::Relaxed);
            out
        });
        b.set_position(base + secs);
        out
    }

    /// No bar at all.
    pub fn hidden() -> Progress {
        Progress {
            bar: None,
            log: None,
            noun: "runs",
        }
    }

    /// One more step done.
    pub fn inc(&self) {
        let Some(b) = &self.bar else { return };
        b.inc(1);
        let Some((label, reported)) = &self.log else {
            return;
        };
        let (pos, len) = (b.position(), b.length().unwrap_or(0).max(1));
        let tenth = pos * 10 / len;
        let last = reported.fetch_max(tenth, Ordering::Relaxed);
        if tenth > last && pos < len {
            eprintln!(
                "{label}: {pos} of {len} {}, {} left",
                self.noun,
                HumanDuration(b.eta())
            );
        }
    }

    /// Removes the bar (a logged one says it is done).
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            if let Some((label, _)) = &self.log {
                eprintln!(
                    "{label}: {} {} in {}",
                    b.position(),
                    self.noun,
                    HumanDuration(b.elapsed())
                );
            }
            b.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_real_time_bar_moves_with_the_seconds_and_ends_past_the_run() {
        // A bar drawn nowhere (tests have no terminal), counting seconds.
        let p = Progress {
            bar: Some(ProgressBar::with_draw_target(
                Some(10),
                ProgressDrawTarget::hidden(),
            )),
            log: None,
            noun: "s",
        };
        let b = p.bar.as_ref().unwrap();
        b.set_position(3);
        let seen = p.while_running(4, || {
            std::thread::sleep(std::time::Duration::from_millis(2500));
            b.position()
        });
        // One or two whole seconds had passed when the run looked (ticks every 0.2 s); at its
        // end the bar is 4 s past where it was.
        assert!((4..=5).contains(&seen), "{seen}");
        assert_eq!(b.position(), 7);
        // Without a bar the run just runs.
        assert_eq!(Progress::hidden().while_running(4, || 5), 5);
    }
}
