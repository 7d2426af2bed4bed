//! Strategies shared by the protocol's property tests.

use proptest::prelude::*;
use protocol::message::Ray;
use protocol::{MAX_SECTORS, Sector};

/// Any valid ray: 2..=8 sectors, a sector below that, 1..=255 robots, moments of 8-bit
/// readings (mean at most 255.0, variance at most 127.5²), votes of at most `robots` each.
pub fn ray() -> impl Strategy<Value = Ray> {
    (
        2..=MAX_SECTORS as u8,
        any::<u8>(),
        1..=255u8,
        0..=0xFF00u16,
        0..=65025u16,
    )
        .prop_flat_map(|(k, s, robots, mean, var)| {
            proptest::collection::vec(0..=robots, usize::from(k)).prop_map(move |v| {
                let mut votes = [0; MAX_SECTORS];
                votes[..v.len()].copy_from_slice(&v);
                Ray {
                    sector: Sector::new(s % k).unwrap(),
                    sectors: k,
                    robots,
                    mean,
                    var,
                    votes,
                }
            })
        })
}
