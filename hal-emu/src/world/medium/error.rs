//! Why the medium's parameters make no sense ([`MediumError`]).

/// Why [`MediumParams::validate`](super::MediumParams::validate) refused the medium's
/// parameters.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MediumError {
    /// A bitrate or bits per byte of zero.
    #[error("the bitrate and bits per byte must be positive")]
    Rate,
    /// A range that is no positive number.
    #[error("the range must be a positive number of metres, not {0}")]
    Range(f64),
    /// A probability out of [0, 1].
    #[error("the {name} must be a probability in [0, 1], not {value}")]
    Probability {
        /// Which one (`loss`, `byte error rate`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
}
