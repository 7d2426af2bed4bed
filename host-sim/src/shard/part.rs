//! Part files: what one shard of a job computed, as JSON Lines.
//!
//! ```text
//! {"format":"cimax-part","version":1,"cimax":"0.1.0","job":{"command":"arena sweep","config":{..}},"shard":{"index":2,"count":3},"units":90}
//! {"unit":1,"result":{..}}
//! {"unit":4,"result":{..}}
//! ...
//! {"end":true,"units":30,"wall_s":12.5,"threads":2}
//! ```
//!
//! Line 1 is the [`Header`]: the job (the command and every option that affects its results,
//! resolved), which shard of how many, and how many units the whole job has. Then one line per
//! unit the shard computed, in unit order, its result as the command serialises it. The last
//! line ([`End`]) counts them, so that a truncated file is told from a complete one, and gives
//! the shard's wall time and threads. A part is written to a temporary name and renamed, so a
//! killed job leaves no half file under the final name.
//!
//! Reading ([`read_part`]) never panics on any bytes: every problem is a [`PartError`] naming
//! the file (and the line). Blank lines are skipped.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::spec::ShardSpec;

/// The `format` of a part's header.
pub const FORMAT: &str = "cimax-part";

/// The part format's version this build writes and reads.
pub const VERSION: u32 = 1;

/// The `cimax` version this build is (the host-sim package's).
pub const CIMAX: &str = env!("CARGO_PKG_VERSION");

/// A job: the command and its configuration, which every part of it repeats.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Job {
    /// The command, e.g. `arena sweep`.
    pub command: String,
    /// Every option that affects the results, resolved (a JSON object).
    pub config: Value,
}

impl Job {
    /// The job of `command` with `config`.
    ///
    /// # Errors
    /// If `config` does not serialise to JSON (a float that is not finite, say).
    pub fn new(command: &str, config: &impl Serialize) -> Result<Job, serde_json::Error> {
        Ok(Job {
            command: command.to_string(),
            config: serde_json::to_value(config)?,
        })
    }
}

/// A part's first line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Always [`FORMAT`].
    pub format: String,
    /// The part format's version ([`VERSION`]).
    pub version: u32,
    /// The version of the `cimax` that wrote it.
    pub cimax: String,
    /// The job.
    pub job: Job,
    /// Which shard this is.
    pub shard: ShardSpec,
    /// Units of the whole job.
    pub units: u64,
}

/// A part's last line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct End {
    /// Always `true`.
    pub end: bool,
    /// Unit lines in the part.
    pub units: u64,
    /// The shard's wall time, s (0 if not given).
    #[serde(default)]
    pub wall_s: f64,
    /// Worker threads the shard ran on (0 if not given).
    #[serde(default)]
    pub threads: usize,
}

/// A part file, read and checked on its own.
#[derive(Clone, Debug)]
pub struct Part {
    /// Where it was read from.
    pub path: PathBuf,
    /// Its header.
    pub header: Header,
    /// Its units, in file order, each with its result.
    pub units: Vec<(u64, Value)>,
    /// Its end line.
    pub end: End,
}

/// Why a part could not be written or read.
#[derive(Debug)]
pub enum PartError {
    /// The file could not be read or written.
    Io {
        /// The file.
        file: PathBuf,
        /// What failed.
        error: std::io::Error,
    },
    /// A result or the job did not serialise.
    Encode {
        /// The file being written.
        file: PathBuf,
        /// What failed.
        error: serde_json::Error,
    },
    /// The file is empty.
    Empty {
        /// The file.
        file: PathBuf,
    },
    /// A line is not JSON, or not the JSON that belongs there.
    Json {
        /// The file.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
        /// What the parser said.
        error: serde_json::Error,
    },
    /// The first line is not a part header.
    NotAPart {
        /// The file.
        file: PathBuf,
    },
    /// A part of another format version.
    FormatVersion {
        /// The file.
        file: PathBuf,
        /// Its version.
        version: u64,
    },
    /// A line that is neither a unit nor the end.
    Stray {
        /// The file.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
    },
    /// A unit number outside the job.
    OutOfRange {
        /// The file.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
        /// The unit.
        unit: u64,
        /// Units of the job.
        total: u64,
    },
    /// A unit another shard owns.
    NotOwned {
        /// The file.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
        /// The unit.
        unit: u64,
        /// The file's shard.
        shard: ShardSpec,
    },
    /// A unit given twice in one part.
    UnitTwice {
        /// The file.
        file: PathBuf,
        /// The second line.
        line: usize,
        /// The unit.
        unit: u64,
        /// The first line.
        first: usize,
    },
    /// No end line: the job was cut short, or the file was.
    Truncated {
        /// The file.
        file: PathBuf,
    },
    /// The end line's count disagrees with the unit lines.
    Count {
        /// The file.
        file: PathBuf,
        /// What the end line says.
        said: u64,
        /// Unit lines found.
        found: u64,
    },
    /// Something after the end line.
    AfterEnd {
        /// The file.
        file: PathBuf,
        /// Its line, from 1.
        line: usize,
    },
}

impl fmt::Display for PartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use PartError as E;
        match self {
            E::Io { file, error } => write!(f, "{}: {error}", file.display()),
            E::Encode { file, error } => write!(f, "{}: {error}", file.display()),
            E::Empty { file } => write!(f, "{}: empty, not a cimax part", file.display()),
            E::Json { file, line, error } => {
                write!(f, "{}:{line}: bad JSON: {error}", file.display())
            }
            E::NotAPart { file } => write!(
                f,
                "{}:1: not a cimax part (no {FORMAT:?} header)",
                file.display()
            ),
            E::FormatVersion { file, version } => write!(
                f,
                "{}: part format version {version}; this cimax reads version {VERSION}",
                file.display()
            ),
            E::Stray { file, line } => write!(
                f,
                "{}:{line}: neither a unit nor the end line",
                file.display()
            ),
            E::OutOfRange {
                file,
                line,
                unit,
                total,
            } => write!(
                f,
                "{}:{line}: unit {unit}, but the job has units 0 to {}",
                file.display(),
                total.saturating_sub(1)
            ),
            E::NotOwned {
                file,
                line,
                unit,
                shard,
            } => write!(
                f,
                "{}:{line}: unit {unit} is not shard {shard}'s",
                file.display()
            ),
            E::UnitTwice {
                file,
                line,
                unit,
                first,
            } => write!(
                f,
                "{}:{line}: unit {unit} given twice (also on line {first})",
                file.display()
            ),
            E::Truncated { file } => write!(f, "{}: truncated (no end line)", file.display()),
            E::Count { file, said, found } => write!(
                f,
                "{}: truncated or edited (the end line counts {said} units, the part has {found})",
                file.display()
            ),
            E::AfterEnd { file, line } => {
                write!(f, "{}:{line}: more after the end line", file.display())
            }
        }
    }
}

impl std::error::Error for PartError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PartError::Io { error, .. } => Some(error),
            PartError::Encode { error, .. } | PartError::Json { error, .. } => Some(error),
            _ => None,
        }
    }
}

/// One unit line, as written.
#[derive(Serialize)]
struct UnitLine<'a, U> {
    unit: u64,
    result: &'a U,
}

/// Writes shard `shard`'s part of `job` into `dir` (created if need be) as
/// `part-I-of-N.jsonl`: the header, `results` (unit number and result, in unit order), the end
/// line with `wall_s` and `threads`. Written to a temporary name first and renamed.
///
/// # Errors
/// If a result does not serialise or the file cannot be written.
pub fn write_part<U: Serialize>(
    dir: &Path,
    header: &Header,
    results: &[(u64, U)],
    wall_s: f64,
    threads: usize,
) -> Result<PathBuf, PartError> {
    let path = dir.join(header.shard.file_name());
    let encode = |error| PartError::Encode {
        file: path.clone(),
        error,
    };
    let mut text = serde_json::to_string(header).map_err(encode)?;
    text.push('\n');
    for (unit, result) in results {
        text += &serde_json::to_string(&UnitLine {
            unit: *unit,
            result,
        })
        .map_err(encode)?;
        text.push('\n');
    }
    let end = End {
        end: true,
        units: results.len() as u64,
        wall_s,
        threads,
    };
    text += &serde_json::to_string(&end).map_err(encode)?;
    text.push('\n');
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        header.shard.file_name(),
        std::process::id()
    ));
    let io = |error| PartError::Io {
        file: path.clone(),
        error,
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, &path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })?;
    Ok(path)
}

/// Reads and checks one part: its header, that every unit is in the job and the shard's, none
/// twice, and that it ends with an end line counting its units and nothing after.
///
/// # Errors
/// A [`PartError`] naming the file and, where there is one, the line.
pub fn read_part(path: &Path) -> Result<Part, PartError> {
    let file = path.to_path_buf();
    let bytes = std::fs::read(path).map_err(|error| PartError::Io {
        file: file.clone(),
        error,
    })?;
    let mut lines = bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l));
    let header = match lines.next() {
        Some((_, l)) if !l.is_empty() => header(&file, l)?,
        _ => return Err(PartError::Empty { file }),
    };
    let mut units = Vec::new();
    let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
    let mut end = None;
    for (line, text) in lines {
        // Blank lines (the one after the last newline, say) are no lines.
        if text.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        if end.is_some() {
            return Err(PartError::AfterEnd { file, line });
        }
        match body_line(&file, line, text)? {
            Line::End(e) => end = Some(e),
            Line::Unit(unit, result) => {
                check_unit(&file, line, unit, &header)?;
                if let Some(&first) = seen.get(&unit) {
                    return Err(PartError::UnitTwice {
                        file,
                        line,
                        unit,
                        first,
                    });
                }
                seen.insert(unit, line);
                units.push((unit, result));
            }
        }
    }
    let end = end.ok_or_else(|| PartError::Truncated { file: file.clone() })?;
    if end.units != units.len() as u64 {
        return Err(PartError::Count {
            file,
            said: end.units,
            found: units.len() as u64,
        });
    }
    Ok(Part {
        path: file,
        header,
        units,
        end,
    })
}

/// The header on line 1 of `file`.
fn header(file: &Path, text: &[u8]) -> Result<Header, PartError> {
    let json = |error| PartError::Json {
        file: file.to_path_buf(),
        line: 1,
        error,
    };
    let value: Value = serde_json::from_slice(text).map_err(json)?;
    if value.get("format").and_then(Value::as_str) != Some(FORMAT) {
        return Err(PartError::NotAPart {
            file: file.to_path_buf(),
        });
    }
    match value.get("version").and_then(Value::as_u64) {
        Some(v) if v == u64::from(VERSION) => {}
        Some(version) => {
            return Err(PartError::FormatVersion {
                file: file.to_path_buf(),
                version,
            });
        }
        None => {
            return Err(PartError::NotAPart {
                file: file.to_path_buf(),
            });
        }
    }
    serde_json::from_value(value).map_err(json)
}

/// A line after the header.
enum Line {
    Unit(u64, Value),
    End(End),
}

/// Line `line` of `file`, a unit or the end.
fn body_line(file: &Path, line: usize, text: &[u8]) -> Result<Line, PartError> {
    let json = |error| PartError::Json {
        file: file.to_path_buf(),
        line,
        error,
    };
    let value: Value = serde_json::from_slice(text).map_err(json)?;
    if value.get("end").is_some() {
        let end: End = serde_json::from_value(value).map_err(json)?;
        if !end.end {
            return Err(PartError::Stray {
                file: file.to_path_buf(),
                line,
            });
        }
        return Ok(Line::End(end));
    }
    #[derive(Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Unit {
        unit: u64,
        result: Value,
    }
    if value.get("unit").is_none() {
        return Err(PartError::Stray {
            file: file.to_path_buf(),
            line,
        });
    }
    let u: Unit = serde_json::from_value(value).map_err(json)?;
    Ok(Line::Unit(u.unit, u.result))
}

/// That `unit`, on `line` of `file`, is in the job and the shard's.
fn check_unit(file: &Path, line: usize, unit: u64, header: &Header) -> Result<(), PartError> {
    if unit >= header.units {
        return Err(PartError::OutOfRange {
            file: file.to_path_buf(),
            line,
            unit,
            total: header.units,
        });
    }
    if !header.shard.owns(unit) {
        return Err(PartError::NotOwned {
            file: file.to_path_buf(),
            line,
            unit,
            shard: header.shard,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(index: u32, count: u32, units: u64) -> Header {
        Header {
            format: FORMAT.into(),
            version: VERSION,
            cimax: CIMAX.into(),
            job: Job::new("test", &serde_json::json!({"runs": 3})).unwrap(),
            shard: ShardSpec::new(index, count).unwrap(),
            units,
        }
    }

    fn dir(what: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("cimax-part-{what}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    }

    #[test]
    fn a_part_reads_back_as_written() {
        let d = dir("roundtrip");
        let results = [(1u64, 0.1f64 + 0.2), (4, f64::MIN_POSITIVE), (7, 1e300)];
        let path = write_part(&d, &header(2, 3, 9), &results, 1.5, 2).unwrap();
        assert_eq!(path, d.join("part-2-of-3.jsonl"));
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["part-2-of-3.jsonl"], "no temporary file left");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with(r#"{"format":"cimax-part","version":1,"cimax":""#));
        assert!(text.ends_with("{\"end\":true,\"units\":3,\"wall_s\":1.5,\"threads\":2}\n"));
        let part = read_part(&path).unwrap();
        assert_eq!(part.header, header(2, 3, 9));
        let back: Vec<(u64, f64)> = part
            .units
            .iter()
            .map(|(k, v)| (*k, v.as_f64().unwrap()))
            .collect();
        assert_eq!(back, results, "floats round-trip bit for bit");
        assert_eq!(part.end.wall_s, 1.5);
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// What reading `text` as a part says.
    fn read_text(text: &[u8]) -> String {
        let d = dir("bad");
        std::fs::create_dir_all(&d).unwrap();
        let path = d.join("p.jsonl");
        std::fs::write(&path, text).unwrap();
        let r = read_part(&path)
            .map(|_| "ok".to_string())
            .unwrap_or_else(|e| e.to_string());
        std::fs::remove_dir_all(&d).unwrap();
        r.replace(&path.display().to_string(), "p")
    }

    #[test]
    fn bad_parts_are_named_with_their_line() {
        let h = serde_json::to_string(&header(2, 3, 9)).unwrap();
        let end = |n: u64| format!("{{\"end\":true,\"units\":{n}}}");
        let ok = format!("{h}\n{{\"unit\":1,\"result\":1}}\n{}\n", end(1));
        assert_eq!(read_text(ok.as_bytes()), "ok");
        assert_eq!(read_text(b""), "p: empty, not a cimax part");
        assert_eq!(
            read_text(b"{}\n"),
            "p:1: not a cimax part (no \"cimax-part\" header)"
        );
        assert!(read_text(b"\xff\xfe\n").starts_with("p:1: bad JSON"));
        let v2 = h.replace("\"version\":1", "\"version\":2");
        assert!(read_text(v2.as_bytes()).contains("format version 2"));
        let cut = format!("{h}\n{{\"unit\":1,\"result\":1}}\n");
        assert_eq!(read_text(cut.as_bytes()), "p: truncated (no end line)");
        let half = format!("{h}\n{{\"unit\":1,\"res");
        assert!(read_text(half.as_bytes()).starts_with("p:2: bad JSON"));
        let cases = [
            (
                format!("{h}\n{{\"unit\":9,\"result\":1}}\n{}", end(1)),
                "p:2: unit 9, but the job has units 0 to 8",
            ),
            (
                format!("{h}\n{{\"unit\":2,\"result\":1}}\n{}", end(1)),
                "p:2: unit 2 is not shard 2/3's",
            ),
            (
                format!(
                    "{h}\n{{\"unit\":1,\"result\":1}}\n{{\"unit\":1,\"result\":2}}\n{}",
                    end(2)
                ),
                "p:3: unit 1 given twice (also on line 2)",
            ),
            (
                format!("{h}\n{{\"unit\":1,\"result\":1}}\n{}", end(2)),
                "p: truncated or edited (the end line counts 2 units, the part has 1)",
            ),
            (
                format!("{h}\n{}\n{{\"unit\":1,\"result\":1}}\n", end(0)),
                "p:3: more after the end line",
            ),
            (
                format!("{h}\n[1]\n{}", end(0)),
                "p:2: neither a unit nor the end line",
            ),
        ];
        for (text, want) in cases {
            assert_eq!(read_text(text.as_bytes()), want);
        }
    }
}
