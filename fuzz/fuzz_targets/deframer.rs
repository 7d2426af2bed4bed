//! cargo-fuzz target `deframer`: see [`protocol_fuzz::deframer`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::deframer::check(data));
