//! Logged rows onto a uniform time grid: spectra and deconvolution assume one sample
//! every 1/rate seconds, while a log's timestamps jitter with the scheduler.

use core::ops::Range;

use super::error::AnalysisError;

/// The fewest samples [`resample`] and [`sample_rate`] accept: two intervals give a
/// median, a third keeps one jittery interval from setting it alone.
const MIN_SAMPLES: usize = 4;

/// How [`resample`] builds its grid.
///
/// ```
/// let options = ulog_core::analysis::ResampleOptions::default().rate_hz(250.0).max_gap(10.0);
/// # let _ = options;
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ResampleOptions {
    rate_hz: Option<f64>,
    span_us: Option<Range<u64>>,
    max_gap: f64,
}

impl Default for ResampleOptions {
    /// The rate estimated from the timestamps, the whole span, gaps of up to 5 median
    /// intervals bridged.
    fn default() -> ResampleOptions {
        ResampleOptions {
            rate_hz: None,
            span_us: None,
            max_gap: 5.0,
        }
    }
}

impl ResampleOptions {
    /// The grid's rate in Hz, instead of the one [`sample_rate`] estimates (to put two
    /// signals on one grid, give both the same rate and span).
    pub fn rate_hz(mut self, rate_hz: f64) -> ResampleOptions {
        self.rate_hz = Some(rate_hz);
        self
    }

    /// The time span of the grid in log µs, which must lie within the samples' span;
    /// the grid starts at its start and ends at or before its end.
    pub fn span_us(mut self, span_us: Range<u64>) -> ResampleOptions {
        self.span_us = Some(span_us);
        self
    }

    /// The longest interval bridged by interpolation, in median intervals (at least 1);
    /// a longer one is an [`AnalysisError::Gap`].
    pub fn max_gap(mut self, intervals: f64) -> ResampleOptions {
        self.max_gap = intervals;
        self
    }
}

/// A signal sampled at a uniform rate.
#[derive(Debug, Clone, PartialEq)]
pub struct Uniform {
    /// The time of the first sample, log µs (not always a whole microsecond).
    pub start_us: f64,
    /// Samples per second.
    pub rate_hz: f64,
    /// The samples, one every `1 / rate_hz` s.
    pub values: Vec<f64>,
}

impl Uniform {
    /// The time of sample `index`, log µs.
    pub fn time_us(&self, index: usize) -> f64 {
        self.start_us + index as f64 * 1e6 / self.rate_hz
    }
}

/// The sample rate of logged rows in Hz: one over the median interval between
/// timestamps (µs), which a few late or early rows do not move.
///
/// ```
/// // 100 Hz with a late row.
/// let t = [0u64, 10_000, 20_000, 33_000, 40_000, 50_000];
/// assert_eq!(ulog_core::analysis::sample_rate(&t)?, 100.0);
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn sample_rate(timestamps_us: &[u64]) -> Result<f64, AnalysisError> {
    check_timestamps(timestamps_us)?;
    Ok(1e6 / median_interval_us(timestamps_us))
}

/// Linear interpolation of `values` logged at `timestamps_us` (µs, strictly
/// increasing) onto a uniform grid, at the rate [`sample_rate`] estimates unless the
/// options set one.
///
/// Refuses fewer than 4 samples, timestamps that do not increase, values that are not
/// finite, and gaps longer than [`ResampleOptions::max_gap`] median intervals.
///
/// ```
/// use ulog_core::analysis::{resample, ResampleOptions};
///
/// let t = [1_000u64, 2_100, 2_900, 4_000, 5_000, 6_000];
/// let v = [0.0f32, 1.1, 1.9, 3.0, 4.0, 5.0];
/// let uniform = resample(&t, &v, &ResampleOptions::default())?;
/// assert_eq!(uniform.rate_hz, 1000.0);
/// let expected = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
/// assert!(uniform.values.iter().zip(expected).all(|(v, e)| (v - e).abs() < 1e-6));
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn resample<T: Copy + Into<f64>>(
    timestamps_us: &[u64],
    values: &[T],
    options: &ResampleOptions,
) -> Result<Uniform, AnalysisError> {
    if timestamps_us.len() != values.len() {
        return Err(AnalysisError::LengthMismatch {
            first: timestamps_us.len(),
            second: values.len(),
        });
    }
    check_timestamps(timestamps_us)?;
    if let Some(index) = values.iter().position(|v| !(*v).into().is_finite()) {
        return Err(AnalysisError::NotFinite { index });
    }
    // NaN fails the comparison too.
    if options.max_gap.is_nan() || options.max_gap < 1.0 {
        return Err(AnalysisError::InvalidParameter {
            name: "max_gap",
            reason: "must be at least 1 (median interval)",
        });
    }
    let median_us = median_interval_us(timestamps_us);
    let limit = median_us * options.max_gap;
    for (i, pair) in timestamps_us.windows(2).enumerate() {
        let interval = pair[1] - pair[0];
        if interval as f64 > limit {
            return Err(AnalysisError::Gap {
                index: i + 1,
                interval_us: interval,
                median_us: median_us.round() as u64,
            });
        }
    }
    let rate_hz = options.rate_hz.unwrap_or(1e6 / median_us);
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(AnalysisError::InvalidParameter {
            name: "rate_hz",
            reason: "must be finite and positive",
        });
    }
    let first = timestamps_us[0];
    let last = timestamps_us[timestamps_us.len() - 1];
    let span = options.span_us.clone().unwrap_or(first..last);
    if span.start >= span.end || span.start < first || span.end > last {
        return Err(AnalysisError::InvalidParameter {
            name: "span_us",
            reason: "must be a non-empty span within the samples' timestamps",
        });
    }
    let step_us = 1e6 / rate_hz;
    let count = ((span.end - span.start) as f64 / step_us).floor() as usize + 1;
    let mut out = Vec::with_capacity(count);
    // The grid and the rows both go forward, so one cursor serves every grid point.
    let mut j = 0;
    for k in 0..count {
        let t = span.start as f64 + k as f64 * step_us;
        while j + 2 < timestamps_us.len() && (timestamps_us[j + 1] as f64) <= t {
            j += 1;
        }
        let (t0, t1) = (timestamps_us[j] as f64, timestamps_us[j + 1] as f64);
        let (v0, v1) = (values[j].into(), values[j + 1].into());
        let frac = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
        out.push(v0 + frac * (v1 - v0));
    }
    Ok(Uniform {
        start_us: span.start as f64,
        rate_hz,
        values: out,
    })
}

/// Enough timestamps, strictly increasing.
fn check_timestamps(timestamps_us: &[u64]) -> Result<(), AnalysisError> {
    if timestamps_us.len() < MIN_SAMPLES {
        return Err(AnalysisError::TooFewSamples {
            needed: MIN_SAMPLES,
            got: timestamps_us.len(),
        });
    }
    match timestamps_us.windows(2).position(|w| w[1] <= w[0]) {
        Some(i) => Err(AnalysisError::NotIncreasing { index: i + 1 }),
        None => Ok(()),
    }
}

/// The median interval of increasing timestamps (at least 2 intervals), µs.
fn median_interval_us(timestamps_us: &[u64]) -> f64 {
    let mut intervals: Vec<u64> = timestamps_us.windows(2).map(|w| w[1] - w[0]).collect();
    let even = intervals.len() % 2 == 0;
    let mid = intervals.len() / 2;
    let (below, m, _) = intervals.select_nth_unstable(mid);
    let m = *m;
    match below.iter().copied().max() {
        // The mean of the two middle intervals, so that an even count is not biased.
        Some(lower) if even => (lower + m) as f64 / 2.0,
        _ => m as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;
    use std::f64::consts::PI;

    #[test]
    fn jittered_timestamps_recover_a_sine() {
        // 200 Hz rows with ±1 ms of jitter around their slots; a 3 Hz sine of them.
        let mut rng = Rng::new(11);
        let t: Vec<u64> = (0..2000u64)
            .map(|i| 5_000_000 + i * 5_000 + rng.below(2001) as u64 - 1000)
            .collect();
        let f = 3.0;
        let v: Vec<f32> = t
            .iter()
            .map(|&t| (2.0 * PI * f * t as f64 * 1e-6).sin() as f32)
            .collect();
        let u = resample(&t, &v, &ResampleOptions::default()).unwrap();
        assert!((u.rate_hz - 200.0).abs() < 200.0 * 0.01, "{}", u.rate_hz);
        // Linear interpolation of a slow sine over ≤7 ms intervals errs by at most
        // (ωΔt)²/8 of the amplitude.
        let bound = (2.0 * PI * f * 0.007).powi(2) / 8.0 + 1e-6;
        for (k, &x) in u.values.iter().enumerate() {
            let expected = (2.0 * PI * f * u.time_us(k) * 1e-6).sin();
            assert!(
                (x - expected).abs() <= bound,
                "sample {k}: {x} vs {expected}"
            );
        }
    }

    #[test]
    fn a_span_and_rate_put_two_signals_on_one_grid() {
        let a: Vec<u64> = (0..100).map(|i| i * 4_000 + 1_000).collect();
        let b: Vec<u64> = (0..100).map(|i| i * 5_000).collect();
        let ones = vec![1.0f64; 100];
        let options = ResampleOptions::default()
            .rate_hz(250.0)
            .span_us(10_000..300_000);
        let ua = resample(&a, &ones, &options).unwrap();
        let ub = resample(&b, &ones, &options).unwrap();
        assert_eq!(
            (ua.start_us, ua.values.len()),
            (ub.start_us, ub.values.len())
        );
        assert_eq!(ua.values.len(), 73);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let opts = ResampleOptions::default();
        let t = [0u64, 10, 20, 30, 40];
        assert_eq!(
            resample::<f64>(&[], &[], &opts),
            Err(AnalysisError::TooFewSamples { needed: 4, got: 0 })
        );
        assert_eq!(
            resample(&[7], &[1.0f64], &opts),
            Err(AnalysisError::TooFewSamples { needed: 4, got: 1 })
        );
        assert_eq!(
            resample(&t, &[1.0f64; 4], &opts),
            Err(AnalysisError::LengthMismatch {
                first: 5,
                second: 4
            })
        );
        assert_eq!(
            resample(&[0, 10, 10, 20, 30], &[0.0f64; 5], &opts),
            Err(AnalysisError::NotIncreasing { index: 2 })
        );
        assert_eq!(
            resample(&[0, 10, 5, 20, 30], &[0.0f64; 5], &opts),
            Err(AnalysisError::NotIncreasing { index: 2 })
        );
        assert_eq!(
            resample(&t, &[0.0, 1.0, f64::NAN, 0.0, 0.0], &opts),
            Err(AnalysisError::NotFinite { index: 2 })
        );
        assert_eq!(
            resample(&[0, 10, 20, 30, 300], &[0.0f64; 5], &opts),
            Err(AnalysisError::Gap {
                index: 4,
                interval_us: 270,
                median_us: 10
            })
        );
        assert!(matches!(
            resample(&t, &[0.0f64; 5], &opts.clone().rate_hz(f64::NAN)),
            Err(AnalysisError::InvalidParameter {
                name: "rate_hz",
                ..
            })
        ));
        assert!(matches!(
            resample(&t, &[0.0f64; 5], &opts.clone().span_us(0..50)),
            Err(AnalysisError::InvalidParameter {
                name: "span_us",
                ..
            })
        ));
        assert!(matches!(
            resample(&t, &[0.0f64; 5], &opts.clone().max_gap(f64::NAN)),
            Err(AnalysisError::InvalidParameter {
                name: "max_gap",
                ..
            })
        ));
        assert_eq!(
            sample_rate(&[3, 2, 1, 0]),
            Err(AnalysisError::NotIncreasing { index: 1 })
        );
    }
}
