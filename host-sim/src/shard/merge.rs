//! Putting a job's parts back together: [`merge`] reads them, checks that they are one job,
//! complete and without overlap, and returns the results of every unit in unit order
//! ([`Merged`]), which the command then writes as it would have unsharded.
//!
//! The checks, in order (the first problem found is the error, and nothing is written):
//! each part on its own ([`read_part`]); one job (the same `cimax` version, this one's, the same
//! command, configuration and shard count); no shard twice; no shard missing; every unit
//! present. The result does not depend on the order the parts are given in.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde_json::Value;

use super::part::{CIMAX, Job, Part, PartError, read_part};
use super::spec::ShardSpec;

/// A job's results, merged from its parts.
#[derive(Clone, Debug)]
pub struct Merged {
    /// The job.
    pub job: Job,
    /// The parts, in shard order.
    pub parts: Vec<PathBuf>,
    /// Every unit's result, in unit order, with the index into `parts` of the part it came
    /// from.
    pub results: Vec<(usize, Value)>,
    /// The shards' wall times added up, s.
    pub wall_s: f64,
    /// The most worker threads a shard ran on.
    pub threads: usize,
}

/// Why parts do not merge.
#[derive(Debug)]
pub enum MergeError {
    /// No part given.
    NoParts,
    /// A part is unreadable or broken on its own.
    Part(PartError),
    /// A part made by another `cimax`.
    Version {
        /// The part.
        file: PathBuf,
        /// The version that made it.
        found: String,
    },
    /// A part of another command.
    Command {
        /// The part.
        file: PathBuf,
        /// Its command.
        found: String,
        /// The other parts' command.
        expected: String,
    },
    /// A part of the same command with other options.
    Config {
        /// The part.
        file: PathBuf,
        /// The first option that differs.
        key: String,
        /// Its value in `file`.
        found: String,
        /// Its value in `reference`.
        expected: String,
        /// The part compared with.
        reference: PathBuf,
    },
    /// A part split into another number of shards.
    Count {
        /// The part.
        file: PathBuf,
        /// Its shard count.
        found: u32,
        /// The other parts' shard count.
        expected: u32,
    },
    /// The same shard twice.
    Duplicate {
        /// The second part.
        file: PathBuf,
        /// The shard.
        shard: u32,
        /// The first part.
        other: PathBuf,
    },
    /// Shards not given.
    Missing {
        /// The missing shard numbers.
        shards: Vec<u32>,
        /// Shards of the job.
        count: u32,
    },
    /// Units missing from a part.
    MissingUnits {
        /// The part that should hold them.
        file: PathBuf,
        /// The missing units (the first few).
        units: Vec<u64>,
        /// How many are missing.
        missing: u64,
    },
    /// The job's configuration does not fit the command.
    BadConfig {
        /// A part.
        file: PathBuf,
        /// What is wrong with it.
        error: String,
    },
    /// A unit's result does not fit the command.
    BadResult {
        /// The part.
        file: PathBuf,
        /// The unit.
        unit: u64,
        /// What is wrong with it.
        error: String,
    },
}

impl fmt::Display for MergeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use MergeError as E;
        match self {
            E::NoParts => f.write_str("no parts given"),
            E::Part(e) => e.fmt(f),
            E::Version { file, found } => write!(
                f,
                "{}: made by cimax {found}; this is cimax {CIMAX} (merge with the cimax that ran the shards)",
                file.display()
            ),
            E::Command {
                file,
                found,
                expected,
            } => write!(
                f,
                "{}: a different job (command {found}, not {expected})",
                file.display()
            ),
            E::Config {
                file,
                key,
                found,
                expected,
                reference,
            } => write!(
                f,
                "{}: a different job: config differs in {key:?}: {found} vs {expected} in {}",
                file.display(),
                reference.display()
            ),
            E::Count {
                file,
                found,
                expected,
            } => write!(
                f,
                "{}: a different split (of {found} shards, not {expected})",
                file.display()
            ),
            E::Duplicate { file, shard, other } => write!(
                f,
                "{}: shard {shard} given twice (also in {})",
                file.display(),
                other.display()
            ),
            E::Missing { shards, count } => {
                let s = if shards.len() == 1 { "" } else { "s" };
                write!(f, "missing shard{s} {} of {count}", list(shards))
            }
            E::MissingUnits {
                file,
                units,
                missing,
            } => {
                let more = if *missing > units.len() as u64 {
                    ", ..."
                } else {
                    ""
                };
                let (file, units) = (file.display(), list(units));
                write!(f, "{file}: {missing} units missing ({units}{more})")
            }
            E::BadConfig { file, error } => {
                write!(
                    f,
                    "{}: a job this cimax cannot redo: {error}",
                    file.display()
                )
            }
            E::BadResult { file, unit, error } => {
                write!(f, "{}: unit {unit}: bad result: {error}", file.display())
            }
        }
    }
}

/// `1, 2, 3`.
fn list<T: ToString>(xs: &[T]) -> String {
    xs.iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

impl std::error::Error for MergeError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MergeError::Part(e) => Some(e),
            _ => None,
        }
    }
}

impl From<PartError> for MergeError {
    fn from(e: PartError) -> Self {
        MergeError::Part(e)
    }
}

/// Reads the parts at `paths` and merges them.
///
/// # Errors
/// The first problem found (module docs), naming the part and what is wrong.
pub fn merge(paths: &[PathBuf]) -> Result<Merged, MergeError> {
    let mut sorted = paths.to_vec();
    sorted.sort();
    let mut parts = sorted
        .iter()
        .map(|p| read_part(p))
        .collect::<Result<Vec<Part>, _>>()?;
    parts.sort_by(|a, b| (a.header.shard.index(), &a.path).cmp(&(b.header.shard.index(), &b.path)));
    let first = parts.first().ok_or(MergeError::NoParts)?;
    for p in &parts {
        same_job(first, p)?;
    }
    let count = first.header.shard.count();
    shards_once(&parts, count)?;
    let total = first.header.units;
    let mut results: BTreeMap<u64, (usize, Value)> = BTreeMap::new();
    for (i, p) in parts.iter().enumerate() {
        for (unit, value) in &p.units {
            results.insert(*unit, (i, value.clone()));
        }
    }
    every_unit(&parts, &results, total)?;
    Ok(Merged {
        job: first.header.job.clone(),
        parts: parts.iter().map(|p| p.path.clone()).collect(),
        results: results.into_values().collect(),
        wall_s: parts.iter().map(|p| p.end.wall_s).sum(),
        threads: parts.iter().map(|p| p.end.threads).max().unwrap_or(0),
    })
}

/// That `p` is a part of `first`'s job, made by this `cimax`.
fn same_job(first: &Part, p: &Part) -> Result<(), MergeError> {
    let (a, b) = (&first.header, &p.header);
    if b.cimax != CIMAX {
        return Err(MergeError::Version {
            file: p.path.clone(),
            found: b.cimax.clone(),
        });
    }
    if b.job.command != a.job.command {
        return Err(MergeError::Command {
            file: p.path.clone(),
            found: b.job.command.clone(),
            expected: a.job.command.clone(),
        });
    }
    if let Some((key, found, expected)) = differs(&b.job.config, &a.job.config) {
        return Err(MergeError::Config {
            file: p.path.clone(),
            key,
            found,
            expected,
            reference: first.path.clone(),
        });
    }
    if b.shard.count() != a.shard.count() {
        return Err(MergeError::Count {
            file: p.path.clone(),
            found: b.shard.count(),
            expected: a.shard.count(),
        });
    }
    if b.units != a.units {
        return Err(MergeError::Config {
            file: p.path.clone(),
            key: "units".into(),
            found: b.units.to_string(),
            expected: a.units.to_string(),
            reference: first.path.clone(),
        });
    }
    Ok(())
}

/// The first top-level key in which two configurations differ, with both values (shortened);
/// `None` if they are equal.
fn differs(found: &Value, expected: &Value) -> Option<(String, String, String)> {
    if found == expected {
        return None;
    }
    let short = |v: Option<&Value>| {
        let s = v.map_or_else(|| "(none)".to_string(), Value::to_string);
        if s.chars().count() > 60 {
            format!("{}...", s.chars().take(57).collect::<String>())
        } else {
            s
        }
    };
    match (found.as_object(), expected.as_object()) {
        (Some(f), Some(e)) => {
            let keys: std::collections::BTreeSet<&String> = f.keys().chain(e.keys()).collect();
            keys.into_iter()
                .find(|k| f.get(*k) != e.get(*k))
                .map(|k| (k.clone(), short(f.get(k)), short(e.get(k))))
        }
        _ => Some(("config".into(), short(Some(found)), short(Some(expected)))),
    }
}

/// That each shard `1..=count` is given exactly once (`parts` in shard order).
fn shards_once(parts: &[Part], count: u32) -> Result<(), MergeError> {
    let mut by_shard: BTreeMap<u32, &Path> = BTreeMap::new();
    for p in parts {
        let i = p.header.shard.index();
        if let Some(other) = by_shard.insert(i, &p.path) {
            return Err(MergeError::Duplicate {
                file: p.path.clone(),
                shard: i,
                other: other.to_path_buf(),
            });
        }
    }
    let missing: Vec<u32> = (1..=count).filter(|i| !by_shard.contains_key(i)).collect();
    if missing.is_empty() {
        Ok(())
    } else {
        Err(MergeError::Missing {
            shards: missing,
            count,
        })
    }
}

/// That every unit of `0..total` has a result, else the part that lacks some (units are
/// checked to be in range and their shard's when read, so a count tells).
fn every_unit(
    parts: &[Part],
    results: &BTreeMap<u64, (usize, Value)>,
    total: u64,
) -> Result<(), MergeError> {
    if results.len() as u64 == total {
        return Ok(());
    }
    let Some(k) = (0..total).find(|k| !results.contains_key(k)) else {
        return Ok(());
    };
    let count = parts.first().map_or(1, |p| p.header.shard.count());
    let owner = ShardSpec::owner(k, count);
    let present = results.keys().filter(|&&u| owner.owns(u)).count() as u64;
    let units: Vec<u64> = owner
        .units(total)
        .filter(|u| !results.contains_key(u))
        .take(5)
        .collect();
    let file = parts
        .iter()
        .find(|p| p.header.shard == owner)
        .map_or_else(|| PathBuf::from(owner.file_name()), |p| p.path.clone());
    Err(MergeError::MissingUnits {
        file,
        missing: owner.share(total) - present,
        units,
    })
}

impl Merged {
    /// The job's configuration as `C` and every unit's result as `U`, in unit order.
    ///
    /// # Errors
    /// [`MergeError::BadConfig`] or [`MergeError::BadResult`] if they are not what the command
    /// writes.
    pub fn decode<C: DeserializeOwned, U: DeserializeOwned>(
        &self,
    ) -> Result<(C, Vec<U>), MergeError> {
        let file = |i: usize| self.parts.get(i).cloned().unwrap_or_default();
        let config =
            serde_json::from_value(self.job.config.clone()).map_err(|e| MergeError::BadConfig {
                file: file(0),
                error: e.to_string(),
            })?;
        let units = self
            .results
            .iter()
            .enumerate()
            .map(|(k, (i, v))| {
                serde_json::from_value(v.clone()).map_err(|e| MergeError::BadResult {
                    file: file(*i),
                    unit: k as u64,
                    error: e.to_string(),
                })
            })
            .collect::<Result<Vec<U>, _>>()?;
        Ok((config, units))
    }

    /// A problem with the job's configuration found by the command (an option it refuses),
    /// as a [`MergeError::BadConfig`].
    pub fn bad_config(&self, error: impl fmt::Display) -> MergeError {
        MergeError::BadConfig {
            file: self.parts.first().cloned().unwrap_or_default(),
            error: error.to_string(),
        }
    }

    /// A problem with unit `unit`'s result found by the command (a result for another unit,
    /// say), as a [`MergeError::BadResult`] naming the part it came from.
    pub fn bad_result(&self, unit: usize, error: impl fmt::Display) -> MergeError {
        let part = self.results.get(unit).map_or(0, |(i, _)| *i);
        MergeError::BadResult {
            file: self.parts.get(part).cloned().unwrap_or_default(),
            unit: unit as u64,
            error: error.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::part::{FORMAT, Header, VERSION, write_part};
    use super::*;
    use serde_json::json;

    /// A scratch directory for one test.
    fn dir(what: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cimax-merge-{what}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    /// Writes shard `index` of `count` of a job of `total` units whose unit k's result is
    /// `k * 10`, with `config`, into `dir`.
    fn part(dir: &Path, index: u32, count: u32, total: u64, config: Value) -> PathBuf {
        let shard = ShardSpec::new(index, count).unwrap();
        let header = Header {
            format: FORMAT.into(),
            version: VERSION,
            cimax: CIMAX.into(),
            job: Job {
                command: "test".into(),
                config,
            },
            shard,
            units: total,
        };
        let results: Vec<(u64, u64)> = shard.units(total).map(|k| (k, k * 10)).collect();
        write_part(dir, &header, &results, 1.0, index as usize).unwrap()
    }

    fn message(paths: &[PathBuf]) -> String {
        merge(paths).unwrap_err().to_string()
    }

    #[test]
    fn parts_merge_in_unit_order_whatever_their_order() {
        let d = dir("order");
        let config = json!({"runs": 10});
        let mut paths: Vec<PathBuf> = (1..=3).map(|i| part(&d, i, 3, 8, config.clone())).collect();
        let m = merge(&paths).unwrap();
        paths.reverse();
        let r = merge(&paths).unwrap();
        let values = |m: &Merged| {
            m.results
                .iter()
                .map(|(_, v)| v.as_u64().unwrap())
                .collect::<Vec<_>>()
        };
        assert_eq!(values(&m), [0, 10, 20, 30, 40, 50, 60, 70]);
        assert_eq!(values(&r), values(&m));
        assert_eq!(m.parts, r.parts);
        assert_eq!((m.wall_s, m.threads), (3.0, 3));
        let (c, u): (Value, Vec<u64>) = m.decode().unwrap();
        assert_eq!(c, config);
        assert_eq!(u[7], 70);
        let e = m.decode::<Value, String>().unwrap_err().to_string();
        assert!(e.contains("part-1-of-3.jsonl: unit 0: bad result"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn parts_of_other_jobs_or_splits_are_named() {
        let d = dir("jobs");
        let a = part(&d, 1, 3, 8, json!({"runs": 10, "seed": 1}));
        let b = part(&d.join("b"), 2, 3, 8, json!({"runs": 20, "seed": 1}));
        let c = part(&d, 3, 3, 8, json!({"runs": 10, "seed": 1}));
        let e = message(&[a.clone(), b.clone(), c.clone()]);
        assert!(
            e.ends_with(&format!(
                "part-2-of-3.jsonl: a different job: config differs in \"runs\": 20 vs 10 in {}",
                a.display()
            )),
            "{e}"
        );
        let four = part(&d.join("four"), 2, 4, 8, json!({"runs": 10, "seed": 1}));
        let e = message(&[a.clone(), four, c.clone()]);
        assert!(e.ends_with("a different split (of 4 shards, not 3)"), "{e}");
        // Another command, another cimax.
        let text = std::fs::read_to_string(&c).unwrap();
        let other = d.join("other.jsonl");
        std::fs::write(
            &other,
            text.replacen("\"command\":\"test\"", "\"command\":\"x y\"", 1),
        )
        .unwrap();
        let e = message(&[a.clone(), other.clone()]);
        assert!(
            e.ends_with("other.jsonl: a different job (command x y, not test)"),
            "{e}"
        );
        std::fs::write(&other, text.replacen(CIMAX, "0.0.0-old", 1)).unwrap();
        assert!(message(&[a.clone(), other]).contains("made by cimax 0.0.0-old"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn missing_and_duplicated_shards_and_units_are_named() {
        let d = dir("missing");
        let config = json!({});
        let p: Vec<PathBuf> = (1..=6)
            .map(|i| part(&d, i, 6, 20, config.clone()))
            .collect();
        let some = [p[0].clone(), p[2].clone(), p[3].clone(), p[5].clone()];
        assert_eq!(message(&some), "missing shards 2, 5 of 6");
        assert_eq!(message(&p[..5]), "missing shard 6 of 6");
        let copy = d.join("copy").join("part-3-of-6.jsonl");
        std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
        std::fs::copy(&p[2], &copy).unwrap();
        let mut twice = p.clone();
        twice.push(copy.clone());
        let e = message(&twice);
        assert_eq!(
            e,
            format!(
                "{}: shard 3 given twice (also in {})",
                p[2].display(),
                copy.display()
            )
        );
        assert_eq!(message(&[]), "no parts given");
        // A part that lacks some of its units but counts right.
        let text = std::fs::read_to_string(&p[1]).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let cut = format!("{}\n{}\n{{\"end\":true,\"units\":1}}\n", lines[0], lines[1]);
        std::fs::write(&p[1], cut).unwrap();
        let e = message(&p);
        assert_eq!(
            e,
            format!("{}: 3 units missing (7, 13, 19)", p[1].display())
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn no_bytes_make_reading_panic() {
        let d = dir("bytes");
        let good = part(&d, 1, 1, 3, json!({"runs": 1.5}));
        let bytes = std::fs::read(&good).unwrap();
        let bad = d.join("bad.jsonl");
        for i in 0..bytes.len() {
            for b in [b'\n', b'"', b'{', b'9', 0xff] {
                let mut v = bytes.clone();
                v[i] = b;
                std::fs::write(&bad, &v).unwrap();
                let _ = merge(std::slice::from_ref(&bad));
            }
            // Cut anywhere but before the last newline, it is no part.
            std::fs::write(&bad, &bytes[..i]).unwrap();
            let cut = merge(std::slice::from_ref(&bad));
            assert_eq!(cut.is_ok(), i == bytes.len() - 1, "cut at {i}");
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}
