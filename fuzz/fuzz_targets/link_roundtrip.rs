//! cargo-fuzz target `link_roundtrip`: see [`protocol_fuzz::link_roundtrip`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::link_roundtrip::check(data));
