//! What every experiment's runs share: a [`Stage`] (log lines, progress bar, seeds from the
//! named blocks of [`crate::stages`]) and the page's [`Scenes`] (the built-in scenarios,
//! placed).

use std::time::Instant as Clock;

use crate::Error;
use crate::builtin_placed;
use crate::stages::Offset;
use crate::units::{Field, Scene};
use swarm_sim::progress::Progress;
use swarm_sim::scenario::{Placement, Scenario};
use swarm_sim::seeds::derive;

/// A stage's log lines, progress bar and seeds.
pub struct Stage<'a> {
    log: &'a mut dyn FnMut(&str),
    quiet: bool,
    t: Clock,
    /// The base seed.
    base: u64,
}

impl<'a> Stage<'a> {
    /// A stage with log `log`, progress bars unless `quiet`, and base seed `base`.
    pub fn new(log: &'a mut dyn FnMut(&str), quiet: bool, base: u64) -> Stage<'a> {
        Stage {
            log,
            quiet,
            t: Clock::now(),
            base,
        }
    }

    /// The seed of stage offset `at` ([`crate::stages`]).
    pub fn seed(&self, at: Offset) -> u64 {
        derive(self.base, &[at.get()])
    }

    /// Logs `what` and starts its progress bar over `runs` runs.
    pub fn start(&mut self, what: &str, runs: u64) -> Progress {
        self.t = Clock::now();
        (self.log)(&format!("{what} ({runs} runs)..."));
        Progress::new(runs, what, self.quiet)
    }

    /// Ends the progress bar and logs the stage's time.
    pub fn done(&mut self, p: &Progress) {
        p.finish();
        (self.log)(&format!(
            "  done in {:.1} s",
            self.t.elapsed().as_secs_f64()
        ));
    }
}

/// The scenarios of the page, placed by the main placement.
pub struct Scenes {
    /// `sharp`.
    pub sharp: Scenario,
    /// `gradient`.
    pub gradient: Scenario,
    /// `cloud`.
    pub cloud: Scenario,
}

impl Scenes {
    /// The built-in scenarios with their agents placed by `main`.
    ///
    /// # Errors
    /// If a built-in scenario is missing or cannot be placed.
    pub fn new(main: Placement) -> Result<Scenes, Error> {
        Ok(Scenes {
            sharp: builtin_placed("sharp", main)?,
            gradient: builtin_placed("gradient", main)?,
            cloud: builtin_placed("cloud", main)?,
        })
    }

    /// The field's scenario.
    pub fn field(&self, f: Field) -> &Scenario {
        match f {
            Field::Sharp => &self.sharp,
            Field::Gradient => &self.gradient,
        }
    }

    /// Both fields' scenarios.
    pub fn fields(&self) -> [&Scenario; 2] {
        [&self.sharp, &self.gradient]
    }

    /// The scenario of a direction map.
    pub fn scene(&self, m: Scene) -> &Scenario {
        match m {
            Scene::Sharp => &self.sharp,
            Scene::Gradient => &self.gradient,
            Scene::Cloud => &self.cloud,
        }
    }
}
