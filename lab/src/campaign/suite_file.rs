//! The lab suite's counts as a file ([`SuiteFile`]): `cimax arena campaign` writes it beside
//! its page as `data/lab-suite.json` (committed as `docs/data/lab-suite.json`), and the
//! reproduction page's lab row (section 4 of the paper) reads it, so that page runs no robot.

use serde::{Deserialize, Serialize};

use super::{Decide, SuiteResult};
use hal_emu::Readings;

/// The lab suite of every rule and readings the campaign ran: successes per experiment.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SuiteFile {
    /// Seeds per experiment.
    pub seeds: u64,
    /// One entry per rule and readings, in the campaign's order.
    pub suites: Vec<SuiteCounts>,
}

/// One rule's lab suite with one kind of readings.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SuiteCounts {
    /// The rule's name on the command line (`fixed`, `adaptive`).
    pub rule: String,
    /// The readings' name (`full`, `binary`, …).
    pub readings: String,
    /// Per experiment of the suite, in order.
    pub experiments: Vec<ExperimentCount>,
}

/// One experiment's runs.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ExperimentCount {
    /// The experiment: a pattern, or e.g. `1000>0001` for an alternating one.
    pub label: String,
    /// Successful runs.
    pub successes: u64,
    /// Runs.
    pub runs: u64,
}

impl SuiteCounts {
    /// This suite's counts from its results.
    pub fn new(rule: Decide, readings: Readings, results: &[SuiteResult]) -> Self {
        SuiteCounts {
            rule: rule.name().into(),
            readings: readings.to_string(),
            experiments: results
                .iter()
                .map(|r| ExperimentCount {
                    label: r.label.clone(),
                    successes: r.runs.iter().filter(|x| x.0).count() as u64,
                    runs: r.runs.len() as u64,
                })
                .collect(),
        }
    }

    /// Successful runs and runs over the experiments `keep` selects (by label).
    pub fn total(&self, keep: impl Fn(&str) -> bool) -> (u64, u64) {
        self.experiments
            .iter()
            .filter(|e| keep(&e.label))
            .fold((0, 0), |(s, n), e| (s + e.successes, n + e.runs))
    }
}

impl SuiteFile {
    /// The file of the campaign's lab suites: per readings, the fixed rule's then the
    /// adaptive rule's.
    pub fn new(seeds: u64, suites: &[(Readings, Vec<SuiteResult>, Vec<SuiteResult>)]) -> Self {
        SuiteFile {
            seeds,
            suites: suites
                .iter()
                .flat_map(|(readings, f, a)| {
                    [
                        SuiteCounts::new(Decide::Fixed, *readings, f),
                        SuiteCounts::new(Decide::Adaptive, *readings, a),
                    ]
                })
                .collect(),
        }
    }

    /// The file as it is written: pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_successes_per_experiment_and_reads_back() {
        let r = |label: &str, ok: &[bool]| SuiteResult {
            label: label.into(),
            runs: ok.iter().map(|&b| (b, None)).collect(),
        };
        let f = vec![r("1000", &[true, true]), r("1000>0001", &[true, false])];
        let a = vec![r("1000", &[false, true]), r("1000>0001", &[true, true])];
        let file = SuiteFile::new(2, &[(Readings::Binary, f, a)]);
        assert_eq!(file.suites.len(), 2);
        assert_eq!(file.suites[0].rule, "fixed");
        assert_eq!(file.suites[0].total(|_| true), (3, 4));
        assert_eq!(file.suites[1].total(|l| !l.contains('>')), (1, 2));
        let back: SuiteFile = serde_json::from_str(&file.to_json()).expect("reads back");
        assert_eq!(back, file);
    }
}
