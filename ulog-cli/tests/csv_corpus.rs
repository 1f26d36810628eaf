//! `ulog csv` on every corpus log equals pyulog's `ulog2csv` output byte for byte.
//!
//! Deliberate difference: in the logs of `common::RECOVERS_ROWS`, this reader
//! recovers data messages after mid-stream corruption that pyulog drops; there our
//! files may hold extra rows, and every other row must equal pyulog's, in order.
//! (The expected files already leave nested padding columns out, as we do; stock
//! ulog2csv 1.3 keeps them.)

mod common;

use std::collections::BTreeSet;
use std::path::Path;

fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// Rows of `ours` that are not in `theirs`, if `theirs` is `ours` with rows left out.
fn extra_rows(ours: &[u8], theirs: &[u8]) -> Option<usize> {
    let mut expected = theirs.split(|&b| b == b'\n').peekable();
    let mut extra = 0;
    for line in ours.split(|&b| b == b'\n') {
        if expected.peek() == Some(&line) {
            expected.next();
        } else {
            extra += 1;
        }
    }
    expected.next().is_none().then_some(extra)
}

#[test]
fn csv_of_every_corpus_log_equals_ulog2csv() {
    let Some(corpus) = common::corpus("csv_of_every_corpus_log_equals_ulog2csv") else {
        return;
    };
    let out_root = common::scratch("csv_corpus");
    let mut recovered = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        let out = out_root.join(&stem);
        let stdout = common::ulog_ok([
            "csv".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        let expected_dir = corpus.join("expected").join(&stem).join("csv");
        let expected = names(&expected_dir);
        assert_eq!(names(&out), expected, "{stem}: set of CSV files");
        assert_eq!(
            stdout.lines().filter(|l| l.starts_with("Writing ")).count(),
            expected.len()
        );
        for name in &expected {
            let ours = std::fs::read(out.join(name)).expect("our csv");
            let theirs = std::fs::read(expected_dir.join(name)).expect("expected csv");
            if ours == theirs {
                continue;
            }
            assert!(
                common::RECOVERS_ROWS.contains(&stem.as_str()),
                "{stem}/{name} differs from ulog2csv's"
            );
            let extra = extra_rows(&ours, &theirs)
                .unwrap_or_else(|| panic!("{stem}/{name}: differs by more than recovered rows"));
            recovered += extra;
        }
    }
    assert!(
        recovered > 0,
        "the logs listed in RECOVERS_ROWS should recover rows"
    );
}

#[test]
fn csv_filters_topics_and_time_like_ulog2csv() {
    let Some(corpus) = common::corpus("csv_filters_topics_and_time_like_ulog2csv") else {
        return;
    };
    let path = corpus.join("files").join("sample.ulg");
    let out = common::scratch("csv_filter");
    let expected_dir = corpus.join("expected/sample/csv");
    let att = std::fs::read_to_string(expected_dir.join("sample_vehicle_attitude_0.csv")).unwrap();
    let first: u64 = att
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let (start, end) = (first / 1_000_000 + 2, first / 1_000_000 + 4);
    let (start_s, end_s) = (start.to_string(), end.to_string());
    common::ulog_ok([
        "csv".as_ref(),
        path.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "-m".as_ref(),
        "vehicle_attitude,sensor_combined".as_ref(),
        "--time-start".as_ref(),
        start_s.as_ref(),
        "--time-end".as_ref(),
        end_s.as_ref(),
        "-d".as_ref(),
        ";".as_ref(),
    ]);
    assert_eq!(
        names(&out),
        [
            "sample_sensor_combined_0.csv",
            "sample_vehicle_attitude_0.csv"
        ]
        .map(String::from)
        .into()
    );
    for name in names(&out) {
        let ours = std::fs::read_to_string(out.join(&name)).unwrap();
        let full = std::fs::read_to_string(expected_dir.join(&name)).unwrap();
        let mut lines = full.lines();
        let header = lines.next().unwrap();
        // ulog2csv: from the first row at or after the start up to the first row at or
        // after the end.
        let ts = |l: &&str| l.split(',').next().unwrap().parse::<u64>().unwrap();
        let rows: Vec<&str> = lines
            .skip_while(|l| ts(l) < start * 1_000_000)
            .take_while(|l| ts(l) < end * 1_000_000)
            .collect();
        assert!(!rows.is_empty());
        let mut expected = header.replace(',', ";") + "\n";
        for r in rows {
            expected += &r.replace(',', ";");
            expected.push('\n');
        }
        assert_eq!(ours, expected, "{name}");
    }
}

#[test]
fn unknown_topic_is_an_error_with_a_suggestion() {
    let file = common::sample_file("csv_unknown_topic");
    let out = common::ulog([
        "csv".as_ref(),
        file.as_os_str(),
        "-m".as_ref(),
        "vehicle_atitude".as_ref(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("did you mean `vehicle_attitude`"), "{err}");
}

#[test]
fn csv_of_the_sample_matches_its_values() {
    let file = common::sample_file("csv_sample");
    let dir = file.parent().unwrap();
    common::ulog_ok(["csv".as_ref(), file.as_os_str()]);
    let esc = std::fs::read_to_string(dir.join("sample_esc_status_0.csv")).unwrap();
    let mut lines = esc.lines();
    assert_eq!(
        lines.next(),
        Some("timestamp,esc_count,esc[0].timestamp,esc[0].esc_rpm,esc[0].esc_voltage,esc[1].timestamp,esc[1].esc_rpm,esc[1].esc_voltage")
    );
    assert_eq!(
        lines.next(),
        Some("1000000,2,1000000,5000,16.0,1000001,5001,16.0")
    );
    let pos = std::fs::read_to_string(dir.join("sample_vehicle_local_position_0.csv")).unwrap();
    assert!(pos.lines().next().unwrap().ends_with(",vz,xy_valid"));
    assert!(pos.lines().nth(1).unwrap().ends_with(",1"));
    assert!(dir.join("sample_battery_status_1.csv").exists());
}

#[test]
fn parallel_jobs_write_the_same_files_and_announce_them_in_name_order() {
    let file = common::sample_file("csv_jobs");
    let dir = file.parent().unwrap();
    let run = |jobs: &str| {
        let out = dir.join(format!("j{jobs}"));
        let stdout = common::ulog_ok([
            "csv".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "-j".as_ref(),
            jobs.as_ref(),
        ]);
        let shown = stdout.replace(&out.display().to_string(), "OUT");
        (out, shown)
    };
    let (one, one_stdout) = run("1");
    let (many, many_stdout) = run("4");
    assert_eq!(one_stdout, many_stdout);
    let written: Vec<&str> = one_stdout
        .lines()
        .filter_map(|l| l.strip_prefix("Writing OUT/sample_"))
        .collect();
    assert!(written.len() > 3, "{one_stdout}");
    assert!(written.windows(2).all(|w| w[0] < w[1]), "{one_stdout}");
    assert_eq!(names(&one), names(&many));
    for name in names(&one) {
        let a = std::fs::read(one.join(&name)).unwrap();
        assert!(a.iter().filter(|&&b| b == b'\n').count() > 1, "{name}");
        assert_eq!(a, std::fs::read(many.join(&name)).unwrap(), "{name}");
    }
}
