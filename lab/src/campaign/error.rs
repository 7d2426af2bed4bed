//! Why a campaign, one of its runs or the lab suite could not run ([`CampaignError`]).

use hal_emu::ArenaError;
use hal_emu::judge::PatternError;

/// Why a campaign, one of its runs or a run of the lab suite could not run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CampaignError {
    /// A run could not start.
    #[error(transparent)]
    Arena(#[from] ArenaError),
    /// A run's light pattern does not parse (cannot happen for the paper's patterns).
    #[error(transparent)]
    Pattern(#[from] PatternError),
    /// A campaign of no seeds.
    #[error("a campaign needs at least one seed")]
    NoSeeds,
    /// A loss that is no probability.
    #[error("--loss must be a probability in [0, 1], not {0}")]
    Loss(f64),
    /// A scenario number past the campaign's scenarios.
    #[error("there is no scenario number {0}")]
    NoScenario(usize),
    /// More robots in the loop than a run has.
    #[error("{count} robots in the loop, but the campaign's runs have {robots} robots")]
    TooManyInTheLoop {
        /// Robots in the loop asked for.
        count: usize,
        /// Robots of the run.
        robots: usize,
    },
    /// An experiment number past the lab suite's.
    #[error("the lab suite has no experiment {0}")]
    NoExperiment(usize),
}
