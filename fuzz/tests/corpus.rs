//! The committed seed corpus: exactly what the generator makes, each seed passing its target's
//! check, and the framing seeds giving the results the generator lists for them.

use std::collections::BTreeMap;
use std::path::Path;

use protocol::frame::decode_frame;
use protocol::{Event, Reception};
use protocol_fuzz::fused_node::Out;
use protocol_fuzz::{
    TARGETS, corpus, deframer, fused_node, keyed, link_corpus, link_decode, link_host, link_pump,
    link_roundtrip, message_decode, roundtrip, three_phase,
};

fn committed() -> BTreeMap<(String, String), Vec<u8>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    let mut out = BTreeMap::new();
    for t in TARGETS {
        for entry in std::fs::read_dir(root.join(t)).expect("corpus/<target> exists") {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            out.insert((t.to_string(), name), std::fs::read(&path).unwrap());
        }
    }
    out
}

/// The check of fuzz target `target`.
fn check_of(target: &str) -> fn(&[u8]) {
    match target {
        "deframer" => deframer::check,
        "message_decode" => message_decode::check,
        "roundtrip" => roundtrip::check,
        "fused_node" => fused_node::check,
        "three_phase" => three_phase::check,
        "keyed" => keyed::check,
        "link_decode" => link_decode::check,
        "link_roundtrip" => link_roundtrip::check,
        "link_pump" => link_pump::check,
        "link_host" => link_host::check,
        other => panic!("unknown target {other}"),
    }
}

#[test]
fn committed_corpus_is_what_the_generator_makes() {
    let generated: BTreeMap<(String, String), Vec<u8>> = corpus::files()
        .into_iter()
        .map(|(t, n, b)| ((t.to_string(), n), b))
        .collect();
    let committed = committed();
    let names = |m: &BTreeMap<(String, String), Vec<u8>>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(
        names(&committed),
        names(&generated),
        "run `cargo run --example gen_corpus` in fuzz/"
    );
    for (k, bytes) in &generated {
        assert_eq!(&committed[k], bytes, "{k:?} is stale: regenerate");
    }
    for t in TARGETS {
        let n = generated.keys().filter(|(target, _)| target == t).count();
        assert!((5..=45).contains(&n), "{n} seeds for {t}");
    }
}

#[test]
fn every_committed_seed_passes_its_check() {
    for ((target, name), bytes) in committed() {
        let check = check_of(&target);
        if std::panic::catch_unwind(|| check(&bytes)).is_err() {
            panic!("{target}/{name} fails its check");
        }
    }
}

#[test]
fn deframer_seeds_give_their_results() {
    for s in corpus::deframer() {
        let (got, d) = deframer::by_push(&s.stream);
        assert_eq!(got, s.expect, "{}", s.name);
        assert_eq!(
            d.stats().frames as usize,
            got.iter().filter(|r| r.is_ok()).count()
        );
        assert_eq!(
            deframer::split(&deframer::input(&s.cuts, &s.stream)),
            (&s.cuts[..], &s.stream[..])
        );
    }
}

#[test]
fn keyed_stream_seeds_give_their_results() {
    for s in corpus::keyed() {
        let Some(expect) = &s.expect else { continue };
        let (key, rest) = keyed::split_key(&s.bytes[1..]);
        let (_, stream) = deframer::split(rest);
        let (got, d) = deframer::by_push_into(
            protocol::Deframer::with_key(protocol::SwarmKey::new(key)),
            stream,
        );
        assert_eq!(&got, expect, "{}", s.name);
        assert_eq!(
            d.stats().bad_mac as usize,
            got.iter()
                .filter(|r| **r == Err(protocol::FrameError::BadMac))
                .count()
        );
    }
}

#[test]
fn message_decode_seeds_give_their_results() {
    for s in corpus::message_decode() {
        assert_eq!(decode_frame(&s.data), s.frame, "{}", s.name);
        if let Some(expected) = &s.as_payload {
            assert_eq!(
                &message_decode::expected_for_payload(&s.data),
                expected,
                "{}",
                s.name
            );
        }
    }
}

#[test]
fn structured_seeds_read_back() {
    for (name, i) in corpus::roundtrip() {
        assert_eq!(roundtrip::Input::read(&i.write()), i, "{name}");
    }
    for (name, i) in corpus::fused_node() {
        assert_eq!(fused_node::Input::read(&i.write()), i, "{name}");
    }
    for (name, i) in corpus::three_phase() {
        assert_eq!(three_phase::Input::read(&i.write()), i, "{name}");
    }
    for (name, i) in link_corpus::link_roundtrip() {
        assert_eq!(link_roundtrip::Input::read(&i.write()), i, "{name}");
    }
    for (name, i) in link_corpus::link_pump() {
        assert_eq!(link_pump::Input::read(&i.write()), i, "{name}");
    }
    for (name, bytes) in link_corpus::link_host() {
        if bytes[0] == link_host::BATCH {
            let b = link_host::Batch::read(&bytes[1..]);
            assert_eq!(b.write(), bytes, "{name}");
        }
    }
}

#[test]
fn link_decode_seeds_give_their_results() {
    for s in link_corpus::link_decode() {
        let mut d = firmware::hil::LinkDecoder::new();
        let got: Vec<_> = link_decode::stream(&s.data)
            .iter()
            .filter_map(|&b| d.push(b))
            .collect();
        assert_eq!(got, s.expect, "{}", s.name);
    }
}

#[test]
fn link_pump_seeds_reach_what_they_are_named_for() {
    let stats = |name: &str| {
        let (_, input) = link_corpus::link_pump()
            .into_iter()
            .find(|(n, _)| *n == name)
            .expect("a seed of that name");
        link_pump::run_model(&input)
    };
    assert_eq!(stats("held-overflow").held_over, 4);
    assert_eq!(stats("pipe-overflow").rx_lost, 32);
    assert_eq!(stats("sync-on-own-clock").unexpected, 2);
    assert_eq!(
        stats("host-clock-asked-of-a-robot-that-cannot").unexpected,
        1
    );
    assert_eq!(stats("robot-messages-to-a-robot").unexpected, 5);
    let run = stats("host-clock-run");
    assert_eq!((run.setups, run.sent, run.held_over), (1, 3, 0));
    let w = stats("writer-fails");
    assert_eq!((w.sent, w.uart_errors), (2, 3));
    let g = stats("garbage-truncation-uart-errors");
    assert_eq!((g.uart_errors, g.link.frames, g.setups), (2, 2, 1));
}

fn fused(name: &str) -> Vec<Out> {
    let (_, input) = corpus::fused_node()
        .into_iter()
        .find(|(n, _)| *n == name)
        .expect("a seed of that name");
    fused_node::run(&input)
}

#[test]
fn fused_seeds_reach_what_they_are_named_for() {
    let decided = |t: &[Out]| {
        t.iter()
            .filter(|o| matches!(o, Out::Event(Event::Decided { .. })))
            .count()
    };
    let lab = fused("robots-lit-left-dark-right-to-decision");
    assert!(decided(&lab) >= 1, "a decision");
    assert_eq!(
        lab.iter()
            .filter(|o| **o == Out::Reception(Reception::Accepted))
            .count(),
        2
    );
    let odd = fused("empty-message-and-unknown-sector");
    assert!(odd.contains(&Out::Reception(Reception::Ignored)));
    assert!(odd.contains(&Out::Reception(Reception::UnknownSector)));
    assert!(
        fused("invalid-params-zero-cycle").is_empty(),
        "refused by new"
    );
    let framed = fused("quick-k5-frames-noise-unknown-sector");
    assert!(framed.iter().any(|o| matches!(o, Out::Deframed(Err(_)))));
    assert!(framed.contains(&Out::Reception(Reception::UnknownSector)));
    // Twelve held deadlines of one-cycle periods overflow both queues: the first drain gets
    // full queues.
    let held = fused("held-outputs-overflow");
    let first_drain: Vec<&Out> = held
        .iter()
        .skip_while(|o| !matches!(o, Out::Transmit(_) | Out::Event(_)))
        .take_while(|o| matches!(o, Out::Transmit(_) | Out::Event(_)))
        .collect();
    let transmits = first_drain
        .iter()
        .filter(|o| matches!(o, Out::Transmit(_)))
        .count();
    assert_eq!((transmits, first_drain.len() - transmits), (2, 8));
    // At the end of time the node stops: later deadlines are all "never".
    let end = fused("end-of-time");
    assert_eq!(
        end.last(),
        Some(&Out::Deadline(protocol::Instant::MAX)),
        "{end:?}"
    );
}

/// Inputs that once failed a check (fuzz/README.md, "Findings"), kept under
/// `tests/regressions/<target>/`: each must pass now.
#[test]
fn past_failures_pass() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions");
    let mut n = 0;
    for t in TARGETS {
        let Ok(dir) = std::fs::read_dir(root.join(t)) else {
            continue;
        };
        for entry in dir {
            let path = entry.unwrap().path();
            let bytes = std::fs::read(&path).unwrap();
            let check = check_of(t);
            if std::panic::catch_unwind(|| check(&bytes)).is_err() {
                panic!("{} fails its check again", path.display());
            }
            n += 1;
        }
    }
    assert!(n >= 1, "the regression inputs are missing");
}
