//! cargo-fuzz target `three_phase`: see [`protocol_fuzz::three_phase`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::three_phase::check(data));
