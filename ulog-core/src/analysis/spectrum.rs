//! Spectra of a uniformly sampled signal: the power spectral density by Welch's
//! method, the amplitude spectrum, and their strongest peaks.

use super::error::AnalysisError;
use super::fft::{check_rate, chosen_segment_len, finite_values, hann, median, Fft, MIN_SEGMENT};

/// A one-sided spectrum: `values[i]` at `frequencies[i]` Hz, from 0 to the Nyquist
/// frequency in even steps. The unit of the values is that of the function that made
/// it ([`psd`]: (unit)²/Hz; [`amplitude_spectrum`]: unit).
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// The frequency of each bin, Hz.
    pub frequencies: Vec<f64>,
    /// The value of each bin.
    pub values: Vec<f64>,
}

/// A peak of a [`Spectrum`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// The frequency of its bin, Hz (the bin width is the error).
    pub frequency_hz: f64,
    /// The spectrum's value there, in the spectrum's unit.
    pub value: f64,
}

impl Spectrum {
    /// The width of a bin, Hz.
    pub fn resolution_hz(&self) -> f64 {
        match self.frequencies.as_slice() {
            [_, second, ..] => *second,
            _ => 0.0,
        }
    }

    /// The sum of the values times the bin width: for a [`psd`], the variance of the
    /// signal, (unit)².
    pub fn integral(&self) -> f64 {
        self.values.iter().sum::<f64>() * self.resolution_hz()
    }

    /// The `count` strongest peaks, strongest first: bins greater than the bin below
    /// and not less than the bin above (the end bins never qualify), and more than
    /// `factor` × the median of all values, so that bumps of the noise floor are not
    /// reported.
    ///
    /// ```
    /// use ulog_core::analysis::Spectrum;
    ///
    /// let s = Spectrum {
    ///     frequencies: vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
    ///     values: vec![9.0, 1.0, 8.0, 1.0, 1.5, 1.0, 1.0],
    /// };
    /// let peaks = s.dominant_frequencies(3, 3.0);
    /// assert_eq!(peaks.len(), 1); // 1.5 at 4 Hz is below 3 × the median (1.0)
    /// assert_eq!((peaks[0].frequency_hz, peaks[0].value), (2.0, 8.0));
    /// ```
    pub fn dominant_frequencies(&self, count: usize, factor: f64) -> Vec<Peak> {
        let floor = median(&self.values) * factor;
        let v = &self.values;
        let mut peaks: Vec<Peak> = (1..v.len().saturating_sub(1))
            .filter(|&i| v[i] > v[i - 1] && v[i] >= v[i + 1] && v[i] > floor)
            .map(|i| Peak {
                frequency_hz: self.frequencies[i],
                value: v[i],
            })
            .collect();
        peaks.sort_by(|a, b| b.value.total_cmp(&a.value));
        peaks.truncate(count);
        peaks
    }
}

/// How [`psd`] splits the signal.
///
/// ```
/// let options = ulog_core::analysis::PsdOptions::default().segment_len(512);
/// # let _ = options;
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PsdOptions {
    segment_len: Option<usize>,
}

impl PsdOptions {
    /// The samples per segment (at least 16, at most the signal's length), instead of
    /// the power of two nearest above one second of samples (capped at half the
    /// signal). Longer segments resolve finer, shorter ones average more.
    pub fn segment_len(mut self, samples: usize) -> PsdOptions {
        self.segment_len = Some(samples);
        self
    }
}

/// The one-sided power spectral density of `values` sampled at `rate_hz`, by Welch's
/// method: Hann-windowed segments overlapping by half, each with its mean removed,
/// their periodograms averaged.
///
/// Density scaling: the values are (unit)²/Hz, and their [`Spectrum::integral`] is the
/// variance of the signal (the power of its mean, removed per segment, is not
/// counted). Refuses fewer than 16 samples and values that are not finite.
///
/// ```
/// use ulog_core::analysis::{psd, PsdOptions};
///
/// // A 20 Hz sine of amplitude 2 sampled at 250 Hz for 8 s: variance 2²/2.
/// let x: Vec<f64> = (0..2000)
///     .map(|i| 2.0 * (2.0 * std::f64::consts::PI * 20.0 * i as f64 / 250.0).sin())
///     .collect();
/// let spectrum = psd(&x, 250.0, &PsdOptions::default())?;
/// assert!((spectrum.integral() - 2.0).abs() < 0.02);
/// let peak = spectrum.dominant_frequencies(1, 10.0)[0];
/// assert!((peak.frequency_hz - 20.0).abs() <= spectrum.resolution_hz());
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn psd<T: Copy + Into<f64>>(
    values: &[T],
    rate_hz: f64,
    options: &PsdOptions,
) -> Result<Spectrum, AnalysisError> {
    check_rate(rate_hz)?;
    let x = finite_values(values, MIN_SEGMENT)?;
    let seg = chosen_segment_len(options.segment_len, rate_hz, 1.0, x.len())?;
    let mut density = Density::new(seg, rate_hz);
    let step = seg - seg / 2;
    let mut sum = vec![0.0; seg / 2 + 1];
    let mut segments = 0usize;
    let mut start = 0;
    while start + seg <= x.len() {
        density.add(&x[start..start + seg], &mut sum)?;
        segments += 1;
        start += step;
    }
    sum.iter_mut().for_each(|p| *p /= segments as f64);
    Ok(Spectrum {
        frequencies: density.frequencies(),
        values: sum,
    })
}

/// The periodogram of one segment with density scaling, shared by [`psd`] and the
/// spectrogram.
pub(crate) struct Density {
    fft: Fft,
    window: Vec<f64>,
    rate_hz: f64,
    /// 1 / (rate × Σw²): the scale that makes the one-sided sum × bin width equal the
    /// mean square of the windowed segment per unit window power.
    scale: f64,
}

impl Density {
    pub(crate) fn new(seg: usize, rate_hz: f64) -> Density {
        let window = hann(seg);
        let power: f64 = window.iter().map(|w| w * w).sum();
        Density {
            fft: Fft::new(seg),
            scale: 1.0 / (rate_hz * power),
            window,
            rate_hz,
        }
    }

    pub(crate) fn frequencies(&self) -> Vec<f64> {
        let n = self.window.len();
        (0..n / 2 + 1)
            .map(|k| k as f64 * self.rate_hz / n as f64)
            .collect()
    }

    /// Adds the density of `segment` (as long as the window) to `out`.
    pub(crate) fn add(&mut self, segment: &[f64], out: &mut [f64]) -> Result<(), AnalysisError> {
        let n = self.window.len();
        let bins = self.fft.forward(segment, &self.window, true)?;
        for (k, (o, b)) in out.iter_mut().zip(bins).enumerate() {
            // One-sided: every bin but DC and (for even n) Nyquist stands for its
            // negative-frequency twin too.
            let twice = k != 0 && !(n % 2 == 0 && k == n / 2);
            let factor = if twice { 2.0 } else { 1.0 };
            *o += b.norm_sqr() * self.scale * factor;
        }
        Ok(())
    }
}

/// The one-sided amplitude spectrum of the whole of `values` sampled at `rate_hz`
/// (for actuator controls and other signals whose tones matter in their own unit).
///
/// The signal's mean is removed and the rest Hann-windowed, and the bins are scaled by
/// the window's coherent gain, so that a sine of amplitude A whose frequency falls on
/// a bin reads A there (between two bins, the Hann window reads up to 15 % less). The
/// 0 Hz bin holds the magnitude of the mean. Bins are `rate_hz / len` apart. Refuses
/// fewer than 16 samples and values that are not finite.
///
/// ```
/// use ulog_core::analysis::amplitude_spectrum;
///
/// // 0.5 + 0.25·sin(2π·10 t) at 100 Hz for 2 s: 10 Hz falls on bin 20.
/// let x: Vec<f32> = (0..200)
///     .map(|i| 0.5 + 0.25 * (2.0 * std::f32::consts::PI * 10.0 * i as f32 / 100.0).sin())
///     .collect();
/// let s = amplitude_spectrum(&x, 100.0)?;
/// assert_eq!(s.frequencies[20], 10.0);
/// assert!((s.values[20] - 0.25).abs() < 1e-4);
/// assert!((s.values[0] - 0.5).abs() < 1e-6);
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn amplitude_spectrum<T: Copy + Into<f64>>(
    values: &[T],
    rate_hz: f64,
) -> Result<Spectrum, AnalysisError> {
    check_rate(rate_hz)?;
    let x = finite_values(values, MIN_SEGMENT)?;
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let window = hann(n);
    let gain: f64 = window.iter().sum();
    let mut fft = Fft::new(n);
    let bins = fft.forward(&x, &window, true)?;
    let mut amplitudes: Vec<f64> = bins
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let twice = k != 0 && !(n % 2 == 0 && k == n / 2);
            b.norm() * if twice { 2.0 } else { 1.0 } / gain
        })
        .collect();
    amplitudes[0] = mean.abs();
    Ok(Spectrum {
        frequencies: (0..amplitudes.len())
            .map(|k| k as f64 * rate_hz / n as f64)
            .collect(),
        values: amplitudes,
    })
}
