//! The `replay:` command of a failed run, derived from the command line that ran it: every
//! option given, as typed (so that an option added to [`ArenaArgs`] is repeated without a line
//! here), but those the replay sets itself ([`NOT_REPLAYED`]). The run's own pattern and seed
//! come from its configuration ([`lab::line::replay_lights`]).

use clap::parser::ValueSource;
use clap::{ArgMatches, Args as _};

use super::ArenaArgs;

/// The options a replay does not repeat: those it sets itself for the one run (`--lights`,
/// `--switch-at`, `--then`, `--seed`, `--runs`), the outputs (`--json`, `--trace`, `--svg`,
/// `--html`) and `--threads` (results do not depend on it).
pub(super) const NOT_REPLAYED: [&str; 10] = [
    "lights",
    "switch_at",
    "then",
    "seed",
    "runs",
    "json",
    "trace",
    "svg",
    "html",
    "threads",
];

/// The options of `matches` (of `cimax arena`) that a replay repeats, each as ` --name VALUE`,
/// in the order of `cimax arena --help`.
pub(super) fn replay_options(matches: &ArgMatches) -> String {
    let cmd = ArenaArgs::augment_args(clap::Command::new("arena"));
    let mut out = String::new();
    for arg in cmd.get_arguments() {
        let id = arg.get_id().as_str();
        if NOT_REPLAYED.contains(&id) || matches.value_source(id) != Some(ValueSource::CommandLine)
        {
            continue;
        }
        let Some(long) = arg.get_long() else { continue };
        if !arg.get_action().takes_values() {
            out += &format!(" --{long}");
            continue;
        }
        let delimiter = arg.get_value_delimiter().map(String::from);
        for values in matches.get_raw_occurrences(id).into_iter().flatten() {
            let values: Vec<String> = values.map(|v| quoted(&v.to_string_lossy())).collect();
            match &delimiter {
                Some(d) => out += &format!(" --{long} {}", values.join(d)),
                None => {
                    for v in values {
                        out += &format!(" --{long} {v}");
                    }
                }
            }
        }
    }
    out
}

/// `v` as a shell word: as it is if it needs no quotes, else in single quotes.
fn quoted(v: &str) -> String {
    let plain = !v.is_empty()
        && v.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.,:/@+=%".contains(c));
    if plain {
        v.to_string()
    } else {
        format!("'{}'", v.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::super::line::build;
    use super::super::print::replay_command;
    use super::super::tests::{Cli, Cmd};
    use super::*;
    use clap::{CommandFactory as _, FromArgMatches as _};
    use lab::line::replay_lights;

    /// The options and matches of `cimax arena ARGS...`.
    fn parse(a: &[String]) -> (ArenaArgs, ArgMatches) {
        let m = Cli::command()
            .try_get_matches_from(
                ["cimax", "arena"]
                    .iter()
                    .map(|s| s.to_string())
                    .chain(a.iter().cloned()),
            )
            .unwrap_or_else(|e| panic!("{a:?}: {e}"));
        let Cmd::Arena(args) = Cli::from_arg_matches(&m).unwrap().command;
        let (_, sub) = m.subcommand().unwrap();
        (args, sub.clone())
    }

    /// Splits a replay command as a shell would (words, single quotes).
    fn words(line: &str) -> Vec<String> {
        let mut out = Vec::new();
        let (mut word, mut quoted, mut any) = (String::new(), false, false);
        for c in line.chars() {
            match c {
                '\'' => (quoted, any) = (!quoted, true),
                ' ' if !quoted => {
                    if any || !word.is_empty() {
                        out.push(std::mem::take(&mut word));
                    }
                    any = false;
                }
                c => word.push(c),
            }
        }
        if any || !word.is_empty() {
            out.push(word);
        }
        out
    }

    /// Every option of `cimax arena` on a line with a value unlike its default, but those a
    /// replay sets itself, and `--hil` (a robot in the loop needs a link; its replay is below).
    fn every_option() -> Vec<Vec<&'static str>> {
        vec![
            vec!["--robots", "4"],
            vec!["--spacing", "1.25"],
            vec!["--range", "1.75"],
            vec!["--duration", "300"],
            vec!["--readings", "levels:16"],
            vec!["--readings", "gain:0.5,offset:100"],
            vec!["--binary-readings"],
            vec!["--loss", "0.05"],
            vec!["--byte-error-rate", "0.001"],
            vec!["--no-collisions"],
            vec!["--bitrate", "4800"],
            vec!["--cycle", "20"],
            vec!["--cycle-spread", "3"],
            vec!["--refractory", "2"],
            vec!["--negotiation", "5"],
            vec!["--decide", "adaptive"],
            vec!["--kill", "1@100", "--kill", "2@150"],
            vec!["--kill", "1@100", "--restart", "1@200"],
            vec!["--key", "000102030405060708090a0b0c0d0e0f"],
        ]
    }

    #[test]
    fn every_replay_line_parses_back_to_the_configuration_of_its_run() {
        let cmd = ArenaArgs::augment_args(clap::Command::new("arena"));
        let tested: Vec<&str> = every_option().iter().flatten().copied().collect();
        // Options that only make sense elsewhere (on a plane, with robots in the loop).
        let elsewhere = [
            "shape",
            "positions",
            "sectors",
            "field",
            "x_init",
            "moves",
            "hil",
            "hil_at",
            "hil_image",
            "hil_clock",
        ];
        for arg in cmd.get_arguments() {
            let id = arg.get_id().as_str();
            let long = format!("--{}", arg.get_long().unwrap_or(id));
            assert!(
                NOT_REPLAYED.contains(&id)
                    || elsewhere.contains(&id)
                    || tested.contains(&long.as_str()),
                "{long}: add it to every_option()"
            );
        }
        for extra in every_option() {
            let mut a: Vec<String> = ["--runs", "2", "--seed", "40"].map(String::from).to_vec();
            a.extend(extra.iter().map(|s| s.to_string()));
            let (args, m) = parse(&a);
            let experiments = build(&args).unwrap();
            let options = replay_options(&m);
            for flag in extra.iter().filter(|f| f.starts_with("--")) {
                assert!(options.contains(flag), "{flag} in {options:?}");
            }
            for e in &experiments {
                for cfg in &e.configs {
                    // What `print_failures` prints after `replay: `.
                    let line = replay_command(&replay_lights(cfg), cfg.seed, &options);
                    let argv = words(&line);
                    assert_eq!(argv[..2], ["cimax", "arena"], "{line}");
                    let (again, _) = parse(&argv[2..]);
                    let replayed = build(&again).unwrap();
                    assert_eq!(replayed.len(), 1, "{line}");
                    assert_eq!(replayed[0].configs.len(), 1, "{line}");
                    assert_eq!(
                        format!("{:?}", replayed[0].configs[0]),
                        format!("{cfg:?}"),
                        "{line}"
                    );
                }
            }
        }
    }

    #[test]
    fn robots_in_the_loop_and_odd_values_replay_as_typed() {
        let a: Vec<String> = [
            "--hil",
            "loopback:1",
            "--hil-at",
            "2",
            "--hil-image",
            "my image.elf",
            "--hil-clock",
            "virtual",
            "--lights",
            "1100",
        ]
        .map(String::from)
        .to_vec();
        let (_, m) = parse(&a);
        let options = replay_options(&m);
        assert_eq!(
            options,
            " --hil loopback:1 --hil-clock virtual --hil-at 2 --hil-image 'my image.elf'"
        );
        assert_eq!(
            words(&options),
            [
                "--hil",
                "loopback:1",
                "--hil-clock",
                "virtual",
                "--hil-at",
                "2",
                "--hil-image",
                "my image.elf"
            ]
        );
    }
}
