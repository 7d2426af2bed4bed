//! cargo-fuzz target `link_decode`: see [`protocol_fuzz::link_decode`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::link_decode::check(data));
