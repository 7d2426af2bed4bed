//! Helpers the end-to-end tests share: the paper's lab line for a pattern and a seed, run for
//! [`RUN`]. Each test file that needs them says `mod common;`.

// Each test file is its own crate and uses only some of these.
#![allow(dead_code)]

use hal_emu::ArenaConfig;
use hal_emu::judge::parse_pattern;
use protocol::Duration;

/// Three negotiation periods of the longest (70 s) cycles.
pub const RUN: Duration = Duration::from_secs(3 * 10 * 70);

/// The lab line for `pattern` (one robot per character, `1` lit), robots 1 m apart, run for
/// [`RUN`] with `seed`.
pub fn lab(pattern: &str, seed: u64) -> ArenaConfig {
    ArenaConfig::line(parse_pattern(pattern).unwrap(), 1.0, RUN, seed)
}
