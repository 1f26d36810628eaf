//! The spectra of the raw IMU while armed, by Welch's method in one pass: rows are
//! interpolated onto a uniform grid as they come and each full segment is
//! transformed and summed, so the pass holds one segment per signal, not the signal.

use crate::analysis::fft::segment_len;
use crate::analysis::spectrum::Density;
use crate::analysis::{sample_rate, Peak, Spectrum};

/// Rows whose median interval sets the grid's rate.
const RATE_ROWS: usize = 65;
/// An interval this many times the grid's step breaks the signal (a dropout or a
/// disarmed stretch): interpolation does not bridge it.
const MAX_GAP_STEPS: f64 = 5.0;
/// Peaks below this frequency are the vehicle's motion, not vibration.
const MIN_VIBRATION_HZ: f64 = 5.0;
/// A peak stands this many times above the spectrum's median.
const PEAK_FACTOR: f64 = 5.0;
/// Dominant frequencies kept per signal.
const PEAKS: usize = 3;

/// The spectrum of one axis of one IMU signal.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct AxisSpectrum {
    /// `gyro_rad[0]` … `accelerometer_m_s2[2]` (`sensor_combined`'s fields).
    pub signal: String,
    /// The grid's rate, Hz.
    pub rate_hz: f64,
    /// Segments averaged (each about 1 s, overlapping by half).
    pub segments: usize,
    /// The power spectral density (unit² / Hz).
    pub psd: Spectrum,
    /// The strongest peaks at or above 5 Hz, strongest first.
    pub dominant: Vec<Peak>,
}

/// Three axes of one signal, as rows come.
pub(super) struct Welch {
    name: &'static str,
    /// Rows before the rate is known.
    warmup: Vec<(u64, [f32; 3])>,
    grid: Option<Grid>,
}

struct Grid {
    rate_hz: f64,
    step_us: f64,
    seg: usize,
    density: Density,
    sums: [Vec<f64>; 3],
    segments: usize,
    /// The samples not yet in a full segment.
    buf: Vec<[f64; 3]>,
    /// The last row, and the next grid time after it.
    prev: Option<(u64, [f32; 3])>,
    next_us: f64,
}

impl Welch {
    pub(super) fn new(name: &'static str) -> Welch {
        Welch {
            name,
            warmup: Vec::new(),
            grid: None,
        }
    }

    /// A row while armed.
    pub(super) fn push(&mut self, time: u64, v: [f32; 3]) {
        if !v.iter().all(|x| x.is_finite()) {
            self.gap();
            return;
        }
        match &mut self.grid {
            Some(g) => g.push(time, v),
            None => {
                if self.warmup.last().is_some_and(|(t, _)| time <= *t) {
                    return;
                }
                self.warmup.push((time, v));
                if self.warmup.len() == RATE_ROWS {
                    let times: Vec<u64> = self.warmup.iter().map(|(t, _)| *t).collect();
                    let Ok(rate_hz) = sample_rate(&times) else {
                        self.warmup.clear();
                        return;
                    };
                    let seg = segment_len(rate_hz, 1.0, usize::MAX);
                    let mut g = Grid {
                        rate_hz,
                        step_us: 1e6 / rate_hz,
                        seg,
                        density: Density::new(seg, rate_hz),
                        sums: std::array::from_fn(|_| vec![0.0; seg / 2 + 1]),
                        segments: 0,
                        buf: Vec::with_capacity(seg),
                        prev: None,
                        next_us: 0.0,
                    };
                    for (t, v) in self.warmup.drain(..) {
                        g.push(t, v);
                    }
                    self.grid = Some(g);
                }
            }
        }
    }

    /// The signal stops (disarmed): the next row starts a new stretch.
    pub(super) fn gap(&mut self) {
        match &mut self.grid {
            Some(g) => g.restart(),
            None => self.warmup.clear(),
        }
    }

    /// The three axes' spectra; none when no segment was complete.
    pub(super) fn finish(self) -> Vec<AxisSpectrum> {
        let Some(g) = self.grid else {
            return Vec::new();
        };
        if g.segments == 0 {
            return Vec::new();
        }
        let frequencies = g.density.frequencies();
        g.sums
            .into_iter()
            .enumerate()
            .map(|(axis, sum)| {
                let values = sum.iter().map(|p| p / g.segments as f64).collect();
                let psd = Spectrum {
                    frequencies: frequencies.clone(),
                    values,
                };
                let dominant = psd
                    .dominant_frequencies(usize::MAX, PEAK_FACTOR)
                    .into_iter()
                    .filter(|p| p.frequency_hz >= MIN_VIBRATION_HZ)
                    .take(PEAKS)
                    .collect();
                AxisSpectrum {
                    signal: format!("{}[{axis}]", self.name),
                    rate_hz: g.rate_hz,
                    segments: g.segments,
                    psd,
                    dominant,
                }
            })
            .collect()
    }
}

impl Grid {
    fn restart(&mut self) {
        self.buf.clear();
        self.prev = None;
    }

    fn push(&mut self, time: u64, v: [f32; 3]) {
        let Some((t0, v0)) = self.prev else {
            self.prev = Some((time, v));
            self.next_us = time as f64;
            return;
        };
        if time <= t0 {
            return;
        }
        if (time - t0) as f64 > MAX_GAP_STEPS * self.step_us {
            self.restart();
            self.prev = Some((time, v));
            self.next_us = time as f64;
            return;
        }
        let span = (time - t0) as f64;
        while self.next_us <= time as f64 {
            let f = (self.next_us - t0 as f64) / span;
            let sample = std::array::from_fn(|i| {
                f64::from(v0[i]) + (f64::from(v[i]) - f64::from(v0[i])) * f
            });
            self.buf.push(sample);
            self.next_us += self.step_us;
            if self.buf.len() == self.seg {
                self.segment();
            }
        }
        self.prev = Some((time, v));
    }

    /// Adds the full segment to the sums and keeps its second half (50 % overlap).
    fn segment(&mut self) {
        let mut axis = vec![0.0; self.seg];
        for (i, sum) in self.sums.iter_mut().enumerate() {
            for (a, s) in axis.iter_mut().zip(&self.buf) {
                *a = s[i];
            }
            // A segment of finite samples always fits the FFT planned for its length.
            let _ = self.density.add(&axis, sum);
        }
        self.segments += 1;
        self.buf.drain(..self.seg - self.seg / 2);
    }
}
