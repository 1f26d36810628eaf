//! `ulog csv` on every corpus log equals pyulog's `ulog2csv` output byte for byte.
//!
//! Deliberate difference: in the logs of `common::RECOVERS_ROWS`, this reader
//! recovers data messages after mid-stream corruption that pyulog drops; there our
//! files may hold extra rows, and every other row must equal pyulog's, in order.
//! (The expected files leave nested padding columns out, which stock ulog2csv 1.3
//! and we keep: they are dropped from our files before comparing, and
//! `csv_columns_equal_stock_ulog2csv_with_nested_padding` compares with ulog2csv
//! itself.)

mod common;

use std::collections::BTreeSet;
use std::path::Path;

fn names(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// `csv` without its nested padding columns (`esc[0]._padding0[3]`).
fn without_nested_padding(csv: &[u8]) -> Vec<u8> {
    let text = std::str::from_utf8(csv).expect("utf-8 csv");
    let Some(header) = text.lines().next() else {
        return csv.to_vec();
    };
    let keep: Vec<bool> = header
        .split(',')
        .map(|c| !c.contains("._padding"))
        .collect();
    if keep.iter().all(|&k| k) {
        return csv.to_vec();
    }
    let mut out = String::with_capacity(text.len());
    for line in text.split_inclusive('\n') {
        let (row, end) = match line.strip_suffix('\n') {
            Some(r) => (r, "\n"),
            None => (line, ""),
        };
        let cells: Vec<&str> = row
            .split(',')
            .zip(&keep)
            .filter_map(|(c, &k)| k.then_some(c))
            .collect();
        out.push_str(&cells.join(","));
        out.push_str(end);
    }
    out.into_bytes()
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
    let corpus = common::corpus();
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
            let ours = without_nested_padding(&std::fs::read(out.join(name)).expect("our csv"));
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
    // The repository's own logs are whole: none of them recovers anything.
    assert!(
        recovered > 0 || !cfg!(full_corpus),
        "the logs listed in RECOVERS_ROWS should recover rows"
    );
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn csv_filters_topics_and_time_like_ulog2csv() {
    let corpus = common::corpus();
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

/// Logs of the corpus with nested padding (`position_setpoint_triplet`'s
/// `previous._padding0[i]`, `esc_status`'s `esc[i]._padding0[j]`, telemetry
/// heartbeats): our files equal stock ulog2csv's, padding columns included.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog: pip install pyulog==1.3.0, then touch ulog-cli/build.rs"
)]
fn csv_columns_equal_stock_ulog2csv_with_nested_padding() {
    let corpus = common::corpus();
    let root = common::scratch("csv_stock_ulog2csv");
    let mut padded = 0;
    let mut stems = vec!["esc_status_log"];
    if cfg!(full_corpus) {
        stems.extend(["sample_log_small", "6ba1abc7-b433-4029-b8f5-3b2bb12d3b6c"]);
    }
    for stem in stems {
        let path = corpus.join("files").join(format!("{stem}.ulg"));
        let (ours, theirs) = (root.join(stem).join("ours"), root.join(stem).join("py"));
        common::ulog_ok([
            "csv".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            ours.as_os_str(),
        ]);
        let py = std::process::Command::new("ulog2csv")
            .arg("-o")
            .arg(&theirs)
            .arg(&path)
            .output()
            .expect("run ulog2csv");
        assert!(
            py.status.success(),
            "{}",
            String::from_utf8_lossy(&py.stderr)
        );
        assert_eq!(names(&ours), names(&theirs), "{stem}: set of CSV files");
        for name in names(&theirs) {
            let a = std::fs::read_to_string(ours.join(&name)).unwrap();
            let b = std::fs::read_to_string(theirs.join(&name)).unwrap();
            assert_eq!(a.lines().next(), b.lines().next(), "{stem}/{name}: header");
            padded += usize::from(b.lines().next().unwrap_or("").contains("._padding"));
            assert!(a == b, "{stem}/{name}: differs from ulog2csv's");
        }
    }
    let least = if cfg!(full_corpus) { 4 } else { 1 };
    assert!(
        padded >= least,
        "files with nested padding columns: {padded}"
    );
}
