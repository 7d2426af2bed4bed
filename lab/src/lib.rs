//! # lab: the emulated lab's experiments
//!
//! The emulated lab arena over `hal-emu`: robots running the unchanged robot program on
//! emulated hardware. [`plane`] puts them on a plane over the swarm simulator's fields,
//! [`campaign`] runs the lab experiment (robots in a line under light patterns, judged by
//! `hal_emu::judge`) under faults against bars (`docs/reliability.md`), and [`stress`] adds the
//! campaign page's loss sweep and initiation counts. These modules run experiments and return
//! result structs; the command line (`cimax arena`) is the binary's `cli/arena`.

pub mod campaign;
pub mod line;
pub mod plane;
pub mod stress;

use std::path::PathBuf;

use hal_emu::world::hil::{HilClock, HilRobot, Transport};
use serde::{Deserialize, Serialize};

/// Robots in the loop in every run of a campaign or a sweep (`--hil qemu:N` or `--hil
/// loopback:N`), on the arena's clock (docs/hil.md, "Time"): the Cortex-M build in QEMU, or its
/// host twin in this process.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct InTheLoop {
    /// How many per run.
    pub robots: usize,
    /// The HIL image QEMU boots for each; `None`: host twins of it in this process.
    pub image: Option<PathBuf>,
}

impl InTheLoop {
    /// As `--hil` says it: `qemu:N` or `loopback:N`.
    pub fn spec(&self) -> String {
        let kind = if self.image.is_some() {
            "qemu"
        } else {
            "loopback"
        };
        format!("{kind}:{}", self.robots)
    }

    /// The robots in the loop at `places`, on the arena's clock.
    pub fn at(&self, places: &[usize]) -> Vec<HilRobot> {
        places
            .iter()
            .map(|&robot| HilRobot {
                robot,
                transport: self
                    .image
                    .clone()
                    .map_or(Transport::InProcess, Transport::Qemu),
                clock: HilClock::Virtual,
            })
            .collect()
    }
}
