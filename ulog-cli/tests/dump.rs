//! `ulog dump`: every message in file order, with the reader's findings where they
//! start; JSON lines agree with pyulog's summaries of the corpus.

mod common;

use std::collections::HashMap;

use serde_json::Value as Json;
use ulog_core::ULog;

fn json_lines(text: &str) -> Vec<Json> {
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

#[test]
fn every_message_of_every_corpus_log() {
    let dir = common::corpus();
    for (stem, path) in common::corpus_logs(&dir) {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let lines = json_lines(&common::ulog_ok([
            "dump".as_ref(),
            "--json".as_ref(),
            path.as_os_str(),
        ]));
        let (findings, messages): (Vec<&Json>, Vec<&Json>) =
            lines.iter().partition(|j| j.get("finding").is_some());
        assert_eq!(
            messages.len() as u64,
            log.message_count(),
            "{stem}: messages"
        );
        assert_eq!(findings.len(), log.findings().len(), "{stem}: findings");
        // File order, each finding where it starts.
        let offsets: Vec<u64> = lines
            .iter()
            .map(|j| j["offset"].as_u64().unwrap())
            .collect();
        assert!(
            offsets.windows(2).all(|w| w[0] <= w[1]),
            "{stem}: not in file order"
        );
        for f in log.findings() {
            assert!(
                findings
                    .iter()
                    .any(|j| j["offset"] == f.offset && j["len"] == f.len),
                "{stem}: finding {f} missing"
            );
        }

        // Data rows per topic instance, their columns and first timestamp, as pyulog.
        let mut rows: HashMap<(String, u64), Vec<&Json>> = HashMap::new();
        for m in messages.iter().filter(|m| m["type"] == "D") {
            if let (Some(t), Some(i)) = (m["topic"].as_str(), m["multi_id"].as_u64()) {
                rows.entry((t.to_owned(), i)).or_default().push(m);
            }
        }
        let summary = common::summary(&dir, &stem);
        for t in summary["topics"].as_array().unwrap() {
            let key = (
                t["name"].as_str().unwrap().to_owned(),
                t["multi_id"].as_u64().unwrap(),
            );
            let expected = t["rows"].as_u64().unwrap() as usize;
            let got = rows.get(&key).map_or(&[][..], |v| v.as_slice());
            if common::RECOVERS_ROWS.contains(&stem.as_str()) {
                assert!(got.len() >= expected, "{stem} {key:?}: {} rows", got.len());
            } else {
                assert_eq!(got.len(), expected, "{stem} {key:?}: rows");
            }
            let Some(first) = got.first() else { continue };
            let fields = first["fields"].as_object().expect("decoded fields");
            let names: Vec<&str> = fields.keys().map(String::as_str).collect();
            // pyulog splits `char[N]` into N columns; the reader keeps one string.
            let mut columns: Vec<&str> = t["columns"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_str().unwrap())
                .map(|c| match c.rsplit_once('[') {
                    Some((base, _)) if fields.get(base).is_some_and(Json::is_string) => base,
                    _ => c,
                })
                .collect();
            columns.dedup();
            assert_eq!(names, columns, "{stem} {key:?}: columns");
            if let Some(ts) = fields.get("timestamp") {
                if !common::RECOVERS_ROWS.contains(&stem.as_str()) {
                    assert_eq!(ts, &t["first_timestamp"], "{stem} {key:?}: first timestamp");
                }
            }
        }
    }
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus: ../shared/corpus beside the workspace, or $ULOG_CORPUS"
)]
fn text_has_one_line_per_message_and_finding() {
    let dir = common::corpus();
    let path = dir.join("files/corrupt_unregistered_msg_id.ulg");
    let text = common::ulog_ok(["dump".as_ref(), path.as_os_str()]);
    let json = common::ulog_ok(["dump".as_ref(), "--json".as_ref(), path.as_os_str()]);
    assert_eq!(text.lines().count(), json.lines().count());
    for (t, j) in text.lines().zip(json_lines(&json)) {
        let mut parts = t.split_whitespace();
        let offset: u64 = parts.next().unwrap().parse().unwrap();
        assert_eq!(offset, j["offset"].as_u64().unwrap(), "{t}");
        let letter = parts.next().unwrap();
        match j.get("type") {
            Some(ty) => assert_eq!(letter, ty.as_str().unwrap(), "{t}"),
            None => assert_eq!(letter, "!", "{t}"),
        }
    }
    let damage = text.lines().filter(|l| l.contains("  !  ")).count();
    assert!(damage >= 3, "the corruptions of this log are shown");
}

#[test]
fn topic_filter_and_unknown_topic() {
    let file = common::sample_file("dump_filter");
    let bytes = std::fs::read(&file).unwrap();
    let log = ULog::parse(&bytes).unwrap();
    let topic = log.topics().next().unwrap();
    let name = topic.name().to_owned();
    let lines = json_lines(&common::ulog_ok([
        "dump".as_ref(),
        "--json".as_ref(),
        file.as_os_str(),
        "-m".as_ref(),
        name.as_ref(),
    ]));
    let data: Vec<&Json> = lines.iter().filter(|j| j["type"] == "D").collect();
    assert_eq!(
        data.len(),
        log.topic_instances(&name)
            .iter()
            .map(|t| t.len())
            .sum::<usize>()
    );
    assert!(data.iter().all(|j| j["topic"] == name.as_str()));
    assert!(
        lines.iter().any(|j| j["type"] == "F"),
        "definitions still shown"
    );

    let none = json_lines(&common::ulog_ok([
        "dump".as_ref(),
        "--json".as_ref(),
        "--no-data".as_ref(),
        file.as_os_str(),
    ]));
    assert!(none.iter().all(|j| j["type"] != "D"));

    let out = common::ulog([
        "dump".as_ref(),
        file.as_os_str(),
        "-m".as_ref(),
        name[..name.len() - 1].as_ref(),
    ]);
    assert_eq!(out.status.code(), Some(5));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains(&name), "suggests {name}: {err}");
}

/// A log that subscribes one topic instance twice (under two msg_ids, the same
/// format): `dump` names the topic for the data of both, as `csv` (every row) and
/// `check` (no finding) read it, by the reader's one rule.
#[test]
fn a_topic_instance_subscribed_twice_is_one_topic_in_dump() {
    use ulog_core::testing::LogBuilder;
    let mut b = LogBuilder::new(1, 0);
    b.flag_bits([0; 8], [0; 8], [0; 3]);
    b.format("t:uint64_t timestamp;uint32_t a;uint32_t b;");
    b.subscribe(0, 0, "t");
    b.subscribe(0, 1, "t");
    for i in 0..6u64 {
        let mut p = (100 * i).to_le_bytes().to_vec();
        p.extend_from_slice(&(i as u32).to_le_bytes());
        p.extend_from_slice(&0u32.to_le_bytes());
        b.data((i % 2) as u16, &p);
    }
    let dir = common::scratch("dump_twice");
    let path = dir.join("twice.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let text = common::ulog_ok(["dump".as_ref(), path.as_os_str()]);
    assert!(!text.contains("no subscription"), "{text}");
    let data_lines = text
        .lines()
        .filter(|l| l.contains(" D ") || l.contains("data"))
        .count();
    assert!(data_lines >= 6, "{text}");
    let json = common::ulog_ok(["dump".as_ref(), path.as_os_str(), "--json".as_ref()]);
    let topics = json
        .lines()
        .filter(|l| l.contains("\"topic\":\"t\""))
        .count();
    assert!(topics >= 6, "{json}");
    let out = dir.join("csv");
    common::ulog_ok([
        "csv".as_ref(),
        path.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let csv = std::fs::read_to_string(out.join("twice_t_0.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7);
    let check = common::ulog(["check".as_ref(), path.as_os_str()]);
    assert_eq!(
        check.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&check.stdout)
    );
}
