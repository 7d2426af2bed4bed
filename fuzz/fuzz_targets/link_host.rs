//! cargo-fuzz target `link_host`: see [`protocol_fuzz::link_host`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::link_host::check(data));
