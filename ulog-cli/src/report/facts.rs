//! The header of a report (vehicle, software, times, figures, damage) and its tables
//! (messages, parameters, information), as text.

use ulog_core::events::Events;
use ulog_core::read::{DefaultKind, KeyValue, UtcClock};
use ulog_core::{Finding, ULog, Value};

use ulog_core::analysis::FlightAnalysis;

use super::flight::Figures;
use crate::pyfmt::py_str;

/// One header row: what, and its value.
pub type Row = (String, String);

/// The header rows of `log` (its metadata: the UTC time and the findings are
/// `utc` and `findings`, from the passes); times from `start` (microseconds since
/// boot).
pub fn header(
    log: &ULog<'_>,
    utc: Option<UtcClock>,
    findings: &[Finding],
    start: u64,
    figures: &Figures,
    armed_s: f64,
    flight: &FlightAnalysis,
) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    let mut add = |k: &str, v: String| rows.push((k.to_owned(), v));
    let info = |key: &str| log.info_value(key).map(|v| py_str(&v));
    let mut vehicle: Vec<String> = Vec::new();
    vehicle.extend(info("sys_name"));
    if let Some(t) = param(log, "MAV_TYPE") {
        vehicle.push(
            match t.parse().ok().and_then(ulog_core::read::vehicle_type) {
                Some(kind) => format!("{kind} (MAV_TYPE {t})"),
                None => format!("MAV_TYPE {t}"),
            },
        );
    }
    if let Some(a) = param(log, "SYS_AUTOSTART") {
        vehicle.push(format!("airframe {a} (SYS_AUTOSTART)"));
    }
    add(
        "Vehicle",
        if vehicle.is_empty() {
            "not logged (no sys_name, MAV_TYPE or SYS_AUTOSTART)".into()
        } else {
            vehicle.join(", ")
        },
    );
    if let Some(uuid) = info("sys_uuid") {
        add("Vehicle UUID", uuid);
    }
    let hw: Vec<String> = ["ver_hw", "ver_hw_subtype", "sys_mcu"]
        .iter()
        .filter_map(|k| info(k))
        .collect();
    add(
        "Hardware",
        if hw.is_empty() {
            "not logged".into()
        } else {
            hw.join(", ")
        },
    );
    let mut sw: Vec<String> = Vec::new();
    if let Some(v) = log.release_version("ver_sw_release") {
        sw.push(v.to_string());
    }
    for k in ["ver_sw", "ver_sw_branch", "sys_os_name", "sys_os_ver"] {
        if let Some(v) = info(k) {
            sw.push(format!("{k} {v}"));
        }
    }
    add(
        "Software",
        if sw.is_empty() {
            "not logged".into()
        } else {
            sw.join(", ")
        },
    );
    add(
        "Start",
        match utc {
            Some(clock) => format!("{} UTC (from {})", clock.at(start), clock.source()),
            None => format!(
                "{:.3} s after boot (no UTC time in the log)",
                start as f64 / 1e6
            ),
        },
    );
    add("Duration", hms(log.span().duration_s()));
    if armed_s > 0.0 {
        add("Armed", hms(armed_s));
    }
    let none = || "no vehicle_local_position".to_owned();
    add(
        "Distance flown",
        figures
            .distance_m
            .map_or_else(none, |d| format!("{d:.1} m")),
    );
    add(
        "Max altitude",
        figures
            .max_altitude_m
            .map_or_else(none, |a| format!("{a:.1} m above the start")),
    );
    add(
        "Max horizontal speed",
        figures
            .max_speed_m_s
            .map_or_else(none, |v| format!("{v:.1} m/s ({:.1} km/h)", v * 3.6)),
    );
    add(
        "Battery",
        match &figures.battery {
            Some(b) => {
                let mut s = format!(
                    "{:.2} V → {:.2} V, {:.0} % → {:.0} % remaining",
                    b.voltage.0,
                    b.voltage.1,
                    b.remaining.0 * 100.0,
                    b.remaining.1 * 100.0
                );
                if let Some(m) = b.discharged_mah {
                    s.push_str(&format!(", {m:.0} mAh used"));
                }
                s
            }
            None => "no battery_status readings".into(),
        },
    );
    let v = &flight.vibration;
    add(
        "Vibration",
        match (v.accel_vibe_mean, v.accel_vibe_max) {
            (Some(mean), Some(max)) => format!(
                "{} (accelerometer vibration metric mean {mean:.2}, peak {max:.2} m/s²)",
                v.status
            ),
            _ => "no vehicle_imu_status".into(),
        },
    );
    let count = |sev: &str| {
        flight
            .diagnostics
            .iter()
            .filter(|d| d.severity.as_str() == sev)
            .count()
    };
    add(
        "Diagnostics",
        if flight.diagnostics.is_empty() {
            "none (battery brownout, EKF failure, GPS interference, motor failure, RC loss)".into()
        } else {
            format!(
                "{} critical, {} warning (table below)",
                count("critical"),
                count("warning")
            )
        },
    );
    let damage: Vec<String> = findings
        .iter()
        .filter(|f| f.is_damage())
        .map(ToString::to_string)
        .collect();
    add(
        "Damage",
        if damage.is_empty() {
            "none found".into()
        } else {
            format!("{} finding(s): {}", damage.len(), damage.join("; "))
        },
    );
    let outliers = span_outliers(log);
    if !outliers.is_empty() {
        add("Timestamps off the time axis", outliers.join("; "));
    }
    let d = log.dropouts();
    add(
        "Dropouts",
        if d.is_empty() {
            "none".into()
        } else {
            let ms: Vec<u64> = d.iter().map(|d| u64::from(d.duration_ms)).collect();
            format!(
                "{} totalling {:.1} s, longest {} ms",
                d.len(),
                ms.iter().sum::<u64>() as f64 / 1000.0,
                ms.iter().max().unwrap_or(&0)
            )
        },
    );
    rows
}

/// The rows far outside the log's time span, one line per topic instance and side.
pub fn span_outliers(log: &ULog<'_>) -> Vec<String> {
    let span = log.span();
    span.outliers()
        .iter()
        .map(|o| {
            let topic = log.subscriptions().get(o.subscription).map_or_else(
                || format!("subscription {}", o.subscription),
                |s| match s.multi_id() {
                    0 => s.name().to_owned(),
                    m => format!("{}:{m}", s.name()),
                },
            );
            o.describe(&topic, span)
        })
        .collect()
}

/// `h:mm:ss` of seconds.
fn hms(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// A parameter's value at the end of the log, as text.
fn param(log: &ULog<'_>, name: &str) -> Option<String> {
    log.params_at_end().get(name).map(py_str)
}

/// The logged messages and events (`events`) as `ulog messages` shows them: (seconds
/// since `start`, level, text).
pub fn messages(
    log: &ULog<'_>,
    events: impl FnOnce() -> Events,
    start: u64,
) -> Vec<(f64, &'static str, String)> {
    let start = start as f64;
    let (lines, _) = crate::messages::lines(log, events, false);
    lines
        .into_iter()
        .map(|(t, level, text)| ((t as f64 - start) / 1e6, level, text))
        .collect()
}

/// Parameters whose value at the end differs from the system default the log gives:
/// (name, value, default).
pub fn params_vs_defaults(log: &ULog<'_>) -> Vec<[String; 3]> {
    let text = |v: &Option<Value<'_>>| v.as_ref().map_or_else(|| "—".into(), py_str);
    log.diff_param_defaults(DefaultKind::System)
        .iter()
        .map(|d| [d.name.clone(), text(&d.values[0]), text(&d.values[1])])
        .collect()
}

/// Parameters set during the flight: (seconds since `start`, name, value).
pub fn params_changed(log: &ULog<'_>, start: u64) -> Vec<(f64, String, String)> {
    let start = start as f64;
    log.param_changes()
        .iter()
        .map(|c| {
            (
                (c.timestamp as f64 - start) / 1e6,
                c.kv.name().into_owned(),
                py_str(&c.kv.value()),
            )
        })
        .collect()
}

/// A value of the information tables: text, or bytes that are no text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Shown {
    /// Text: a string, or a number as Python prints it.
    Text(String),
    /// The bytes of an array of a basic type other than `char` (PX4's
    /// `metadata_events` is xz-compressed JSON in a `uint8_t` array) or of a value this
    /// reader cannot decode.
    Bytes(Vec<u8>),
}

/// An information row: the key, and its value (one per entry of a multi-information
/// key, in file order).
pub type InfoRow = (String, Vec<Shown>);

/// A value as the tables show it.
fn shown(parts: &[KeyValue<'_>]) -> Shown {
    let bytes = |kv: &KeyValue<'_>| matches!(kv.value(), Value::Array(_) | Value::Bytes(_));
    // The entry's first part decides, as for ulog_info: the parts of one entry are
    // the pieces of one value.
    if parts.first().is_some_and(bytes) {
        return Shown::Bytes(parts.iter().flat_map(|kv| kv.raw.iter().copied()).collect());
    }
    let texts: Vec<String> = parts.iter().map(|kv| py_str(&kv.value())).collect();
    // PX4 logs its perf counters one line per part, without line breaks, and its boot
    // console output in chunks cut anywhere: parts without a line break are lines.
    let lines = texts.len() > 1 && !texts.iter().any(|t| t.contains('\n'));
    Shown::Text(texts.join(if lines { "\n" } else { "" }))
}

/// Information (last value per key, in file order of first appearance) and
/// multi-information (each entry's parts joined; the entries of a key that are all
/// text as the lines of one text, as PX4's `excluded_optional_topics`).
pub fn information(log: &ULog<'_>) -> (Vec<InfoRow>, Vec<InfoRow>) {
    let mut info: Vec<InfoRow> = Vec::new();
    for kv in log.info() {
        let (k, v) = (
            kv.name().into_owned(),
            vec![shown(std::slice::from_ref(kv))],
        );
        match info.iter_mut().find(|r| r.0 == k) {
            Some(r) => r.1 = v,
            None => info.push((k, v)),
        }
    }
    let multi = log
        .multi_info()
        .iter()
        .map(|m| {
            let entries: Vec<Shown> = m.entries.iter().map(|e| shown(e)).collect();
            let texts: Option<Vec<&str>> = entries
                .iter()
                .map(|e| match e {
                    Shown::Text(t) => Some(t.as_str()),
                    Shown::Bytes(_) => None,
                })
                .collect();
            match texts {
                Some(t) if t.len() > 1 => (m.name.clone(), vec![Shown::Text(t.join("\n"))]),
                _ => (m.name.clone(), entries),
            }
        })
        .collect();
    (info, multi)
}
