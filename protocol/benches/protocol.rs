//! `cargo bench -p protocol`: deframing throughput and the cost of handling one received frame.

use std::hint::black_box;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use protocol::frame::{Deframer, encode};
use protocol::{FusedNode, Hop, Instant, Level, MAX_HOPS, Message, Params, Sector, Tag};
use rand_pcg::Pcg32;

fn full_message() -> Message {
    let hops: Vec<Hop> = (0..MAX_HOPS as u8)
        .map(|i| Hop {
            reading: Level(i.wrapping_mul(37)),
            pref: Sector::new(i % 2),
            tag: Tag::from_id(u16::from(i)),
        })
        .collect();
    Message::from_hops(&hops).unwrap()
}

fn deframing(c: &mut Criterion) {
    let frame = encode(&full_message()).unwrap();
    let stream: Vec<u8> = frame
        .iter()
        .copied()
        .cycle()
        .take(frame.len() * 1000)
        .collect();
    let mut g = c.benchmark_group("deframe");
    g.throughput(Throughput::Bytes(stream.len() as u64));
    g.bench_function("1000 full frames, byte by byte", |b| {
        b.iter(|| {
            let mut d = Deframer::new();
            let mut n = 0u32;
            for &x in black_box(&stream) {
                if let Some(Ok(_)) = d.push(x) {
                    n += 1;
                }
            }
            assert_eq!(n, 1000);
            n
        })
    });
    g.finish();
    c.bench_function("encode full frame", |b| {
        b.iter(|| encode(black_box(&full_message())))
    });
}

fn handling(c: &mut Criterion) {
    let mut rng = Pcg32::new(1, 1);
    // Tag 15: not in the full message (tags 0..=11), which it therefore accepts.
    let tag = Tag::from_id(15);
    let mut node = FusedNode::new(Params::robots(), tag, Instant::ZERO, &mut rng).unwrap();
    node.handle_reading(Level(200));
    let frame = encode(&full_message()).unwrap();
    let t = Instant::from_secs(1);
    c.bench_function("receive one full frame: deframe + score + relay", |b| {
        b.iter_batched_ref(
            || (node.clone(), Deframer::new(), rng.clone()),
            |(n, d, r)| {
                for m in d.frames(black_box(&frame)).flatten() {
                    n.handle_message(t, Sector::LEFT, &m, r);
                }
                n.handle_timeout(t + protocol::Duration::from_secs(1), r);
                let out = n.poll_transmit();
                assert!(out.is_some());
                out
            },
            BatchSize::SmallInput,
        )
    });
}

criterion_group!(benches, deframing, handling);
criterion_main!(benches);
