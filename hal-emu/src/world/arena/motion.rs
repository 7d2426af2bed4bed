//! The swarm's motion over a plane field ([`Motion`]): every period it moves rigidly along the
//! decision its LEDs show ([`swarm_heading`]), each move recorded ([`Move`]) and traced.

use std::cell::RefCell;
use std::rc::Rc;

use firmware::{Clock, LedColor};
use nalgebra::{Point2, Vector2};
use protocol::{Duration, Instant, Sector};

use super::lives::Shared;
use crate::world::medium::TraceEvent;

/// The swarm's motion over a [`PlaneField`](crate::world::env::PlaneField), as in the paper's 2D
/// simulations: every `period` (a negotiation period) the swarm moves rigidly by `step` R along
/// its decision, the circular mean of the sectors the robots' LEDs show ([`swarm_heading`]).
/// Relative positions do not change, so neither does what the robots hear: only what they
/// sense.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Time between moves.
    pub period: Duration,
    /// Length of a move, in R.
    pub step: f64,
}

/// One move of the swarm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// When.
    pub t: Instant,
    /// The centre of mass before the move, in R.
    pub centre: Point2<f64>,
    /// The swarm's heading (radians), if any robot had decided.
    pub heading: Option<f64>,
    /// Fraction of all robots whose LEDs show the sector nearest the heading.
    pub consensus: f64,
}

/// The swarm's decision from its LEDs: the circular mean of the directions of the sectors the
/// decided robots show (`sectors` per robot), or `None` if none has decided or they cancel
/// out. Also the fraction of all robots showing the sector nearest that heading.
pub fn swarm_heading(leds: &[LedColor], sectors: u8) -> (Option<f64>, f64) {
    let (mut x, mut y, mut n) = (0.0, 0.0, 0.0f64);
    for s in leds.iter().filter_map(|c| c.decision()) {
        let b = f64::from(s.bearing(sectors));
        x += b.cos();
        y += b.sin();
        n += 1.0;
    }
    // Bearings are `f32`: opposite sectors cancel to within a rounding, not exactly.
    if x.hypot(y) < 1e-5 * n.max(1.0) {
        return (None, 0.0);
    }
    let heading = y.atan2(x);
    let nearest = Sector::from_bearing(heading as f32, sectors);
    let agree = leds
        .iter()
        .filter(|c| c.decision() == Some(nearest))
        .count();
    (Some(heading), agree as f64 / leds.len().max(1) as f64)
}

/// Moves the swarm every `motion.period` along the heading of the LEDs, for ever.
pub(super) async fn mover(shared: Rc<Shared>, motion: Motion, moves: Rc<RefCell<Vec<Move>>>) {
    let Some(plane) = shared.surroundings.env().field.clone() else {
        return;
    };
    let sectors = shared.config.params.sectors;
    let n = plane.positions.len();
    let mut t = Instant::ZERO;
    loop {
        t += motion.period;
        shared.clock.sleep_until(t).await;
        let leds = shared.leds.now(n);
        let (heading, consensus) = swarm_heading(&leds, sectors);
        let offset = shared.surroundings.offset();
        let centre = plane.centre(offset);
        moves.borrow_mut().push(Move {
            t,
            centre,
            heading,
            consensus,
        });
        shared.medium.borrow_mut().log(TraceEvent::Moved {
            t_ms: t.as_millis(),
            centre: [centre.x, centre.y],
            heading,
            step: if heading.is_some() { motion.step } else { 0.0 },
            consensus,
        });
        if let Some(h) = heading {
            shared
                .surroundings
                .set_offset(offset + Vector2::new(h.cos(), h.sin()) * motion.step);
        }
    }
}
