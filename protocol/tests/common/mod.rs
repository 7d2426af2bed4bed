//! Strategies shared by the protocol's property tests.

use proptest::prelude::*;
use protocol::message::Ray;
use protocol::{MAX_SECTORS, Sector};

/// Any valid ray: 2..=8 sectors, a sector below that, 1..=255 robots, the sums of that many
/// readings in `0..=255` (drawn as the readings themselves), votes of at most `robots` each.
pub fn ray() -> impl Strategy<Value = Ray> {
    (2..=MAX_SECTORS as u8, any::<u8>(), 1..=255u8).prop_flat_map(|(k, s, robots)| {
        (
            proptest::collection::vec(0..=robots, usize::from(k)),
            proptest::collection::vec(any::<u8>(), usize::from(robots)),
        )
            .prop_map(move |(v, readings)| {
                let mut votes = [0; MAX_SECTORS];
                votes[..v.len()].copy_from_slice(&v);
                let sum = readings.iter().map(|&x| u32::from(x)).sum::<u32>();
                let sum_sq = readings.iter().map(|&x| u32::from(x).pow(2)).sum::<u32>();
                Ray {
                    sector: Sector::new(s % k).unwrap(),
                    sectors: k,
                    robots,
                    sum: sum as u16,
                    sum_sq,
                    votes,
                    // Both values of the closed bit (revision 3.1).
                    closed: robots % 2 == 0,
                }
            })
    })
}
