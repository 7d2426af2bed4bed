//! Serde for the counters an [`Outcome`](super::Outcome) carries, which their crates
//! (`hal-emu`'s [`MediumStats`], `protocol`'s [`WaveStats`] and [`NodeStats`]) do not derive
//! both ways: serde's remote derives, field for field (a field added there fails to compile
//! here, so none is dropped silently). A campaign's runs go through them into part files
//! (`cimax arena campaign --shard`) and back.

use hal_emu::MediumStats;
use protocol::fused::NodeStats;
use protocol::wave::WaveStats;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// [`MediumStats`], field for field.
#[derive(Serialize, Deserialize)]
#[serde(remote = "MediumStats")]
pub(super) struct MediumStatsDef {
    sent: u64,
    delivered: u64,
    garbled: u64,
    corrupted_bytes: u64,
    lost: u64,
    receiver_transmitting: u64,
    receiver_dead: u64,
    rogue_bursts: u64,
    replayed: u64,
    adversary_delivered: u64,
    captured: u64,
    capture_missed: u64,
}

/// [`WaveStats`], field for field.
#[derive(Serialize, Deserialize)]
#[serde(remote = "WaveStats")]
struct WaveStatsDef {
    initiated: u32,
    relayed: u32,
    ignored: u32,
    skipped_initiations: u32,
}

/// [`NodeStats`], field for field.
#[derive(Serialize, Deserialize)]
#[serde(remote = "NodeStats")]
struct NodeStatsDef {
    accepted: u32,
    unknown_sector: u32,
    own_tag: u32,
    hops_evicted: u32,
    rays: u32,
    rays_refused: u32,
    transmits_lost: u32,
    events_lost: u32,
    periods: u32,
    periods_short: u32,
}

#[derive(Serialize, Deserialize)]
struct Wave(#[serde(with = "WaveStatsDef")] WaveStats);

#[derive(Serialize, Deserialize)]
struct Node(#[serde(with = "NodeStatsDef")] NodeStats);

/// `Vec<WaveStats>` (`#[serde(with = "stats_serde::waves")]`).
pub(super) mod waves {
    use super::*;

    pub fn serialize<S: Serializer>(v: &[WaveStats], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|w| Wave(*w)))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<WaveStats>, D::Error> {
        Ok(Vec::<Wave>::deserialize(d)?
            .into_iter()
            .map(|w| w.0)
            .collect())
    }
}

/// `Vec<NodeStats>` (`#[serde(with = "stats_serde::nodes")]`).
pub(super) mod nodes {
    use super::*;

    pub fn serialize<S: Serializer>(v: &[NodeStats], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(v.iter().map(|n| Node(*n)))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<NodeStats>, D::Error> {
        Ok(Vec::<Node>::deserialize(d)?
            .into_iter()
            .map(|n| n.0)
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::super::Outcome;
    use super::*;

    #[test]
    fn an_outcome_round_trips_bit_for_bit() {
        let o = Outcome {
            seed: u64::MAX,
            pattern: "1000".into(),
            expected: "LLLL".into(),
            leds: "LL-L".into(),
            success: false,
            why: Some("wrong LEDs at the end".into()),
            crashed: false,
            consensus_s: Some(0.1 + 0.2),
            restore_s: Some(-1.0 / 3.0),
            medium: MediumStats {
                sent: 1,
                delivered: 2,
                garbled: 3,
                corrupted_bytes: 4,
                lost: 5,
                receiver_transmitting: 6,
                receiver_dead: 7,
                rogue_bursts: 8,
                replayed: 9,
                adversary_delivered: 10,
                captured: 11,
                capture_missed: u64::MAX,
            },
            frame_errors: 12,
            waves: vec![WaveStats {
                initiated: 1,
                relayed: 2,
                ignored: 3,
                skipped_initiations: 4,
            }],
            nodes: vec![
                NodeStats {
                    accepted: 1,
                    periods: 9,
                    periods_short: 10,
                    ..NodeStats::default()
                },
                NodeStats::default(),
            ],
            duration_s: 2_101.000_000_000_1,
        };
        let text = serde_json::to_string(&o).unwrap();
        let back: Outcome = serde_json::from_str(&text).unwrap();
        assert_eq!(serde_json::to_string(&back).unwrap(), text);
        assert_eq!(back.medium, o.medium);
        assert_eq!(back.waves, o.waves);
        assert_eq!(back.nodes, o.nodes);
        for (a, b) in [
            (back.consensus_s, o.consensus_s),
            (back.restore_s, o.restore_s),
            (Some(back.duration_s), Some(o.duration_s)),
        ] {
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
    }
}
