//! cargo-fuzz target `roundtrip`: see [`protocol_fuzz::roundtrip`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::roundtrip::check(data));
