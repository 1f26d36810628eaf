//! Every log of the shared corpus read by `ulog-core` and compared, value for value,
//! with what pyulog 1.3 makes of it (`../shared/corpus/expected`).
//!
//! Deliberate differences from pyulog, each asserted below where it shows:
//! - findings: pyulog's `file_corruption` flag is compared with our damage findings,
//!   and we also report damage pyulog is silent about (a zero-filled tail);
//! - after corruption, pyulog skips to the next sync message; we resynchronise on the
//!   first header that starts a chain of valid messages, so we keep the data messages
//!   between the damage and that sync. Such extra rows are allowed only in those
//!   stretches, and their timestamps must run on into the rows that follow.

use std::collections::BTreeMap;

use serde_json::Value as J;
use ulog_core::{LogFile, Value};
use ulog_tests::{
    cell_matches, corpus_files, expected_summary, json_matches, recovered_stretches, stem,
};

fn check_summary(path: &std::path::Path) {
    let name = stem(path);
    let exp = expected_summary(path);
    let file = LogFile::open(path).unwrap();
    let log = file.parse().unwrap_or_else(|e| panic!("{name}: {e}"));

    assert_eq!(
        exp["file_version"],
        J::from(log.version()),
        "{name}: version"
    );
    assert_eq!(
        exp["start_timestamp"],
        J::from(log.start_timestamp()),
        "{name}: start"
    );
    assert_eq!(
        exp["last_timestamp"],
        J::from(log.last_timestamp()),
        "{name}: last timestamp"
    );

    // Flag bits.
    let (compat, incompat, offsets) = match log.flag_bits() {
        Some(f) => (
            f.compat_flags.to_vec(),
            f.incompat_flags.to_vec(),
            f.appended_offsets
                .iter()
                .copied()
                .filter(|&o| o != 0)
                .collect::<Vec<_>>(),
        ),
        None => (vec![0; 8], vec![0; 8], vec![]),
    };
    assert_eq!(exp["compat_flags"], J::from(compat), "{name}: compat");
    assert_eq!(exp["incompat_flags"], J::from(incompat), "{name}: incompat");
    assert_eq!(
        exp["appended_offsets"],
        J::from(offsets.clone()),
        "{name}: offsets"
    );
    assert_eq!(
        log.appended_sections(),
        &offsets[..],
        "{name}: appended sections reached"
    );

    // Damage: pyulog's flag against our findings.
    let pyulog_corrupt = exp["file_corruption"].as_bool().unwrap();
    if pyulog_corrupt {
        assert!(
            log.has_damage(),
            "{name}: pyulog found corruption, we found none"
        );
    }

    // Information: a dictionary in pyulog (the last value of a key wins).
    let info = exp["info"].as_object().unwrap();
    let mut ours: BTreeMap<String, Value> = BTreeMap::new();
    for kv in log.info() {
        ours.insert(kv.name().into_owned(), kv.value());
    }
    assert_eq!(
        info.keys().collect::<Vec<_>>(),
        ours.keys().collect::<Vec<_>>(),
        "{name}: info keys"
    );
    for (k, v) in info {
        assert!(
            json_matches(v, &ours[k]),
            "{name}: info {k}: {v} vs {:?}",
            ours[k]
        );
    }

    // Multi-information: key -> entries -> continued parts.
    let multi = exp["info_multi"].as_object().unwrap();
    assert_eq!(
        multi.len(),
        log.multi_info().len(),
        "{name}: multi-info keys"
    );
    for m in log.multi_info() {
        let e = multi[&m.name].as_array().unwrap();
        assert_eq!(
            e.len(),
            m.entries.len(),
            "{name}: multi-info {} entries",
            m.name
        );
        for (ee, oe) in e.iter().zip(&m.entries) {
            let ee = ee.as_array().unwrap();
            assert_eq!(ee.len(), oe.len(), "{name}: multi-info {} parts", m.name);
            for (ev, ov) in ee.iter().zip(oe) {
                assert!(
                    json_matches(ev, &ov.value()),
                    "{name}: multi-info {}",
                    m.name
                );
            }
        }
    }

    // Parameters.
    let initial = exp["initial_parameters"].as_object().unwrap();
    let mut ours: BTreeMap<String, Value> = BTreeMap::new();
    for kv in log.initial_params() {
        ours.insert(kv.name().into_owned(), kv.value());
    }
    assert_eq!(initial.len(), ours.len(), "{name}: initial parameter count");
    for (k, v) in initial {
        assert!(
            json_matches(v, &ours[k]),
            "{name}: param {k}: {v} vs {:?}",
            ours[k]
        );
    }
    let changed = exp["changed_parameters"].as_array().unwrap();
    assert_eq!(
        changed.len(),
        log.param_changes().len(),
        "{name}: changed parameters"
    );
    for (e, c) in changed.iter().zip(log.param_changes()) {
        assert_eq!(e[0], J::from(c.timestamp), "{name}: change time");
        assert_eq!(
            e[1],
            J::from(c.kv.name().into_owned()),
            "{name}: change name"
        );
        assert!(json_matches(&e[2], &c.kv.value()), "{name}: change value");
    }
    let defaults = exp["default_parameters"].as_object().unwrap();
    for (group, bit) in [("system", 1u8), ("current_setup", 2u8)] {
        let mut ours: BTreeMap<String, Value> = BTreeMap::new();
        for d in log.default_params() {
            if d.default_types & bit != 0 {
                ours.insert(d.kv.name().into_owned(), d.kv.value());
            }
        }
        let e = defaults.get(group).and_then(J::as_object);
        assert_eq!(
            e.map_or(0, |e| e.len()),
            ours.len(),
            "{name}: defaults {group}"
        );
        for (k, v) in e.into_iter().flatten() {
            assert!(json_matches(v, &ours[k]), "{name}: default {k}");
        }
    }

    // Logged strings.
    let plain: Vec<_> = log
        .logged_messages()
        .iter()
        .filter(|l| l.tag.is_none())
        .collect();
    let e = exp["logged_messages"].as_array().unwrap();
    assert_eq!(e.len(), plain.len(), "{name}: logged messages");
    for (e, l) in e.iter().zip(&plain) {
        assert_eq!(e[0], J::from(l.raw_level), "{name}: level");
        assert_eq!(e[1], J::from(l.timestamp), "{name}: log time");
        assert!(json_matches(&e[2], &Value::Str(l.text)), "{name}: log text");
    }
    let tagged = exp["logged_messages_tagged"].as_object().unwrap();
    let total: usize = tagged.values().map(|v| v.as_array().unwrap().len()).sum();
    assert_eq!(
        total,
        log.logged_messages().len() - plain.len(),
        "{name}: tagged messages"
    );
    for (tag, msgs) in tagged {
        let ours: Vec<_> = log
            .logged_messages()
            .iter()
            .filter(|l| l.tag.map(|t| t.to_string()).as_deref() == Some(tag.as_str()))
            .collect();
        for (e, l) in msgs.as_array().unwrap().iter().zip(ours) {
            assert_eq!(e[0], J::from(l.raw_level));
            assert_eq!(e[1], J::from(l.timestamp));
            assert!(json_matches(&e[2], &Value::Str(l.text)));
        }
    }

    // Dropouts: (timestamp, duration).
    let drops: Vec<J> = log
        .dropouts()
        .iter()
        .map(|d| J::from(vec![d.timestamp, u64::from(d.duration_ms)]))
        .collect();
    assert_eq!(exp["dropouts"], J::from(drops), "{name}: dropouts");

    // Formats: name -> [type, array length (0 for none), field name].
    let formats = exp["formats"].as_object().unwrap();
    assert_eq!(formats.len(), log.formats().len(), "{name}: format count");
    for f in log.formats() {
        let fields: Vec<J> = f
            .fields
            .iter()
            .map(|x| {
                J::from(vec![
                    J::from(x.ty.as_str()),
                    J::from(x.array_len.unwrap_or(0)),
                    J::from(x.name.as_str()),
                ])
            })
            .collect();
        assert_eq!(
            formats[&f.name],
            J::from(fields),
            "{name}: format {}",
            f.name
        );
    }

    // Topics: every (name, multi_id) with its rows, timestamps and columns.
    let topics = exp["topics"].as_array().unwrap();
    let recovered = recovered_stretches(&log);
    let with_data: Vec<_> = log.topics().filter(|t| !t.is_empty()).collect();
    assert_eq!(topics.len(), with_data.len(), "{name}: topics with data");
    for e in topics {
        let t = log
            .topic(
                e["name"].as_str().unwrap(),
                e["multi_id"].as_u64().unwrap() as u8,
            )
            .unwrap();
        let tn = format!("{name}: {}/{}", t.name(), t.multi_id());
        // Rows we recover where pyulog skips to the next sync are left out here; the CSV
        // test checks them.
        let ts: Vec<u64> = t
            .timestamps()
            .into_iter()
            .zip(t.message_offsets())
            .filter(|&(_, o)| !recovered.iter().any(|&(a, b)| a <= o && o < b))
            .map(|(ts, _)| ts)
            .collect();
        assert_eq!(e["rows"], J::from(ts.len()), "{tn}: rows");
        assert_eq!(
            e["first_timestamp"],
            J::from(ts[0]),
            "{tn}: first timestamp"
        );
        assert_eq!(
            e["last_timestamp"],
            J::from(*ts.last().unwrap()),
            "{tn}: last timestamp"
        );
        // pyulog's data columns list a `char[N]` element by element.
        let mut cols: Vec<String> = Vec::new();
        for c in t.fields().unwrap() {
            match c.shape() {
                ulog_core::read::FieldShape::String(n) => {
                    cols.extend((0..n).map(|i| format!("{}[{i}]", c.path())))
                }
                _ => cols.push(c.path().to_owned()),
            }
        }
        let tpos = cols.iter().position(|c| c == "timestamp").unwrap();
        let tcol = cols.remove(tpos);
        cols.insert(0, tcol);
        assert_eq!(e["columns"], J::from(cols), "{tn}: columns");
    }
}

fn check_csv(path: &std::path::Path) -> usize {
    let name = stem(path);
    let dir = ulog_tests::corpus_dir()
        .join("expected")
        .join(&name)
        .join("csv");
    let file = LogFile::open(path).unwrap();
    let log = file.parse().unwrap();
    let mut checked = 0;
    let recovered = recovered_stretches(&log);
    let mut csv_files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    csv_files.sort();
    let topics: Vec<_> = log.topics().filter(|t| !t.is_empty()).collect();
    assert_eq!(
        csv_files.len(),
        topics.len(),
        "{name}: one CSV per topic instance"
    );
    for t in topics {
        let csv = dir.join(format!(
            "{name}_{}_{}.csv",
            t.name().replace('/', "_"),
            t.multi_id()
        ));
        let text =
            std::fs::read_to_string(&csv).unwrap_or_else(|e| panic!("{}: {e}", csv.display()));
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let readers: Vec<_> = header.iter().map(|h| t.field(h).unwrap()).collect();
        let offsets = t.message_offsets();
        let timestamps = t.timestamps();
        let mut ours = 0usize;
        let mut extra = 0usize;
        for (row, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            assert_eq!(
                cells.len(),
                readers.len(),
                "{}: row {row}: cell count",
                csv.display()
            );
            loop {
                let payload = t
                    .payload(ours)
                    .unwrap_or_else(|| panic!("{}: row {row}: we have fewer rows", csv.display()));
                let same = cells
                    .iter()
                    .zip(&readers)
                    .all(|(cell, r)| cell_matches(cell, &r.read(payload).unwrap()));
                if same {
                    checked += cells.len();
                    ours += 1;
                    break;
                }
                let o = offsets.get(ours).unwrap();
                assert!(
                    recovered.iter().any(|&(a, b)| a <= o && o < b),
                    "{}: row {row}: pyulog {line:?}, ours {:?} (offset {o})",
                    csv.display(),
                    readers
                        .iter()
                        .map(|r| r.read(payload).unwrap().to_string())
                        .collect::<Vec<_>>()
                );
                // A recovered row belongs to the stretch after the damage: its time
                // runs on into the rows pyulog kept.
                if ours + 1 < timestamps.len() {
                    assert!(
                        timestamps[ours] <= timestamps[ours + 1],
                        "{name}: recovered row in order"
                    );
                }
                extra += 1;
                ours += 1;
            }
        }
        while ours < t.len() {
            let o = offsets.get(ours).unwrap();
            assert!(
                recovered.iter().any(|&(a, b)| a <= o && o < b),
                "{}: we have more rows than pyulog",
                csv.display()
            );
            extra += 1;
            ours += 1;
        }
        if extra > 0 {
            eprintln!(
                "{name}: {}/{}: {extra} rows recovered that pyulog drops",
                t.name(),
                t.multi_id()
            );
        }
    }
    checked
}

#[test]
fn every_corpus_log_matches_pyulog_summaries() {
    for path in corpus_files() {
        check_summary(&path);
    }
}

#[test]
fn every_corpus_log_matches_pyulog_csv_value_for_value() {
    let mut total = 0;
    for path in corpus_files() {
        total += check_csv(&path);
    }
    eprintln!("compared {total} values");
}
