//! The LED record of a run: every LED change of every robot with its time ([`LedChange`]), as
//! a camera over the arena would see it, and the LEDs it shows at a time ([`leds_at`]).

use firmware::LedColor;
use protocol::Instant;

/// One LED change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LedChange {
    /// When.
    pub t: Instant,
    /// Which robot.
    pub robot: usize,
    /// What it shows from then on.
    pub color: LedColor,
}

/// The LEDs of `n` robots at `t`: the last of `changes` (in time order) at or before `t` for
/// each robot, off before its first.
pub(crate) fn leds_at(changes: &[LedChange], n: usize, t: Instant) -> Vec<LedColor> {
    let mut out = vec![LedColor::Off; n];
    for c in changes.iter().take_while(|c| c.t <= t) {
        if let Some(o) = out.get_mut(c.robot) {
            *o = c.color;
        }
    }
    out
}
