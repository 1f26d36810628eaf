//! Flight statistics, battery figures and the accelerometer's vibration, each as its
//! rows come.

use super::topics::{
    BatteryStatus, VehicleAngularVelocity, VehicleAttitude, VehicleImuStatus, VehicleLocalPosition,
};

/// Distance, altitude, speeds, tilt and rotation over the log (Flight Review v2's
/// definitions: every row of the log, on the ground too).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct FlightStats {
    /// The length of the local position's path (3D) over every row, m (Flight Review
    /// v2's figure: estimator noise on the ground and origin resets count).
    pub total_distance_m: f64,
    /// Metres flown: the 3D steps between consecutive estimates that are both valid
    /// horizontally, a step faster than 100 m/s (an origin reset) left out.
    pub flown_distance_m: f64,
    /// The highest altitude minus the lowest (local position), m.
    pub max_altitude_diff_m: f64,
    /// The highest altitude above the first local position, m.
    pub max_altitude_above_start_m: f64,
    /// Fastest 3D speed, m/s.
    pub max_speed_m_s: f64,
    /// Fastest horizontal speed, m/s.
    pub max_horizontal_speed_m_s: f64,
    /// Fastest climb, m/s.
    pub max_speed_up_m_s: f64,
    /// Fastest descent, m/s.
    pub max_speed_down_m_s: f64,
    /// Mean 3D speed over the rows, m/s.
    pub avg_speed_m_s: f64,
    /// Largest tilt (angle between the body's z axis and the vertical), degrees.
    pub max_tilt_deg: f64,
    /// Fastest rotation (norm of the body rates), degrees/s.
    pub max_rotation_speed_deg_s: f64,
    /// Rows of `vehicle_local_position` read.
    pub position_rows: u64,
}

/// The battery (`battery_status` instance 0).
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct BatterySummary {
    /// Lowest voltage, V.
    pub min_voltage_v: Option<f64>,
    /// Mean current, A.
    pub avg_current_a: Option<f64>,
    /// Highest current, A.
    pub max_current_a: Option<f64>,
    /// Charge used, mAh (the last `discharged_mah`).
    pub discharged_mah: Option<f64>,
    /// The first and last voltage with a battery connected (above 1 V: before, PX4
    /// logs zeros), V.
    pub voltage_first_last_v: Option<(f32, f32)>,
    /// The remaining fraction (0–1) at those two readings.
    pub remaining_first_last: Option<(f32, f32)>,
}

/// The accelerometer's vibration (`vehicle_imu_status.accel_vibration_metric`, every
/// IMU), m/s².
#[derive(Debug, Clone, Default, PartialEq)]
#[non_exhaustive]
pub struct VibrationSummary {
    /// Mean over every row.
    pub accel_vibe_mean: Option<f64>,
    /// Highest.
    pub accel_vibe_max: Option<f64>,
    /// `good`, `warning` or `critical`: the worse of the mean's (from 4.905 warning,
    /// from 9.81 critical) and the peak's (from 9.81, 19.62); `unknown` without rows.
    pub status: &'static str,
}

/// The statistics being gathered.
#[derive(Default)]
pub(super) struct Stats {
    s: FlightStats,
    prev: Option<[f32; 3]>,
    /// The last estimate valid horizontally (time, position), for the distance flown.
    prev_valid: Option<(u64, [f32; 3])>,
    z_range: Option<(f32, f32)>,
    z_start: Option<f32>,
    speed_sum: f64,
    speed_rows: u64,
    tilt_rad: f32,
    rate_rad_s: f32,
    rate_rows: u64,
    attitude_rate_rad_s: f32,
    battery: BatterySummary,
    current_sum: f64,
    current_rows: u64,
    vibe_sum: f64,
    vibe_rows: u64,
    vibe_max: f32,
}

/// A step between two estimates faster than this is a reset of the estimator's
/// origin, not flight.
const MAX_FLOWN_SPEED_M_S: f32 = 100.0;

fn finite3(v: [f32; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn norm(v: [f32; 3]) -> f32 {
    v.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>().sqrt() as f32
}

impl Stats {
    pub(super) fn position(&mut self, p: &VehicleLocalPosition) {
        self.s.position_rows += 1;
        let at = [p.x, p.y, p.z];
        // A row without a finite position is skipped; one not valid horizontally
        // breaks the path flown.
        if finite3(at) && p.xy_valid == Some(false) {
            self.prev_valid = None;
        } else if finite3(at) {
            if let Some((t0, a)) = self.prev_valid {
                let d: [f32; 3] = std::array::from_fn(|i| at[i] - a[i]);
                let step = norm(d);
                let dt = p.timestamp.saturating_sub(t0) as f32 * 1e-6;
                if step <= MAX_FLOWN_SPEED_M_S * dt.max(1e-3) {
                    self.s.flown_distance_m += f64::from(step);
                }
            }
            self.prev_valid = Some((p.timestamp, at));
        }
        if finite3(at) {
            if let Some(prev) = self.prev {
                let d: [f32; 3] = std::array::from_fn(|i| at[i] - prev[i]);
                self.s.total_distance_m += f64::from(norm(d));
            }
            self.prev = Some(at);
            let (lo, hi) = self.z_range.get_or_insert((p.z, p.z));
            *lo = lo.min(p.z);
            *hi = hi.max(p.z);
            let start = *self.z_start.get_or_insert(p.z);
            // NED: up is −z.
            self.s.max_altitude_above_start_m = self
                .s
                .max_altitude_above_start_m
                .max(f64::from(start - p.z));
        }
        let horizontal = norm([p.vx, p.vy, 0.0]);
        if horizontal.is_finite() {
            let s = &mut self.s;
            s.max_horizontal_speed_m_s = s.max_horizontal_speed_m_s.max(f64::from(horizontal));
        }
        let v = [p.vx, p.vy, p.vz];
        if finite3(v) {
            let s = &mut self.s;
            let speed = norm(v);
            s.max_speed_m_s = s.max_speed_m_s.max(f64::from(speed));
            s.max_speed_up_m_s = s.max_speed_up_m_s.max(f64::from(-p.vz));
            s.max_speed_down_m_s = s.max_speed_down_m_s.max(f64::from(p.vz));
            self.speed_sum += f64::from(speed);
            self.speed_rows += 1;
        }
    }

    pub(super) fn attitude(&mut self, a: &VehicleAttitude) {
        let (roll, pitch) = match (a.q, a.roll, a.pitch) {
            (Some([w, x, y, z]), _, _) => {
                let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
                let sin_pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0);
                (roll, sin_pitch.asin())
            }
            (None, Some(roll), Some(pitch)) => (roll, pitch),
            _ => return,
        };
        let tilt = (roll.cos() * pitch.cos()).clamp(-1.0, 1.0).acos();
        if tilt.is_finite() {
            self.tilt_rad = self.tilt_rad.max(tilt);
        }
        if let (Some(x), Some(y), Some(z)) = (a.rollspeed, a.pitchspeed, a.yawspeed) {
            if finite3([x, y, z]) {
                self.attitude_rate_rad_s = self.attitude_rate_rad_s.max(norm([x, y, z]));
            }
        }
    }

    pub(super) fn rates(&mut self, r: &VehicleAngularVelocity) {
        if finite3(r.xyz) {
            self.rate_rows += 1;
            self.rate_rad_s = self.rate_rad_s.max(norm(r.xyz));
        }
    }

    pub(super) fn battery(&mut self, b: &BatteryStatus) {
        let bat = &mut self.battery;
        if b.current_a.is_finite() && b.current_a >= 0.0 {
            let c = f64::from(b.current_a);
            self.current_sum += c;
            self.current_rows += 1;
            bat.max_current_a = Some(bat.max_current_a.map_or(c, |m| m.max(c)));
        }
        if b.voltage_v.is_finite() && b.voltage_v > 0.0 {
            let v = f64::from(b.voltage_v);
            bat.min_voltage_v = Some(bat.min_voltage_v.map_or(v, |m| m.min(v)));
        }
        if b.voltage_v > 1.0 {
            let (first, _) = bat.voltage_first_last_v.unwrap_or((b.voltage_v, 0.0));
            bat.voltage_first_last_v = Some((first, b.voltage_v));
            if let Some(r) = b.remaining {
                let (first, _) = bat.remaining_first_last.unwrap_or((r, 0.0));
                bat.remaining_first_last = Some((first, r));
            }
        }
        if let Some(d) = b.discharged_mah.filter(|d| d.is_finite() && *d >= 0.0) {
            bat.discharged_mah = Some(f64::from(d));
        }
    }

    pub(super) fn imu(&mut self, i: &VehicleImuStatus) {
        let v = i.accel_vibration_metric;
        if v.is_finite() && v >= 0.0 {
            self.vibe_sum += f64::from(v);
            self.vibe_rows += 1;
            self.vibe_max = self.vibe_max.max(v);
        }
    }

    pub(super) fn finish(mut self) -> (FlightStats, BatterySummary, VibrationSummary) {
        let s = &mut self.s;
        if let Some((lo, hi)) = self.z_range {
            s.max_altitude_diff_m = f64::from(hi - lo);
        }
        if self.speed_rows > 0 {
            s.avg_speed_m_s = self.speed_sum / self.speed_rows as f64;
        }
        s.max_tilt_deg = f64::from(self.tilt_rad).to_degrees();
        // Logs before 2019 have the body rates in the attitude.
        let rate = if self.rate_rows > 0 {
            self.rate_rad_s
        } else {
            self.attitude_rate_rad_s
        };
        s.max_rotation_speed_deg_s = f64::from(rate).to_degrees();
        if self.current_rows > 0 {
            self.battery.avg_current_a = Some(self.current_sum / self.current_rows as f64);
        }
        let vibration = if self.vibe_rows == 0 {
            VibrationSummary {
                status: "unknown",
                ..VibrationSummary::default()
            }
        } else {
            let mean = self.vibe_sum / self.vibe_rows as f64;
            let max = f64::from(self.vibe_max);
            let grade = |v: f64, warn: f64| usize::from(v >= warn) + usize::from(v >= 2.0 * warn);
            let status = ["good", "warning", "critical"][grade(mean, 4.905).max(grade(max, 9.81))];
            VibrationSummary {
                accel_vibe_mean: Some(mean),
                accel_vibe_max: Some(max),
                status,
            }
        };
        (self.s, self.battery, vibration)
    }
}
