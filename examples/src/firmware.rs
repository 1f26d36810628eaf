//! One struct per topic for every PX4 firmware the corpus has (v1.7 to v1.16): the
//! bindings the `flight_summary` example reads, and that the tests read every corpus
//! log with, value by value against pyulog.
//!
//! What changed across firmware, and how each struct spans it:
//!
//! - `battery_status.cell_count` went from `int32_t` to `uint8_t`: an `i32` field reads
//!   both (`uint8_t` widens to `int32_t` without loss, as Rust's `From<u8> for i32`).
//! - `battery_status.voltage_cell_v` has been `float[4]`, `float[10]` and `float[14]`,
//!   or absent: an `Option<[f32; 14]>` reads each, a shorter array's further cells `0.0`
//!   (what PX4 logs for cells a battery does not have).
//! - `sensor_combined.gyro_integral_dt` and `accelerometer_integral_dt` went from
//!   `float` seconds to `uint32_t` microseconds: an `f32` field in seconds declares the
//!   conversion from `uint32_t` (`#[ulog(convert(uint32_t = …))]`).
//! - `vehicle_status.system_id` went from `uint32_t` to `uint8_t`: a `u32` field reads
//!   both.
//! - The receiver's fix moved to `sensor_gps` (newer logs have both, and
//!   `vehicle_gps_position` is then the fix blended from every receiver; some logs
//!   have only one of them): the binding is named `vehicle_gps_position` with the
//!   alias `sensor_gps`, read under the first of the two names a log has. Positions went from `int32_t` degrees·1e7 to `double`
//!   degrees in 2023: both are `Option`s.

use ulog_core::ULogMessage;

/// `uint32_t` microseconds as `f32` seconds: the unit of the older `float` fields.
pub fn micros_to_seconds(us: u32) -> f32 {
    (f64::from(us) * 1e-6) as f32
}

/// Battery state, every firmware.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct BatteryStatus {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Volts.
    pub voltage_v: f32,
    /// Remaining charge, 0..1.
    pub remaining: f32,
    /// Charge drawn so far, mAh (not in every firmware).
    pub discharged_mah: Option<f32>,
    /// The number of cells: `int32_t` in older firmware, `uint8_t` in newer.
    pub cell_count: i32,
    /// Volts per cell: 4, 10 or 14 cells logged, or none; cells beyond the log's are 0.
    pub voltage_cell_v: Option<[f32; 14]>,
}

/// The IMU's combined sample, every firmware.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct SensorCombined {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Rad/s.
    pub gyro_rad: [f32; 3],
    /// Seconds the gyro sample integrates: `float` seconds in older firmware,
    /// `uint32_t` microseconds in newer.
    #[ulog(convert(uint32_t = micros_to_seconds))]
    pub gyro_integral_dt: f32,
    /// m/s².
    pub accelerometer_m_s2: [f32; 3],
    /// Seconds, as `gyro_integral_dt`.
    #[ulog(convert(uint32_t = micros_to_seconds))]
    pub accelerometer_integral_dt: f32,
}

/// The vehicle's state, every firmware.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct VehicleStatus {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Armed, disarmed…: PX4's `arming_state`.
    pub arming_state: u8,
    /// PX4's `nav_state`.
    pub nav_state: u8,
    /// The MAVLink system id: `uint32_t` in older firmware, `uint8_t` in newer.
    pub system_id: u32,
}

/// A GPS fix, every firmware: `vehicle_gps_position`, or `sensor_gps` in logs that
/// do not have it.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
#[ulog(name = "vehicle_gps_position", alias = "sensor_gps")]
pub struct GpsFix {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Degrees (since 2023).
    pub latitude_deg: Option<f64>,
    /// Degrees (since 2023).
    pub longitude_deg: Option<f64>,
    /// Metres above mean sea level (since 2023).
    pub altitude_msl_m: Option<f64>,
    /// Degrees·1e7 (before 2023).
    pub lat: Option<i32>,
    /// Degrees·1e7 (before 2023).
    pub lon: Option<i32>,
    /// Millimetres above mean sea level (before 2023).
    pub alt: Option<i32>,
    /// 0-1: no fix, 2: 2D, 3: 3D…
    pub fix_type: u8,
    /// Satellites used.
    pub satellites_used: u8,
}

/// A fix in degrees and metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fix {
    /// Degrees.
    pub lat: f64,
    /// Degrees.
    pub lon: f64,
    /// Metres above mean sea level.
    pub alt: f64,
}

impl GpsFix {
    /// The fix in degrees and metres, from whichever fields the log has.
    pub fn degrees(&self) -> Option<Fix> {
        match (self.latitude_deg, self.longitude_deg, self.altitude_msl_m) {
            (Some(lat), Some(lon), Some(alt)) => Some(Fix { lat, lon, alt }),
            _ => Some(Fix {
                lat: f64::from(self.lat?) * 1e-7,
                lon: f64::from(self.lon?) * 1e-7,
                alt: f64::from(self.alt?) * 1e-3,
            }),
        }
    }
}
