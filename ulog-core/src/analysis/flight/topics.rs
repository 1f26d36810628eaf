//! The topics the flight analysis reads: one binding per topic for every PX4 firmware
//! the corpus has (v1.7 to v1.16), fields only some firmware logs as `Option`s.

use crate::{ULogMessage, ULogTopics};

/// `vehicle_status`: arming, flight mode, vehicle type.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleStatus {
    pub timestamp: u64,
    /// 2 is armed in every firmware.
    pub arming_state: u8,
    pub nav_state: u8,
    /// Since 2017.
    pub vehicle_type: Option<u8>,
    pub in_transition_mode: Option<bool>,
}

/// `vehicle_land_detected`: takeoffs and landings.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleLandDetected {
    pub timestamp: u64,
    pub landed: bool,
}

/// `battery_status`.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct BatteryStatus {
    pub timestamp: u64,
    pub voltage_v: f32,
    pub voltage_filtered_v: Option<f32>,
    pub current_a: f32,
    pub remaining: Option<f32>,
    pub discharged_mah: Option<f32>,
    /// `int32_t` until 2020, `uint8_t` since (widened); absent in the oldest logs.
    pub cell_count: Option<i32>,
}

/// `estimator_status`: the EKF's innovation test ratios.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct EstimatorStatus {
    pub timestamp: u64,
    pub vel_test_ratio: Option<f32>,
    pub pos_test_ratio: Option<f32>,
    pub hgt_test_ratio: Option<f32>,
}

/// The GPS fix: `vehicle_gps_position`, or `sensor_gps` in logs that do not have it.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate", name = "vehicle_gps_position", alias = "sensor_gps")]
pub(super) struct GpsPosition {
    pub timestamp: u64,
    pub fix_type: u8,
    pub satellites_used: u8,
    pub eph: f32,
    pub epv: f32,
    pub hdop: Option<f32>,
    pub jamming_indicator: Option<i32>,
    pub noise_per_ms: Option<i32>,
}

/// `actuator_outputs`: what each output was driven with (PWM in µs on most vehicles).
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct ActuatorOutputs {
    pub timestamp: u64,
    pub noutputs: u32,
    pub output: [f32; 16],
}

/// `input_rc`: the RC receiver.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct InputRc {
    pub timestamp: u64,
    pub rc_lost: bool,
}

/// `vehicle_local_position` (NED, metres).
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleLocalPosition {
    pub timestamp: u64,
    /// Absent in the oldest logs: every estimate counts as valid there.
    pub xy_valid: Option<bool>,
    pub x: f32,
    pub y: f32,
    pub z: f32,
    pub vx: f32,
    pub vy: f32,
    pub vz: f32,
}

/// `vehicle_attitude`: the quaternion since 2017, Euler angles before.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleAttitude {
    pub timestamp: u64,
    pub q: Option<[f32; 4]>,
    pub roll: Option<f32>,
    pub pitch: Option<f32>,
    /// The body rates, in the attitude until 2019.
    pub rollspeed: Option<f32>,
    pub pitchspeed: Option<f32>,
    pub yawspeed: Option<f32>,
}

/// `vehicle_angular_velocity` (since 2019): the controllers' body rates, rad/s.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleAngularVelocity {
    pub timestamp: u64,
    pub xyz: [f32; 3],
}

/// `vehicle_rates_setpoint`: the rate controllers' setpoints, rad/s.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleRatesSetpoint {
    pub timestamp: u64,
    pub roll: f32,
    pub pitch: f32,
    pub yaw: f32,
}

/// `vehicle_imu_status` (since 2020): the accelerometer's vibration metric.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleImuStatus {
    pub timestamp: u64,
    pub accel_vibration_metric: f32,
}

/// `sensor_combined`: the raw IMU, for the spectra.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct SensorCombined {
    pub timestamp: u64,
    pub gyro_rad: [f32; 3],
    pub accelerometer_m_s2: [f32; 3],
}

/// `actuator_controls_0` (until 2023): the controllers' outputs, roll, pitch, yaw,
/// thrust first.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate", name = "actuator_controls_0")]
pub(super) struct ActuatorControls {
    pub timestamp: u64,
    pub control: [f32; 8],
}

/// `vehicle_torque_setpoint` (since 2021): the rate controllers' torque outputs.
#[derive(ULogMessage, Debug, Clone, Copy)]
#[ulog(crate = "crate")]
pub(super) struct VehicleTorqueSetpoint {
    pub timestamp: u64,
    pub xyz: [f32; 3],
}

/// Every topic the analysis reads, decoded in one pass.
#[derive(ULogTopics, Debug)]
#[ulog(crate = "crate")]
pub(super) enum FlightTopic {
    Status(VehicleStatus),
    Land(VehicleLandDetected),
    Battery(BatteryStatus),
    Estimator(EstimatorStatus),
    Gps(GpsPosition),
    Outputs(ActuatorOutputs),
    Rc(InputRc),
    Position(VehicleLocalPosition),
    Attitude(VehicleAttitude),
    Rates(VehicleAngularVelocity),
    RatesSetpoint(VehicleRatesSetpoint),
    Imu(VehicleImuStatus),
    Sensors(SensorCombined),
    Controls(ActuatorControls),
    Torque(VehicleTorqueSetpoint),
}

impl FlightTopic {
    /// The row's time, µs.
    pub(super) fn timestamp(&self) -> u64 {
        match self {
            FlightTopic::Status(m) => m.timestamp,
            FlightTopic::Land(m) => m.timestamp,
            FlightTopic::Battery(m) => m.timestamp,
            FlightTopic::Estimator(m) => m.timestamp,
            FlightTopic::Gps(m) => m.timestamp,
            FlightTopic::Outputs(m) => m.timestamp,
            FlightTopic::Rc(m) => m.timestamp,
            FlightTopic::Position(m) => m.timestamp,
            FlightTopic::Attitude(m) => m.timestamp,
            FlightTopic::Rates(m) => m.timestamp,
            FlightTopic::RatesSetpoint(m) => m.timestamp,
            FlightTopic::Imu(m) => m.timestamp,
            FlightTopic::Sensors(m) => m.timestamp,
            FlightTopic::Controls(m) => m.timestamp,
            FlightTopic::Torque(m) => m.timestamp,
        }
    }
}
