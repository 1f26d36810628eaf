//! A typed analysis of a flight log: flight time, distance flown, peak altitude and
//! battery used, from `vehicle_local_position`, `vehicle_gps_position` and
//! `battery_status`.
//!
//! ```text
//! cargo run -p ulog-examples --example flight_summary -- [LOG.ulg]
//! ```
//!
//! Without a path it reads the bundled sample log (`ulog_core::testing::sample_log`).
//!
//! Each binding names only the fields it needs. The reader checks it against the log's
//! format once per topic: where a newer firmware added or moved fields, the fields are
//! found by name (a mapped plan), so the same structs read logs from 2016 to today.
//! Where a field's type changed (GPS positions went from `int32_t` degrees·1e7 to
//! `double` degrees), there are two bindings, and the one that fits is used.

use std::process::ExitCode;

use ulog_core::typed::ULogMessage;
use ulog_core::{ErrorKind, MappedFile, ULog};

/// The local position estimate (NED, metres, relative to the EKF origin).
#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    y: f32,
    z: f32,
    xy_valid: bool,
}

/// GPS fixes as PX4 logs them since 2023: degrees and metres as `double`.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(name = "vehicle_gps_position")]
struct GpsPosition {
    timestamp: u64,
    latitude_deg: f64,
    longitude_deg: f64,
    altitude_msl_m: f64,
    fix_type: u8,
}

/// GPS fixes as older PX4 logs them: degrees·1e7 and millimetres as `int32_t`.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(name = "vehicle_gps_position")]
struct GpsPositionInt {
    timestamp: u64,
    lat: i32,
    lon: i32,
    alt: i32,
    fix_type: u8,
}

/// Battery state: voltage and the estimated remaining charge (0..1).
#[derive(ULogMessage, Debug, Clone, Copy)]
struct BatteryStatus {
    timestamp: u64,
    voltage_v: f32,
    remaining: f32,
}

/// The charge drawn so far, where the firmware logs it.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(name = "battery_status")]
struct BatteryDischarge {
    timestamp: u64,
    discharged_mah: f32,
}

/// Height above the start at which the vehicle counts as flying.
const AIRBORNE_M: f32 = 1.0;
/// A step between two estimates faster than this is a reset of the estimator's
/// origin, not flight.
const MAX_SPEED_M_S: f32 = 100.0;

fn main() -> ExitCode {
    let path = std::env::args_os().nth(1);
    let (name, bytes) = match &path {
        Some(p) => match MappedFile::open(p) {
            Ok(file) => (p.to_string_lossy().into_owned(), Bytes::Mapped(file)),
            Err(e) => {
                eprintln!("flight_summary: {e}");
                return ExitCode::FAILURE;
            }
        },
        None => (
            "the bundled sample log".to_owned(),
            Bytes::Owned(ulog_core::testing::sample_log()),
        ),
    };
    let log = match ULog::parse(bytes.as_slice()) {
        Ok(log) => log,
        Err(e) => {
            eprintln!("flight_summary: {name}: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("flight summary of {name}");
    let logged = log.last_timestamp().saturating_sub(log.start_timestamp());
    println!("  logged:          {:.1} s", seconds(logged));
    local_position(&log);
    gps(&log);
    battery(&log);
    ExitCode::SUCCESS
}

enum Bytes {
    Mapped(MappedFile),
    Owned(Vec<u8>),
}

impl Bytes {
    fn as_slice(&self) -> &[u8] {
        match self {
            Bytes::Mapped(m) => m.bytes(),
            Bytes::Owned(v) => v,
        }
    }
}

fn seconds(us: u64) -> f64 {
    us as f64 / 1e6
}

/// Prints why a topic cannot be used: absent, or a format the binding cannot read.
fn unavailable(what: &str, e: &ulog_core::Error) {
    match e.kind() {
        ErrorKind::TopicNotFound { name, .. } => {
            println!("  {what:<16} no `{name}` topic in this log")
        }
        _ => println!("  {what:<16} unreadable: {e}"),
    }
}

/// Flight time, distance flown and peak altitude from the local position estimate.
fn local_position(log: &ULog<'_>) {
    let rows = match log.read::<VehicleLocalPosition>(0) {
        Ok(rows) => rows,
        Err(e) => return unavailable("local position:", &e),
    };
    let positions: Vec<VehicleLocalPosition> = rows.iter().filter_map(Result::ok).collect();
    let Some(start) = positions.first() else {
        println!("  local position:  the topic has no data");
        return;
    };
    // Up is -z (NED); heights are relative to the first estimate.
    let ground = -start.z;
    let mut airborne_us = 0u64;
    let mut distance = 0f64;
    let mut peak = 0f32;
    let mut resets = 0;
    for pair in positions.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let height = -b.z - ground;
        peak = peak.max(height);
        if height > AIRBORNE_M && -a.z - ground > AIRBORNE_M {
            airborne_us += b.timestamp.saturating_sub(a.timestamp);
        }
        if a.xy_valid && b.xy_valid {
            let (dx, dy, dz) = (b.x - a.x, b.y - a.y, b.z - a.z);
            let step = (dx * dx + dy * dy + dz * dz).sqrt();
            let dt = b.timestamp.saturating_sub(a.timestamp) as f32 / 1e6;
            if step > MAX_SPEED_M_S * dt.max(1e-3) {
                resets += 1;
            } else {
                distance += f64::from(step);
            }
        }
    }
    println!(
        "  flight time:     {:.1} s more than {AIRBORNE_M} m above the start",
        seconds(airborne_us)
    );
    println!(
        "  distance flown:  {distance:.1} m ({} local positions, {:?} plan{})",
        positions.len(),
        rows.plan().kind(),
        match resets {
            0 => String::new(),
            n => format!(", {n} position resets skipped"),
        }
    );
    println!("  peak altitude:   {peak:.1} m above the start");
}

/// A GPS fix in degrees and metres.
struct Fix {
    lat: f64,
    lon: f64,
    alt: f64,
}

/// The GPS track: length and highest point, from whichever binding fits the log.
fn gps(log: &ULog<'_>) {
    let fixes: Vec<Fix> = match log.read::<GpsPosition>(0) {
        Ok(rows) => rows
            .iter()
            .filter_map(Result::ok)
            .filter(|g| g.fix_type >= 3)
            .map(|g| Fix {
                lat: g.latitude_deg,
                lon: g.longitude_deg,
                alt: g.altitude_msl_m,
            })
            .collect(),
        // An older firmware: the same topic with integer fields.
        Err(e) if matches!(e.kind(), ErrorKind::Mismatch(_)) => {
            match log.read::<GpsPositionInt>(0) {
                Ok(rows) => rows
                    .iter()
                    .filter_map(Result::ok)
                    .filter(|g| g.fix_type >= 3)
                    .map(|g| Fix {
                        lat: f64::from(g.lat) * 1e-7,
                        lon: f64::from(g.lon) * 1e-7,
                        alt: f64::from(g.alt) * 1e-3,
                    })
                    .collect(),
                // Neither binding fits: show how the log differs from the newer one.
                Err(_) => return unavailable("GPS:", &e),
            }
        }
        Err(e) => return unavailable("GPS:", &e),
    };
    if fixes.is_empty() {
        println!("  GPS:             no 3D fix in this log");
        return;
    }
    let track: f64 = fixes.windows(2).map(|w| haversine(&w[0], &w[1])).sum();
    let highest = fixes.iter().map(|f| f.alt).fold(f64::MIN, f64::max);
    println!(
        "  GPS track:       {track:.1} m over {} fixes, highest {highest:.1} m AMSL",
        fixes.len()
    );
}

/// Great-circle distance in metres.
fn haversine(a: &Fix, b: &Fix) -> f64 {
    const EARTH_RADIUS_M: f64 = 6_371_000.0;
    let (la, lb) = (a.lat.to_radians(), b.lat.to_radians());
    let dlat = lb - la;
    let dlon = (b.lon - a.lon).to_radians();
    let h = (dlat / 2.0).sin().powi(2) + la.cos() * lb.cos() * (dlon / 2.0).sin().powi(2);
    2.0 * EARTH_RADIUS_M * h.sqrt().asin()
}

/// Battery used per battery instance: voltage, charge fraction and drawn mAh.
fn battery(log: &ULog<'_>) {
    let instances = match log.read_instances::<BatteryStatus>() {
        Ok(i) if !i.is_empty() => i,
        Ok(_) => return println!("  battery:         no `battery_status` topic in this log"),
        Err(e) => return unavailable("battery:", &e),
    };
    for rows in instances {
        let id = rows.topic().multi_id();
        let label = format!("battery {id}:");
        // Before a battery is connected PX4 logs zeros; keep the readings of one.
        let readings: Vec<BatteryStatus> = rows
            .iter()
            .filter_map(Result::ok)
            .filter(|b| b.voltage_v > 1.0)
            .collect();
        let (Some(first), Some(last)) = (readings.first(), readings.last()) else {
            println!("  {label:<16} no readings with a battery connected");
            continue;
        };
        let mut line = format!(
            "  {label:<16} {:.2} V -> {:.2} V",
            first.voltage_v, last.voltage_v
        );
        if (0.0..=1.0).contains(&first.remaining) && (0.0..=1.0).contains(&last.remaining) {
            line += &format!(", {:.1} % used", (first.remaining - last.remaining) * 100.0);
        }
        let drawn = log.read::<BatteryDischarge>(id).ok().and_then(|rows| {
            let mah: Vec<f32> = rows
                .iter()
                .filter_map(Result::ok)
                .map(|b| b.discharged_mah)
                .filter(|m| m.is_finite() && *m >= 0.0)
                .collect();
            Some(mah.last()? - mah.first()?)
        });
        if let Some(mah) = drawn {
            line += &format!(", {mah:.0} mAh drawn");
        }
        println!("{line}");
    }
}
