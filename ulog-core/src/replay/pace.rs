//! [`Pace`]: how fast a player releases items, and the rate it refuses.

/// How fast a [`Player`](super::Player) releases items.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Pace {
    /// Each item as soon as it is polled for.
    #[default]
    AsFastAsPossible,
    /// On the log's clock × this rate (1: real time; 2: twice as fast); a positive,
    /// finite number.
    Rate(f64),
}

impl Pace {
    /// The pace of log time × `rate`, if `rate` is a positive, finite number.
    ///
    /// ```
    /// use ulog_core::replay::Pace;
    /// assert_eq!(Pace::rate(0.5), Ok(Pace::Rate(0.5)));
    /// assert!(Pace::rate(0.0).is_err());
    /// assert_eq!(Pace::rate(-2.0).unwrap_err().to_string(),
    ///            "rate -2: log time × rate must be a positive, finite number");
    /// ```
    pub fn rate(rate: f64) -> Result<Pace, InvalidRate> {
        if rate > 0.0 && rate.is_finite() {
            Ok(Pace::Rate(rate))
        } else {
            Err(InvalidRate(rate))
        }
    }

    /// The pace itself, or the error of a rate [`Pace::rate`] refuses.
    pub(super) fn checked(self) -> Result<Pace, InvalidRate> {
        match self {
            Pace::Rate(r) => Pace::rate(r),
            fast => Ok(fast),
        }
    }
}

/// A rate that is not a positive, finite number ([`Pace::rate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InvalidRate(pub f64);

impl core::fmt::Display for InvalidRate {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "rate {}: log time × rate must be a positive, finite number",
            self.0
        )
    }
}

impl std::error::Error for InvalidRate {}
