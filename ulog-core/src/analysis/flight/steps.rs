//! The rate controllers' step responses (roll, pitch, yaw): the setpoints
//! (`vehicle_rates_setpoint`) and the body rates (`vehicle_angular_velocity`) of the
//! longest armed stretch, held up to a bound, deconvolved at the end.

use crate::analysis::{
    resample, sample_rate, step_response, AnalysisError, ResampleOptions, StepMetrics,
    StepResponse, StepResponseOptions,
};

/// Rows held per topic: 2^18, about 17 minutes at 250 Hz (5 MiB per topic). A longer
/// armed stretch is analysed over its first this many rows.
pub(super) const MAX_ROWS: usize = 1 << 18;
/// Interpolation bridges intervals up to this many times the median one.
const MAX_GAP: f64 = 20.0;
/// A window whose setpoint moves less than this (peak to peak, rad/s: about 20°/s)
/// is left out: deconvolving a setpoint that barely moves gives noise, not a
/// response (a yaw held still, a hover).
const MIN_EXCITATION_RAD_S: f64 = 0.35;

/// The axes, in `xyz` order.
const AXES: [&str; 3] = ["roll", "pitch", "yaw"];

/// The step response of one rate controller.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct AxisStep {
    /// `roll`, `pitch` or `yaw`.
    pub axis: &'static str,
    /// The rate both signals were resampled to, Hz.
    pub rate_hz: f64,
    /// The response: mean over the windows, with the windows themselves.
    pub response: StepResponse,
    /// Rise time, overshoot and settling of the mean response; `None` when it never
    /// rises (too little excitation).
    pub metrics: Option<StepMetrics>,
}

/// The rows of one armed stretch.
#[derive(Default)]
struct Stretch {
    setpoint: Vec<(u64, [f32; 3])>,
    rates: Vec<(u64, [f32; 3])>,
}

impl Stretch {
    fn span_us(&self) -> u64 {
        let span = |rows: &[(u64, [f32; 3])]| match (rows.first(), rows.last()) {
            (Some(a), Some(b)) => b.0.saturating_sub(a.0),
            _ => 0,
        };
        span(&self.setpoint).min(span(&self.rates))
    }
}

/// The rows being held.
#[derive(Default)]
pub(super) struct Steps {
    current: Stretch,
    longest: Stretch,
}

fn keep(rows: &mut Vec<(u64, [f32; 3])>, time: u64, v: [f32; 3]) {
    let forward = rows.last().map_or(true, |(t, _)| time > *t);
    if rows.len() < MAX_ROWS && forward && v.iter().all(|x| x.is_finite()) {
        rows.push((time, v));
    }
}

impl Steps {
    pub(super) fn setpoint(&mut self, time: u64, v: [f32; 3]) {
        keep(&mut self.current.setpoint, time, v);
    }

    pub(super) fn rates(&mut self, time: u64, v: [f32; 3]) {
        keep(&mut self.current.rates, time, v);
    }

    /// Disarmed: the stretch ends.
    pub(super) fn disarmed(&mut self) {
        if self.current.span_us() > self.longest.span_us() {
            self.longest = std::mem::take(&mut self.current);
        } else {
            self.current = Stretch::default();
        }
    }

    /// Each axis's response, and why an axis has none (an axis whose setpoint never
    /// moves, as a yaw held still, leaves the others).
    pub(super) fn finish(mut self) -> Result<Vec<Result<AxisStep, String>>, String> {
        self.disarmed();
        let s = self.longest;
        match (s.setpoint.len(), s.rates.len()) {
            (0, 0) => return Err("no rows of either while armed".into()),
            (0, _) => return Err("no rows of vehicle_rates_setpoint while armed".into()),
            (_, 0) => return Err("no rows of vehicle_angular_velocity while armed".into()),
            _ => {}
        }
        responses(&s).map_err(|e| e.to_string())
    }
}

/// The three axes' responses over a stretch with rows of both topics: an error of the
/// whole (rows that do not overlap, a gap), or per axis its response or why not.
fn responses(s: &Stretch) -> Result<Vec<Result<AxisStep, String>>, AnalysisError> {
    let times = |rows: &[(u64, [f32; 3])]| rows.iter().map(|(t, _)| *t).collect::<Vec<_>>();
    let (ts, tr) = (times(&s.setpoint), times(&s.rates));
    let rate_hz = sample_rate(&ts)?.min(sample_rate(&tr)?);
    let start = ts[0].max(tr[0]);
    let end = ts[ts.len() - 1].min(tr[tr.len() - 1]);
    if end <= start {
        return Err(AnalysisError::TooFewSamples { needed: 2, got: 0 });
    }
    let options = ResampleOptions::default()
        .rate_hz(rate_hz)
        .span_us(start..end)
        .max_gap(MAX_GAP);
    let mut out = Vec::new();
    for (k, axis) in AXES.into_iter().enumerate() {
        let column = |rows: &[(u64, [f32; 3])]| rows.iter().map(|(_, v)| v[k]).collect::<Vec<_>>();
        let sp = resample(&ts, &column(&s.setpoint), &options)?;
        let re = resample(&tr, &column(&s.rates), &options)?;
        let n = sp.values.len().min(re.values.len());
        let response = step_response(
            &sp.values[..n],
            &re.values[..n],
            rate_hz,
            &StepResponseOptions::default().min_excitation(MIN_EXCITATION_RAD_S),
        );
        out.push(
            response
                .map(|response| AxisStep {
                    axis,
                    rate_hz,
                    metrics: response.metrics(),
                    response,
                })
                .map_err(|e| format!("{axis}: {e}")),
        );
    }
    Ok(out)
}
