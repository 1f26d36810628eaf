//! `ulog params`, `messages` and `info` on every corpus log, checked against pyulog's
//! summary (`expected/<stem>/summary.json`). The exact text layout is checked on the
//! bundled sample (`text_sample.rs`) and, with pyulog installed, by
//! `compare_with_pyulog.sh`.

mod common;

use serde_json::Value as Json;

/// A parameter value printed by `ulog params` equals pyulog's value.
fn same_value(text: &str, expected: &Json) -> bool {
    match expected {
        Json::Number(n) if n.is_f64() => {
            text.contains(['.', 'e', 'n']) && text.parse::<f64>().ok() == n.as_f64()
        }
        Json::Number(n) => text == n.to_string(),
        Json::String(s) => text == s,
        other => *other == *text,
    }
}

#[test]
fn params_equal_pyulog_summary() {
    let corpus = common::corpus();
    for (stem, path) in common::corpus_logs(&corpus) {
        let s = common::summary(&corpus, &stem);
        let initial = s["initial_parameters"].as_object().unwrap();
        let changes = s["changed_parameters"].as_array().unwrap();
        let out = common::ulog_ok(["params".as_ref(), path.as_os_str(), "-t".as_ref()]);
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines.len(), 2 * initial.len(), "{stem}");
        for (pair, (name, value)) in lines.chunks(2).zip(initial) {
            let vals: Vec<&str> = pair[0].split(',').collect();
            let times: Vec<&str> = pair[1].split(',').collect();
            assert_eq!(vals[0], name, "{stem}: sorted names");
            assert!(
                same_value(vals[1], value),
                "{stem}: {name} = {} vs {value}",
                vals[1]
            );
            let mine: Vec<&Json> = changes.iter().filter(|c| c[1] == name.as_str()).collect();
            assert_eq!(vals.len() - 2, mine.len(), "{stem}: changes of {name}");
            assert_eq!(times[0], "timestamp");
            for (i, c) in mine.iter().enumerate() {
                assert!(same_value(vals[2 + i], &c[2]), "{stem}: change of {name}");
                if !common::RECOVERS_ROWS.contains(&stem.as_str()) {
                    assert_eq!(
                        times[2 + i],
                        c[0].to_string(),
                        "{stem}: time of change of {name}"
                    );
                }
            }
        }
        for (kind, list) in s["default_parameters"].as_object().unwrap() {
            let out = common::ulog_ok([
                "params".as_ref(),
                path.as_os_str(),
                "--default".as_ref(),
                kind.as_ref() as &std::ffi::OsStr,
            ]);
            let list = list.as_object().unwrap();
            assert_eq!(out.lines().count(), list.len(), "{stem} {kind}");
            for (line, (name, value)) in out.lines().zip(list) {
                let (n, v) = line.split_once(',').unwrap();
                assert_eq!(n, name);
                assert!(same_value(v, value), "{stem} {kind}: {name}");
            }
        }
    }
}

#[test]
fn messages_equal_pyulog_summary() {
    let corpus = common::corpus();
    for (stem, path) in common::corpus_logs(&corpus) {
        let s = common::summary(&corpus, &stem);
        let msg = |m: &Json| {
            common::message_line(
                m[0].as_u64().unwrap(),
                m[1].as_u64().unwrap(),
                m[2].as_str().unwrap(),
            )
        };
        let mut plain: Vec<(u64, String)> = s["logged_messages"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| (m[1].as_u64().unwrap(), msg(m)))
            .collect();
        // As ulog_messages: PX4 logs are ordered by time (a stable sort).
        if s["info"]["sys_name"] == "PX4" {
            plain.sort_by_key(|m| m.0);
        }
        let out = common::ulog_ok([
            "messages".as_ref(),
            "--no-tagged".as_ref(),
            path.as_os_str(),
        ]);
        let bytes = std::fs::read(&path).unwrap();
        let log = ulog_core::ULog::parse(&bytes).unwrap();
        let events = log.topic("event", 0).is_ok_and(|t| !t.is_empty());
        if s["info"]["sys_name"] == "PX4" && events {
            // Events are printed among the strings (`messages_events.rs` compares the
            // whole output with ulog_messages'): the strings that are not copies of
            // events (no trailing tab) are there, in order.
            let mut lines = out.lines();
            for (_, m) in plain.iter().filter(|m| !m.1.ends_with('\t')) {
                assert!(lines.any(|l| l == m), "{stem}: `{m}`");
            }
            continue;
        }
        let expected: String = plain.iter().map(|m| m.1.clone() + "\n").collect();
        assert_eq!(out, expected, "{stem}");

        let all = common::ulog_ok(["messages".as_ref(), path.as_os_str()]);
        let tagged: Vec<String> = s["logged_messages_tagged"]
            .as_object()
            .unwrap()
            .values()
            .flat_map(|v| v.as_array().unwrap().iter().map(msg))
            .collect();
        assert_eq!(all.lines().count(), plain.len() + tagged.len(), "{stem}");
        for t in tagged {
            assert!(all.lines().any(|l| l == t), "{stem}: tagged `{t}`");
        }
    }
}

#[test]
fn info_equals_pyulog_summary() {
    let corpus = common::corpus();
    for (stem, path) in common::corpus_logs(&corpus) {
        let s = common::summary(&corpus, &stem);
        let text = common::ulog_ok(["info".as_ref(), path.as_os_str()]);
        let corrupt = s["file_corruption"].as_bool().unwrap();
        assert_eq!(
            text.starts_with("Warning: file has data corruption(s)\n"),
            corrupt,
            "{stem}"
        );
        let start = s["start_timestamp"].as_u64().unwrap();
        let last = s["last_timestamp"].as_u64().unwrap();
        let hms = |us: u64| {
            let t = us / 1_000_000;
            format!("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
        };
        let recovers = common::RECOVERS_ROWS.contains(&stem.as_str());
        if !recovers {
            let line = format!(
                "Logging start time: {}, duration: {}\n",
                hms(start),
                hms(last - start)
            );
            assert!(text.contains(&line), "{stem}: {line}");
        }
        let info_lines: Vec<&str> = text
            .lines()
            .skip_while(|l| *l != "Info Messages:")
            .skip(1)
            .take_while(|l| l.starts_with(' '))
            .collect();
        let info = s["info"].as_object().unwrap();
        let shown: Vec<(&String, &Json)> = info
            .iter()
            .filter(|(k, _)| !k.starts_with("perf_"))
            .collect();
        assert_eq!(info_lines.len(), shown.len(), "{stem}: info keys");
        for (line, (k, v)) in info_lines.iter().zip(shown) {
            let (name, value) = line[1..].split_once(": ").unwrap();
            assert_eq!(name, k);
            let value_ok = match v {
                Json::String(s) => s.starts_with(value),
                v => same_value(value, v),
            };
            assert!(value_ok, "{stem}: info {k}: {value} vs {v}");
        }

        let j: Json = serde_json::from_str(&common::ulog_ok([
            "info".as_ref(),
            "--json".as_ref(),
            path.as_os_str(),
        ]))
        .unwrap();
        assert_eq!(j["file_version"], s["file_version"], "{stem}");
        assert_eq!(j["start_timestamp"], s["start_timestamp"], "{stem}");
        assert_eq!(j["corrupted"], s["file_corruption"], "{stem}");
        if !recovers {
            assert_eq!(j["last_timestamp"], s["last_timestamp"], "{stem}");
        }
        let expected_offsets = s["appended_offsets"].as_array().unwrap();
        assert_eq!(
            j["appended_sections"].as_array().unwrap(),
            expected_offsets,
            "{stem}"
        );
        let topics: Vec<(String, u64, u64)> = s["topics"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|t| t["rows"].as_u64().unwrap() > 0)
            .map(|t| {
                (
                    t["name"].as_str().unwrap().to_owned(),
                    t["multi_id"].as_u64().unwrap(),
                    t["rows"].as_u64().unwrap(),
                )
            })
            .collect();
        let ours = j["topics"].as_array().unwrap();
        assert_eq!(ours.len(), topics.len(), "{stem}: topics with data");
        for (name, multi_id, rows) in topics {
            let row = ours
                .iter()
                .find(|t| t["name"] == name.as_str() && t["multi_id"] == multi_id)
                .unwrap_or_else(|| panic!("{stem}: topic {name} {multi_id}"));
            let points = row["data_points"].as_u64().unwrap();
            if recovers {
                assert!(points >= rows, "{stem}: {name} {multi_id}");
            } else {
                assert_eq!(points, rows, "{stem}: {name} {multi_id}");
            }
            let table_row = format!(
                " {:<40} {points:7} ",
                format!("{name} ({multi_id}, {})", row["message_size"])
            );
            assert!(text.contains(&table_row), "{stem}: table row for {name}");
        }
    }
}
