//! What the report reads through typed bindings: attitude (Euler angles from the
//! quaternions), flight modes and arming, takeoff and landing, the local track and the
//! summary's distance, altitude, speed and battery figures.
//!
//! One struct per topic, whatever the firmware: fields that only some firmware logs
//! are `Option`s, and the reader finds the rest by name.

use serde::Serialize;
use ulog_core::{ULog, ULogMessage};

use super::table::{Builder, Table};
use crate::report::plots::Plot;

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitude {
    timestamp: u64,
    /// Since 2017.
    q: Option<[f32; 4]>,
    /// Before.
    roll: Option<f32>,
    pitch: Option<f32>,
    yaw: Option<f32>,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleAttitudeSetpoint {
    timestamp: u64,
    /// Until 2024 (PX4 v1.15 logs only the quaternion).
    roll_body: Option<f32>,
    pitch_body: Option<f32>,
    yaw_body: Option<f32>,
    q_d: Option<[f32; 4]>,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleStatus {
    timestamp: u64,
    nav_state: u8,
    arming_state: u8,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleLandDetected {
    timestamp: u64,
    landed: bool,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct VehicleLocalPosition {
    timestamp: u64,
    x: f32,
    y: f32,
    z: f32,
    vx: f32,
    vy: f32,
    vz: f32,
    xy_valid: bool,
}

#[derive(ULogMessage, Debug, Clone, Copy)]
struct BatteryStatus {
    timestamp: u64,
    voltage_v: f32,
    remaining: f32,
    discharged_mah: Option<f32>,
}

/// Roll, pitch and yaw (degrees) of a unit quaternion (w, x, y, z), as PX4's
/// `matrix::Eulerf` gives them.
fn euler(q: [f32; 4]) -> [f32; 3] {
    let [w, x, y, z] = q.map(f64::from);
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    [roll, pitch, yaw].map(|a| a.to_degrees() as f32)
}

/// The roll, pitch and yaw plots (estimate and setpoint), where the log has attitude.
pub fn attitude(log: &ULog<'_>, start_us: u64, end_us: u64) -> Vec<Plot> {
    let estimate = log.read::<VehicleAttitude>(0).ok().map(|rows| {
        let mut b = Builder::new(names("estimate"), rows.len(), start_us, end_us);
        for a in rows.iter().filter_map(Result::ok) {
            let angles = match (a.q, a.roll, a.pitch, a.yaw) {
                (Some(q), ..) => euler(q),
                (None, Some(r), Some(p), Some(y)) => [r, p, y].map(f32::to_degrees),
                _ => continue,
            };
            b.push(a.timestamp, &angles);
        }
        b.finish()
    });
    let setpoint = log.read::<VehicleAttitudeSetpoint>(0).ok().map(|rows| {
        let mut b = Builder::new(names("setpoint"), rows.len(), start_us, end_us);
        for s in rows.iter().filter_map(Result::ok) {
            let angles = match (s.roll_body, s.pitch_body, s.yaw_body, s.q_d) {
                (Some(r), Some(p), Some(y), _) => [r, p, y].map(f32::to_degrees),
                (.., Some(q)) => euler(q),
                _ => continue,
            };
            b.push(s.timestamp, &angles);
        }
        b.finish()
    });
    let mut plots = Vec::new();
    for (axis, (id, title)) in [
        ("roll", "Roll angle"),
        ("pitch", "Pitch angle"),
        ("yaw", "Yaw angle"),
    ]
    .iter()
    .enumerate()
    {
        let mut plot = Plot {
            id: (*id).to_owned(),
            title: (*title).to_owned(),
            unit: "deg".into(),
            sources: Vec::new(),
            tables: Vec::new(),
        };
        for (table, topic) in [
            (&estimate, "vehicle_attitude"),
            (&setpoint, "vehicle_attitude_setpoint"),
        ] {
            if let Some(t) = table.as_ref().filter(|t| !t.x.is_empty()) {
                plot.sources.push(topic.to_owned());
                plot.tables.push(Table {
                    labels: vec![t.labels[axis].clone()],
                    x: t.x.clone(),
                    y: vec![t.y[axis].clone()],
                    thinned: t.thinned,
                });
            }
        }
        if !plot.tables.is_empty() {
            plots.push(plot);
        }
    }
    plots
}

fn names(what: &str) -> Vec<String> {
    ["roll", "pitch", "yaw"]
        .iter()
        .map(|a| format!("{a} {what}"))
        .collect()
}

/// The name of a PX4 flight mode (`vehicle_status.nav_state`).
pub fn mode_name(nav_state: u8) -> String {
    let name = match nav_state {
        0 => "Manual",
        1 => "Altitude",
        2 => "Position",
        3 => "Mission",
        4 => "Hold",
        5 => "Return",
        6 => "Position slow",
        10 => "Acro",
        12 => "Descend",
        13 => "Termination",
        14 => "Offboard",
        15 => "Stabilized",
        17 => "Takeoff",
        18 => "Land",
        19 => "Follow target",
        20 => "Precision land",
        21 => "Orbit",
        22 => "VTOL takeoff",
        n => return format!("mode {n}"),
    };
    name.to_owned()
}

/// A flight mode from one time to another (seconds since the log's start).
#[derive(Debug, Serialize)]
pub struct ModeBand {
    /// Start.
    pub t0: f64,
    /// End.
    pub t1: f64,
    /// `nav_state`.
    pub mode: u8,
    /// Its name.
    pub name: String,
}

/// A marked instant: arming, takeoff, a logged error.
#[derive(Debug, Serialize)]
pub struct Mark {
    /// Seconds since the log's start.
    pub t: f64,
    /// `arm`, `disarm`, `takeoff`, `landing`, `error`.
    pub kind: &'static str,
    /// What to show.
    pub text: String,
}

/// Flight modes, arming and takeoff/landing, and the armed time (seconds).
pub struct Timeline {
    /// The flight modes.
    pub modes: Vec<ModeBand>,
    /// Arming, disarming, takeoffs and landings.
    pub marks: Vec<Mark>,
    /// Time armed.
    pub armed_s: f64,
}

/// The log's modes and marks from `vehicle_status` and `vehicle_land_detected`.
pub fn timeline(log: &ULog<'_>, start_us: u64, end_us: u64) -> Timeline {
    let sec = |t: u64| (t as f64 - start_us as f64) / 1e6;
    let mut modes: Vec<ModeBand> = Vec::new();
    let mut marks = Vec::new();
    let mut armed_s = 0.0;
    if let Ok(rows) = log.read::<VehicleStatus>(0) {
        let mut armed_at: Option<f64> = None;
        // Rows PX4 never stamped left out, as in the plots.
        for s in rows
            .iter()
            .filter_map(Result::ok)
            .filter(|s| s.timestamp > 0 || start_us == 0)
        {
            let t = sec(s.timestamp);
            match modes.last_mut() {
                Some(m) if m.mode == s.nav_state => m.t1 = t,
                last => {
                    if let Some(m) = last {
                        m.t1 = t;
                    }
                    modes.push(ModeBand {
                        t0: t,
                        t1: t,
                        mode: s.nav_state,
                        name: mode_name(s.nav_state),
                    });
                }
            }
            let armed = s.arming_state == 2;
            match (armed, armed_at) {
                (true, None) => {
                    armed_at = Some(t);
                    marks.push(Mark {
                        t,
                        kind: "arm",
                        text: "armed".into(),
                    });
                }
                (false, Some(at)) => {
                    armed_s += t - at;
                    armed_at = None;
                    marks.push(Mark {
                        t,
                        kind: "disarm",
                        text: "disarmed".into(),
                    });
                }
                _ => {}
            }
        }
        if let Some(at) = armed_at {
            armed_s += sec(end_us) - at;
        }
        if let Some(m) = modes.last_mut() {
            m.t1 = m.t1.max(sec(end_us));
        }
    }
    if let Ok(rows) = log.read::<VehicleLandDetected>(0) {
        let mut landed: Option<bool> = None;
        for l in rows.iter().filter_map(Result::ok) {
            if landed.is_some_and(|was| was != l.landed) {
                marks.push(Mark {
                    t: sec(l.timestamp),
                    kind: if l.landed { "landing" } else { "takeoff" },
                    text: if l.landed { "landed" } else { "takeoff" }.into(),
                });
            }
            landed = Some(l.landed);
        }
    }
    Timeline {
        modes,
        marks,
        armed_s,
    }
}

/// Figures of the header from the local position estimate and the battery.
#[derive(Debug, Default)]
pub struct Figures {
    /// Metres flown (horizontal and vertical steps between valid estimates).
    pub distance_m: Option<f64>,
    /// Highest point above the first estimate, metres.
    pub max_altitude_m: Option<f64>,
    /// Fastest horizontal speed, m/s.
    pub max_speed_m_s: Option<f64>,
    /// (first, last) voltage with a battery connected, remaining fraction and mAh drawn.
    pub battery: Option<Battery>,
}

/// The battery's use over the log.
#[derive(Debug)]
pub struct Battery {
    /// Volts at the first and last reading.
    pub voltage: (f32, f32),
    /// Remaining fraction at the first and last reading.
    pub remaining: (f32, f32),
    /// Charge drawn, where logged.
    pub discharged_mah: Option<f32>,
}

/// A step between two estimates faster than this is a reset of the estimator's origin,
/// not flight.
const MAX_SPEED_M_S: f32 = 100.0;

/// The header's figures, where the log has the topics.
pub fn figures(log: &ULog<'_>) -> Figures {
    let mut f = Figures::default();
    if let Ok(rows) = log.read::<VehicleLocalPosition>(0) {
        let mut ground: Option<f32> = None;
        let mut prev: Option<VehicleLocalPosition> = None;
        let (mut distance, mut top, mut fastest) = (0f64, f32::NEG_INFINITY, 0f32);
        for p in rows.iter().filter_map(Result::ok) {
            if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                continue;
            }
            let g = *ground.get_or_insert(-p.z);
            top = top.max(-p.z - g);
            let speed = (p.vx * p.vx + p.vy * p.vy).sqrt();
            if speed.is_finite() {
                fastest = fastest.max(speed);
            }
            if let Some(a) = prev.filter(|a| a.xy_valid && p.xy_valid) {
                let (dx, dy, dz) = (p.x - a.x, p.y - a.y, p.z - a.z);
                let step = (dx * dx + dy * dy + dz * dz).sqrt();
                let dt = p.timestamp.saturating_sub(a.timestamp) as f32 / 1e6;
                if step <= MAX_SPEED_M_S * dt.max(1e-3) {
                    distance += f64::from(step);
                }
            }
            prev = Some(p);
        }
        if ground.is_some() {
            f.distance_m = Some(distance);
            f.max_altitude_m = Some(f64::from(top));
            f.max_speed_m_s = Some(f64::from(fastest));
        }
    }
    if let Ok(rows) = log.read::<BatteryStatus>(0) {
        // Before a battery is connected PX4 logs zeros.
        let readings: Vec<BatteryStatus> = rows
            .iter()
            .filter_map(Result::ok)
            .filter(|b| b.voltage_v > 1.0)
            .collect();
        if let (Some(a), Some(b)) = (readings.first(), readings.last()) {
            f.battery = Some(Battery {
                voltage: (a.voltage_v, b.voltage_v),
                remaining: (a.remaining, b.remaining),
                discharged_mah: b.discharged_mah.filter(|m| m.is_finite()),
            });
        }
    }
    f
}

/// The track in local metres (east, north) from the local position estimate, at
/// most `points` points (every n-th estimate).
pub fn track(log: &ULog<'_>, points: usize) -> Option<Vec<[f32; 2]>> {
    let rows = log.read::<VehicleLocalPosition>(0).ok()?;
    let step = rows.len().div_ceil(points.max(1)).max(1);
    let track: Vec<[f32; 2]> = rows
        .iter()
        .step_by(step)
        .filter_map(Result::ok)
        .filter(|p| p.xy_valid && p.x.is_finite() && p.y.is_finite())
        .map(|p| [p.y, p.x])
        .collect();
    (track.len() > 1).then_some(track)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_of_quaternions() {
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-3);
        assert!(close(euler([1.0, 0.0, 0.0, 0.0]), [0.0, 0.0, 0.0]));
        let h = (0.5f32).sqrt();
        assert!(close(euler([h, h, 0.0, 0.0]), [90.0, 0.0, 0.0]));
        assert!(close(euler([h, 0.0, 0.0, h]), [0.0, 0.0, 90.0]));
        // Pitch away from ±90°, where roll and yaw are undefined.
        let (c, s) = (15f32.to_radians().cos(), 15f32.to_radians().sin());
        assert!(close(euler([c, 0.0, s, 0.0]), [0.0, 30.0, 0.0]));
    }

    #[test]
    fn modes_have_names() {
        assert_eq!(mode_name(2), "Position");
        assert_eq!(mode_name(99), "mode 99");
    }
}
