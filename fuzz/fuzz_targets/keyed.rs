//! cargo-fuzz target `keyed`: see [`protocol_fuzz::keyed`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::keyed::check(data));
