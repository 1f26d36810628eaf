//! A typed analysis of a flight log: flight time, distance flown, peak altitude, GPS
//! track and battery used, from `vehicle_local_position`, `vehicle_gps_position` (or
//! `sensor_gps`) and `battery_status`.
//!
//! ```text
//! cargo run -p ulog-examples --example flight_summary -- [LOG.ulg]
//! ```
//!
//! Without a path it reads the bundled sample log (`ulog_core::testing::sample_log`).
//!
//! There is one struct per topic, whatever the firmware (`ulog_examples::firmware`
//! holds the GPS and battery ones, which the tests check against pyulog on every
//! corpus log). The reader checks each against the log's format once per topic
//! instance, and finds the fields by name where newer firmware added or moved others.
//! Fields that exist only in some firmware are `Option`s (GPS positions went from
//! `int32_t` degrees·1e7 to `double` degrees in 2023); fields whose type changed take
//! the wider type (`cell_count`: `int32_t`, then `uint8_t`); the GPS fix is found
//! as `vehicle_gps_position` or, in logs without it, `sensor_gps` (an alias of the
//! binding). A topic a log lacks is said as such, with the closest topic names the
//! log has.

use std::process::ExitCode;

use ulog_core::{LogFile, TypedError, ULog, ULogMessage};
use ulog_examples::firmware::{BatteryStatus, Fix, GpsFix, SensorCombined, VehicleStatus};

/// The local position estimate (NED, metres, relative to the EKF origin).
#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    y: f32,
    z: f32,
    xy_valid: bool,
}

/// Height above the start at which the vehicle counts as flying.
const AIRBORNE_M: f32 = 1.0;
/// A step between two estimates faster than this is a reset of the estimator's
/// origin, not flight.
const MAX_SPEED_M_S: f32 = 100.0;

fn main() -> ExitCode {
    let path = std::env::args_os().nth(1);
    let (name, bytes) = match &path {
        Some(p) => match LogFile::open(p) {
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
    imu_and_status(&log);
    ExitCode::SUCCESS
}

enum Bytes {
    Mapped(LogFile),
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

/// Says why a topic cannot be used: the log lacks it (the error names the closest
/// topics it has), or its format does not fit (every difference).
fn unavailable(what: &str, e: &TypedError) {
    println!("  {what:<16} {e}");
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

/// The GPS track: length and highest point, from `vehicle_gps_position`, or from
/// `sensor_gps` in logs without it (the binding's alias).
fn gps(log: &ULog<'_>) {
    let rows = match log.read::<GpsFix>(0) {
        Ok(rows) => rows,
        Err(e) => return unavailable("GPS:", &e),
    };
    let fixes: Vec<Fix> = rows
        .iter()
        .filter_map(Result::ok)
        .filter(|g| g.fix_type >= 3)
        .filter_map(|g| g.degrees())
        .collect();
    if fixes.is_empty() {
        println!("  GPS:             no 3D fix in `{}`", rows.topic().name());
        return;
    }
    let track: f64 = fixes.windows(2).map(|w| haversine(&w[0], &w[1])).sum();
    let highest = fixes.iter().map(|f| f.alt).fold(f64::MIN, f64::max);
    println!(
        "  GPS track:       {track:.1} m over {} fixes of `{}`, highest {highest:.1} m AMSL",
        fixes.len(),
        rows.topic().name()
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

/// Battery used per battery instance: voltage, charge fraction and drawn mAh. Each
/// instance is read on its own: one whose format does not fit is reported alone.
fn battery(log: &ULog<'_>) {
    let instances = match log.read_instances::<BatteryStatus>() {
        Ok(instances) => instances,
        Err(e) => return unavailable("battery:", &e),
    };
    for rows in instances {
        let rows = match rows {
            Ok(rows) => rows,
            Err(e) => {
                let id = e.topic().map_or(0, |(_, id)| id);
                unavailable(&format!("battery {id}:"), &e);
                continue;
            }
        };
        let id = rows.topic().multi_id();
        let label = format!("battery {id}:");
        let all: Vec<BatteryStatus> = rows.iter().filter_map(Result::ok).collect();
        // Before a battery is connected PX4 logs zeros; keep the readings of one.
        let readings: Vec<&BatteryStatus> = all.iter().filter(|b| b.voltage_v > 1.0).collect();
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
        let drawn: Vec<f32> = all
            .iter()
            .filter_map(|b| b.discharged_mah)
            .filter(|m| m.is_finite() && *m >= 0.0)
            .collect();
        if let (Some(a), Some(b)) = (drawn.first(), drawn.last()) {
            line += &format!(", {:.0} mAh drawn", b - a);
        }
        // The lowest cell under load, where the firmware logs cells (4, 10 or 14 of
        // them; `cell_count` says how many the battery has).
        let cells = usize::try_from(last.cell_count).unwrap_or(0);
        let lowest = readings
            .iter()
            .filter_map(|b| b.voltage_cell_v)
            .flat_map(|v| v.into_iter().take(cells))
            .filter(|v| *v > 1.0)
            .fold(f32::INFINITY, f32::min);
        if lowest.is_finite() {
            line += &format!(", {cells} cells, lowest {lowest:.2} V");
        }
        println!("{line}");
    }
}

/// The IMU's rate and the vehicle's MAVLink id: fields whose types changed across
/// firmware (`*_integral_dt` from `float` seconds to `uint32_t` microseconds,
/// `system_id` from `uint32_t` to `uint8_t`), read by one struct each.
fn imu_and_status(log: &ULog<'_>) {
    match log.read::<SensorCombined>(0) {
        Ok(rows) => {
            let mut dts: Vec<f32> = rows
                .iter()
                .filter_map(Result::ok)
                .map(|s| s.gyro_integral_dt)
                .filter(|dt| *dt > 0.0)
                .collect();
            dts.sort_by(f32::total_cmp);
            match dts.get(dts.len() / 2) {
                Some(dt) => println!(
                    "  IMU:             {} samples, each integrating {:.2} ms (median)",
                    rows.len(),
                    dt * 1e3
                ),
                None => println!("  IMU:             no samples"),
            }
        }
        Err(e) => unavailable("IMU:", &e),
    }
    match log.read::<VehicleStatus>(0) {
        Ok(rows) => match rows.iter().filter_map(Result::ok).last() {
            Some(s) => println!("  vehicle:         MAVLink system id {}", s.system_id),
            None => println!("  vehicle:         no status"),
        },
        Err(e) => unavailable("vehicle:", &e),
    }
}
