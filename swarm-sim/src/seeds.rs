//! Seeds: every run gets its own seed derived from the command's `--seed` and the run's
//! coordinates (point index, run index), so runs are independent of each other and of the order
//! (and the number of threads) in which they are executed.

/// SplitMix64's finaliser: a bijective mix of 64 bits.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
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
