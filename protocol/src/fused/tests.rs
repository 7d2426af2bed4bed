//! Tests of the node with either rule, and the helpers the rules' own tests share.

use super::state::{COSINES, resultant_scores};
use super::*;
use crate::message::Hop;
use crate::message::MAX_HOPS;
use crate::params::DecisionRule;
use crate::time::Duration;
use rand_pcg::Pcg32;

/// The hop robot `t` adds with reading `r` and preference `p`.
pub(super) fn hop(t: u8, r: u8, p: Option<Sector>) -> Hop {
    Hop {
        reading: Level(r),
        pref: p,
        tag: Tag::new(t).unwrap(),
    }
}

pub(super) const L: Option<Sector> = Some(Sector::LEFT);
pub(super) const R: Option<Sector> = Some(Sector::RIGHT);

/// Robot `tag` with reading `reading`, whose first initiation is 600 s away, so that tests
/// feeding it messages by hand are not disturbed by its own waves.
pub(super) fn node(tag: u8, reading: u8) -> (FusedNode, Pcg32) {
    let mut rng = Pcg32::new(11, 13);
    let mut p = Params::robots();
    p.wave.cycle = Duration::from_secs(600);
    p.wave.cycle_spread = Duration::ZERO;
    let tag = Tag::new(tag).unwrap();
    let mut n = FusedNode::new(p, tag, Instant::ZERO, &mut rng).unwrap();
    n.handle_reading(Level(reading));
    (n, rng)
}

/// Feeds `msg` at a quiet moment and lets the relay go out; returns what was relayed.
pub(super) fn hear(
    n: &mut FusedNode,
    rng: &mut Pcg32,
    t: &mut Instant,
    from: Sector,
    msg: &[Hop],
) -> Message {
    *t += Duration::from_secs(12);
    // What went out meanwhile (the adaptive rule's news) is not the relay.
    n.handle_timeout(*t, rng);
    while n.poll_transmit().is_some() {}
    let m = Message::from_hops(msg).unwrap();
    assert_eq!(n.handle_message(*t, from, &m, rng), Reception::Accepted);
    n.handle_timeout(*t + Duration::from_secs(1), rng);
    n.poll_transmit().expect("relayed")
}

#[test]
fn prefers_the_more_diverse_side_and_relays_with_its_own_hop() {
    let (mut n, mut rng) = node(5, 0);
    let mut t = Instant::from_secs(1);
    // From the right, uniform darkness; from the left, a lit robot.
    let out = hear(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(7, 0, None), hop(6, 0, None)],
    );
    assert_eq!(
        out.hops(),
        &[hop(7, 0, None), hop(6, 0, None), hop(5, 0, None)]
    );
    assert_eq!(n.preference(), None, "zero diversity gives no preference");
    let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &[hop(4, 1, R)]);
    assert_eq!(n.preference(), L);
    assert_eq!(
        out.hops(),
        &[hop(4, 1, R), hop(5, 0, L)],
        "relay carries the new preference and the own tag"
    );
    assert_eq!(n.weight(Sector::LEFT), Some(0.25));
    assert_eq!(n.weight(Sector::RIGHT), Some(0.0));
    assert_eq!(n.tag(), Tag::new(5).unwrap());
}

#[test]
fn initiations_carry_the_own_tag() {
    let (mut n, mut rng) = node(9, 3);
    let t = n.poll_timeout();
    n.handle_timeout(t, &mut rng);
    let m = n.poll_transmit().expect("initiated");
    assert_eq!(m.hops(), &[hop(9, 3, None)]);
}

#[test]
fn ignores_while_active_or_refractory_and_unknown_sectors() {
    let (mut n, mut rng) = node(5, 0);
    let m = Message::initiate(hop(4, 1, None));
    let t = Instant::from_secs(1);
    let r = &mut rng;
    assert_eq!(
        n.handle_message(t, Sector::LEFT, &m, r),
        Reception::Accepted
    );
    assert_eq!(
        n.handle_message(t, Sector::RIGHT, &m, r),
        Reception::Ignored
    );
    let t1 = t + Duration::from_secs(1);
    assert_eq!(
        n.handle_message(t1, Sector::RIGHT, &m, r),
        Reception::Ignored
    );
    assert!(n.poll_transmit().is_some(), "relayed on time");
    let t5 = t + Duration::from_secs(5);
    assert_eq!(
        n.handle_message(t5, Sector::LEFT, &m, r),
        Reception::Accepted
    );
    let s7 = Sector::new(7).unwrap();
    let t9 = t + Duration::from_secs(9);
    assert_eq!(n.handle_message(t9, s7, &m, r), Reception::UnknownSector);
    assert_eq!(n.stats().unknown_sector, 1);
    assert_eq!(n.wave_stats().ignored, 2);
}

#[test]
fn a_message_holding_the_own_tag_is_dropped_and_counted() {
    let (mut n, mut rng) = node(1, 1);
    let mut t = Instant::from_secs(1);
    hear(&mut n, &mut rng, &mut t, Sector::LEFT, &[hop(0, 1, R)]);
    while n.poll_event().is_some() {}
    let (votes, prefs, weights) = (n.votes(), n.preference(), n.weight(Sector::RIGHT));
    let (accepted, ignored) = (n.stats().accepted, n.wave_stats().ignored);
    // Its own relay of a wave from the left, come back from the right (an echo, or a replay
    // of what robot 2 relayed), while it could accept a message: dropped, whatever its
    // position, and nothing else happens.
    for msg in [
        &[hop(0, 1, R), hop(1, 1, R), hop(2, 0, L)][..],
        &[hop(1, 1, None)],
        &[hop(1, 1, R), hop(2, 0, L), hop(3, 0, L)],
    ] {
        t += Duration::from_secs(6);
        n.handle_timeout(t, &mut rng);
        while n.poll_event().is_some() {}
        let m = Message::from_hops(msg).unwrap();
        let got = n.handle_message(t, Sector::RIGHT, &m, &mut rng);
        assert_eq!(got, Reception::OwnTag, "{msg:?}");
        assert_eq!(n.state(), WaveState::Inactive, "no activation");
        n.handle_timeout(t + Duration::from_secs(1), &mut rng);
        assert_eq!(n.poll_transmit(), None, "not relayed");
        assert_eq!(n.poll_event(), None, "no event");
    }
    assert_eq!(n.stats().own_tag, 3);
    assert_eq!(n.votes(), votes, "not counted");
    assert_eq!(n.weight(Sector::RIGHT), weights, "not scored");
    assert_eq!(n.preference(), prefs);
    assert_eq!(n.stats().accepted, accepted);
    assert_eq!(n.wave_stats().ignored, ignored, "not the wave's business");
    // Messages without its tag are still heard.
    hear(&mut n, &mut rng, &mut t, Sector::RIGHT, &[hop(3, 0, L)]);
    assert_eq!(n.stats().own_tag, 3);
}

/// The ray robots `far..near` (readings and preferences, farthest first) send toward a
/// robot that hears the nearest of them from `from`.
pub(super) fn ray(from: Sector, robots: &[(u8, Option<Sector>)]) -> Ray {
    let (&(r0, p0), rest) = robots.split_first().unwrap();
    let first = Ray::single(from, 2, Level(r0), p0).unwrap();
    rest.iter()
        .fold(first, |ray, &(r, p)| ray.extended(Level(r), p))
}

/// `ray` as a ray that reaches the end of its side ([`Ray::closed`]).
pub(super) fn closed(mut ray: Ray) -> Ray {
    ray.closed = true;
    ray
}

/// Like [`hear`], for a message carrying `ray`.
pub(super) fn hear_ray(
    n: &mut FusedNode,
    rng: &mut Pcg32,
    t: &mut Instant,
    from: Sector,
    msg: &[Hop],
    ray: Ray,
) -> Message {
    *t += Duration::from_secs(12);
    n.handle_timeout(*t, rng);
    while n.poll_transmit().is_some() {}
    let mut m = Message::from_hops(msg).unwrap();
    m.set_ray(Some(ray));
    assert_eq!(n.handle_message(*t, from, &m, rng), Reception::Accepted);
    n.handle_timeout(*t + Duration::from_secs(1), rng);
    n.poll_transmit().expect("relayed")
}

#[test]
fn full_message_relay_drops_the_oldest_hops_to_make_room_for_the_ray() {
    let (mut n, mut rng) = node(15, 9);
    let mut t = Instant::from_secs(1);
    let full: std::vec::Vec<Hop> = (0..MAX_HOPS as u8).map(|r| hop(r, r, None)).collect();
    let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full);
    // 24 payload bytes: header, a two-sector ray (9 bytes), 7 hops (an eighth does not
    // fit the 25).
    assert_eq!(out.len(), 7);
    assert_eq!(out.encoded_len(), 24);
    assert_eq!(out.hops()[0], hop(6, 6, None));
    let last = out.hops()[6];
    assert_eq!((last.reading, last.tag), (Level(9), n.tag()));
    assert_eq!(n.stats().hops_evicted, 6);
    // Nothing held from the left yet: the ray is the robot alone.
    let ray = out.ray().unwrap();
    assert_eq!(
        (ray.sector, ray.robots, ray.mean_level()),
        (Sector::LEFT, 1, 9.0)
    );
    assert!(crate::frame::encode(&out).is_ok());
}

#[test]
fn relays_keep_at_most_max_hops() {
    let (mut n, mut rng) = node(15, 9);
    let mut p = *n.params();
    p.max_hops = crate::frame::KEYED_MAX_HOPS as u8;
    n = FusedNode::new(p, n.tag(), Instant::ZERO, &mut rng).unwrap();
    n.handle_reading(Level(9));
    let mut t = Instant::from_secs(1);
    // A full plain message (12 hops) relayed by an 11-hop node: a payload of 23 bytes,
    // the ray's 9 and 6 hops.
    let full: std::vec::Vec<Hop> = (0..MAX_HOPS as u8).map(|r| hop(r, r, None)).collect();
    let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full);
    assert_eq!(out.len(), 6);
    assert_eq!(out.encoded_len(), 22);
    assert_eq!(out.hops()[0], hop(7, 7, None));
    assert_eq!(out.hops()[5].reading, Level(9));
    assert_eq!(n.stats().hops_evicted, 7);
    // Shorter ones just grow, and an encoded relay always fits a keyed frame.
    let out = hear(&mut n, &mut rng, &mut t, Sector::LEFT, &full[..3]);
    assert_eq!(out.len(), 4);
    assert_eq!(n.stats().hops_evicted, 7);
    #[cfg(feature = "keyed")]
    assert!(crate::frame::encode_keyed(&out, &crate::auth::SwarmKey::new([5; 16])).is_ok());
}

#[test]
fn rays_count_every_robot_beyond_the_horizon_once() {
    // Robot 20 of a long line: 20 robots to its left (12 preferring R, 8 L), 30 to its
    // right preferring L; the messages hold only the nearest few.
    let (mut n, mut rng) = node(4, 30);
    let mut t = Instant::from_secs(1);
    let mut left: std::vec::Vec<(u8, Option<Sector>)> = std::vec![(200, R); 12];
    left.extend([(30, L); 8]);
    let right = std::vec![(30, L); 30];
    let out = hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(2, 30, L), hop(3, 30, L)],
        ray(Sector::LEFT, &left),
    );
    // The left is diverse (a border somewhere beyond), the right uniform.
    assert_eq!(n.preference(), L);
    // The relay goes right with the left's ray extended by this robot.
    let sent = out.ray().unwrap();
    assert_eq!((sent.sector, sent.robots), (Sector::LEFT, 21));
    assert_eq!(sent.votes[..2], [12, 9]);
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(6, 30, L), hop(5, 30, L)],
        ray(Sector::RIGHT, &right),
    );
    assert_eq!(n.preference(), L, "the right is uniform");
    assert_eq!(n.votes()[..2], [12, 39]);
    assert_eq!(n.stats().rays, 2);
    let Event::Decided { decision, .. } = run_to_decision(&mut n, &mut rng) else {
        unreachable!()
    };
    assert_eq!(decision, L);
}

#[test]
fn the_direction_is_scored_by_its_whole_ray() {
    // Robot far to the right of a border: the nearest hops are dark like itself, but the
    // ray from the left holds lit robots beyond the horizon.
    let (mut n, mut rng) = node(4, 30);
    let mut t = Instant::from_secs(1);
    let mut left = std::vec![(200, R); 5];
    left.extend([(30, L); 20]);
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(2, 30, L), hop(3, 30, L)],
        ray(Sector::LEFT, &left),
    );
    let expected = ray(Sector::LEFT, &left)
        .extended(Level(30), None)
        .variance();
    assert_eq!(n.weight(Sector::LEFT), Some(expected));
    assert!(expected > 1000.0);
    // Without a ray: the message's readings with the own (Alg. 1), here uniform.
    hear(&mut n, &mut rng, &mut t, Sector::RIGHT, &[hop(6, 30, L)]);
    assert_eq!(n.weight(Sector::RIGHT), Some(0.0));
    assert_eq!(n.preference(), L);
}

#[test]
fn a_ray_is_taken_only_for_its_own_sector_and_from_the_followed_neighbour() {
    let (mut n, mut rng) = node(1, 0);
    let mut t = Instant::from_secs(1);
    let far = [(0, L), (0, L), (0, L)];
    // A ray of the left heard from the right (an initiation meant for the other side).
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(2, 0, L)],
        ray(Sector::LEFT, &far),
    );
    assert_eq!((n.stats().rays, n.stats().rays_refused), (0, 1));
    // Robot 2's ray of the right: followed from now on.
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(2, 0, L)],
        ray(Sector::RIGHT, &far),
    );
    assert_eq!(n.votes()[..2], [0, 3]);
    // Robot 3 (two away) sends a shorter ray: refused while robot 2 is heard.
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(3, 0, R)],
        ray(Sector::RIGHT, &[(0, R), (0, R)]),
    );
    assert_eq!(n.votes()[..2], [0, 3]);
    // Robot 2 again, preferences changed: it replaces its own ray, shorter or not.
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(2, 0, R)],
        ray(Sector::RIGHT, &[(0, R), (0, R)]),
    );
    assert_eq!(n.votes()[..2], [2, 0]);
    // A ray reaching farther, from another neighbour, is taken.
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(7, 0, L)],
        ray(Sector::RIGHT, &[(0, L); 4]),
    );
    assert_eq!(n.votes()[..2], [0, 4]);
    // Robot 0 on the left; a frame of robot 0 moved to the right by a replayer, with a ray
    // that reaches farther, is refused: robot 0 is followed on the left.
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(0, 1, R)],
        ray(Sector::LEFT, &[(1, R)]),
    );
    let before = n.votes();
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(0, 1, R)],
        ray(Sector::RIGHT, &[(1, R); 9]),
    );
    assert_eq!(n.votes(), before);
    // After three silent cycles of its neighbour another sender is taken, shorter or not.
    t += Duration::from_secs(3 * 600 + 1);
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(3, 0, R)],
        ray(Sector::RIGHT, &[(0, R)]),
    );
    assert_eq!(n.votes()[..2], [2, 1], "robot 3 R; its own L");
}

#[test]
fn initiations_carry_the_shortest_sides_ray() {
    let (mut n, mut rng) = node(1, 7);
    let mut t = Instant::from_secs(1);
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(2, 0, L)],
        ray(Sector::RIGHT, &[(0, L); 3]),
    );
    let initiate = |n: &mut FusedNode, rng: &mut Pcg32| loop {
        let at = n.poll_timeout();
        n.handle_timeout(at, rng);
        if let Some(m) = n.poll_transmit() {
            return m;
        }
    };
    // Nothing held on the left: the edge's own ray goes out, meant for the right.
    let m = initiate(&mut n, &mut rng);
    assert_eq!(m.hops(), &[hop(1, 7, R)]);
    let r = m.ray().unwrap();
    assert_eq!((r.sector, r.robots, r.votes[0]), (Sector::LEFT, 1, 1));
    // With a longer left, the right is the short side.
    // Rested after the initiation.
    t = n.poll_timeout();
    n.handle_timeout(t, &mut rng);
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(0, 0, R)],
        ray(Sector::LEFT, &[(0, R); 5]),
    );
    let r = *initiate(&mut n, &mut rng).ray().unwrap();
    assert_eq!((r.sector, r.robots), (Sector::RIGHT, 4));
}

pub(super) fn run_to_decision(n: &mut FusedNode, rng: &mut Pcg32) -> Event {
    loop {
        let t = n.poll_timeout();
        n.handle_timeout(t, rng);
        while n.poll_transmit().is_some() {}
        while let Some(e) = n.poll_event() {
            if matches!(e, Event::Decided { .. }) {
                return e;
            }
        }
    }
}

#[test]
fn tie_keeps_own_preference_and_rays_expire_after_a_period() {
    let (mut n, mut rng) = node(1, 1);
    let mut t = Instant::from_secs(1);
    // 1100 seen by the second robot: left lit (pref R), right dark (prefs L, L).
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(0, 1, R)],
        ray(Sector::LEFT, &[(1, R)]),
    );
    hear_ray(
        &mut n,
        &mut rng,
        &mut t,
        Sector::RIGHT,
        &[hop(3, 0, L), hop(2, 0, L)],
        ray(Sector::RIGHT, &[(0, L), (0, L)]),
    );
    assert_eq!(n.preference(), R);
    let e = run_to_decision(&mut n, &mut rng);
    let Event::Decided {
        decision,
        votes,
        period,
        changed,
    } = e
    else {
        unreachable!()
    };
    assert_eq!((decision, period, changed), (R, 1, true));
    assert_eq!(votes[..2], [2, 2]);
    assert_eq!(n.decision(), R);
    // Nothing heard in the next period: the rays are a period old and forgotten.
    let Event::Decided {
        decision,
        votes,
        changed,
        ..
    } = run_to_decision(&mut n, &mut rng)
    else {
        unreachable!()
    };
    assert_eq!((decision, changed), (R, false));
    assert_eq!(votes[..2], [1, 0], "rays expired");
    // The diversities carry over as one-message priors: the left's 0 (robot 0 lit like
    // this robot), the right's 2/9 (readings 0, 0 and the own 1, exact in the ray's sums).
    let right = n.weight(Sector::RIGHT).unwrap();
    assert_eq!(right, 2.0 / 9.0);
    assert_eq!(n.weight(Sector::LEFT), Some(0.0));
    // Robot 0's light goes out, and a wave from farther left (robots 6, 5, 4: 1, 2, 1)
    // passes it: with the own 1, diversity 2/5. On its own that beats the right's 1/4;
    // averaged with the left's prior it gives 1/5, and the preference holds.
    let v = Variance.measure([1.0, 2.0, 1.0, 0.0, 1.0].into_iter());
    assert!(v > right && v / 2.0 < right, "only the prior keeps it: {v}");
    // Two periods of fixed 600 s cycles have passed; the node last initiated at 12000 s.
    t = Instant::from_secs(12_010);
    hear(
        &mut n,
        &mut rng,
        &mut t,
        Sector::LEFT,
        &[hop(6, 1, R), hop(5, 2, R), hop(4, 1, R), hop(0, 0, R)],
    );
    assert_eq!(n.preference(), R, "one message does not flip it");
    assert_eq!(n.weight(Sector::LEFT), Some(v / 2.0));
}

#[test]
fn the_cosine_table_is_the_cosine() {
    for k in 2..=MAX_SECTORS {
        for (d, &table) in COSINES[k][..k].iter().enumerate() {
            let c = libm::cos(core::f64::consts::TAU * d as f64 / k as f64);
            assert!((f64::from(table) - c).abs() < 1e-6, "{k} {d}");
        }
        assert!(COSINES[k][k..].iter().all(|&c| c == 0.0));
    }
    assert_eq!(COSINES[4][1], 0.0);
    assert_eq!(COSINES[6][1], 0.5);
}

#[test]
fn plane_votes_add_up_along_their_resultant() {
    // K = 6: sector 1 has the plurality, but sectors 0, 1 and 5 all point to +x and
    // sector 0 is nearest their resultant.
    let votes = [2, 3, 0, 0, 0, 2, 0, 0];
    let s = resultant_scores(&votes, 6);
    assert_eq!(s[0], 4.5);
    assert_eq!(s[1], 3.0);
    assert!(s[..6].iter().all(|&x| x <= s[0]));
    // K = 2: the difference of the counts, exact ties stay ties.
    let s = resultant_scores(&[3, 3, 0, 0, 0, 0, 0, 0], 2);
    assert_eq!(s[..2], [0.0, 0.0]);
    // K = 4: perpendicular votes do not count.
    let s = resultant_scores(&[1, 5, 0, 0, 0, 0, 0, 0], 4);
    assert_eq!(s[..4], [1.0, 5.0, -1.0, -5.0]);
}

#[test]
fn a_period_lasts_the_configured_cycles() {
    let (mut n, mut rng) = node(0, 0);
    let Event::Decided { decision, .. } = run_to_decision(&mut n, &mut rng) else {
        unreachable!()
    };
    assert_eq!(decision, None, "no preference, no votes: undecided");
    assert_eq!(n.wave_stats().initiated, 10);
    assert_eq!(n.periods(), 1);
}

#[test]
fn invalid_params_are_refused() {
    let mut p = Params::robots();
    p.sectors = 0;
    assert_eq!(
        FusedNode::new(p, Tag::default(), Instant::ZERO, &mut Pcg32::new(0, 0)).err(),
        Some(ParamError::BadSectorCount)
    );
}

/// Two robots side by side (robot 0 left of robot 1), each hearing the other's transmissions,
/// driven to `until`: every event with its time and robot.
fn pair_events<R: Rule>(
    decide: DecisionRule,
    until: Instant,
) -> std::vec::Vec<(u64, usize, Event)> {
    let mut p = Params::robots();
    p.decide = decide;
    let mut rngs = [Pcg32::new(3, 5), Pcg32::new(7, 9)];
    let mut nodes: std::vec::Vec<FusedNode<Variance, R>> = (0..2)
        .map(|i| {
            let tag = Tag::new(i as u8).unwrap();
            let mut n =
                FusedNode::with_rule(p, tag, Variance, Instant::ZERO, &mut rngs[i]).unwrap();
            n.handle_reading(Level(30 * i as u8));
            n
        })
        .collect();
    let mut log = std::vec::Vec::new();
    loop {
        let (i, t) = (0..2)
            .map(|i| (i, nodes[i].poll_timeout()))
            .min_by_key(|&(_, t)| t)
            .unwrap();
        if t > until {
            return log;
        }
        nodes[i].handle_timeout(t, &mut rngs[i]);
        while let Some(m) = nodes[i].poll_transmit() {
            // Robot 0 hears robot 1 on its right, robot 1 hears robot 0 on its left.
            let (j, from) = if i == 0 {
                (1, Sector::LEFT)
            } else {
                (0, Sector::RIGHT)
            };
            nodes[j].handle_message(t, from, &m, &mut rngs[j]);
        }
        for (k, n) in nodes.iter_mut().enumerate() {
            log.extend(core::iter::from_fn(|| n.poll_event()).map(|e| (t.as_millis(), k, e)));
        }
    }
}

#[test]
fn a_node_named_for_its_rule_does_what_the_rule_chosen_at_run_time_does() {
    let until = Instant::from_secs(3 * 600);
    for decide in [DecisionRule::Fixed, DecisionRule::Adaptive] {
        let any = pair_events::<AnyRule>(decide, until);
        let decided = any
            .iter()
            .filter(|(_, _, e)| matches!(e, Event::Decided { .. }));
        assert!(decided.count() >= 2, "{decide:?}: the pair decided nothing");
        let named = match decide {
            DecisionRule::Fixed => pair_events::<Fixed>(decide, until),
            DecisionRule::Adaptive => pair_events::<Adaptive>(decide, until),
        };
        assert_eq!(any, named, "{decide:?}");
    }
}

#[test]
fn a_node_named_for_one_rule_refuses_params_naming_another() {
    let mut rng = Pcg32::new(1, 2);
    let tag = Tag::new(1).unwrap();
    let mut p = Params::robots();
    p.decide = DecisionRule::Fixed;
    let adaptive =
        FusedNode::<Variance, Adaptive>::with_rule(p, tag, Variance, Instant::ZERO, &mut rng);
    assert_eq!(adaptive.err(), Some(ParamError::RuleMismatch));
    assert!(
        FusedNode::<Variance, Fixed>::with_rule(p, tag, Variance, Instant::ZERO, &mut rng).is_ok()
    );
    p.decide = DecisionRule::Adaptive;
    let fixed = FusedNode::<Variance, Fixed>::with_rule(p, tag, Variance, Instant::ZERO, &mut rng);
    assert_eq!(fixed.err(), Some(ParamError::RuleMismatch));
}

/// fuzz/README.md, finding 14: an initiation skipped while busy a few seconds before the end
/// of time owes an extra initiation that cannot be scheduled (it would fall at `Instant::MAX`,
/// "never"). A later call before the deadline, at an earlier instant (a clock set back), must
/// not schedule it: it would change what the robot does with nothing due.
#[test]
fn a_debt_at_the_end_of_time_is_not_scheduled_before_the_deadline() {
    for decide in [DecisionRule::Fixed, DecisionRule::Adaptive] {
        let mut rng = Pcg32::new(3, 7);
        let mut p = Params::robots();
        p.decide = decide;
        p.wave.cycle = Duration::from_secs(600);
        p.wave.cycle_spread = Duration::ZERO;
        let start = Instant::MAX - Duration::from_secs(603);
        let mut n = FusedNode::new(p, Tag::new(1).unwrap(), start, &mut rng).unwrap();
        n.handle_reading(Level(9));
        // The first initiation, at the cycle's end, 3 s before the end of time.
        let init = Instant::MAX - Duration::from_secs(3);
        assert_eq!(n.poll_timeout(), init, "{decide:?}");
        // Active when it falls: skipped, and owed.
        let m = Message::from_hops(&[hop(2, 40, None)]).unwrap();
        let heard = init - Duration::from_millis(500);
        assert_eq!(
            n.handle_message(heard, Sector::LEFT, &m, &mut rng),
            Reception::Accepted
        );
        n.handle_timeout(init, &mut rng);
        assert_eq!(n.wave_stats().skipped_initiations, 1, "{decide:?}");
        // The relay goes; the refractory time then lasts to the end of time.
        n.handle_timeout(n.poll_timeout(), &mut rng);
        assert!(n.poll_transmit().is_some(), "{decide:?}: relayed");
        while n.poll_transmit().is_some() || n.poll_event().is_some() {}
        assert_eq!(n.poll_timeout(), Instant::MAX, "{decide:?}");
        // The clock set back: nothing is due, so nothing changes.
        n.handle_timeout(start, &mut rng);
        assert_eq!(
            n.poll_timeout(),
            Instant::MAX,
            "{decide:?}: a deferral scheduled"
        );
        assert!(n.poll_transmit().is_none() && n.poll_event().is_none());
    }
}
