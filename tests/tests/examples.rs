//! Runs the examples as CI does (`cargo run -p ulog-examples --example NAME -- ARGS`)
//! and checks what they print; and keeps `examples/data/reference.ulg`, the schema
//! `replay_check` is compiled against, equal to what `reference_log()` builds
//! (`ULOG_BLESS=1` rewrites it).

use std::path::{Path, PathBuf};
use std::process::Command;

use ulog_core::testing::LogBuilder;

/// Runs an example through cargo; returns (exit code, stdout).
fn run(example: &str, args: &[&str]) -> (i32, String) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .args([
            "run",
            "--quiet",
            "-p",
            "ulog-examples",
            "--example",
            example,
            "--",
        ])
        .args(args)
        .output()
        .expect("cargo runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("--- {example} {args:?}\n{stdout}{stderr}");
    (out.status.code().unwrap_or(-1), stdout)
}

/// A log of the corpus the tests check (see `ulog_tests::corpus_dir`).
fn corpus_file(name: &str) -> PathBuf {
    ulog_tests::corpus_dir().join("files").join(name)
}

/// A line of `text` that starts with `label` (after indentation).
fn line<'t>(text: &'t str, label: &str) -> &'t str {
    text.lines()
        .find(|l| l.trim_start().starts_with(label))
        .unwrap_or_else(|| panic!("no line `{label}` in:\n{text}"))
}

/// The first number in a line.
fn number(line: &str) -> f64 {
    let start = line
        .find(|c: char| c.is_ascii_digit() || c == '-')
        .expect("a number");
    let rest = &line[start..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .unwrap_or(rest.len());
    rest[..end].parse().expect("a number")
}

#[test]
fn reference_log_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/reference.ulg");
    let bytes = ulog_examples::reference_log();
    if std::env::var_os("ULOG_BLESS").is_some() {
        std::fs::write(&path, &bytes).unwrap();
    }
    let committed = std::fs::read(&path).expect("data/reference.ulg (ULOG_BLESS=1 writes it)");
    assert!(
        committed == bytes,
        "data/reference.ulg is stale: run with ULOG_BLESS=1"
    );
    assert!(committed.len() < 20_000);
}

#[test]
fn flight_summary_of_the_sample_log() {
    let (code, out) = run("flight_summary", &[]);
    assert_eq!(code, 0);
    assert!(out.starts_with("flight summary of the bundled sample log"));
    assert_eq!(number(line(&out, "logged:")), 9.9);
    // The sample flies a half circle of radius 20 m (62.8 m) while climbing to 10 m.
    assert_eq!(
        line(&out, "distance flown:"),
        "  distance flown:  65.1 m (100 local positions, Mapped plan)"
    );
    assert_eq!(number(line(&out, "peak altitude:")), 10.0);
    assert_eq!(number(line(&out, "flight time:")), 9.6);
    assert!(
        line(&out, "GPS:").contains("no topic `vehicle_gps_position` or `sensor_gps` in the log")
    );
    assert_eq!(
        line(&out, "battery 0:"),
        "  battery 0:       16.80 V -> 15.85 V, 28.5 % used"
    );
    assert_eq!(
        line(&out, "battery 1:"),
        "  battery 1:       16.70 V -> 15.75 V, 28.5 % used"
    );
}

#[test]
fn flight_summary_of_real_logs() {
    // Flights of an older and a recent firmware: GPS fields `int32_t` and `double`.
    let mut names = vec!["esc_status_log.ulg"];
    if ulog_tests::FULL_CORPUS {
        names.push("corrupt_unregistered_msg_id.ulg");
    }
    for name in names {
        let path = corpus_file(name);
        let (code, out) = run("flight_summary", &[path.to_str().unwrap()]);
        assert_eq!(code, 0, "{name}");
        let peak = number(line(&out, "peak altitude:"));
        assert!((1.0..500.0).contains(&peak), "{name}: {peak}");
        assert!(number(line(&out, "distance flown:")) > 10.0, "{name}");
        assert!(number(line(&out, "flight time:")) > 10.0, "{name}");
        assert!(line(&out, "GPS track:").contains("m AMSL"), "{name}");
        assert!(line(&out, "battery 0:").contains("mAh drawn"), "{name}");
        // 4-5 ms: PX4's IMU at 200-250 Hz, whether the log says `float` seconds or
        // `uint32_t` microseconds (a unit read wrongly is 1000 times off).
        let dt = number(line(&out, "IMU:").split("integrating").nth(1).unwrap());
        assert!((3.9..=5.1).contains(&dt), "{name}: {dt} ms");
        assert!(number(line(&out, "vehicle:")) >= 1.0, "{name}");
    }
}

/// Every corpus log, PX4's and others', goes through the same three structs (one per
/// topic, whatever the firmware): each topic the log has (as pyulog lists them) gives
/// its figures, each it lacks is named as lacking.
#[test]
fn flight_summary_of_every_corpus_log() {
    let dir = ulog_tests::corpus_dir();
    let mut logs: Vec<PathBuf> = std::fs::read_dir(dir.join("files"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ulg"))
        .collect();
    logs.sort();
    assert!(logs.len() >= if ulog_tests::FULL_CORPUS { 19 } else { 5 });
    let mut with_data = [0usize; 3];
    for path in &logs {
        let stem = path.file_stem().unwrap().to_string_lossy();
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join("expected").join(&*stem).join("summary.json"))
                .unwrap(),
        )
        .unwrap();
        let has = |topic: &str| {
            summary["topics"]
                .as_array()
                .unwrap()
                .iter()
                .any(|t| t["name"] == topic && t["multi_id"] == 0)
        };
        let (code, out) = run("flight_summary", &[path.to_str().unwrap()]);
        assert_eq!(code, 0, "{stem}");
        if has("vehicle_local_position") {
            assert!(number(line(&out, "distance flown:")) >= 0.0, "{stem}");
            with_data[0] += 1;
        } else {
            // pyulog lists the topics with data: one without is lacking, or empty.
            let l = line(&out, "local position:");
            assert!(
                l.contains("no topic `vehicle_local_position` in the log")
                    || l.contains("the topic has no data"),
                "{stem}: {l}"
            );
        }
        if has("vehicle_gps_position") || has("sensor_gps") {
            let gps = out
                .lines()
                .find(|l| l.trim_start().starts_with("GPS"))
                .unwrap();
            assert!(gps.contains("fix"), "{stem}: {gps}");
            with_data[1] += 1;
        } else {
            let l = line(&out, "GPS:");
            assert!(
                l.contains("no topic `vehicle_gps_position` or `sensor_gps` in the log")
                    || l.contains("no 3D fix"),
                "{stem}: {l}"
            );
        }
        if has("battery_status") {
            assert!(line(&out, "battery 0:").len() > 20, "{stem}");
            with_data[2] += 1;
        } else {
            let l = out
                .lines()
                .find(|l| l.trim_start().starts_with("battery"))
                .unwrap();
            assert!(
                l.contains("no topic `battery_status` in the log") || l.contains("no readings"),
                "{stem}: {l}"
            );
        }
    }
    // Not a check that passes for want of data: most logs, of older and newer
    // firmware, have data in each of the three.
    let least = if ulog_tests::FULL_CORPUS { 10 } else { 1 };
    assert!(with_data.iter().all(|&n| n >= least), "{with_data:?}");
}

#[test]
fn replay_check_accepts_the_reference_schema() {
    let (code, out) = run("replay_check", &[]);
    assert_eq!(code, 0, "{out}");
    assert!(line(&out, "vehicle_attitude/0").contains("same format, 200 messages"));
    assert!(line(&out, "esc_status/0").contains("same format"));
    assert!(line(&out, "accepted:").contains("360 messages"));
}

/// A log of the sample's topics with a changed `battery_status` and `esc_report` (types
/// that do not widen to the binding's: `double` into `float`, `float` into `int32_t`),
/// and a `vehicle_attitude` with a field added in front.
fn changed_log() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("vehicle_attitude:uint64_t timestamp;uint8_t quality;float[4] q;");
    b.format("battery_status:uint64_t timestamp;double voltage_v;uint8_t[3] cell_count;");
    b.format(
        "esc_status:uint64_t timestamp;uint8_t esc_count;uint8_t[7] _padding0;esc_report[2] esc;",
    );
    b.format("esc_report:uint64_t timestamp;float esc_rpm;float esc_voltage;");
    b.subscribe(0, 0, "vehicle_attitude");
    b.subscribe(0, 1, "battery_status");
    b.subscribe(0, 2, "esc_status");
    b.data(0, &[&7u64.to_le_bytes()[..], &[1], &[0; 16]].concat());
    b.into_bytes()
}

#[test]
fn replay_check_refuses_changed_formats_with_every_difference() {
    let path = std::env::temp_dir().join(format!("ulog-replay-check-{}.ulg", std::process::id()));
    std::fs::write(&path, changed_log()).unwrap();
    let (code, out) = run("replay_check", &[path.to_str().unwrap()]);
    let (strict, strict_out) = run("replay_check", &["--exact", path.to_str().unwrap()]);
    std::fs::remove_file(&path).ok();
    assert_eq!(code, 1, "{out}");
    for expected in [
        "battery_status/0         REFUSED: the log's format of `battery_status` does not fit binding `BatteryStatus` (3 differences)",
        "field `voltage_v`: type `float` expected, the log has `double`",
        "field `remaining`: missing in the log",
        "field `cell_count`: not an array expected, the log has an array of 3",
        "binding's format:\n  battery_status:uint64_t timestamp;float voltage_v;float remaining;uint8_t cell_count;uint8_t[7] _padding0;",
        "log's format:\n  battery_status:uint64_t timestamp;double voltage_v;uint8_t[3] cell_count;",
        "field `esc[*].esc_rpm`: type `int32_t` expected, the log has `float`",
        "esc_report:uint64_t timestamp;float esc_rpm;float esc_voltage;",
        "vehicle_local_position   not in this log",
        "refused: 2 topic(s) changed: battery_status/0, esc_status/0",
    ] {
        assert!(out.contains(expected), "missing {expected:?} in:\n{out}");
    }
    // The attitude gained a field: readable by name, accepted unless --exact.
    assert!(line(&out, "vehicle_attitude/0").contains("accepted: format changed"));
    assert_eq!(strict, 1);
    assert!(line(&strict_out, "refused:").contains("vehicle_attitude/0"));
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn replay_check_refuses_a_log_of_another_firmware() {
    let path = corpus_file("sample.ulg");
    let (code, out) = run("replay_check", &[path.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        out.contains("field `xy_valid`") || out.contains("REFUSED"),
        "{out}"
    );
    assert!(line(&out, "refused:").contains("battery_status/0"));
}

/// The writer example logs a flight, reads it back, and `flight_summary` analyses the
/// log it wrote: the whole loop of the README's first command.
#[test]
fn simulated_flight_writes_a_log_that_reads_back_and_analyses() {
    let dir = std::env::temp_dir().join(format!("ulog-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("flight.ulg");
    let p = path.to_str().unwrap();
    let (code, out) = run("simulated_flight", &[p]);
    assert_eq!(code, 0);
    assert!(out.contains("0 findings"), "{out}");
    assert!(
        out.contains("vehicle_attitude") && out.contains("3001 rows"),
        "{out}"
    );
    assert!(out.contains("peak altitude: 10.0 m"), "{out}");
    let log_bytes = std::fs::read(&path).unwrap();
    let log = ulog_core::ULog::parse(&log_bytes).unwrap();
    assert_eq!(log.param_changes().len(), 1);
    let (code, out) = run("flight_summary", &[p]);
    assert_eq!(code, 0);
    assert_eq!(number(line(&out, "peak altitude:")), 10.0);
    std::fs::remove_dir_all(&dir).ok();
}
