//! The fused variant on a plane: 61 robots on the paper's hexagonal lattice (0.75 R apart,
//! six receive sectors), wired directly (no medium), a sharp border to their right. Rays carry
//! what each robot knows of each of its six directions, so the swarm decides toward the
//! border.

use std::f64::consts::TAU;

use protocol::frame::{Deframer, encode};
use protocol::{Duration, Event, FusedNode, Instant, Level, Params, Sector, Tag};
use rand_pcg::Pcg32;

const K: u8 = 6;

/// The `n` nodes of a triangular lattice of spacing `s` nearest the origin, with their lattice
/// coordinates.
fn lattice(n: usize, s: f64) -> Vec<((i32, i32), (f64, f64))> {
    let mut v = Vec::new();
    for a in -10i32..=10 {
        for b in -10i32..=10 {
            let x = s * (f64::from(a) + f64::from(b) / 2.0);
            let y = s * f64::from(b) * 3f64.sqrt() / 2.0;
            v.push(((a, b), (x, y)));
        }
    }
    v.sort_by(|p, q| {
        let d = |(x, y): (f64, f64)| x * x + y * y;
        d(p.1).total_cmp(&d(q.1)).then(p.0.cmp(&q.0))
    });
    v.truncate(n);
    v
}

struct Robot {
    node: FusedNode,
    rng: Pcg32,
    deframers: Vec<Deframer>,
    /// (neighbour, the sector of this robot it is heard on)
    hears: Vec<(usize, Sector)>,
}

/// Runs 61 robots whose centre is `x0` R from a sharp border at x = 0 (lit beyond it) for
/// `periods` negotiation periods; returns each robot's decision.
fn run(x0: f64, seed: u64, periods: u64) -> Vec<Option<Sector>> {
    let mut params = Params::robots();
    params.sectors = K;
    let pos = lattice(61, 0.75);
    let mut robots: Vec<Robot> = pos
        .iter()
        .enumerate()
        .map(|(i, &((a, b), (x, _)))| {
            let mut rng = Pcg32::new(seed, i as u64);
            // Tags a + 4b mod 16: robots with one tag are at least 3.6 spacings apart.
            let tag = Tag::from_id((a + 4 * b).rem_euclid(16) as u16);
            let mut node = FusedNode::new(params, tag, Instant::ZERO, &mut rng).unwrap();
            let lit = x + x0 > 0.0;
            let noise = ((i * 7) % 11) as u8; // a fixed small spread per robot
            node.handle_reading(Level(if lit { 200 } else { 30 } + noise));
            let hears = pos
                .iter()
                .enumerate()
                .filter(|&(j, &(_, (xj, yj)))| {
                    let (dx, dy) = (xj - pos[i].1.0, yj - pos[i].1.1);
                    j != i && (dx * dx + dy * dy).sqrt() <= 1.0
                })
                .map(|(j, &(_, (xj, yj)))| {
                    let bearing = (yj - pos[i].1.1).atan2(xj - pos[i].1.0);
                    (j, Sector::from_bearing(bearing as f32, K))
                })
                .collect();
            Robot {
                node,
                rng,
                deframers: (0..K).map(|_| Deframer::new()).collect(),
                hears,
            }
        })
        .collect();
    let end = Instant::ZERO + Duration::from_secs(periods * 10 * 70);
    let mut decisions = vec![None; robots.len()];
    loop {
        let (i, t) = robots
            .iter()
            .enumerate()
            .map(|(i, r)| (i, r.node.poll_timeout()))
            .min_by_key(|&(i, t)| (t, i))
            .unwrap();
        if t > end {
            break;
        }
        let r = &mut robots[i];
        r.node.handle_timeout(t, &mut r.rng);
        let sent: Vec<_> = std::iter::from_fn(|| robots[i].node.poll_transmit()).collect();
        while let Some(e) = robots[i].node.poll_event() {
            if let Event::Decided { decision, .. } = e {
                decisions[i] = decision;
            }
        }
        for m in sent {
            let frame = encode(&m).unwrap();
            for j in 0..robots.len() {
                let Some(&(_, s)) = robots[j].hears.iter().find(|(k, _)| *k == i) else {
                    continue;
                };
                let r = &mut robots[j];
                for got in r.deframers[usize::from(s.index())].frames(&frame) {
                    r.node.handle_message(t, s, &got.unwrap(), &mut r.rng);
                }
                while let Some(e) = r.node.poll_event() {
                    if let Event::Decided { decision, .. } = e {
                        decisions[j] = decision;
                    }
                }
            }
        }
    }
    decisions
}

/// The mean direction of the decided sectors (radians) and the fraction of robots deciding
/// a sector with a component toward +x.
fn summary(d: &[Option<Sector>]) -> (f64, f64, usize) {
    let (mut sx, mut sy) = (0.0, 0.0);
    let mut toward = 0;
    let mut decided = 0;
    for s in d.iter().flatten() {
        let b = TAU * f64::from(s.index()) / f64::from(K);
        sx += b.cos();
        sy += b.sin();
        decided += 1;
        if b.cos() > 0.1 {
            toward += 1;
        }
    }
    (sy.atan2(sx), toward as f64 / d.len() as f64, decided)
}

#[test]
fn a_lattice_two_r_from_the_border_heads_for_it() {
    for (x0, toward_plus_x) in [(-2.0, true), (2.0, false)] {
        for seed in 1..=2 {
            let d = run(x0, seed, 2);
            let (mean, toward, decided) = summary(&d);
            let hist: Vec<usize> = (0..K)
                .map(|k| d.iter().filter(|s| s.map(|s| s.index()) == Some(k)).count())
                .collect();
            let why = format!(
                "x0 {x0}, seed {seed}: mean {:.1} deg, {toward:.2} toward +x, {decided} decided, \
                 per sector {hist:?}",
                mean.to_degrees()
            );
            assert!(decided >= 58, "{why}");
            let (want, frac) = if toward_plus_x {
                (0.0, toward)
            } else {
                (180.0, 1.0 - toward)
            };
            let off = (mean.to_degrees() - want + 540.0).rem_euclid(360.0) - 180.0;
            assert!(off.abs() < 30.0, "{why}");
            assert!(frac >= 0.9, "{why}");
            // The votes of the three sectors facing the border add up: most robots pick the
            // one straight at it.
            let straight = if toward_plus_x { hist[0] } else { hist[3] };
            assert!(straight >= 40, "{why}");
        }
    }
}
