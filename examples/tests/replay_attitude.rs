//! The `replay_attitude` example's logic on the repository's real log: its reference
//! log up to date, the admission check, the replay into the filter, the log it writes.

use std::path::{Path, PathBuf};

use ulog_examples::{reference_of, ATTITUDE_SOURCE_LOG, ATTITUDE_TOPICS};

fn workspace_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

fn source_log() -> Vec<u8> {
    std::fs::read(workspace_file(ATTITUDE_SOURCE_LOG)).expect("the corpus log")
}

#[test]
fn attitude_reference_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/attitude_reference.ulg");
    let bytes = source_log();
    let log = ulog_core::ULog::parse(&bytes).unwrap();
    let reference = reference_of(&log, &ATTITUDE_TOPICS);
    if std::env::var_os("ULOG_BLESS").is_some() {
        std::fs::write(&path, &reference).unwrap();
    }
    let committed =
        std::fs::read(&path).expect("data/attitude_reference.ulg (ULOG_BLESS=1 writes it)");
    assert!(
        committed == reference,
        "data/attitude_reference.ulg is stale: run with ULOG_BLESS=1"
    );
    assert!(committed.len() < 2_000, "{}", committed.len());
}

// The example itself, its `main` aside: the test runs the same code.
#[allow(dead_code)]
#[path = "../examples/replay_attitude.rs"]
mod replay_attitude;

use std::time::Duration;

use replay_attitude::{admit, px4, replay, AttitudeFilter};
use ulog_core::replay::{Clock, Pace, VirtualClock};
use ulog_core::ULog;

#[test]
fn the_corpus_log_is_admitted() {
    let bytes = source_log();
    let log = ULog::parse(&bytes).unwrap();
    let admission = admit(&log);
    assert!(admission.refused.is_empty(), "{:?}", admission.refused);
    assert_eq!(
        admission.accepted,
        [
            "sensor_combined: same format, 2373 rows",
            "vehicle_attitude: same format, 306 rows"
        ]
    );
}

#[test]
fn replay_writes_both_attitudes_and_tracks_the_logged_one() {
    let bytes = source_log();
    let log = ULog::parse(&bytes).unwrap();
    let (r, written) = replay(
        &log,
        VirtualClock::new(),
        Pace::AsFastAsPossible,
        Vec::new(),
    )
    .unwrap();

    // What to expect, from the log directly: the filter starts at the first IMU row
    // with a logged attitude around it, and estimates every row from there.
    let imu_times: Vec<u64> = log
        .read::<px4::SensorCombined>(0)
        .unwrap()
        .iter()
        .map(|r| r.unwrap().timestamp)
        .collect();
    let logged: Vec<px4::VehicleAttitude> = log
        .read::<px4::VehicleAttitude>(0)
        .unwrap()
        .iter()
        .map(Result::unwrap)
        .collect();
    let first_logged = logged[0].timestamp;
    let start = *imu_times.iter().find(|&&t| t > first_logged).unwrap();
    let estimated: Vec<u64> = imu_times.iter().copied().filter(|&t| t >= start).collect();
    assert_eq!(r.steps, imu_times.len());
    assert_eq!(r.start_us, Some(start));
    assert_eq!(
        (r.logged_rows, r.estimates),
        (logged.len(), estimated.len())
    );

    let out = ULog::parse(&written).unwrap();
    assert!(out.findings().is_empty(), "{:?}", out.findings());
    let mine: Vec<px4::VehicleAttitude> = out
        .read::<px4::VehicleAttitude>(1)
        .unwrap()
        .iter()
        .map(Result::unwrap)
        .collect();
    let theirs: Vec<px4::VehicleAttitude> = out
        .read::<px4::VehicleAttitude>(0)
        .unwrap()
        .iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(theirs, logged, "the logged rows, as logged");
    assert_eq!(
        mine.iter().map(|a| a.timestamp).collect::<Vec<_>>(),
        estimated
    );
    // Written in time order, both topics merged.
    let times: Vec<u64> = out
        .messages()
        .filter_map(|m| m.ok())
        .filter_map(|m| match m.message {
            ulog_core::Message::Data { payload, .. } => {
                Some(u64::from_le_bytes(payload[..8].try_into().unwrap()))
            }
            _ => None,
        })
        .collect();
    assert_eq!(times.len(), logged.len() + estimated.len());
    assert!(times.windows(2).all(|w| w[0] <= w[1]));

    // The log is a bench run at rest, roll -1.8° and pitch 3.1°: the accelerometer
    // gives both within a few tenths of a degree (the filter measured 0.2° and 0.3°),
    // so 1° leaves room for another gain, not for a sign error (which drifts tens of
    // degrees off within the log's 10 s). Yaw follows the gyro alone: its bias over
    // 10 s (the filter measured 0.9°) must stay within 3°.
    let [roll, pitch, yaw, angle] = r.rms_deg;
    assert!(roll < 1.0 && pitch < 1.0, "roll {roll}°, pitch {pitch}°");
    assert!(yaw < 3.0 && angle < 3.5, "yaw {yaw}°, angle {angle}°");
    // An estimate of its own, not the log's copied.
    assert!(roll > 0.01 && pitch > 0.01, "roll {roll}°, pitch {pitch}°");
    assert_eq!(
        r.compared,
        estimated
            .iter()
            .filter(|&&t| t <= logged.last().unwrap().timestamp)
            .count()
    );
}

#[test]
fn a_paced_replay_keeps_the_logs_clock() {
    let bytes = source_log();
    let log = ULog::parse(&bytes).unwrap();
    let clock = VirtualClock::new();
    let (r, _) = replay(&log, clock.clone(), Pace::Rate(2.0), Vec::new()).unwrap();
    assert_eq!((r.late, r.worst_lateness), (0, Duration::ZERO));
    // The IMU's 9.6 s at twice the speed, on the virtual clock (no wall-clock wait).
    let first = ulog_core::ULog::parse(&bytes).unwrap();
    let imu = first.read::<px4::SensorCombined>(0).unwrap();
    let t = |i: usize| imu.iter().nth(i).unwrap().unwrap().timestamp;
    let span_us = t(imu.len() - 1) - t(0);
    assert!(clock.now().abs_diff(Duration::from_micros(span_us / 2)) < Duration::from_micros(1));
}

#[test]
fn a_changed_format_is_refused_with_every_difference() {
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 0);
    // Gyro rates as doubles, the accelerometer renamed; the attitude as logged.
    b.format(
        "sensor_combined:uint64_t timestamp;double[3] gyro_rad;float gyro_integral_dt;\
         int32_t accelerometer_timestamp_relative;float[3] accel_m_s2;\
         float accelerometer_integral_dt;int32_t magnetometer_timestamp_relative;\
         float[3] magnetometer_ga;int32_t baro_timestamp_relative;float baro_alt_meter;\
         float baro_temp_celcius;",
    );
    b.format(
        "vehicle_attitude:uint64_t timestamp;float rollspeed;float pitchspeed;\
         float yawspeed;float[4] q;uint8_t[4] _padding0;",
    );
    b.subscribe(0, 0, "sensor_combined");
    b.subscribe(0, 1, "vehicle_attitude");
    let bytes = b.into_bytes();
    let log = ULog::parse(&bytes).unwrap();
    let admission = admit(&log);
    assert_eq!(
        admission.accepted,
        ["vehicle_attitude: same format, 0 rows"]
    );
    let [refused] = &admission.refused[..] else {
        panic!("{:?}", admission.refused)
    };
    assert!(
        refused.starts_with(
            "the log's format of `sensor_combined` does not fit binding `SensorCombined` (2 differences)"
        ),
        "{refused}"
    );
    assert!(refused.contains("field `gyro_rad`: type `float` expected, the log has `double`"));
    assert!(refused.contains("field `accelerometer_m_s2`: missing in the log"));
    assert!(
        refused.contains("log's format:\n  sensor_combined:uint64_t timestamp;double[3] gyro_rad;")
    );
}

#[test]
fn a_missing_topic_is_refused_beside_a_changed_one() {
    // The bundled sample has no IMU, and an attitude of quaternion only.
    let bytes = ulog_core::testing::sample_log();
    let log = ULog::parse(&bytes).unwrap();
    let admission = admit(&log);
    assert!(admission.accepted.is_empty());
    let [imu, attitude] = &admission.refused[..] else {
        panic!("{:?}", admission.refused)
    };
    assert_eq!(imu, "no topic `sensor_combined` in the log");
    assert!(attitude.contains("(3 differences)"), "{attitude}");
    assert!(attitude.contains("field `rollspeed`: missing in the log"));
}

/// The filter on its own: a turn about yaw integrates exactly, and a wrong tilt is
/// pulled to the accelerometer's.
#[test]
fn the_filter_integrates_and_levels() {
    let level = [1.0, 0.0, 0.0, 0.0];
    let down = [0.0, 0.0, -9.81];
    let mut f = AttitudeFilter::new(level, 0);
    // 90°/s about z for 1 s at 250 Hz.
    for i in 1..=250 {
        f.update(i * 4_000, [0.0, 0.0, std::f32::consts::FRAC_PI_2], down);
    }
    let [roll, pitch, yaw] = replay_attitude::euler(f.q());
    assert!((yaw.to_degrees() - 90.0).abs() < 0.01, "{yaw}");
    assert!(roll.abs() < 1e-6 && pitch.abs() < 1e-6);

    // Started 10° off in roll, at rest: within 0.5° after 5 s.
    let s = (5f32.to_radians()).sin();
    let mut f = AttitudeFilter::new([5f32.to_radians().cos(), s, 0.0, 0.0], 0);
    for i in 1..=1_250 {
        f.update(i * 4_000, [0.0; 3], down);
    }
    let [roll, ..] = replay_attitude::euler(f.q());
    assert!(roll.to_degrees().abs() < 0.5, "{}", roll.to_degrees());
}

/// Runs the example as its header says (`cargo run -p ulog-examples --example
/// replay_attitude -- ARGS`), in a scratch folder; returns (exit code, stdout).
fn run_example(args: &[&std::ffi::OsStr]) -> (i32, String) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = std::process::Command::new(cargo)
        .current_dir(env!("CARGO_TARGET_TMPDIR"))
        .args(["run", "--quiet", "-p", "ulog-examples", "--example"])
        .args(["replay_attitude", "--"])
        .args(args)
        .output()
        .expect("cargo runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    (out.status.code().unwrap_or(-1), stdout)
}

#[test]
fn the_example_replays_refuses_and_checks_its_arguments() {
    // Without arguments: the repository's log, into the current folder.
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("replay_attitude.ulg");
    let _ = std::fs::remove_file(&out);
    let (code, said) = run_example(&[]);
    assert_eq!(code, 0, "{said}");
    assert!(
        said.starts_with("replay of the repository's bench log"),
        "{said}"
    );
    assert!(said.contains("accepted: sensor_combined: same format, 2373 rows"));
    assert!(said.contains("replayed 2373 IMU steps as fast as possible"));
    assert!(said.contains("RMS error against the logged estimate over 2370 steps: roll "));
    assert!(
        said.contains("vehicle_attitude:1 (estimate, 2372 rows)"),
        "{said}"
    );
    let written = std::fs::read(&out).expect("replay_attitude.ulg written");
    let written = ULog::parse(&written).unwrap();
    assert_eq!(written.topic_instances("vehicle_attitude").len(), 2);

    // PX4 v1.9's `sensor_combined` (integer `integral_dt`, no magnetometer): refused.
    let v1_9 = workspace_file("tests/corpus/files/esc_status_log.ulg");
    let elsewhere = out.with_file_name("refused.ulg");
    let (code, said) = run_example(&[v1_9.as_os_str(), elsewhere.as_os_str()]);
    assert_eq!(code, 1, "{said}");
    assert!(said.contains("REFUSED: the log's format of `sensor_combined`"));
    assert!(said.contains("(7 differences)"), "{said}");
    assert!(!elsewhere.exists(), "nothing written for a refused log");

    let (code, _) = run_example(&["--rate".as_ref(), "0".as_ref()]);
    assert_eq!(code, 2);
}
