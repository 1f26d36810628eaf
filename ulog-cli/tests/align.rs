//! `ulog align` against pandas and numpy on pyulog's data (scripts/align_check.py):
//! `previous` is `merge_asof(direction="backward")` (with and without a tolerance),
//! `nearest` is `merge_asof(direction="nearest")`, `linear` is `numpy.interp` per
//! float column within each topic's rows, on every corpus log; the grid of `--rate`
//! and the windows on written logs; and the Parquet table (`-o OUT.parquet`) read by
//! pyarrow against the CSV table of the same command (scripts/align_parquet_check.py).

mod common;

use std::path::{Path, PathBuf};

use ulog_core::read::FieldShape;
use ulog_core::testing::LogBuilder;
use ulog_core::ULog;

/// The grid (a topic of about 2,000 rows: enough steps, a quick check) and the
/// topics to align on it: the one with the most rows, the one with the fewest (at
/// least 2), and `vehicle_attitude` (a quaternion) when the log has it.
fn choose(log: &ULog<'_>) -> Option<(String, Vec<String>)> {
    let mut topics: Vec<(String, usize)> = log
        .topics()
        .filter(|t| t.multi_id() == 0 && t.timestamp_field().is_some() && t.len() >= 2)
        .map(|t| (t.name().to_owned(), t.len()))
        .collect();
    topics.sort();
    let grid = topics
        .iter()
        .min_by_key(|(_, n)| n.abs_diff(2000))?
        .0
        .clone();
    let mut others: Vec<String> = Vec::new();
    let mut by_rows: Vec<&(String, usize)> = topics.iter().filter(|(n, _)| *n != grid).collect();
    by_rows.sort_by_key(|(_, n)| *n);
    for pick in [by_rows.last(), by_rows.first()].into_iter().flatten() {
        if !others.contains(&pick.0) {
            others.push(pick.0.clone());
        }
    }
    if grid != "vehicle_attitude"
        && topics.iter().any(|(n, _)| n == "vehicle_attitude")
        && !others.iter().any(|n| n == "vehicle_attitude")
    {
        others.push("vehicle_attitude".into());
    }
    (!others.is_empty()).then_some((grid, others))
}

/// The corpus logs that parse and have topics to align, with [`choose`]'s grid and
/// topics.
fn chosen_logs() -> Vec<(String, PathBuf, String, Vec<String>)> {
    common::corpus_logs(&common::corpus())
        .into_iter()
        .filter_map(|(stem, file)| {
            let bytes = std::fs::read(&file).unwrap();
            let (grid, topics) = choose(&ULog::parse(&bytes).ok()?)?;
            Some((stem, file, grid, topics))
        })
        .collect()
}

fn check(
    file: &Path,
    counts: &str,
    out: &Path,
    grid: &str,
    topics: &[String],
    method: &str,
    tol_us: Option<u64>,
) -> String {
    let selection = topics.join(",");
    let mut args: Vec<String> = vec![
        "align".into(),
        file.display().to_string(),
        selection,
        "--on".into(),
        grid.into(),
        "--method".into(),
        method.into(),
        "-o".into(),
        out.display().to_string(),
    ];
    if let Some(us) = tol_us {
        args.push("--tolerance".into());
        args.push(format!("{}", us as f64 / 1e6));
    }
    common::ulog_ok(&args);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/align_check.py");
    let mut py: Vec<String> = vec![
        script.display().to_string(),
        file.display().to_string(),
        out.display().to_string(),
        grid.into(),
        method.into(),
        tol_us.map_or("-".into(), |u| u.to_string()),
        counts.into(),
    ];
    py.extend(topics.iter().cloned());
    String::from_utf8(common::python(&py)).unwrap()
}

#[test]
#[cfg_attr(
    not(pandas),
    ignore = "needs pyulog, pandas and numpy (pip install pyulog==1.3.0 pandas)"
)]
fn previous_nearest_and_linear_equal_pandas_and_numpy_on_every_corpus_log() {
    let scratch = common::scratch("align_corpus");
    let mut logs = 0;
    for (stem, file, grid, topics) in chosen_logs() {
        let out = scratch.join(format!("{stem}.csv"));
        let bytes = std::fs::read(&file).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let counts: serde_json::Map<String, serde_json::Value> = topics
            .iter()
            .chain([&grid])
            .map(|t| (t.clone(), log.topic(t, 0).unwrap().len().into()))
            .collect();
        let counts = serde_json::Value::Object(counts).to_string();
        let mut compared = true;
        for (method, tol) in [
            ("previous", None),
            ("previous", Some(20_000)),
            ("nearest", None),
            ("nearest", Some(5_000)),
            ("linear", None),
        ] {
            let summary = check(&file, &counts, &out, &grid, &topics, method, tol);
            // pyulog prints its warnings on stdout: the summary is the last line.
            let summary = summary.lines().last().unwrap_or_default().to_owned();
            let json: serde_json::Value = serde_json::from_str(&summary).unwrap();
            if json.get("skipped").is_some() {
                eprintln!("{stem}: skipped: {summary}");
                compared = false;
                break;
            }
            assert!(
                json["cells"].as_u64().unwrap() > 0,
                "{stem} {method}: {summary}"
            );
            eprintln!("{stem} on {grid} {method} {tol:?}: {summary}");
        }
        logs += usize::from(compared);
    }
    // The repository's own corpus has four logs with two timed topics (`short_list`
    // has none); the full one 17 besides two damaged ones skipped above.
    assert!(logs >= 4, "{logs} logs compared");
}

/// A log of two topics written for the test: `a` every 10 ms from 1 s to 1.49 s, `b`
/// every 50 ms from 1.025 s to 1.475 s with a float that is its time in ms.
fn written() -> Vec<u8> {
    let mut b = LogBuilder::new(1, 1_000_000);
    b.format("a:uint64_t timestamp;int32_t n;");
    b.format("b:uint64_t timestamp;float ms;int16_t k;");
    b.subscribe(0, 0, "a");
    b.subscribe(0, 1, "b");
    for i in 0..50u64 {
        let t = 1_000_000 + i * 10_000;
        let mut p = t.to_le_bytes().to_vec();
        p.extend_from_slice(&(i as i32).to_le_bytes());
        b.data(0, &p);
        if i % 5 == 2 {
            let tb = t + 5_000;
            let mut p = tb.to_le_bytes().to_vec();
            p.extend_from_slice(&((tb / 1000) as f32).to_le_bytes());
            p.extend_from_slice(&((i / 5) as i16).to_le_bytes());
            b.data(1, &p);
        }
    }
    b.into_bytes()
}

fn table(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn rate_grid_windows_and_absent_cells() {
    let file = common::scratch("align_written").join("two.ulg");
    std::fs::write(&file, written()).unwrap();
    let f = file.display().to_string();
    // 20 Hz from the span's start (1 s) to its end (1.49 s): 10 steps.
    let out = common::ulog_ok(["align", &f, "a.n,b", "--rate", "20"]);
    let t = table(&out);
    assert_eq!(t[0], ["timestamp", "a.n", "b.timestamp", "b.ms", "b.k"]);
    let steps: Vec<u64> = t[1..].iter().map(|r| r[0].parse().unwrap()).collect();
    let expected: Vec<u64> = (0..10).map(|k| 1_000_000 + k * 50_000).collect();
    assert_eq!(steps, expected);
    // b's first row is at 1.025 s: the steps before it have no b.
    assert_eq!(t[1][1], "0");
    assert_eq!(&t[1][2..], ["", "", ""]);
    assert_eq!(t[2][1], "5");
    assert_eq!(t[2][2], "1025000");
    // Linear: b.ms is its time in ms, so between rows it is the step's time; b.k (an
    // integer) is the earlier row's; after b's last row (1.475 s) nothing.
    let out = common::ulog_ok([
        "align", &f, "b", "--rate", "20", "--method", "linear", "--start", "0.1", "--end", "0.45",
    ]);
    let t = table(&out);
    let steps: Vec<u64> = t[1..].iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(
        steps,
        [1_100_000, 1_150_000, 1_200_000, 1_250_000, 1_300_000, 1_350_000, 1_400_000]
    );
    for r in &t[1..] {
        let step: f64 = r[0].parse().unwrap();
        let ms: f64 = r[2].parse().unwrap();
        assert!((ms - step / 1000.0).abs() < 1e-3, "{r:?}");
    }
    // Tolerance: `previous` more than 10 ms away is absent.
    let out = common::ulog_ok(["align", &f, "b.ms", "--on", "a", "--tolerance", "0.01"]);
    let t = table(&out);
    let absent = t[1..].iter().filter(|r| r[1].is_empty()).count();
    assert!(absent > 20 && absent < 48, "{absent} absent");
}

#[test]
fn unknown_names_and_bad_options_are_refused() {
    let file = common::scratch("align_refused").join("two.ulg");
    std::fs::write(&file, written()).unwrap();
    let f = file.display().to_string();
    let out = common::ulog(["align", &f, "b.mss", "--on", "a"]);
    assert_eq!(out.status.code(), Some(5));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("`ms`"), "{err}");
    let out = common::ulog(["align", &f, "b", "--on", "c"]);
    assert_eq!(out.status.code(), Some(5));
    let out = common::ulog(["align", &f, "b", "--rate", "0"]);
    assert_eq!(out.status.code(), Some(6));
    let out = common::ulog(["align", &f, "b"]);
    assert_eq!(out.status.code(), Some(2), "--on or --rate is required");
}

/// The first topic (instance 0, with rows and a timestamp) of `log` that has a
/// `char[N]` field, other than those of `taken`.
fn with_text(log: &ULog<'_>, taken: &[String]) -> Option<String> {
    let mut topics: Vec<_> = log
        .topics()
        .filter(|t| t.multi_id() == 0 && !t.is_empty() && t.timestamp_field().is_some())
        .filter(|t| !taken.iter().any(|n| n == t.name()))
        .filter(|t| {
            t.fields()
                .is_ok_and(|f| f.iter().any(|r| matches!(r.shape(), FieldShape::String(_))))
        })
        .map(|t| t.name().to_owned())
        .collect();
    topics.sort();
    topics.into_iter().next()
}

/// Runs `ulog align FILE TOPICS ARGS` to a CSV and to a Parquet table, and `ulog
/// parquet --per-log --flatten` of the topics (the types to expect), in `dir`; the summary of
/// scripts/align_parquet_check.py, which fails the test at the first difference.
fn parquet_against_csv(
    file: &Path,
    dir: &Path,
    topics: &[String],
    args: &[&str],
) -> serde_json::Value {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).unwrap();
    let (csv, parquet, flat) = (dir.join("t.csv"), dir.join("t.parquet"), dir.join("flat"));
    let selection = topics.join(",");
    let file = file.display().to_string();
    for out in [&csv, &parquet] {
        let mut a: Vec<String> = vec!["align".into(), file.clone(), selection.clone()];
        a.extend(args.iter().map(|s| s.to_string()));
        a.extend(["-o".into(), out.display().to_string()]);
        common::ulog_ok(a);
    }
    let flat_dir = flat.display().to_string();
    common::ulog_ok([
        "parquet",
        &file,
        "--per-log",
        "--flatten",
        "-m",
        &selection,
        "-o",
        &flat_dir,
    ]);
    let stem = Path::new(&file).file_stem().unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/align_parquet_check.py");
    let out = common::python([
        script.as_os_str(),
        csv.as_os_str(),
        parquet.as_os_str(),
        flat.join(stem).as_os_str(),
    ]);
    serde_json::from_slice(&out).unwrap()
}

/// How many cells of a summary were compared, and how many were null.
fn counts(summary: &serde_json::Value) -> (u64, u64) {
    (
        summary["cells"].as_u64().unwrap(),
        summary["nulls"].as_u64().unwrap(),
    )
}

#[test]
#[cfg_attr(not(pyarrow), ignore = "needs pyarrow (pip install pyarrow)")]
fn parquet_table_holds_the_csv_tables_cells_and_the_exports_types_on_every_corpus_log() {
    let scratch = common::scratch("align_parquet_corpus");
    let (mut logs, mut nulls, mut text) = (0, 0, 0);
    for (stem, file, grid, mut topics) in chosen_logs() {
        let bytes = std::fs::read(&file).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        if let Some(t) = with_text(&log, &topics) {
            topics.push(t);
            text += 1;
        }
        for args in [
            &["--on", grid.as_str()][..],
            &[
                "--on",
                grid.as_str(),
                "--method",
                "nearest",
                "--tolerance",
                "0.005",
            ],
        ] {
            let summary = parquet_against_csv(&file, &scratch.join(&stem), &topics, args);
            let (cells, n) = counts(&summary);
            assert!(cells > 0, "{stem} {args:?}: {summary}");
            nulls += n;
            eprintln!("{stem} {topics:?} {args:?}: {summary}");
        }
        logs += 1;
    }
    // As in the pandas check: four logs of the repository's own corpus, 17 of the full.
    assert!(logs >= 4, "{logs} logs compared");
    assert!(nulls > 0, "no absent value compared");
    if cfg!(full_corpus) {
        assert!(text > 0, "no text column compared");
    }
}

#[test]
#[cfg_attr(not(pyarrow), ignore = "needs pyarrow (pip install pyarrow)")]
fn parquet_table_of_a_rate_grid_with_linear_holds_the_csv_tables_cells() {
    let scratch = common::scratch("align_parquet_rate");
    let mut logs = 0;
    for (stem, file, grid, mut topics) in chosen_logs() {
        topics.insert(0, grid);
        let summary = parquet_against_csv(
            &file,
            &scratch.join(&stem),
            &topics,
            &["--rate", "50", "--method", "linear"],
        );
        assert!(counts(&summary).0 > 0, "{stem}: {summary}");
        eprintln!("{stem} {topics:?}: {summary}");
        logs += 1;
        if logs == 5 {
            break;
        }
    }
    assert!(logs >= 4, "{logs} logs compared");

    // More steps than a record batch holds (65,536): 98,001 steps over 0.49 s, `b`
    // absent before its first row and after its last.
    let file = scratch.join("two.ulg");
    std::fs::write(&file, written()).unwrap();
    let args = ["--rate", "200000", "--method", "linear"];
    let topics = ["a".to_owned(), "b".to_owned()];
    let summary = parquet_against_csv(&file, &scratch.join("written"), &topics, &args);
    assert_eq!(summary["rows"], 98_001, "{summary}");
    assert!(counts(&summary).1 > 0, "{summary}");
    // The CSV is formatted in parts on threads: the same text on one thread.
    let f = file.display().to_string();
    let one = common::ulog_ok([
        "align", &f, "a,b", "--rate", "200000", "--method", "linear", "-j", "1",
    ]);
    let three = common::ulog_ok([
        "align", &f, "a,b", "--rate", "200000", "--method", "linear", "-j", "3",
    ]);
    assert!(one == three, "the CSV differs with the number of threads");
}

#[test]
fn parquet_to_a_path_that_cannot_be_written_is_an_error_naming_it() {
    let dir = common::scratch("align_parquet_unwritable");
    let file = dir.join("two.ulg");
    std::fs::write(&file, written()).unwrap();
    let f = file.display().to_string();
    // In a folder that does not exist.
    let missing = dir.join("no such folder").join("t.parquet");
    let out = common::ulog([
        "align",
        &f,
        "a,b",
        "--on",
        "a",
        "-o",
        &missing.display().to_string(),
    ]);
    assert_eq!(out.status.code(), Some(3), "a file that cannot be written");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&missing.display().to_string()) && err.contains("no such file or directory"),
        "{err}"
    );
    // A folder by the name.
    let folder = dir.join("t.parquet");
    std::fs::create_dir(&folder).unwrap();
    let out = common::ulog([
        "align",
        &f,
        "a,b",
        "--on",
        "a",
        "-o",
        &folder.display().to_string(),
    ]);
    assert_eq!(out.status.code(), Some(3));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("is a directory"), "{err}");
    assert!(folder.is_dir(), "the folder is left as it was");
}

/// Runs `ulog align` with `args` to `out`; its standard error.
fn align_to(out: &Path, args: &[String]) -> String {
    let mut a: Vec<String> = vec!["align".into()];
    a.extend(args.iter().cloned());
    a.extend(["-o".into(), out.display().to_string()]);
    let run = common::ulog(&a);
    assert!(
        run.status.success(),
        "{a:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    String::from_utf8(run.stderr).unwrap()
}

#[test]
fn one_pass_writes_the_indexed_table_unless_it_says_why_not_on_every_corpus_log() {
    let scratch = common::scratch("align_one_pass");
    let (mut same, mut noted) = (0, 0);
    for (stem, file, grid, topics) in chosen_logs() {
        for method in ["previous", "nearest", "linear"] {
            let args: Vec<String> = vec![
                file.display().to_string(),
                topics.join(","),
                "--on".into(),
                grid.clone(),
                "--method".into(),
                method.into(),
            ];
            let (a, b) = (scratch.join("indexed.csv"), scratch.join("one_pass.csv"));
            assert_eq!(align_to(&a, &args), "", "{stem}");
            let one_pass: Vec<String> = args.iter().cloned().chain(["--one-pass".into()]).collect();
            let notes = align_to(&b, &one_pass);
            let (a, b) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
            if notes.is_empty() {
                assert!(
                    a == b,
                    "{stem} {method}: tables differ and nothing said why"
                );
                same += 1;
            } else {
                assert!(notes.lines().all(|l| l.contains(": note: ")), "{notes}");
                noted += 1;
            }
            // Parquet: the same file.
            if method == "linear" && notes.is_empty() {
                let (a, b) = (
                    scratch.join("indexed.parquet"),
                    scratch.join("one_pass.parquet"),
                );
                align_to(&a, &args);
                align_to(&b, &one_pass);
                assert!(
                    std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
                    "{stem}: Parquet tables differ"
                );
            }
        }
    }
    assert!(same >= 3, "{same} tables equal, {noted} with notes");
}

#[test]
fn one_pass_names_a_row_written_long_after_its_time() {
    let dir = common::scratch("align_one_pass_late");
    let mut b = LogBuilder::new(1, 1_000_000);
    b.format("a:uint64_t timestamp;int32_t n;");
    b.format("b:uint64_t timestamp;float v;");
    b.subscribe(0, 0, "a");
    b.subscribe(0, 1, "b");
    for k in 0..3_000u64 {
        let t = 1_000_000 + k * 10_000;
        b.data(
            0,
            &[t.to_le_bytes().as_slice(), &(k as i32).to_le_bytes()].concat(),
        );
        b.data(
            1,
            &[t.to_le_bytes().as_slice(), &(k as f32).to_le_bytes()].concat(),
        );
    }
    let late_at = b.bytes().len();
    b.data(
        1,
        &[
            1_500_000u64.to_le_bytes().as_slice(),
            &(-1f32).to_le_bytes(),
        ]
        .concat(),
    );
    let file = dir.join("late.ulg");
    std::fs::write(&file, b.into_bytes()).unwrap();
    let f = file.display().to_string();
    let args: Vec<String> = [&f, "b.v", "--on", "a", "--one-pass"]
        .map(String::from)
        .to_vec();
    let notes = align_to(&dir.join("t.csv"), &args);
    assert!(
        notes.contains("1 row(s) of b came after") && notes.contains(&format!("byte {late_at}")),
        "{notes}"
    );
    // The horizon is an option of --one-pass only; a field is no grid.
    assert_eq!(
        common::ulog(["align", &f, "b", "--on", "a", "--horizon", "1"])
            .status
            .code(),
        Some(2)
    );
    let out = common::ulog(["align", &f, "b", "--on", "a.n", "--one-pass"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("`a.n`"));
    let out = common::ulog(["align", &f, "b.x", "--on", "a", "--one-pass"]);
    assert_eq!(
        out.status.code(),
        Some(5),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
