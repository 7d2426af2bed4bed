//! The ratchet of numbers typed into the strings of the page's code (issue 38, "no free
//! prose"): [`tests::code_strings_fill_every_number_from_data`].
//!
//! The templates' test (`tests::templates_fill_every_number_from_data`) moves every number of
//! the view model and looks for pieces of the page that did not move. A number typed into a
//! Rust string that the view model carries (a verdict's row, a figure's title) moves with it
//! there, so that test cannot see it. This one reads the code instead: every string literal
//! of `pages/src/reproduction` and `pages/src/figures` (tests left out) that holds a digit
//! once its `{…}` placeholders are taken out is listed, and the list must equal
//! `typed_code.txt`, whose entries are definitions and quotes, not data (each group says
//! why). A new one fails: fill it from the scenario, the parameters or the constant the
//! computation uses, or list it with its reason.

use std::path::Path;

/// The string literals of `src` (Rust source), as written (escapes kept), outside comments,
/// up to its test module (`#[cfg(test)]` then `mod`; a test-only item elsewhere, such as
/// settings.rs's list of quotes, does not end the scan).
pub(super) fn literals(src: &str) -> Vec<String> {
    let end = src
        .match_indices("#[cfg(test)]")
        .map(|(k, m)| k + m.len())
        .find(|&k| src[k..].trim_start().starts_with("mod "))
        .map_or(src.len(), |k| k - "#[cfg(test)]".len());
    let src = &src[..end];
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '/' if chars.get(i + 1) == Some(&'/') => {
                while i < chars.len() && chars[i] != '\n' {
                    i += 1;
                }
            }
            // A char literal ('"', '\'', 'x'); a lifetime ('a) is no literal.
            '\'' if chars.get(i + 1) == Some(&'\\') => {
                i += 2;
                while i < chars.len() && chars[i] != '\'' {
                    i += 1;
                }
            }
            '\'' if chars.get(i + 2) == Some(&'\'') => i += 2,
            '"' => {
                let mut s = String::new();
                i += 1;
                while i < chars.len() && chars[i] != '"' {
                    if chars[i] == '\\' && i + 1 < chars.len() {
                        s.push(chars[i]);
                        i += 1;
                    }
                    s.push(chars[i]);
                    i += 1;
                }
                out.push(continued(&s));
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// A literal as Rust reads a `\` at a line's end: the line break and the next line's
/// leading blanks left out.
fn continued(s: &str) -> String {
    let mut out = String::new();
    let mut rest = s;
    while let Some(k) = rest.find("\\\n") {
        out.push_str(&rest[..k]);
        rest = rest[k + 2..].trim_start();
    }
    out.push_str(rest);
    out
}

/// `s` without its format placeholders (`{}`, `{:.2}`, `{name}`; `{{` and `}}` are braces).
pub(super) fn without_placeholders(s: &str) -> String {
    let mut out = String::new();
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '{' if chars.peek() == Some(&'{') => {
                chars.next();
                out.push('{');
            }
            '}' if chars.peek() == Some(&'}') => {
                chars.next();
                out.push('}');
            }
            '{' => {
                for d in chars.by_ref() {
                    if d == '}' {
                        break;
                    }
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// Every literal of the `.rs` files under `dir` (recursively; `tests.rs` and this file left
/// out) with a digit outside its placeholders, as `path | literal` (path from `src/`).
pub(super) fn typed(src_root: &Path, dir: &str) -> Vec<String> {
    let mut files = Vec::new();
    let mut stack = vec![src_root.join(dir)];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("a source folder").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    files.sort();
    let mut out = Vec::new();
    for f in files {
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name == "tests.rs" || name == "typed_code.rs" {
            continue;
        }
        let src = std::fs::read_to_string(&f).expect("a source file");
        let rel = f.strip_prefix(src_root).unwrap_or(&f).display().to_string();
        for l in literals(&src) {
            // "2D" names the paper's simulations (as the templates' test has it).
            let bare = without_placeholders(&l).replace("2D ", "D ");
            if bare.chars().any(|c| c.is_ascii_digit()) {
                out.push(format!("{rel} | {l}"));
            }
        }
    }
    out
}

/// A ratchet over `found` against the list `known` (the text of `pages/src/reproduction/`'s
/// file `list`: one entry a line, `//` comments and blank lines left out): fails on an entry
/// found and not listed (`what` says what it is), and on one listed and no longer found (take
/// it off the list).
pub(super) fn ratchet(found: &[String], known: &str, list: &str, what: &str) {
    let known: Vec<&str> = known
        .lines()
        .filter(|l| !l.starts_with("//") && !l.trim().is_empty())
        .collect();
    let new: Vec<&str> = found
        .iter()
        .map(String::as_str)
        .filter(|f| !known.contains(f))
        .collect();
    let gone: Vec<&str> = known
        .iter()
        .copied()
        .filter(|k| !found.iter().any(|f| f == k))
        .collect();
    assert!(
        new.is_empty(),
        "{} {what} (pages/src/reproduction/{list}):\n{}",
        new.len(),
        new.join("\n")
    );
    assert!(
        gone.is_empty(),
        "no longer found, take them off pages/src/reproduction/{list}:\n{}",
        gone.join("\n")
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals_are_read_as_written() {
        let src = r#"let a = format!("x ≥ {x} and \"2\"", x); // "in a comment 3"
let c = '"'; let d = '\''; let e: &'static str = "5 R";
let f = "one \
         two";
#[cfg(test)]
const U: &str = "8 s";
#[cfg(test)]
mod tests { const T: &str = "7"; }"#;
        assert_eq!(
            literals(src),
            vec![
                r#"x ≥ {x} and \"2\""#.to_string(),
                "5 R".to_string(),
                "one two".to_string(),
                "8 s".to_string()
            ]
        );
        assert_eq!(
            without_placeholders("{:.2} R at 1, {{0}} {n}"),
            " R at 1, {0} "
        );
    }

    /// The ratchet: see the module.
    #[test]
    fn code_strings_fill_every_number_from_data() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut found = typed(&root, "reproduction");
        found.extend(typed(&root, "figures"));
        ratchet(
            &found,
            include_str!("typed_code.txt"),
            "typed_code.txt",
            "numbers typed into the page's code (fill them from data, or list them with a reason)",
        );
    }
}
