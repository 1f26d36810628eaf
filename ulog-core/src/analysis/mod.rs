//! Flight analysis over sampled signals (feature `analysis`): resampling logged rows
//! onto a uniform grid, power spectral densities and their peaks, amplitude spectra,
//! spectrograms, and control-loop step responses with their rise time, overshoot and
//! settling time.
//!
//! The functions take plain slices of `f32` or `f64` samples (and µs timestamps where
//! they resample), so they work however the signal was read: [`ULog::read`],
//! [`Topic::field`], [`load_columns`]. Bad input (too few samples, NaN, timestamps
//! that go back, gaps) is an [`AnalysisError`], never a panic.
//!
//! [`ULog::read`]: crate::ULog::read
//! [`Topic::field`]: crate::Topic::field
//! [`load_columns`]: crate::load_columns
//!
//! ```
//! use ulog_core::analysis::{psd, resample, PsdOptions, ResampleOptions};
//!
//! // Gyro rows logged at about 250 Hz with jitter, a 30 Hz vibration in them.
//! let t: Vec<u64> = (0..2500u64).map(|i| 1_000_000 + i * 4_000 + (i * 7919) % 300).collect();
//! let gyro: Vec<f32> = t
//!     .iter()
//!     .map(|&t| (2.0 * std::f64::consts::PI * 30.0 * t as f64 * 1e-6).sin() as f32)
//!     .collect();
//! let uniform = resample(&t, &gyro, &ResampleOptions::default())?;
//! let spectrum = psd(&uniform.values, uniform.rate_hz, &PsdOptions::default())?;
//! let peak = spectrum.dominant_frequencies(1, 10.0)[0];
//! assert!((peak.frequency_hz - 30.0).abs() <= spectrum.resolution_hz());
//! # Ok::<(), ulog_core::analysis::AnalysisError>(())
//! ```

mod error;
mod fft;
mod flight;
mod resample;
mod spectrogram;
mod spectrum;
mod step_metrics;
mod step_response;
#[cfg(test)]
mod tests;

pub use error::AnalysisError;
pub use flight::{
    analyze, mode_name, AnalyzeOptions, AxisSpectrum, AxisStep, BatterySummary, Diagnostic,
    EventKind, Evidence, EvidenceValue, FlightAnalysis, FlightAnalyzer, FlightStats, GpsQuality,
    ModeSegment, Severity, SignalSpectrogram, Timeline, VibrationSummary,
};
pub use resample::{resample, sample_rate, ResampleOptions, Uniform};
pub use spectrogram::{spectrogram, Spectrogram, SpectrogramOptions};
pub use spectrum::{amplitude_spectrum, psd, Peak, PsdOptions, Spectrum};
pub use step_metrics::{step_metrics, StepMetrics};
pub use step_response::{step_response, StepResponse, StepResponseOptions};
