//! `--shard I/N`: which share of a job's units one process runs.
//!
//! A job's units are numbered `0..total` in an order fixed by the command; shard `I` of `N`
//! (`I` from 1, as `sbatch --array=1-N` numbers its tasks and GNU parallel its `{#}`) owns the
//! units `k` with `k % N == I - 1`. Dealing the units round-robin spreads slow and fast ones
//! (a far start, a near one) evenly over the shards.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// Shard `index` of `count`, `1 <= index <= count`. Parsed from and shown as `I/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "RawShard", into = "RawShard")]
pub struct ShardSpec {
    index: u32,
    count: u32,
}

/// What a part file's header holds, checked into a [`ShardSpec`] when read.
#[derive(Clone, Copy, Serialize, Deserialize)]
struct RawShard {
    index: u32,
    count: u32,
}

impl From<ShardSpec> for RawShard {
    fn from(s: ShardSpec) -> Self {
        RawShard {
            index: s.index,
            count: s.count,
        }
    }
}

impl TryFrom<RawShard> for ShardSpec {
    type Error = ShardSpecError;

    fn try_from(r: RawShard) -> Result<Self, Self::Error> {
        ShardSpec::new(r.index, r.count)
    }
}

/// Why a `--shard` value is not one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShardSpecError {
    /// Not of the form `I/N`.
    Form(String),
    /// `I` or `N` is not a whole number (the text given).
    Number(String),
    /// `N` is 0.
    NoShards,
    /// `I` is 0: shards count from 1.
    Zero,
    /// `I` is greater than `N`.
    Beyond {
        /// `I`.
        index: u32,
        /// `N`.
        count: u32,
    },
}

impl fmt::Display for ShardSpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShardSpecError::Form(s) => {
                write!(f, "{s:?} is not I/N (shard I of N, e.g. 2/3)")
            }
            ShardSpecError::Number(s) => write!(
                f,
                "{s:?} is not a whole number (I/N: shard I of N, e.g. 2/3)"
            ),
            ShardSpecError::NoShards => f.write_str("N must be at least 1 (I/N: shard I of N)"),
            ShardSpecError::Zero => {
                f.write_str("shard 0: shards count from 1 (I/N with 1 <= I <= N)")
            }
            ShardSpecError::Beyond { index, count } => write!(
                f,
                "shard {index} of {count}: I must be at most N (I/N with 1 <= I <= N)"
            ),
        }
    }
}

impl std::error::Error for ShardSpecError {}

impl ShardSpec {
    /// Shard `index` of `count`.
    ///
    /// # Errors
    /// Unless `1 <= index <= count`.
    pub fn new(index: u32, count: u32) -> Result<ShardSpec, ShardSpecError> {
        if count == 0 {
            Err(ShardSpecError::NoShards)
        } else if index == 0 {
            Err(ShardSpecError::Zero)
        } else if index > count {
            Err(ShardSpecError::Beyond { index, count })
        } else {
            Ok(ShardSpec { index, count })
        }
    }

    /// `I`, from 1.
    pub fn index(self) -> u32 {
        self.index
    }

    /// `N`.
    pub fn count(self) -> u32 {
        self.count
    }

    /// Whether unit `unit` is this shard's: `unit % N == I - 1`.
    pub fn owns(self, unit: u64) -> bool {
        unit % u64::from(self.count) == u64::from(self.index - 1)
    }

    /// This shard's units of `0..total`, in order.
    pub fn units(self, total: u64) -> impl Iterator<Item = u64> {
        (u64::from(self.index - 1)..total).step_by(self.count as usize)
    }

    /// How many of `0..total` are this shard's.
    pub fn share(self, total: u64) -> u64 {
        let (n, i) = (u64::from(self.count), u64::from(self.index - 1));
        total / n + u64::from(total % n > i)
    }

    /// The shard that owns `unit` among `count`.
    ///
    /// # Panics
    /// If `count` is 0.
    pub fn owner(unit: u64, count: u32) -> ShardSpec {
        let index = (unit % u64::from(count)) as u32 + 1;
        ShardSpec { index, count }
    }

    /// The part file's name: `part-I-of-N.jsonl`.
    pub fn file_name(self) -> String {
        format!("part-{}-of-{}.jsonl", self.index, self.count)
    }
}

impl fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for ShardSpec {
    type Err = ShardSpecError;

    /// `I/N`, e.g. `2/3`; spaces around either number are allowed.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| ShardSpecError::Form(s.to_string()))?;
        let number = |t: &str| {
            let t = t.trim();
            if t.is_empty() || !t.bytes().all(|b| b.is_ascii_digit()) {
                return Err(ShardSpecError::Number(t.to_string()));
            }
            t.parse::<u32>()
                .map_err(|_| ShardSpecError::Number(t.to_string()))
        };
        ShardSpec::new(number(i)?, number(n)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_print_as_i_of_n() {
        let s: ShardSpec = "2/3".parse().unwrap();
        assert_eq!((s.index(), s.count()), (2, 3));
        assert_eq!(s.to_string(), "2/3");
        assert_eq!(" 1 / 1 ".parse::<ShardSpec>().unwrap().to_string(), "1/1");
        assert_eq!(s.file_name(), "part-2-of-3.jsonl");
    }

    #[test]
    fn bad_shards_are_refused_with_the_reason() {
        let e = |s: &str| s.parse::<ShardSpec>().unwrap_err();
        assert_eq!(e("0/3"), ShardSpecError::Zero);
        assert_eq!(e("4/3"), ShardSpecError::Beyond { index: 4, count: 3 });
        assert_eq!(e("0/0"), ShardSpecError::NoShards);
        assert_eq!(e("1/0"), ShardSpecError::NoShards);
        assert_eq!(e("3"), ShardSpecError::Form("3".into()));
        assert_eq!(e("x"), ShardSpecError::Form("x".into()));
        assert_eq!(e("x/3"), ShardSpecError::Number("x".into()));
        assert_eq!(e("-1/3"), ShardSpecError::Number("-1".into()));
        assert_eq!(e("+1/3"), ShardSpecError::Number("+1".into()));
        assert_eq!(e("1/"), ShardSpecError::Number(String::new()));
        assert_eq!(e("1/2/3"), ShardSpecError::Number("2/3".into()));
        assert_eq!(
            e("1/99999999999"),
            ShardSpecError::Number("99999999999".into())
        );
        assert!(e("4/3").to_string().contains("at most N"));
    }

    #[test]
    fn every_unit_has_exactly_one_owner() {
        for n in 1..=7u32 {
            for total in [0u64, 1, 5, 6, 7, 50] {
                let shards: Vec<ShardSpec> =
                    (1..=n).map(|i| ShardSpec::new(i, n).unwrap()).collect();
                let mut seen = vec![0u32; total as usize];
                for s in &shards {
                    let mine: Vec<u64> = s.units(total).collect();
                    assert_eq!(mine.len() as u64, s.share(total), "{s} of {total}");
                    for k in mine {
                        assert!(s.owns(k));
                        assert_eq!(ShardSpec::owner(k, n), *s);
                        seen[k as usize] += 1;
                    }
                }
                assert!(seen.iter().all(|&c| c == 1), "{n} shards, {total} units");
            }
        }
        // Round-robin: shard 2 of 3 takes 1, 4, 7, ...
        let s = ShardSpec::new(2, 3).unwrap();
        assert_eq!(s.units(10).collect::<Vec<_>>(), [1, 4, 7]);
        assert!(s.owns(4) && !s.owns(5));
    }

    #[test]
    fn a_header_shard_is_checked_when_read() {
        let s: ShardSpec = serde_json::from_str(r#"{"index":2,"count":3}"#).unwrap();
        assert_eq!(s.to_string(), "2/3");
        assert_eq!(
            serde_json::to_string(&s).unwrap(),
            r#"{"index":2,"count":3}"#
        );
        assert!(serde_json::from_str::<ShardSpec>(r#"{"index":0,"count":3}"#).is_err());
        assert!(serde_json::from_str::<ShardSpec>(r#"{"index":4,"count":3}"#).is_err());
    }
}
