//! The compute and write phases apart: results through JSON and back are the same results, and
//! the page written from them is the same page.

use std::path::{Path, PathBuf};

use super::*;
use reproduce::{Field, Side, UNITS, Unit, UnitResult, compute, units};
use swarm_sim::waves::SNAPSHOTS;

fn options(docs: PathBuf) -> Options {
    Options {
        seed: 1,
        docs,
        quiet: true,
        placement: DEFAULT_PLACEMENT,
    }
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("cimax-repro-{name}-{}", std::process::id()))
}

/// `r` through one line of JSON and back.
fn through_json(r: &UnitResult) -> UnitResult {
    let line = serde_json::to_string(r).unwrap();
    assert!(!line.contains('\n'));
    serde_json::from_str(&line).unwrap()
}

/// Every file under `a` has a twin under `b` with the same bytes, and no other file is there.
fn same_files(a: &Path, b: &Path) {
    let list = |d: &Path| -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        v.sort();
        v
    };
    let (xs, ys) = (list(a), list(b));
    assert_eq!(
        xs.iter().map(|p| p.file_name()).collect::<Vec<_>>(),
        ys.iter().map(|p| p.file_name()).collect::<Vec<_>>()
    );
    for (x, y) in xs.iter().zip(&ys) {
        if x.is_dir() {
            same_files(x, y);
        } else {
            assert!(
                std::fs::read(x).unwrap() == std::fs::read(y).unwrap(),
                "{} differs",
                y.display()
            );
        }
    }
}

#[test]
fn results_of_cheap_units_read_back_the_same() {
    let opts = options(temp("cheap"));
    for unit in [
        Unit::Run(Field::Gradient),
        Unit::Refractory,
        Unit::Waves,
        Unit::Placements,
        Unit::Plateau(Side::Main, 2),
    ] {
        let r = compute(unit, &opts.runs(), &mut |_| {}).unwrap();
        let back = through_json(&r);
        // Debug prints every float as the shortest decimal that reads back to it.
        assert_eq!(format!("{back:?}"), format!("{r:?}"), "{unit}");
    }
}

#[test]
fn the_wave_written_from_json_is_the_same() {
    let r = compute(Unit::Waves, &options(temp("unused")).runs(), &mut |_| {}).unwrap();
    let back = through_json(&r);
    let (a, b) = (temp("wave-a"), temp("wave-b"));
    for (dir, r) in [(&a, &r), (&b, &back)] {
        std::fs::create_dir_all(dir).unwrap();
        let mut results = Results::default();
        results.insert(r.clone()).unwrap();
        let w = results.waves(Unit::Waves).unwrap();
        crate::figures::write_waves_csv(&dir.join("waves.csv"), w, &SNAPSHOTS).unwrap();
        crate::figures::waves_figure(&dir.join("waves.svg"), w, &SNAPSHOTS).unwrap();
    }
    same_files(&a, &b);
    std::fs::remove_dir_all(&a).ok();
    std::fs::remove_dir_all(&b).ok();
}

#[test]
fn results_are_refused_twice_or_for_another_unit() {
    let opts = options(temp("unused"));
    let r = compute(Unit::Placements, &opts.runs(), &mut |_| {}).unwrap();
    let mut results = Results::default();
    results.insert(r.clone()).unwrap();
    assert!(results.insert(r.clone()).is_err());
    let mut wrong = through_json(&r);
    wrong.unit = Unit::Speed;
    assert!(Results::default().insert(wrong).is_err());
    assert_eq!(results.missing().len(), UNITS.len() - 1);
    assert!(!results.missing().contains(&Unit::Placements));
    assert!(write(&results, &opts).is_err());
}

/// The whole page twice: written from the results as computed, and from the same results
/// through JSON lines, read back in the reverse order. Every file is the same, byte for byte
/// (the timing lines too: the wall times are results). Takes the whole page's time; run with
/// `cargo test --release -p pages -- --ignored the_whole_page`.
#[test]
#[ignore = "runs every experiment of the page (minutes in release)"]
fn the_whole_page_written_from_json_lines_is_the_same() {
    let base = temp("whole");
    let opts = options(base.join("computed"));
    let mut results = Results::default();
    for &unit in units() {
        results
            .insert(compute(unit, &opts.runs(), &mut |_| {}).unwrap())
            .unwrap();
    }
    write(&results, &opts).unwrap();
    let lines: Vec<String> = results
        .iter()
        .map(|r| serde_json::to_string(r).unwrap())
        .collect();
    let mut back = Results::default();
    for line in lines.iter().rev() {
        back.insert(serde_json::from_str(line).unwrap()).unwrap();
    }
    let again = options(base.join("from-json"));
    write(&back, &again).unwrap();
    same_files(&opts.docs, &again.docs);
    std::fs::remove_dir_all(&base).ok();
}

/// Every number of the view model moved: each run of digits in a string, and each JSON
/// number, one up ("0.52 ± 0.02" becomes "1.53 ± 1.03").
fn perturbed(v: &serde_json::Value) -> serde_json::Value {
    use serde_json::Value as V;
    match v {
        V::String(s) => {
            let mut out = String::new();
            let mut digits = String::new();
            for c in s.chars().chain(['\0']) {
                if c.is_ascii_digit() {
                    digits.push(c);
                    continue;
                }
                if !digits.is_empty() {
                    let n: u128 = digits.parse().unwrap_or(0);
                    out.push_str(&format!("{:0w$}", n + 1, w = digits.len()));
                    digits.clear();
                }
                if c != '\0' {
                    out.push(c);
                }
            }
            V::String(out)
        }
        V::Number(n) => n.as_u64().map_or_else(
            || serde_json::json!(n.as_f64().unwrap_or(0.0) + 1.0),
            |u| serde_json::json!(u + 1),
        ),
        V::Array(xs) => V::Array(xs.iter().map(perturbed).collect()),
        V::Object(m) => V::Object(m.iter().map(|(k, x)| (k.clone(), perturbed(x))).collect()),
        other => other.clone(),
    }
}

/// The pieces of a page line that carry a number the reader takes for data: the line cut at
/// sentence ends and table cells, without what no data fills (the paper's figure and section
/// numbers, which come from the `fig`/`sec` globals and are checked against the LaTeX source;
/// code spans; link targets; the word "2D", the name of the paper's simulations, not a
/// quantity).
fn number_pieces(line: &str) -> Vec<String> {
    let mut clean = String::new();
    let mut in_code = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '`' => in_code = !in_code,
            _ if in_code => {}
            ']' if chars.peek() == Some(&'(') => {
                for d in chars.by_ref() {
                    if d == ')' {
                        break;
                    }
                }
            }
            _ => clean.push(c),
        }
    }
    let clean = without_paper_refs(&clean).replace("2D ", "D ");
    let mut out = Vec::new();
    for piece in clean.split(['|', ';']).flat_map(|p| p.split(". ")) {
        if piece.chars().any(|c| c.is_ascii_digit()) {
            out.push(piece.trim().to_owned());
        }
    }
    out
}

/// `s` with the paper's figure and section references ("Fig. 5b", "Figs. 6 and 9",
/// "Figs. 8–10", "§3.2") cut down to "Fig" and "§".
fn without_paper_refs(s: &str) -> String {
    let c: Vec<char> = s.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    // The number list from `j` on: digits, a panel letter or "(d)", joined by ", ", " and ",
    // "–"; where it ends.
    let list_end = |mut j: usize| -> usize {
        loop {
            let start = j;
            while j < c.len() && (c[j].is_ascii_digit() || c[j] == '.' && j > start) {
                j += 1;
            }
            if j == start {
                return start;
            }
            if j < c.len() && c[j].is_ascii_lowercase() {
                j += 1;
            }
            let rest: String = c[j..].iter().take(6).collect();
            let sep = [" and ", "–"].into_iter().find(|p| {
                rest.starts_with(p) && rest[p.len()..].starts_with(|d: char| d.is_ascii_digit())
            });
            match sep {
                Some(p) => j += p.chars().count(),
                None => return j,
            }
        }
    };
    while i < c.len() {
        let rest: String = c[i..].iter().take(6).collect();
        let head = ["Figs. ", "Fig. ", "§"]
            .into_iter()
            .find(|p| rest.starts_with(p));
        if let Some(h) = head {
            let j = list_end(i + h.chars().count());
            if j > i + h.chars().count() {
                out.push_str(h.trim_end_matches(['.', ' ']));
                i = j;
                continue;
            }
        }
        out.push(c[i]);
        i += 1;
    }
    out
}

/// No number on the page is typed into a template: rendered from the committed view model and
/// from a copy with every number moved, every piece of the page that carries a digit
/// changes. A piece that stays is a number the template typed in (fill it from data, or name
/// the constant in the view model). Fenced code blocks are left out, as code spans are
/// ([`number_pieces`]): the page's only ones are shell commands to copy, whose arguments are
/// examples, not results.
#[test]
fn templates_fill_every_number_from_data() {
    let model: serde_json::Value =
        serde_json::from_str(include_str!("../../../docs/data/reproduction-page.json"))
            .expect("docs/data/reproduction-page.json: swarm reproduce writes it");
    let a = crate::page::render("reproduction.md.j2", &model).unwrap();
    let b = crate::page::render("reproduction.md.j2", perturbed(&model)).unwrap();
    let (la, lb): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    assert_eq!(la.len(), lb.len(), "the perturbed page has other lines");
    let mut typed = Vec::new();
    let mut fenced = false;
    for (x, y) in la.iter().zip(&lb) {
        if x.starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Piece by piece in place: a moved number may land on another's value elsewhere.
        // A line whose wording turns on a number (a branch of the template) is data's.
        let (before, after) = (number_pieces(x), number_pieces(y));
        if before.len() != after.len() {
            continue;
        }
        typed.extend(
            before
                .into_iter()
                .zip(after)
                .filter(|(p, q)| p == q)
                .map(|(p, _)| p),
        );
    }
    // The ratchet: the pieces typed in today, each to be filled from data or deleted (issue
    // 38); a new one fails, and so does a listed one that is gone (take it off the list).
    super::typed_code::ratchet(
        &typed,
        include_str!("typed_numbers.txt"),
        "typed_numbers.txt",
        "pieces of the page keep their numbers whatever the data (typed into a template; fill them from the view model)",
    );
}
