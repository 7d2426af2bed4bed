//! Replays one input through a target's check on the ordinary (pinned) toolchain, after
//! printing what the input means: a crash found by `cargo fuzz` debugged with a plain backtrace.
//!
//! ```text
//! cd fuzz && cargo run --example replay -- fused_node artifacts/fused_node/crash-…
//! ```

use protocol_fuzz::{
    deframer, fused_node, keyed, link_decode, link_host, link_pump, link_roundtrip, message_decode,
    roundtrip, three_phase,
};

fn main() {
    let mut args = std::env::args().skip(1);
    let (Some(target), Some(path)) = (args.next(), args.next()) else {
        eprintln!("usage: cargo run --example replay -- <target> <input file>");
        std::process::exit(2);
    };
    let data = std::fs::read(&path).unwrap_or_else(|e| {
        eprintln!("cannot read {path}: {e}");
        std::process::exit(2);
    });
    let check: fn(&[u8]) = match target.as_str() {
        "deframer" => {
            let (cuts, stream) = deframer::split(&data);
            println!("cuts {cuts:?}\nstream {stream:02x?}");
            println!("byte by byte: {:?}", deframer::by_push(stream).0);
            deframer::check
        }
        "message_decode" => {
            println!("decode_frame: {:?}", protocol::frame::decode_frame(&data));
            message_decode::check
        }
        "roundtrip" => {
            println!("{:#?}", roundtrip::Input::read(&data));
            roundtrip::check
        }
        "fused_node" => {
            println!("{:#?}", fused_node::Input::read(&data));
            fused_node::check
        }
        "three_phase" => {
            println!("{:#?}", three_phase::Input::read(&data));
            three_phase::check
        }
        "keyed" => {
            println!(
                "mode {:?}, {} bytes",
                data.first().map(|m| m % 3),
                data.len()
            );
            keyed::check
        }
        "link_decode" => {
            let stream = link_decode::stream(&data);
            println!("stream {stream:02x?}");
            let mut d = firmware::hil::LinkDecoder::new();
            let got: Vec<_> = stream.iter().filter_map(|&b| d.push(b)).collect();
            println!("results {got:?}\n{:?}", d.stats());
            link_decode::check
        }
        "link_roundtrip" => {
            println!("{:#?}", link_roundtrip::Input::read(&data));
            link_roundtrip::check
        }
        "link_pump" => {
            println!("{:#?}", link_pump::Input::read(&data));
            link_pump::check
        }
        "link_host" => {
            match data.split_first() {
                Some((m, rest)) if m % 2 == link_host::BATCH => {
                    println!("{:#?}", link_host::Batch::read(rest));
                }
                Some((_, rest)) => {
                    let (cuts, stream) = deframer::split(rest);
                    println!("cuts {cuts:?}\nstream {stream:02x?}");
                }
                None => println!("empty"),
            }
            link_host::check
        }
        other => {
            eprintln!(
                "unknown target {other}; one of {:?}",
                protocol_fuzz::TARGETS
            );
            std::process::exit(2);
        }
    };
    check(&data);
    println!("{target}: the check passes on {path}");
}
