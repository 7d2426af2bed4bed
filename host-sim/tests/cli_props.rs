//! Issue 36, Deliver 2: a property test over the command line. Argument vectors are drawn from
//! the subcommands, their options and edge-case values (negative, zero, huge, NaN, infinite,
//! empty, malformed, folders and missing paths where paths go); each runs the real binary with
//! a time limit. Whatever the arguments, `cimax` ends with 0, 1 or 2 (never 101), never prints
//! `panicked`, and never outlives its limit: every command starts from options that keep its
//! runs small, and the options drawn leave those alone.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;

/// How long one small command may take (a debug build, on a busy machine).
const LIMIT: Duration = Duration::from_secs(30);

/// Values drawn for any option: edge cases of every kind.
const VALUES: &[&str] = &[
    "-1",
    "0",
    "1",
    "2",
    "7",
    "-0.1",
    "0.5",
    "1e300",
    "-1e300",
    "nan",
    "inf",
    "-inf",
    "",
    " ",
    "18446744073709551616",
    "4294967296",
    "1100",
    "1010",
    "10x1",
    "abc",
    "1@5",
    "9@1",
    "1@-1",
    "adir",
    "afile",
    "missing/deeper/x.out",
    "-",
    "sharp",
    "gradient",
    "cloud",
    "1/2",
    "0/0",
    "levels:2",
    "gain:0.5,offset:100",
    "adaptive",
    "lattice",
    "random",
    "file",
    "000102",
];

/// A command that stays small: its words, the options that keep it small, and the options
/// drawn from (without those).
struct Small {
    words: &'static [&'static str],
    options: &'static [&'static str],
}

const COMMANDS: &[Small] = &[
    Small {
        words: &["arena", "--runs", "1", "--duration", "40"],
        options: &[
            "--robots",
            "--lights",
            "--switch-at",
            "--then",
            "--seed",
            "--readings",
            "--binary-readings",
            "--loss",
            "--byte-error-rate",
            "--no-collisions",
            "--bitrate",
            "--cycle",
            "--cycle-spread",
            "--refractory",
            "--negotiation",
            "--decide",
            "--kill",
            "--restart",
            "--json",
            "--trace",
            "--svg",
            "--html",
            "--key",
            "--spacing",
            "--range",
            "--threads",
            "--field",
        ],
    },
    Small {
        words: &[
            "arena", "--field", "sharp", "--robots", "7", "--moves", "1", "--runs", "1",
        ],
        options: &[
            "--shape",
            "--positions",
            "--sectors",
            "--x-init",
            "--seed",
            "--loss",
            "--range",
            "--cycle",
            "--json",
            "--trace",
            "--html",
            "--readings",
            "--svg",
            "--lights",
            "--decide",
        ],
    },
    Small {
        words: &[
            "arena",
            "sweep",
            "--robots",
            "7",
            "--from",
            "0",
            "--to",
            "0",
            "--runs",
            "1",
            "--moves",
            "1",
            "--swarm-runs",
            "1",
        ],
        options: &[
            "--field",
            "--shape",
            "--sectors",
            "--seed",
            "--loss",
            "--readings",
            "--out",
            "--shard",
        ],
    },
    Small {
        words: &[
            "arena",
            "campaign",
            "--scenario",
            "rogue",
            "--seeds",
            "1",
            "--decide",
            "fixed",
        ],
        options: &[
            "--seed", "--loss", "--out", "--figure", "--trace", "--shard",
        ],
    },
    Small {
        words: &["arena", "bench", "--robots", "4"],
        options: &["--sectors", "--seed"],
    },
    Small {
        words: &[
            "swarm",
            "run",
            "--periods",
            "1",
            "--quiet",
            "--out-dir",
            "out",
        ],
        options: &[
            "--scenario",
            "--seed",
            "--cycle",
            "--placement",
            "--csv",
            "--plot",
            "--x",
            "--y",
            "--html",
            "--lattice",
        ],
    },
    Small {
        words: &[
            "swarm",
            "sweep",
            "--runs",
            "1",
            "--from",
            "0",
            "--to",
            "0",
            "--quiet",
            "--out-dir",
            "out",
        ],
        options: &[
            "--scenario",
            "--seed",
            "--cycle",
            "--placement",
            "--csv",
            "--plot",
            "--shard",
        ],
    },
    Small {
        words: &["swarm", "bench", "--agents", "20"],
        options: &["--seed", "--scenario"],
    },
    Small {
        words: &["view"],
        options: &[
            "-o",
            "--output",
            "adir",
            "afile",
            "missing.jsonl",
            "t.jsonl",
        ],
    },
    Small {
        words: &["merge"],
        options: &["--out", "afile", "adir", "t.jsonl", "missing.jsonl"],
    },
];

/// One command line: a small command and up to four options, each with a value or none.
fn command_line() -> impl Strategy<Value = Vec<String>> {
    (0..COMMANDS.len()).prop_flat_map(|c| {
        let small = &COMMANDS[c];
        let option = (
            proptest::sample::select(small.options),
            proptest::option::of(proptest::sample::select(VALUES)),
        );
        proptest::collection::vec(option, 0..=4).prop_map(move |opts| {
            let mut words: Vec<String> = small.words.iter().map(|s| s.to_string()).collect();
            for (o, v) in opts {
                words.push(o.to_string());
                if let Some(v) = v {
                    words.push(v.to_string());
                }
            }
            words
        })
    })
}

/// The folder the commands run in: a folder `adir`, a file `afile`, a trace `t.jsonl`.
fn workdir(name: &str) -> std::path::PathBuf {
    let dir = common::scratch(name);
    std::fs::create_dir_all(dir.join("adir")).unwrap();
    std::fs::write(dir.join("afile"), "0 0\n0.5 0\n").unwrap();
    std::fs::write(dir.join("t.jsonl"), "{\"t_ms\":0,\"event\":\"sent\"}\n").unwrap();
    dir
}

/// Runs `cimax args...` in `dir` within [`LIMIT`]; what went wrong, if anything.
fn misbehaves(dir: &Path, args: &[String]) -> Option<String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cimax"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cimax starts");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Some(format!("still running after {LIMIT:?}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    match status.code() {
        _ if err.contains("panicked") => Some(format!("panicked: {err}")),
        Some(0..=2) => None,
        code => Some(format!("exit {code:?}: {err}")),
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn no_command_line_panics_or_hangs(args in command_line()) {
        let dir = workdir("props");
        let bad = misbehaves(&dir, &args);
        prop_assert!(bad.is_none(), "cimax {:?}: {}", args, bad.unwrap_or_default());
    }
}
