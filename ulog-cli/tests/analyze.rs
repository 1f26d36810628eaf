//! `ulog analyze`: its JSON on every corpus log, and its diagnostics and statistics
//! against flight-review-rs (PX4 Flight Review v2's converter) where that is built.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use common::{corpus, corpus_logs, scratch, ulog, ulog_ok};
use serde_json::Value;

const IDS: [&str; 5] = [
    "battery_brownout",
    "ekf_failure",
    "gps_interference",
    "motor_failure",
    "rc_loss",
];

// Used by the comparisons with flight-review-rs, built only where it is.
#[cfg_attr(not(flight_review), allow(dead_code))]
fn ours(path: &Path) -> Value {
    let out = ulog_ok([Path::new("analyze"), Path::new("--json"), path]);
    let mut lines = out.lines();
    let v: Value = serde_json::from_str(lines.next().expect("one line")).expect("JSON");
    assert!(lines.next().is_none(), "one object per log");
    v
}

#[test]
fn every_corpus_log_gives_one_object_with_its_diagnostics_listed() {
    let logs = corpus_logs(&corpus());
    assert!(!logs.is_empty());
    let mut args = vec!["analyze".to_owned(), "--json".to_owned()];
    args.extend(logs.iter().map(|(_, p)| p.display().to_string()));
    let out = ulog_ok(&args);
    let objects: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line is a JSON object"))
        .collect();
    assert_eq!(
        objects.len(),
        logs.len(),
        "one object per log, one per line"
    );
    for ((stem, path), o) in logs.iter().zip(&objects) {
        assert_eq!(
            o["file"],
            path.display().to_string(),
            "{stem}: in the order given"
        );
        for d in o["diagnostics"].as_array().expect("a list") {
            let keys: BTreeSet<&str> = d.as_object().unwrap().keys().map(|k| k.as_str()).collect();
            let expected = BTreeSet::from([
                "id",
                "severity",
                "timestamp_us",
                "end_timestamp_us",
                "summary",
                "evidence",
            ]);
            assert_eq!(keys, expected, "{stem}: a diagnostic's keys");
            assert!(IDS.contains(&d["id"].as_str().unwrap()), "{stem}: {d}");
            assert!(["info", "warning", "critical"].contains(&d["severity"].as_str().unwrap()));
            assert!(
                d["evidence"]["type"].is_string(),
                "{stem}: evidence has its type"
            );
        }
        for k in ["stats", "battery", "vibration", "flight"] {
            assert!(o[k].is_object(), "{stem}: {k}");
        }
        // The text form reads the same log without failing.
        let text = ulog_ok([Path::new("analyze"), path.as_path()]);
        assert!(text.contains("Diagnostics:"), "{stem}: {text}");
    }
}

#[test]
fn a_missing_file_or_a_directory_fails_with_its_name() {
    let dir = scratch("analyze_missing");
    let missing = dir.join("nope.ulg");
    let out = ulog([Path::new("analyze"), missing.as_path()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("nope.ulg"), "{err}");
    let out = ulog([Path::new("analyze"), dir.as_path()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("analyze_missing"));
}

/// What flight-review-rs says of a log: `metadata.json`'s `analysis`, or `None`
/// where it fails to read the log.
#[cfg(flight_review)]
fn theirs(path: &Path, out: &Path) -> Option<Value> {
    let status = std::process::Command::new(env!("ULOG_TESTS_FLIGHT_REVIEW"))
        .args(["--metadata-only", "--output-format", "compact"])
        .arg(path)
        .arg(out)
        .output()
        .expect("run ulog-convert");
    if !status.status.success() {
        return None;
    }
    let text = std::fs::read_to_string(out.join("metadata.json")).expect("metadata.json");
    let v: Value = serde_json::from_str(&text).expect("metadata JSON");
    Some(v["analysis"].clone())
}

/// The rows of docs/ANALYSIS.md's comparison table: (log, id) → (theirs, ours).
#[cfg_attr(not(flight_review), allow(dead_code))]
fn documented() -> BTreeMap<(String, String), (String, String)> {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/ANALYSIS.md"))
            .expect("docs/ANALYSIS.md");
    let section = doc
        .split("## Against flight-review-rs on the corpus")
        .nth(1)
        .expect("the comparison section");
    let mut rows = BTreeMap::new();
    for line in section.lines().filter(|l| l.starts_with("| ")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells[0] == "Log" || cells.len() != 5 {
            continue;
        }
        assert!(!cells[4].is_empty(), "every row says why: {line}");
        rows.insert(
            (cells[0].to_owned(), cells[1].to_owned()),
            (cells[2].to_owned(), cells[3].to_owned()),
        );
    }
    rows
}

#[test]
#[cfg_attr(
    not(all(flight_review, full_corpus)),
    ignore = "needs flight-review-rs built (python3 bench/source_peers.py flight-review) and the full corpus"
)]
fn diagnostics_match_flight_review_or_are_listed() {
    #[cfg(all(flight_review, full_corpus))]
    {
        let table = documented();
        let dir = scratch("analyze_vs_flight_review");
        let mut seen = BTreeMap::new();
        for (stem, path) in corpus_logs(&corpus()) {
            let o = ours(&path);
            let found = |id: &str, list: &Value| {
                list.as_array()
                    .is_some_and(|l| l.iter().any(|d| d["id"] == id))
            };
            match theirs(&path, &dir.join(&stem)) {
                None => {
                    let detected: Vec<&str> = IDS
                        .iter()
                        .copied()
                        .filter(|id| found(id, &o["diagnostics"]))
                        .collect();
                    let mark = if detected.is_empty() {
                        "—".to_owned()
                    } else {
                        detected.join(", ")
                    };
                    seen.insert((stem.clone(), "all".to_owned()), ("fails".to_owned(), mark));
                }
                Some(a) => {
                    for id in IDS {
                        let pair = (found(id, &a["diagnostics"]), found(id, &o["diagnostics"]));
                        let mark = |b: bool| if b { "detected" } else { "—" }.to_owned();
                        if pair != (false, false) {
                            seen.insert(
                                (stem.clone(), id.to_owned()),
                                (mark(pair.0), mark(pair.1)),
                            );
                        }
                    }
                }
            }
        }
        assert_eq!(
            seen, table,
            "docs/ANALYSIS.md's table (right) is not what the two tools say now (left)"
        );
    }
}

#[test]
#[cfg_attr(
    not(all(flight_review, full_corpus)),
    ignore = "needs flight-review-rs built (python3 bench/source_peers.py flight-review) and the full corpus"
)]
fn statistics_match_flight_review_or_are_explained() {
    #[cfg(all(flight_review, full_corpus))]
    {
        let dir = scratch("analyze_stats_vs_flight_review");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-4 * a.abs().max(b.abs()).max(1.0);
        let mut compared = 0;
        for (stem, path) in corpus_logs(&corpus()) {
            let Some(a) = theirs(&path, &dir.join(&stem)) else {
                continue;
            };
            let o = ours(&path);
            let bytes = std::fs::read(&path).unwrap();
            let log = ulog_core::ULog::parse(&bytes).unwrap();
            let instances = |name: &str| log.topics().filter(|t| t.name() == name).count();
            for (k, v) in a["stats"].as_object().unwrap() {
                let (t, w) = (v.as_f64().unwrap(), o["stats"][k].as_f64().unwrap());
                if k == "max_rotation_speed_deg_s" && instances("vehicle_angular_velocity") == 0 {
                    // Theirs reads only vehicle_angular_velocity; ours the attitude's rates.
                    assert_eq!(t, 0.0, "{stem}");
                    if instances("vehicle_attitude") == 0 {
                        assert_eq!(w, 0.0, "{stem}: no body rates at all");
                    } else {
                        assert!(w > 0.0, "{stem}: the attitude's body rates");
                    }
                    continue;
                }
                assert!(close(t, w), "{stem}: stats.{k}: theirs {t}, ours {w}");
                compared += 1;
            }
            if instances("battery_status") <= 1 {
                for (k, v) in a["battery"].as_object().unwrap() {
                    assert_eq!(
                        v.is_null(),
                        o["battery"][k].is_null(),
                        "{stem}: battery.{k}"
                    );
                    if let (Some(t), Some(w)) = (v.as_f64(), o["battery"][k].as_f64()) {
                        assert!(close(t, w), "{stem}: battery.{k}: theirs {t}, ours {w}");
                        compared += 1;
                    }
                }
            }
            let g = &a["gps_quality"];
            for (k, v) in g.as_object().unwrap() {
                let w = &o["gps"][k];
                match (v.as_f64(), w.as_f64()) {
                    (Some(t), Some(w)) => {
                        assert!(close(t, w), "{stem}: gps.{k}: theirs {t}, ours {w}");
                        compared += 1;
                    }
                    // Theirs leaves out a most of 0 satellites (or 0 m).
                    (None, Some(w)) => assert_eq!(w, 0.0, "{stem}: gps.{k}"),
                    (t, w) => assert_eq!(t.is_some(), w.is_some(), "{stem}: gps.{k}: {v} vs {w:?}"),
                }
            }
            if let Some(seen) = g["fix_types_seen"].as_array().filter(|s| !s.is_empty()) {
                assert_eq!(
                    seen,
                    o["gps"]["fix_types_seen"].as_array().unwrap(),
                    "{stem}"
                );
            }
            let (tv, ov) = (&a["vibration"], &o["vibration"]);
            for k in ["accel_vibe_mean", "accel_vibe_max"] {
                assert_eq!(tv[k].is_null(), ov[k].is_null(), "{stem}: vibration.{k}");
                if let (Some(t), Some(w)) = (tv[k].as_f64(), ov[k].as_f64()) {
                    assert!(close(t, w), "{stem}: vibration.{k}: theirs {t}, ours {w}");
                    compared += 1;
                }
            }
            if !tv["accel_vibe_mean"].is_null() {
                assert_eq!(tv["status"], ov["status"], "{stem}: vibration status");
            }
        }
        assert!(compared > 150, "{compared} figures compared");
    }
}
