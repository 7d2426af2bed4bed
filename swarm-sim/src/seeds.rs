//! Seeds: every run gets its own seed derived from the command's `--seed` and the run's
//! coordinates (point index, run index), so runs are independent of each other and of the order
//! (and the number of threads) in which they are executed.

use protocol::hash::{SPLITMIX64_GAMMA, splitmix64_mix};

/// One step of SplitMix64 from state `z`: the gamma added, then the finaliser; a bijective
/// mix of 64 bits.
pub fn mix(z: u64) -> u64 {
    splitmix64_mix(z.wrapping_add(SPLITMIX64_GAMMA))
}

/// The seed of the thing at coordinates `parts` under `base`.
pub fn derive(base: u64, parts: &[u64]) -> u64 {
    parts.iter().fold(mix(base), |h, &p| mix(h ^ mix(p)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coordinates_give_distinct_seeds() {
        let mut seen = std::collections::HashSet::new();
        for p in 0..50 {
            for r in 0..50 {
                assert!(seen.insert(derive(1, &[p, r])));
            }
        }
        assert_ne!(derive(1, &[0, 1]), derive(1, &[1, 0]));
        assert_ne!(derive(1, &[0]), derive(2, &[0]));
    }
}
