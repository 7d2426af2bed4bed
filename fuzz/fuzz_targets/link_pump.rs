//! cargo-fuzz target `link_pump`: see [`protocol_fuzz::link_pump`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::link_pump::check(data));
