//! What the spectral functions share: the Hann window, the choice of segment length,
//! checks of their input, and a real FFT planned once and run on many segments.

use std::f64::consts::PI;
use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

use super::error::AnalysisError;

/// The shortest segment of a spectrum: shorter ones resolve too little to be useful.
pub(crate) const MIN_SEGMENT: usize = 16;

/// The periodic Hann window of length `n` (the DFT-even form, as Welch's method and
/// scipy's `get_window("hann")` use: the segments tile without a doubled zero).
pub(crate) fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / n as f64).cos())
        .collect()
}

/// The power of two nearest above `rate_hz × seconds` (so that a segment spans about
/// `seconds`), at least [`MIN_SEGMENT`], and no longer than half of `len` rounded down
/// to a power of two, so that a short signal still has several segments to average.
pub(crate) fn segment_len(rate_hz: f64, seconds: f64, len: usize) -> usize {
    let target = (rate_hz * seconds).ceil().max(1.0) as usize;
    let wanted = target.next_power_of_two();
    let cap = prev_power_of_two(len / 2);
    wanted.min(cap).max(MIN_SEGMENT)
}

/// The segment length asked (`Some`: at least [`MIN_SEGMENT`], at most `len`), or
/// [`segment_len`] of `seconds` by default: the one rule of every windowed transform.
pub(crate) fn chosen_segment_len(
    asked: Option<usize>,
    rate_hz: f64,
    seconds: f64,
    len: usize,
) -> Result<usize, AnalysisError> {
    match asked {
        Some(n) if (MIN_SEGMENT..=len).contains(&n) => Ok(n),
        Some(_) => Err(AnalysisError::InvalidParameter {
            name: "segment_len",
            reason: "must be at least 16 and at most the number of samples",
        }),
        None => Ok(segment_len(rate_hz, seconds, len)),
    }
}

fn prev_power_of_two(n: usize) -> usize {
    if n == 0 {
        0
    } else {
        1 << (usize::BITS - 1 - n.leading_zeros())
    }
}

/// Values as `f64`, refusing too few and any that are not finite.
pub(crate) fn finite_values<T: Copy + Into<f64>>(
    values: &[T],
    needed: usize,
) -> Result<Vec<f64>, AnalysisError> {
    if values.len() < needed {
        return Err(AnalysisError::TooFewSamples {
            needed,
            got: values.len(),
        });
    }
    let mut out = Vec::with_capacity(values.len());
    for (index, v) in values.iter().enumerate() {
        let v: f64 = (*v).into();
        if !v.is_finite() {
            return Err(AnalysisError::NotFinite { index });
        }
        out.push(v);
    }
    Ok(out)
}

/// A sample rate that is finite and positive.
pub(crate) fn check_rate(rate_hz: f64) -> Result<(), AnalysisError> {
    if rate_hz.is_finite() && rate_hz > 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::InvalidParameter {
            name: "rate_hz",
            reason: "must be finite and positive",
        })
    }
}

/// A forward real FFT of one length with its buffers, reused for every segment.
pub(crate) struct Fft {
    plan: Arc<dyn RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Fft {
    pub(crate) fn new(len: usize) -> Fft {
        let plan = RealFftPlanner::<f64>::new().plan_fft_forward(len);
        Fft {
            input: plan.make_input_vec(),
            output: plan.make_output_vec(),
            scratch: plan.make_scratch_vec(),
            plan,
        }
    }

    /// The `len / 2 + 1` bins of `segment × window`, the segment's mean removed first
    /// when `detrend` (the "constant" detrend of Welch's method); zero-padded when
    /// `segment` is shorter than the FFT.
    pub(crate) fn forward(
        &mut self,
        segment: &[f64],
        window: &[f64],
        detrend: bool,
    ) -> Result<&[Complex<f64>], AnalysisError> {
        let mean = if detrend && !segment.is_empty() {
            segment.iter().sum::<f64>() / segment.len() as f64
        } else {
            0.0
        };
        self.input.iter_mut().for_each(|x| *x = 0.0);
        for ((x, &s), &w) in self.input.iter_mut().zip(segment).zip(window) {
            *x = (s - mean) * w;
        }
        self.plan
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .map_err(|_| AnalysisError::InvalidParameter {
                name: "segment length",
                reason: "does not fit the FFT planned for it",
            })?;
        Ok(&self.output)
    }
}

/// The median of finite values (0 when there are none).
pub(crate) fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    *m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_lengths_follow_the_rate_and_the_length() {
        // About a second at 250 Hz, unless the signal is short.
        assert_eq!(segment_len(250.0, 1.0, 100_000), 256);
        assert_eq!(segment_len(250.0, 1.0, 300), 128);
        assert_eq!(segment_len(250.0, 1.0, 20), MIN_SEGMENT);
        assert_eq!(segment_len(1000.0, 0.25, 100_000), 256);
    }

    #[test]
    fn hann_is_periodic() {
        let w = hann(4);
        assert_eq!(w[0], 0.0);
        assert!((w[1] - 0.5).abs() < 1e-15 && (w[2] - 1.0).abs() < 1e-15);
    }
}
