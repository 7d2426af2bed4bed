//! `cimax swarm reproduce`: every experiment of the paper's section 3 and
//! `docs/reproduction.md` ([`pages::reproduction`]), whole or one shard, and the
//! merge of its shards.
//!
//! The job ([`ReproduceJob`]: the seed and the placement) has one unit per entry of
//! [`reproduce::units()`], unit `k` the `k`-th. Unsharded, the command computes them all side
//! by side on the worker threads ([`reproduce::compute()`], the crate that runs) and writes
//! with [`reproduction::write`] (the crate that writes), the page's time being the computing's;
//! `--shard I/N` computes its share, one unit after another (each is a stage that runs its own
//! runs in parallel and times itself), into a part; `cimax merge` rebuilds the [`Results`] from
//! the parts and writes them with the same [`reproduction::write`], so the files are the same
//! bytes but for the page's timing lines (a merge's time is the units' wall times added up:
//! they are part of their results).

use crate::cli::out::{Exit, StdoutError, outln};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use host_sim::shard::{self, Job, ShardSpec, merge::Merged};
use pages::reproduction::{self, Options, Summary};
use reproduce::{Results, UnitResult, units};
use serde::{Deserialize, Serialize};
use swarm_sim::experiment;
use swarm_sim::scenario::{DEFAULT_PLACEMENT, Placement, PlacementError};

use super::Res;

/// The job's command in a part's header.
pub const COMMAND: &str = "swarm reproduce";

/// Everything that makes the page's results besides this cimax: the job in a part's header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReproduceJob {
    /// The base seed.
    seed: u64,
    /// The page's placement, `random` or `lattice`.
    placement: String,
}

/// The options of `swarm reproduce`.
pub struct ReproduceOptions {
    /// Base seed.
    pub seed: u64,
    /// The docs directory; with `shard`, the directory of the part.
    pub docs: Option<PathBuf>,
    /// No progress bars.
    pub quiet: bool,
    /// The page's placement.
    pub placement: Option<Placement>,
    /// Only this shard.
    pub shard: Option<ShardSpec>,
}

/// `cimax swarm reproduce`, whole or one shard.
pub fn reproduce(o: &ReproduceOptions) -> Res {
    let placement = o.placement.unwrap_or(DEFAULT_PLACEMENT);
    if let Some(shard) = o.shard {
        let dir = o
            .docs
            .clone()
            .ok_or("--shard needs --docs DIR, the directory of the part")?;
        crate::cli::files::check_dir("--docs", &dir)?;
        return run_shard(o.seed, placement, shard, &dir, o.quiet);
    }
    let docs = match &o.docs {
        Some(d) => d.clone(),
        None => crate::cli::files::checkout_docs("--docs DIR")?,
    };
    crate::cli::files::check_dir("--docs", &docs)?;
    outln!(
        "swarm reproduce: seed {}, {placement} placement, {} threads, writing {}",
        o.seed,
        rayon::current_num_threads(),
        docs.display()
    )?;
    // The stages' log lines; the first that cannot be written stops the command after them.
    let mut unwritten: Option<StdoutError> = None;
    // Written beside the docs folder and moved in only when the page and every figure are,
    // as a merge does: a failure leaves the docs as they were.
    let s = staged(&docs, |stage| {
        let opts = Options {
            seed: o.seed,
            docs: stage.to_path_buf(),
            quiet: o.quiet,
            placement,
        };
        reproduce_all(&opts, &mut |line| {
            if unwritten.is_none() {
                unwritten = outln!("{line}").err();
            }
        })
    })?;
    if let Some(e) = unwritten {
        return Err(e.into());
    }
    print_summary(&Summary {
        report: docs.join("reproduction.md"),
        ..s
    })?;
    outln!("wall time {:.1} s", s.wall_s)?;
    Ok(())
}

/// Every unit of the page ([`reproduce::compute()`]), then every file of it
/// ([`reproduction::write`]) into `opts.docs`. `log` receives each unit's lines, unit after
/// unit in the order of [`units()`].
///
/// The units run side by side on the worker threads (each also runs its own runs in
/// parallel): a thread that has finished its share of one unit's runs takes up another unit
/// instead of waiting for the last run. Each unit's results depend on the options alone, so
/// the page is the same; its progress bar counts units, and a unit's log lines come when it
/// and every unit before it are done.
///
/// # Errors
/// If a run fails or a file cannot be written.
fn reproduce_all(opts: &Options, log: &mut dyn FnMut(&str)) -> Result<Summary, experiment::Error> {
    use rayon::prelude::*;
    let t0 = std::time::Instant::now();
    let all = units();
    let runs = reproduce::Options {
        quiet: true,
        ..opts.runs()
    };
    let progress =
        swarm_sim::progress::Progress::new(all.len() as u64, "swarm reproduce", opts.quiet);
    let (tx, rx) = std::sync::mpsc::channel::<(usize, Vec<String>)>();
    let (runs, progress) = (&runs, &progress);
    let computed = std::thread::scope(|scope| {
        // The sender goes with the worker: if a unit fails and the rest are skipped, the
        // lines below stop when it is done.
        let worker = scope.spawn(move || {
            all.par_iter()
                .enumerate()
                .map(|(k, &unit)| {
                    let mut lines = Vec::new();
                    let r = reproduce::compute(unit, runs, &mut |l| lines.push(l.to_owned()));
                    progress.inc();
                    // The receiver is gone only if the command is: nothing left to tell.
                    let _ = tx.send((k, lines));
                    r
                })
                .collect::<Result<Vec<UnitResult>, _>>()
        });
        // Each unit's lines in the units' order, as soon as they can be.
        let mut waiting = std::collections::BTreeMap::new();
        let mut next = 0;
        for (k, lines) in rx.iter() {
            waiting.insert(k, lines);
            while let Some(lines) = waiting.remove(&next) {
                for l in &lines {
                    log(l);
                }
                next += 1;
            }
        }
        worker.join()
    });
    progress.finish();
    let computed = computed.map_err(|_| "a unit of swarm reproduce panicked".to_string())??;
    let mut results = Results::default();
    for r in computed {
        results.insert(r)?;
    }
    // The units overlapped: the page's time is the computing's, not their times added up.
    results.set_wall_s(t0.elapsed().as_secs_f64());
    let summary = reproduction::write(&results, opts)?;
    Ok(Summary {
        wall_s: t0.elapsed().as_secs_f64(),
        ..summary
    })
}

/// Shard `shard` of the page's units into `dir/part-I-of-N.jsonl`, one unit after another
/// (no stage's own progress bar or log lines: the shard's progress counts units).
fn run_shard(seed: u64, placement: Placement, shard: ShardSpec, dir: &Path, quiet: bool) -> Res {
    let job = Job::new(
        COMMAND,
        &ReproduceJob {
            seed,
            placement: placement.name().into(),
        },
    )?;
    let opts = Options {
        seed,
        docs: dir.to_path_buf(),
        quiet: true,
        placement,
    };
    let all = units();
    let unit = |k: u64| -> Result<UnitResult, String> {
        let u = usize::try_from(k)
            .ok()
            .and_then(|k| all.get(k))
            .ok_or_else(|| format!("no unit {k}"))?;
        reproduce::compute(*u, &opts.runs(), &mut |_| {}).map_err(|e| format!("{u}: {e}"))
    };
    let path = shard::run_shard_in_order(job, all.len() as u64, shard, dir, quiet, unit)
        .map_err(|e| e.to_string())?;
    outln!("wrote {}", path.display())?;
    Ok(())
}

/// `cimax merge` of the page's parts: `OUT/reproduction.md` and `OUT/figures/`, the very files
/// `swarm reproduce --docs OUT` writes with the parts' seed and placement; its page's wall
/// time is the units' added up, over all the shards. The files are written beside `out` first
/// and moved in only when all are written, so a failure leaves `out` as it was.
///
/// # Errors
/// If the parts are not this cimax's page (a unit's result for another unit, or of the wrong
/// kind; a job that is not every unit), or the files cannot be written.
pub fn merge(m: &Merged, out: &Path) -> Exit {
    let (job, results): (ReproduceJob, Vec<UnitResult>) = m.decode().map_err(|e| e.to_string())?;
    let placement: Placement = job
        .placement
        .parse()
        .map_err(|e: PlacementError| m.bad_config(format!("placement: {e}")).to_string())?;
    let all = units();
    if results.len() != all.len() {
        let e = format!(
            "{} units, but swarm reproduce has {}",
            results.len(),
            all.len()
        );
        return Err(m.bad_config(e).to_string().into());
    }
    let mut page = Results::default();
    for (k, (r, &unit)) in results.into_iter().zip(all).enumerate() {
        if r.unit != unit {
            let e = format!("the result of {}, not of {unit}", r.unit);
            return Err(m.bad_result(k, e).to_string().into());
        }
        page.insert(r).map_err(|e| m.bad_result(k, e).to_string())?;
    }
    outln!(
        "swarm reproduce: seed {}, {placement} placement, merged from {} parts, writing {}",
        job.seed,
        m.parts.len(),
        out.display()
    )?;
    let s = staged(out, |docs| {
        let opts = Options {
            seed: job.seed,
            docs: docs.to_path_buf(),
            quiet: true,
            placement,
        };
        reproduction::write(&page, &opts)
    })?;
    print_summary(&Summary {
        report: out.join("reproduction.md"),
        ..s
    })?;
    outln!("wall time {:.1} s (the units' added up)", s.wall_s)?;
    Ok(ExitCode::SUCCESS)
}

/// What the command prints after writing the page: the four sweeps and where the page went.
fn print_summary(s: &Summary) -> Result<(), StdoutError> {
    let fmt = |pts: &[experiment::SweepPoint]| {
        pts.iter()
            .map(|p| format!("{}: {:.2}", p.x_init, p.success_rate()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let main = s.placement;
    for (what, placement, pts) in [
        ("sharp border", main, &s.sharp),
        ("sharp border", main.other(), &s.sharp_other),
        ("gradient", main, &s.gradient),
        ("gradient", main.other(), &s.gradient_other),
    ] {
        outln!("{what} sweep, {placement} placement (x_init: success rate):")?;
        outln!("  {}", fmt(pts))?;
    }
    outln!("wrote {}", s.report.display())
}

/// Runs `write` on a new directory beside `out` and, if it succeeds, moves every file it
/// wrote into `out` (created if need be; files of the same name replaced, others left); if it
/// fails, removes that directory, so that `out` is as it was.
///
/// # Errors
/// `write`'s error, or a file not moved.
fn staged<T, E: std::fmt::Display>(
    out: &Path,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, String> {
    let name = out
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stage = parent.join(format!(".{name}.merge-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&stage);
    let result = std::fs::create_dir_all(&stage)
        .map_err(|e| format!("{}: {e}", stage.display()))
        .and_then(|()| write(&stage).map_err(|e| e.to_string()))
        .and_then(|t| move_into(&stage, out).map(|()| t));
    let _ = std::fs::remove_dir_all(&stage);
    result
}

/// Moves every file under `from` to the same place under `to`.
fn move_into(from: &Path, to: &Path) -> Result<(), String> {
    let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
    std::fs::create_dir_all(to).map_err(|e| io(to, e))?;
    for entry in std::fs::read_dir(from).map_err(|e| io(from, e))? {
        let entry = entry.map_err(|e| io(from, e))?;
        let (src, dst) = (entry.path(), to.join(entry.file_name()));
        if entry.file_type().map_err(|e| io(&src, e))?.is_dir() {
            move_into(&src, &dst)?;
        } else {
            std::fs::rename(&src, &dst).map_err(|e| io(&dst, e))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(what: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cimax-staged-{what}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_staged_write_moves_in_only_when_it_succeeds() {
        let root = scratch("write");
        let out = root.join("out");
        std::fs::create_dir_all(out.join("figures")).unwrap();
        std::fs::write(out.join("keep.md"), "mine").unwrap();
        std::fs::write(out.join("figures/a.svg"), "old").unwrap();
        let failed = staged(&out, |d| {
            std::fs::create_dir_all(d.join("figures")).unwrap();
            std::fs::write(d.join("figures/a.svg"), "new").unwrap();
            Err::<(), _>("the tapped runs are not the courses'")
        });
        assert_eq!(failed.unwrap_err(), "the tapped runs are not the courses'");
        assert_eq!(
            std::fs::read_to_string(out.join("figures/a.svg")).unwrap(),
            "old"
        );
        let names = |d: &Path| {
            let mut v: Vec<String> = std::fs::read_dir(d)
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        };
        assert_eq!(names(&root), ["out"], "no stage left");
        let done = staged(&out, |d| {
            std::fs::create_dir_all(d.join("figures")).unwrap();
            std::fs::write(d.join("figures/a.svg"), "new").unwrap();
            std::fs::write(d.join("page.md"), "page").map(|()| 7)
        });
        assert_eq!(done, Ok(7));
        assert_eq!(
            std::fs::read_to_string(out.join("figures/a.svg")).unwrap(),
            "new"
        );
        assert_eq!(names(&out), ["figures", "keep.md", "page.md"]);
        assert_eq!(names(&root), ["out"]);
        // Into a directory that is not there yet.
        let fresh = root.join("fresh");
        staged(&fresh, |d| std::fs::write(d.join("page.md"), "page")).unwrap();
        assert_eq!(names(&fresh), ["page.md"]);
        std::fs::remove_dir_all(&root).unwrap();
    }
}
