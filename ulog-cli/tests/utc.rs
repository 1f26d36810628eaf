//! `--utc`: the times printed and exported in UTC agree with what the logs say of
//! their wall-clock time by other means: the file name PX4 gives the log it opens
//! (`logging: opening log file 2024-2-6/8_25_44.ulg`, the autopilot's own clock), the
//! receiver's time of every GPS row as pyulog reads it, and `boot_time_utc_us` where a
//! log has both. A log without a UTC time is an error for `--utc`, never boot times
//! printed as UTC. Units: `dump` shows them.

mod common;

use serde_json::Value as Json;
use ulog_core::read::{UtcClock, UtcSource};

/// Microseconds since the Unix epoch of a civil UTC time.
fn epoch_us(y: i64, mo: i64, d: i64, h: i64, mi: i64, s: f64) -> i64 {
    // Days from civil, by counting from 1970 (the tests' dates are after it).
    let is_leap = |y: i64| (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let mut days = (1970..y)
        .map(|y| if is_leap(y) { 366 } else { 365 })
        .sum::<i64>();
    let month_days = [31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
    for m in 1..mo {
        days += month_days[m as usize - 1] + i64::from(m == 2 && is_leap(y));
    }
    days += d - 1;
    ((days * 86_400 + h * 3600 + mi * 60) as f64 * 1e6 + s * 1e6).round() as i64
}

/// `2024-02-06T08:25:44.608Z` (any number of second digits) as microseconds.
fn parse_rfc3339(t: &str) -> i64 {
    let t = t.strip_suffix('Z').expect("ends in Z");
    let (date, time) = t.split_once('T').expect("a T");
    let d: Vec<i64> = date.split('-').map(|p| p.parse().unwrap()).collect();
    let c: Vec<&str> = time.split(':').collect();
    epoch_us(
        d[0],
        d[1],
        d[2],
        c[0].parse().unwrap(),
        c[1].parse().unwrap(),
        c[2].parse().unwrap(),
    )
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its PX4 logs that name their file"
)]
fn utc_messages_agree_with_the_file_name_px4_gave_the_log() {
    let corpus = common::corpus();
    let mut checked = Vec::new();
    for (stem, path) in common::corpus_logs(&corpus) {
        let bytes = std::fs::read(&path).unwrap();
        let Ok(log) = ulog_core::ULog::parse(&bytes) else {
            continue;
        };
        if log.utc().is_none() {
            continue;
        }
        let text = common::ulog_ok(["messages".as_ref(), "--utc".as_ref(), path.as_os_str()]);
        // `… opening log file 2024-2-6/8_25_44.ulg`: PX4's clock (UTC plus the
        // information key `time_ref_utc`, zero in these logs) when it opened the file.
        let Some(line) = text.lines().find(|l| l.contains("opening log file ")) else {
            continue;
        };
        let (time, rest) = line.split_once(' ').unwrap();
        let name = rest.rsplit(' ').next().unwrap().trim_end_matches(".ulg");
        let (date, clock) = name.split_once('/').unwrap();
        let d: Vec<i64> = date.split('-').map(|p| p.parse().unwrap()).collect();
        let c: Vec<i64> = clock.split('_').map(|p| p.parse().unwrap()).collect();
        let zone_s = match log.info_value("time_ref_utc") {
            Some(ulog_core::Value::I32(v)) => i64::from(v),
            _ => 0,
        };
        let named = epoch_us(d[0], d[1], d[2], c[0], c[1], c[2] as f64) - zone_s * 1_000_000;
        let ours = parse_rfc3339(time);
        // The name has whole seconds, taken at most a moment before the message.
        assert!(
            (ours - named).abs() < 2_000_000,
            "{stem}: {line}: {} s from the file's name",
            (ours - named) as f64 / 1e6
        );
        checked.push(stem);
    }
    assert!(checked.len() >= 3, "logs that name their file: {checked:?}");
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus) and pyulog's CSV of its GPS topics"
)]
fn csv_utc_column_agrees_with_each_gps_rows_own_time_as_pyulog_reads_it() {
    let corpus = common::corpus();
    let mut checked = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        let theirs = corpus
            .join("expected")
            .join(&stem)
            .join("csv")
            .join(format!("{stem}_vehicle_gps_position_0.csv"));
        let Ok(theirs) = std::fs::read_to_string(&theirs) else {
            continue;
        };
        let header: Vec<&str> = theirs.lines().next().unwrap().split(',').collect();
        let Some(col) = header.iter().position(|c| *c == "time_utc_usec") else {
            continue;
        };
        // pyulog's timestamp and receiver time per row.
        let rows: Vec<(u64, u64)> = theirs
            .lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f[0].parse().unwrap(), f[col].parse().unwrap())
            })
            .collect();
        let with_time: Vec<&(u64, u64)> = rows
            .iter()
            .filter(|r| r.1 > 1_262_304_000_000_000)
            .collect();
        let out = common::scratch(&format!("utc_csv_{stem}"));
        let run = common::ulog([
            "csv".as_ref(),
            "--utc".as_ref(),
            "-m".as_ref(),
            "vehicle_gps_position".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        if with_time.is_empty() {
            continue;
        }
        assert!(
            run.status.success(),
            "{stem}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let ours = std::fs::read_to_string(out.join(format!("{stem}_vehicle_gps_position_0.csv")))
            .unwrap();
        let ours: Vec<(u64, i64)> = ours
            .lines()
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f[0].parse().unwrap(), parse_rfc3339(f[1]))
            })
            .collect();
        // Rows by timestamp: this reader keeps rows pyulog drops after corruption.
        let theirs: std::collections::HashMap<u64, u64> = rows.iter().copied().collect();
        let mut errors: Vec<i64> = ours
            .iter()
            .filter_map(|o| Some((o, *theirs.get(&o.0)?)))
            .filter(|(_, utc)| *utc > 1_262_304_000_000_000)
            .map(|(o, utc)| (o.1 - utc as i64).abs())
            .collect();
        assert!(
            errors.len() >= with_time.len() * 9 / 10,
            "{stem}: rows compared"
        );
        errors.sort_unstable();
        // The receiver's time of a row is the fix's; the row's timestamp is when it
        // arrived: within a fraction of a second, the same for most rows.
        let median = errors[errors.len() / 2];
        let p90 = errors[errors.len() * 9 / 10];
        assert!(median < 100_000, "{stem}: median {median} µs");
        assert!(p90 < 500_000, "{stem}: 90th percentile {p90} µs");
        checked += 1;
    }
    assert!(checked >= 5, "logs with GPS time: {checked}");
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): a log with both GPS time and boot_time_utc_us"
)]
fn gps_time_and_boot_time_information_agree_where_a_log_has_both() {
    let path = common::corpus().join("files/corrupt_unregistered_msg_id.ulg");
    let bytes = std::fs::read(path).unwrap();
    let log = ulog_core::ULog::parse(&bytes).unwrap();
    let gps = log.utc().unwrap();
    assert!(
        matches!(gps.source(), UtcSource::Gps { .. }),
        "{:?}",
        gps.source()
    );
    let Some(ulog_core::Value::U64(boot)) = log.info_value("boot_time_utc_us") else {
        panic!("boot_time_utc_us")
    };
    let info = UtcClock::from_boot(boot as i64);
    let t = log.start_timestamp();
    let apart = (gps.at(t).micros() - info.at(t).micros()).abs();
    assert!(apart < 1_000_000, "{apart} µs apart");
}

#[test]
fn utc_without_a_time_in_the_log_is_an_error_of_every_command() {
    // The bundled sample has neither GPS time nor boot_time_utc_us.
    let file = common::sample_file("utc_none");
    let out = common::scratch("utc_none_out");
    let svg = out.join("p.svg");
    let runs: [Vec<&std::ffi::OsStr>; 6] = [
        vec!["params".as_ref(), "--utc".as_ref(), file.as_os_str()],
        vec![
            "plot".as_ref(),
            "--utc".as_ref(),
            file.as_os_str(),
            "vehicle_local_position.z".as_ref(),
            "-o".as_ref(),
            svg.as_os_str(),
        ],
        vec!["messages".as_ref(), "--utc".as_ref(), file.as_os_str()],
        vec!["dump".as_ref(), "--utc".as_ref(), file.as_os_str()],
        vec![
            "csv".as_ref(),
            "--utc".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        vec![
            "parquet".as_ref(),
            "--per-log".as_ref(),
            "--utc".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
    ];
    for args in runs {
        let run = common::ulog(&args);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(7), "{args:?}: {err}");
        assert!(err.contains("does not say its UTC time"), "{args:?}: {err}");
        assert!(
            run.stdout.is_empty(),
            "{args:?}: nothing written before the failure"
        );
    }
    let info: Json = serde_json::from_str(&common::ulog_ok([
        "info".as_ref(),
        "--json".as_ref(),
        file.as_os_str(),
    ]))
    .unwrap();
    assert_eq!(info["utc_start"], Json::Null);
}

/// A log with `boot_time_utc_us`: every command prints the same UTC times, from it.
#[test]
fn every_command_prints_the_same_utc_times() {
    use ulog_core::testing::LogBuilder;
    let boot = 1_707_207_944_000_000u64; // 2024-02-06T08:25:44Z
    let mut b = LogBuilder::new(1, 0);
    b.info("uint64_t boot_time_utc_us", &boot.to_le_bytes());
    b.info_str("sys_name", "test");
    b.param("float MPC_XY_P", &1.0f32.to_le_bytes());
    b.format("vehicle_local_position:uint64_t timestamp;float z;float vx;");
    b.subscribe(0, 1, "vehicle_local_position");
    for i in 0..3u64 {
        let mut p = (1_000_000 + i * 250_000).to_le_bytes().to_vec();
        p.extend_from_slice(&(-1.5f32).to_le_bytes());
        p.extend_from_slice(&(0.25f32).to_le_bytes());
        b.data(1, &p);
    }
    b.log(b'6', 1_500_000, "hello");
    b.param("float MPC_XY_P", &2.0f32.to_le_bytes());
    let dir = common::scratch("utc_all");
    let path = dir.join("boot.ulg");
    std::fs::write(&path, b.bytes()).unwrap();

    let info: Json = serde_json::from_str(&common::ulog_ok([
        "info".as_ref(),
        "--json".as_ref(),
        path.as_os_str(),
    ]))
    .unwrap();
    assert_eq!(info["utc_start"], "2024-02-06T08:25:44.000000Z");
    assert_eq!(info["utc_source"], "information key boot_time_utc_us");

    let messages = common::ulog_ok(["messages".as_ref(), "--utc".as_ref(), path.as_os_str()]);
    assert_eq!(messages, "2024-02-06T08:25:45.500Z INFO: hello\n");

    let text = common::ulog_ok(["dump".as_ref(), "--utc".as_ref(), path.as_os_str()]);
    let rows: Vec<&str> = text.lines().filter(|l| l.contains("  D  ")).collect();
    assert_eq!(rows.len(), 3);
    // Units after the values whose names say them, the row's UTC time at the end.
    assert!(
        rows[1].ends_with("timestamp=1250000 z=-1.5 m vx=0.25 m/s utc=2024-02-06T08:25:45.250000Z"),
        "{}",
        rows[1]
    );
    assert!(
        text.contains("INFO at 1500000 us (2024-02-06T08:25:45.500000Z): hello"),
        "{text}"
    );
    let json = common::ulog_ok([
        "dump".as_ref(),
        "--utc".as_ref(),
        "--json".as_ref(),
        path.as_os_str(),
    ]);
    let lines: Vec<Json> = json
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let sub = lines.iter().find(|j| j["type"] == "A").unwrap();
    assert_eq!(sub["units"], serde_json::json!({"z": "m", "vx": "m/s"}));
    let data: Vec<&Json> = lines.iter().filter(|j| j["type"] == "D").collect();
    assert_eq!(data[2]["utc"], "2024-02-06T08:25:45.500000Z");

    let csv_dir = dir.join("csv");
    common::ulog_ok([
        "csv".as_ref(),
        "--utc".as_ref(),
        path.as_os_str(),
        "-o".as_ref(),
        csv_dir.as_os_str(),
    ]);
    let csv = std::fs::read_to_string(csv_dir.join("boot_vehicle_local_position_0.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "timestamp,timestamp_utc,z,vx");
    assert_eq!(lines[1], "1000000,2024-02-06T08:25:45.000000Z,-1.5,0.25");

    let params = common::ulog_ok(["params".as_ref(), "--utc".as_ref(), path.as_os_str()]);
    assert_eq!(
        params,
        "MPC_XY_P,1.0,2.0\ntimestamp,2024-02-06T08:25:44.000000Z,2024-02-06T08:25:45.500000Z\n"
    );

    let svg = dir.join("z.svg");
    common::ulog_ok([
        "plot".as_ref(),
        "--utc".as_ref(),
        path.as_os_str(),
        "vehicle_local_position.z".as_ref(),
        "-o".as_ref(),
        svg.as_os_str(),
    ]);
    let svg = std::fs::read_to_string(svg).unwrap();
    assert!(
        svg.contains("UTC time of day (log start: 2024-02-06 08:25:45Z)"),
        "axis named"
    );
    // The rows span 0.5 s: tenths of a second.
    assert!(svg.contains("08:25:45.2"), "ticks at UTC times of day");
}
