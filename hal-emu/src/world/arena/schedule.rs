//! The run's schedule: the kills, restarts and pattern changes of an
//! [`ArenaConfig`] in time order ([`controls`]), carried out on the robots'
//! lives ([`Robots`]), which also keeps what each robot's last life left.

use std::rc::Rc;

use firmware::{Clock, LedColor};
use protocol::Instant;

use super::config::ArenaConfig;
use super::error::{LifeError, RobotFailure};
use super::lives::{Counters, Shared, Stop, life};
use crate::board::clock::EmuTask;
use crate::world::medium::TraceEvent;

/// One scheduled change.
pub(super) enum Control {
    /// The robot dies.
    Kill(usize),
    /// The robot boots again, if dead.
    Restart(usize),
    /// The light pattern changes (the environment changes by itself; this traces it).
    Pattern(String),
}

/// The run's scheduled changes in time order; simultaneous ones keep their listed order
/// (kills, restarts, then pattern changes).
pub(super) fn controls(cfg: &ArenaConfig) -> Vec<(Instant, Control)> {
    let mut controls: Vec<(Instant, Control)> = Vec::new();
    for &(t, r) in &cfg.kills {
        controls.push((t, Control::Kill(r)));
    }
    for &(t, r) in &cfg.restarts {
        controls.push((t, Control::Restart(r)));
    }
    for (t, p) in cfg.env.schedule.iter().skip(1) {
        let lights = p.iter().map(|&b| if b { '1' } else { '0' }).collect();
        controls.push((*t, Control::Pattern(lights)));
    }
    // Stable: simultaneous controls keep their listed order.
    controls.sort_by_key(|(t, _)| *t);
    controls
}

/// The robots of a run: each one's running life (how to stop it, its task), how many lives
/// it had, and what its last life left.
pub(super) struct Robots {
    shared: Rc<Shared>,
    lives: Vec<u32>,
    stops: Vec<Option<Rc<Stop>>>,
    handles: Vec<Option<EmuTask<Result<Counters, LifeError>>>>,
    /// Each robot's counters, of its last life that ended.
    pub(super) stats: Vec<Counters>,
    /// The first robot that stopped on its own (a panic, or no boot), if any: the run goes
    /// on to its end (so that it stays the same run) and then fails.
    pub(super) failure: Option<RobotFailure>,
}

impl Robots {
    /// `n` robots, none running yet.
    pub(super) fn new(shared: Rc<Shared>, n: usize) -> Self {
        Robots {
            shared,
            lives: vec![0; n],
            stops: (0..n).map(|_| None).collect(),
            handles: (0..n).map(|_| None).collect(),
            stats: vec![Counters::default(); n],
            failure: None,
        }
    }

    /// Boots robot `robot`'s next life.
    pub(super) fn boot(&mut self, robot: usize) {
        let stop = Rc::new(Stop::default());
        let life = life(self.shared.clone(), robot, self.lives[robot], stop.clone());
        let h = self.shared.clock.spawn_joined(life);
        self.lives[robot] += 1;
        self.stops[robot] = Some(stop);
        self.handles[robot] = Some(h);
    }

    /// Tells robot `robot`'s life (if any) to stop, waits for it to end and keeps its
    /// counters, or its failure.
    pub(super) async fn stop(&mut self, robot: usize) {
        if let Some(s) = self.stops[robot].take() {
            s.signal();
        }
        let Some(h) = self.handles[robot].take() else {
            return;
        };
        let seed = self.shared.seed;
        let f = match h.await {
            Ok(Ok(s)) => {
                self.stats[robot] = s;
                return;
            }
            Ok(Err(e)) => RobotFailure {
                robot,
                seed,
                panicked: false,
                message: e.to_string(),
            },
            Err(e) => RobotFailure::from_join(robot, seed, e),
        };
        self.failure.get_or_insert(f);
    }

    /// Stops every robot's life, in order.
    pub(super) async fn stop_all(&mut self) {
        for robot in 0..self.lives.len() {
            self.stop(robot).await;
        }
    }

    /// Carries out `controls` at their times, up to `end`, then waits for `end`.
    pub(super) async fn follow(&mut self, controls: Vec<(Instant, Control)>, end: Instant) {
        let clock = self.shared.clock.clone();
        for (t, c) in controls {
            if t > end {
                break;
            }
            clock.sleep_until(t).await;
            match c {
                Control::Kill(r) => self.kill(r, t).await,
                Control::Restart(r) => self.restart(r, t),
                Control::Pattern(lights) => {
                    self.shared.medium.borrow_mut().log(TraceEvent::Pattern {
                        t_ms: t.as_millis(),
                        lights,
                    });
                }
            }
        }
        clock.sleep_until(end).await;
    }

    /// Robot `r` dies at `t`: its life stops, it hears nothing more, its LEDs go off.
    async fn kill(&mut self, r: usize, t: Instant) {
        self.stop(r).await;
        let medium = &self.shared.medium;
        medium.borrow_mut().detach(r);
        medium.borrow_mut().log(TraceEvent::Killed {
            t_ms: t.as_millis(),
            robot: r,
        });
        self.shared.leds.record(r, LedColor::Off);
    }

    /// Robot `r` boots again at `t` with fresh state, if it is dead.
    fn restart(&mut self, r: usize, t: Instant) {
        if self.stops[r].is_none() {
            self.shared.medium.borrow_mut().log(TraceEvent::Restarted {
                t_ms: t.as_millis(),
                robot: r,
            });
            self.boot(r);
        }
    }
}
