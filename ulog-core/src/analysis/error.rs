//! The one error of the analysis functions: an input they cannot analyse, saying why.

use core::fmt;

/// Why a signal could not be analysed.
///
/// ```
/// use ulog_core::analysis::{resample, AnalysisError, ResampleOptions};
///
/// let err = resample(&[0u64], &[1.0f64], &ResampleOptions::default()).unwrap_err();
/// assert_eq!(err, AnalysisError::TooFewSamples { needed: 4, got: 1 });
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum AnalysisError {
    /// Fewer samples than the computation needs.
    TooFewSamples {
        /// The fewest samples accepted.
        needed: usize,
        /// The samples given.
        got: usize,
    },
    /// Two sequences that go together (timestamps and values, setpoint and response)
    /// differ in length.
    LengthMismatch {
        /// The length of the first.
        first: usize,
        /// The length of the second.
        second: usize,
    },
    /// A value is NaN or infinite.
    NotFinite {
        /// Its index.
        index: usize,
    },
    /// A timestamp is not greater than the one before it.
    NotIncreasing {
        /// The index of the timestamp.
        index: usize,
    },
    /// An interval between two samples is far longer than the usual one (a dropout, or
    /// the topic stopped): interpolating across it would invent data.
    Gap {
        /// The index of the sample after the gap.
        index: usize,
        /// The interval before it, µs.
        interval_us: u64,
        /// The median interval, µs.
        median_us: u64,
    },
    /// An option is out of its range.
    InvalidParameter {
        /// The option.
        name: &'static str,
        /// What it must be.
        reason: &'static str,
    },
    /// No window of a step-response analysis had enough setpoint excitation.
    NoExcitation {
        /// The windows looked at.
        windows: usize,
    },
}

impl fmt::Display for AnalysisError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AnalysisError::TooFewSamples { needed, got } => {
                write!(f, "too few samples: {got}, at least {needed} are needed")
            }
            AnalysisError::LengthMismatch { first, second } => write!(
                f,
                "lengths differ: {first} and {second}; give one value per timestamp (or put both signals on one grid)"
            ),
            AnalysisError::NotFinite { index } => write!(
                f,
                "sample {index} is NaN or infinite; cut the signal around it"
            ),
            AnalysisError::NotIncreasing { index } => write!(
                f,
                "timestamp {index} is not after the one before it; sort the rows and drop duplicates"
            ),
            AnalysisError::Gap {
                index,
                interval_us,
                median_us,
            } => write!(
                f,
                "a gap of {interval_us} µs before sample {index} (the median interval is {median_us} µs); analyse the parts on either side, or raise `max_gap`"
            ),
            AnalysisError::InvalidParameter { name, reason } => {
                write!(f, "`{name}` {reason}")
            }
            AnalysisError::NoExcitation { windows } => write!(
                f,
                "none of {windows} windows has enough setpoint excitation; lower `min_excitation` or pick a more active part of the flight"
            ),
        }
    }
}

impl std::error::Error for AnalysisError {}
