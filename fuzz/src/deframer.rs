//! `deframer`: the streaming [`Deframer`] on arbitrary byte streams.
//!
//! Input: one header byte `h`, then `h % 16` cut bytes, then the stream. The stream is fed three
//! ways: byte by byte with `push`, in slices through the `frames` iterator, and in the same
//! slices through `feed`. The slices' lengths are the cut bytes modulo 41, in turn (a zero
//! gives an empty slice; all zero, or no cut bytes, give one slice). Checks:
//!
//! - all three ways give the same results and the same [`DeframerStats`]; `feed` always
//!   consumes at least one byte when it returns a result, and nothing is left when it does not;
//! - the counters are those of the results (one per kind, `errors()` their sum), no deframer
//!   result is `Incomplete`, and they never claim more than the stream could hold: each result
//!   owns at least 3 bytes plus the first delimiter, each decoded frame at least 8 plus the first
//!   delimiter, and skipped bytes plus two per result never exceed the stream;
//! - every decoded message has 1..=MAX_HOPS hops and re-encodes to a frame that decodes back to
//!   it ([`crate::reference::check_decoded`]);
//! - `decode_frame(stream)` is the first result (or `Incomplete`);
//! - recovery (`docs/protocol.md` §2.3): after the stream, a whole golden frame gives at most two
//!   results, the last being its message; after `resync()` it gives exactly that message and
//!   the counters are kept.

use protocol::Message;
use protocol::frame::{Deframer, DeframerStats, FrameError, decode_frame};

use crate::reference::{self, GOLDEN_FOUR_HOPS, GOLDEN_ONE_HOP};

/// Cut bytes are `header % (MAX_CUTS + 1)`.
pub const MAX_CUTS: usize = 15;
/// A slice is `cut % (MAX_SLICE + 1)` bytes long: longer than a frame.
pub const MAX_SLICE: usize = 40;

type Outcome = Result<Message, FrameError>;

/// The cut bytes and the stream of an input.
pub fn split(data: &[u8]) -> (&[u8], &[u8]) {
    match data.split_first() {
        None => (&[], &[]),
        Some((&h, rest)) => rest.split_at((usize::from(h) % (MAX_CUTS + 1)).min(rest.len())),
    }
}

/// The input for `cuts` and `stream` (the inverse of [`split`] for at most [`MAX_CUTS`] cuts).
pub fn input(cuts: &[u8], stream: &[u8]) -> Vec<u8> {
    assert!(cuts.len() <= MAX_CUTS);
    let mut v = vec![u8::try_from(cuts.len()).expect("at most 15 cuts")];
    v.extend_from_slice(cuts);
    v.extend_from_slice(stream);
    v
}

/// The slices the stream is fed in.
pub fn slices<'a>(stream: &'a [u8], cuts: &[u8]) -> Vec<&'a [u8]> {
    let lens: Vec<usize> = cuts
        .iter()
        .map(|&c| usize::from(c) % (MAX_SLICE + 1))
        .collect();
    if lens.iter().all(|&l| l == 0) {
        return vec![stream];
    }
    let mut out = Vec::new();
    let mut rest = stream;
    for &l in lens.iter().cycle() {
        if rest.is_empty() {
            break;
        }
        let (a, b) = rest.split_at(l.min(rest.len()));
        out.push(a);
        rest = b;
    }
    out
}

/// Byte by byte, through a plain deframer.
pub fn by_push(stream: &[u8]) -> (Vec<Outcome>, Deframer) {
    by_push_into(Deframer::new(), stream)
}

/// Byte by byte, through `d`.
pub fn by_push_into(mut d: Deframer, stream: &[u8]) -> (Vec<Outcome>, Deframer) {
    let out = stream.iter().filter_map(|&b| d.push(b)).collect();
    (out, d)
}

fn by_frames(mut d: Deframer, slices: &[&[u8]]) -> (Vec<Outcome>, DeframerStats) {
    let mut out = Vec::new();
    for s in slices {
        out.extend(d.frames(s));
    }
    (out, *d.stats())
}

fn by_feed(mut d: Deframer, slices: &[&[u8]]) -> (Vec<Outcome>, DeframerStats) {
    let mut out = Vec::new();
    for &s in slices {
        let mut rest = s;
        loop {
            let (r, next) = d.feed(rest);
            match r {
                Some(r) => {
                    assert!(
                        next.len() < rest.len(),
                        "feed returned a result without reading"
                    );
                    assert!(rest.ends_with(next), "feed's rest is not a suffix");
                    out.push(r);
                    rest = next;
                }
                None => {
                    assert!(next.is_empty(), "feed stopped early without a result");
                    break;
                }
            }
        }
    }
    (out, *d.stats())
}

/// The counters the results imply.
pub fn stats_of(results: &[Outcome], skipped: u32) -> DeframerStats {
    let n = |e: FrameError| results.iter().filter(|r| **r == Err(e)).count() as u32;
    DeframerStats {
        frames: results.iter().filter(|r| r.is_ok()).count() as u32,
        skipped_bytes: skipped,
        too_long: n(FrameError::TooLong),
        lone_delimiter: n(FrameError::LoneDelimiter),
        bad_stuffing: n(FrameError::BadStuffing),
        too_short: n(FrameError::TooShort),
        bad_check: n(FrameError::BadCheck),
        undecodable: n(FrameError::Undecodable),
        // Counters of later kinds (e.g. the keyed deframer's) stay zero for a plain deframer.
        ..DeframerStats::default()
    }
}

/// What differs between the plain deframer and others (the keyed one, see [`crate::keyed`]).
pub struct Flavour<'a> {
    /// A fresh deframer.
    pub new: &'a dyn Fn() -> Deframer,
    /// The counters a list of results implies (given the skipped bytes).
    pub stats_of: &'a dyn Fn(&[Outcome], u32) -> DeframerStats,
    /// The first result of a fresh deframer over some bytes, by the module's own function.
    pub decode_first: &'a dyn Fn(&[u8]) -> Outcome,
    /// What every decoded message must satisfy.
    pub check_message: &'a dyn Fn(&Message),
    /// Whole frames of two messages, for the recovery checks.
    pub recovery: [(Vec<u8>, Message); 2],
    /// The fewest bytes a decodable frame takes besides its opening delimiter.
    pub min_frame: usize,
}

/// The plain deframer's flavour.
pub fn plain() -> Flavour<'static> {
    Flavour {
        new: &Deframer::new,
        stats_of: &stats_of,
        decode_first: &decode_frame,
        check_message: &reference::check_decoded,
        recovery: [
            (GOLDEN_FOUR_HOPS.to_vec(), reference::four_hops()),
            (GOLDEN_ONE_HOP.to_vec(), reference::one_hop()),
        ],
        // A one-hop body: 3 payload + 2 CRC + 1 COBS bytes, and a closing `ss`.
        min_frame: 8,
    }
}

/// The check of this target.
pub fn check(data: &[u8]) {
    check_with(&plain(), data);
}

/// The checks of this module's documentation, for any flavour of deframer.
pub fn check_with(f: &Flavour<'_>, data: &[u8]) {
    let (cuts, stream) = split(data);
    let (pushed, deframer) = by_push_into((f.new)(), stream);
    let stats = *deframer.stats();

    let slices = slices(stream, cuts);
    assert_eq!(slices.concat(), stream, "slices cover the stream");
    let (framed, framed_stats) = by_frames((f.new)(), &slices);
    let (fed, fed_stats) = by_feed((f.new)(), &slices);
    assert_eq!(pushed, framed, "push vs frames over slices {slices:?}");
    assert_eq!(pushed, fed, "push vs feed over slices {slices:?}");
    assert_eq!(stats, framed_stats);
    assert_eq!(stats, fed_stats);
    let mut empty = (f.new)();
    assert_eq!(empty.feed(&[]), (None, &[][..]));

    // Counters.
    assert_eq!(
        stats,
        (f.stats_of)(&pushed, stats.skipped_bytes),
        "{pushed:?}"
    );
    assert_eq!(
        stats.errors(),
        pushed.iter().filter(|r| r.is_err()).count() as u32
    );
    assert!(!pushed.contains(&Err(FrameError::Incomplete)));
    let len = stream.len();
    let results = pushed.len();
    let frames = stats.frames as usize;
    assert!(
        stats.skipped_bytes as usize + 2 * results <= len,
        "{stats:?} from {len} bytes"
    );
    if results > 0 {
        assert!(3 * results + 2 <= len, "{results} results from {len} bytes");
    }
    if frames > 0 {
        assert!(
            f.min_frame * frames + 2 <= len,
            "{frames} frames from {len} bytes"
        );
    }

    // Messages.
    for m in pushed.iter().flatten() {
        (f.check_message)(m);
    }
    assert_eq!(
        (f.decode_first)(stream),
        pushed
            .first()
            .cloned()
            .unwrap_or(Err(FrameError::Incomplete))
    );

    // Recovery.
    let [(frame_a, msg_a), (frame_b, msg_b)] = &f.recovery;
    let mut after = deframer.clone();
    let tail: Vec<Outcome> = after.frames(frame_a).collect();
    assert!(tail.len() <= 2, "{tail:?}");
    assert_eq!(tail.last(), Some(&Ok(msg_a.clone())), "{tail:?}");
    let mut resynced = deframer;
    resynced.resync();
    assert_eq!(*resynced.stats(), stats, "resync keeps the counters");
    let tail: Vec<Outcome> = resynced.frames(frame_b).collect();
    assert_eq!(tail, [Ok(msg_b.clone())]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_follow_the_cut_bytes() {
        let s = b"0123456789";
        assert_eq!(slices(s, &[]), [&s[..]]);
        assert_eq!(slices(s, &[0, 41]), [&s[..]], "all cuts zero");
        assert_eq!(
            slices(s, &[3, 0]),
            [&b"012"[..], b"", b"345", b"", b"678", b"", b"9"]
        );
    }

    #[test]
    fn split_reads_the_header() {
        assert_eq!(split(&[]), (&[][..], &[][..]));
        assert_eq!(split(&input(&[4, 5], b"ss")), (&[4, 5][..], &b"ss"[..]));
        // A header asking for more cuts than there are bytes takes what there is.
        assert_eq!(split(&[15, 1]), (&[1][..], &[][..]));
    }

    #[test]
    fn golden_stream_passes() {
        let mut stream = GOLDEN_ONE_HOP.to_vec();
        stream.extend_from_slice(GOLDEN_FOUR_HOPS);
        check(&input(&[1, 7, 0], &stream));
        let (r, d) = by_push(&stream);
        assert_eq!(r, [Ok(reference::one_hop()), Ok(reference::four_hops())]);
        assert_eq!(d.stats().frames, 2);
    }
}
