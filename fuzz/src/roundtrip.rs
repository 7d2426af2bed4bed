//! `roundtrip`: arbitrary messages through `encode` and back.
//!
//! Input (read with the `arbitrary` crate, format in [`crate::input`]): a list of up to
//! [`MAX_INPUT_HOPS`] hops ([`reference::ArbHop`]: `u8` reading, `Option<u8>` sector taken
//! modulo MAX_SECTORS, `u8` robot tag taken modulo 16), then a byte position and an XOR mask
//! for a corruption, then an optional ray ([`reference::ArbRay`], always valid). Checks:
//!
//! - `Message::from_hops` gives `None` exactly for no hop or more than MAX_HOPS, and else the
//!   hops; `set_ray` keeps the newest `min(len, (25 − 1 − ray bytes) / 2)` hops and returns
//!   how many it dropped; `Message::initiate` (then `set_ray`) plus `push_evicting` keeps the
//!   last MAX_HOPS hops (fewer with a ray: as many as fit 25 bytes beside it) and returns
//!   each dropped hop (oldest first); `keep_newest(at % 14)` keeps the newest hops and counts
//!   the dropped ones; `encode` refuses the empty message;
//! - the frame is `7 + payload` ≤ FRAME_MAX bytes (`8 + 2·len` without a ray), the payload
//!   at most 25 bytes, starts and ends with `ss`, and its body holds no `s` (§1.4: `s` only in
//!   the delimiters); unstuffed independently it is the format-2 payload and its
//!   CRC-16/IBM-3740, and the independent encoder gives the same bytes;
//! - `decode_frame` gives the message back, and a deframer fed the frame twice, byte by byte,
//!   gives it twice with no error and no skipped byte;
//! - one corrupted body byte (§2.3) never gives the message back. A corrupted data byte gives
//!   `LoneDelimiter`, `BadStuffing` or `BadCheck`; so does a corrupted COBS code byte, except
//!   when the unstuffed bytes it rearranges pass the CRC by chance (about 2⁻¹⁶, README finding
//!   9): then the independent unstuffing must show that collision.

use arbitrary::Unstructured;
use protocol::frame::{self, BODY_MAX, CRC_LEN, DELIMITER, EncodeError, FRAME_MAX, FrameError};
use protocol::message::{PAYLOAD_BUDGET, Ray};
use protocol::{Deframer, Hop, MAX_HOPS, Message};

use crate::input::{Writer, get};
use crate::reference::{self, ArbRay, CRC16};

/// Hops read at most (more than MAX_HOPS, to exercise eviction and `from_hops`' refusal).
pub const MAX_INPUT_HOPS: usize = 3 * MAX_HOPS;

/// A parsed input.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The hops, oldest first.
    pub hops: Vec<Hop>,
    /// Which body byte to corrupt (modulo the body length).
    pub at: u8,
    /// The corruption (an XOR mask; 0 is replaced by 1).
    pub mask: u8,
    /// A ray to carry, if any.
    pub ray: Option<Ray>,
}

impl Input {
    /// Reads an input.
    pub fn read(data: &[u8]) -> Input {
        let mut u = Unstructured::new(data);
        let hops = reference::read_hops(&mut u, MAX_INPUT_HOPS);
        let at = get(&mut u);
        let mask = get(&mut u);
        let ray = get::<bool>(&mut u)
            .then(|| u.arbitrary::<ArbRay>().ok())
            .flatten()
            .map(|r| r.0);
        Input {
            hops,
            at,
            mask,
            ray,
        }
    }

    /// The bytes [`read`](Self::read) turns into this input.
    pub fn write(&self) -> Vec<u8> {
        let mut w = Writer::new();
        reference::write_hops(&mut w, &self.hops);
        w.u8(self.at).u8(self.mask);
        match self.ray {
            Some(r) => {
                w.bool(true);
                ArbRay(r).write(&mut w);
            }
            None => {
                w.bool(false);
            }
        }
        w.finish()
    }
}

/// The check of this target.
pub fn check(data: &[u8]) {
    let input = Input::read(data);
    let hops = &input.hops;

    // Hops that fit beside the ray (all MAX_HOPS without one).
    let cap = input.ray.map_or(MAX_HOPS, |r| {
        ((PAYLOAD_BUDGET - 1 - 7 - usize::from(r.sectors)) / 2).min(MAX_HOPS)
    });

    match Message::from_hops(hops) {
        None => assert!(hops.is_empty() || hops.len() > MAX_HOPS, "{hops:?}"),
        Some(m) => {
            assert_eq!(m.hops(), hops.as_slice());
            assert_eq!(m.ray(), None);
            check_framed(&m, input.at, input.mask);
            let mut with = m.clone();
            let dropped = with.set_ray(input.ray);
            assert_eq!(dropped, hops.len().saturating_sub(cap), "set_ray on {m:?}");
            assert_eq!(with.hops(), &hops[dropped..]);
            assert_eq!(with.ray(), input.ray.as_ref());
            check_framed(&with, input.at, input.mask);
            assert_eq!(with.set_ray(None), 0);
            assert_eq!(with.ray(), None);
        }
    }

    let Some((&first, rest)) = hops.split_first() else {
        assert_eq!(frame::encode(&Message::default()), Err(EncodeError::Empty));
        let mut m = Message::default();
        m.set_ray(input.ray);
        assert_eq!(frame::encode(&m), Err(EncodeError::Empty));
        return;
    };
    let mut m = Message::initiate(first);
    assert_eq!(m.set_ray(input.ray), 0, "one hop fits beside any ray");
    for (i, &h) in rest.iter().enumerate() {
        // `i + 1` hops came before `h`; the oldest still held is hops[i + 1 - cap].
        let dropped = m.push_evicting(h);
        let expected = (i + 1 >= cap).then(|| hops[i + 1 - cap]);
        assert_eq!(dropped, expected, "push_evicting hop {}", i + 1);
    }
    let kept = &hops[hops.len().saturating_sub(cap)..];
    assert_eq!(m.hops(), kept);
    assert_eq!(m.is_full(), kept.len() == cap);
    check_framed(&m, input.at, input.mask);

    let n = usize::from(input.at) % (MAX_HOPS + 2);
    let mut cut = m.clone();
    assert_eq!(cut.keep_newest(n), m.len().saturating_sub(n));
    assert_eq!(cut.hops(), &m.hops()[m.len().saturating_sub(n)..]);
    assert_eq!(cut.ray(), m.ray());
}

fn check_framed(m: &Message, at: u8, mask: u8) {
    let f = frame::encode(m).expect("a message with hops encodes");
    let payload = reference::payload_of(m);
    assert!(payload.len() <= PAYLOAD_BUDGET, "{m:?}");
    assert_eq!(m.encoded_len(), payload.len());
    assert_eq!(f.len(), 7 + payload.len());
    if m.ray().is_none() {
        assert_eq!(f.len(), 8 + 2 * m.len());
    }
    assert!(f.len() <= FRAME_MAX);
    assert!(f.starts_with(b"ss") && f.ends_with(b"ss"), "{f:02x?}");
    let body = &f[2..f.len() - 2];
    assert!(!body.contains(&DELIMITER), "an `s` in the body: {f:02x?}");
    assert!(body.len() <= BODY_MAX);

    // The layout, unstuffed without the protocol's code.
    let unxored: Vec<u8> = body.iter().map(|b| b ^ DELIMITER).collect();
    let raw = reference::cobs_decode(&unxored).expect("valid COBS");
    assert_eq!(raw.len(), payload.len() + CRC_LEN);
    assert_eq!(&raw[..payload.len()], payload.as_slice());
    assert_eq!(
        &raw[payload.len()..],
        &CRC16.checksum(&payload).to_le_bytes()
    );
    assert_eq!(f.as_slice(), reference::frame_payload(&payload).as_slice());

    assert_eq!(frame::decode_frame(&f).as_ref(), Ok(m));
    let mut d = Deframer::new();
    let twice: Vec<_> = f
        .iter()
        .chain(f.iter())
        .filter_map(|&b| d.push(b))
        .collect();
    assert_eq!(twice, [Ok(m.clone()), Ok(m.clone())]);
    assert_eq!(d.stats().errors(), 0);
    assert_eq!(d.stats().skipped_bytes, 0);

    // One corrupted body byte.
    let mut bad = f.to_vec();
    let i = 2 + usize::from(at) % body.len();
    bad[i] ^= mask.max(1);
    let got = frame::decode_frame(&bad);
    let caught = matches!(
        got,
        Err(FrameError::LoneDelimiter | FrameError::BadStuffing | FrameError::BadCheck)
    );
    if !cobs_codes(&unxored).contains(&(i - 2)) {
        // A data byte: one changed unstuffed byte, which the CRC always catches.
        assert!(caught, "{bad:02x?} (byte {i} of {f:02x?}) gave {got:?}");
    } else if matches!(got, Ok(_) | Err(FrameError::Undecodable)) {
        // A COBS code byte moves the zeros it stands for: several unstuffed bytes change,
        // and the CRC misses that with probability about 2^-16 (§2.3, finding 9). Then, and
        // only then, the body passes the check and the payload parser decides. (A code byte
        // can fail in other ways too, `TooShort` for one: any error but these is a catch.)
        assert_ne!(got.as_ref(), Ok(m), "{bad:02x?} decoded to the original");
        // The body the deframer closed: up to the first `ss` after the opening one (a code byte
        // turned into `s` beside the closing delimiter ends the body a byte early).
        let end = (2..bad.len() - 1)
            .find(|&j| bad[j] == DELIMITER && bad[j + 1] == DELIMITER)
            .unwrap_or(bad.len() - 2);
        let unstuffed: Vec<u8> = bad[2..end].iter().map(|b| b ^ DELIMITER).collect();
        let raw = reference::cobs_decode(&unstuffed)
            .unwrap_or_else(|| panic!("{bad:02x?} gave {got:?} but does not unstuff"));
        let (payload, crc) = raw.split_at(raw.len() - CRC_LEN);
        assert_eq!(
            crc,
            CRC16.checksum(payload).to_le_bytes(),
            "{bad:02x?} (code byte {i} of {f:02x?}) gave {got:?} without a CRC collision"
        );
    }
}

/// Positions of the COBS code bytes in a stuffed (un-XORed) body.
fn cobs_codes(enc: &[u8]) -> Vec<usize> {
    let mut codes = Vec::new();
    let mut i = 0;
    while i < enc.len() && enc[i] != 0 {
        codes.push(i);
        i += usize::from(enc[i]);
    }
    codes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{hop, tagged};

    #[test]
    fn inputs_read_back() {
        let input = Input {
            hops: vec![
                hop(1, Some(0)),
                tagged(b's', 7, None),
                tagged(255, 15, Some(7)),
            ],
            at: 3,
            mask: 0x80,
            ray: None,
        };
        assert_eq!(Input::read(&input.write()), input);
        check(&input.write());
        let input = Input {
            ray: Some(reference::ray_left_k2()),
            ..input
        };
        assert_eq!(Input::read(&input.write()), input);
        check(&input.write());
    }

    #[test]
    fn sector_bytes_wrap() {
        let mut w = Writer::new();
        w.item().u8(4).bool(true).u8(10).u8(18).end();
        assert_eq!(Input::read(&w.finish()).hops, [tagged(4, 2, Some(2))]);
    }

    #[test]
    fn many_hops_evict() {
        let hops: Vec<Hop> = (0..30).map(|r| hop(r, None)).collect();
        let input = Input {
            hops,
            at: 0,
            mask: 1,
            ray: None,
        };
        check(&input.write());
        for k in 2..=8u8 {
            let mut votes = [0; 8];
            votes[usize::from(k) - 1] = 255;
            let ray = Ray {
                sector: reference::sector(k - 1),
                sectors: k,
                robots: 255,
                // 128 robots reading 255, 127 reading 0: the largest variance.
                sum: 255 * 128,
                sum_sq: 255 * 255 * 128,
                votes,
                closed: k % 2 == 0,
            };
            let with = Input {
                ray: Some(ray),
                ..input.clone()
            };
            assert_eq!(Input::read(&with.write()), with);
            check(&with.write());
        }
        check(&[]);
    }
}
