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

use std::path::Path;

pub use header::{
    Goal, Header, Heatmap, Kind, PatternAt, Verdict, goal_of, header_of, heatmap, move_verdict,
};
pub use replay::{REPLAY_VERSION, Replay};

use hal_emu::TraceEvent;

/// The page's script, style and skeleton (inlined into every page).
const SCRIPT: &str = include_str!("assets/viewer.js");
const STYLE: &str = include_str!("assets/viewer.css");
const SKELETON: &str = include_str!("assets/viewer.html");

/// The self-contained HTML page of `replay`.
///
/// # Errors
/// If the replay cannot be serialised (a non-finite number where JSON has none).
pub fn page(replay: &Replay) -> Result<String, String> {
    let json = serde_json::to_string(replay).map_err(|e| format!("replay: {e}"))?;
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
/// A message naming the file if it cannot be written.
pub fn write_page(path: &Path, header: Header, trace: &[TraceEvent]) -> Result<(), String> {
    let replay = Replay::from_trace(header, trace);
    let html = page(&replay)?;
    std::fs::write(path, html).map_err(|e| format!("{}: {e}", path.display()))
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
/// A message naming the file if it cannot be written.
pub fn write_trace(path: &Path, header: Header, trace: &[TraceEvent]) -> Result<(), String> {
    use std::io::Write as _;
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
    let line = serde_json::to_string(&HeaderLine { header }).map_err(|e| e.to_string())?;
    writeln!(out, "{line}").map_err(err)?;
    for e in trace {
        let line = serde_json::to_string(e).map_err(|e| e.to_string())?;
        writeln!(out, "{line}").map_err(err)?;
    }
    out.flush().map_err(err)
}

/// Reads a `--trace` file back: its header and events.
///
/// # Errors
/// A message naming the line and what is wrong with it: no header (a trace from before the
/// viewer), another replay version, an event that does not parse.
pub fn read_trace(text: &str, source: &str) -> Result<(Header, Vec<TraceEvent>), String> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, first)) = lines.next() else {
        return Err(format!("{source}: empty file"));
    };
    let header = serde_json::from_str::<HeaderLine>(first)
        .map_err(|e| {
            format!(
                "{source}:1: not a trace header ({e}); write the trace with `cimax arena --trace` \
                 of this version"
            )
        })?
        .header;
    if header.version != REPLAY_VERSION {
        return Err(format!(
            "{source}:1: trace version {}, this viewer reads {REPLAY_VERSION}",
            header.version
        ));
    }
    let events = lines
        .map(|(i, l)| {
            serde_json::from_str::<TraceEvent>(l).map_err(|e| format!("{source}:{}: {e}", i + 1))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((header, events))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trace_without_a_header_or_with_a_bad_line_is_named() {
        let e = read_trace("", "t.jsonl").unwrap_err();
        assert!(e.contains("empty"), "{e}");
        let e = read_trace(
            "{\"event\":\"sent\",\"t_ms\":0,\"robot\":0,\"len\":32}\n",
            "t.jsonl",
        )
        .unwrap_err();
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
