//! The emulated lab arena over `hal-emu`: robots running the unchanged robot program on
//! emulated hardware. [`plane`] puts them on a plane over the swarm simulator's fields,
//! [`campaign`] runs the lab experiment (robots in a line under light patterns, judged by
//! `hal_emu::judge`) under faults against bars (`docs/reliability.md`), and [`stress`] adds the
//! campaign page's loss sweep and initiation counts. These modules run experiments and return
//! result structs; the command line (`cimax arena`) is the binary's `cli/arena`.

pub mod campaign;
pub mod plane;
pub mod stress;
