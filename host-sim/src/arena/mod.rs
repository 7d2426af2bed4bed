//! The emulated lab arena over `hal-emu`: robots running the unchanged robot program on
//! emulated hardware. [`line`](mod@line) is `cimax arena` itself (the paper's lab experiment:
//! robots in a line under light patterns), [`plane`] puts them on a plane over the swarm
//! simulator's fields, [`campaign`] runs the lab experiment under faults against bars
//! (`docs/reliability.md`), and [`stress`] adds the campaign page's loss sweep and initiation
//! counts.

pub mod campaign;
pub mod line;
pub mod plane;
pub mod stress;
