//! Per-direction weights: the average diversity of the messages received from each direction
//! (paper Alg. 2: "calculate average of variances for each direction of reception").

use heapless::Vec;

/// True if `a` and `b` are within a relative `tolerance` of each other.
pub fn within(a: f32, b: f32, tolerance: f32) -> bool {
    (a - b).abs() <= tolerance * a.abs().max(b.abs())
}

/// One direction's running average.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slot<K> {
    dir: K,
    sum: f32,
    count: u32,
}

/// Average diversity per direction of reception, for up to `D` distinct directions `K`
/// (receive sectors on the robots, exact bearings in the 2D simulation).
#[derive(Clone, Debug)]
pub struct DirectionWeights<K, const D: usize> {
    slots: Vec<Slot<K>, D>,
}

impl<K, const D: usize> Default for DirectionWeights<K, D> {
    fn default() -> Self {
        DirectionWeights { slots: Vec::new() }
    }
}

impl<K: Copy + PartialEq, const D: usize> DirectionWeights<K, D> {
    /// Records one message's diversity `v` as received from `dir`. Returns `false` (and records
    /// nothing) if `dir` is new and all `D` slots are taken, or if `v` is not finite.
    pub fn add(&mut self, dir: K, v: f32) -> bool {
        self.record(dir, v, |s| {
            s.sum += v;
            s.count = s.count.saturating_add(1);
        })
    }

    /// Applies `update` to `dir`'s slot, or starts one holding `v` alone; `false` if `v` is not
    /// finite or the table is full.
    fn record(&mut self, dir: K, v: f32, update: impl FnOnce(&mut Slot<K>)) -> bool {
        if !v.is_finite() {
            return false;
        }
        if let Some(s) = self.slots.iter_mut().find(|s| s.dir == dir) {
            update(s);
            return true;
        }
        self.slots
            .push(Slot {
                dir,
                sum: v,
                count: 1,
            })
            .is_ok()
    }

    /// The average diversity received from `dir`, if any message came from it.
    pub fn weight(&self, dir: K) -> Option<f32> {
        self.slots
            .iter()
            .find(|s| s.dir == dir)
            .map(|s| s.sum / s.count as f32)
    }

    /// Every direction heard from, with its average diversity and message count.
    pub fn iter(&self) -> impl Iterator<Item = (K, f32, u32)> + '_ {
        self.slots
            .iter()
            .map(|s| (s.dir, s.sum / s.count as f32, s.count))
    }

    /// The heaviest direction: the one with the largest average diversity, if that average is
    /// strictly positive and strictly larger than every other. Otherwise `None`: no direction is
    /// more informative than another (no message, only uniform readings, or an exact tie), and
    /// the caller keeps its preference.
    pub fn heaviest(&self) -> Option<K> {
        let mut best: Option<(K, f32)> = None;
        let mut tied = false;
        for (dir, w, _) in self.iter() {
            match best {
                Some((_, b)) if w < b => {}
                Some((_, b)) if w == b => tied = true,
                _ => {
                    best = Some((dir, w));
                    tied = false;
                }
            }
        }
        match best {
            Some((dir, w)) if !tied && w > 0.0 => Some(dir),
            _ => None,
        }
    }

    /// Like [`heaviest`](Self::heaviest), but two averages within a relative `tolerance` of
    /// each other count as equal (`|a − b| <= tolerance · max(a, b)`): the heaviest direction
    /// must lead every other by more than that. The fused variant uses it so that rounding in
    /// `f32` does not break an exact tie differently when the readings are scaled
    /// (`docs/protocol.md` §5.6).
    pub fn heaviest_within(&self, tolerance: f32) -> Option<K> {
        let (dir, best) =
            self.iter()
                .map(|(d, w, _)| (d, w))
                .fold(None, |acc: Option<(K, f32)>, (d, w)| match acc {
                    Some((_, b)) if w <= b => acc,
                    _ => Some((d, w)),
                })?;
        let tied = self
            .iter()
            .any(|(d, w, _)| d != dir && within(w, best, tolerance));
        (!tied && best > 0.0).then_some(dir)
    }

    /// Keeps each direction's average but with the weight of a single message: a prior that
    /// the next messages quickly outweigh if the environment changed.
    pub fn shrink_to_prior(&mut self) {
        for s in self.slots.iter_mut() {
            s.sum /= s.count as f32;
            s.count = 1;
        }
    }

    /// Replaces `dir`'s average by `v` alone (a whole-side summary that supersedes what was
    /// heard before). Returns `false` (and does nothing) if `v` is not finite or the table is
    /// full.
    pub fn set(&mut self, dir: K, v: f32) -> bool {
        self.record(dir, v, |s| {
            s.sum = v;
            s.count = 1;
        })
    }

    /// Forgets everything (the start of a new period).
    pub fn clear(&mut self) {
        self.slots.clear();
    }

    /// True if no message was recorded since the last [`clear`](Self::clear).
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averages_per_direction_and_picks_the_heaviest() {
        let mut w = DirectionWeights::<u8, 4>::default();
        assert_eq!(w.heaviest(), None);
        assert!(w.add(0, 1.0));
        assert!(w.add(0, 3.0));
        assert!(w.add(1, 2.5));
        assert_eq!(w.weight(0), Some(2.0));
        assert_eq!(w.heaviest(), Some(1));
        assert!(w.add(1, 0.0));
        assert_eq!(w.heaviest(), Some(0));
    }

    #[test]
    fn ties_and_zero_weights_give_no_preference() {
        let mut w = DirectionWeights::<u8, 4>::default();
        w.add(0, 0.0);
        assert_eq!(w.heaviest(), None, "zero diversity is no reason to move");
        w.add(1, 2.0);
        w.add(2, 2.0);
        assert_eq!(w.heaviest(), None, "exact tie");
        w.add(3, 2.5);
        assert_eq!(w.heaviest(), Some(3));
    }

    #[test]
    fn a_prior_counts_as_one_message() {
        let mut w = DirectionWeights::<u8, 4>::default();
        for _ in 0..9 {
            w.add(0, 10.0);
        }
        w.add(1, 1.0);
        w.shrink_to_prior();
        assert_eq!(w.weight(0), Some(10.0));
        w.add(0, 0.0);
        assert_eq!(
            w.weight(0),
            Some(5.0),
            "one new message weighs as much as the past"
        );
        assert_eq!(w.heaviest(), Some(0));
    }

    #[test]
    fn full_table_and_non_finite_values_are_refused() {
        let mut w = DirectionWeights::<u8, 2>::default();
        assert!(w.add(0, 1.0));
        assert!(w.add(1, 1.0));
        assert!(!w.add(2, 9.0));
        assert!(!w.add(0, f32::NAN));
        assert_eq!(w.weight(0), Some(1.0));
        w.clear();
        assert!(w.is_empty());
    }
}
