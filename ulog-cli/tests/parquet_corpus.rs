//! `ulog parquet` over the corpus: every log of the corpus directory converted in one
//! call, every Parquet file read back with the `parquet` crate's Arrow reader, and
//! every value compared with what the reader gives for the same field of the same
//! data message; file sets and flattened column names compared with pyulog's
//! (summary.json, CSV headers); metadata.json compared with pyulog's summary.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use ulog_core::export::arrow_array::cast::AsArray;
use ulog_core::export::arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use ulog_core::export::arrow_array::{Array, ArrayRef, RecordBatch};
use ulog_core::export::arrow_schema::DataType;
use ulog_core::export::parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use ulog_core::read::FieldShape;
use ulog_core::{FieldReader, Topic, ULog, Value};

fn file_set(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

/// Where a leaf's values are in a record batch: a flat array, and the index of row
/// `r` in it, `r * mult + add` (nested lists multiply, list indexes add).
struct Located {
    array: ArrayRef,
    mult: usize,
    add: usize,
}

/// Finds leaf `path` (`a`, `a[2]`, `a[1].b.c[0]`) in a nested batch by walking its
/// struct and fixed-size-list columns.
fn locate_nested(batch: &RecordBatch, path: &str) -> Located {
    let mut array: Option<ArrayRef> = None;
    let (mut mult, mut add) = (1, 0);
    for part in path.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (
                n,
                Some(rest.trim_end_matches(']').parse::<usize>().unwrap()),
            ),
            None => (part, None),
        };
        let column = match &array {
            None => batch.column_by_name(name).cloned(),
            Some(a) => a
                .as_struct_opt()
                .and_then(|s| s.column_by_name(name).cloned()),
        };
        let mut column = column.unwrap_or_else(|| panic!("no column for `{name}` of {path}"));
        if let Some(i) = index {
            let list = column
                .as_fixed_size_list_opt()
                .unwrap_or_else(|| panic!("{path}: `{name}` is not a fixed-size list"));
            let n = list.value_length() as usize;
            assert!(i < n, "{path}: index past the list");
            mult *= n;
            add = add * n + i;
            column = list.values().clone();
        }
        array = Some(column);
    }
    Located {
        array: array.expect("a path has a part"),
        mult,
        add,
    }
}

/// Compares every value of `leaf` in `payloads` (the rows of one batch) with the
/// Arrow values.
fn compare_leaf(what: &str, leaf: &FieldReader, at: &Located, payloads: &[&[u8]]) {
    let idx = |r: usize| r * at.mult + at.add;
    let values = payloads.iter().map(|p| {
        leaf.read(p)
            .unwrap_or_else(|| panic!("{what}: the reader has no value"))
    });
    macro_rules! same {
        ($arrow:ty, $variant:ident, $conv:expr) => {{
            let a = at
                .array
                .as_primitive_opt::<$arrow>()
                .unwrap_or_else(|| panic!("{what}: type {:?}", at.array.data_type()));
            for (r, v) in values.enumerate() {
                match v {
                    Value::$variant(v) => {
                        #[allow(clippy::redundant_closure_call)]
                        let (ours, theirs) = ($conv(a.value(idx(r))), $conv(v));
                        assert!(ours == theirs, "{what} row {r}: {ours:?} != {theirs:?}");
                    }
                    v => panic!("{what}: reader gives {v:?}"),
                }
            }
        }};
    }
    match (leaf.shape(), leaf.ty()) {
        (FieldShape::String(_), _) => {
            let a = at
                .array
                .as_string_opt::<i32>()
                .unwrap_or_else(|| panic!("{what}: type {:?}", at.array.data_type()));
            for (r, v) in values.enumerate() {
                let bytes = v.as_str().expect("a string").as_bytes();
                let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
                let back: Vec<u8> = a
                    .value(idx(r))
                    .chars()
                    .map(|c| u8::try_from(u32::from(c)).expect("one character per byte"))
                    .collect();
                assert_eq!(back, &bytes[..end], "{what} row {r}");
            }
        }
        (FieldShape::Scalar, ty) => {
            use ulog_core::format::BasicType as B;
            match ty {
                B::Int8 => same!(Int8Type, I8, |x| x),
                B::UInt8 => same!(UInt8Type, U8, |x| x),
                B::Char => same!(UInt8Type, Char, |x| x),
                B::Int16 => same!(Int16Type, I16, |x| x),
                B::UInt16 => same!(UInt16Type, U16, |x| x),
                B::Int32 => same!(Int32Type, I32, |x| x),
                B::UInt32 => same!(UInt32Type, U32, |x| x),
                B::Int64 => same!(Int64Type, I64, |x| x),
                B::UInt64 => same!(UInt64Type, U64, |x| x),
                B::Float => same!(Float32Type, F32, |x: f32| x.to_bits()),
                B::Double => same!(Float64Type, F64, |x: f64| x.to_bits()),
                B::Bool => {
                    let a = at
                        .array
                        .as_boolean_opt()
                        .unwrap_or_else(|| panic!("{what}: type {:?}", at.array.data_type()));
                    for (r, v) in values.enumerate() {
                        assert_eq!(Value::Bool(a.value(idx(r))), v, "{what} row {r}");
                    }
                }
            }
        }
        (shape, _) => panic!("{what}: a column is never {shape:?}"),
    }
}

/// Reads a topic's Parquet file back and compares every value with the reader's.
/// Returns the column names.
fn check_topic(stem: &str, topic: &Topic<'_, '_>, path: &Path, flatten: bool) -> Vec<String> {
    let what = format!("{stem}/{}", path.file_name().unwrap().to_string_lossy());
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{what}: {e}"));
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).expect("a Parquet file");
    let schema = builder.schema().clone();
    assert_eq!(schema.metadata()["ulog.topic"], topic.name(), "{what}");
    assert_eq!(
        schema.metadata()["ulog.multi_id"],
        topic.multi_id().to_string()
    );
    let names: Vec<String> = schema.fields().iter().map(|f| f.name().clone()).collect();
    for f in schema.fields() {
        assert!(!f.is_nullable(), "{what}: {} is nullable", f.name());
    }
    if let Some(ts) = schema.fields().iter().find(|f| f.name() == "timestamp") {
        assert!(
            matches!(
                ts.data_type(),
                DataType::UInt64 | DataType::UInt32 | DataType::UInt16 | DataType::UInt8
            ),
            "{what}: timestamp {:?}",
            ts.data_type()
        );
    }
    let leaves = topic.fields().expect("the topic was exported");
    let payloads: Vec<&[u8]> = topic.payloads().collect();
    let mut row = 0;
    for batch in builder.build().expect("reader") {
        let batch = batch.expect("a record batch");
        let n = batch.num_rows();
        assert!(row + n <= payloads.len(), "{what}: more rows than the log");
        for leaf in &leaves {
            let at = if flatten {
                Located {
                    array: batch
                        .column_by_name(leaf.path())
                        .unwrap_or_else(|| panic!("{what}: no column {}", leaf.path()))
                        .clone(),
                    mult: 1,
                    add: 0,
                }
            } else {
                locate_nested(&batch, leaf.path())
            };
            let leaf_what = format!("{what}: {}", leaf.path());
            compare_leaf(&leaf_what, leaf, &at, &payloads[row..row + n]);
        }
        row += n;
    }
    assert_eq!(row, topic.len(), "{what}: rows");
    names
}

/// Converts the whole corpus directory in one call and checks every log.
fn check_corpus(test: &str, flatten: bool) {
    let corpus = common::corpus();
    let out = common::scratch(test);
    let files = corpus.join("files");
    let mut args = vec![
        "parquet".as_ref(),
        "--per-log".as_ref(),
        files.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ];
    if flatten {
        args.push("--flatten".as_ref());
    }
    let stdout = common::ulog_ok(args);
    let logs = common::corpus_logs(&corpus);
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("Writing ")).count(),
        logs.len()
    );
    for (stem, path) in logs {
        let bytes = std::fs::read(&path).expect("read log");
        let log = ULog::parse(&bytes).expect("corpus logs parse");
        let dir = out.join(&stem);
        let summary = common::summary(&corpus, &stem);

        // The files: one per topic instance with data (as pyulog lists them), and
        // the metadata.
        let theirs: BTreeMap<String, u64> = summary["topics"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|t| t["rows"].as_u64().unwrap() > 0)
            .map(|t| {
                let name = format!(
                    "{}_{}.parquet",
                    t["name"].as_str().unwrap().replace('/', "_"),
                    t["multi_id"]
                );
                (name, t["rows"].as_u64().unwrap())
            })
            .collect();
        let mut expected: BTreeSet<String> = theirs.keys().cloned().collect();
        expected.insert("metadata.json".into());
        assert_eq!(file_set(&dir), expected, "{stem}: files");

        for topic in log.topics().filter(|t| !t.is_empty()) {
            let name = format!(
                "{}_{}.parquet",
                topic.name().replace('/', "_"),
                topic.multi_id()
            );
            if !common::RECOVERS_ROWS.contains(&stem.as_str()) {
                assert_eq!(
                    Some(&(topic.len() as u64)),
                    theirs.get(&name),
                    "{stem}/{name}: rows"
                );
            }
            let columns = check_topic(&stem, &topic, &dir.join(&name), flatten);
            if flatten {
                // pyulog's column names, in ulog2csv's order.
                let csv = corpus
                    .join("expected")
                    .join(&stem)
                    .join("csv")
                    .join(format!("{stem}_{}", name.replace(".parquet", ".csv")));
                let text = std::fs::read_to_string(&csv).expect("pyulog's csv");
                let header: Vec<&str> = text.lines().next().unwrap_or("").split(',').collect();
                assert_eq!(columns, header, "{stem}/{name}: columns");
            }
        }
        check_metadata(&stem, &log, &dir.join("metadata.json"), &summary);
    }
}

/// Whether a metadata value equals pyulog's: numbers by value (float32 values that
/// pyulog widened compare as float32), strings as text, lists element by element.
fn same(ours: &serde_json::Value, theirs: &serde_json::Value) -> bool {
    use serde_json::Value as J;
    match (ours, theirs) {
        (J::Number(a), J::Number(b)) => {
            if let (Some(x), Some(y)) = (a.as_i64(), b.as_i64()) {
                return x == y;
            }
            if let (Some(x), Some(y)) = (a.as_u64(), b.as_u64()) {
                return x == y;
            }
            let (x, y) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            x == y || x as f32 == y as f32
        }
        (J::Array(a), J::Array(b)) => {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(x, y))
        }
        // pyulog turns a `uint8_t[N]` value into text (invalid UTF-8 replaced); we
        // keep the bytes.
        (J::Array(a), J::String(b)) => {
            let bytes: Option<Vec<u8>> = a
                .iter()
                .map(|x| x.as_u64().and_then(|x| u8::try_from(x).ok()))
                .collect();
            bytes.is_some_and(|bytes| String::from_utf8_lossy(&bytes) == *b)
        }
        (a, b) => a == b,
    }
}

fn assert_same_map(what: &str, ours: &serde_json::Value, theirs: &serde_json::Value) {
    let (ours, theirs) = (ours.as_object().unwrap(), theirs.as_object().unwrap());
    let keys = |m: &serde_json::Map<String, serde_json::Value>| {
        m.keys().cloned().collect::<BTreeSet<String>>()
    };
    assert_eq!(keys(ours), keys(theirs), "{what}: keys");
    for (k, v) in theirs {
        assert!(same(&ours[k], v), "{what} {k}: {} != {v}", ours[k]);
    }
}

fn check_metadata(stem: &str, log: &ULog<'_>, path: &Path, summary: &serde_json::Value) {
    let text = std::fs::read_to_string(path).expect("metadata.json");
    let m: serde_json::Value = serde_json::from_str(&text).expect("metadata.json is JSON");
    assert_eq!(m["version"], summary["file_version"], "{stem}");
    assert_eq!(m["start_timestamp"], summary["start_timestamp"], "{stem}");
    assert_eq!(m["last_timestamp"], log.last_timestamp(), "{stem}");
    assert_eq!(m["damaged"], log.has_damage(), "{stem}");
    assert_same_map(&format!("{stem}: info"), &m["info"], &summary["info"]);
    assert_same_map(
        &format!("{stem}: parameters"),
        &m["parameters"],
        &summary["initial_parameters"],
    );
    // Multi-information: per key, the entries, each the list of its parts.
    let multi = m["multi_info"].as_object().unwrap();
    let theirs = summary["info_multi"].as_object().unwrap();
    assert_eq!(multi.len(), theirs.len(), "{stem}: multi_info keys");
    for (k, v) in theirs {
        assert!(same(&multi[k], v), "{stem}: multi_info {k}");
    }

    let changed: Vec<serde_json::Value> = m["changed_parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| serde_json::json!([c["timestamp"], c["name"], c["value"]]))
        .collect();
    assert!(
        same(
            &serde_json::Value::from(changed),
            &summary["changed_parameters"]
        ),
        "{stem}: changed parameters"
    );
    let dropouts: Vec<serde_json::Value> = m["dropouts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| serde_json::json!([d["timestamp"], d["duration_ms"]]))
        .collect();
    assert_eq!(
        serde_json::Value::from(dropouts),
        summary["dropouts"],
        "{stem}: dropouts"
    );

    // Default parameters by kind: bit 0 system, bit 1 current setup.
    let mut defaults: BTreeMap<&str, serde_json::Map<String, serde_json::Value>> = BTreeMap::new();
    for d in m["default_parameters"].as_array().unwrap() {
        let types = d["default_types"].as_u64().unwrap();
        for (bit, kind) in [(1, "system"), (2, "current_setup")] {
            if types & bit != 0 {
                defaults
                    .entry(kind)
                    .or_default()
                    .insert(d["name"].as_str().unwrap().to_owned(), d["value"].clone());
            }
        }
    }
    let theirs = summary["default_parameters"].as_object().unwrap();
    assert_eq!(defaults.len(), theirs.len(), "{stem}: default kinds");
    for (kind, values) in defaults {
        assert_same_map(
            &format!("{stem}: defaults {kind}"),
            &serde_json::Value::Object(values),
            &theirs[kind],
        );
    }

    // Logged messages: plain ones as pyulog lists them, tagged ones by tag.
    let mut plain = Vec::new();
    let mut tagged: BTreeMap<String, Vec<serde_json::Value>> = BTreeMap::new();
    for l in m["logged_messages"].as_array().unwrap() {
        let row = serde_json::json!([l["level_raw"], l["timestamp"], l["text"]]);
        match l["tag"].as_u64() {
            Some(t) => tagged.entry(t.to_string()).or_default().push(row),
            None => plain.push(row),
        }
    }
    assert_eq!(
        serde_json::Value::from(plain),
        summary["logged_messages"],
        "{stem}: logged messages"
    );
    let theirs = summary["logged_messages_tagged"].as_object().unwrap();
    assert_eq!(tagged.len(), theirs.len(), "{stem}: tags");
    for (tag, rows) in tagged {
        assert_eq!(
            serde_json::Value::from(rows),
            theirs[&tag],
            "{stem}: tag {tag}"
        );
    }

    let topics = m["topics"].as_array().unwrap();
    assert_eq!(topics.len(), log.subscriptions().len(), "{stem}: topics");
    for (t, topic) in topics.iter().zip(log.topics()) {
        assert_eq!(t["name"], topic.name());
        assert_eq!(t["rows"], topic.len());
    }
}

#[test]
fn parquet_of_every_corpus_log_holds_the_readers_values() {
    check_corpus(
        "parquet_of_every_corpus_log_holds_the_readers_values",
        false,
    );
}

#[test]
fn flattened_parquet_has_pyulogs_columns_and_the_readers_values() {
    check_corpus(
        "flattened_parquet_has_pyulogs_columns_and_the_readers_values",
        true,
    );
}

/// The library's export read from each corpus file in chunks (never held whole), with
/// a buffer budget far below the logs' sizes and three writing threads: rows are put
/// aside in files and read back, and every value is still the reader's; the metadata
/// file, built from the messages kept as the pass went by, is the text that the
/// parsed log gives.
#[test]
fn export_in_one_pass_under_a_small_budget_keeps_every_value_and_the_metadata() {
    use ulog_core::export::{self, Options};
    let corpus = common::corpus();
    let out = common::scratch("export_in_one_pass_under_a_small_budget");
    let options = Options {
        buffer_bytes: 64 << 10,
        threads: 3,
        ..Options::default()
    };
    let mut kept_whole = 0;
    for (stem, path) in common::corpus_logs(&corpus) {
        let bytes = std::fs::read(&path).expect("read log");
        let log = ULog::parse(&bytes).expect("corpus logs parse");
        let dir = out.join(&stem);
        let source = ulog_core::Source::file(&path);
        let export = export::write_parquet(source, &dir, &options).expect("export");
        assert!(export.skipped.is_empty(), "{stem}: {:?}", export.skipped);
        let mut topics: Vec<_> = log.topics().filter(|t| !t.is_empty()).collect();
        topics.sort_by_key(|t| (t.name(), t.multi_id(), t.subscription().index()));
        assert_eq!(export.files.len(), topics.len(), "{stem}: files");
        for (topic, written) in topics.iter().zip(&export.files) {
            assert_eq!(
                (written.topic.as_str(), written.multi_id, written.rows),
                (topic.name(), topic.multi_id(), topic.len()),
                "{stem}"
            );
            check_topic(&stem, topic, &written.path, false);
            let file = std::fs::File::open(&written.path).unwrap();
            let groups = ParquetRecordBatchReaderBuilder::try_new(file)
                .unwrap()
                .metadata()
                .num_row_groups();
            // A topic of more bytes than the budget and fewer than the smallest row
            // group cut for the budget (4 MiB): its rows were put aside and come
            // back whole, in one row group.
            let bytes = topic.layout().unwrap().size() * topic.len();
            if bytes > 2 * options.buffer_bytes && bytes < (4 << 20) {
                assert_eq!(groups, 1, "{stem}: {}", topic.name());
                kept_whole += 1;
            }
        }
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".partial"))
            .collect();
        assert!(left.is_empty(), "{stem}: {left:?}");
        let metadata = std::fs::read_to_string(&export.metadata).unwrap();
        assert!(
            metadata == export::metadata_json(&log),
            "{stem}: metadata.json differs from the parsed log's"
        );
    }
    assert!(kept_whole > 0, "no topic put aside and kept whole");
}
