//! `cimax swarm reproduce --shard I/N` and `cimax merge` of its parts, with the built binary.
//! The fast tests use the cheapest units (a split into 53 shards of one unit each: unit 50 is
//! one wave, unit 52 the placements' neighbour counts) and crafted parts: parts that are not
//! one whole page are refused with the problem named and nothing written. The ignored test
//! runs the whole page unsharded and in three shards and compares every file (minutes in
//! release: `cargo test --release -p host-sim --test shard_reproduce -- --ignored`).

mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use common::{cimax_in, files, merge_in, scratch, text};
use serde_json::Value;

/// Units of the page.
const UNITS: u64 = 53;

/// Shard `i` of `n` of `swarm reproduce EXTRA...` into `dir`: checks what it said and returns
/// its part.
fn shard(dir: &Path, i: u32, n: u32, extra: &[&str]) -> PathBuf {
    let spec = format!("{i}/{n}");
    let mut args = vec![
        "swarm",
        "reproduce",
        "--shard",
        &spec,
        "--docs",
        dir.to_str().unwrap(),
    ];
    args.extend(extra);
    let out = cimax_in(dir, &args);
    assert!(out.status.success(), "shard {spec}: {}", text(&out.stderr));
    let share = UNITS / u64::from(n) + u64::from(UNITS % u64::from(n) >= u64::from(i));
    let said = format!("shard {spec}: {share} of {UNITS} units of swarm reproduce, into ");
    assert!(text(&out.stderr).contains(&said), "{}", text(&out.stderr));
    let part = dir.join(format!("part-{i}-of-{n}.jsonl"));
    assert_eq!(
        text(&out.stdout),
        format!("wrote {}\n", part.display()),
        "a shard writes its part only"
    );
    part
}

/// A merge that must fail ([`common::refused`]), and nothing written beside `out` either (the
/// reproduce merge writes into a folder beside it first).
fn refused(dir: &Path, parts: &[&PathBuf], message: &str) {
    common::refused(dir, parts, message);
    let beside: Vec<PathBuf> = files(dir).into_keys().collect();
    assert_eq!(beside, [PathBuf::from("out/keep.txt")], "nothing beside it");
}

/// A part's lines: the header, the unit lines, the end line.
fn lines(part: &Path) -> Vec<String> {
    std::fs::read_to_string(part)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

/// Writes a part of one shard of one (`1/1`) with `header` (its `units` set to `units`) and a
/// unit line per result, numbered from 0.
fn crafted(path: &Path, header: &str, units: u64, results: &[Value]) {
    let mut h: Value = serde_json::from_str(header).unwrap();
    h["shard"] = serde_json::json!({"index": 1, "count": 1});
    h["units"] = units.into();
    let mut s = format!("{h}\n");
    for (k, r) in results.iter().enumerate() {
        s += &format!("{}\n", serde_json::json!({"unit": k, "result": r}));
    }
    s += &format!(
        "{}\n",
        serde_json::json!({"end": true, "units": results.len()})
    );
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, s).unwrap();
}

#[test]
fn reproduce_parts_that_are_not_one_whole_page_are_refused_and_named() {
    let root = scratch("shard-reproduce-refused");
    let _ = std::fs::remove_dir_all(&root);
    let parts = root.join("parts");
    let wave = shard(&parts, 51, 53, &["--quiet"]);
    let placements = shard(&parts, 53, 53, &["--quiet"]);
    refused(
        &root.join("missing"),
        &[&placements, &wave],
        &format!(
            "missing shards {} of 53",
            (1..=50)
                .chain([52])
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    );
    // Another seed, another placement: another job.
    let seed2 = shard(&root.join("seed2"), 53, 53, &["--quiet", "--seed", "2"]);
    refused(
        &root.join("seed"),
        &[&wave, &seed2],
        &format!(
            "part-53-of-53.jsonl: a different job: config differs in \"seed\": 2 vs 1 in {}",
            wave.display()
        ),
    );
    let random = shard(&root.join("random"), 53, 53, &["--placement", "random"]);
    refused(
        &root.join("placement"),
        &[&random, &wave],
        "config differs in \"placement\": \"random\" vs \"lattice\"",
    );
    // The same shard twice; the same unit twice in a part.
    let copy = root.join("copy").join("part-53-of-53.jsonl");
    std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
    std::fs::copy(&placements, &copy).unwrap();
    refused(
        &root.join("twice"),
        &[&wave, &placements, &copy],
        "shard 53 given twice (also in ",
    );
    let l = lines(&placements);
    let doubled = root.join("doubled").join("part-53-of-53.jsonl");
    std::fs::create_dir_all(doubled.parent().unwrap()).unwrap();
    let end = l[2].replace("\"units\":1", "\"units\":2");
    std::fs::write(&doubled, format!("{}\n{}\n{}\n{end}\n", l[0], l[1], l[1])).unwrap();
    refused(
        &root.join("unit-twice"),
        &[&wave, &doubled],
        "part-53-of-53.jsonl:3: unit 52 given twice (also on line 2)",
    );
    // Whole parts (every unit there) whose results are not the page's: the placements'
    // result for every unit; unit 0's result of the wrong kind; a job of 52 units.
    let result: Value = serde_json::from_str::<Value>(&l[1]).unwrap()["result"].clone();
    let forged = root.join("forged").join("part-1-of-1.jsonl");
    crafted(&forged, &l[0], UNITS, &vec![result.clone(); UNITS as usize]);
    refused(
        &root.join("other-unit"),
        &[&forged],
        "part-1-of-1.jsonl: unit 0: bad result: the result of placements, not of run/sharp",
    );
    let mut all = vec![result.clone(); UNITS as usize];
    all[0]["unit"] = "run/sharp".into();
    crafted(&forged, &l[0], UNITS, &all);
    refused(
        &root.join("kind"),
        &[&forged],
        "part-1-of-1.jsonl: unit 0: bad result: run/sharp: the result is not of this unit's kind",
    );
    crafted(&forged, &l[0], UNITS - 1, &vec![result; UNITS as usize - 1]);
    refused(
        &root.join("fewer"),
        &[&forged],
        "part-1-of-1.jsonl: a job this cimax cannot redo: 52 units, but swarm reproduce has 53",
    );
    // The part of a shard needs a directory: there is no default (docs/ is the page's).
    let out = cimax_in(&root, &["swarm", "reproduce", "--shard", "1/3"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("--docs"),
        "{}",
        text(&out.stderr)
    );
    std::fs::remove_dir_all(&root).unwrap();
}

/// The page's lines with the two that tell the time and speed of the run that wrote it (CI's
/// staleness diff leaves them out too) hidden.
fn untimed(page: &str) -> String {
    page.lines()
        .map(|l| {
            if l.starts_with("Generated by ") || l.starts_with("Speed: ") {
                "(timing)"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The lines of `swarm reproduce`'s output that give the sweeps (two per sweep).
fn sweeps(stdout: &[u8]) -> Vec<String> {
    text(stdout)
        .lines()
        .skip_while(|l| !l.starts_with("sharp border sweep, "))
        .take(8)
        .map(str::to_string)
        .collect()
}

/// The whole page unsharded, and in three shards merged (the parts given in another order):
/// every figure and CSV file the same bytes; the page the same but for its timing lines, which
/// in the merged page say what the parts' results say (the units' wall times added up, the
/// most threads a unit ran on).
#[test]
#[ignore = "runs the whole page twice (minutes in release): cargo test --release -p host-sim --test shard_reproduce -- --ignored"]
fn three_shards_merge_to_the_unsharded_page() {
    let root = scratch("shard-reproduce-whole");
    let _ = std::fs::remove_dir_all(&root);
    let t = Instant::now();
    let whole = cimax_in(&root, &["swarm", "reproduce", "--quiet", "--docs", "whole"]);
    assert!(whole.status.success(), "{}", text(&whole.stderr));
    eprintln!("unsharded: {:.0} s", t.elapsed().as_secs_f64());
    let dir = root.join("parts");
    let parts: Vec<PathBuf> = (1..=3)
        .map(|i| {
            let t = Instant::now();
            let p = shard(&dir, i, 3, &[]);
            eprintln!("shard {i}/3: {:.0} s", t.elapsed().as_secs_f64());
            p
        })
        .collect();
    let t = Instant::now();
    let merged = merge_in(&root.join("merged"), &[&parts[1], &parts[2], &parts[0]]);
    assert!(merged.status.success(), "{}", text(&merged.stderr));
    eprintln!("merge: {:.1} s", t.elapsed().as_secs_f64());
    assert_eq!(sweeps(&merged.stdout), sweeps(&whole.stdout));
    assert_eq!(sweeps(&merged.stdout).len(), 8, "{}", text(&merged.stdout));
    let expected = files(&root.join("whole"));
    let got = files(&root.join("merged").join("out"));
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        expected.keys().collect::<Vec<_>>()
    );
    assert!(expected.len() > 50, "{:?}", expected.keys());
    for (name, bytes) in &expected {
        if name == Path::new("reproduction.md") {
            assert_eq!(untimed(&text(&got[name])), untimed(&text(bytes)));
        } else {
            assert!(&got[name] == bytes, "{} differs", name.display());
        }
    }
    // The merged page's time and threads: the parts' units'.
    let (mut wall, mut threads) = (0.0, 0);
    for p in &parts {
        for l in &lines(p)[1..] {
            let v: Value = serde_json::from_str(l).unwrap();
            if let Some(r) = v.get("result") {
                wall += r["wall_s"].as_f64().unwrap();
                threads = threads.max(r["threads"].as_u64().unwrap());
            }
        }
    }
    let page = text(&got[Path::new("reproduction.md")]);
    let said = format!("swarm reproduce --seed 1` in {wall:.0} s on {threads} threads (");
    assert!(page.contains(&said), "{said}");
    assert!(page.contains(&format!(
        "; the whole page in {wall:.0} s on {threads} threads."
    )));
    std::fs::remove_dir_all(&root).unwrap();
}
