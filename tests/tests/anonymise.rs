//! `ulog anonymise` (`ulog_core::write::Anonymise`) on every corpus log: no original
//! `sys_uuid` byte string and no original position value is left anywhere in the
//! output, distances between positions are kept, every other row is the same.

use std::collections::HashSet;

use ulog_core::format::BasicType;
use ulog_core::write::{Anonymise, ARRAY_POSITIONS, POSITION_FIELDS, RAW_GPS_TOPICS};
use ulog_core::{FieldReader, Topic, ULog};
use ulog_tests::{corpus_files, stem};

/// The position pairs of a topic: latitude and longitude readers.
fn pairs(topic: &Topic<'_, '_>) -> Vec<(FieldReader, FieldReader)> {
    let Ok(fields) = topic.fields() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for f in &fields {
        let (prefix, last) = match f.path().rsplit_once('.') {
            Some((p, l)) => (format!("{p}."), l),
            None => (String::new(), f.path()),
        };
        for (lat, lon) in POSITION_FIELDS {
            if last == *lat {
                if let Some(g) = fields.iter().find(|g| g.path() == format!("{prefix}{lon}")) {
                    if [f.ty(), g.ty()].iter().all(|t| {
                        matches!(t, BasicType::Int32 | BasicType::Float | BasicType::Double)
                    }) {
                        out.push((f.clone(), g.clone()));
                    }
                }
            }
        }
    }
    for (name, lat, lon) in ARRAY_POSITIONS {
        if topic.name() == *name {
            let (Ok(a), Ok(b)) = (topic.field(lat), topic.field(lon)) else {
                continue;
            };
            if a.ty() == BasicType::Double && b.ty() == BasicType::Double {
                out.push((a, b));
            }
        }
    }
    out
}

/// A value in degrees (`int32_t` fields hold 1e-7 degrees).
fn degrees(f: &FieldReader, payload: &[u8]) -> f64 {
    let v = f.read(payload).and_then(|v| v.as_f64()).unwrap();
    if f.ty() == BasicType::Int32 {
        v * 1e-7
    } else {
        v
    }
}

/// Great-circle distance in metres.
fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (p1, p2) = (a.0.to_radians(), b.0.to_radians());
    let h = ((p2 - p1) / 2.0).sin().powi(2)
        + p1.cos() * p2.cos() * ((b.1 - a.1).to_radians() / 2.0).sin().powi(2);
    2.0 * 6_371_000.0 * h.sqrt().asin()
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its logs with GPS and a sys_uuid"
)]
fn anonymised_logs_hold_no_identity_and_no_original_position_and_keep_distances() {
    let mut positions = 0usize;
    let mut uuids = 0;
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let name = stem(&path);
        let mut out = Vec::new();
        Anonymise::new()
            .to(-33.9, 151.2)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        let anon = ULog::parse(&out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let contains = |needle: &[u8]| out.windows(needle.len()).any(|w| w == needle);
        let mut doubles: std::collections::HashMap<u64, String> = Default::default();

        if let Some(uuid) = log.info().iter().find(|kv| kv.name() == "sys_uuid") {
            let text = uuid.value().to_string();
            assert!(text.len() >= 8, "{name}: {text}");
            assert!(
                !contains(text.as_bytes()),
                "{name}: the sys_uuid is still there"
            );
            assert!(anon.info_value("sys_uuid").is_none());
            uuids += 1;
        }

        for topic in log.topics().filter(|t| !t.is_empty()) {
            let what = format!("{name}: {} {}", topic.name(), topic.multi_id());
            if RAW_GPS_TOPICS.contains(&topic.name()) {
                assert!(anon.topic_instances(topic.name()).is_empty(), "{what}");
                continue;
            }
            let moved = anon
                .topics()
                .find(|t| {
                    t.name() == topic.name()
                        && t.multi_id() == topic.multi_id()
                        && t.subscription().msg_id() == topic.subscription().msg_id()
                })
                .unwrap_or_else(|| panic!("{what}: missing"));
            assert_eq!(moved.len(), topic.len(), "{what}: rows");
            let pairs = pairs(&topic);
            if pairs.is_empty() {
                assert!(
                    moved.payloads().eq(topic.payloads()),
                    "{what}: rows changed"
                );
                continue;
            }
            let mut originals: HashSet<u64> = HashSet::new();
            let mut fixes = Vec::new();
            for (p, q) in topic.payloads().zip(moved.payloads()) {
                for (lat, lon) in &pairs {
                    let a = (degrees(lat, p), degrees(lon, p));
                    let b = (degrees(lat, q), degrees(lon, q));
                    if !a.0.is_finite() || !a.1.is_finite() || (a == (0.0, 0.0)) {
                        assert!(a.0.to_bits() == b.0.to_bits() || (a.0.is_nan() && b.0.is_nan()));
                        continue;
                    }
                    originals.insert(a.0.to_bits());
                    originals.insert(a.1.to_bits());
                    fixes.push((a, b));
                    // The raw values of double fields, looked for anywhere in the
                    // output below.
                    if lat.ty() == BasicType::Double {
                        doubles.insert(a.0.to_bits(), format!("{what}: latitude {}", a.0));
                        doubles.insert(a.1.to_bits(), format!("{what}: longitude {}", a.1));
                    }
                }
            }
            for (_, b) in &fixes {
                assert!(
                    !originals.contains(&b.0.to_bits()),
                    "{what}: an original latitude"
                );
                assert!(
                    !originals.contains(&b.1.to_bits()),
                    "{what}: an original longitude"
                );
            }
            // Distances between consecutive positions, to the precision of the field:
            // 1e-7 degrees (about 1 cm) for `int32_t`, a `float`'s step at the new
            // longitude (151°: 1.5e-5 degrees, 1.7 m) for `float`.
            let float = |f: &FieldReader| f.ty() == BasicType::Float;
            let slack = if pairs.iter().any(|(a, b)| float(a) || float(b)) {
                4.0
            } else {
                0.05
            };
            for w in fixes.windows(2) {
                let (d0, d1) = (distance(w[0].0, w[1].0), distance(w[0].1, w[1].1));
                assert!(
                    (d0 - d1).abs() < slack + d0 * 1e-9,
                    "{what}: {d0} m became {d1} m"
                );
            }
            positions += fixes.len();
        }
        for w in out.windows(8) {
            let bits = u64::from_le_bytes(w.try_into().unwrap());
            if let Some(what) = doubles.get(&bits) {
                panic!("{what} left in the output");
            }
        }
    }
    assert!(positions > 10_000, "{positions} positions checked");
    assert!(uuids > 0, "no log with a sys_uuid");
}
