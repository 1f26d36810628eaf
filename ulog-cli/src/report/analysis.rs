//! What the flight analysis ([`ulog_core::analysis`], fed by the report's second pass)
//! adds to the page: the diagnostics (a table and marks), the spectra of the IMU and
//! of the controllers' outputs, the spectrograms, the rate controllers' step
//! responses, and the figures of the header it shares with `ulog analyze`.

use serde::Serialize;
use ulog_core::analysis::{EvidenceValue, FlightAnalysis, SignalSpectrogram};
use ulog_core::read::TimeSpan;

use super::timeline::{Mark, ModeBand};

/// A plot whose x axis is not the log's time (frequency, or time after a step).
#[derive(Debug, Serialize)]
pub struct XyPlot {
    /// Its id.
    pub id: String,
    /// Its heading.
    pub title: String,
    /// The x axis: `Hz` or `s`.
    pub x_unit: String,
    /// The y axis's unit.
    pub unit: String,
    /// Whether y is drawn on a log scale (power spectra).
    pub log_y: bool,
    /// The x values, shared by the lines.
    pub x: Vec<f64>,
    /// The lines: label and values (`None` where there is none).
    pub lines: Vec<(String, Vec<Option<f64>>)>,
}

/// A spectrogram: power in dB per column (time) and bin (frequency).
#[derive(Debug, Serialize)]
pub struct Heatmap {
    /// Its id.
    pub id: String,
    /// Its heading.
    pub title: String,
    /// Each column's start, seconds on the page's time axis.
    pub t: Vec<f64>,
    /// A column's width, s.
    pub width_s: f64,
    /// The highest frequency, Hz (bins are evenly spaced from 0).
    pub max_hz: f64,
    /// Per column, per bin, 10·log10 of the power (clipped 120 dB below the
    /// strongest cell).
    pub db: Vec<Vec<Option<f32>>>,
}

/// A diagnostic as the page lists it.
#[derive(Debug)]
pub struct DiagnosticRow {
    /// Start, seconds since the page's zero.
    pub t: f64,
    /// End, when it has one.
    pub end: Option<f64>,
    /// `critical`, `warning`, `info`.
    pub severity: &'static str,
    /// The rule's id.
    pub id: &'static str,
    /// The summary.
    pub summary: String,
    /// The evidence as `name=value` pairs.
    pub evidence: String,
}

/// Seconds on the page's time axis of a time of the log's clock.
fn seconds(span: &TimeSpan, t: u64) -> f64 {
    span.seconds(t.clamp(span.start(), span.end().max(span.start())))
}

/// The modes and the arming, takeoff and landing marks of the analysis's timeline, on
/// the page's time axis; the armed time.
pub fn timeline(flight: &FlightAnalysis, span: &TimeSpan) -> (Vec<ModeBand>, Vec<Mark>, f64) {
    let t = &flight.timeline;
    let modes = t
        .modes
        .iter()
        .map(|m| ModeBand {
            t0: seconds(span, m.start_us),
            t1: seconds(span, m.end_us),
            mode: m.mode,
            name: m.name.clone(),
        })
        .collect();
    let marks = t
        .events
        .iter()
        .map(|(time, kind)| Mark {
            t: seconds(span, *time),
            kind: kind.as_str(),
            text: match kind.as_str() {
                "arm" => "armed",
                "disarm" => "disarmed",
                "landing" => "landed",
                other => other,
            }
            .to_owned(),
        })
        .collect();
    (modes, marks, t.armed_s)
}

/// The diagnostics as rows of the page's table, and as marks.
pub fn diagnostics(flight: &FlightAnalysis, span: &TimeSpan) -> (Vec<DiagnosticRow>, Vec<Mark>) {
    let mut rows = Vec::new();
    let mut marks = Vec::new();
    for d in &flight.diagnostics {
        let t = seconds(span, d.timestamp_us);
        let evidence: Vec<String> = d
            .evidence
            .fields()
            .into_iter()
            .map(|(k, v)| {
                let v = match v {
                    EvidenceValue::Float(f) => format!("{f:.3}"),
                    EvidenceValue::Int(i) => i.to_string(),
                    EvidenceValue::Text(s) => s,
                    EvidenceValue::Bool(b) => b.to_string(),
                    EvidenceValue::Missing => "not logged".to_owned(),
                };
                format!("{k}={v}")
            })
            .collect();
        marks.push(Mark {
            t,
            kind: "diagnostic",
            text: d.id.to_owned(),
        });
        rows.push(DiagnosticRow {
            t,
            end: d.end_timestamp_us.map(|e| seconds(span, e)),
            severity: d.severity.as_str(),
            id: d.id,
            summary: d.summary.clone(),
            evidence: evidence.join(", "),
        });
    }
    (rows, marks)
}

/// Spectra of one topic's signals as one plot per field (PSD against frequency).
fn spectra_plots(flight: &FlightAnalysis) -> Vec<XyPlot> {
    let groups: [(&str, &str, &str, &str, [&str; 3]); 4] = [
        (
            "psd_gyro",
            "gyro_rad",
            "Angular rate spectrum (raw gyro, armed)",
            "(rad/s)²/Hz",
            ["x", "y", "z"],
        ),
        (
            "psd_accel",
            "accelerometer_m_s2",
            "Acceleration spectrum (raw accelerometer, armed)",
            "(m/s²)²/Hz",
            ["x", "y", "z"],
        ),
        (
            "psd_controls",
            "control",
            "Actuator controls spectrum (actuator_controls_0, armed)",
            "1/Hz",
            ["roll", "pitch", "yaw"],
        ),
        (
            "psd_torque",
            "xyz",
            "Torque setpoint spectrum (vehicle_torque_setpoint, armed)",
            "1/Hz",
            ["roll", "pitch", "yaw"],
        ),
    ];
    let mut plots = Vec::new();
    for (id, field, title, unit, axes) in groups {
        let axes_of: Vec<_> = flight
            .spectra
            .iter()
            .filter(|s| s.signal.starts_with(&format!("{field}[")))
            .collect();
        let Some(first) = axes_of.first() else {
            continue;
        };
        let mut lines = Vec::new();
        for (s, axis) in axes_of.iter().zip(axes) {
            let peaks: Vec<String> = s
                .dominant
                .iter()
                .map(|p| format!("{:.0}", p.frequency_hz))
                .collect();
            let label = if peaks.is_empty() {
                axis.to_owned()
            } else {
                format!("{axis} (peaks {} Hz)", peaks.join(", "))
            };
            let values = s
                .psd
                .values
                .iter()
                .map(|v| (v.is_finite() && *v > 0.0).then_some(*v))
                .collect();
            lines.push((label, values));
        }
        plots.push(XyPlot {
            id: id.to_owned(),
            title: format!(
                "{title}, {} segments at {:.0} Hz",
                first.segments, first.rate_hz
            ),
            x_unit: "Hz".into(),
            unit: unit.into(),
            log_y: true,
            x: first.psd.frequencies.clone(),
            lines,
        });
    }
    plots
}

/// The mean step response of each axis, in one plot.
fn step_plot(flight: &FlightAnalysis) -> Option<XyPlot> {
    let first = flight.step_responses.first()?;
    let lines = flight
        .step_responses
        .iter()
        .map(|a| {
            let label = match &a.metrics {
                Some(m) => format!(
                    "{} (rise {}, overshoot {:.0} %)",
                    a.axis,
                    m.rise_time_s
                        .map_or_else(|| "-".to_owned(), |r| format!("{:.0} ms", r * 1e3)),
                    m.overshoot_percent
                ),
                None => a.axis.to_owned(),
            };
            (label, a.response.mean.iter().map(|v| Some(*v)).collect())
        })
        .collect();
    Some(XyPlot {
        id: "step_response".into(),
        title: format!(
            "Rate controllers' step response ({} windows at {:.0} Hz)",
            first.response.windows.len(),
            first.rate_hz
        ),
        x_unit: "s".into(),
        unit: "".into(),
        log_y: false,
        x: first.response.time_s.clone(),
        lines,
    })
}

/// The plots not on the time axis: spectra, then the step responses.
pub fn xy_plots(flight: &FlightAnalysis) -> Vec<XyPlot> {
    let mut plots = spectra_plots(flight);
    plots.extend(step_plot(flight));
    plots
}

fn heatmap(s: &SignalSpectrogram, span: &TimeSpan) -> Heatmap {
    let (id, title) = match s.signal {
        "gyro_rad" => (
            "spectrogram_gyro",
            "Angular rate power over time (raw gyro, dB)",
        ),
        _ => (
            "spectrogram_accel",
            "Acceleration power over time (raw accelerometer, dB)",
        ),
    };
    let g = &s.spectrogram;
    Heatmap {
        id: id.into(),
        title: title.into(),
        t: g.times_s
            .iter()
            .map(|t| seconds(span, s.start_us + (t * 1e6).round() as u64))
            .collect(),
        width_s: s.column_s,
        max_hz: g.frequencies.last().copied().unwrap_or(0.0),
        db: g
            .power_db
            .iter()
            .map(|c| {
                c.iter()
                    .map(|p| p.is_finite().then_some(*p as f32))
                    .collect()
            })
            .collect(),
    }
}

/// The spectrograms.
pub fn heatmaps(flight: &FlightAnalysis, span: &TimeSpan) -> Vec<Heatmap> {
    flight
        .spectrograms
        .iter()
        .filter(|s| !s.spectrogram.times_s.is_empty())
        .map(|s| heatmap(s, span))
        .collect()
}
