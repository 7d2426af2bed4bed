//! `--shard I/N` and `cimax merge`, with the built binary: for `arena sweep`, `arena campaign`
//! and `swarm sweep`, three shards merged write the very bytes the unsharded command writes
//! (every file of the output directory) and print the same, whatever the order of the parts;
//! parts that do not make one whole job are refused with the problem named and nothing
//! written; bad `--shard` values are refused by the parser.

mod common;

use std::path::{Path, PathBuf};

use common::{cimax_in, files, merge_in, refused, scratch, text};

/// A small `cimax arena sweep`: 2 positions, 2 runs of 4 robots, 2 moves, 2 runs of the 2D
/// simulator (8 units).
const ARENA_SWEEP: &[&str] = &[
    "arena",
    "sweep",
    "--robots",
    "4",
    "--from",
    "-1",
    "--to",
    "0",
    "--step",
    "1",
    "--runs",
    "2",
    "--moves",
    "2",
    "--swarm-runs",
    "2",
];

/// A small `cimax swarm sweep`: 2 positions, 4 runs each (8 units).
const SWARM_SWEEP: &[&str] = &[
    "swarm", "sweep", "--from", "-1", "--to", "0", "--step", "1", "--runs", "4", "--quiet",
];

/// A smaller one (4 units), for the parts that do not merge.
const TINY_SWEEP: &[&str] = &[
    "swarm", "sweep", "--from", "-1", "--to", "0", "--step", "1", "--runs", "2", "--quiet",
];

/// A small campaign under one rule that misses its bars (90 % loss): 2 scenarios, 2 seeds
/// (4 units); it exits 1, and so must its merge.
const CAMPAIGN: &[&str] = &[
    "arena",
    "campaign",
    "--scenario",
    "cycle-spread",
    "--scenario",
    "dead-end",
    "--seeds",
    "2",
    "--decide",
    "fixed",
    "--loss",
    "0.9",
];

/// The documented campaign's shape (both rules) on one scenario and one seed: 2 campaign runs,
/// 48 of the lab suite, 16 of the loss sweep.
const BOTH_RULES: &[&str] = &[
    "arena",
    "campaign",
    "--scenario",
    "cycle-spread",
    "--seeds",
    "1",
];

/// `a` then `b`.
fn with<'a>(a: &[&'a str], b: &[&'a str]) -> Vec<&'a str> {
    a.iter().chain(b).copied().collect()
}

/// Runs shards 1 to `n` of `args` (each `--shard I/N --out DIR`) into `dir`; returns the
/// parts, in shard order, after checking what each said and that it wrote its part only.
fn shards(args: &[&str], n: u32, dir: &Path, total: u64) -> Vec<PathBuf> {
    let d = dir.to_str().unwrap();
    (1..=n)
        .map(|i| {
            let spec = format!("{i}/{n}");
            let out = cimax_in(dir, &with(args, &["--shard", &spec, "--out", d]));
            assert!(out.status.success(), "shard {spec}: {}", text(&out.stderr));
            let share = total / u64::from(n) + u64::from(total % u64::from(n) >= u64::from(i));
            let said = format!("shard {spec}: {share} of {total} runs");
            assert!(text(&out.stderr).contains(&said), "{}", text(&out.stderr));
            dir.join(format!("part-{i}-of-{n}.jsonl"))
        })
        .collect()
}

/// The unsharded command in `root/whole` (writing into `out`), three shards in `root/parts`,
/// and their merges in `root/merged` and (parts in another order) `root/again`: the outputs,
/// exit codes (the unsharded one `code`), stdout and stderr, each through `mask` (which hides
/// wall times).
fn whole_and_merged(
    root: &Path,
    (args, out): (&[&str], &[&str]),
    total: u64,
    code: i32,
    mask: fn(&str) -> String,
) {
    let _ = std::fs::remove_dir_all(root);
    let whole = cimax_in(&root.join("whole"), &with(args, out));
    assert_eq!(whole.status.code(), Some(code), "{}", text(&whole.stderr));
    let parts = shards(args, 3, &root.join("parts"), total);
    let names: Vec<PathBuf> = files(&root.join("parts")).into_keys().collect();
    assert_eq!(
        names,
        [
            "part-1-of-3.jsonl",
            "part-2-of-3.jsonl",
            "part-3-of-3.jsonl"
        ]
        .map(PathBuf::from),
        "each shard writes its part and nothing else"
    );
    let merged = merge_in(&root.join("merged"), &[&parts[2], &parts[0], &parts[1]]);
    let again = merge_in(&root.join("again"), &[&parts[1], &parts[2], &parts[0]]);
    let expected = files(&root.join("whole").join("out"));
    assert!(expected.len() >= 2, "{:?}", expected.keys());
    for m in [&merged, &again] {
        assert_eq!(m.status.code(), whole.status.code(), "{}", text(&m.stderr));
        assert_eq!(mask(&text(&m.stdout)), mask(&text(&whole.stdout)));
        assert_eq!(mask(&text(&m.stderr)), mask(&text(&whole.stderr)));
    }
    for dir in ["merged", "again"] {
        let got = files(&root.join(dir).join("out"));
        assert_eq!(
            got.keys().collect::<Vec<_>>(),
            expected.keys().collect::<Vec<_>>()
        );
        for (name, bytes) in &expected {
            let m = &got[name];
            if name.extension().is_some_and(|e| e == "md") {
                assert_eq!(mask(&text(m)), mask(&text(bytes)), "{}", name.display());
            } else {
                assert!(m == bytes, "{dir}/out/{} differs", name.display());
            }
        }
    }
    std::fs::remove_dir_all(root).unwrap();
}

/// Nothing to mask: the command prints no time.
fn exact(s: &str) -> String {
    s.to_string()
}

/// `swarm sweep`'s first line ends with its wall time.
fn swarm_wall(s: &str) -> String {
    s.lines()
        .map(|l| match l.rsplit_once(", ") {
            Some((head, t)) if t.ends_with(" s") => format!("{head}, (time)"),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The campaign's tables and page say its wall time (the merge: the shards' added up) and
/// threads: `(X s wall, T threads)` and the page's `in X s on T threads`.
fn campaign_wall(s: &str) -> String {
    s.lines()
        .map(|l| {
            if let (true, Some(i)) = (l.starts_with("CIMAX fault campaign"), l.rfind(" (")) {
                format!("{} (time)", &l[..i])
            } else if l.starts_with("Generated by ") {
                let (head, rest) = l.split_once("` in ").unwrap_or((l, ""));
                let tail = rest.split_once(" threads;").map_or("", |(_, t)| t);
                format!("{head}` in (time) threads;{tail}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn an_arena_sweep_merges_to_the_unsharded_bytes() {
    whole_and_merged(
        &scratch("shard-arena-sweep"),
        (ARENA_SWEEP, &["--out", "out"]),
        8,
        0,
        exact,
    );
}

#[test]
fn with_robots_in_the_loop_an_arena_sweep_and_a_campaign_merge_to_the_unsharded_bytes() {
    // Host twins of the HIL image on the arena's clock in every run (the QEMU robots' stand-in:
    // `.ci/run` compares the two unit for unit).
    whole_and_merged(
        &scratch("shard-arena-sweep-hil"),
        (
            &with(ARENA_SWEEP, &["--hil", "loopback:2"]),
            &["--out", "out"],
        ),
        8,
        0,
        exact,
    );
    whole_and_merged(
        &scratch("shard-campaign-hil"),
        (
            &with(CAMPAIGN, &["--hil", "loopback:1"]),
            &["--out", "out/reliability.md"],
        ),
        4,
        1,
        campaign_wall,
    );
}

#[test]
fn a_swarm_sweep_merges_to_the_unsharded_bytes() {
    whole_and_merged(
        &scratch("shard-swarm-sweep"),
        (SWARM_SWEEP, &["--out-dir", "out"]),
        8,
        0,
        swarm_wall,
    );
}

#[test]
fn a_campaign_merges_to_the_unsharded_page_and_exit_code() {
    whole_and_merged(
        &scratch("shard-campaign"),
        (CAMPAIGN, &["--out", "out/reliability.md"]),
        4,
        1,
        campaign_wall,
    );
}

/// The documented campaign's shape (both rules: the page adds the lab suite under both rules
/// and readings, and the loss sweep) on one scenario and one seed: 66 runs, twice.
#[test]
#[ignore = "about 40 s in a debug build: cargo test -p host-sim --test shard -- --ignored"]
fn a_campaign_of_both_rules_merges_to_the_unsharded_page() {
    whole_and_merged(
        &scratch("shard-campaign-both"),
        (BOTH_RULES, &["--out", "out/reliability.md"]),
        66,
        0,
        campaign_wall,
    );
}

#[test]
fn parts_that_are_not_one_whole_job_are_refused_and_named() {
    let root = scratch("shard-refused");
    let _ = std::fs::remove_dir_all(&root);
    // A scenario file: the job carries its text.
    let scenario = root.join("mine.toml");
    std::fs::create_dir_all(&root).unwrap();
    let sharp = Path::new(env!("CARGO_MANIFEST_DIR")).join("../swarm-sim/scenarios/sharp.toml");
    std::fs::copy(&sharp, &scenario).unwrap();
    let sweep = with(TINY_SWEEP, &["--scenario", scenario.to_str().unwrap()]);
    let p = shards(&sweep, 3, &root.join("parts"), 4);
    let ok = merge_in(&root.join("ok"), &[&p[0], &p[1], &p[2]]);
    assert!(ok.status.success(), "{}", text(&ok.stderr));
    refused(
        &root.join("missing"),
        &[&p[0], &p[2]],
        "missing shard 2 of 3",
    );
    let copy = root.join("copy").join("part-2-of-3.jsonl");
    std::fs::create_dir_all(copy.parent().unwrap()).unwrap();
    std::fs::copy(&p[1], &copy).unwrap();
    refused(
        &root.join("twice"),
        &[&p[0], &p[1], &copy, &p[2]],
        "part-2-of-3.jsonl: shard 2 given twice (also in ",
    );
    // Another seed: another job.
    let seed2 = shards(&with(&sweep, &["--seed", "2"]), 3, &root.join("seed2"), 4);
    refused(
        &root.join("seed"),
        &[&p[0], &seed2[1], &p[2]],
        "part-2-of-3.jsonl: a different job: config differs in \"seed\": 2 vs 1 in ",
    );
    // The scenario file changed between shards.
    let text_now = std::fs::read_to_string(&scenario).unwrap();
    std::fs::write(&scenario, format!("{text_now}\n# edited\n")).unwrap();
    let edited = shards(&sweep, 3, &root.join("edited"), 4);
    refused(
        &root.join("scenario"),
        &[&p[0], &p[1], &edited[2]],
        "config differs in \"scenario\"",
    );
    // Another command.
    let arena = shards(ARENA_SWEEP, 3, &root.join("arena"), 8);
    refused(
        &root.join("command"),
        &[&p[0], &arena[1], &p[2]],
        "a different job (command arena sweep, not swarm sweep)",
    );
    // A part cut short: its last line gone, or cut inside a line.
    let full = std::fs::read_to_string(&p[1]).unwrap();
    let cut = root.join("cut").join("part-2-of-3.jsonl");
    std::fs::create_dir_all(cut.parent().unwrap()).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    std::fs::write(&cut, format!("{}\n", lines[..lines.len() - 1].join("\n"))).unwrap();
    refused(
        &root.join("cut1"),
        &[&p[0], &cut, &p[2]],
        "part-2-of-3.jsonl: truncated (no end line)",
    );
    std::fs::write(&cut, &full[..full.len() - 10]).unwrap();
    refused(
        &root.join("cut2"),
        &[&p[0], &cut, &p[2]],
        &format!("part-2-of-3.jsonl:{}: bad JSON", lines.len()),
    );
    std::fs::write(&cut, "not json\n").unwrap();
    refused(
        &root.join("cut3"),
        &[&p[0], &cut, &p[2]],
        "part-2-of-3.jsonl:1: bad JSON",
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn bad_shard_values_are_refused_by_the_parser() {
    let root = scratch("shard-bad");
    let _ = std::fs::remove_dir_all(&root);
    let d = root.join("parts");
    let d = d.to_str().unwrap();
    let cases = [
        ("0/3", "shards count from 1"),
        ("4/3", "shard 4 of 3: I must be at most N"),
        ("x", "\"x\" is not I/N"),
        ("3", "\"3\" is not I/N"),
        ("1/0", "N must be at least 1"),
        ("a/3", "\"a\" is not a whole number"),
    ];
    for command in [ARENA_SWEEP, SWARM_SWEEP, CAMPAIGN] {
        for (value, why) in cases {
            let out = cimax_in(&root, &with(command, &["--shard", value, "--out", d]));
            assert_eq!(out.status.code(), Some(2), "{command:?} --shard {value}");
            let err = text(&out.stderr);
            assert!(
                err.contains(&format!("invalid value '{value}' for '--shard <I/N>'"))
                    && err.contains(why),
                "{err}"
            );
        }
    }
    // The campaign's part goes where --out says; there is no default.
    let out = cimax_in(&root, &with(CAMPAIGN, &["--shard", "1/3"]));
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--out"), "{}", text(&out.stderr));
    assert!(files(&root).is_empty(), "nothing written");
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_part_in_the_loop_is_set_beside_the_pages_own_runs_of_its_seeds() {
    // One scenario and rule (the documented campaign has both; one keeps the page's lab
    // suite and loss sweep out): a part with a host twin of the HIL image in the loop over
    // seeds 1 and 2, then the page over seeds 1 to 3 with it beside.
    let root = scratch("campaign-hil-part");
    let _ = std::fs::remove_dir_all(&root);
    let scenario = [
        "arena",
        "campaign",
        "--scenario",
        "cycle-spread",
        "--decide",
        "adaptive",
    ];
    // Shard `spec` of the campaign in the loop over seeds 1 and 2, into `dir`: its part.
    let loop_part = |dir: &Path, spec: &str| -> PathBuf {
        let args = [
            "--seeds",
            "2",
            "--hil",
            "loopback:1",
            "--runs-only",
            "--shard",
            spec,
            "--out",
            ".",
        ];
        let out = cimax_in(dir, &with(&scenario, &args));
        assert!(out.status.success(), "{}", text(&out.stderr));
        let (i, n) = spec.split_once('/').unwrap();
        dir.join(format!("part-{i}-of-{n}.jsonl"))
    };
    let part = loop_part(&root.join("loop"), "1/1");
    let part_arg = part.to_str().unwrap();
    let page_dir = root.join("page");
    let out = cimax_in(
        &page_dir,
        &with(
            &scenario,
            &[
                "--seeds",
                "3",
                "--out",
                "reliability.md",
                "--hil-part",
                part_arg,
            ],
        ),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let page = std::fs::read_to_string(page_dir.join("reliability.md")).unwrap();
    assert!(
        page.contains(&format!("--hil-part {part_arg}` in")),
        "{page}"
    );
    let section = &page[page
        .find("## The HIL program's host build in the loop")
        .expect("the section")..];
    assert!(section.contains("`loopback:1` in the loop"), "{section}");
    assert!(section.contains("Seeds 1 to 2"), "{section}");
    assert!(
        section.contains("**2 of 2 runs in the loop right**"),
        "{section}"
    );
    assert!(
        section.contains("| scenario | adaptive: right, in the loop / host |"),
        "{section}"
    );
    assert!(
        section.contains(
            "cimax arena campaign --scenario cycle-spread --decide adaptive --hil loopback:1 \
             --seeds 2 --runs-only --shard 1/1 --out DIR"
        ),
        "{section}"
    );
    assert!(
        section.contains("| `cycle-spread` | 100.0 % / 100.0 % |"),
        "{section}"
    );

    // The same part in two shards, both given after one --hil-part and out of order (as a
    // shell glob may give them): the same section but for how it was made, the parts named
    // in shard order, and the page's command gives them as one glob.
    let two = root.join("two");
    let parts = [loop_part(&two, "1/2"), loop_part(&two, "2/2")];
    let mut args = vec!["--seeds", "3", "--out", "reliability.md", "--hil-part"];
    args.extend(parts.iter().rev().map(|p| p.to_str().unwrap()));
    let out = cimax_in(&root.join("page-two"), &with(&scenario, &args));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let page2 = std::fs::read_to_string(root.join("page-two").join("reliability.md")).unwrap();
    let section2 = &page2[page2.find("## The HIL").unwrap()..];
    assert!(
        section2.contains("**2 of 2 runs in the loop right**"),
        "{section2}"
    );
    assert!(
        section2.contains("--runs-only --shard I/2 --out DIR, I = 1 to 2"),
        "{section2}"
    );
    let two_slashed = two.to_str().unwrap().replace('\\', "/");
    assert!(
        section2.contains(&format!(
            "committed parts `{two_slashed}/part-I-of-2.jsonl, I = 1 to 2`"
        )),
        "{section2}"
    );
    assert!(
        page2.contains(&format!("--hil-part {two_slashed}/part-*-of-2.jsonl` in")),
        "{page2}"
    );
    let table = |s: &str| s[s.find("| scenario").unwrap()..].to_string();
    assert_eq!(table(section), table(section2));

    // Refused before any run, naming the part: other scenarios, seeds the page does not run,
    // a part without robots in the loop, no such file; and no page is written.
    let plain = root.join("plain");
    let out = cimax_in(
        &plain,
        &with(&scenario, &["--seeds", "1", "--shard", "1/1", "--out", "."]),
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let plain_part = plain.join("part-1-of-1.jsonl");
    let missing = root.join("no-such-part.jsonl");
    for (args, why) in [
        (
            vec!["--scenario", "cycle-spread", "--seeds", "3"],
            "scenarios, rules or loss",
        ),
        (
            vec![
                "--scenario",
                "cycle-spread",
                "--decide",
                "adaptive",
                "--seeds",
                "1",
            ],
            "its seeds 1 to 2 are not all among this campaign's (1 to 1)",
        ),
    ] {
        let mut a = vec!["arena", "campaign"];
        a.extend(args);
        a.extend(["--out", "refused.md", "--hil-part", part_arg]);
        let out = cimax_in(&root.join("refused"), &a);
        assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
        assert!(
            text(&out.stderr).contains(part_arg),
            "{}",
            text(&out.stderr)
        );
        assert!(text(&out.stderr).contains(why), "{}", text(&out.stderr));
    }
    for (p, why) in [
        (&plain_part, "without robots in the loop"),
        (&missing, "no-such-part.jsonl"),
    ] {
        let out = cimax_in(
            &root.join("refused"),
            &with(
                &scenario,
                &[
                    "--seeds",
                    "1",
                    "--out",
                    "refused.md",
                    "--hil-part",
                    p.to_str().unwrap(),
                ],
            ),
        );
        assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
        assert!(text(&out.stderr).contains(why), "{}", text(&out.stderr));
    }
    // A part whose header was edited to hold no seeds: named, not a panic.
    let edited = root.join("no-seeds.jsonl");
    let text_of = std::fs::read_to_string(&part).unwrap();
    assert!(text_of.contains("\"seeds\":2"));
    std::fs::write(&edited, text_of.replacen("\"seeds\":2", "\"seeds\":0", 1)).unwrap();
    let out = cimax_in(
        &root.join("refused"),
        &with(
            &scenario,
            &[
                "--seeds",
                "1",
                "--out",
                "refused.md",
                "--hil-part",
                edited.to_str().unwrap(),
            ],
        ),
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("no-seeds.jsonl"),
        "{}",
        text(&out.stderr)
    );
    assert!(!root.join("refused").join("refused.md").exists());
    let _ = std::fs::remove_dir_all(&root);
}
