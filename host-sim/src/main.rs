//! `cimax`: the CIMAX command-line tool.
//!
//! `cimax arena` runs the paper's four-robot lab experiment (section 4): the six light patterns
//! and the alternating experiment, and checks that the robots' LEDs show the expected decisions.
//! For now the robots are wired directly ([`protocol::line`]: frames reach the neighbours at
//! once, with no light-medium model); the emulated arena over `hal-emu` replaces that wiring.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use protocol::line::{Happening, Line};
use protocol::{Event, Instant, Level, Params, Sector};
use rand_pcg::Pcg32;

#[derive(Parser, Debug)]
#[command(
    name = "cimax",
    version,
    about = "CIMAX swarm tools: the lab arena and (later) 2D swarm simulations"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The four-robot lab experiment: six light patterns and the alternating experiment.
    Arena {
        /// Base seed; run k of a pattern uses seed + k.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Runs per pattern.
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=10_000))]
        runs: u64,
    },
}

const ROBOTS: usize = 4;
/// Robot time per run: three negotiation periods of the longest (70 s) cycles.
const RUN_S: u64 = 3 * 10 * 70;

/// Expected LEDs for a pattern with one border: each robot prefers the border's direction and
/// all follow the majority; on an exact tie each side moves toward the border.
fn expected(pattern: &[u8; ROBOTS]) -> Option<[Option<Sector>; ROBOTS]> {
    let borders: Vec<usize> = (1..ROBOTS)
        .filter(|&i| pattern[i] != pattern[i - 1])
        .collect();
    let &[b] = borders.as_slice() else {
        return None;
    };
    let (left, right) = (b, ROBOTS - b);
    Some(core::array::from_fn(|i| {
        let toward = if i < b { Sector::RIGHT } else { Sector::LEFT };
        // Robots left of the border prefer right and vice versa: the majority is the larger side.
        Some(match left.cmp(&right) {
            std::cmp::Ordering::Greater => Sector::RIGHT,
            std::cmp::Ordering::Less => Sector::LEFT,
            std::cmp::Ordering::Equal => toward,
        })
    }))
}

fn leds(d: &[Option<Sector>]) -> String {
    d.iter()
        .map(|s| match *s {
            Some(Sector::LEFT) => 'L',
            Some(Sector::RIGHT) => 'R',
            _ => '-',
        })
        .collect()
}

fn readings(p: &[u8; ROBOTS]) -> [Level; ROBOTS] {
    p.map(|b| Level(if b == b'1' { 1 } else { 0 }))
}

struct Outcome {
    leds: [Option<Sector>; ROBOTS],
    /// Time of the last LED change, i.e. since when the LEDs show their final state.
    settled_s: f64,
}

/// Runs one line from `start` to `end`, returning its LEDs and when they last changed.
fn run(line: &mut Line<Pcg32, ROBOTS>, end: Instant) -> Outcome {
    let mut settled = line.now();
    line.run_until(end, |t, _, h| {
        if let Happening::Event(Event::Decided { changed: true, .. }) = h {
            settled = t;
        }
    });
    Outcome {
        leds: line.decisions(),
        settled_s: settled.as_secs_f64(),
    }
}

fn new_line(pattern: &[u8; ROBOTS], seed: u64) -> Line<Pcg32, ROBOTS> {
    let rngs = core::array::from_fn(|i| Pcg32::new(seed, 2 * i as u64 + 1));
    match Line::new(Params::robots(), readings(pattern), rngs) {
        Ok(l) => l,
        Err(e) => unreachable!("the paper's parameters validate: {e}"),
    }
}

fn arena(seed: u64, runs: u64) -> ExitCode {
    let cycle_s = Params::robots().wave.cycle.as_secs_f64();
    println!(
        "CIMAX lab arena: {ROBOTS} robots in a line, ideal direct links (no light medium yet), {runs} runs per pattern"
    );
    println!(
        "{:<10} {:<9} {:<40} {:>8} {:>22}",
        "pattern", "expected", "LEDs per run", "success", "consensus s (cycles)"
    );
    let mut failures = Vec::new();
    let mut total = 0;
    let patterns = ["1000", "0111", "0001", "1110", "1100", "0011"];
    let mut row = |name: String, exp: [Option<Sector>; ROBOTS], outs: Vec<(u64, Outcome)>| {
        let ok = outs.iter().filter(|(_, o)| o.leds == exp).count();
        let mean = outs.iter().map(|(_, o)| o.settled_s).sum::<f64>() / outs.len() as f64;
        let runs_s: Vec<String> = outs.iter().map(|(_, o)| leds(&o.leds)).collect();
        println!(
            "{:<10} {:<9} {:<40} {:>7.0}% {:>13.0} ({:>5.1})",
            name,
            leds(&exp),
            runs_s.join(" "),
            100.0 * ok as f64 / outs.len() as f64,
            mean,
            mean / cycle_s
        );
        total += outs.len();
        for (s, o) in &outs {
            if o.leds != exp {
                failures.push(format!(
                    "{name} seed {s}: LEDs {} expected {}",
                    leds(&o.leds),
                    leds(&exp)
                ));
            }
        }
    };
    for p in patterns {
        let pat: [u8; ROBOTS] = p.as_bytes().try_into().expect("four characters");
        let exp = expected(&pat).expect("one border");
        let outs = (0..runs)
            .map(|k| {
                let s = seed + k;
                (s, run(&mut new_line(&pat, s), Instant::from_secs(RUN_S)))
            })
            .collect();
        row(p.to_string(), exp, outs);
    }
    // Alternating: after consensus on 1000 the pattern is mirrored; the LEDs must follow.
    let (a, b) = (*b"1000", *b"0001");
    let outs = (0..runs)
        .map(|k| {
            let s = seed + k;
            let mut l = new_line(&a, s);
            let first = run(&mut l, Instant::from_secs(RUN_S));
            l.set_readings(readings(&b));
            let mut second = run(&mut l, Instant::from_secs(2 * RUN_S));
            if first.leds != expected(&a).expect("one border") {
                second.leds = first.leds;
            }
            second.settled_s -= RUN_S as f64;
            (s, second)
        })
        .collect();
    row("1000>0001".into(), expected(&b).expect("one border"), outs);

    if failures.is_empty() {
        println!("all {total} runs successful");
        ExitCode::SUCCESS
    } else {
        for f in &failures {
            eprintln!(
                "FAILED {f} (replay: cimax arena --seed {} --runs 1)",
                f.split_whitespace().nth(2).unwrap_or("?")
            );
        }
        ExitCode::FAILURE
    }
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Arena { seed, runs } => arena(seed, runs),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expected_outcomes_follow_the_border_rule() {
        let l = Some(Sector::LEFT);
        let r = Some(Sector::RIGHT);
        assert_eq!(expected(b"1000"), Some([l; 4]));
        assert_eq!(expected(b"1110"), Some([r; 4]));
        assert_eq!(expected(b"0011"), Some([r, r, l, l]));
        assert_eq!(expected(b"1010"), None);
        assert_eq!(expected(b"0000"), None);
    }
}
