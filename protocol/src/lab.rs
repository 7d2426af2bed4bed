//! The paper's lab experiment as data: the six light patterns of its Fig. 13 over four robots in
//! a line, and the decisions the paper reports for each.
//!
//! One definition for every harness that runs them: the direct-wired line's tests
//! (`protocol/tests/lab_line.rs`), the robot program's wired line (`firmware/tests/line.rs`),
//! the QEMU board (`firmware/qemu`) and the emulator's judge (`hal-emu`, whose general rule
//! must agree with these six).
//!
//! Robots are numbered left to right. The rule behind the decisions: each robot prefers the
//! direction of the light border, and all follow the majority of those preferences; on an exact
//! tie each side moves toward the border.

use crate::direction::Sector;
use crate::message::Level;

/// Robots in the paper's lab line.
pub const ROBOTS: usize = 4;

/// One of the paper's lab runs: a light pattern and the decision every robot should show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LabPattern {
    /// The pattern, one character per robot left to right: `1` lit, `0` dark.
    pub lights: &'static str,
    /// The paper's decision of each robot, left to right.
    pub decisions: [Sector; ROBOTS],
}

const L: Sector = Sector::LEFT;
const R: Sector = Sector::RIGHT;

/// The six patterns of the paper's Fig. 13 with their decisions, in the paper's order.
pub const PAPER: [LabPattern; 6] = [
    LabPattern::new("1000", [L, L, L, L]),
    LabPattern::new("0111", [L, L, L, L]),
    LabPattern::new("0001", [R, R, R, R]),
    LabPattern::new("1110", [R, R, R, R]),
    LabPattern::new("1100", [R, R, L, L]),
    LabPattern::new("0011", [R, R, L, L]),
];

/// The six patterns of [`PAPER`] alone, as text.
pub const PAPER_LIGHTS: [&str; 6] = {
    let mut out = [""; 6];
    let mut i = 0;
    while i < PAPER.len() {
        out[i] = PAPER[i].lights;
        i += 1;
    }
    out
};

impl LabPattern {
    /// A pattern and its decisions.
    ///
    /// # Panics
    /// If `lights` is not [`ROBOTS`] characters `0` or `1` (at compile time in a constant).
    pub const fn new(lights: &'static str, decisions: [Sector; ROBOTS]) -> Self {
        let b = lights.as_bytes();
        assert!(b.len() == ROBOTS, "a lab pattern has one light per robot");
        let mut i = 0;
        while i < ROBOTS {
            assert!(b[i] == b'0' || b[i] == b'1', "a lab pattern is 0s and 1s");
            i += 1;
        }
        LabPattern { lights, decisions }
    }

    /// Which robots are lit, left to right.
    pub const fn lit(&self) -> [bool; ROBOTS] {
        let b = self.lights.as_bytes();
        let mut out = [false; ROBOTS];
        let mut i = 0;
        while i < ROBOTS {
            out[i] = b[i] == b'1';
            i += 1;
        }
        out
    }

    /// What the robots' sensors read: `lit` for a lit robot, `dark` for a dark one.
    pub fn levels(&self, lit: Level, dark: Level) -> [Level; ROBOTS] {
        self.lit().map(|l| if l { lit } else { dark })
    }

    /// The decisions as robots report them ([`crate::FusedNode::decision`]): all decided.
    pub fn expected(&self) -> [Option<Sector>; ROBOTS] {
        self.decisions.map(Some)
    }

    /// The paper's run of pattern `lights`, if it is one of the six.
    pub const fn find(lights: &str) -> Option<LabPattern> {
        let mut i = 0;
        while i < PAPER.len() {
            if eq(PAPER[i].lights.as_bytes(), lights.as_bytes()) {
                return Some(PAPER[i]);
            }
            i += 1;
        }
        None
    }
}

/// Byte-wise equality, in a constant.
const fn eq(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_six_patterns_read_and_are_found() {
        assert_eq!(
            PAPER_LIGHTS,
            ["1000", "0111", "0001", "1110", "1100", "0011"]
        );
        assert_eq!(PAPER[4].lit(), [true, true, false, false]);
        assert_eq!(
            PAPER[2].levels(Level(200), Level(30)),
            [Level(30), Level(30), Level(30), Level(200)]
        );
        assert_eq!(PAPER[0].expected(), [Some(Sector::LEFT); 4]);
        for p in PAPER {
            assert_eq!(LabPattern::find(p.lights), Some(p));
        }
        assert_eq!(LabPattern::find("1010"), None);
        assert_eq!(LabPattern::find("100"), None);
    }
}
