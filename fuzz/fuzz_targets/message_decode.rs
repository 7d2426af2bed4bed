//! cargo-fuzz target `message_decode`: see [`protocol_fuzz::message_decode`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::message_decode::check(data));
