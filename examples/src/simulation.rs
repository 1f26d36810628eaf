//! A short simulated quadcopter flight, logged with derived types through the writer:
//! take-off, a circle at 10 m, landing; attitude, local and global position, battery,
//! logged messages, a parameter change mid-flight.

use std::io::Write;

use ulog_core::read::LogLevel;
use ulog_core::write::{DefaultTypes, WriterOptions};
use ulog_core::{LogWriter, ULogMessage, WriteError};

type Result<T, E = WriteError> = core::result::Result<T, E>;

/// `vehicle_attitude`: the attitude quaternion.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct VehicleAttitude {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Attitude quaternion (w, x, y, z).
    pub q: [f32; 4],
    /// Padding to 8-byte alignment, as PX4 lays the message out.
    pub _padding0: [u8; 8],
}

/// `vehicle_local_position`: position and velocity in metres (NED).
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct VehicleLocalPosition {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// North, metres.
    pub x: f32,
    /// East, metres.
    pub y: f32,
    /// Down, metres.
    pub z: f32,
    /// North velocity, m/s.
    pub vx: f32,
    /// East velocity, m/s.
    pub vy: f32,
    /// Down velocity, m/s.
    pub vz: f32,
    /// Whether x and y are valid.
    pub xy_valid: bool,
    /// Whether z is valid.
    pub z_valid: bool,
    /// Trailing padding.
    pub _padding0: [u8; 6],
}

/// `vehicle_gps_position`: a GPS fix.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct VehicleGpsPosition {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Latitude, degrees.
    pub latitude_deg: f64,
    /// Longitude, degrees.
    pub longitude_deg: f64,
    /// Altitude above mean sea level, metres.
    pub altitude_msl_m: f64,
    /// Fix type (3: 3D).
    pub fix_type: u8,
    /// Satellites used.
    pub satellites_used: u8,
    /// Trailing padding.
    pub _padding0: [u8; 6],
}

/// `battery_status`.
#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
pub struct BatteryStatus {
    /// Microseconds since boot.
    pub timestamp: u64,
    /// Voltage, volts.
    pub voltage_v: f32,
    /// Current, amperes.
    pub current_a: f32,
    /// Charge drawn so far, mAh.
    pub discharged_mah: f32,
    /// Remaining charge, 0 to 1.
    pub remaining: f32,
    /// Cells in series.
    pub cell_count: u8,
    /// Trailing padding.
    pub _padding0: [u8; 7],
}

/// Where the simulated flight takes off.
pub const HOME: (f64, f64, f64) = (47.397_742, 8.545_594, 488.0);
/// Length of the flight in seconds.
pub const DURATION_S: f64 = 60.0;
/// Logging starts at this boot time (microseconds).
pub const START_US: u64 = 2_000_000;

fn quaternion(yaw: f32) -> [f32; 4] {
    [(yaw / 2.0).cos(), 0.0, 0.0, (yaw / 2.0).sin()]
}

/// Writes the simulated flight as a ULog file to `out`; returns it back.
pub fn simulate_flight<W: Write>(out: W) -> Result<W> {
    let mut w = LogWriter::with_options(out, START_US, WriterOptions::default())?;
    w.info("sys_name", "PX4")?;
    w.info("ver_hw", "SITL_RUST")?;
    w.info("ver_sw", "ulog-rs simulated flight")?;
    w.info("ver_sw_release", &0x010f_00ffu32)?;
    w.info("time_ref_utc", &0i32)?;
    w.multi_info(
        "boot_console_output",
        "INFO  [init] simulated vehicle\n",
        false,
    )?;
    w.param("MPC_XY_CRUISE", 5.0f32)?;
    w.param("MIS_TAKEOFF_ALT", 10.0f32)?;
    w.param("SYS_AUTOSTART", 4001i32)?;
    w.default_param("MPC_XY_CRUISE", 5.0f32, DefaultTypes::BOTH)?;
    let att = w.subscribe::<VehicleAttitude>(0)?;
    let pos = w.subscribe::<VehicleLocalPosition>(0)?;
    let gps = w.subscribe::<VehicleGpsPosition>(0)?;
    let bat = w.subscribe::<BatteryStatus>(0)?;
    let mut d = w.start_data()?;
    d.log(
        LogLevel::Info,
        START_US,
        "[commander] Armed by external command",
    )?;

    let radius = 20.0f64;
    let steps = (DURATION_S * 50.0) as u64; // 50 Hz
    let mut discharged = 0.0f32;
    for i in 0..=steps {
        let t_s = i as f64 / 50.0;
        let t = START_US + (t_s * 1e6) as u64;
        // Climb for 10 s, circle for 40 s, descend for 10 s.
        let (alt, climb) = if t_s < 10.0 {
            (t_s, 1.0)
        } else if t_s < 50.0 {
            (10.0, 0.0)
        } else {
            (10.0 - (t_s - 50.0), -1.0)
        };
        let angle = if t_s < 10.0 {
            0.0
        } else {
            ((t_s - 10.0) / 40.0).min(1.0) * std::f64::consts::TAU
        };
        let speed = if (10.0..50.0).contains(&t_s) {
            radius * std::f64::consts::TAU / 40.0
        } else {
            0.0
        };
        let (x, y) = (radius * angle.sin(), radius * (1.0 - angle.cos()));
        let (vx, vy) = (speed * angle.cos(), speed * angle.sin());
        d.write(
            &att,
            &VehicleAttitude {
                timestamp: t,
                q: quaternion(angle as f32),
                _padding0: [0; 8],
            },
        )?;
        if i % 2 == 0 {
            d.write(
                &pos,
                &VehicleLocalPosition {
                    timestamp: t,
                    x: x as f32,
                    y: y as f32,
                    z: -alt as f32,
                    vx: vx as f32,
                    vy: vy as f32,
                    vz: -climb as f32,
                    xy_valid: true,
                    z_valid: true,
                    _padding0: [0; 6],
                },
            )?;
        }
        if i % 10 == 0 {
            let m_per_deg = 111_320.0;
            d.write(
                &gps,
                &VehicleGpsPosition {
                    timestamp: t,
                    latitude_deg: HOME.0 + x / m_per_deg,
                    longitude_deg: HOME.1 + y / (m_per_deg * HOME.0.to_radians().cos()),
                    altitude_msl_m: HOME.2 + alt,
                    fix_type: 3,
                    satellites_used: 14,
                    _padding0: [0; 6],
                },
            )?;
            let current = if alt > 0.1 { 18.0 } else { 1.0 };
            discharged += current * 1000.0 * 0.2 / 3600.0;
            d.write(
                &bat,
                &BatteryStatus {
                    timestamp: t,
                    voltage_v: 16.8 - discharged / 1000.0,
                    current_a: current,
                    discharged_mah: discharged,
                    remaining: 1.0 - discharged / 5000.0,
                    cell_count: 4,
                    _padding0: [0; 7],
                },
            )?;
        }
        if i == 500 {
            d.log(
                LogLevel::Info,
                t,
                "[navigator] Takeoff complete, starting the circle",
            )?;
        }
        if i == 1500 {
            d.param("MPC_XY_CRUISE", 6.5f32)?;
            d.tagged_log(LogLevel::Warning, 1, t, "wind above 8 m/s")?;
        }
        if i == 2500 {
            d.log(LogLevel::Info, t, "[navigator] Landing")?;
        }
    }
    d.log(
        LogLevel::Info,
        START_US + (DURATION_S * 1e6) as u64,
        "[commander] Disarmed",
    )?;
    d.finish()
}
