//! A replay tool end to end: bindings from a reference log at compile time
//! (`ulog_module!`), the admission check of a log against them, then its IMU
//! (`sensor_combined`) replayed through a `ulog_core::replay::Player` into a small
//! attitude filter, whose estimate is written with the writer into a new log beside
//! the logged `vehicle_attitude`.
//!
//! ```text
//! cargo run -p ulog-examples --example replay_attitude -- [--rate X] [LOG.ulg [OUT.ulg]]
//! ```
//!
//! Without a path it replays the repository's bench log
//! (`tests/corpus/files/sample_appended_multiple.ulg`, the log the reference
//! `data/attitude_reference.ulg` was made of) into `replay_attitude.ulg` in the
//! current directory. The IMU is replayed as fast as possible, or with `--rate X` on
//! the log's clock × X (`--rate 1`: real time), releases later than 1 ms counted.
//!
//! - **Admission**: `sensor_combined` and `vehicle_attitude` of the log are checked
//!   against the bindings generated from the reference; a log whose formats do not fit
//!   is refused with every difference and both formats. A format that gained or moved
//!   fields is read by name, and said so.
//! - **Replay**: the steps are `sensor_combined`'s rows (`ULog::align`); at each, a
//!   `#[derive(Aligned)]` struct of the IMU row and the logged attitude interpolated to
//!   it (`method = "linear"`, quaternions by slerp) goes through the player, which
//!   pulls the steps from the log one at a time.
//! - **Filter**: a complementary filter (Mahony's): the gyro integrated over the time
//!   between rows, roll and pitch pulled toward the gravity the accelerometer measures
//!   (with the gyro's bias learned from that pull). It starts from the logged attitude
//!   at the first step that has one. Yaw has no absolute reference here (no
//!   magnetometer is used): it starts from the log's, then follows the gyro alone and
//!   drifts with its bias.
//! - **Output**: a log with `vehicle_attitude` instance 0 (the logged estimate, row for
//!   row) and instance 1 (the filter's, one row per IMU step from its start), in the
//!   reference's format. `ulog plot OUT.ulg vehicle_attitude.q vehicle_attitude:1.q`
//!   draws both; `ulog report OUT.ulg` draws both in its roll, pitch and yaw plots.
//!   The RMS angle errors against the logged estimate are printed.
//!
//! Exit status: 0 replayed, 1 refused, 2 unreadable or not written.

use std::error::Error;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use ulog_core::align::{AlignOptions, Aligned, Grid};
use ulog_core::replay::{Clock, Pace, Player, PlayerOptions, SystemClock};
use ulog_core::typed::{BindingVisitor, PlanKind, TypedErrorKind};
use ulog_core::{LogFile, LogWriter, ULog, ULogMessage};
use ulog_examples::ATTITUDE_SOURCE_LOG;

// One struct per format of the reference log, checked when this tool is compiled.
ulog_core::ulog_module!(pub mod px4 = "data/attitude_reference.ulg");

/// What the admission check found, per topic.
#[derive(Debug, Default)]
pub struct Admission {
    /// Why the log is refused: each topic that does not fit, with every difference.
    pub refused: Vec<String>,
    /// What was accepted, and how.
    pub accepted: Vec<String>,
}

/// Checks the log's instance 0 of each topic of the reference against its binding.
pub fn admit(log: &ULog<'_>) -> Admission {
    struct Check<'l, 'a> {
        log: &'l ULog<'a>,
        out: Admission,
    }
    impl BindingVisitor for Check<'_, '_> {
        fn visit<T: ULogMessage>(&mut self) {
            // One check per subscription; after it, rows decode without lookups.
            match self.log.read::<T>(0) {
                Ok(rows) if rows.plan().kind() == PlanKind::Mapped => {
                    self.out.accepted.push(format!(
                        "{}: format changed, fields found by name ({} rows)",
                        T::NAME,
                        rows.len()
                    ))
                }
                Ok(rows) => {
                    self.out
                        .accepted
                        .push(format!("{}: same format, {} rows", T::NAME, rows.len()))
                }
                Err(e) => self.out.refused.push(match e.kind() {
                    TypedErrorKind::Mismatch(m) => m.to_string(),
                    _ => e.to_string(),
                }),
            }
        }
    }
    let mut check = Check {
        log,
        out: Admission::default(),
    };
    px4::visit_bindings(&mut check);
    check.out
}

/// One step of the replay: the IMU row, and the logged attitude at its time; both
/// bindings checked against the log together when the alignment is read.
#[derive(Aligned, Debug, Clone, Copy)]
pub struct Step {
    /// The step's own `sensor_combined` row (none for a row shorter than the
    /// format: damage).
    pub imu: Option<px4::SensorCombined>,
    /// The logged estimate interpolated to the step (none before its first row or
    /// after its last).
    #[ulog(method = "linear")]
    pub logged: Option<px4::VehicleAttitude>,
}

/// The proportional gain of the accelerometer's pull on roll and pitch (rad/s per
/// unit of error): a time constant of about a second, long against the vibration the
/// accelerometer sees, short against the gyro's drift.
const KP: f64 = 1.0;
/// The integral gain that learns the gyro's bias from the same pull (rad/s² per
/// unit): over some tens of seconds.
const KI: f64 = 0.05;
/// Standard gravity, m/s².
const G: f64 = 9.80665;
/// A gap between IMU rows longer than this (a dropout) is not integrated: the rate
/// over it is unknown.
const MAX_DT_S: f64 = 0.5;

/// A Mahony-style complementary filter of attitude (quaternion `w, x, y, z`, body to
/// NED, as PX4 logs it).
#[derive(Debug, Clone)]
pub struct AttitudeFilter {
    q: [f64; 4],
    bias: [f64; 3],
    t_us: u64,
}

impl AttitudeFilter {
    /// The filter at attitude `q` at time `t_us`.
    pub fn new(q: [f32; 4], t_us: u64) -> AttitudeFilter {
        AttitudeFilter {
            q: normalised(q.map(f64::from)),
            bias: [0.0; 3],
            t_us,
        }
    }

    /// The estimate.
    pub fn q(&self) -> [f32; 4] {
        self.q.map(|v| v as f32)
    }

    /// Takes an IMU row at `t_us`: `gyro` rad/s and `accel` m/s² in body axes (FRD).
    /// Returns the corrected body rates.
    pub fn update(&mut self, t_us: u64, gyro: [f32; 3], accel: [f32; 3]) -> [f64; 3] {
        let dt = t_us.saturating_sub(self.t_us) as f64 * 1e-6;
        self.t_us = t_us;
        let mut w = gyro.map(f64::from);
        let a = accel.map(f64::from);
        let norm = dot(a, a).sqrt();
        // Only near 1 g is the accelerometer mostly gravity (not a manoeuvre, not a
        // free fall); otherwise the gyro alone.
        if (0.5 * G..1.5 * G).contains(&norm) {
            let a = a.map(|v| v / norm);
            // The specific force at rest ("up") in body axes, as the estimate has it.
            let [qw, qx, qy, qz] = self.q;
            let up = [
                -2.0 * (qx * qz - qw * qy),
                -2.0 * (qy * qz + qw * qx),
                -(qw * qw - qx * qx - qy * qy + qz * qz),
            ];
            // The rotation that takes the estimate's "up" to the measured one; it has
            // no part about gravity, so yaw is not corrected.
            let e = cross(a, up);
            let integrate = dt > 0.0 && dt <= MAX_DT_S;
            for ((w, b), e) in w.iter_mut().zip(&mut self.bias).zip(e) {
                if integrate {
                    *b += KI * e * dt;
                }
                *w += KP * e + *b;
            }
        }
        if dt > 0.0 && dt <= MAX_DT_S {
            self.q = normalised(multiply(self.q, rotation(w.map(|v| v * dt))));
        }
        w
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalised(q: [f64; 4]) -> [f64; 4] {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / n)
}

/// The Hamilton product `a ⊗ b`.
fn multiply(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [aw, ax, ay, az] = a;
    let [bw, bx, by, bz] = b;
    [
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ]
}

/// The quaternion of rotation vector `r` (radians): exact for any step, so that a
/// log's slower IMU rows integrate as well as fast ones.
fn rotation(r: [f64; 3]) -> [f64; 4] {
    let angle = dot(r, r).sqrt();
    if angle < 1e-12 {
        return [1.0, r[0] / 2.0, r[1] / 2.0, r[2] / 2.0];
    }
    let s = (angle / 2.0).sin() / angle;
    [(angle / 2.0).cos(), r[0] * s, r[1] * s, r[2] * s]
}

/// Roll, pitch and yaw (radians) of a quaternion, as PX4's `matrix::Eulerf` gives
/// them.
pub fn euler(q: [f32; 4]) -> [f64; 3] {
    let [w, x, y, z] = q.map(f64::from);
    [
        (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y)),
        (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin(),
        (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
    ]
}

/// The angle (radians) of the rotation between two attitudes.
pub fn angle_between(a: [f32; 4], b: [f32; 4]) -> f64 {
    let d: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| f64::from(*x) * f64::from(y))
        .sum();
    2.0 * d.abs().min(1.0).acos()
}

/// What a replay did.
#[derive(Debug, Clone, PartialEq)]
pub struct Replayed {
    /// IMU steps released by the player.
    pub steps: usize,
    /// Rows of the logged estimate written (instance 0).
    pub logged_rows: usize,
    /// Rows of the filter's estimate written (instance 1).
    pub estimates: usize,
    /// The log time the filter started at (the first step with a logged attitude).
    pub start_us: Option<u64>,
    /// Steps compared with the logged estimate.
    pub compared: usize,
    /// RMS error against the logged estimate, degrees: roll, pitch, yaw, and the
    /// whole rotation between the two.
    pub rms_deg: [f64; 4],
    /// Releases later than the player's threshold (paced replays).
    pub late: u64,
    /// The latest release after its due time.
    pub worst_lateness: Duration,
}

/// Replays `log`'s IMU through the filter on `clock` at `pace`, and writes the logged
/// and the estimated attitude to `out`, which is given back.
pub fn replay<C: Clock, W: Write>(
    log: &ULog<'_>,
    clock: C,
    pace: Pace,
    out: W,
) -> Result<(Replayed, W), Box<dyn Error>> {
    let steps = log.align(&Grid::topic("sensor_combined", 0), &AlignOptions::default())?;
    // The player pulls the steps one by one from the log: nothing is copied ahead.
    let items = steps.read::<Step>()?;

    let mut w = LogWriter::new(out, log.start_timestamp())?;
    w.info("sys_name", "PX4")?;
    w.info("ver_sw", "ulog-rs replay_attitude")?;
    let logged_handle = w.subscribe::<px4::VehicleAttitude>(0)?;
    let estimate_handle = w.subscribe::<px4::VehicleAttitude>(1)?;
    let mut data = w.start_data()?;
    // The logged rows as logged, merged in time with the estimates as they come.
    let logged_rows = log.read::<px4::VehicleAttitude>(0)?;
    let mut logged_rows = logged_rows.iter().filter_map(Result::ok).peekable();

    let options = PlayerOptions {
        pace,
        ..PlayerOptions::default()
    };
    let player = Player::new(items, clock, options)?;
    let mut filter: Option<AttitudeFilter> = None;
    let mut out = Replayed {
        steps: 0,
        logged_rows: 0,
        estimates: 0,
        start_us: None,
        compared: 0,
        rms_deg: [0.0; 4],
        late: 0,
        worst_lateness: Duration::ZERO,
    };
    let mut squares = [0.0f64; 4];
    for release in player {
        out.steps += 1;
        out.late += u64::from(release.late);
        out.worst_lateness = out.worst_lateness.max(release.lateness);
        let (t, step) = (release.t_us, release.item);
        let Some(imu) = step.imu else { continue };
        let rates = match &mut filter {
            Some(f) => f.update(t, imu.gyro_rad, imu.accelerometer_m_s2),
            None => match step.logged {
                Some(att) => {
                    filter = Some(AttitudeFilter::new(att.q, t));
                    out.start_us = Some(t);
                    imu.gyro_rad.map(f64::from)
                }
                None => continue,
            },
        };
        let Some(f) = &filter else { continue };
        while let Some(row) = logged_rows.next_if(|r| r.timestamp <= t) {
            data.write(&logged_handle, &row)?;
            out.logged_rows += 1;
        }
        let estimate = px4::VehicleAttitude {
            timestamp: t,
            rollspeed: rates[0] as f32,
            pitchspeed: rates[1] as f32,
            yawspeed: rates[2] as f32,
            q: f.q(),
            _padding0: [0; 4],
        };
        data.write(&estimate_handle, &estimate)?;
        out.estimates += 1;
        if let Some(att) = step.logged {
            let (mine, theirs) = (euler(estimate.q), euler(att.q));
            for i in 0..3 {
                // Wrapped: 179° and -179° are 2° apart.
                let d = (mine[i] - theirs[i] + std::f64::consts::PI)
                    .rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI;
                squares[i] += d * d;
            }
            squares[3] += angle_between(estimate.q, att.q).powi(2);
            out.compared += 1;
        }
    }
    for row in logged_rows {
        data.write(&logged_handle, &row)?;
        out.logged_rows += 1;
    }
    let n = out.compared.max(1) as f64;
    out.rms_deg = squares.map(|s| (s / n).sqrt().to_degrees());
    Ok((out, data.finish()?))
}

fn main() -> ExitCode {
    let mut pace = Pace::AsFastAsPossible;
    let mut paths = Vec::new();
    let mut args = std::env::args_os().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--rate" {
            let rate = args.next().and_then(|r| r.to_str()?.parse::<f64>().ok());
            match rate.map(Pace::rate) {
                Some(Ok(p)) => pace = p,
                Some(Err(e)) => {
                    eprintln!("replay_attitude: --rate: {e}");
                    return ExitCode::from(2);
                }
                None => {
                    eprintln!("replay_attitude: --rate takes a number (1: real time)");
                    return ExitCode::from(2);
                }
            }
        } else {
            paths.push(arg);
        }
    }
    let mut paths = paths.into_iter();
    let (input, input_name) = match paths.next() {
        Some(p) => (p.clone(), p.to_string_lossy().into_owned()),
        // The repository's log, found where this example was built.
        None => (
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(ATTITUDE_SOURCE_LOG)
                .into_os_string(),
            format!("the repository's bench log ({ATTITUDE_SOURCE_LOG})"),
        ),
    };
    let output = paths.next().unwrap_or_else(|| "replay_attitude.ulg".into());
    let output_name = output.to_string_lossy();

    let file = match LogFile::open(&input) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("replay_attitude: {e}");
            return ExitCode::from(2);
        }
    };
    let log = match file.parse() {
        Ok(log) => log,
        Err(e) => {
            eprintln!("replay_attitude: {input_name}: {e}");
            return ExitCode::from(2);
        }
    };
    println!("replay of {input_name} against data/attitude_reference.ulg");
    let admission = admit(&log);
    for a in &admission.accepted {
        println!("  accepted: {a}");
    }
    if !admission.refused.is_empty() {
        for r in &admission.refused {
            println!("  REFUSED: {}", r.replace('\n', "\n    "));
        }
        println!("refused: the log's formats do not fit the reference");
        return ExitCode::FAILURE;
    }

    let written = File::create(&*output)
        .map_err(Box::<dyn Error>::from)
        .and_then(|f| replay(&log, SystemClock::new(), pace, BufWriter::new(f)))
        .and_then(|(r, mut out)| {
            out.flush()?;
            Ok(r)
        });
    let r = match written {
        Ok(r) => r,
        Err(e) => {
            eprintln!("replay_attitude: {output_name}: {e}");
            return ExitCode::from(2);
        }
    };
    match pace {
        Pace::Rate(rate) => println!(
            "replayed {} IMU steps at {rate} x the log's clock: {} late (over 1 ms), the latest {:.3} ms after its time",
            r.steps,
            r.late,
            r.worst_lateness.as_secs_f64() * 1e3
        ),
        _ => println!("replayed {} IMU steps as fast as possible", r.steps),
    }
    let Some(start) = r.start_us else {
        println!("no step has a logged attitude to start the filter from: nothing estimated");
        return ExitCode::SUCCESS;
    };
    println!(
        "filter started from the logged attitude at {:.3} s (yaw has no absolute reference: from the log, then the gyro alone)",
        start as f64 * 1e-6
    );
    let [roll, pitch, yaw, angle] = r.rms_deg;
    println!(
        "RMS error against the logged estimate over {} steps: roll {roll:.2}°, pitch {pitch:.2}°, yaw {yaw:.2}°, angle {angle:.2}°",
        r.compared
    );
    println!(
        "wrote {output_name}: vehicle_attitude (logged, {} rows) and vehicle_attitude:1 (estimate, {} rows)",
        r.logged_rows, r.estimates
    );
    println!("  ulog plot {output_name} vehicle_attitude.q vehicle_attitude:1.q");
    ExitCode::SUCCESS
}
