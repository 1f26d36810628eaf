//! `ulog parquet` on the bundled sample log: where files go, failures (one line, a
//! distinct exit status each), many logs in one call, in parallel or not; and topic
//! names that file systems refuse or fold, in a dataset, `--per-log` and `ulog csv`.

mod common;

use std::path::Path;

fn stderr_line(out: &std::process::Output) -> String {
    let text = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(text.lines().count(), 1, "one line: {text}");
    text
}

fn tree(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v = Vec::new();
    for entry in std::fs::read_dir(dir).expect("read dir") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            for (name, bytes) in tree(&path) {
                let parent = path.file_name().unwrap().to_string_lossy();
                v.push((format!("{parent}/{name}"), bytes));
            }
        } else {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            v.push((name, std::fs::read(&path).expect("read file")));
        }
    }
    v.sort();
    v
}

#[test]
fn writes_beside_the_log_by_default() {
    let log = common::sample_file("parquet_default_dir");
    let stdout = common::ulog_ok(["parquet".as_ref(), "--per-log".as_ref(), log.as_os_str()]);
    let dir = log.with_file_name("sample");
    assert!(
        stdout.contains(&format!("Writing {}", dir.display())),
        "{stdout}"
    );
    let names: Vec<String> = tree(&dir).into_iter().map(|(n, _)| n).collect();
    assert_eq!(
        names,
        [
            "battery_status_0.parquet",
            "battery_status_1.parquet",
            "esc_status_0.parquet",
            "metadata.json",
            "vehicle_attitude_0.parquet",
            "vehicle_local_position_0.parquet",
        ]
    );
}

#[test]
fn failures_are_one_line_with_distinct_statuses() {
    let log = common::sample_file("parquet_failures");
    let dir = log.parent().unwrap().to_owned();

    let missing = dir.join("missing.ulg");
    let out = common::ulog([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        missing.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(3));
    assert!(stderr_line(&out).contains("missing.ulg: no such file"));

    let text = dir.join("text.ulg");
    std::fs::write(&text, "not a log").unwrap();
    let out = common::ulog(["parquet".as_ref(), "--per-log".as_ref(), text.as_os_str()]);
    assert_eq!(out.status.code(), Some(4));
    assert!(stderr_line(&out).contains("not a ULog file"));

    let out_dir = dir.join("out");
    let out = common::ulog([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        out_dir.as_os_str(),
        "-m".as_ref(),
        "battery_status,esc_statsu".as_ref(),
    ]);
    assert_eq!(out.status.code(), Some(5));
    assert!(
        stderr_line(&out).contains("no topic `esc_statsu` in the log (did you mean `esc_status`?)")
    );
    assert!(!out_dir.exists(), "nothing is written for an unknown topic");

    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let out = common::ulog(["parquet".as_ref(), "--per-log".as_ref(), empty.as_os_str()]);
    assert_eq!(out.status.code(), Some(3));
    assert!(stderr_line(&out).contains("no .ulg or .ulog files"));

    let out = common::ulog(["parquet"]);
    assert_eq!(out.status.code(), Some(2), "usage error");
}

#[test]
fn a_directory_of_logs_converts_in_one_call_in_parallel_or_not() {
    let root = common::scratch("parquet_many");
    let logs = root.join("logs");
    std::fs::create_dir_all(&logs).unwrap();
    let sample = ulog_core::testing::sample_log();
    for name in ["a.ulg", "b.ulg", "c.ULG"] {
        std::fs::write(logs.join(name), &sample).unwrap();
    }
    std::fs::write(logs.join("bad.ulg"), "not a log").unwrap();
    std::fs::write(logs.join("notes.txt"), "not a log either, and not .ulg").unwrap();

    let mut trees = Vec::new();
    for jobs in ["1", "2"] {
        let out_dir = root.join(format!("out{jobs}"));
        let out = common::ulog([
            "parquet".as_ref(),
            "--per-log".as_ref(),
            logs.as_os_str(),
            "-o".as_ref(),
            out_dir.as_os_str(),
            "--jobs".as_ref(),
            jobs.as_ref(),
        ]);
        // The bad log fails; the others are converted all the same.
        assert_eq!(out.status.code(), Some(4), "jobs {jobs}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = stderr.lines().collect();
        assert_eq!(lines.len(), 2, "{stderr}");
        assert!(lines[0].contains("bad.ulg: not a ULog file"), "{stderr}");
        assert_eq!(lines[1], "ulog: parquet: 1 of 4 logs failed (see above)");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            stdout.lines().filter(|l| l.starts_with("Writing ")).count(),
            3
        );
        let tree = tree(&out_dir);
        let dirs: std::collections::BTreeSet<&str> = tree
            .iter()
            .map(|(n, _)| n.split('/').next().unwrap())
            .collect();
        assert_eq!(dirs.into_iter().collect::<Vec<_>>(), ["a", "b", "c"]);
        trees.push(tree);
    }
    // The same files, byte for byte, whatever the number of threads.
    let names = |t: &[(String, Vec<u8>)]| t.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&trees[0]), names(&trees[1]));
    for ((name, a), (_, b)) in trees[0].iter().zip(&trees[1]) {
        assert!(a == b, "{name} differs between --jobs 1 and --jobs 2");
    }

    // Topics: each log gets those it has; a name in none of them is an error.
    std::fs::remove_file(logs.join("bad.ulg")).unwrap();
    let out_dir = root.join("filtered");
    let out = common::ulog([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        logs.as_os_str(),
        "-o".as_ref(),
        out_dir.as_os_str(),
        "-m".as_ref(),
        "battery_status,vehicle_local_positon".as_ref(),
    ]);
    assert_eq!(out.status.code(), Some(5));
    assert_eq!(
        stderr_line(&out).trim_end(),
        "ulog: parquet: no topic `vehicle_local_positon` in any of the 3 logs (did you mean `vehicle_local_position`?)"
    );
    let names: Vec<String> = tree(&out_dir.join("a"))
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    assert_eq!(
        names,
        [
            "battery_status_0.parquet",
            "battery_status_1.parquet",
            "metadata.json"
        ]
    );

    // Two logs that would write to one folder are refused before any work.
    let other = root.join("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("a.ulg"), &sample).unwrap();
    let out_dir = root.join("clash");
    let out = common::ulog([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        logs.as_os_str(),
        other.as_os_str(),
        "-o".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(6));
    assert!(stderr_line(&out).contains("would be written here"));
    assert!(!out_dir.exists());
}

#[test]
fn each_codec_is_what_the_files_say_and_the_values_are_the_same() {
    use ulog_core::export::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    use ulog_core::export::parquet::basic::Compression;
    use ulog_core::export::parquet::file::reader::{FileReader, SerializedFileReader};

    let log = common::sample_file("parquet_codecs");
    let root = log.parent().unwrap().to_owned();
    let mut batches = Vec::new();
    let mut sizes = Vec::new();
    for codec in ["snappy", "zstd", "none"] {
        let out_dir = root.join(codec);
        common::ulog_ok([
            "parquet".as_ref(),
            "--per-log".as_ref(),
            log.as_os_str(),
            "-o".as_ref(),
            out_dir.as_os_str(),
            "--compression".as_ref(),
            codec.as_ref(),
        ]);
        let dir = out_dir.join("sample");
        let mut read = Vec::new();
        let mut bytes = 0;
        for (name, data) in tree(&dir) {
            if !name.ends_with(".parquet") {
                continue;
            }
            bytes += data.len();
            let path = dir.join(&name);
            // The codec the parquet crate's reader finds in every column chunk.
            let reader = SerializedFileReader::new(std::fs::File::open(&path).unwrap()).unwrap();
            for group in reader.metadata().row_groups() {
                for column in group.columns() {
                    let found = column.compression();
                    let expected = match codec {
                        "snappy" => matches!(found, Compression::SNAPPY),
                        "zstd" => matches!(found, Compression::ZSTD(_)),
                        _ => matches!(found, Compression::UNCOMPRESSED),
                    };
                    assert!(expected, "{codec}: {name}: {found:?}");
                }
            }
            let rows: Vec<_> =
                ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&path).unwrap())
                    .unwrap()
                    .build()
                    .unwrap()
                    .collect::<Result<_, _>>()
                    .unwrap();
            read.push((name, rows));
        }
        assert!(!read.is_empty());
        batches.push(read);
        sizes.push(bytes);
    }
    assert_eq!(batches[0], batches[1], "zstd reads back as snappy does");
    assert_eq!(
        batches[0], batches[2],
        "uncompressed reads back as snappy does"
    );
    assert!(sizes[1] < sizes[2], "zstd {} < none {}", sizes[1], sizes[2]);
}

/// Whether `name` is a valid file name on Windows, macOS and Linux alike.
fn portable(name: &str) -> bool {
    let stem = name.split('.').next().unwrap_or("").to_ascii_uppercase();
    let devices = ["CON", "PRN", "AUX", "NUL"];
    let numbered = stem.len() == 4
        && (stem.starts_with("COM") || stem.starts_with("LPT"))
        && stem.as_bytes()[3].is_ascii_digit();
    !name.is_empty()
        && name.len() <= 255
        && name.is_ascii()
        && !name
            .chars()
            .any(|c| c.is_control() || r#"<>:"/\|?*"#.contains(c))
        && !name.ends_with(['.', ' '])
        && !devices.contains(&stem.as_str())
        && !numbered
}

/// Every file name in `dir` (one level), checked portable and distinct in any case.
fn portable_names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut folded = std::collections::HashSet::new();
    for n in &names {
        assert!(portable(n), "{n}");
        assert!(folded.insert(n.to_lowercase()), "{n} meets another name");
    }
    names
}

#[test]
fn topic_names_file_systems_refuse_or_fold_keep_every_row() {
    let dir = common::scratch("parquet_awkward");
    let (bytes, names) = ulog_core::testing::awkward_names_log();
    let log = dir.join("awkward.ulg");
    std::fs::write(&log, bytes).unwrap();

    // A dataset: a folder per topic, every topic's rows in it.
    let ds = dir.join("dataset");
    common::ulog_ok([
        "parquet".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        ds.as_os_str(),
    ]);
    // The topic folders (`_schemas` holds their union schemas).
    let folders: Vec<String> = portable_names(&ds)
        .into_iter()
        .filter(|n| ds.join(n).is_dir() && n != ulog_core::export::SCHEMAS_DIR)
        .collect();
    assert_eq!(folders.len(), names.len(), "{folders:?}");
    // `--per-log`: a file per topic instance.
    let per_log = dir.join("per_log");
    common::ulog_ok([
        "parquet".as_ref(),
        "--per-log".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        per_log.as_os_str(),
    ]);
    let files = portable_names(&per_log.join("awkward"));
    assert_eq!(
        files.iter().filter(|f| f.ends_with(".parquet")).count(),
        names.len()
    );
    assert!(files.contains(&"vehicle_status_0.parquet".to_owned()));
    assert!(files.contains(&"foo_0.parquet".to_owned()));
    // CSV: a file per topic instance, pyulog's names for the plain ones.
    let csv = dir.join("csv");
    std::fs::create_dir_all(&csv).unwrap();
    common::ulog_ok([
        "csv".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        csv.as_os_str(),
    ]);
    let csvs = portable_names(&csv);
    assert_eq!(csvs.len(), names.len(), "{csvs:?}");
    assert!(csvs.contains(&"awkward_vehicle_status_0.csv".to_owned()));
    assert!(csvs.contains(&"awkward_a_b_0.csv".to_owned()));
    for (i, _) in names.iter().enumerate() {
        let n = i.to_string();
        let holding = csvs
            .iter()
            .filter(|f| {
                let text = std::fs::read_to_string(csv.join(f)).unwrap();
                let rows: Vec<&str> = text.lines().skip(1).collect();
                rows.len() == i + 1 && rows.iter().all(|r| r.ends_with(&format!(",{n}")))
            })
            .count();
        assert_eq!(holding, 1, "the rows of topic {i}");
    }

    // Each topic found by its real name, with its rows: by DuckDB where it is, by
    // the files' metadata otherwise.
    for (i, name) in names.iter().enumerate() {
        let expected = format!("{}", i + 1);
        if cfg!(query_engines) {
            let script = "import duckdb, sys\n\
                f = duckdb.execute(\"SELECT file_name FROM parquet_kv_metadata(? || '/*/*.parquet') \
                WHERE decode(key) = 'ulog.topic' AND decode(value) = ?\", [sys.argv[1], sys.argv[2]]).fetchall()\n\
                assert len(f) == 1, f\n\
                print(duckdb.execute('SELECT count(*) FROM read_parquet(?) WHERE n = ?', \
                [f[0][0], int(sys.argv[3])]).fetchone()[0])";
            let out = common::python([
                "-c".as_ref(),
                script.as_ref(),
                ds.as_os_str(),
                name.as_ref(),
                i.to_string().as_ref() as &std::ffi::OsStr,
            ]);
            assert_eq!(String::from_utf8_lossy(&out).trim(), expected, "{name}");
        } else {
            let found: Vec<i64> = folders
                .iter()
                .flat_map(|f| std::fs::read_dir(ds.join(f)).unwrap())
                .map(|e| e.unwrap().path())
                .filter_map(|p| {
                    let file = std::fs::File::open(&p).unwrap();
                    let reader =
                        ulog_core::export::parquet::file::reader::SerializedFileReader::new(file)
                            .unwrap();
                    use ulog_core::export::parquet::file::reader::FileReader;
                    let meta = reader.metadata().file_metadata();
                    let topic = meta
                        .key_value_metadata()?
                        .iter()
                        .find(|kv| kv.key == "ulog.topic")?
                        .value
                        .clone()?;
                    (topic == *name).then_some(meta.num_rows())
                })
                .collect();
            assert_eq!(found, [i as i64 + 1], "{name}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
