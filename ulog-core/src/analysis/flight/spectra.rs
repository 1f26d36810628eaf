//! The spectra of the raw IMU while armed, by Welch's method in one pass: rows are
//! interpolated onto a uniform grid as they come and each full segment is
//! transformed and summed, so the pass holds one segment per signal, not the signal.

use crate::analysis::fft::segment_len;
use crate::analysis::spectrogram::to_db;
use crate::analysis::spectrum::Density;
use crate::analysis::{sample_rate, Peak, Spectrogram, Spectrum};

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

/// Columns a spectrogram keeps at most: past this, neighbouring columns are averaged
/// in pairs (each then spans twice the time), so a long log holds no more.
const MAX_COLUMNS: usize = 512;

/// The spectrum of one axis of one signal: the IMU's, or the controllers' outputs.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct AxisSpectrum {
    /// The topic: `sensor_combined`, or `actuator_controls_0` /
    /// `vehicle_torque_setpoint` for the rate controllers' outputs.
    pub topic: &'static str,
    /// The field and axis: `gyro_rad[0]` … `accelerometer_m_s2[2]`, `control[0]` …
    /// `control[2]` (roll, pitch, yaw), `xyz[0]` … `xyz[2]`.
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

/// The power over time of one signal while armed, its three axes summed: a
/// [`Spectrogram`] whose columns are one segment each (about 1 s, overlapping by
/// half), or the mean of 2, 4, … neighbouring segments in a long log (at most 512
/// columns). A stretch disarmed or a dropout is a gap between columns.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SignalSpectrogram {
    /// The topic, as in [`AxisSpectrum::topic`].
    pub topic: &'static str,
    /// The field: `gyro_rad` or `accelerometer_m_s2`.
    pub signal: &'static str,
    /// The time its `times_s` count from: the first column's, µs on the log's clock.
    pub start_us: u64,
    /// The time each column spans, s.
    pub column_s: f64,
    /// The columns: `times_s` is where each starts (the middle of its first segment),
    /// s after `start_us`; `power_db` the sum of the axes' densities in dB.
    pub spectrogram: Spectrogram,
}

/// Three axes of one signal, as rows come.
pub(super) struct Welch {
    topic: &'static str,
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
    /// The spectrogram: its columns, the segments averaged per column, and the
    /// segments summed towards the next column (with the middle time of the first).
    columns: Vec<(u64, Vec<f32>)>,
    per_column: usize,
    pending: Option<(u64, Vec<f64>, usize)>,
    /// One segment's PSD (scratch).
    one: Vec<f64>,
}

impl Welch {
    pub(super) fn new(topic: &'static str, name: &'static str) -> Welch {
        Welch {
            topic,
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
                        columns: Vec::new(),
                        per_column: 1,
                        pending: None,
                        one: vec![0.0; seg / 2 + 1],
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

    /// The three axes' spectra and the spectrogram; none when no segment was complete.
    pub(super) fn finish(self) -> (Vec<AxisSpectrum>, Option<SignalSpectrogram>) {
        let Some(mut g) = self.grid else {
            return (Vec::new(), None);
        };
        if g.segments == 0 {
            return (Vec::new(), None);
        }
        g.flush_column();
        let frequencies = g.density.frequencies();
        let spectra = g
            .sums
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
                    topic: self.topic,
                    signal: format!("{}[{axis}]", self.name),
                    rate_hz: g.rate_hz,
                    segments: g.segments,
                    psd,
                    dominant,
                }
            })
            .collect();
        let hop = (g.seg - g.seg / 2) as f64 * g.step_us;
        // The earliest: a damaged log's clock may go back between stretches.
        let start_us = g.columns.iter().map(|(t, _)| *t).min().unwrap_or(0);
        let (times, columns): (Vec<u64>, Vec<Vec<f32>>) = g.columns.into_iter().unzip();
        let rows = columns
            .into_iter()
            .map(|c| c.into_iter().map(f64::from).collect())
            .collect();
        let spectrogram = SignalSpectrogram {
            topic: self.topic,
            signal: self.name,
            start_us,
            column_s: hop * g.per_column as f64 * 1e-6,
            spectrogram: Spectrogram {
                times_s: times.iter().map(|t| (t - start_us) as f64 * 1e-6).collect(),
                frequencies,
                power_db: to_db(rows),
            },
        };
        (spectra, Some(spectrogram))
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

    /// Adds the full segment to the sums and the spectrogram, and keeps its second
    /// half (50 % overlap).
    fn segment(&mut self) {
        let mut axis = vec![0.0; self.seg];
        let mut power = vec![0.0; self.seg / 2 + 1];
        for (i, sum) in self.sums.iter_mut().enumerate() {
            for (a, s) in axis.iter_mut().zip(&self.buf) {
                *a = s[i];
            }
            self.one.iter_mut().for_each(|p| *p = 0.0);
            // A segment of finite samples always fits the FFT planned for its length.
            let _ = self.density.add(&axis, &mut self.one);
            for ((s, p), o) in sum.iter_mut().zip(power.iter_mut()).zip(&self.one) {
                *s += o;
                *p += o;
            }
        }
        self.segments += 1;
        let middle = (self.next_us - (self.seg / 2) as f64 * self.step_us).max(0.0) as u64;
        let (_, acc, n) = self
            .pending
            .get_or_insert_with(|| (middle, vec![0.0; power.len()], 0));
        acc.iter_mut().zip(&power).for_each(|(a, p)| *a += p);
        *n += 1;
        if *n == self.per_column {
            self.flush_column();
        }
        self.buf.drain(..self.seg - self.seg / 2);
    }

    /// The segments summed so far become a column; past [`MAX_COLUMNS`], neighbours
    /// are averaged in pairs.
    fn flush_column(&mut self) {
        let Some((time, acc, n)) = self.pending.take() else {
            return;
        };
        let column = acc.iter().map(|a| (a / n as f64) as f32).collect();
        self.columns.push((time, column));
        if self.columns.len() == MAX_COLUMNS {
            let old = std::mem::take(&mut self.columns);
            for pair in old.chunks(2) {
                let time = pair[0].0;
                let values = match pair {
                    [a, b] => a.1.iter().zip(&b.1).map(|(x, y)| (x + y) / 2.0).collect(),
                    [a] => a.1.clone(),
                    _ => unreachable!("chunks of two"),
                };
                self.columns.push((time, values));
            }
            self.per_column *= 2;
        }
    }
}
