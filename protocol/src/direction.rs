//! Directions of reception.
//!
//! A robot has K receivers, each covering one sector of the horizon (K = 2, left and right, for
//! robots in a line; up to [`MAX_SECTORS`] for robots in the plane). Sector `i` is centred on the
//! bearing `i · 2π / K`, measured counter-clockwise from the +x axis ("east"). With K = 2 this makes
//! sector 0 [`Sector::RIGHT`] and sector 1 [`Sector::LEFT`].
//!
//! The 2D simulations use exact bearings instead (radians, any real value; see
//! [`crate::three_phase`]): the paper's remark that a cross-shaped swarm "moves like the king on a
//! chess board" says they were not binned.

use core::f32::consts::{PI, TAU};

/// The largest number of receive sectors a robot may have.
pub const MAX_SECTORS: usize = 8;

/// One receive sector, `0..K`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sector(u8);

impl Sector {
    /// With K = 2: the receiver facing +x (shown blue on the top cap).
    pub const RIGHT: Sector = Sector(0);
    /// With K = 2: the receiver facing −x (shown green on the top cap).
    pub const LEFT: Sector = Sector(1);

    /// The sector with this index, if it is below [`MAX_SECTORS`].
    pub const fn new(index: u8) -> Option<Sector> {
        if (index as usize) < MAX_SECTORS {
            Some(Sector(index))
        } else {
            None
        }
    }

    /// The sector's index.
    pub const fn index(self) -> u8 {
        self.0
    }

    /// The sector of `k` that contains `bearing` (radians, any value). `k` is clamped to
    /// `1..=MAX_SECTORS`; a NaN bearing falls in sector 0.
    pub fn from_bearing(bearing: f32, k: u8) -> Sector {
        let k = k.clamp(1, MAX_SECTORS as u8);
        let width = TAU / f32::from(k);
        let a = wrap_positive(bearing + width / 2.0);
        // `as` saturates (and maps NaN to 0); `min` guards the a == TAU rounding edge.
        let i = libm::floorf(a / width) as u8;
        Sector(i.min(k - 1))
    }

    /// The bearing this sector of `k` is centred on, in `[0, 2π)`.
    pub fn bearing(self, k: u8) -> f32 {
        let k = k.clamp(1, MAX_SECTORS as u8);
        wrap_positive(f32::from(self.0) * TAU / f32::from(k))
    }
}

/// `angle` wrapped into `[0, 2π)`; −0 becomes +0, so one direction has one bit pattern.
pub fn wrap_positive(angle: f32) -> f32 {
    // `fmodf` is exact and returns `x` itself when `|x| < |y|`: skip the call then (every
    // bearing of the 2D simulator, which calls this for each message scored).
    let a = if angle.abs() < TAU {
        angle
    } else {
        libm::fmodf(angle, TAU)
    };
    let a = if a < 0.0 { a + TAU } else { a };
    // `a == 0.0` also holds for −0.0 (found by fuzz/three_phase).
    if a >= TAU || a == 0.0 { 0.0 } else { a }
}

/// `angle` wrapped into `(−π, π]`: the signed shorter arc.
pub fn wrap_signed(angle: f32) -> f32 {
    let a = wrap_positive(angle);
    if a > PI { a - TAU } else { a }
}

/// What an agent does with an opinion exactly opposite its own, where the shorter arc is not
/// defined. The paper does not say; the 2D simulations run both to show what hangs on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Opposite {
    /// Turn counter-clockwise ([`turn_toward`]; this crate's rule from the start).
    #[default]
    CounterClockwise,
    /// Keep its own bearing: an exactly opposite opinion does not move it.
    Keep,
}

/// [`turn_toward`] with the rule `opposite` for an opinion exactly opposite `from`.
#[inline]
pub fn turn_toward_by(from: f32, to: f32, fraction: f32, opposite: Opposite) -> f32 {
    let arc = wrap_signed(to - from);
    if opposite == Opposite::Keep && arc == PI {
        wrap_positive(from)
    } else {
        wrap_positive(from + fraction * arc)
    }
}

/// Moves `from` toward `to` by `fraction` of the shorter arc between them, in `[0, 2π)`.
///
/// This is the paper's opinion diffusion (Alg. 3): "adjust own preferred direction by 10 %
/// towards the preferred direction contained by the incoming message". When the two are exactly
/// opposite the arc is taken counter-clockwise.
pub fn turn_toward(from: f32, to: f32, fraction: f32) -> f32 {
    turn_toward_by(from, to, fraction, Opposite::CounterClockwise)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exactly_opposite_opinion_turns_counter_clockwise_or_is_kept() {
        let ccw = turn_toward_by(0.0, PI, 0.1, Opposite::CounterClockwise);
        assert!((ccw - 0.1 * PI).abs() < 1e-6);
        assert_eq!(turn_toward_by(0.0, PI, 0.1, Opposite::Keep), 0.0);
        assert_eq!(turn_toward_by(PI, 0.0, 0.1, Opposite::Keep), PI);
        // Not exactly opposite: both rules turn the same way.
        let near = turn_toward_by(0.0, PI - 0.01, 0.1, Opposite::Keep);
        assert_eq!(near, turn_toward(0.0, PI - 0.01, 0.1));
        assert!(near > 0.0);
    }

    #[test]
    fn minus_zero_wraps_to_plus_zero() {
        assert_eq!(wrap_positive(-0.0).to_bits(), 0.0f32.to_bits());
        assert_eq!(wrap_positive(TAU).to_bits(), 0.0f32.to_bits());
        assert_eq!(wrap_signed(-0.0).to_bits(), 0.0f32.to_bits());
    }

    #[test]
    fn two_sectors_are_right_and_left() {
        assert_eq!(Sector::from_bearing(0.0, 2), Sector::RIGHT);
        assert_eq!(Sector::from_bearing(PI, 2), Sector::LEFT);
        assert_eq!(Sector::from_bearing(-PI, 2), Sector::LEFT);
        assert_eq!(Sector::from_bearing(1.5, 2), Sector::RIGHT);
        assert_eq!(Sector::from_bearing(1.6, 2), Sector::LEFT);
        assert_eq!(Sector::LEFT.bearing(2), PI);
    }

    #[test]
    fn eight_sectors_round_trip_their_centres() {
        for i in 0..8u8 {
            let s = Sector::new(i).unwrap();
            assert_eq!(Sector::from_bearing(s.bearing(8), 8), s);
            assert_eq!(Sector::from_bearing(s.bearing(8) + TAU * 3.0, 8), s);
        }
        assert_eq!(Sector::new(8), None);
    }

    #[test]
    fn hostile_bearings_do_not_panic() {
        for b in [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
        ] {
            assert!(Sector::from_bearing(b, 8).index() < 8);
            assert!(Sector::from_bearing(b, 0).index() < 1);
        }
    }

    #[test]
    fn diffusion_takes_the_shorter_arc() {
        // From 350° toward 10°: the short way crosses 0°, 10 % of 20° is 2°.
        let from = 350f32.to_radians();
        let to = 10f32.to_radians();
        let got = turn_toward(from, to, 0.1).to_degrees();
        assert!((got - 352.0).abs() < 1e-3, "{got}");
        // And back the other way.
        let got = turn_toward(to, from, 0.1).to_degrees();
        assert!((got - 8.0).abs() < 1e-3, "{got}");
        // A full step lands on the target.
        assert!((turn_toward(1.0, 2.0, 1.0) - 2.0).abs() < 1e-6);
    }
}
