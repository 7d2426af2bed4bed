//! The `cimax` binary: exit codes and messages.

mod common;

use common::{cimax, scratch};

#[test]
fn a_bad_scenario_file_names_the_line_and_fails() {
    let dir = scratch("cli");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "[swarm]\nagents = 61\n\n[[field]]\nalong = \"z\"\nsegments = [{ from = 0.0, level = 1.0 }]\n",
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let out = cimax(&["swarm", "run", "--scenario", p, "--periods", "1", "--quiet"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("{p}:5:9:")), "{err}");
    assert!(err.contains("unknown along = \"z\""), "{err}");

    std::fs::write(&path, "noise = [1\n").unwrap();
    let out = cimax(&["swarm", "sweep", "--scenario", p, "--quiet"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("{p}:1:")), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn swarm_run_writes_csv_and_svg() {
    let dir = scratch("run");
    let d = dir.to_str().unwrap();
    let out = cimax(&[
        "swarm",
        "run",
        "--x",
        "-1",
        "--periods",
        "3",
        "--out-dir",
        d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("sharp-run.csv")).unwrap();
    assert_eq!(
        csv.lines().count(),
        1 + 1 + 3,
        "header, start, 3 periods:\n{csv}"
    );
    let svg = std::fs::read_to_string(dir.join("sharp-run.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn arena_runs_the_paper_suite_in_the_emulator() {
    let out = cimax(&["arena", "--runs", "1"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("12 runs, 12 successful"), "{stdout}");
    // Every pattern's alternating experiment, with the LEDs before and after the mirroring.
    for row in [
        "1000>0001    LLLL>RRRR  RRRR ",
        "0111>1110    LLLL>RRRR  RRRR ",
        "0001>1000    RRRR>LLLL  LLLL ",
        "1110>0111    RRRR>LLLL  LLLL ",
        "1100>0011    RRLL>RRLL  RRLL ",
        "0011>1100    RRLL>RRLL  RRLL ",
    ] {
        assert!(stdout.contains(row), "{row:?} in\n{stdout}");
    }
    let out = cimax(&["arena", "--runs", "1", "--binary-readings"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("binary readings (g = 1 lit, 0 dark)"),
        "{stdout}"
    );
    assert!(stdout.contains("12 runs, 12 successful"), "{stdout}");
}

#[test]
fn arena_failing_runs_exit_1_and_print_the_command_that_replays_them() {
    // 100 s is too short for a decision: every LED is still off, every run fails.
    let out = cimax(&["arena", "--runs", "1", "--duration", "100", "--seed", "7"]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("12 runs, 0 successful"), "{stdout}");
    let stderr = String::from_utf8_lossy(&out.stderr);
    for replay in [
        "FAILED 1100 seed 7: LEDs ----, expected RRLL (replay: cimax arena --lights 1100 \
         --seed 7 --runs 1 --duration 100)",
        "FAILED 1100 seed 7: LEDs ----, expected RRLL; but pattern 0011 showed LEDs ---- when \
         it changed at 100 s, expected RRLL (a switch before the first decision: no robot had \
         decided yet) (replay: cimax arena --lights 0011 --switch-at 100 --then 1100 --seed 7 \
         --runs 1 --duration 100)",
    ] {
        assert!(stderr.contains(replay), "{replay:?} in\n{stderr}");
    }
}

#[test]
fn arena_json_trace_and_svg() {
    let dir = scratch("arena");
    std::fs::create_dir_all(&dir).unwrap();
    let trace = dir.join("t.jsonl");
    let svg = dir.join("t.svg");
    let html = dir.join("t.html");
    let out = cimax(&[
        "arena",
        "--lights",
        "0011",
        "--runs",
        "2",
        "--loss",
        "0.1",
        "--json",
        "--trace",
        trace.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--html",
        html.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["summary"]["runs"], 2);
    assert_eq!(v["summary"]["successes"], 2);
    assert_eq!(v["runs"][0]["leds"], "RRLL");
    assert_eq!(v["runs"][1]["seed"], 2);
    let lines = std::fs::read_to_string(&trace).unwrap();
    assert!(lines.lines().count() > 100);
    // The first line is the run's set-up (the viewer's header), then one event per line.
    let header: serde_json::Value = serde_json::from_str(lines.lines().next().unwrap()).unwrap();
    assert_eq!(header["header"]["lights"][0]["expected"], "RRLL");
    assert_eq!(header["header"]["verdict"]["leds"], "RRLL");
    for l in lines.lines().skip(1) {
        let e: serde_json::Value = serde_json::from_str(l).unwrap();
        assert!(e["event"].is_string() && e["t_ms"].is_u64(), "{l}");
    }
    assert!(lines.contains(r#""reason":"loss""#));
    assert!(lines.contains(r#""event":"decided""#));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    // The page, and the same page again from the saved trace.
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("window.cimax"));
    assert!(
        !page.contains("http://") && !page.contains("https://"),
        "no network"
    );
    let again = dir.join("again.html");
    let out = cimax(&[
        "view",
        trace.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read_to_string(&again).unwrap(), page);
    // A file that is no trace is named, and nothing is written.
    let bad = dir.join("bad.html");
    let out = cimax(&["view", svg.to_str().unwrap(), "-o", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("t.svg:1: not a trace header"));
    assert!(!bad.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn arena_bad_options_name_the_problem() {
    for (args, needle) in [
        (
            &["arena", "--robots", "5", "--lights", "1100"][..],
            "has 4 robots but there are 5",
        ),
        (&["arena", "--lights", "10x0"], "character 3"),
        (&["arena", "--kill", "7@100"], "no robot 7"),
        (&["arena", "--kill", "1-100"], "ROBOT@SECONDS"),
        (&["arena", "--loss", "2"], "loss"),
        (&["arena", "--refractory", "60"], "refractory"),
        (&["arena", "--robots", "65"], "65"),
        (&["arena", "--lights", "1"], "2 to 64 robots"),
        (
            &["arena", "--lights", "", "--kill", "0@1"],
            "2 to 64 robots",
        ),
    ] {
        let out = cimax(args);
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn arena_with_a_swarm_key() {
    let out = cimax(&[
        "arena",
        "--lights",
        "1100",
        "--runs",
        "2",
        "--key",
        "000102030405060708090A0B0C0D0E0F",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("2 runs, 2 successful"), "{stdout}");
    // Link version 3 carries the key to robots in the loop on the arena's clock (two host
    // twins here), and refuses it for one on its own clock, before any work.
    let key = "000102030405060708090A0B0C0D0E0F";
    let out = cimax(&[
        "arena",
        "--lights",
        "1100",
        "--runs",
        "1",
        "--key",
        key,
        "--hil",
        "loopback:2",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("1 runs, 1 successful"), "{stdout}");
    let out = cimax(&[
        "arena",
        "--lights",
        "1100",
        "--key",
        key,
        "--hil",
        "serial:/dev/null@9600",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--key with --hil serial:/dev/null") && err.contains("on its own clock"),
        "{err}"
    );
    for (key, needle) in [
        ("0011", "32 hex digits (128 bits), not 4"),
        ("0x0102030405060708090a0b0c0d0e0f", "character 2"),
        ("", "not 0"),
    ] {
        let out = cimax(&["arena", "--lights", "1100", "--key", key]);
        assert_eq!(out.status.code(), Some(2), "--key {key:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--key") && err.contains(needle),
            "{key:?}: {err}"
        );
    }
}

#[test]
fn bad_plane_options_exit_2_naming_the_problem() {
    for (args, says) in [
        (&["arena", "--field", "nosuch"][..], "nosuch"),
        (
            &["arena", "--field", "sharp", "--lights", "1010"],
            "--lights",
        ),
        (
            &["arena", "--field", "sharp", "--x-init", "NaN"],
            "--x-init",
        ),
        (&["arena", "--field", "sharp", "--sectors", "9"], "9"),
        (&["arena", "--sectors", "6"], "--field"),
        (&["arena", "sweep", "--from", "2", "--to", "1"], "--from"),
        (
            &["arena", "sweep", "--field", "cloud"],
            "no success criterion",
        ),
        (
            &["arena", "sweep", "--hil", "tcp:127.0.0.1:9"],
            "only qemu:N and loopback:N",
        ),
        (
            &["arena", "sweep", "--hil", "qemu:2", "--sectors", "4"],
            "2 (hil) or 6 (hil6) receivers",
        ),
        (
            &["arena", "--field", "sharp", "--shape", "file"],
            "--positions",
        ),
        (
            &[
                "arena",
                "--field",
                "sharp",
                "--shape",
                "file",
                "--positions",
                "/no/such/file",
            ],
            "/no/such/file",
        ),
    ] {
        let out = cimax(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn a_small_lattice_over_the_sharp_field_reports_json() {
    let out = cimax(&[
        "arena", "--field", "sharp", "--robots", "19", "--x-init", "-1", "--moves", "4", "--runs",
        "1", "--json",
    ]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let run = &v["runs"][0];
    assert_eq!(run["consensus"].as_array().unwrap().len(), 4);
    assert!(run["final_position"][0].as_f64().unwrap() > -1.0, "{run}");
    assert_eq!(v["summary"]["runs"], 1);
}

#[test]
fn counts_and_sizes_beyond_their_limits_fail_naming_the_option() {
    for (args, says) in [
        (&["swarm", "sweep", "--runs", "0"][..], "--runs"),
        (&["swarm", "sweep", "--runs", "100001"], "from 1 to 100000"),
        (
            &["swarm", "sweep", "--runs", "18446744073709551616"],
            "--runs",
        ),
        (
            &["swarm", "sweep", "--runs", "100000", "--quiet"],
            "--runs 100000: 21 positions × 100000 runs = 2100000 runs; at most 1000000",
        ),
        (&["swarm", "run", "--periods", "4294967295"], "--periods"),
        (&["swarm", "run", "--periods", "0"], "--periods"),
        (&["swarm", "bench", "--agents", "1"], "--agents"),
        (&["swarm", "bench", "--agents", "61,1000001"], "--agents"),
        (
            &["swarm", "run", "--cycle", "18446744073709551615", "--quiet"],
            "--cycle",
        ),
        (
            &["swarm", "run", "--cycle", "600000", "--quiet"],
            "--cycle 600000: a negotiation period of (gather_cycles + decide_cycles) × cycle = (1 + 1) × 600000 s = 1200000 s is longer than the limit of 1000000 s",
        ),
        (
            &["swarm", "field", "--cycle", "400000", "--quiet"],
            "--cycle 400000 with the scenario's [grid]:",
        ),
        (&["--threads", "0", "swarm", "run"], "--threads"),
        (&["--threads", "100000000000", "swarm", "run"], "--threads"),
        (&["arena", "--duration", "1000001"], "--duration"),
        (&["arena", "--cycle", "1e9"], "at most 1000000"),
        (
            &["arena", "sweep", "--step", "1e-9"],
            "positions; at most 10001",
        ),
        (
            &[
                "arena", "sweep", "--from", "0", "--to", "1", "--step", "0.001", "--runs", "1000",
            ],
            "--runs 1000: 1001 positions × 1000 runs = 1001000 runs; at most 1000000",
        ),
        (
            &["arena", "sweep", "--swarm-runs", "100001"],
            "--swarm-runs",
        ),
        (&["arena", "bench", "--robots", "4,10001"], "--robots"),
    ] {
        let out = cimax(args);
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn a_scenario_too_large_to_place_fails_naming_the_key() {
    let dir = scratch("huge");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge.toml");
    let p = path.to_str().unwrap();
    for (swarm, at, says) in [
        (
            "diameter = 1e5",
            "3:12:",
            "diameter = 100000: at most 1000 R",
        ),
        (
            "shape = \"rectangle\"\nwidth = 6.0\nheight = 1e300",
            "5:10:",
            "height = 1e300: at most 1000 R",
        ),
    ] {
        std::fs::write(
            &path,
            format!(
                "[swarm]\nagents = 61\n{swarm}\n\n[[field]]\nalong = \"x\"\nsegments = [{{ from = 0.0, level = 1.0 }}]\n"
            ),
        )
        .unwrap();
        let out = cimax(&["swarm", "run", "--scenario", p, "--periods", "1", "--quiet"]);
        assert_eq!(out.status.code(), Some(2), "{swarm}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("{p}:{at} {says}")), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn agents_sit_on_the_lattice_unless_placement_random() {
    let dir = scratch("placement");
    let d = dir.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["swarm", "run", "--periods", "1", "--out-dir", d];
        args.extend_from_slice(extra);
        cimax(&args)
    };
    for extra in [&[][..], &["--placement", "lattice"], &["--lattice"]] {
        let out = run(extra);
        assert!(out.status.success(), "{extra:?}");
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(
            said.contains("(lattice placement): 61 agents (mean 5.1 neighbours)"),
            "{said}"
        );
        assert!(dir.join("sharp-run.csv").exists(), "{extra:?}");
    }
    let out = run(&["--placement", "random"]);
    assert!(out.status.success());
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("(random placement): 61 agents"), "{said}");
    assert!(dir.join("sharp-random-run.csv").exists());

    let out = run(&["--placement", "grid"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("random or lattice"));
    let out = run(&["--lattice", "--placement", "random"]);
    assert_eq!(out.status.code(), Some(2));

    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("hex.toml");
    std::fs::write(
        &path,
        "[swarm]\nagents = 7\nshape = \"lattice\"\nspacing = 1.0\n\n[[field]]\nalong = \"x\"\nsegments = [{ from = 0.0, level = 1.0 }]\n",
    )
    .unwrap();
    let p = path.to_str().unwrap();
    let out = run(&["--scenario", p, "--placement", "random", "--quiet"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--placement random: scenario"), "{err}");
    let out = run(&["--scenario", p, "--quiet"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
