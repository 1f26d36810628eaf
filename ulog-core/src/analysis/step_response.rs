//! The step response of a control loop estimated from flight data, by deconvolving the
//! measured response with the setpoint (the method of PID-Analyzer, which PX4's Flight
//! Review uses for its rate-controller plots).
//!
//! Per window of the flight, the loop's impulse response is the regularised (Wiener)
//! quotient H = Y·conj(X) / (|X|² + N(f)) of the spectra of the response Y and the
//! setpoint X; its running sum is the step response. Averaged over the windows whose
//! setpoint moves enough, it shows how the loop answers a unit step of its setpoint.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner};

use super::error::AnalysisError;
use super::fft::{check_rate, finite_values, hann, Fft};
use super::step_metrics::{step_metrics, StepMetrics};

/// How [`step_response`] windows and regularises.
///
/// ```
/// use ulog_core::analysis::StepResponseOptions;
///
/// // PX4 rate setpoints are in rad/s: skip windows that move less than 0.35 rad/s.
/// let options = StepResponseOptions::default().min_excitation(0.35).cutoff_hz(None);
/// # let _ = options;
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct StepResponseOptions {
    window_s: f64,
    overlap: f64,
    response_s: f64,
    min_excitation: f64,
    regularisation: f64,
    cutoff_hz: Option<f64>,
}

impl Default for StepResponseOptions {
    /// Windows of 1 s overlapping by half, responses of 0.5 s, every window whose
    /// setpoint is not constant, regularisation 1e-4, cutoff 25 Hz (PID-Analyzer's
    /// window, response length and cutoff).
    fn default() -> StepResponseOptions {
        StepResponseOptions {
            window_s: 1.0,
            overlap: 0.5,
            response_s: 0.5,
            min_excitation: 0.0,
            regularisation: 1e-4,
            cutoff_hz: Some(25.0),
        }
    }
}

impl StepResponseOptions {
    /// The length of a window, s: several times the loop's settling time.
    pub fn window_s(mut self, seconds: f64) -> StepResponseOptions {
        self.window_s = seconds;
        self
    }

    /// The fraction by which successive windows overlap, in `0.0..1.0`.
    pub fn overlap(mut self, fraction: f64) -> StepResponseOptions {
        self.overlap = fraction;
        self
    }

    /// The length of the step response, s (at most the window's).
    pub fn response_s(mut self, seconds: f64) -> StepResponseOptions {
        self.response_s = seconds;
        self
    }

    /// The least peak-to-peak change of the setpoint within a window (in its unit) for
    /// the window to count: a still setpoint excites nothing to measure, and its
    /// windows would average noise into the response.
    pub fn min_excitation(mut self, peak_to_peak: f64) -> StepResponseOptions {
        self.min_excitation = peak_to_peak;
        self
    }

    /// The noise-to-signal power assumed, relative to the setpoint's strongest bin
    /// (positive): larger is smoother and more biased towards zero where the setpoint
    /// has little power.
    pub fn regularisation(mut self, relative: f64) -> StepResponseOptions {
        self.regularisation = relative;
        self
    }

    /// The frequency above which the assumed noise grows as exp((f / cutoff)²), so that
    /// sensor noise above the loop's bandwidth does not enter the response smoothly
    /// (no ringing of a hard cut); `None` keeps it flat.
    pub fn cutoff_hz(mut self, cutoff: Option<f64>) -> StepResponseOptions {
        self.cutoff_hz = cutoff;
        self
    }
}

/// The estimated step response of a loop.
#[derive(Debug, Clone, PartialEq)]
pub struct StepResponse {
    /// The time of each sample after the step, s (from 0, one per sample).
    pub time_s: Vec<f64>,
    /// The mean of the windows' step responses: the response to a unit step.
    pub mean: Vec<f64>,
    /// The step response of each window counted (for a histogram of their spread).
    pub windows: Vec<Vec<f64>>,
    /// The windows looked at, counted or not.
    pub windows_total: usize,
}

impl StepResponse {
    /// The rise time, overshoot, settling time and peak of the mean response.
    pub fn metrics(&self) -> Option<StepMetrics> {
        step_metrics(&self.time_s, &self.mean)
    }
}

/// The step response of the loop that turns `setpoint` into `response`, both sampled
/// at `rate_hz` on one grid (see [`resample`](super::resample) to put them there).
///
/// Refuses signals of different lengths, non-finite values, signals shorter than one
/// window, and (as [`AnalysisError::NoExcitation`]) a flight in which no window's
/// setpoint moves by [`StepResponseOptions::min_excitation`].
///
/// ```
/// use ulog_core::analysis::{step_response, StepResponseOptions};
///
/// // A loop that follows its setpoint one sample late, at 100 Hz.
/// let setpoint: Vec<f64> = (0..1000).map(|i| if (i / 37) % 2 == 0 { 1.0 } else { -1.0 }).collect();
/// let mut response = vec![0.0; 1000];
/// response[1..].copy_from_slice(&setpoint[..999]);
/// let step = step_response(&setpoint, &response, 100.0, &StepResponseOptions::default())?;
/// // 1 s windows every 0.5 s, each giving 0.5 s (50 samples) of response.
/// assert_eq!((step.windows_total, step.windows.len(), step.mean.len()), (19, 19, 50));
/// # Ok::<(), ulog_core::analysis::AnalysisError>(())
/// ```
pub fn step_response<S: Copy + Into<f64>, R: Copy + Into<f64>>(
    setpoint: &[S],
    response: &[R],
    rate_hz: f64,
    options: &StepResponseOptions,
) -> Result<StepResponse, AnalysisError> {
    check_rate(rate_hz)?;
    if setpoint.len() != response.len() {
        return Err(AnalysisError::LengthMismatch {
            first: setpoint.len(),
            second: response.len(),
        });
    }
    let o = options;
    let invalid = |name, reason| Err(AnalysisError::InvalidParameter { name, reason });
    if !(0.0..1.0).contains(&o.overlap) {
        return invalid("overlap", "must be in 0.0..1.0");
    }
    if !(o.regularisation > 0.0 && o.regularisation.is_finite()) {
        return invalid("regularisation", "must be finite and positive");
    }
    if o.min_excitation.is_nan() || o.min_excitation < 0.0 {
        return invalid("min_excitation", "must be zero or more");
    }
    if matches!(o.cutoff_hz, Some(c) if !(c > 0.0 && c.is_finite())) {
        return invalid("cutoff_hz", "must be finite and positive");
    }
    let window_len = (o.window_s * rate_hz).round();
    let response_len = (o.response_s * rate_hz).round();
    if !(window_len >= 4.0 && window_len.is_finite()) {
        return invalid("window_s", "must span at least 4 samples");
    }
    if !(response_len >= 2.0 && response_len <= window_len) {
        return invalid(
            "response_s",
            "must span at least 2 samples and be at most `window_s`",
        );
    }
    let (window_len, response_len) = (window_len as usize, response_len as usize);
    let sp = finite_values(setpoint, window_len)?;
    let out = finite_values(response, window_len)?;

    let step = ((window_len as f64 * (1.0 - o.overlap)).round() as usize).max(1);
    let mut deconvolver = Deconvolver::new(window_len, response_len, rate_hz, o);
    let mut windows = Vec::new();
    let mut windows_total = 0;
    let mut start = 0;
    while start + window_len <= sp.len() {
        windows_total += 1;
        let x = &sp[start..start + window_len];
        let y = &out[start..start + window_len];
        start += step;
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        // A constant window (`hi == lo`) never counts, even with no threshold.
        if hi - lo <= o.min_excitation {
            continue;
        }
        if let Some(s) = deconvolver.step(x, y)? {
            windows.push(s);
        }
    }
    if windows.is_empty() {
        return Err(AnalysisError::NoExcitation {
            windows: windows_total,
        });
    }
    let mut mean = vec![0.0; response_len];
    for w in &windows {
        for (m, v) in mean.iter_mut().zip(w) {
            *m += v;
        }
    }
    mean.iter_mut().for_each(|m| *m /= windows.len() as f64);
    Ok(StepResponse {
        time_s: (0..response_len).map(|k| k as f64 / rate_hz).collect(),
        mean,
        windows,
        windows_total,
    })
}

/// The FFTs and buffers of one window length, reused for every window.
struct Deconvolver {
    forward: Fft,
    inverse: Arc<dyn ComplexToReal<f64>>,
    window: Vec<f64>,
    /// The assumed noise power at each bin, relative to the setpoint's strongest.
    noise_shape: Vec<f64>,
    response_len: usize,
    centred: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    impulse: Vec<f64>,
    scratch: Vec<Complex<f64>>,
}

impl Deconvolver {
    fn new(
        window_len: usize,
        response_len: usize,
        rate_hz: f64,
        o: &StepResponseOptions,
    ) -> Deconvolver {
        // Zero-padded past window + response so that the circular convolution of the
        // FFT does not wrap the end of a window's response onto its start.
        let fft_len = (window_len + response_len).next_power_of_two();
        let inverse = RealFftPlanner::<f64>::new().plan_fft_inverse(fft_len);
        let noise_shape = (0..fft_len / 2 + 1)
            .map(|k| {
                let f = k as f64 * rate_hz / fft_len as f64;
                let rise = o
                    .cutoff_hz
                    .map_or(1.0, |c| (f / c).powi(2).min(700.0).exp());
                o.regularisation * rise
            })
            .collect();
        Deconvolver {
            forward: Fft::new(fft_len),
            window: hann(window_len),
            noise_shape,
            response_len,
            centred: Vec::with_capacity(window_len),
            spectrum: inverse.make_input_vec(),
            impulse: inverse.make_output_vec(),
            scratch: inverse.make_scratch_vec(),
            inverse,
        }
    }

    /// The step response of one window (`None` when its setpoint has no power).
    fn step(&mut self, x: &[f64], y: &[f64]) -> Result<Option<Vec<f64>>, AnalysisError> {
        // Both signals lose the setpoint's mean: the same offset on both sides keeps
        // their relation, and the regularisation, relative to the strongest bin, then
        // scales with how the setpoint moves rather than where it sits.
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        self.centred.clear();
        self.centred.extend(x.iter().map(|v| v - mean));
        let sx: Vec<Complex<f64>> = self
            .forward
            .forward(&self.centred, &self.window, false)?
            .to_vec();
        self.centred.clear();
        self.centred.extend(y.iter().map(|v| v - mean));
        let sy = self.forward.forward(&self.centred, &self.window, false)?;
        let strongest = sx.iter().map(|c| c.norm_sqr()).fold(0.0, f64::max);
        if !(strongest > 0.0 && strongest.is_finite()) {
            return Ok(None);
        }
        for (((h, x), y), shape) in self
            .spectrum
            .iter_mut()
            .zip(&sx)
            .zip(sy)
            .zip(&self.noise_shape)
        {
            *h = y * x.conj() / (x.norm_sqr() + shape * strongest);
        }
        // The ends of a real signal's spectrum are real; rounding must not make the
        // inverse refuse them.
        if let Some(first) = self.spectrum.first_mut() {
            first.im = 0.0;
        }
        if let Some(last) = self.spectrum.last_mut() {
            last.im = 0.0;
        }
        self.inverse
            .process_with_scratch(&mut self.spectrum, &mut self.impulse, &mut self.scratch)
            .map_err(|_| AnalysisError::InvalidParameter {
                name: "window_s",
                reason: "gives a length the inverse FFT refused",
            })?;
        // realfft's inverse is unnormalised: it returns n × the impulse response.
        let scale = 1.0 / self.impulse.len() as f64;
        let mut sum = 0.0;
        let step: Vec<f64> = self.impulse[..self.response_len]
            .iter()
            .map(|h| {
                sum += h * scale;
                sum
            })
            .collect();
        Ok(Some(step))
    }
}
