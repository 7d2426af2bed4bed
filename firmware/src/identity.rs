//! Who a robot is and how it draws: its id from the chip's unique ID, its random seed from a
//! hardware random number generator mixed with that ID.
//!
//! Both are pure functions so the host tests them; the Nucleo image feeds them the STM32's
//! 96-bit unique ID (RM0351 §48.2: wafer X and Y coordinates, wafer number, lot number) and
//! 16 bytes from the RNG peripheral.

use protocol::hash::{fnv1a_32, splitmix64_mix as mix};

/// The chip's unique ID: 96 bits.
pub type Uid = [u8; 12];

/// The robot id of a chip without a build-time id: the 32-bit FNV-1a hash of all 96 bits of
/// its unique ID, folded to 16 bits. Every byte moves every later bit of the hash, so UIDs
/// that differ only in the wafer coordinates (neighbouring dies of one wafer, the likely case
/// for one lab's boards) give unrelated ids.
///
/// Its tag on the wire is the id modulo 16, so two robots share a tag with probability 1/16
/// whatever their dies; set `CIMAX_ROBOT_ID` at build time to guarantee distinct tags. (The
/// first two bytes of the UID, used before, are the wafer X coordinate: boards cut from one
/// wafer row all got the same id.)
pub fn id_from_uid(uid: &Uid) -> u16 {
    let h = fnv1a_32(uid.iter().copied());
    (h ^ (h >> 16)) as u16
}

/// The state and stream of the robot's PCG (`Pcg32::new(state, stream)`): 16 bytes of the
/// hardware RNG, each half mixed with half of the UID.
///
/// With the hardware RNG (`Some`), a robot draws differently on every boot, so a robot that
/// resets (a panic, the watchdog) does not replay the draws that led it there; the UID keeps
/// two robots apart even if their RNGs failed the same way. Without it (`None`: the RNG
/// reported a seed or clock error) the seed is the UID's alone, as before: distinct per
/// robot, the same on every boot.
pub fn rng_seed(uid: &Uid, hardware: Option<[u8; 16]>) -> (u64, u64) {
    let [a, b, c, d, e, f, g, h, i, j, k, l] = *uid;
    let uid_lo = u64::from_le_bytes([a, b, c, d, e, f, g, h]);
    let uid_hi = u64::from(u32::from_le_bytes([i, j, k, l]));
    let (hw_lo, hw_hi) = match hardware {
        Some(bytes) => {
            let mut lo = [0u8; 8];
            let mut hi = [0u8; 8];
            lo.copy_from_slice(&bytes[..8]);
            hi.copy_from_slice(&bytes[8..]);
            (u64::from_le_bytes(lo), u64::from_le_bytes(hi))
        }
        None => (0, 0),
    };
    (mix(hw_lo ^ mix(uid_lo)), mix(hw_hi ^ mix(uid_hi ^ uid_lo)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UID of die (x, y) on wafer `w` of lot `lot`, laid out as RM0351 §48.2 says.
    fn uid(x: u16, y: u16, w: u8, lot: [u8; 7]) -> Uid {
        let mut u = [0u8; 12];
        u[..2].copy_from_slice(&x.to_le_bytes());
        u[2..4].copy_from_slice(&y.to_le_bytes());
        u[4] = w;
        u[5..].copy_from_slice(&lot);
        u
    }

    const LOT: [u8; 7] = *b"L476RG1";

    #[test]
    fn every_bit_of_the_uid_counts() {
        let base = uid(12, 40, 3, LOT);
        for byte in 0..12 {
            for bit in 0..8 {
                let mut other = base;
                other[byte] ^= 1 << bit;
                assert_ne!(
                    id_from_uid(&other),
                    id_from_uid(&base),
                    "byte {byte} bit {bit}"
                );
            }
        }
    }

    #[test]
    fn dies_of_one_wafer_row_get_spread_tags() {
        // The old id (the first two UID bytes) gave every die of column x = 12 one id. The
        // hash spreads the 64 dies of that column over the 16 tags: each tag used, none by
        // more than a quarter of them.
        let mut per_tag = [0u32; 16];
        let mut ids = std::collections::BTreeSet::new();
        for y in 0..64 {
            let id = id_from_uid(&uid(12, y, 3, LOT));
            ids.insert(id);
            per_tag[usize::from(id % 16)] += 1;
        }
        assert_eq!(ids.len(), 64, "distinct ids");
        assert!(
            per_tag.iter().all(|&n| (1..=16).contains(&n)),
            "{per_tag:?}"
        );
    }

    #[test]
    fn the_seed_changes_with_each_boot_and_each_chip() {
        let a = uid(1, 1, 1, LOT);
        let b = uid(2, 1, 1, LOT);
        let boot1 = Some([7u8; 16]);
        let mut boot2 = [7u8; 16];
        boot2[15] = 8;
        assert_ne!(rng_seed(&a, boot1), rng_seed(&a, Some(boot2)), "two boots");
        assert_ne!(
            rng_seed(&a, boot1),
            rng_seed(&b, boot1),
            "two chips, same draw"
        );
        assert_ne!(
            rng_seed(&a, None),
            rng_seed(&b, None),
            "no RNG: the UID alone"
        );
        assert_eq!(rng_seed(&a, boot1), rng_seed(&a, boot1), "a pure function");
        // Both halves of the hardware draw count.
        let mut low = [7u8; 16];
        low[0] = 0;
        let (s1, t1) = rng_seed(&a, boot1);
        let (s2, t2) = rng_seed(&a, Some(low));
        assert!(s1 != s2 && t1 == t2);
        let (s3, t3) = rng_seed(&a, Some(boot2));
        assert!(s1 == s3 && t1 != t3);
    }
}
