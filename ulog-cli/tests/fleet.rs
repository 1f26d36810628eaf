//! `ulog parquet LOGS -o DATASET`: many logs as one dataset.
//!
//! - The README's five "Fleet analysis" queries, run with DuckDB (and three of them
//!   with DataFusion) over a dataset of the whole corpus, answer what this library's
//!   reader says of each log; so do the rows per topic and log; `log_id` is the XXH3-64
//!   that Python's `xxhash` computes, and `sha256` the SHA-256 of its `hashlib`.
//! - `logs.parquet`, read back with the `parquet` crate, says of every log what the
//!   reader says (versions, counts, duration, UTC start, damage).
//! - The same logs converted twice give the same bytes; adding a log adds only its
//!   files (and rewrites the four tables with its rows); a log that fails is reported
//!   and the rest go on.
//! - Two conversions into one dataset at once (two processes): the second waits for
//!   the first, both succeed, and the dataset is the one a single conversion writes,
//!   every file readable (by the `parquet` crate, and by DuckDB where it is).

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use serde_json::Value as Json;
use ulog_core::export;
use ulog_core::export::arrow_array::cast::AsArray;
use ulog_core::export::arrow_array::types::{
    Float64Type, TimestampMicrosecondType, UInt32Type, UInt64Type,
};
use ulog_core::export::arrow_array::{Array, RecordBatch};
use ulog_core::export::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use ulog_core::ULog;

/// The corpus's logs (every one converts).
fn logs() -> Vec<PathBuf> {
    common::corpus_logs(&common::corpus())
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

/// A Parquet file read back as one batch.
fn read(path: &Path) -> RecordBatch {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // The reader caps the batch at the file's rows: one batch.
    let mut reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.with_batch_size(usize::MAX).build())
        .expect("parquet reader");
    let batch = reader.next().expect("rows").expect("batch");
    assert!(reader.next().is_none(), "one batch");
    batch
}

/// An information value as text.
fn info(log: &ULog<'_>, key: &str) -> Option<String> {
    log.info_value(key)
        .and_then(|v| v.as_str())
        .map(|t| {
            t.as_bytes()
                .iter()
                .map(|&b| char::from(b))
                .collect::<String>()
        })
        .map(|s| s.trim_end_matches('\0').to_owned())
}

/// `ulog parquet LOGS -o DIR` (one thread per log, or `-j 1`).
fn convert(logs: &[PathBuf], dir: &Path, extra: &[&str]) -> std::process::Output {
    let mut args: Vec<std::ffi::OsString> = vec!["parquet".into()];
    args.extend(logs.iter().map(|p| p.as_os_str().to_owned()));
    args.extend(["-o".into(), dir.as_os_str().to_owned()]);
    args.extend(extra.iter().map(|s| (*s).into()));
    common::ulog(args)
}

/// A dataset of the whole corpus in the scratch folder `name`, and the logs.
fn corpus_dataset(name: &str) -> (PathBuf, Vec<PathBuf>) {
    let dir = common::scratch(name).join("dataset");
    let logs = logs();
    let out = convert(&logs, &dir, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (dir, logs)
}

fn json_text(v: &Json) -> Option<String> {
    v.as_str().map(str::to_owned)
}

#[test]
#[cfg_attr(
    not(query_engines),
    ignore = "needs python3 with duckdb and datafusion (pip install duckdb datafusion)"
)]
fn the_readmes_queries_answer_what_the_reader_says() {
    let (dir, logs) = corpus_dataset("fleet_queries");
    readme_queries_answer_what_the_reader_says(&dir, &logs);
}

#[test]
#[cfg_attr(
    not(query_engines),
    ignore = "needs python3 with duckdb and datafusion (pip install duckdb datafusion)"
)]
fn the_readmes_queries_answer_the_same_in_the_fleet_layout() {
    let dir = common::scratch("fleet_queries_fleet").join("dataset");
    let logs = logs();
    // Files of 1 MB at most, by vehicle and month: several logs per file, files
    // closed part way through a topic, and partition folders two deep.
    let layout = [
        "--layout",
        "fleet",
        "--partition-by",
        "vehicle,month",
        "--file-size",
        "1",
    ];
    let out = convert(&logs, &dir, &layout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    readme_queries_answer_what_the_reader_says(&dir, &logs);
}

/// The README's queries over the dataset `dir` of `logs` answer what the reader says.
fn readme_queries_answer_what_the_reader_says(dir: &Path, logs: &[PathBuf]) {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/fleet_queries.py");
    let answers: Json = serde_json::from_slice(&common::python([
        script.as_os_str(),
        readme.as_os_str(),
        dir.as_os_str(),
    ]))
    .expect("json");

    // log_id → the log; log_id is the file's XXH3-64 (Python's xxhash) and the
    // sha256 column its SHA-256 (hashlib's).
    let mut ids: BTreeMap<String, PathBuf> = BTreeMap::new();
    let mut sha256: BTreeMap<String, String> = BTreeMap::new();
    for row in answers["logs"].as_array().expect("logs") {
        let id = row[0].as_str().expect("id").to_owned();
        ids.insert(id.clone(), PathBuf::from(row[1].as_str().expect("path")));
        sha256.insert(id, row[2].as_str().expect("sha256").to_owned());
    }
    assert_eq!(ids.len(), logs.len(), "one row per log");
    let hashes: Json = serde_json::from_slice(&common::python(
        [
            "-c",
            "import hashlib, json, sys, xxhash\n\
             def both(p):\n\
             \x20   data = open(p, 'rb').read()\n\
             \x20   return [xxhash.xxh3_64_hexdigest(data), hashlib.sha256(data).hexdigest()]\n\
             print(json.dumps({p: both(p) for p in sys.argv[1:]}))",
        ]
        .into_iter()
        .map(std::ffi::OsString::from)
        .chain(logs.iter().map(|p| p.as_os_str().to_owned())),
    ))
    .expect("hashes");
    for (id, path) in &ids {
        let both = &hashes[path.to_str().expect("utf-8 path")];
        assert_eq!(
            Some(id.as_str()),
            both[0].as_str(),
            "{}: log_id",
            path.display()
        );
        assert_eq!(
            Some(sha256[id].as_str()),
            both[1].as_str(),
            "{}: sha256",
            path.display()
        );
    }

    let bytes: BTreeMap<String, Vec<u8>> = ids
        .iter()
        .map(|(id, p)| (id.clone(), std::fs::read(p).expect("read log")))
        .collect();
    let parsed: BTreeMap<&String, ULog<'_>> = bytes
        .iter()
        .map(|(id, b)| (id, ULog::parse(b).expect("parse")))
        .collect();

    // Rows per topic and log.
    let mut expected: BTreeSet<(String, String, u64)> = BTreeSet::new();
    for (id, log) in &parsed {
        let mut rows: BTreeMap<String, u64> = BTreeMap::new();
        for t in log.topics().filter(|t| !t.is_empty()) {
            *rows.entry(t.name().replace('/', "_")).or_default() += t.len() as u64;
        }
        expected.extend(rows.into_iter().map(|(t, n)| (t, (*id).clone(), n)));
    }
    let found: BTreeSet<(String, String, u64)> = answers["counts"]
        .as_array()
        .expect("counts")
        .iter()
        .map(|r| {
            (
                r[0].as_str().unwrap().to_owned(),
                r[1].as_str().unwrap().to_owned(),
                r[2].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(found, expected, "rows per topic and log");

    let duck = answers["duckdb"].as_array().expect("duckdb");
    let fusion = &answers["datafusion"];

    // 1. Flights per vehicle and firmware.
    let mut flights: BTreeMap<(Option<String>, Option<String>), u64> = BTreeMap::new();
    for log in parsed.values() {
        let vehicle = info(log, "sys_uuid").or_else(|| info(log, "ver_hw"));
        let firmware = log.release_version("ver_sw_release").map(|r| r.to_string());
        *flights.entry((vehicle, firmware)).or_default() += 1;
    }
    for rows in [&duck[0], &fusion["1"]] {
        let got: BTreeMap<(Option<String>, Option<String>), u64> = rows
            .as_array()
            .unwrap()
            .iter()
            .map(|r| ((json_text(&r[0]), json_text(&r[1])), r[2].as_u64().unwrap()))
            .collect();
        assert_eq!(got, flights, "flights per vehicle and firmware");
    }

    // 2. Highest point: the reader's maximum of -z, NaN left out.
    let mut highest: BTreeMap<String, f64> = BTreeMap::new();
    for (id, log) in &parsed {
        for t in log.topic_instances("vehicle_local_position") {
            let z = t.field("z").expect("z");
            for p in t.payloads() {
                let v = z.read(p).and_then(|v| v.as_f64()).expect("z value");
                if !v.is_nan() {
                    let m = highest.entry((*id).clone()).or_insert(f64::NEG_INFINITY);
                    *m = m.max(-v);
                }
            }
        }
    }
    assert!(highest.len() > 1 || !cfg!(full_corpus));
    for rows in [&duck[1], &fusion["2"]] {
        let got: BTreeMap<String, f64> = rows
            .as_array()
            .unwrap()
            .iter()
            .map(|r| (r[0].as_str().unwrap().to_owned(), r[1].as_f64().unwrap()))
            .collect();
        assert_eq!(got, highest, "max altitude per flight");
    }

    // 3. Lowest battery voltage above 0.
    let mut lowest: BTreeMap<String, f64> = BTreeMap::new();
    for (id, log) in &parsed {
        for t in log.topic_instances("battery_status") {
            let Ok(v) = t.field("voltage_v") else {
                continue;
            };
            for p in t.payloads() {
                let v = v.read(p).and_then(|v| v.as_f64()).expect("voltage");
                if v > 0.0 {
                    let m = lowest.entry((*id).clone()).or_insert(f64::INFINITY);
                    *m = m.min(v);
                }
            }
        }
    }
    let got: BTreeMap<String, f64> = duck[2]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r[0].as_str().unwrap().to_owned(), r[1].as_f64().unwrap()))
        .collect();
    assert_eq!(got, lowest, "min battery voltage per flight");

    // 4. Initial parameters that differ between v1.13.0 (dev) and v1.15.0 (dev).
    let of = |release: &str| -> Option<BTreeMap<String, f64>> {
        let mut found = parsed.values().filter(|l| {
            l.release_version("ver_sw_release")
                .map(|r| r.to_string())
                .as_deref()
                == Some(release)
        });
        let log = found.next()?;
        assert!(found.next().is_none(), "one log of {release} in the corpus");
        Some(
            log.initial_params()
                .iter()
                .map(|kv| (kv.name().into_owned(), kv.value().as_f64().expect("number")))
                .collect(),
        )
    };
    let (a, b) = (
        of("v1.13.0 (dev)").unwrap_or_default(),
        of("v1.15.0 (dev)").unwrap_or_default(),
    );
    let names: BTreeSet<&String> = a.keys().chain(b.keys()).collect();
    let differ: Vec<(String, Option<f64>, Option<f64>)> = names
        .into_iter()
        .map(|n| (n.clone(), a.get(n).copied(), b.get(n).copied()))
        .filter(|(_, x, y)| x != y)
        .collect();
    assert!(!differ.is_empty() || !cfg!(full_corpus));
    let got: Vec<(String, Option<f64>, Option<f64>)> = duck[3]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r[0].as_str().unwrap().to_owned(),
                r[1].as_f64(),
                r[2].as_f64(),
            )
        })
        .collect();
    assert_eq!(
        got, differ,
        "parameters that differ between two firmware versions"
    );

    // 5. Logs with damage.
    let mut damaged: Vec<(String, bool, u64, u64)> = parsed
        .iter()
        .filter(|(_, l)| l.has_damage() || l.is_truncated())
        .map(|(id, l)| {
            let corrupt = l
                .findings()
                .iter()
                .filter(|f| f.is_damage() && f.kind != ulog_core::read::FindingKind::Truncated)
                .map(|f| f.len)
                .sum();
            (
                ids[*id].display().to_string(),
                l.is_truncated(),
                corrupt,
                l.findings().len() as u64,
            )
        })
        .collect();
    damaged.sort();
    assert!(!damaged.is_empty() || !cfg!(full_corpus));
    for rows in [&duck[4], &fusion["5"]] {
        let got: Vec<(String, bool, u64, u64)> = rows
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r[0].as_str().unwrap().to_owned(),
                    r[1].as_bool().unwrap(),
                    r[2].as_u64().unwrap(),
                    r[3].as_u64().unwrap(),
                )
            })
            .collect();
        assert_eq!(got, damaged, "logs with damage");
    }
}

#[test]
fn the_table_of_logs_says_what_the_reader_says() {
    let (dir, logs) = corpus_dataset("fleet_logs");
    let table = read(&dir.join("logs.parquet"));
    assert_eq!(table.num_rows(), logs.len());
    let text = |name: &str, i: usize| -> Option<String> {
        let c = table.column_by_name(name).expect(name).as_string::<i32>();
        c.is_valid(i).then(|| c.value(i).to_owned())
    };
    let u64s = |name: &str| {
        table
            .column_by_name(name)
            .expect(name)
            .as_primitive::<UInt64Type>()
            .clone()
    };
    let u32s = |name: &str| {
        table
            .column_by_name(name)
            .expect(name)
            .as_primitive::<UInt32Type>()
            .clone()
    };
    let bools = |name: &str| table.column_by_name(name).expect(name).as_boolean().clone();
    let mut ids = Vec::new();
    for i in 0..table.num_rows() {
        let path = PathBuf::from(text("path", i).expect("path"));
        let bytes = std::fs::read(&path).expect("read");
        let log = ULog::parse(&bytes).expect("parse");
        let what = path.display().to_string();
        ids.push(text("log_id", i).expect("id"));
        assert_eq!(u64s("size").value(i), bytes.len() as u64, "{what}");
        assert_eq!(text("sys_name", i), info(&log, "sys_name"), "{what}");
        assert_eq!(text("ver_hw", i), info(&log, "ver_hw"), "{what}");
        assert_eq!(text("ver_sw", i), info(&log, "ver_sw"), "{what}");
        assert_eq!(
            text("ver_sw_release", i),
            log.release_version("ver_sw_release").map(|r| r.to_string()),
            "{what}"
        );
        // Times by the log's span, the one rule for where a log starts and ends.
        let span = log.span();
        assert_eq!(u64s("start_timestamp").value(i), span.start(), "{what}");
        let utc = table
            .column_by_name("start_utc")
            .unwrap()
            .as_primitive::<TimestampMicrosecondType>();
        let clock = log.utc();
        assert_eq!(
            utc.is_valid(i).then(|| utc.value(i)),
            clock.as_ref().map(|c| c.at(span.start()).micros()),
            "{what}: UTC start, by ULog::utc's rule"
        );
        assert_eq!(
            text("utc_source", i),
            clock.map(|c| c.source().to_string()),
            "{what}"
        );
        let duration = table
            .column_by_name("duration_s")
            .unwrap()
            .as_primitive::<Float64Type>();
        assert_eq!(
            duration.value(i),
            (span.end() - span.start()) as f64 / 1e6,
            "{what}"
        );
        let topics = log.topics().filter(|t| !t.is_empty()).count() as u32;
        let messages: u64 = log.topics().map(|t| t.len() as u64).sum();
        assert_eq!(u32s("topics").value(i), topics, "{what}");
        assert_eq!(u64s("messages").value(i), messages, "{what}");
        assert_eq!(bools("truncated").value(i), log.is_truncated(), "{what}");
        assert_eq!(bools("damaged").value(i), log.has_damage(), "{what}");
        assert_eq!(
            u32s("findings").value(i),
            log.findings().len() as u32,
            "{what}"
        );
        assert_eq!(
            u32s("dropouts").value(i),
            log.dropouts().len() as u32,
            "{what}"
        );
    }
    let mut sorted = ids.clone();
    sorted.sort();
    assert_eq!(ids, sorted, "rows sorted by log_id");

    // The other tables: as many rows per log as the reader has.
    let params = read(&dir.join("parameters.parquet"));
    let messages = read(&dir.join("messages.parquet"));
    let formats = read(&dir.join("formats.parquet"));
    let count = |t: &RecordBatch, id: &str, kind: Option<&str>| {
        let ids = t.column(0).as_string::<i32>();
        let kinds = t
            .column_by_name("kind")
            .map(|k| k.as_string::<i32>().clone());
        (0..t.num_rows())
            .filter(|&i| ids.value(i) == id)
            .filter(|&i| kind.map_or(true, |k| kinds.as_ref().unwrap().value(i) == k))
            .count()
    };
    for (i, id) in ids.iter().enumerate() {
        let path = PathBuf::from(text("path", i).unwrap());
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let what = path.display().to_string();
        assert_eq!(
            count(&params, id, Some("initial")),
            log.initial_params().len(),
            "{what}"
        );
        assert_eq!(
            count(&params, id, Some("changed")),
            log.param_changes().len(),
            "{what}"
        );
        let logged = log
            .logged_messages()
            .iter()
            .filter(|m| m.tag.is_none())
            .count();
        let tagged = log.logged_messages().len() - logged;
        assert_eq!(count(&messages, id, Some("logged")), logged, "{what}");
        assert_eq!(count(&messages, id, Some("tagged")), tagged, "{what}");
        let events = log.events(&Default::default());
        assert_eq!(
            count(&messages, id, Some("event")),
            events.iter().count(),
            "{what}"
        );
        assert_eq!(count(&formats, id, None), log.formats().len(), "{what}");
    }
}

#[test]
fn converting_twice_gives_the_same_bytes_and_adding_a_log_adds_its_files() {
    let scratch = common::scratch("fleet_incremental");
    let logs = logs();
    let (first, rest) = logs.split_at(logs.len().min(3));

    // All at once, twice (and on one thread): the same bytes.
    let once = scratch.join("once");
    let again = scratch.join("again");
    assert!(convert(&logs, &once, &[]).status.success());
    assert!(convert(&logs, &again, &["-j", "1"]).status.success());
    let all = common::files(&once);
    assert_eq!(
        all,
        common::files(&again),
        "the same logs give the same files"
    );

    // A few, then the rest: the files of the first are not written again, and the
    // dataset ends as the one written at once.
    let grown = scratch.join("grown");
    assert!(convert(first, &grown, &[]).status.success());
    let before = common::files(&grown);
    let mut times = BTreeMap::new();
    for rel in before.keys() {
        let m = std::fs::metadata(grown.join(rel))
            .unwrap()
            .modified()
            .unwrap();
        times.insert(rel.clone(), m);
    }
    std::thread::sleep(std::time::Duration::from_millis(20));
    let mut all_logs = first.to_vec();
    all_logs.extend_from_slice(rest);
    let out = convert(&all_logs, &grown, &[]);
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        stdout.matches("the dataset has it already").count(),
        first.len(),
        "{stdout}"
    );
    let after = common::files(&grown);
    assert_eq!(after, all, "the grown dataset is the one written at once");
    let tables = [
        "logs.parquet",
        "parameters.parquet",
        "messages.parquet",
        "formats.parquet",
        "analysis.parquet",
        "flights.parquet",
    ];
    for (rel, time) in &times {
        let now = std::fs::metadata(grown.join(rel))
            .unwrap()
            .modified()
            .unwrap();
        // The tables, and the union schemas of the topics the new logs have (widened
        // by theirs), are written again; no topic file is.
        if tables.iter().any(|t| rel == Path::new(t)) || rel.starts_with(export::SCHEMAS_DIR) {
            continue;
        }
        assert_eq!(&now, time, "{} was written again", rel.display());
    }
    let added: Vec<&PathBuf> = after.keys().filter(|k| !before.contains_key(*k)).collect();
    assert!(!added.is_empty());
    assert!(
        added.iter().all(|k| k.components().count() == 2),
        "only topic files (and the union schemas of new topics) are new"
    );
    // Each topic folder has its union schema.
    for rel in after.keys().filter(|k| !k.starts_with(export::SCHEMAS_DIR)) {
        if let (2, Some(folder)) = (rel.components().count(), rel.parent()) {
            let schema = Path::new(export::SCHEMAS_DIR)
                .join(folder)
                .with_extension("parquet");
            assert!(
                after.contains_key(&schema),
                "{} has no union schema",
                folder.display()
            );
        }
    }

    // A log that fails is reported; the others are added.
    let mixed = scratch.join("mixed");
    std::fs::create_dir_all(&mixed).unwrap();
    std::fs::write(mixed.join("broken.ulg"), b"not a log at all").unwrap();
    std::fs::create_dir_all(mixed.join("sub")).unwrap();
    std::fs::copy(&logs[0], mixed.join("sub").join("a.ulg")).unwrap();
    let ds = scratch.join("mixed_dataset");
    let out = common::ulog([
        "parquet".as_ref(),
        mixed.as_os_str(),
        "-o".as_ref(),
        ds.as_os_str(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(4),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("broken.ulg: not a ULog file"), "{stderr}");
    assert!(stderr.contains("1 of 2 logs failed"), "{stderr}");
    assert_eq!(
        read(&ds.join("logs.parquet")).num_rows(),
        1,
        "the log in the subfolder is in"
    );
}

/// Every file under `dir` whose name ends in `suffix`.
fn ending_in(dir: &Path, suffix: &str) -> Vec<PathBuf> {
    common::files(dir)
        .into_keys()
        .filter(|p| p.to_string_lossy().ends_with(suffix))
        .collect()
}

/// `ulog parquet LOGS -o DIR` started as a process, its output captured.
fn start(logs: &[PathBuf], dir: &Path) -> std::process::Child {
    std::process::Command::new(env!("CARGO_BIN_EXE_ulog"))
        .arg("parquet")
        .args(logs)
        .arg("-o")
        .arg(dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start ulog")
}

#[test]
fn two_conversions_at_once_both_land() {
    let scratch = common::scratch("fleet_concurrent");
    let logs: Vec<PathBuf> = logs().into_iter().take(4).collect();
    let single = scratch.join("single");
    assert!(convert(&logs, &single, &[]).status.success());

    // Two processes of the same logs into one folder, started together.
    let dir = scratch.join("dataset");
    let (a, b) = (start(&logs, &dir), start(&logs, &dir));
    for out in [a.wait_with_output().unwrap(), b.wait_with_output().unwrap()] {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        // Waited, or ran alone.
        assert!(
            stderr.is_empty() || stderr.contains("waiting for it to end"),
            "{stderr}"
        );
    }
    assert!(ending_in(&dir, ".partial").is_empty());
    assert!(!dir.join(export::LOCK_FILE).exists());
    assert_eq!(
        common::files(&dir),
        common::files(&single),
        "the dataset of one conversion"
    );
    let parquet = ending_in(&dir, ".parquet");
    for rel in &parquet {
        // The corpus's logs have no diagnostic: the table of them is empty (DuckDB
        // reads it below).
        if rel == Path::new(export::ANALYSIS_FILE) {
            continue;
        }
        // A topic's union schema has no rows: its schema is what it holds.
        if rel.starts_with(export::SCHEMAS_DIR) {
            let file = std::fs::File::open(dir.join(rel)).unwrap();
            let reader = ParquetRecordBatchReaderBuilder::try_new(file).expect("parquet");
            assert!(!reader.schema().fields().is_empty(), "{}", rel.display());
            continue;
        }
        assert!(read(&dir.join(rel)).num_rows() > 0, "{}", rel.display());
    }
    assert_eq!(read(&dir.join("logs.parquet")).num_rows(), logs.len());
    if cfg!(query_engines) {
        let script = "import duckdb, sys\n\
            for p in sys.argv[2:]:\n\
            \x20   duckdb.sql(f\"SELECT count(*) FROM read_parquet('{sys.argv[1]}/{p}')\").fetchall()\n\
            print(len(sys.argv) - 2)";
        let mut args: Vec<std::ffi::OsString> =
            vec!["-c".into(), script.into(), dir.clone().into()];
        args.extend(parquet.iter().map(|p| p.as_os_str().to_owned()));
        let read = common::python(args);
        assert_eq!(
            String::from_utf8_lossy(&read).trim(),
            parquet.len().to_string()
        );
    }

    // While another process holds the lock, a conversion waits, then lands; the
    // temporary files a conversion that died left behind are removed.
    let held = scratch.join("held");
    std::fs::create_dir_all(held.join("vehicle_status")).unwrap();
    let lock = held.join(export::LOCK_FILE);
    std::fs::write(
        &lock,
        format!("pid {}\nhost elsewhere\n", std::process::id()),
    )
    .unwrap();
    let left = held
        .join("vehicle_status")
        .join("0123.parquet.99-0.partial");
    std::fs::write(&left, b"half a file").unwrap();
    let mut waiting = start(&logs, &held);
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(waiting.try_wait().unwrap().is_none(), "it waits");
    assert!(!held.join("logs.parquet").exists());
    std::fs::remove_file(&lock).unwrap();
    let out = waiting.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("another conversion (process")
            && stderr.contains("waiting for it to end")
            && stderr.contains(export::LOCK_FILE),
        "{stderr}"
    );
    assert!(!left.exists(), "the leftover is removed");
    assert_eq!(common::files(&held), common::files(&single));
}

#[test]
fn several_logs_need_a_dataset_folder() {
    let logs = logs();
    let out = common::ulog(["parquet".as_ref(), logs[0].as_os_str(), logs[1].as_os_str()]);
    assert_eq!(out.status.code(), Some(6));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("name its folder with -o DATASET"),
        "{stderr}"
    );

    // One log that fails leaves no dataset behind.
    let bad = common::scratch("fleet_bad").join("notalog.ulg");
    std::fs::write(&bad, b"not a log").unwrap();
    let out = common::ulog([OsStr::new("parquet"), bad.as_os_str()]);
    assert_eq!(out.status.code(), Some(4));
    assert!(
        !bad.with_file_name("notalog").exists(),
        "nothing left written"
    );

    // One log alone is a dataset of one, beside it.
    let log = common::sample_file("fleet_single");
    common::ulog_ok([OsStr::new("parquet"), log.as_os_str()]);
    let dir = log.with_file_name("sample");
    assert_eq!(read(&dir.join("logs.parquet")).num_rows(), 1);
    assert!(dir.join("esc_status").is_dir());
}

#[test]
#[cfg_attr(
    not(query_engines),
    ignore = "needs python3 with duckdb and datafusion (pip install duckdb datafusion)"
)]
fn the_readmes_analysis_queries_answer_what_ulog_analyze_says() {
    let dir = common::scratch("fleet_analysis");
    let mut logs = logs();
    logs.push(common::brownout_log(&dir));
    let dataset = dir.join("dataset");
    let out = convert(&logs, &dataset, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/fleet_queries.py");
    let answers: Json = serde_json::from_slice(&common::python([
        script.as_os_str(),
        readme.as_os_str(),
        dataset.as_os_str(),
    ]))
    .expect("json");
    let duck = answers["duckdb"].as_array().expect("answers");
    // What `ulog analyze` says of each log.
    let mut brownouts = Vec::new();
    let mut flights = Vec::new();
    for log in &logs {
        let text = common::ulog_ok([OsStr::new("analyze"), OsStr::new("--json"), log.as_os_str()]);
        let a: Json = serde_json::from_str(text.trim()).expect("analyze's JSON");
        let path = log.display().to_string();
        let diagnostics = a["diagnostics"].as_array().unwrap();
        for d in diagnostics.iter().filter(|d| d["id"] == "battery_brownout") {
            brownouts.push((
                path.clone(),
                d["severity"].as_str().unwrap().to_owned(),
                d["timestamp_us"].as_u64().unwrap(),
                d["summary"].as_str().unwrap().to_owned(),
            ));
        }
        let critical = diagnostics
            .iter()
            .filter(|d| d["severity"] == "critical")
            .count();
        flights.push((
            path,
            a["vibration"]["status"].as_str().unwrap().to_owned(),
            a["vibration"]["accel_vibe_max"].as_f64(),
            diagnostics.len() as u64,
            critical as u64,
        ));
    }
    // 6. The written log's brownout, and no other.
    assert_eq!(brownouts.len(), 1, "{brownouts:?}");
    let got: Vec<(String, String, u64, String)> = duck[5]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r[0].as_str().unwrap().to_owned(),
                r[2].as_str().unwrap().to_owned(),
                r[3].as_u64().unwrap(),
                r[4].as_str().unwrap().to_owned(),
            )
        })
        .collect();
    assert_eq!(got, brownouts, "which flights had a brownout");
    // 7. One row per flight, worst vibration first.
    let mut got: Vec<(String, String, Option<f64>, u64, u64)> = duck[6]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r[0].as_str().unwrap().to_owned(),
                r[1].as_str().unwrap().to_owned(),
                r[2].as_f64(),
                r[3].as_u64().unwrap(),
                r[4].as_u64().unwrap(),
            )
        })
        .collect();
    let maxima: Vec<Option<f64>> = got.iter().map(|r| r.2).collect();
    let mut sorted = maxima.clone();
    sorted.sort_by(|a, b| match (a, b) {
        (Some(a), Some(b)) => b.total_cmp(a),
        (a, b) => b.is_some().cmp(&a.is_some()),
    });
    assert_eq!(
        maxima, sorted,
        "worst vibration first, flights without last"
    );
    got.sort_by(|a, b| a.0.cmp(&b.0));
    flights.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(got, flights, "vibration and diagnostics per flight");
}

/// The logs `logs.parquet` of `dir` lists (with their topic counts), and the log ids
/// of the topic files in its folders.
fn listed_and_filed(dir: &Path) -> (BTreeMap<String, u64>, BTreeSet<String>) {
    let mut listed = BTreeMap::new();
    if dir.join("logs.parquet").exists() {
        let logs = read(&dir.join("logs.parquet"));
        let ids = logs.column_by_name("log_id").unwrap().as_string::<i32>();
        let topics = logs.column_by_name("topics").unwrap();
        let topics = topics.as_primitive::<UInt32Type>();
        for i in 0..logs.num_rows() {
            listed.insert(ids.value(i).to_owned(), u64::from(topics.value(i)));
        }
    }
    let mut filed = BTreeSet::new();
    for folder in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let name = folder.file_name().to_string_lossy().into_owned();
        if !folder.path().is_dir() || name.starts_with(['_', '.']) {
            continue;
        }
        for file in topic_folder_files(&folder.path()) {
            // A fleet file names its logs in its metadata; a log's file is named
            // after it.
            match kv(&file).get(export::LOG_IDS_KEY) {
                Some(ids) => filed.extend(ids.split(',').map(str::to_owned)),
                None => {
                    let stem = file.file_stem().unwrap().to_string_lossy();
                    filed.insert(stem.into_owned());
                }
            }
        }
    }
    (listed, filed)
}

/// The `.parquet` files of a topic folder and its partition folders (`key=value`).
fn topic_folder_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            assert!(
                name.contains('='),
                "{}: not a partition folder",
                path.display()
            );
            out.extend(topic_folder_files(&path));
        } else if name.ends_with(".parquet") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// A Parquet file's key-value metadata.
fn kv(path: &Path) -> BTreeMap<String, String> {
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    builder
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .into_iter()
        .flatten()
        .filter_map(|kv| Some((kv.key.clone(), kv.value.clone()?)))
        .collect()
}

#[test]
fn a_conversion_killed_at_any_point_then_run_again_leaves_a_consistent_dataset() {
    killed_then_run_again("fleet_killed", &[], &[0.1, 0.3, 0.5, 0.7, 0.9, 0.97]);
}

#[test]
fn a_fleet_layout_conversion_killed_then_run_again_leaves_a_consistent_dataset() {
    // Most of a fleet conversion's files are written at its end (compacted).
    let layout = ["--layout", "fleet", "--file-size", "1"];
    killed_then_run_again("fleet_layout_killed", &layout, &[0.3, 0.8, 0.9, 0.95, 0.99]);
}

/// `ulog ARGS`, killed (SIGKILL) `after` it started.
fn killed_after(args: &[&OsStr], after: std::time::Duration) {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ulog"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let _ = child.kill();
    let _ = child.wait();
}

/// Conversions with `extra` options killed at `fractions` of a whole one's time, then
/// run again, leave the dataset the whole one writes; meanwhile every log listed has
/// its files.
fn killed_then_run_again(name: &str, extra: &[&str], fractions: &[f64]) {
    let scratch = common::scratch(name);
    let logs = logs();
    let whole = scratch.join("whole");
    let started = std::time::Instant::now();
    assert!(convert(&logs, &whole, extra).status.success());
    let took = started.elapsed();
    for (i, &fraction) in fractions.iter().enumerate() {
        let dir = scratch.join(format!("killed{i}"));
        let mut args: Vec<&OsStr> = vec![OsStr::new("parquet")];
        args.extend(logs.iter().map(|p| p.as_os_str()));
        args.extend([OsStr::new("-o"), dir.as_os_str()]);
        args.extend(extra.iter().map(OsStr::new));
        killed_after(&args, took.mul_f64(fraction));
        // What a reader sees meanwhile: every log listed has its files.
        let (listed, filed) = listed_and_filed(&dir);
        for (id, topics) in &listed {
            assert!(
                *topics == 0 || filed.contains(id),
                "{id} listed without files"
            );
        }
        // Run again: consistent, and the dataset one conversion writes.
        let again = convert(&logs, &dir, extra);
        assert!(
            again.status.success(),
            "{}",
            String::from_utf8_lossy(&again.stderr)
        );
        let (listed, filed) = listed_and_filed(&dir);
        let with_files: BTreeSet<String> = listed
            .iter()
            .filter(|(_, t)| **t > 0)
            .map(|(id, _)| id.clone())
            .collect();
        assert_eq!(filed, with_files, "killed at {fraction} of the run");
        let (got, want) = (common::files(&dir), common::files(&whole));
        let differ: Vec<&PathBuf> = got
            .keys()
            .chain(want.keys())
            .filter(|p| got.get(*p) != want.get(*p))
            .collect();
        assert!(
            differ.is_empty(),
            "killed at {fraction} of the run: {differ:?}"
        );
    }

    // Files of a log the table does not list (a conversion killed between them and
    // the tables) are removed by the next conversion, whatever logs it is given.
    let dir = scratch.join("leftover");
    assert!(convert(&logs[..1], &dir, extra).status.success());
    let mut stray = dir.join("vehicle_status");
    if !extra.is_empty() {
        stray.push("month=2024-02");
    }
    let stray = stray.join("0123456789abcdef.parquet");
    std::fs::create_dir_all(stray.parent().unwrap()).unwrap();
    std::fs::write(&stray, b"PAR1").unwrap();
    let pending = dir.join(export::PENDING_DIR).join("vehicle_status");
    std::fs::create_dir_all(&pending).unwrap();
    std::fs::write(pending.join("0123456789abcdef.parquet"), b"PAR1").unwrap();
    assert!(convert(&logs[..1], &dir, extra).status.success());
    assert!(!stray.exists());
    assert!(!dir.join(export::PENDING_DIR).exists());
}

#[test]
fn the_fleet_layout_files_hold_logs_in_order_and_adding_logs_adds_files() {
    let scratch = common::scratch("fleet_layout");
    let logs = logs();
    let layout = ["--layout", "fleet", "--file-size", "1"];
    let whole = scratch.join("whole");
    assert!(convert(&logs, &whole, &layout).status.success());

    let (files, shared) = fleet_files_in_order(&whole);
    assert!(files > 0 && (shared > 0 || !cfg!(full_corpus)));

    // Adding logs adds files, and rewrites none; the result holds what one conversion
    // of all the logs holds.
    let dir = scratch.join("added");
    let half = logs.len() / 2;
    assert!(convert(&logs[..half], &dir, &layout).status.success());
    let before = common::files(&dir);
    // The dataset keeps its layout: no `--layout` needed, another refused.
    let other = convert(&logs[half..], &dir, &["--layout", "file-per-log"]);
    assert!(!other.status.success());
    let said = String::from_utf8_lossy(&other.stderr);
    assert!(
        said.contains("the dataset's layout is fleet:month"),
        "{said}"
    );
    assert!(convert(&logs[half..], &dir, &[]).status.success());
    let after = common::files(&dir);
    for (path, bytes) in &before {
        let table = path.components().count() == 1;
        if !table && !path.starts_with("_schemas") {
            assert_eq!(after.get(path), Some(bytes), "{} rewritten", path.display());
        }
    }
    assert!(after.len() > before.len());
    let (listed, filed) = listed_and_filed(&dir);
    let (whole_listed, whole_filed) = listed_and_filed(&whole);
    assert_eq!((listed, filed), (whole_listed, whole_filed));
}

/// Checks every topic file of the fleet-layout dataset `dir`: in partition folders,
/// named after its first log, its logs in id order, a row group (or more) per log, each
/// log's rows in time order, the format's hash and firmware versions in its metadata;
/// and no log in two files of a folder. Its files, and those holding several logs.
fn fleet_files_in_order(dir: &Path) -> (usize, usize) {
    let firmware: BTreeMap<String, Option<String>> = {
        let table = read(&dir.join("logs.parquet"));
        let ids = table.column_by_name("log_id").unwrap().as_string::<i32>();
        let release = table
            .column_by_name("ver_sw_release")
            .unwrap()
            .as_string::<i32>();
        let sw = table.column_by_name("ver_sw").unwrap().as_string::<i32>();
        (0..table.num_rows())
            .map(|i| {
                let v = [release, sw].into_iter().find(|c| c.is_valid(i));
                (ids.value(i).to_owned(), v.map(|c| c.value(i).to_owned()))
            })
            .collect()
    };
    let (mut files, mut shared) = (0, 0);
    // Each partition folder's logs: a log's rows of a topic are in one file.
    let mut in_folder: BTreeMap<PathBuf, BTreeSet<String>> = BTreeMap::new();
    for topic in std::fs::read_dir(dir).unwrap().flatten() {
        let name = topic.file_name().to_string_lossy().into_owned();
        if !topic.path().is_dir() || name.starts_with(['_', '.']) {
            continue;
        }
        for file in topic_folder_files(&topic.path()) {
            files += 1;
            let partition = file
                .parent()
                .unwrap()
                .file_name()
                .unwrap()
                .to_string_lossy();
            assert!(partition.starts_with("month="), "{}", file.display());
            let meta = kv(&file);
            let ids: Vec<&str> = meta[export::LOG_IDS_KEY].split(',').collect();
            shared += usize::from(ids.len() > 1);
            let folder_logs = in_folder
                .entry(file.parent().unwrap().to_owned())
                .or_default();
            for id in &ids {
                assert!(
                    folder_logs.insert((*id).to_owned()),
                    "{}: {id} is in another file of its folder too",
                    file.display()
                );
            }
            assert_eq!(
                file.file_stem().unwrap().to_string_lossy(),
                ids[0],
                "named after its first log"
            );
            assert!(ids.windows(2).all(|w| w[0] < w[1]), "logs in id order");
            let hash = xxhash_rust::xxh3::xxh3_64(meta["ulog.format"].as_bytes());
            assert_eq!(meta[export::FORMAT_HASH_KEY], format!("{hash:016x}"));
            let versions: BTreeSet<&str> = ids
                .iter()
                .filter_map(|id| firmware[*id].as_deref())
                .collect();
            let recorded: BTreeSet<&str> = meta[export::FIRMWARE_KEY]
                .split(',')
                .filter(|v| !v.is_empty())
                .collect();
            assert_eq!(recorded, versions, "{}", file.display());

            // Rows by log, in id order; each log's rows in time order; a log in one
            // row group (a log's rows fill at most a few here); the row groups'
            // `log_id` statistics give their logs' range.
            let builder =
                ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&file).unwrap())
                    .unwrap();
            let groups = builder.metadata().row_groups().to_vec();
            let log_column = builder
                .parquet_schema()
                .columns()
                .iter()
                .position(|c| c.name() == "log_id")
                .unwrap();
            let mut seen: Vec<String> = Vec::new();
            let mut times: BTreeMap<String, Vec<u64>> = BTreeMap::new();
            for (g, meta) in groups.iter().enumerate() {
                let reader =
                    ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&file).unwrap())
                        .unwrap()
                        .with_row_groups(vec![g])
                        .build()
                        .unwrap();
                let mut group_ids: Vec<String> = Vec::new();
                for b in reader.map(Result::unwrap) {
                    let id = b.column_by_name("log_id").unwrap().as_string::<i32>();
                    let t = b
                        .column_by_name("timestamp")
                        .map(|t| t.as_primitive::<UInt64Type>().clone());
                    for i in 0..b.num_rows() {
                        let id = id.value(i).to_owned();
                        if let Some(t) = &t {
                            times.entry(id.clone()).or_default().push(t.value(i));
                        }
                        if group_ids.last() != Some(&id) {
                            group_ids.push(id);
                        }
                    }
                }
                let stats = meta
                    .column(log_column)
                    .statistics()
                    .expect("log_id statistics");
                let bytes = |b: Option<&[u8]>| String::from_utf8(b.unwrap().to_vec()).unwrap();
                assert_eq!(bytes(stats.min_bytes_opt()), group_ids[0]);
                assert_eq!(bytes(stats.max_bytes_opt()), *group_ids.last().unwrap());
                for id in group_ids {
                    if seen.last() != Some(&id) {
                        assert!(
                            !seen.contains(&id),
                            "{}: {id} in two places",
                            file.display()
                        );
                        seen.push(id);
                    }
                }
            }
            assert_eq!(seen, ids, "logs in the order the metadata gives");
            for (id, t) in times {
                assert!(
                    t.windows(2).all(|w| w[0] <= w[1]),
                    "{}: {id}'s rows in time order",
                    file.display()
                );
            }
        }
    }
    (files, shared)
}

/// Each topic file of the dataset `dir` by its path below it: its key-value metadata
/// and its rows as one batch. What two datasets with the same rows in the same files
/// agree on when their bytes need not (row groups may be cut elsewhere).
fn topic_rows(dir: &Path) -> BTreeMap<PathBuf, (BTreeMap<String, String>, RecordBatch)> {
    let mut out = BTreeMap::new();
    for folder in std::fs::read_dir(dir).unwrap().flatten() {
        let name = folder.file_name().to_string_lossy().into_owned();
        if !folder.path().is_dir() || name.starts_with(['_', '.']) {
            continue;
        }
        for file in topic_folder_files(&folder.path()) {
            let mut meta = kv(&file);
            meta.remove("ARROW:schema");
            let builder =
                ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&file).unwrap())
                    .unwrap();
            let rows = builder.metadata().file_metadata().num_rows().max(1) as usize;
            let schema = builder.schema().clone();
            let mut batches: Vec<RecordBatch> = builder
                .with_batch_size(rows)
                .build()
                .unwrap()
                .map(Result::unwrap)
                .collect();
            assert!(batches.len() <= 1, "{}: one batch", file.display());
            let batch = batches
                .pop()
                .unwrap_or_else(|| RecordBatch::new_empty(schema));
            out.insert(file.strip_prefix(dir).unwrap().to_owned(), (meta, batch));
        }
    }
    out
}

/// `ulog parquet --compact -o DIR`: the output.
fn compact(dir: &Path) -> std::process::Output {
    convert(&[], dir, &["--compact"])
}

/// In the scratch folder `name`: the corpus converted in the fleet layout at once
/// (`whole`), and a log at a time (`steps`: a file per topic and log, as many as the
/// file-per-log layout has); the scratch folder, the logs, `whole` and `steps`.
fn whole_and_steps(name: &str) -> (PathBuf, Vec<PathBuf>, PathBuf, PathBuf) {
    let scratch = common::scratch(name);
    let logs = logs();
    let layout = ["--layout", "fleet"];
    let whole = scratch.join("whole");
    assert!(convert(&logs, &whole, &layout).status.success());
    let steps = scratch.join("steps");
    for log in &logs {
        assert!(convert(std::slice::from_ref(log), &steps, &layout)
            .status
            .success());
    }
    (scratch, logs, whole, steps)
}

#[test]
fn compacting_merges_the_small_files_of_logs_added_one_at_a_time() {
    let (scratch, logs, whole, dir) = whole_and_steps("fleet_compact");
    let before = topic_rows(&dir);
    let merged = topic_rows(&whole);
    assert!(before.len() >= merged.len());

    // What is not a compaction of a local fleet dataset is refused, saying why.
    let refused = [
        (
            convert(&[], &scratch.join("none"), &["--compact"]),
            "no dataset to compact here",
        ),
        (
            convert(&[], &dir, &["--compact", "--per-log"]),
            "leave out --per-log",
        ),
        (
            common::ulog(["parquet", "--compact"]),
            "name the dataset to compact with -o DATASET",
        ),
    ];
    for (out, says) in refused {
        assert!(!out.status.success());
        let said = String::from_utf8_lossy(&out.stderr);
        assert!(said.contains(says), "{said}");
    }
    let flat = scratch.join("flat");
    assert!(convert(&logs[..1], &flat, &[]).status.success());
    let out = compact(&flat);
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("has a file per topic and log"), "{said}");

    // Compacted: the files one conversion of every log writes, with the same rows in
    // the same order and the same metadata; the tables untouched.
    let tables = |dir: &Path| -> BTreeMap<PathBuf, Vec<u8>> {
        common::files(dir)
            .into_iter()
            .filter(|(p, _)| p.components().count() == 1 || p.starts_with("_schemas"))
            .collect()
    };
    let tables_before = tables(&dir);
    let out = compact(&dir);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stdout);
    let after = topic_rows(&dir);
    assert!(
        said.contains(&format!("({} topic files now)", after.len())),
        "{said}"
    );
    assert_eq!(tables(&dir), tables_before);
    assert_eq!(
        after.keys().collect::<Vec<_>>(),
        merged.keys().collect::<Vec<_>>()
    );
    for (path, (meta, rows)) in &after {
        let (want_meta, want_rows) = &merged[path];
        assert_eq!(meta, want_meta, "{}", path.display());
        assert!(rows == want_rows, "{}: other rows", path.display());
    }
    if cfg!(full_corpus) {
        assert!(after.len() < before.len(), "files were merged");
    }
    fleet_files_in_order(&dir);
    assert_eq!(listed_and_filed(&dir), listed_and_filed(&whole));

    // Again: nothing to merge.
    let out = compact(&dir);
    assert!(String::from_utf8_lossy(&out.stdout).contains("0 small files merged into 0"));
    assert_eq!(topic_rows(&dir).len(), after.len());

    // A log in two files of a folder (a copy put there by hand, no compaction under
    // way): refused, naming both, rather than merged twice; the logs stay added. (A
    // copy rather than a file merged away: the repository's five logs alone leave
    // no small files to merge in month partitions.)
    let copied = after.keys().next().expect("a topic file");
    // Named after a log the dataset lists (a file of a log it does not list is
    // removed as a dead conversion's), not one of this folder's.
    let copy = listed_and_filed(&dir)
        .0
        .keys()
        .map(|id| copied.with_file_name(format!("{id}.parquet")))
        .find(|p| !dir.join(p).exists())
        .expect("a log without a file in the folder");
    std::fs::copy(dir.join(copied), dir.join(&copy)).unwrap();
    let out = compact(&dir);
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("is in two files of this folder")
            && said.contains("the logs were added, but merging the small files stopped"),
        "{said}"
    );
}

#[test]
fn a_compaction_that_died_is_finished_by_the_next_conversion() {
    let (scratch, logs, whole, steps) = whole_and_steps("fleet_compact_died");
    let merged = topic_rows(&whole);

    // Killed between a merged file's rename and the removal of the files it holds:
    // those are put back beside it with the marker, as a compaction that died there
    // leaves them; and a merged file still under its temporary name.
    let dir = scratch.join("died");
    copy_dir(&steps, &dir);
    assert!(compact(&dir).status.success());
    let after = common::files(&dir);
    let mut restored = 0;
    for (path, _) in common::files(&steps) {
        let is_topic = path.components().count() > 1 && !path.starts_with("_schemas");
        if is_topic && !after.contains_key(&path) {
            std::fs::copy(steps.join(&path), dir.join(&path)).unwrap();
            restored += 1;
        }
    }
    if cfg!(full_corpus) {
        assert!(restored > 0);
    }
    std::fs::write(dir.join(export::COMPACTING), b"").unwrap();
    let partial = merged
        .keys()
        .next()
        .unwrap()
        .with_extension("parquet.partial");
    std::fs::write(dir.join(&partial), b"PAR1").unwrap();
    // Any conversion opening the dataset finishes it: here one adding a log it has.
    assert!(convert(&logs[..1], &dir, &[]).status.success());
    assert!(!dir.join(export::COMPACTING).exists());
    assert!(!dir.join(&partial).exists());
    let got = topic_rows(&dir);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        merged.keys().collect::<Vec<_>>()
    );
    for (path, (_, rows)) in &got {
        assert!(*rows == merged[path].1, "{}: other rows", path.display());
    }
    fleet_files_in_order(&dir);

    // Killed by SIGKILL at points of a compaction, then compacted again: the same.
    let took = {
        let probe = scratch.join("probe");
        copy_dir(&steps, &probe);
        let started = std::time::Instant::now();
        assert!(compact(&probe).status.success());
        started.elapsed()
    };
    for (i, fraction) in [0.2, 0.5, 0.8, 0.95].into_iter().enumerate() {
        let dir = scratch.join(format!("killed{i}"));
        copy_dir(&steps, &dir);
        let args = ["parquet", "--compact", "-o"].map(OsStr::new);
        killed_after(
            &[&args[..], &[dir.as_os_str()]].concat(),
            took.mul_f64(fraction),
        );
        let out = compact(&dir);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let got = topic_rows(&dir);
        assert_eq!(
            got.keys().collect::<Vec<_>>(),
            merged.keys().collect::<Vec<_>>(),
            "killed at {fraction}"
        );
        for (path, (_, rows)) in &got {
            assert!(*rows == merged[path].1, "{}: other rows", path.display());
        }
        assert_eq!(listed_and_filed(&dir), listed_and_filed(&whole));
    }
}

/// Copies the folder `from` to `to`, recursively.
fn copy_dir(from: &Path, to: &Path) {
    for (path, _) in common::files(from) {
        let target = to.join(&path);
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        std::fs::copy(from.join(&path), &target).unwrap();
    }
}
