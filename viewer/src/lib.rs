//! The replay viewer: one self-contained HTML page per run (`--html FILE`, `cimax view`).
//!
//! A run becomes a [`Header`] (the set-up: robots, sectors, lamps or field, goal, verdict) and
//! its trace ([`TraceEvent`]s, or for the 2D simulator its own events). [`Replay`] packs them
//! as deltas (one flat integer stream, each frame once with only the receivers it did *not*
//! reach intact), and [`page`] puts that JSON, the script and the style into one file that
//! opens offline. The page replays the stream itself: nothing is stored per frame of the
//! animation, so a 61-robot plane run of 10 moves is about 2 MB and 1,000 robots still open.
//!
//! `--trace FILE` writes the same header as its first line, so `cimax view` can build the
//! page from a saved trace ([`read_trace`]). docs/viewer.md describes the page.

mod header;
mod replay;
pub mod swarm;

use std::path::{Path, PathBuf};

pub use header::{
    Goal, Header, Heatmap, Kind, PatternAt, Verdict, goal_of, header_of, heatmap, move_verdict,
};
pub use replay::{REPLAY_VERSION, Replay};

use hal_emu::TraceEvent;

/// Why a page or trace could not be made, written or read.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The replay could not be serialised.
    #[error("replay: {0}")]
    Replay(#[source] serde_json::Error),
    /// A trace line could not be serialised.
    #[error(transparent)]
    Json(serde_json::Error),
    /// A file could not be written.
    #[error("{}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The trace has no lines.
    #[error("{file}: empty file")]
    Empty {
        /// The trace, as named.
        file: String,
    },
    /// The trace's first line is no header.
    #[error(
        "{file}:1: not a trace header ({error}); write the trace with `cimax arena --trace` \
         of this version"
    )]
    NoHeader {
        /// The trace, as named.
        file: String,
        /// Why the line is no header.
        #[source]
        error: serde_json::Error,
    },
    /// The trace is of another replay version.
    #[error("{file}:1: trace version {version}, this viewer reads {REPLAY_VERSION}")]
    Version {
        /// The trace, as named.
        file: String,
        /// Its version.
        version: u32,
    },
    /// A line of the trace is no event.
    #[error("{file}:{line}: {error}")]
    Event {
        /// The trace, as named.
        file: String,
        /// The line, from 1.
        line: usize,
        /// Why it is no event.
        #[source]
        error: serde_json::Error,
    },
}

/// The page's script, style and skeleton (inlined into every page).
const SCRIPT: &str = include_str!("assets/viewer.js");
const STYLE: &str = include_str!("assets/viewer.css");
const SKELETON: &str = include_str!("assets/viewer.html");

/// The self-contained HTML page of `replay`.
///
/// # Errors
/// If the replay cannot be serialised (a non-finite number where JSON has none).
pub fn page(replay: &Replay) -> Result<String, Error> {
    let json = serde_json::to_string(replay).map_err(Error::Replay)?;
    // Inside <script>, "</script" or "<!--" would end or confuse the element: every "<" is
    // written as the JSON escape "\u003c" (it only occurs inside strings).
    let json = json.replace('<', "\\u003c");
    let title = html_escape(&replay.header.title);
    Ok(SKELETON
        .replace("{{TITLE}}", &title)
        .replace("{{STYLE}}", STYLE)
        .replace("{{SCRIPT}}", SCRIPT)
        .replace("{{REPLAY}}", &json))
}

/// Writes the page of `header` and `trace` to `path`.
///
/// # Errors
/// [`Error::Write`] naming the file if it cannot be written.
pub fn write_page(path: &Path, header: Header, trace: &[TraceEvent]) -> Result<(), Error> {
    let replay = Replay::from_trace(header, trace);
    let html = page(&replay)?;
    std::fs::write(path, html).map_err(|source| Error::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Escapes text for HTML.
fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The first line of a `--trace` file: the run's set-up.
#[derive(serde::Serialize, serde::Deserialize)]
struct HeaderLine {
    header: Header,
}

/// Writes a trace as JSON lines: the header first, then one event per line.
///
/// # Errors
/// [`Error::Write`] naming the file if it cannot be written.
pub fn write_trace(path: &Path, header: Header, trace: &[TraceEvent]) -> Result<(), Error> {
    use std::io::Write as _;
    let err = |source| Error::Write {
        path: path.to_path_buf(),
        source,
    };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
    let line = serde_json::to_string(&HeaderLine { header }).map_err(Error::Json)?;
    writeln!(out, "{line}").map_err(err)?;
    for e in trace {
        let line = serde_json::to_string(e).map_err(Error::Json)?;
        writeln!(out, "{line}").map_err(err)?;
    }
    out.flush().map_err(err)
}

/// Reads a `--trace` file back: its header and events.
///
/// # Errors
/// An [`Error`] naming the line and what is wrong with it: no header (a trace from before the
/// viewer), another replay version, an event that does not parse.
pub fn read_trace(text: &str, source: &str) -> Result<(Header, Vec<TraceEvent>), Error> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, first)) = lines.next() else {
        return Err(Error::Empty {
            file: source.to_string(),
        });
    };
    let header = serde_json::from_str::<HeaderLine>(first)
        .map_err(|error| Error::NoHeader {
            file: source.to_string(),
            error,
        })?
        .header;
    if header.version != REPLAY_VERSION {
        return Err(Error::Version {
            file: source.to_string(),
            version: header.version,
        });
    }
    let events = lines
        .map(|(i, l)| {
            serde_json::from_str::<TraceEvent>(l).map_err(|error| Error::Event {
                file: source.to_string(),
                line: i + 1,
                error,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((header, events))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trace_without_a_header_or_with_a_bad_line_is_named() {
        let e = read_trace("", "t.jsonl").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
        let e = read_trace(
            "{\"event\":\"sent\",\"t_ms\":0,\"robot\":0,\"len\":32}\n",
            "t.jsonl",
        )
        .unwrap_err()
        .to_string();
        assert!(e.starts_with("t.jsonl:1: not a trace header"), "{e}");
    }

    #[test]
    fn the_page_cannot_be_closed_early_by_the_data() {
        let mut h = Header::empty(Kind::Line);
        h.title = "</script><b>".into();
        let r = Replay::from_trace(h, &[]);
        let html = page(&r).unwrap();
        // The data adds no element end: only the skeleton's own.
        assert_eq!(
            html.matches("</script>").count(),
            SKELETON.matches("</script>").count()
        );
        assert!(html.contains("&lt;/script&gt;"));
    }
}
