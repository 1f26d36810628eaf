//! The figures a step response is judged by: rise time, overshoot, settling time and
//! peak, each measured against the response's final value.

/// The share of a step response, at its end, whose mean is taken as its final value.
const FINAL_SHARE: usize = 5;

/// The band around the final value a response settles into: ±5 %.
const SETTLING_BAND: f64 = 0.05;

/// Figures of a step response, relative to its final value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepMetrics {
    /// The final value: the mean of the last fifth of the response (a response long
    /// enough to have settled by then reads its steady state).
    pub final_value: f64,
    /// The time from first reaching 10 % of the final value to first reaching 90 % of
    /// it, s, with both crossings interpolated between samples; `None` when the
    /// response never reaches 90 %.
    pub rise_time_s: Option<f64>,
    /// How far the peak goes beyond the final value, in % of the final value (0 when it
    /// never goes beyond).
    pub overshoot_percent: f64,
    /// The time after which the response stays within ±5 % of the final value, s
    /// (interpolated at its last exit from that band); `None` when the last sample is
    /// still outside.
    pub settling_time_s: Option<f64>,
    /// The value furthest beyond zero in the direction of the final value.
    pub peak: f64,
    /// The time of the peak, s.
    pub peak_time_s: f64,
}

/// The [`StepMetrics`] of a step response sampled at `time_s`, or `None` when there is
/// none to measure: fewer than 5 samples, lengths that differ, a value that is not
/// finite, or a final value of zero.
///
/// ```
/// use ulog_core::analysis::step_metrics;
///
/// // 1 − e^(−t/τ) with τ = 0.1 s, sampled at 1 kHz for 1 s.
/// let t: Vec<f64> = (0..1000).map(|k| k as f64 / 1000.0).collect();
/// let y: Vec<f64> = t.iter().map(|t| 1.0 - (-t / 0.1).exp()).collect();
/// let m = step_metrics(&t, &y).unwrap();
/// assert!((m.rise_time_s.unwrap() - 0.1 * 9f64.ln()).abs() < 2e-3);
/// // The last fifth's mean sits just under the response's end: a trace of overshoot.
/// assert!(m.overshoot_percent < 0.1);
/// assert!((m.settling_time_s.unwrap() - 0.1 * 20f64.ln()).abs() < 5e-3);
/// ```
pub fn step_metrics(time_s: &[f64], response: &[f64]) -> Option<StepMetrics> {
    let n = response.len();
    if n < FINAL_SHARE || time_s.len() != n {
        return None;
    }
    if response.iter().chain(time_s).any(|v| !v.is_finite()) {
        return None;
    }
    let tail = (n / FINAL_SHARE).max(1);
    let final_value = response[n - tail..].iter().sum::<f64>() / tail as f64;
    if final_value == 0.0 {
        return None;
    }
    // In units of the final value, so that a negative step reads as a positive one.
    let r: Vec<f64> = response.iter().map(|v| v / final_value).collect();
    let (peak_index, peak_r) = r
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let rise_time_s = match (
        first_crossing(time_s, &r, 0.1),
        first_crossing(time_s, &r, 0.9),
    ) {
        (Some(t10), Some(t90)) => Some(t90 - t10),
        _ => None,
    };
    let settling_time_s = match r.iter().rposition(|v| (v - 1.0).abs() > SETTLING_BAND) {
        None => Some(time_s[0]),
        Some(i) if i + 1 == n => None,
        Some(i) => {
            // The exit through the band's edge on the side the response was on.
            let edge = if r[i] > 1.0 {
                1.0 + SETTLING_BAND
            } else {
                1.0 - SETTLING_BAND
            };
            Some(interpolate(time_s, &r, i, edge))
        }
    };
    Some(StepMetrics {
        final_value,
        rise_time_s,
        overshoot_percent: ((peak_r - 1.0) * 100.0).max(0.0),
        settling_time_s,
        peak: response[peak_index],
        peak_time_s: time_s[peak_index],
    })
}

/// The time at which `r` first reaches `level` from below, interpolated (the first
/// time when it starts there already).
fn first_crossing(time_s: &[f64], r: &[f64], level: f64) -> Option<f64> {
    let i = r.iter().position(|&v| v >= level)?;
    if i == 0 {
        return Some(time_s[0]);
    }
    Some(interpolate(time_s, r, i - 1, level))
}

/// The time between samples `i` and `i + 1` at which the line through them passes
/// `level`.
fn interpolate(time_s: &[f64], r: &[f64], i: usize, level: f64) -> f64 {
    let (r0, r1) = (r[i], r[i + 1]);
    let frac = if r1 == r0 {
        0.0
    } else {
        ((level - r0) / (r1 - r0)).clamp(0.0, 1.0)
    };
    time_s[i] + frac * (time_s[i + 1] - time_s[i])
}
