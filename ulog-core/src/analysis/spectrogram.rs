//! Spectra over time (a short-time Fourier transform), for a heatmap of how a
//! signal's tones move through a flight (motor noise rising with throttle).

use super::error::AnalysisError;
use super::fft::{check_rate, chosen_segment_len, finite_values, MIN_SEGMENT};
use super::spectrum::Density;

/// The power below which a spectrogram's cells are clipped, relative to its strongest
/// cell: 120 dB, so that exact zeros (a constant stretch) do not draw as −∞.
const FLOOR_BELOW_MAX: f64 = 1e-12;

/// Power spectral densities of successive windows of a signal, in dB.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrogram {
    /// The centre of each window, s after the first sample.
    pub times_s: Vec<f64>,
    /// The frequency of each bin, Hz.
    pub frequencies: Vec<f64>,
    /// `power_db[t][f]`: 10·log10 of the density ((unit)²/Hz) of window `t` at bin `f`,
    /// clipped 120 dB below the strongest cell.
    pub power_db: Vec<Vec<f64>>,
}

impl Spectrogram {
    /// The frequency of the strongest bin of window `t` (ignoring 0 Hz), if there is
    /// such a window.
    pub fn peak_frequency(&self, t: usize) -> Option<f64> {
        let row = self.power_db.get(t)?;
        let (k, _) = row
            .iter()
            .enumerate()
            .skip(1)
            .max_by(|a, b| a.1.total_cmp(b.1))?;
        self.frequencies.get(k).copied()
    }
}

/// How [`spectrogram`] cuts the signal into windows.
///
/// ```
/// let options = ulog_core::analysis::SpectrogramOptions::default()
///     .segment_len(128)
///     .overlap(0.75);
/// # let _ = options;
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrogramOptions {
    segment_len: Option<usize>,
    overlap: f64,
}

impl Default for SpectrogramOptions {
    /// Windows of the power of two nearest above a quarter second of samples,
    /// overlapping by half.
    fn default() -> SpectrogramOptions {
        SpectrogramOptions {
            segment_len: None,
            overlap: 0.5,
        }
    }
}

impl SpectrogramOptions {
    /// The samples per window (at least 16, at most the signal's length).
    pub fn segment_len(mut self, samples: usize) -> SpectrogramOptions {
        self.segment_len = Some(samples);
        self
    }

    /// The fraction by which successive windows overlap, in `0.0..1.0`.
    pub fn overlap(mut self, fraction: f64) -> SpectrogramOptions {
        self.overlap = fraction;
        self
    }
}

/// The spectrogram of `values` sampled at `rate_hz`: Hann-windowed segments, each with
/// its mean removed, as one-sided power spectral densities in dB (see [`psd`] for the
/// scaling). Refuses fewer than 16 samples and values that are not finite.
///
/// [`psd`]: super::psd
///
/// ```
/// use ulog_core::analysis::{spectrogram, SpectrogramOptions};
///
/// // 10 Hz for 2 s, then 40 Hz for 2 s, at 200 Hz.
/// let x: Vec<f64> = (0..800)
///     .map(|i| {
///         let f = if i < 400 { 10.0 } else { 40.0 };
///         (2.0 * std::f64::consts::PI * f * i as f64 / 200.0).sin()
///     })
///     .collect();
/// let s = spectrogram(&x, 200.0, &SpectrogramOptions::default())?;
/// let first = s.peak_frequency(0).unwrap();
/// let last = s.peak_frequency(s.times_s.len() - 1).unwrap();
/// assert!((first - 10.0).abs() < 4.0 && (last - 40.0).abs() < 4.0);
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn spectrogram<T: Copy + Into<f64>>(
    values: &[T],
    rate_hz: f64,
    options: &SpectrogramOptions,
) -> Result<Spectrogram, AnalysisError> {
    check_rate(rate_hz)?;
    let x = finite_values(values, MIN_SEGMENT)?;
    let seg = chosen_segment_len(options.segment_len, rate_hz, 0.25, x.len())?;
    if !(0.0..1.0).contains(&options.overlap) {
        return Err(AnalysisError::InvalidParameter {
            name: "overlap",
            reason: "must be in 0.0..1.0",
        });
    }
    let step = ((seg as f64 * (1.0 - options.overlap)).round() as usize).max(1);
    let mut density = Density::new(seg, rate_hz);
    let mut times_s = Vec::new();
    let mut rows = Vec::new();
    let mut start = 0;
    while start + seg <= x.len() {
        let mut row = vec![0.0; seg / 2 + 1];
        density.add(&x[start..start + seg], &mut row)?;
        rows.push(row);
        times_s.push((start as f64 + seg as f64 / 2.0) / rate_hz);
        start += step;
    }
    Ok(Spectrogram {
        times_s,
        frequencies: density.frequencies(),
        power_db: to_db(rows),
    })
}

/// Densities as dB, clipped [`FLOOR_BELOW_MAX`] below the strongest cell.
pub(crate) fn to_db(rows: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let max = rows.iter().flatten().copied().fold(0.0f64, f64::max);
    let floor = (max * FLOOR_BELOW_MAX).max(f64::MIN_POSITIVE);
    rows.into_iter()
        .map(|row| {
            row.into_iter()
                .map(|p| 10.0 * p.max(floor).log10())
                .collect()
        })
        .collect()
}
