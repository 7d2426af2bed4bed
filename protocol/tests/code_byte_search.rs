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

/// The odds per frame (issue 34): frames of binary readings (0 and 1, the paper's: many zero
/// bytes, so many COBS code bytes), every change of every code byte that keeps the stuffing
/// valid; prints how many pass the CRC (`Undecodable` or a valid other message) in all, and the
/// frame with the most. Run by hand:
/// `cargo test --release -p protocol --test code_byte_search -- --ignored --nocapture odds`
/// (`CODE_BYTE_FRAMES=N`, 20,000 by default; `CODE_BYTE_MIX=1` for frames whose readings are 0
/// half the time and any level otherwise, with or without a ray). 2026-11-27, seed 34: 300,000
/// binary frames, 8,074,685 changes, none passed; 300,000 mixed frames, 4,694,216 changes, none
/// passed.
#[test]
#[ignore = "a search; run by hand"]
fn code_byte_odds_per_frame() {
    let mut rng = Pcg32::seed_from_u64(34);
    let (mut trials, mut passes, mut valid) = (0u64, 0u64, 0u64);
    let mut worst = (0u64, 0u64, Vec::new());
    // CODE_BYTE_FRAMES=N for another number of frames.
    let frames: u64 = std::env::var("CODE_BYTE_FRAMES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let mix = std::env::var("CODE_BYTE_MIX").is_ok();
    for _ in 0..frames {
        let n: usize = rng.random_range(1..=7);
        let hops: Vec<Hop> = (0..n)
            .map(|_| Hop {
                // With CODE_BYTE_MIX set: 0 half the time, else any level.
                reading: Level(if mix && rng.random() {
                    rng.random()
                } else if mix {
                    0
                } else {
                    rng.random_range(0..=1)
                }),
                pref: Sector::new(rng.random_range(0..3)),
                tag: Tag::new(rng.random_range(0..16)).unwrap(),
            })
            .collect();
        let robots: u8 = rng.random_range(1..=20);
        let ones: u8 = rng.random_range(0..=robots);
        let mut votes = [0u8; MAX_SECTORS];
        votes[0] = rng.random_range(0..=robots);
        votes[1] = rng.random_range(0..=robots - votes[0]);
        let ray = Ray {
            sector: Sector::new(rng.random_range(0..2)).unwrap(),
            sectors: 2,
            robots,
            sum: u16::from(ones),
            sum_sq: u32::from(ones),
            votes,
            closed: rng.random(),
        };
        let mut m = Message::from_hops(&hops).unwrap();
        if !mix || rng.random() {
            m.set_ray(Some(ray));
        }
        let f = encode(&m).unwrap();
        // The COBS code bytes: the body (between the delimiters) XOR 's', walked code to code.
        let body: Vec<u8> = f[2..f.len() - 2].iter().map(|b| b ^ b's').collect();
        let mut codes = Vec::new();
        let mut at = 0usize;
        while at < body.len() && body[at] != 0 {
            codes.push(at + 2);
            at += usize::from(body[at]);
        }
        let (mut t, mut p) = (0u64, 0u64);
        for &pos in &codes {
            for d in 1u8..=255 {
                let mut bad = f.clone();
                bad[pos] = bad[pos].wrapping_add(d);
                if bad[pos] == b's' {
                    continue;
                }
                match decode_frame(&bad) {
                    Err(FrameError::BadStuffing) | Err(FrameError::LoneDelimiter) => {}
                    Err(FrameError::Undecodable) => {
                        t += 1;
                        p += 1;
                    }
                    Ok(other) => {
                        t += 1;
                        p += 1;
                        valid += 1;
                        assert_ne!(other, m);
                    }
                    Err(_) => t += 1,
                }
            }
        }
        trials += t;
        passes += p;
        if p * worst.1.max(1) > worst.0 * t.max(1) && t > 0 {
            worst = (p, t, f.to_vec());
        }
    }
    println!(
        "{trials} stuffing-valid code-byte changes of {frames} {} frames: {passes} pass the CRC ({valid} as a valid other message); worst frame {} of {}: {:02x?}",
        if mix {
            "mixed (half the readings 0, half any; a ray or none)"
        } else {
            "binary-reading ray"
        },
        worst.0,
        worst.1,
        worst.2
    );
}
