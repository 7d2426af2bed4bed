//! Issue 36: `cimax` as a Unix tool. Each test runs the real binary and checks its exit code,
//! its message and the files it leaves behind.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::{cimax, scratch, text};

/// Runs `cimax ARGS...` with its standard output going to `stdout`.
fn cimax_to(stdout: Stdio, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cimax"))
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("cimax runs")
}

/// Runs `cimax ARGS...` writing into a pipe whose reader is already gone (`cimax ... | true`).
fn into_closed_pipe(args: &[&str]) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    cimax_to(Stdio::from(writer), args)
}

/// Runs `cimax ARGS...` writing into `/dev/full`.
fn into_full_disk(args: &[&str]) -> Output {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    cimax_to(Stdio::from(full), args)
}

/// No panic and no backtrace on stderr.
fn assert_no_panic(out: &Output) {
    let err = text(&out.stderr);
    assert_ne!(out.status.code(), Some(101), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_closed_pipe_ends_quietly_with_0() {
    for args in [
        &["arena", "--lights", "1100", "--runs", "1"][..],
        &["arena", "--lights", "1100", "--runs", "1", "--json"],
        &["swarm", "run", "--periods", "1", "--quiet", "--out-dir"],
    ] {
        let dir = scratch("pipe");
        let mut args = args.to_vec();
        let d = dir.to_string_lossy().into_owned();
        if args.last() == Some(&"--out-dir") {
            args.push(&d);
        }
        let out = into_closed_pipe(&args);
        assert_no_panic(&out);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            text(&out.stderr)
        );
        assert!(out.stderr.is_empty(), "{args:?}: {}", text(&out.stderr));
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn a_full_disk_is_named_and_exits_1() {
    let dir = scratch("full");
    let d = dir.to_string_lossy().into_owned();
    for args in [
        &["arena", "--lights", "1100", "--runs", "1", "--json"][..],
        &["arena", "--lights", "1100", "--runs", "1"],
        &["swarm", "bench", "--agents", "20"],
        &["swarm", "run", "--periods", "1", "--quiet", "--out-dir", &d],
    ] {
        let out = into_full_disk(args);
        assert_no_panic(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert_eq!(
            text(&out.stderr).trim_end(),
            "cimax: cannot write standard output: No space left on device",
            "{args:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cimax ARGS...` must fail with exit code 2 and `message` on stderr.
fn usage_error(args: &[&str], message: &str) -> Output {
    let out = cimax(args);
    assert_no_panic(&out);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(message), "{args:?}: {message:?} in\n{err}");
    out
}

#[test]
fn swarm_usage_and_input_errors_exit_2_as_arena_does() {
    usage_error(&["swarm", "run", "--scenario", "nosuch"], "nosuch");
    usage_error(&["swarm", "run", "--bogus"], "--bogus");
    usage_error(&["arena", "--lights", "10x1"], "10x1");
    let missing = Path::new("/nonexistent-cimax/s.toml");
    usage_error(
        &["swarm", "sweep", "--scenario", missing.to_str().unwrap()],
        "nonexistent-cimax",
    );
}

#[test]
fn a_robot_in_the_loop_whose_link_does_not_open_is_a_set_up_error() {
    for (spec, says) in [
        ("tcp:127.0.0.1:1", "tcp:127.0.0.1:1: Connection refused"),
        ("serial:/dev/nosuch", "serial:/dev/nosuch: No such file"),
    ] {
        let out = usage_error(
            &[
                "arena", "--hil", spec, "--lights", "1100", "--runs", "1", "--cycle", "2",
            ],
            "its link did not open",
        );
        let err = text(&out.stderr);
        assert!(err.contains(says), "{err}");
        // No verdict line, no table: nothing ran.
        assert!(!err.contains("FAILED"), "{err}");
        assert!(!err.contains("expected"), "{err}");
        assert!(out.stdout.is_empty(), "{}", text(&out.stdout));
    }
}

#[test]
fn the_qemu_image_is_found_from_any_folder() {
    let checkout = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let image = checkout.join("firmware/qemu/target/thumbv7em-none-eabihf/release/hil");
    if image.is_file() {
        // Built here: the run would boot QEMU; the message below is for a missing image.
        return;
    }
    let dir = scratch("qemu");
    let out = common::cimax_in(&dir, &["arena", "--hil", "qemu:1", "--lights", "1100"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    // The checkout's image, by its absolute path, not one relative to the working folder.
    let said = checkout
        .canonicalize()
        .unwrap()
        .join("firmware/qemu/target");
    assert!(
        err.contains(&format!("no image at {}", said.display())),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn numbers_that_are_not_finite_too_large_or_negative_are_refused_with_what_is_allowed() {
    for (args, says) in [
        (
            &["swarm", "run", "--periods", "1", "--x", "inf"][..],
            "inf is not a finite number",
        ),
        (
            &["swarm", "run", "--periods", "1", "--y", "inf"],
            "inf is not a finite number",
        ),
        (
            &["swarm", "run", "--x", "nan"],
            "nan is not a finite number",
        ),
        (&["swarm", "run", "--x", "1e300"], "from -1000 to 1000"),
        (
            &["arena", "--field", "sharp", "--x-init", "1e300"],
            "from -1000 to 1000",
        ),
        (
            &["arena", "--field", "sharp", "--x-init", "inf"],
            "not a finite number",
        ),
        (
            &["arena", "--loss", "-0.1"],
            "'-0.1' for '--loss <LOSS>': -0.1 is out of range; a probability from 0 to 1",
        ),
        (
            &["arena", "--byte-error-rate", "2"],
            "a probability from 0 to 1",
        ),
        (&["arena", "--range", "-1"], "'-1' for '--range <RANGE>'"),
        (&["arena", "--cycle", "-1"], "'-1' for '--cycle <CYCLE>'"),
        (
            &["arena", "--seed", "-1"],
            "'-1' for '--seed <SEED>': -1 is out of range; a whole number from 0",
        ),
        (&["arena", "--spacing", "0"], "greater than 0"),
        (
            &["swarm", "run", "--seed", "-1"],
            "'-1' for '--seed <SEED>'",
        ),
        (
            &["swarm", "run", "--cycle", "-1"],
            "'-1' for '--cycle <CYCLE>'",
        ),
        (
            &["swarm", "sweep", "--step", "-1"],
            "'-1' for '--step <STEP>'",
        ),
        (
            &["arena", "campaign", "--loss", "-0.5"],
            "a probability from 0 to 1",
        ),
        (
            &["arena", "sweep", "--runs", "-2"],
            "'-2' for '--runs <RUNS>'",
        ),
    ] {
        let out = usage_error(args, says);
        assert!(out.stdout.is_empty(), "{args:?}");
        assert!(
            !text(&out.stderr).contains("unexpected argument"),
            "{args:?}"
        );
    }
    // Negative values where they are allowed still pass.
    let dir = scratch("negative");
    let out = cimax(&[
        "swarm",
        "run",
        "--x",
        "-1",
        "--y",
        "-0.5",
        "--periods",
        "1",
        "--quiet",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_positions_file_with_a_far_double_or_lonely_robot_is_refused_naming_the_line() {
    let dir = scratch("positions");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("p.txt");
    let f = file.to_str().unwrap();
    for (body, says) in [
        (
            "0 0\n0.5 0\n1e300 0\n",
            ":3: 1e300 is too far: at most 1000 R",
        ),
        (
            "0 0\n0.5 0\n0 0\n",
            ":3: two robots in one place: (0, 0) is also on line 1",
        ),
        (
            "0 0\n0.5 0\n50 0\n",
            ":3: the robot at (50, 0) is out of everyone's range",
        ),
    ] {
        std::fs::write(&file, body).unwrap();
        usage_error(
            &[
                "arena",
                "--field",
                "sharp",
                "--shape",
                "file",
                "--positions",
                f,
                "--runs",
                "1",
            ],
            &format!("{f}{says}"),
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The `replay: cimax ...` commands on stderr, as argument vectors (no quoted words in these).
fn replays(stderr: &str) -> Vec<Vec<String>> {
    stderr
        .lines()
        .filter_map(|l| l.split_once("(replay: cimax ")?.1.strip_suffix(')'))
        .map(|c| c.split_whitespace().map(String::from).collect())
        .collect()
}

#[test]
fn a_failing_run_replays_with_every_option_it_ran_with() {
    let args = [
        "arena",
        "--lights",
        "1100",
        "--runs",
        "1",
        "--seed",
        "3",
        "--kill",
        "1@700",
        "--key",
        "000102030405060708090a0b0c0d0e0f",
        "--byte-error-rate",
        "0.001",
        "--bitrate",
        "4800",
        "--json",
    ];
    let out = cimax(&args);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let failed: Vec<&str> = err.lines().filter(|l| l.starts_with("FAILED")).collect();
    assert_eq!(failed.len(), 1, "{err}");
    let replay = &replays(&err)[0];
    for option in ["--kill", "--key", "--byte-error-rate", "--bitrate"] {
        assert!(replay.iter().any(|a| a == option), "{option} in {replay:?}");
    }
    // Outputs are not repeated.
    assert!(!replay.iter().any(|a| a == "--json"), "{replay:?}");
    let again: Vec<&str> = replay.iter().map(String::as_str).collect();
    let out = cimax(&again);
    let err2 = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "the replay fails too: {err2}");
    let failed2: Vec<&str> = err2.lines().filter(|l| l.starts_with("FAILED")).collect();
    assert_eq!(failed, failed2, "the same failure, the same replay");
    // Without the kill the run passes: the replay needed it.
    let mut without: Vec<&str> = again.clone();
    let k = without.iter().position(|a| *a == "--kill").unwrap();
    without.drain(k..k + 2);
    assert_eq!(cimax(&without).status.code(), Some(0));
}

#[test]
fn a_failing_alternating_run_of_the_suite_replays_with_its_switch_and_cycle() {
    // --cycle 20: the suite's runs last 764.65 s, and the alternating ones switch then.
    let out = cimax(&["arena", "--runs", "1", "--cycle", "20", "--duration", "30"]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let all = replays(&err);
    assert_eq!(all.len(), 12, "{err}");
    let switching = all
        .iter()
        .find(|r| r.iter().any(|a| a == "--switch-at"))
        .unwrap();
    let again: Vec<&str> = switching.iter().map(String::as_str).collect();
    assert!(
        again.windows(2).any(|w| w == ["--switch-at", "30"]),
        "{again:?}"
    );
    assert!(
        again.windows(2).any(|w| w == ["--cycle", "20"]),
        "{again:?}"
    );
    assert_eq!(cimax(&again).status.code(), Some(1));
}

#[test]
fn a_pattern_without_a_verdict_is_not_judged_not_a_success() {
    let out = cimax(&["arena", "--lights", "1010", "--runs", "2"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let said = text(&out.stdout);
    assert!(
        said.contains("2 runs, 0 successful, 2 not judged (no verdict for the pattern)"),
        "{said}"
    );
    let out = cimax(&["arena", "--lights", "1010", "--runs", "2", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["summary"]["successes"], 0);
    assert_eq!(v["summary"]["not_judged"], 2);
    assert!(v["runs"][0]["success"].is_null(), "{}", v["runs"][0]);
    // A judged run keeps its boolean.
    let out = cimax(&["arena", "--lights", "1100", "--runs", "1", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["runs"][0]["success"], true);
    assert_eq!(v["summary"]["not_judged"], 0);
}

#[test]
fn a_switch_before_the_first_decision_is_said_to_be_one() {
    let out = cimax(&[
        "arena",
        "--lights",
        "1000",
        "--switch-at",
        "100",
        "--then",
        "0001",
        "--runs",
        "1",
    ]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "but pattern 1000 showed LEDs ---- when it changed at 100 s, expected LLLL (a switch \
             before the first decision: no robot had decided yet)"
        ),
        "{err}"
    );
}

#[test]
fn kills_and_restarts_that_cannot_be_are_refused() {
    let base = ["arena", "--lights", "1100", "--runs", "1"];
    for (extra, says) in [
        (
            &["--restart", "0@100"][..],
            "--restart 0@100: robot 0 is alive then",
        ),
        (
            &["--kill", "0@200", "--restart", "0@100"],
            "--restart 0@100: robot 0 is alive then",
        ),
        (
            &["--kill", "1@700", "--kill", "1@700"],
            "--kill 1@700 is given twice",
        ),
        (
            &["--kill", "1@700", "--kill", "1@800"],
            "--kill 1@800: robot 1 is already dead then",
        ),
    ] {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let out = usage_error(&args, says);
        assert!(out.stdout.is_empty());
    }
    // A kill, a restart, a kill again: one run, judged.
    let args: Vec<&str> = base
        .iter()
        .chain(&["--kill", "1@700", "--restart", "1@800", "--kill", "1@900"])
        .copied()
        .collect();
    assert!(matches!(cimax(&args).status.code(), Some(0 | 1)));
}

#[test]
fn an_alternating_run_in_json_carries_both_patterns_and_the_switch() {
    let out = cimax(&[
        "arena",
        "--lights",
        "1000",
        "--switch-at",
        "2101",
        "--then",
        "0001",
        "--runs",
        "1",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let p = &v["runs"][0]["patterns"];
    assert_eq!(p[0]["at_s"], 0.0);
    assert_eq!(p[0]["lights"], "1000");
    assert_eq!(p[0]["expected"], "LLLL");
    assert_eq!(p[1]["at_s"], 2101.0);
    assert_eq!(p[1]["lights"], "0001");
    assert_eq!(p[1]["expected"], "RRRR");
    // One pattern: no `patterns`.
    let out = cimax(&["arena", "--lights", "1100", "--runs", "1", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["runs"][0].get("patterns").is_none());
}

#[test]
fn a_line_option_on_a_plane_is_refused_with_the_reason() {
    let base = [
        "arena", "--field", "sharp", "--robots", "7", "--moves", "1", "--runs", "1",
    ];
    for (extra, says) in [
        (
            &["--duration", "100"][..],
            "--duration (a plane runs --moves",
        ),
        (
            &["--key", "000102030405060708090a0b0c0d0e0f"],
            "--key (the robots on a plane run without",
        ),
        (
            &["--spacing", "2"],
            "--spacing (robots on a plane are placed by --shape",
        ),
    ] {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        usage_error(&args, says);
    }
}

#[test]
fn plane_runs_draw_a_progress_bar_on_a_terminal_only() {
    // `script` gives the command a terminal; without it (no util-linux) there is none to test.
    let bin = env!("CARGO_BIN_EXE_cimax");
    let cmd = format!("{bin} arena --field sharp --robots 7 --moves 1 --runs 6");
    let Ok(out) = Command::new("script")
        .args(["-qec", &cmd, "/dev/null"])
        .stdin(Stdio::null())
        .output()
    else {
        return;
    };
    let tty = text(&out.stdout);
    assert!(out.status.success(), "{tty}");
    assert!(
        tty.contains("arena plane [") && tty.contains("/6 runs"),
        "{tty}"
    );
    // Not a terminal: no bar.
    let out = cimax(&[
        "arena", "--field", "sharp", "--robots", "7", "--moves", "1", "--runs", "6",
    ]);
    assert!(out.status.success());
    assert!(
        !text(&out.stderr).contains("arena plane ["),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn the_arena_timeline_has_a_time_axis_a_legend_and_text_of_11_px_or_more() {
    let dir = scratch("svg");
    let svg = dir.join("t.svg");
    let out = cimax(&[
        "arena",
        "--lights",
        "1100",
        "--runs",
        "1",
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = std::fs::read_to_string(&svg).unwrap();
    for label in [
        "time (s)",
        ">0<",
        ">1000<",
        ">2000<",
        "LED left (L)",
        "LED right (R)",
        "LED off",
        "wave: active",
        "wave: refractory",
        "frame sent",
        "frame received",
        "received garbled, or dropped",
        "robot 3",
    ] {
        let bare = label.trim_matches(|c| c == '<' || c == '>');
        let found = s.contains(label) || s.contains(&format!(">\n{bare}\n<"));
        assert!(found, "{label:?} in the timeline");
    }
    let sizes: Vec<f64> = s
        .split("font-size=\"")
        .skip(1)
        .map(|r| r.split('"').next().unwrap().parse().unwrap())
        .collect();
    assert!(sizes.len() > 20, "{sizes:?}");
    assert!(sizes.iter().all(|&px| px >= 11.0), "{sizes:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merge_into_a_full_disk_is_named_and_exits_1() {
    let dir = scratch("merge-full");
    let d = dir.to_str().unwrap();
    let out = cimax(&[
        "swarm",
        "sweep",
        "--runs",
        "1",
        "--from",
        "0",
        "--to",
        "0",
        "--quiet",
        "--shard",
        "1/1",
        "--out-dir",
        d,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let part = dir.join("part-1-of-1.jsonl");
    let merged = dir.join("merged");
    let out = into_full_disk(&[
        "merge",
        part.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert_no_panic(&out);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr).trim_end(),
        "cimax: cannot write standard output: No space left on device"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
