//! The swarm's result types through JSON without loss, for the part files of a sharded
//! `swarm reproduce` (`pages::reproduction`): a field of a [`Lossless`] type marked
//! `#[serde(with = "crate::json")]` reads back bit for bit what was written.
//!
//! What plain serde with `serde_json` would lose, and what this module does instead:
//!
//! - NaN and the infinities (JSON has no such numbers; `serde_json` writes `null`, which does
//!   not read back as an `f64`, and reads back as `None` in an `Option<f64>`): written as the
//!   strings `"NaN"`, `"inf"` and `"-inf"`. A NaN reads back as [`f64::NAN`] (its payload is
//!   not kept; nothing here tells NaNs apart).
//! - Finite `f64`s are written as the shortest decimal that reads back to the same bits
//!   (`serde_json`'s own writer) and read with its `float_roundtrip` feature, so they come back
//!   exactly (`-0.0` included). An `f32` goes through its exact `f64`.
//! - nalgebra's `Point2<f64>` and `Vector2<f64>` (the crate is built without its serde feature)
//!   are written as `[x, y]`.
//! - [`WaveState`] (a protocol type) is written as its number: 0 inactive, 1 active,
//!   2 refractory.
//!
//! Nothing here changes how a type behaves; it is only how its fields are written and read.

use nalgebra::{Point2, Vector2};
use protocol::WaveState;
use serde::de::{self, DeserializeOwned, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A type whose values go through JSON without loss, by way of [`Lossless::Repr`].
pub trait Lossless: Sized {
    /// How the value is written.
    type Repr: Serialize + DeserializeOwned;
    /// The value as written.
    fn to_repr(&self) -> Self::Repr;
    /// The value back from what was written.
    ///
    /// # Errors
    /// If `r` is no value of this type.
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError>;
}

/// Why [`Lossless::from_repr`] refused what was read: it is no value of the type.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ReprError {
    /// An `f64` that no `f32` is.
    #[error("{0} is no f32")]
    NoF32(f64),
    /// An array of another length.
    #[error("{got} values where {expected} were expected")]
    Length {
        /// The values read.
        got: usize,
        /// The array's length.
        expected: usize,
    },
    /// A number that is no [`WaveState`].
    #[error("{0} is no wave state")]
    WaveState(u8),
}

/// Writes `v` (the `serialize` of `#[serde(with = "crate::json")]`).
///
/// # Errors
/// The serializer's.
pub fn serialize<T: Lossless, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    v.to_repr().serialize(s)
}

/// Reads a `T` (the `deserialize` of `#[serde(with = "crate::json")]`).
///
/// # Errors
/// The deserializer's, or if what was read is no `T`.
pub fn deserialize<'de, T: Lossless, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
    T::from_repr(T::Repr::deserialize(d)?).map_err(de::Error::custom)
}

/// An `f64` as JSON can hold it: a number if finite, else `"NaN"`, `"inf"` or `"-inf"`.
#[derive(Clone, Copy, Debug)]
pub struct Float(f64);

impl Serialize for Float {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0 {
            v if v.is_finite() => s.serialize_f64(v),
            v if v.is_nan() => s.serialize_str("NaN"),
            v if v > 0.0 => s.serialize_str("inf"),
            _ => s.serialize_str("-inf"),
        }
    }
}

impl<'de> Deserialize<'de> for Float {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FloatVisitor)
    }
}

struct FloatVisitor;

impl Visitor<'_> for FloatVisitor {
    type Value = Float;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a number, \"NaN\", \"inf\" or \"-inf\"")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Float, E> {
        Ok(Float(v))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Float, E> {
        Ok(Float(v as f64))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Float, E> {
        Ok(Float(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Float, E> {
        match v {
            "NaN" => Ok(Float(f64::NAN)),
            "inf" => Ok(Float(f64::INFINITY)),
            "-inf" => Ok(Float(f64::NEG_INFINITY)),
            _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
        }
    }
}

impl Lossless for f64 {
    type Repr = Float;
    fn to_repr(&self) -> Float {
        Float(*self)
    }
    fn from_repr(r: Float) -> Result<f64, ReprError> {
        Ok(r.0)
    }
}

impl Lossless for f32 {
    type Repr = Float;
    fn to_repr(&self) -> Float {
        Float(f64::from(*self))
    }
    fn from_repr(r: Float) -> Result<f32, ReprError> {
        let v = r.0 as f32;
        if f64::from(v).to_bits() == r.0.to_bits() || r.0.is_nan() {
            Ok(v)
        } else {
            Err(ReprError::NoF32(r.0))
        }
    }
}

impl<T: Lossless> Lossless for Option<T> {
    type Repr = Option<T::Repr>;
    fn to_repr(&self) -> Self::Repr {
        self.as_ref().map(T::to_repr)
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        r.map(T::from_repr).transpose()
    }
}

impl<T: Lossless> Lossless for Vec<T> {
    type Repr = Vec<T::Repr>;
    fn to_repr(&self) -> Self::Repr {
        self.iter().map(T::to_repr).collect()
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        r.into_iter().map(T::from_repr).collect()
    }
}

impl<A: Lossless, B: Lossless> Lossless for (A, B) {
    type Repr = (A::Repr, B::Repr);
    fn to_repr(&self) -> Self::Repr {
        (self.0.to_repr(), self.1.to_repr())
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        Ok((A::from_repr(r.0)?, B::from_repr(r.1)?))
    }
}

impl<A: Lossless, B: Lossless, C: Lossless> Lossless for (A, B, C) {
    type Repr = (A::Repr, B::Repr, C::Repr);
    fn to_repr(&self) -> Self::Repr {
        (self.0.to_repr(), self.1.to_repr(), self.2.to_repr())
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        Ok((A::from_repr(r.0)?, B::from_repr(r.1)?, C::from_repr(r.2)?))
    }
}

impl<T: Lossless, const N: usize> Lossless for [T; N] {
    type Repr = Vec<T::Repr>;
    fn to_repr(&self) -> Self::Repr {
        self.iter().map(T::to_repr).collect()
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        let n = r.len();
        let v: Vec<T> = r.into_iter().map(T::from_repr).collect::<Result<_, _>>()?;
        v.try_into().map_err(|_| ReprError::Length {
            got: n,
            expected: N,
        })
    }
}

impl Lossless for Point2<f64> {
    type Repr = (Float, Float);
    fn to_repr(&self) -> Self::Repr {
        (Float(self.x), Float(self.y))
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        Ok(Point2::new(r.0.0, r.1.0))
    }
}

impl Lossless for Vector2<f64> {
    type Repr = (Float, Float);
    fn to_repr(&self) -> Self::Repr {
        (Float(self.x), Float(self.y))
    }
    fn from_repr(r: Self::Repr) -> Result<Self, ReprError> {
        Ok(Vector2::new(r.0.0, r.1.0))
    }
}

impl Lossless for WaveState {
    type Repr = u8;
    fn to_repr(&self) -> u8 {
        match self {
            WaveState::Inactive => 0,
            WaveState::Active => 1,
            WaveState::Refractory => 2,
        }
    }
    fn from_repr(r: u8) -> Result<Self, ReprError> {
        match r {
            0 => Ok(WaveState::Inactive),
            1 => Ok(WaveState::Active),
            2 => Ok(WaveState::Refractory),
            _ => Err(ReprError::WaveState(r)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Serialize, Deserialize)]
    struct Sample {
        #[serde(with = "super")]
        xs: Vec<f64>,
        #[serde(with = "super")]
        maybe: Vec<Option<f64>>,
        #[serde(with = "super")]
        narrow: f32,
        #[serde(with = "super")]
        at: Point2<f64>,
        #[serde(with = "super")]
        triples: Vec<(f64, f64, f64)>,
        #[serde(with = "super")]
        states: Vec<Vec<WaveState>>,
    }

    fn bits(xs: &[f64]) -> Vec<u64> {
        xs.iter()
            .map(|x| if x.is_nan() { 1 } else { x.to_bits() })
            .collect()
    }

    #[test]
    fn every_float_reads_back_bit_for_bit() {
        let xs = vec![
            0.1 + 0.2,
            -0.0,
            0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            1.0 / 3.0,
            1e21,
            -123_456_789.123_456_78,
        ];
        let s = Sample {
            xs: xs.clone(),
            maybe: vec![None, Some(f64::NAN), Some(2.5)],
            narrow: 0.1,
            at: Point2::new(-2.5, 1e-17),
            triples: vec![(1.0, f64::NAN, -0.0)],
            states: vec![vec![WaveState::Inactive, WaveState::Refractory]],
        };
        let json = serde_json::to_string(&s).unwrap();
        let back: Sample = serde_json::from_str(&json).unwrap();
        assert_eq!(bits(&back.xs), bits(&xs), "{json}");
        assert!(back.maybe[0].is_none() && back.maybe[1].is_some_and(f64::is_nan));
        assert_eq!(back.maybe[2], Some(2.5));
        assert_eq!(back.narrow.to_bits(), 0.1f32.to_bits());
        assert_eq!(back.at, s.at);
        assert_eq!(back.triples[0].2.to_bits(), (-0.0f64).to_bits());
        assert_eq!(back.states, s.states);
    }

    #[test]
    fn what_is_no_float_is_refused() {
        let bad = r#"{"xs":["nan"],"maybe":[],"narrow":0.1,"at":[0,0],"triples":[],"states":[]}"#;
        assert!(serde_json::from_str::<Sample>(bad).is_err());
        let wide =
            r#"{"xs":[],"maybe":[],"narrow":0.1000000000001,"at":[0,0],"triples":[],"states":[]}"#;
        assert!(serde_json::from_str::<Sample>(wide).is_err());
    }
}
