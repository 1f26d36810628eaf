//! `ulog analyze`: what happened in each flight ([`ulog_core::analysis::analyze`]):
//! Flight Review v2's diagnostics, flight statistics, battery, GPS, vibration and its
//! frequencies, the rate controllers' step responses.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use ulog_core::analysis::{analyze, AnalyzeOptions, FlightAnalysis};

use crate::failure::{stdout_err, Failure};
use crate::input::{self, Input};

/// Analyse flights: per log, the diagnostics of Flight Review v2 (`battery_brownout`,
/// `ekf_failure`, `gps_interference`, `motor_failure`, `rc_loss`) with severity,
/// start and end times and evidence; flight statistics (distance, altitude, speeds,
/// tilt, rotation); battery (lowest voltage, charge used, highest current); GPS
/// quality; the accelerometer's vibration and its status; the dominant frequencies of
/// the gyro and accelerometer spectra while armed; the rate controllers' step
/// responses (rise time, overshoot, settling). Each log is read once, in chunks.
///
/// With `--json`, one JSON object per log, one per line, whose `diagnostics` is a
/// list of `{id, severity, timestamp_us, end_timestamp_us, summary, evidence}`.
#[derive(Debug, clap::Args)]
#[command(
    about = "Diagnostics, flight statistics, vibration and PID step responses",
    long_about
)]
pub struct Args {
    /// The ULog files.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// One JSON object per log, one per line.
    #[arg(long)]
    json: bool,
    /// Leave out the spectra and the step responses (faster).
    #[arg(long)]
    no_signals: bool,
}

pub fn run(args: &Args) -> Result<(), Failure> {
    let options = AnalyzeOptions::default()
        .spectra(!args.no_signals)
        .step_response(!args.no_signals);
    let mut out = std::io::stdout().lock();
    for (i, path) in args.files.iter().enumerate() {
        let name = path.display().to_string();
        let flight = analyse(path, &name, &options)?;
        input::note_damage(&name, &flight.findings);
        if args.json {
            let line = to_json(&name, &flight)
                .map_err(|e| Failure::about(&name, format_args!("cannot write JSON: {e}")))?;
            writeln!(out, "{line}").map_err(stdout_err)?;
        } else {
            if i > 0 {
                writeln!(out).map_err(stdout_err)?;
            }
            write_text(&mut out, &name, &flight).map_err(stdout_err)?;
        }
    }
    Ok(())
}

fn analyse(path: &Path, name: &str, options: &AnalyzeOptions) -> Result<FlightAnalysis, Failure> {
    let input = Input::open(path)?;
    analyze(input.source(), options).map_err(|e| input.failure(name, &e))
}

/// The library's JSON of the analysis ([`FlightAnalysis::json`], an object) with the
/// log's name as its first key.
fn to_json(name: &str, f: &FlightAnalysis) -> Result<String, serde_json::Error> {
    let json = f.json();
    let rest = json.strip_prefix('{').unwrap_or(&json);
    Ok(format!(
        "{{\"file\":{},{rest}",
        serde_json::to_string(name)?
    ))
}

fn opt(v: Option<f64>, unit: &str) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.2} {unit}"))
}

fn write_text(
    out: &mut impl std::io::Write,
    name: &str,
    f: &FlightAnalysis,
) -> std::io::Result<()> {
    writeln!(out, "{name}")?;
    let t = &f.timeline;
    if let Some((a, b)) = f.span_us {
        writeln!(
            out,
            "  log {:.1} s to {:.1} s, armed {:.1} s, in the air {:.1} s",
            a as f64 * 1e-6,
            b as f64 * 1e-6,
            t.armed_s,
            t.airborne_s
        )?;
    }
    writeln!(out, "Diagnostics: {}", f.diagnostics.len())?;
    for d in &f.diagnostics {
        writeln!(
            out,
            "  {:<8} {:<16} {}",
            d.severity.as_str(),
            d.id,
            d.summary
        )?;
    }
    let s = &f.stats;
    writeln!(out, "Flight")?;
    writeln!(
        out,
        "  distance {:.1} m, altitude range {:.1} m, up to {:.1} m above the start",
        s.total_distance_m, s.max_altitude_diff_m, s.max_altitude_above_start_m
    )?;
    writeln!(
        out,
        "  max speed {:.1} m/s (horizontal {:.1}, up {:.1}, down {:.1}), mean {:.1} m/s",
        s.max_speed_m_s,
        s.max_horizontal_speed_m_s,
        s.max_speed_up_m_s,
        s.max_speed_down_m_s,
        s.avg_speed_m_s
    )?;
    writeln!(
        out,
        "  max tilt {:.1}°, max rotation {:.0}°/s",
        s.max_tilt_deg, s.max_rotation_speed_deg_s
    )?;
    let b = &f.battery;
    writeln!(
        out,
        "Battery: min {}, mean current {}, max current {}, used {}",
        opt(b.min_voltage_v, "V"),
        opt(b.avg_current_a, "A"),
        opt(b.max_current_a, "A"),
        opt(b.discharged_mah, "mAh")
    )?;
    match &f.gps {
        Some(g) => writeln!(
            out,
            "GPS ({}): satellites {}–{}, max EPH {}, max EPV {}, max HDOP {}, fix types {:?}",
            g.topic,
            g.min_satellites.unwrap_or(0),
            g.max_satellites.unwrap_or(0),
            opt(g.max_eph_m.map(f64::from), "m"),
            opt(g.max_epv_m.map(f64::from), "m"),
            opt(g.max_hdop.map(f64::from), ""),
            g.fix_types_seen
        )?,
        None => writeln!(out, "GPS: none")?,
    }
    let v = &f.vibration;
    writeln!(
        out,
        "Vibration: {} (accelerometer metric mean {}, max {}); spectra while armed:",
        v.status,
        opt(v.accel_vibe_mean, "m/s²"),
        opt(v.accel_vibe_max, "m/s²")
    )?;
    for a in &f.spectra {
        let peaks: Vec<String> = a
            .dominant
            .iter()
            .map(|p| format!("{:.1} Hz", p.frequency_hz))
            .collect();
        let peaks = if peaks.is_empty() {
            "none".to_owned()
        } else {
            peaks.join(", ")
        };
        let name = format!("{}.{}", a.topic, a.signal);
        writeln!(out, "  {name:<40} dominant: {peaks}")?;
    }
    if !f.step_responses.is_empty() {
        writeln!(out, "Rate controllers' step response")?;
    }
    for a in &f.step_responses {
        match &a.metrics {
            Some(m) => writeln!(
                out,
                "  {:<5} rise {}, overshoot {:.1} %, settling {} ({} windows)",
                a.axis,
                opt(m.rise_time_s.map(|r| r * 1e3), "ms"),
                m.overshoot_percent,
                opt(m.settling_time_s.map(|r| r * 1e3), "ms"),
                a.response.windows.len()
            )?,
            None => writeln!(out, "  {:<5} no rise (too little excitation)", a.axis)?,
        }
    }
    for n in &f.notes {
        writeln!(out, "Note: {n}")?;
    }
    Ok(())
}
