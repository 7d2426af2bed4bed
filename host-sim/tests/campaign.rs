//! `cimax arena campaign`: the fault campaign meets its bars on a few seeds, reports a missed
//! bar with exit code 1, prints replay commands that reproduce their run, does not depend on
//! the number of threads, and refuses bad options with exit code 2.

mod common;

use common::{cimax, pool, scratch};
use lab::campaign::{self, Decide, Plan, SCENARIOS};
use pages::reliability;
use swarm_sim::progress::Progress;

fn index(name: &str) -> usize {
    SCENARIOS.iter().position(|s| s.name == name).unwrap()
}

#[test]
fn a_small_campaign_meets_the_bars() {
    // Seeds 1 to 6 cover the six patterns once.
    let plan = Plan {
        scenarios: (0..SCENARIOS.len()).collect(),
        seed: 1,
        seeds: 6,
        loss: None,
        decide: Decide::Fixed,
        hil: None,
    };
    let report = campaign::run(&plan, &Progress::hidden()).unwrap();
    assert_eq!(report.results.len(), SCENARIOS.len());
    for r in &report.results {
        assert_eq!(r.runs.len(), 6);
        let patterns: std::collections::BTreeSet<&str> =
            r.runs.iter().map(|o| o.pattern.as_str()).collect();
        assert_eq!(patterns.len(), 6, "{}: every pattern once", r.scenario.name);
        for o in &r.runs {
            assert!(
                o.success,
                "{} seed {}: LEDs {} expected {} ({:?})",
                r.scenario.name, o.seed, o.leds, o.expected, o.why
            );
            assert!(o.consensus_s.is_some_and(|c| c > 300.0));
        }
        assert_ne!(r.passed(), Some(false), "{}", r.scenario.name);
        match r.scenario.name {
            "loss-20" => assert!(r.runs.iter().all(|o| o.medium.lost > 0)),
            "byte-errors" => assert!(r.runs.iter().all(|o| o.medium.corrupted_bytes > 0)),
            "rogue" => assert!(r.runs.iter().all(|o| {
                o.medium.rogue_bursts > 500 && o.medium.garbled > 0 && o.frame_errors > 500
            })),
            "dead-end" => assert!(r.runs.iter().all(|o| o.leds.contains('-'))),
            "replayer" => assert!(r.runs.iter().all(|o| o.medium.replayed > 50)),
            "reboot" => assert!(
                r.runs
                    .iter()
                    .all(|o| o.restore_s.is_some_and(|s| s > 0.0 && s <= 1100.0))
            ),
            _ => {}
        }
    }
    assert!(report.missed().is_empty());
    let md = reliability::markdown(&report, Some("figures/reliability.svg"));
    assert!(
        md.contains("| `loss-20` | 6 | 100.0 % (6) | 95 % | **PASS** |"),
        "{md}"
    );
    assert!(md.contains("Every bar is met."));
}

#[test]
fn results_do_not_depend_on_the_number_of_threads() {
    let plan = Plan {
        scenarios: vec![index("reboot"), index("rogue"), index("replayer")],
        seed: 40,
        seeds: 3,
        loss: None,
        decide: Decide::Fixed,
        hil: None,
    };
    let on = |threads| {
        let r = pool(threads).install(|| campaign::run(&plan, &Progress::hidden()).unwrap());
        format!("{:?}", r.results)
    };
    assert_eq!(on(1), on(2));
}

#[test]
fn a_missed_bar_exits_1_names_it_and_its_replay_reproduces_the_run() {
    let dir = scratch("campaign-fail");
    let out = dir.join("r.md");
    let res = cimax(&[
        "arena",
        "campaign",
        "--scenario",
        "loss-10",
        "--loss",
        "0.9",
        "--seeds",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&res.stderr);
    assert_eq!(res.status.code(), Some(1), "{err}");
    assert!(err.contains("bar missed: loss-10"), "{err}");
    let md = std::fs::read_to_string(&out).unwrap();
    assert!(md.contains("**FAIL**") && md.contains("--loss 0.9"), "{md}");
    // Both decision rules, side by side, with their figure.
    assert!(
        md.contains("## The fixed and the adaptive decision rule")
            && md.contains("adaptive rule: bar missed: `loss-10`"),
        "{md}"
    );
    assert!(
        std::fs::read_to_string(dir.join("figures/reliability-rules.svg"))
            .unwrap()
            .starts_with("<svg")
    );
    assert!(
        std::fs::read_to_string(dir.join("figures/reliability.svg"))
            .unwrap()
            .starts_with("<svg")
    );
    // The first failure's replay command, run as printed, fails the same way.
    let line = err.lines().find(|l| l.starts_with("FAILED")).unwrap();
    let leds = line
        .split("LEDs ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap();
    let replay = line.split("replay: cimax ").nth(1).unwrap();
    let args: Vec<&str> = replay.split_whitespace().collect();
    let again = cimax(&args);
    assert_eq!(again.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&again.stdout);
    assert!(stdout.contains(&format!("LEDs {leds}, FAILED")), "{stdout}");
    assert!(
        !stdout.contains("wrote"),
        "a replay writes no report: {stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn campaign_bad_options_name_the_problem_and_exit_2() {
    for (args, needle) in [
        (&["arena", "campaign", "--scenario", "nope"][..], "nope"),
        (&["arena", "campaign", "--loss", "2"], "--loss"),
        (&["arena", "campaign", "--seeds", "0"], "--seeds"),
        (&["arena", "--loss", "0.1", "campaign"], "campaign"),
        (
            &["arena", "campaign", "--hil", "loopback:5"],
            "5 robots in the loop",
        ),
        (
            &["arena", "campaign", "--hil", "tcp:127.0.0.1:9"],
            "only qemu:N and loopback:N",
        ),
        (
            &[
                "arena",
                "campaign",
                "--hil",
                "qemu:1",
                "--hil-image",
                "/no/such.elf",
            ],
            "/no/such.elf",
        ),
    ] {
        let out = cimax(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn the_robot_in_the_loop_is_the_one_rebooted_and_recovers_on_the_arenas_clock() {
    // The HIL program's host build (a twin, on the lockstep) in the place of the robot the
    // scenario kills and boots again: consensus comes back, and the replay line says so.
    let hil = campaign::InTheLoop {
        robots: 1,
        image: None,
    };
    let reboot = &SCENARIOS[index("reboot")];
    for seed in [2, 9] {
        let (cfg, t) =
            campaign::run_config(reboot, seed, None, Decide::Adaptive, Some(&hil)).unwrap();
        assert_eq!(cfg.hil.len(), 1);
        assert_eq!(cfg.hil[0].robot, cfg.kills[0].1, "seed {seed}");
        assert!(t.is_some());
        let o = campaign::run_in_loop(reboot, seed, None, Decide::Adaptive, Some(&hil)).unwrap();
        assert!(o.success && !o.crashed, "seed {seed}: {o:?}");
        assert!(o.restore_s.is_some(), "seed {seed}: {o:?}");
    }
    let plan = Plan {
        scenarios: vec![index("reboot")],
        seed: 2,
        seeds: 1,
        loss: None,
        decide: Decide::Adaptive,
        hil: Some(hil),
    };
    assert!(
        campaign::replay_command("reboot", 2, &plan)
            .ends_with("--decide adaptive --hil loopback:1")
    );
}
