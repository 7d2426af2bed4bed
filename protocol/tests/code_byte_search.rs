//! A search, not a check (`#[ignore]`; run it with
//! `cargo test --release -p protocol --test code_byte_search -- --ignored --nocapture`):
//! for random format-3 frames with a ray, every single-byte change of the body; it stops at the
//! first changed frame that passes the CRC and is refused as `Undecodable` (format 2 had such
//! a pair, `frame.rs`'s `GOLDEN_CODE_BYTE`), prints it and passes, and fails if none is found.
//! Seed 19, 200,000 frames (about 10⁹ changed frames, a few minutes): none found
//! (2026-11-24). It also fails if a changed frame decodes to a valid message.

use protocol::frame::{FrameError, decode_frame, encode};
use protocol::message::Ray;
use protocol::{Hop, Level, MAX_SECTORS, Message, Sector, Tag};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg32;

#[test]
#[ignore = "a search of about 10^9 frames; run by hand"]
fn a_corrupted_byte_that_passes_the_crc() {
    let mut rng = Pcg32::seed_from_u64(19);
    for _ in 0..200_000u64 {
        let k: u8 = rng.random_range(2..=4);
        let n: usize = rng.random_range(1..=5);
        let hops: Vec<Hop> = (0..n)
            .map(|_| Hop {
                reading: Level(rng.random()),
                pref: Sector::new(rng.random_range(0..3)),
                tag: Tag::new(rng.random_range(0..16)).unwrap(),
            })
            .collect();
        let robots: u8 = rng.random_range(1..=6);
        let readings: Vec<u32> = (0..robots).map(|_| rng.random_range(0..=255)).collect();
        let mut votes = [0u8; MAX_SECTORS];
        votes[0] = rng.random_range(0..=robots);
        let ray = Ray {
            sector: Sector::new(rng.random_range(0..k)).unwrap(),
            sectors: k,
            robots,
            sum: readings.iter().sum::<u32>() as u16,
            sum_sq: readings.iter().map(|x| x * x).sum(),
            votes,
            closed: false,
        };
        let mut m = Message::from_hops(&hops).unwrap();
        m.set_ray(Some(ray));
        let f = encode(&m).unwrap();
        for pos in 2..f.len() - 2 {
            for d in 1u8..=255 {
                let mut bad = f.clone();
                bad[pos] = bad[pos].wrapping_add(d);
                if bad[pos] == b's' {
                    continue;
                }
                match decode_frame(&bad) {
                    Err(FrameError::Undecodable) => {
                        println!("good {:02x?}\nbad  {:02x?}", f.as_slice(), bad.as_slice());
                        return;
                    }
                    Ok(other) => panic!("{f:02x?} changed at {pos} decodes: {other:?}"),
                    Err(_) => {}
                }
            }
        }
    }
    panic!("no single-byte change of 200,000 frames passed the CRC");
}
