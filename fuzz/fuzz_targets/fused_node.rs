//! cargo-fuzz target `fused_node`: see [`protocol_fuzz::fused_node`] and README.md.

#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| protocol_fuzz::fused_node::check(data));
