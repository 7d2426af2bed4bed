//! The judge: the paper's lab experiment (section 4) as runs of the emulated world (robots in a
//! line under a light pattern), and the check a person makes by looking at the top-cap LEDs.
//! It only reads what a run reports ([`RunReport`]); the world and the board know nothing of
//! it.

use firmware::LedColor;
use protocol::{Duration, Instant};

use crate::world::arena::{ArenaConfig, ArenaError, RunReport, run};

/// The six patterns of the paper's Fig. 13, lit = 1, robots left to right
/// ([`protocol::lab::PAPER_LIGHTS`]; their decisions are [`protocol::lab::PAPER`], which
/// [`expected`] agrees with).
pub const PAPER_PATTERNS: [&str; 6] = protocol::lab::PAPER_LIGHTS;

/// A light pattern: one entry per robot, `true` if lit.
pub type Pattern = Vec<bool>;

/// Parses a pattern of `0`s and `1`s.
///
/// # Errors
/// The first character that is neither.
pub fn parse_pattern(s: &str) -> Result<Pattern, PatternError> {
    s.chars()
        .enumerate()
        .map(|(i, c)| match c {
            '1' => Ok(true),
            '0' => Ok(false),
            _ => Err(PatternError {
                pattern: s.to_string(),
                at: i + 1,
                found: c,
            }),
        })
        .collect()
}

/// Why [`parse_pattern`] refused a pattern: a character that is neither `0` nor `1`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("pattern {pattern:?}: character {at} is {found:?}, expected 0 or 1")]
pub struct PatternError {
    /// The pattern.
    pub pattern: String,
    /// The character's place, from 1.
    pub at: usize,
    /// The character.
    pub found: char,
}

/// A pattern as `0`/`1` text.
pub fn pattern_str(p: &[bool]) -> String {
    p.iter().map(|&b| if b { '1' } else { '0' }).collect()
}

/// The pattern mirrored left to right.
pub fn mirrored(p: &[bool]) -> Pattern {
    p.iter().rev().copied().collect()
}

/// LEDs as text: `L` green (left), `R` blue (right), `-` off.
pub fn leds_str(leds: &[LedColor]) -> String {
    leds.iter()
        .map(|c| match c {
            LedColor::Green => 'L',
            LedColor::Blue => 'R',
            LedColor::Off => '-',
            LedColor::Sector(i) => char::from_digit(u32::from(*i), 10).unwrap_or('?'),
        })
        .collect()
}

/// What the LEDs should show for a pattern with exactly one border: each robot prefers the
/// direction of the border and all follow the majority of those preferences; on an exact tie
/// each side moves toward the border. `None` for other patterns (no verdict).
pub fn expected(p: &[bool]) -> Option<Vec<LedColor>> {
    let borders: Vec<usize> = (1..p.len()).filter(|&i| p[i] != p[i - 1]).collect();
    let &[b] = borders.as_slice() else {
        return None;
    };
    // Robots left of the border prefer right (blue), the others left (green).
    let (prefer_right, prefer_left) = (b, p.len() - b);
    Some(
        (0..p.len())
            .map(|i| match prefer_right.cmp(&prefer_left) {
                std::cmp::Ordering::Greater => LedColor::Blue,
                std::cmp::Ordering::Less => LedColor::Green,
                std::cmp::Ordering::Equal if i < b => LedColor::Blue,
                std::cmp::Ordering::Equal => LedColor::Green,
            })
            .collect(),
    )
}

/// The verdict of a run of `cfg` in which a robot stopped on its own (a panic), which has no
/// LEDs to judge: the pattern at its end (what a judged run reports as its lights) and the
/// LEDs it should have ended with, if that pattern has a verdict. Such a run failed. The lab
/// campaign and `cimax arena` both judge a crashed run by this.
pub fn crash_verdict(cfg: &ArenaConfig) -> (Vec<bool>, Option<Vec<LedColor>>) {
    let end = Instant::ZERO + cfg.duration;
    let lights = cfg
        .env
        .pattern_at(end)
        .map(<[bool]>::to_vec)
        .unwrap_or_default();
    let expected = expected_without(&lights, &absent(cfg));
    (lights, expected)
}

/// The robots of `cfg` that never run: dead from the start and never restarted.
pub fn absent(cfg: &ArenaConfig) -> Vec<usize> {
    let mut a: Vec<usize> = cfg
        .dead_at_start
        .iter()
        .copied()
        .filter(|r| !cfg.restarts.iter().any(|(_, x)| x == r))
        .collect();
    a.sort_unstable();
    a.dedup();
    a
}

/// [`expected`] when the robots in `absent` never run: the others are judged as a line of
/// their own (the pattern without the absent robots) and the absent robots' LEDs stay off.
/// Absent robots must be at the ends of the line (else the others are not one line): `None`
/// (no verdict) otherwise.
pub fn expected_without(p: &[bool], absent: &[usize]) -> Option<Vec<LedColor>> {
    let present: Vec<usize> = (0..p.len()).filter(|i| !absent.contains(i)).collect();
    let (&first, &last) = (present.first()?, present.last()?);
    if last - first + 1 != present.len() {
        return None;
    }
    let inner = expected(&p[first..=last])?;
    let mut out = vec![LedColor::Off; p.len()];
    out[first..=last].copy_from_slice(&inner);
    Some(out)
}

/// One experiment of the paper's lab suite: a light pattern, and for an alternating experiment
/// the pattern it changes to once a run's duration has passed (paper section 4: "after
/// reaching consensus, the light configurations were changed").
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LabExperiment {
    /// The pattern from the start.
    pub first: Pattern,
    /// The pattern after the change, for an alternating experiment.
    pub then: Option<Pattern>,
}

impl LabExperiment {
    /// `1000`, or `1000>0001` for an alternating experiment.
    pub fn label(&self) -> String {
        match &self.then {
            Some(t) => format!("{}>{}", pattern_str(&self.first), pattern_str(t)),
            None => pattern_str(&self.first),
        }
    }

    /// A line of robots `spacing` metres apart under this experiment with `seed`: the first
    /// pattern for `run`, then for an alternating experiment the second one for another `run`
    /// (the run lasts twice `run`, [`judge`] checks the LEDs just before the change too).
    pub fn config(&self, spacing: f64, run: Duration, seed: u64) -> ArenaConfig {
        let mut cfg = ArenaConfig::line(self.first.clone(), spacing, run, seed);
        if let Some(t) = &self.then {
            cfg.env.schedule.push((Instant::ZERO + run, t.clone()));
            cfg.duration = run.saturating_mul(2);
        }
        cfg
    }
}

/// The paper's lab suite, what `cimax arena` runs without options: the six patterns
/// ([`PAPER_PATTERNS`]) in the paper's order, then the alternating experiment from each of them
/// to its mirror image ([`mirrored`]): `1000>0001`, `0111>1110`, `0001>1000`, `1110>0111`,
/// `1100>0011`, `0011>1100`.
///
/// Mirroring a pattern mirrors its decisions and swaps left and right ([`expected`]), so the
/// LEDs of `1000>0001` go from `LLLL` to `RRRR` and back for `0001>1000`. The border in the
/// middle (`1100`, `0011`) stays in the middle: every robot's reading flips but its decision
/// (`RRLL`) does not, and the LEDs must hold through the change (any robot changing its LEDs
/// after it showed its side is a flicker and fails the run).
pub fn paper_suite() -> Vec<LabExperiment> {
    let six = protocol::lab::PAPER.map(|p| p.lit().to_vec());
    let plain = six.iter().map(|p| LabExperiment {
        first: p.clone(),
        then: None,
    });
    let alternating = six.iter().map(|p| LabExperiment {
        first: p.clone(),
        then: Some(mirrored(p)),
    });
    plain.chain(alternating).collect()
}

/// The outcome of one run, as the paper's table reports it.
#[derive(Clone, Debug)]
pub struct LabRun {
    /// The pattern at the end of the run.
    pub lights: Pattern,
    /// The LEDs expected at the end, if the pattern has a verdict.
    pub expected: Option<Vec<LedColor>>,
    /// The LEDs at the end.
    pub leds: Vec<LedColor>,
    /// True if every verdict of the run held (at the end, and at the switch for a run with one).
    pub success: bool,
    /// Seconds from the start (or the last pattern change) until the LEDs reached the state
    /// they kept to the end, if it was the expected one.
    pub consensus_s: Option<f64>,
    /// The first flicker, if any (seconds from the start, robot): a robot's LED change after
    /// that robot had shown its expected colour, before the lights changed. The run fails.
    /// Changes from the first kill of a robot on do not count (it goes dark, decides anew
    /// after a restart, and its neighbours may follow; the campaign's reboot scenario judges
    /// the recovery by its own bar).
    pub flicker: Option<(f64, usize)>,
    /// How many robots flickered, counted once per robot and lights phase: a change after
    /// the whole swarm agreed is one, and so is a robot that showed its side and changed away
    /// while others were still deciding.
    pub flickers: usize,
    /// The seed that replays it.
    pub seed: u64,
    /// The whole report (LED log, medium counters, trace if asked).
    pub report: RunReport,
}

/// Runs `cfg` and judges it: the LEDs at the end against [`expected`] of the final pattern,
/// and, if the pattern changed, the LEDs just before each change against the pattern before.
/// Robots that never run ([`absent`]) are left out of the pattern ([`expected_without`]).
///
/// # Errors
/// The [`ArenaError`] if the configuration is unusable.
pub fn judge(cfg: &ArenaConfig) -> Result<LabRun, ArenaError> {
    let report = run(cfg)?;
    let end = Instant::ZERO + cfg.duration;
    let schedule = &cfg.env.schedule;
    let last_change = schedule.last().map_or(Instant::ZERO, |(t, _)| *t);
    let lights = cfg
        .env
        .pattern_at(end)
        .map(<[bool]>::to_vec)
        .unwrap_or_default();
    let absent = absent(cfg);
    let exp = expected_without(&lights, &absent);
    let mut success = exp.as_ref().is_none_or(|e| report.final_leds == *e);
    // Every earlier pattern must have been reached before it changed, and no LED may change
    // once the expected state was reached, until the pattern changes.
    let mut flicker: Option<(f64, usize)> = None;
    let mut flickers = 0;
    let mut phases: Vec<(Instant, Instant, Option<Vec<LedColor>>)> = schedule
        .windows(2)
        .map(|w| (w[0].0, w[1].0, expected_without(&w[0].1, &absent)))
        .collect();
    phases.push((last_change, end, exp.clone()));
    if schedule.is_empty() {
        phases[0].0 = Instant::ZERO;
    }
    for (i, (from, to, e)) in phases.iter().enumerate() {
        let Some(e) = e else { continue };
        if i + 1 < phases.len() {
            success &= report.leds_at(*to - Duration::from_millis(1)) == *e;
        }
        let phase = flickers_in(&report, e, *from, *to, &cfg.kills);
        flickers += phase.len();
        flicker = flicker
            .into_iter()
            .chain(phase)
            .min_by(|a, b| a.0.total_cmp(&b.0));
    }
    success &= flicker.is_none();
    let consensus_s = exp
        .as_ref()
        .and_then(|e| report.consensus_since(e, end))
        .map(|t| {
            t.max(last_change)
                .saturating_since(last_change)
                .as_secs_f64()
        });
    Ok(LabRun {
        lights,
        expected: exp,
        leds: report.final_leds.clone(),
        success,
        consensus_s,
        flicker,
        flickers,
        seed: cfg.seed,
        report,
    })
}

/// Each robot's first flicker in `[from, to)`, as (seconds from the start, robot): its first
/// LED change after it first showed its colour of `expected` there (or showed it at `from`).
/// Changes at or after the first kill do not count.
fn flickers_in(
    report: &RunReport,
    expected: &[LedColor],
    from: Instant,
    to: Instant,
    kills: &[(Instant, usize)],
) -> Vec<(f64, usize)> {
    let first_kill = kills.iter().map(|&(k, _)| k).min();
    let start = report.leds_at(from);
    let mut shown: Vec<bool> = start.iter().zip(expected).map(|(a, b)| a == b).collect();
    let mut out: Vec<(f64, usize)> = Vec::new();
    let window = report
        .leds
        .iter()
        .filter(|c| c.t > from && c.t < to)
        .take_while(|c| first_kill.is_none_or(|k| c.t < k));
    for c in window {
        let Some(seen) = shown.get_mut(c.robot) else {
            continue;
        };
        if *seen {
            if !out.iter().any(|&(_, r)| r == c.robot) {
                out.push((c.t.saturating_since(Instant::ZERO).as_secs_f64(), c.robot));
            }
        } else {
            *seen = expected.get(c.robot) == Some(&c.color);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Pattern {
        parse_pattern(s).unwrap()
    }

    #[test]
    fn expectations_follow_the_border_rule() {
        // The paper's six, as it reports them.
        for lab in protocol::lab::PAPER {
            let leds = lab.decisions.map(|d| LedColor::for_decision(Some(d)));
            assert_eq!(expected(&lab.lit()), Some(leds.to_vec()), "{}", lab.lights);
            assert_eq!(p(lab.lights), lab.lit());
        }
        let e = |s: &str| expected(&p(s)).map(|l| leds_str(&l));
        assert_eq!(e("1000").as_deref(), Some("LLLL"));
        assert_eq!(e("1100").as_deref(), Some("RRLL"));
        assert_eq!(e("110000").as_deref(), Some("LLLLLL"));
        assert_eq!(e("1010"), None);
        assert_eq!(e("0000"), None);
    }

    #[test]
    fn absent_end_robots_leave_a_shorter_line() {
        let e = |s: &str, a: &[usize]| expected_without(&p(s), a).map(|l| leds_str(&l));
        assert_eq!(e("1000", &[]).as_deref(), Some("LLLL"));
        assert_eq!(e("1000", &[3]).as_deref(), Some("LLL-"));
        assert_eq!(e("0001", &[0]).as_deref(), Some("-RRR"));
        assert_eq!(e("1100", &[3]).as_deref(), Some("RRR-"));
        assert_eq!(e("1100", &[0]).as_deref(), Some("-LLL"));
        assert_eq!(e("1000", &[0]), None, "000 has no border");
        assert_eq!(e("1100", &[1]), None, "not one line");
        assert_eq!(e("1100", &[0, 1, 2, 3]), None);
        let mut cfg = ArenaConfig::line(p("1000"), 1.0, Duration::from_secs(1), 1);
        cfg.dead_at_start = vec![3, 0, 3];
        cfg.restarts = vec![(Instant::from_secs(1), 0)];
        assert_eq!(absent(&cfg), vec![3]);
    }

    #[test]
    fn the_suite_is_the_six_patterns_then_each_mirrored() {
        let labels: Vec<String> = paper_suite().iter().map(LabExperiment::label).collect();
        assert_eq!(
            labels,
            [
                "1000",
                "0111",
                "0001",
                "1110",
                "1100",
                "0011",
                "1000>0001",
                "0111>1110",
                "0001>1000",
                "1110>0111",
                "1100>0011",
                "0011>1100"
            ]
        );
        // What the LEDs must show before and after each change, from the paper's decisions
        // (protocol::lab): mirroring swaps left and right, except for the border in the middle.
        let leds = |p: &[bool]| {
            let lab = protocol::lab::LabPattern::find(&pattern_str(p)).unwrap();
            leds_str(&lab.decisions.map(|d| LedColor::for_decision(Some(d))))
        };
        let mut seen = Vec::new();
        for e in paper_suite() {
            let Some(t) = &e.then else { continue };
            assert_eq!(leds(&e.first), leds_str(&expected(&e.first).unwrap()));
            assert_eq!(leds(t), leds_str(&expected(t).unwrap()));
            seen.push(format!("{} {}>{}", e.label(), leds(&e.first), leds(t)));
        }
        assert_eq!(
            seen,
            [
                "1000>0001 LLLL>RRRR",
                "0111>1110 LLLL>RRRR",
                "0001>1000 RRRR>LLLL",
                "1110>0111 RRRR>LLLL",
                "1100>0011 RRLL>RRLL",
                "0011>1100 RRLL>RRLL"
            ]
        );
        let cfg = paper_suite()[10].config(1.0, Duration::from_secs(100), 7);
        assert_eq!(cfg.duration, Duration::from_secs(200));
        assert_eq!(
            cfg.env.schedule,
            [
                (Instant::ZERO, p("1100")),
                (Instant::from_secs(100), p("0011"))
            ]
        );
        assert_eq!(cfg.seed, 7);
    }

    /// Runs `e` with seeds 1 to 5 (readings as `readings`) and returns, per run, the LEDs just
    /// before the change and at the end; panics with the seed if a run fails.
    fn alternate(e: &LabExperiment, readings: crate::Readings) -> Vec<(String, String)> {
        let run = protocol::Params::robots().lab_run();
        (1..=5)
            .map(|seed| {
                let mut cfg = e.config(1.0, run, seed);
                cfg.env.readings = readings;
                let r = judge(&cfg).unwrap();
                assert!(
                    r.success,
                    "{} {readings:?} seed {seed}: LEDs {}, flicker {:?}",
                    e.label(),
                    leds_str(&r.leds),
                    r.flicker
                );
                let before = r
                    .report
                    .leds_at(Instant::ZERO + run - Duration::from_millis(1));
                (leds_str(&before), leds_str(&r.leds))
            })
            .collect()
    }

    #[test]
    fn mirrored_alternating_experiments_end_as_the_paper_decides() {
        let suite = paper_suite();
        let find = |l: &str| suite.iter().find(|e| e.label() == l).unwrap();
        for readings in [crate::Readings::Levels, crate::Readings::Binary] {
            let both = |a: &str, b: &str| vec![(a.to_string(), b.to_string()); 5];
            assert_eq!(alternate(find("1000>0001"), readings), both("LLLL", "RRRR"));
            assert_eq!(alternate(find("0111>1110"), readings), both("LLLL", "RRRR"));
            assert_eq!(alternate(find("0001>1000"), readings), both("RRRR", "LLLL"));
            assert_eq!(alternate(find("1110>0111"), readings), both("RRRR", "LLLL"));
            // The border stays in the middle: the LEDs hold RRLL through the change.
            assert_eq!(alternate(find("1100>0011"), readings), both("RRLL", "RRLL"));
            assert_eq!(alternate(find("0011>1100"), readings), both("RRLL", "RRLL"));
        }
    }

    #[test]
    fn patterns_parse_and_mirror() {
        assert_eq!(pattern_str(&mirrored(&p("1100"))), "0011");
        assert!(
            parse_pattern("10x1")
                .unwrap_err()
                .to_string()
                .contains("character 3")
        );
    }
}
