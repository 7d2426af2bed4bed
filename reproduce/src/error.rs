//! What can go wrong in the runs of the page, typed.

use crate::units::Unit;

/// Why a unit could not be run, or its result not be had.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A built-in scenario the page runs is not compiled in.
    #[error("built-in scenario {0} is missing")]
    NoScenario(String),
    /// A built-in scenario lacks the part an experiment needs (`sweep`, `grid`).
    #[error("built-in scenario without {0}")]
    ScenarioWithout(&'static str),
    /// A run figure's tries gave no run at all.
    #[error("no run")]
    NoRun,
    /// An index past its list: a knob, a plateau cycle, a steepness case.
    #[error("no {what} {index}")]
    NoSuch {
        /// What was indexed.
        what: &'static str,
        /// The index.
        index: usize,
    },
    /// An entropy bin width the measure refuses.
    #[error("bad bin width")]
    BadBin,
    /// The simulator's delivery rule, as a model, gave another wave than the protocol.
    #[error("refractory {0} s: the model's wave is not the protocol's")]
    ModelDiffers(u64),
    /// No unit has this name.
    #[error("no unit of swarm reproduce is named {0:?}")]
    NoUnit(String),
    /// A unit has no result yet.
    #[error("{0}: no result")]
    NoResult(Unit),
    /// A unit's result was asked for as another kind.
    #[error("{0}: its result is no {1}")]
    WrongKind(Unit, &'static str),
    /// A result is not of its unit's kind.
    #[error("{0}: the result is not of this unit's kind")]
    NotOfKind(Unit),
    /// A unit got a second result.
    #[error("{0}: a second result")]
    SecondResult(Unit),
    /// A built-in scenario's agents cannot be placed.
    #[error(transparent)]
    Placement(#[from] swarm_sim::scenario::PlacementError),
    /// A swarm's agents cannot be placed connected.
    #[error(transparent)]
    Connect(#[from] swarm_sim::geometry::PlacementError),
    /// The simulator failed (its own error).
    #[error(transparent)]
    Sim(#[from] swarm_sim::experiment::Error),
}
