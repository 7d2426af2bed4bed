//! The two small non-cryptographic hashes the robots and the tools share, written once:
//! FNV-1a (32-bit) over bytes, and SplitMix64's finaliser over a `u64`.
//!
//! Both are a few lines of public-domain arithmetic, `const` and `no_std`; a crate for each
//! (`fnv` is a 64-bit `Hasher`, `rand`'s SplitMix is an RNG, not its finaliser) would add a
//! dependency to the robot image for less than what is here.

/// FNV-1a's 32-bit offset basis.
const FNV_OFFSET: u32 = 0x811c_9dc5;
/// FNV-1a's 32-bit prime.
const FNV_PRIME: u32 = 0x0100_0193;

/// SplitMix64's increment (the golden ratio's 64-bit fraction): what its generator adds to
/// its state before each [`splitmix64_mix`].
pub const SPLITMIX64_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// FNV-1a (32-bit) of `bytes`: every byte moves every later bit.
pub fn fnv1a_32(bytes: impl IntoIterator<Item = u8>) -> u32 {
    bytes.into_iter().fold(FNV_OFFSET, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(FNV_PRIME)
    })
}

/// SplitMix64's finaliser: a bijection of `u64` whose output bits each depend on every input
/// bit.
pub const fn splitmix64_mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published FNV-1a test vectors (the empty string, "a", "foobar").
    #[test]
    fn fnv1a_32_matches_the_reference_vectors() {
        assert_eq!(fnv1a_32([]), 0x811c_9dc5);
        assert_eq!(fnv1a_32(*b"a"), 0xe40c_292c);
        assert_eq!(fnv1a_32(*b"foobar"), 0xbf9c_f968);
    }

    /// SplitMix64 seeded with 0 gives 0xe220a8397b1dcdaf first (the reference generator:
    /// state += gamma, then the finaliser); the finaliser keeps 0 at 0.
    #[test]
    fn splitmix64_matches_the_reference_generator() {
        assert_eq!(splitmix64_mix(SPLITMIX64_GAMMA), 0xe220_a839_7b1d_cdaf);
        assert_eq!(splitmix64_mix(0), 0);
    }
}
