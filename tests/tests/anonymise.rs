//! `ulog anonymise` (`ulog_core::write::Anonymise`) on every corpus log and on built
//! logs: no original `sys_uuid`, no value or pair of values within 0.01° of where the
//! vehicle was (in any field, parameter or string, in degrees, radians or 1e-7
//! degrees), no date or time of day in any string or event message with `zero_utc`; distances between
//! positions are kept, and nothing else changes.
//!
//! The scan is this file's own: the places the vehicle was are read from the original
//! log with the generic reader (fields named as positions, `lat`/`lon` and the like,
//! by this file's list), and the output is searched by value, not by the anonymiser's
//! rules.

use std::collections::{HashMap, HashSet};

use ulog_core::events::EventOptions;
use ulog_core::format::BasicType;
use ulog_core::read::FieldShape;
use ulog_core::testing::LogBuilder;
use ulog_core::write::{Anonymise, ARRAY_POSITIONS, POSITION_FIELDS, RAW_GPS_TOPICS};
use ulog_core::{FieldReader, Topic, ULog, Value};
use ulog_tests::{corpus_files, stem};

/// How near to where the vehicle was a value must not be, in degrees.
const TOL: f64 = 0.01;

/// This file's names of a position's fields (the last part of a path, with one
/// prefix): `int32_t` in 1e-7 degrees, floats in degrees.
const NAMES: &[(&str, &str)] = &[
    ("lat", "lon"),
    ("latitude", "longitude"),
    ("latitude_deg", "longitude_deg"),
    ("ref_lat", "ref_lon"),
];

/// Where the vehicle was: every position of the original log's fields named as one.
struct Origins {
    lats: Vec<f64>,
    lons: Vec<f64>,
    grid: HashMap<(i64, i64), Vec<(f64, f64)>>,
    count: usize,
    /// The first position met (topics in order, then rows).
    first: Option<(f64, f64)>,
}

fn grid_cell(lat: f64, lon: f64) -> (i64, i64) {
    ((lat / TOL).floor() as i64, (lon / TOL).floor() as i64)
}

fn sorted_near(sorted: &[f64], v: f64, tol: f64) -> bool {
    let i = sorted.partition_point(|&x| x < v - tol);
    sorted.get(i).is_some_and(|&x| x <= v + tol)
}

impl Origins {
    fn of(log: &ULog<'_>) -> Origins {
        let mut points: HashSet<(u64, u64)> = HashSet::new();
        let mut count = 0;
        let mut first = None;
        for topic in log.topics() {
            let Ok(fields) = topic.fields() else {
                continue;
            };
            for f in &fields {
                let (prefix, last) = match f.path().rsplit_once('.') {
                    Some((p, l)) => (format!("{p}."), l),
                    None => (String::new(), f.path()),
                };
                for (lat, lon) in NAMES {
                    if last != *lat {
                        continue;
                    }
                    let Some(g) = fields.iter().find(|g| g.path() == format!("{prefix}{lon}"))
                    else {
                        continue;
                    };
                    for p in topic.payloads() {
                        let (Some(a), Some(b)) = (named_degrees(f, p), named_degrees(g, p)) else {
                            continue;
                        };
                        if a.is_finite() && b.is_finite() && (a, b) != (0.0, 0.0) {
                            points.insert((a.to_bits(), b.to_bits()));
                            first.get_or_insert((a, b));
                            count += 1;
                        }
                    }
                }
            }
        }
        let mut grid: HashMap<(i64, i64), Vec<(f64, f64)>> = HashMap::new();
        let (mut lats, mut lons) = (Vec::new(), Vec::new());
        for (a, b) in points {
            let (lat, lon) = (f64::from_bits(a), f64::from_bits(b));
            grid.entry(grid_cell(lat, lon))
                .or_default()
                .push((lat, lon));
            lats.push(lat);
            lons.push(lon);
        }
        lats.sort_by(f64::total_cmp);
        lons.sort_by(f64::total_cmp);
        lats.dedup();
        lons.dedup();
        Origins {
            lats,
            lons,
            grid,
            count,
            first,
        }
    }

    fn lat_near(&self, v: f64, tol: f64) -> bool {
        sorted_near(&self.lats, v, tol)
    }

    fn lon_near(&self, v: f64, tol: f64) -> bool {
        sorted_near(&self.lons, v, tol)
    }

    /// Whether a position is within [`TOL`] of where the vehicle was, in latitude and
    /// in longitude.
    fn near(&self, lat: f64, lon: f64) -> bool {
        let (y, x) = grid_cell(lat, lon);
        (y - 1..=y + 1).any(|cy| {
            (x - 1..=x + 1).any(|cx| {
                self.grid.get(&(cy, cx)).is_some_and(|ps| {
                    ps.iter()
                        .any(|&(a, b)| (a - lat).abs() <= TOL && (b - lon).abs() <= TOL)
                })
            })
        })
    }
}

/// A field named as a position, in degrees.
fn named_degrees(f: &FieldReader, payload: &[u8]) -> Option<f64> {
    match f.read(payload)? {
        Value::I32(v) => Some(f64::from(v) * 1e-7),
        Value::F32(v) => Some(f64::from(v)),
        Value::F64(v) => Some(v),
        _ => None,
    }
}

/// The ways a number may hold a coordinate: a float in degrees or in radians, an
/// integer of 32 or 64 bits in 1e-7 degrees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unit {
    Degrees,
    Radians,
    E7,
}

/// A number as coordinates in each unit it may hold one in.
fn as_coordinates(v: &Value<'_>) -> Vec<(Unit, f64)> {
    let int = |x: f64| vec![(Unit::E7, x * 1e-7)];
    let float = |x: f64| vec![(Unit::Degrees, x), (Unit::Radians, x.to_degrees())];
    match *v {
        Value::I32(x) => int(f64::from(x)),
        Value::U32(x) => int(f64::from(x)),
        Value::I64(x) => int(x as f64),
        Value::U64(x) => int(x as f64),
        Value::F32(x) if x.is_finite() => float(f64::from(x)),
        Value::F64(x) if x.is_finite() => float(x),
        _ => Vec::new(),
    }
}

/// The numbers written in a text, as coordinates: with a decimal point in degrees,
/// seven to ten digits in 1e-7 degrees.
fn text_coordinates(text: &[u8]) -> Vec<(String, Unit, f64)> {
    let text = String::from_utf8_lossy(text);
    text.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .flat_map(|piece| {
            piece
                .split('-')
                .enumerate()
                .map(|(i, p)| (i, p.to_string()))
        })
        .filter_map(|(_, p)| {
            let p = p.trim_matches('.');
            let v: f64 = p.parse().ok()?;
            if p.contains('.') {
                Some((p.to_string(), Unit::Degrees, v))
            } else if (7..=10).contains(&p.len()) {
                Some((p.to_string(), Unit::E7, v * 1e-7))
            } else {
                None
            }
        })
        .flat_map(|(p, unit, v)| {
            // A minus sign before the number was split off: both signs.
            [(p.clone(), unit, v), (format!("-{p}"), unit, -v)]
        })
        .collect()
}

/// Pairs among `values` (what, unit, degrees) that are a position within [`TOL`] of
/// where the vehicle was: a latitude and a longitude of two different values, in one
/// unit.
fn leaks(origins: &Origins, what: &str, values: &[(String, Unit, f64)], found: &mut Vec<String>) {
    let lat: Vec<&(String, Unit, f64)> = values
        .iter()
        .filter(|v| origins.lat_near(v.2, TOL))
        .collect();
    if lat.is_empty() {
        return;
    }
    for a in lat {
        for b in values.iter().filter(|b| origins.lon_near(b.2, TOL)) {
            if a.0 != b.0 && a.1 == b.1 && origins.near(a.2, b.2) {
                found.push(format!(
                    "{what}: {} = {} and {} = {} ({:?})",
                    a.0, a.2, b.0, b.2, a.1
                ));
            }
        }
    }
}

/// The numbers of a key-value message as coordinates, named by its key.
fn key_coordinates(name: &str, v: &Value<'_>) -> Vec<(String, Unit, f64)> {
    as_coordinates(v)
        .into_iter()
        .map(|(u, d)| (name.to_string(), u, d))
        .collect()
}

/// Every place in `log` (the anonymised one) where a position within [`TOL`] of
/// `origins` is: data rows, `char[N]` fields, parameters, information and
/// multi-information, logged strings.
fn scan(origins: &Origins, log: &ULog<'_>) -> (Vec<String>, usize) {
    let mut found = Vec::new();
    let mut values_seen = 0;
    for topic in log.topics() {
        let Ok(fields) = topic.fields() else {
            continue;
        };
        for (row, p) in topic.payloads().enumerate() {
            let mut values = Vec::new();
            for f in &fields {
                let Some(v) = f.read(p) else {
                    continue;
                };
                if let FieldShape::String(_) = f.shape() {
                    if let Some(text) = v.as_str() {
                        let what = format!("{} row {row} {}", topic.name(), f.path());
                        leaks(
                            origins,
                            &what,
                            &text_coordinates(text.as_bytes()),
                            &mut found,
                        );
                    }
                    continue;
                }
                for (u, d) in as_coordinates(&v) {
                    values.push((f.path().to_string(), u, d));
                }
            }
            values_seen += values.len();
            let what = format!("{}/{} row {row}", topic.name(), topic.multi_id());
            leaks(origins, &what, &values, &mut found);
        }
    }
    // Parameters (initial, changed, defaults) as one set of values; information the
    // same; strings one by one.
    let mut params = Vec::new();
    for kv in log
        .initial_params()
        .iter()
        .chain(log.param_changes().iter().map(|c| &c.kv))
        .chain(log.default_params().iter().map(|d| &d.kv))
    {
        params.extend(key_coordinates(&kv.name(), &kv.value()));
    }
    values_seen += params.len();
    leaks(origins, "parameters", &params, &mut found);
    let mut info = Vec::new();
    for kv in log.info() {
        match kv.value() {
            Value::Str(s) => leaks(
                origins,
                &format!("information {}", kv.name()),
                &text_coordinates(s.as_bytes()),
                &mut found,
            ),
            v => info.extend(key_coordinates(&kv.name(), &v)),
        }
    }
    leaks(origins, "information", &info, &mut found);
    for m in log.multi_info() {
        for entry in &m.entries {
            let text: Vec<u8> = entry
                .iter()
                .flat_map(|kv| kv.value().as_str().map(|s| s.as_bytes().to_vec()))
                .flatten()
                .collect();
            leaks(
                origins,
                &format!("multi-information {}", m.name),
                &text_coordinates(&text),
                &mut found,
            );
        }
    }
    for l in log.logged_messages() {
        leaks(
            origins,
            &format!("logged string at {}", l.offset),
            &text_coordinates(l.text.as_bytes()),
            &mut found,
        );
    }
    for e in log.events(&EventOptions::default()).iter() {
        leaks(
            origins,
            &format!("event row {}", e.row),
            &text_coordinates(e.text.as_bytes()),
            &mut found,
        );
    }
    (found, values_seen)
}

/// Every string of a log: logged strings, the messages of PX4 events (decoded with
/// the metadata the log embeds), information and multi-information (parts joined),
/// `char[N]` fields.
fn strings(log: &ULog<'_>) -> Vec<Vec<u8>> {
    let mut out: Vec<Vec<u8>> = log
        .logged_messages()
        .iter()
        .map(|l| l.text.as_bytes().to_vec())
        .collect();
    for e in log.events(&EventOptions::default()).iter() {
        out.push(e.text.as_bytes().to_vec());
    }
    for kv in log.info() {
        if let Value::Str(s) = kv.value() {
            out.push(s.as_bytes().to_vec());
        }
    }
    for m in log.multi_info() {
        for entry in &m.entries {
            out.push(
                entry
                    .iter()
                    .filter_map(|kv| kv.value().as_str().map(|s| s.as_bytes().to_vec()))
                    .flatten()
                    .collect(),
            );
        }
    }
    for topic in log.topics() {
        let Ok(fields) = topic.fields() else {
            continue;
        };
        for f in fields
            .iter()
            .filter(|f| matches!(f.shape(), FieldShape::String(_)))
        {
            for p in topic.payloads() {
                if let Some(s) = f.read(p).and_then(|v| v.as_str()) {
                    out.push(s.as_bytes().to_vec());
                }
            }
        }
    }
    out
}

/// The dates (`2021-05-22`, `2026-8-20`, years from 1990) and times of day
/// (`19_41_57` of a log file's name, `06:46:06`) written in a text, that are not all
/// zeros.
fn dates_and_times(text: &[u8]) -> Vec<String> {
    let text = String::from_utf8_lossy(text);
    let b = text.as_bytes();
    let digits = |i: usize, max: usize| -> usize {
        b[i..]
            .iter()
            .take(max)
            .take_while(|c| c.is_ascii_digit())
            .count()
    };
    let mut out = Vec::new();
    for i in 0..b.len() {
        if !b[i].is_ascii_digit() || (i > 0 && b[i - 1].is_ascii_digit()) {
            continue;
        }
        // YYYY-M-D
        if digits(i, 5) == 4 && b.get(i + 4) == Some(&b'-') {
            let y: u32 = text[i..i + 4].parse().unwrap();
            let m = digits(i + 5, 3);
            if (1990..=2100).contains(&y) && (1..=2).contains(&m) && b.get(i + 5 + m) == Some(&b'-')
            {
                let d = digits(i + 6 + m, 3);
                if (1..=2).contains(&d) {
                    out.push(text[i..i + 6 + m + d].to_string());
                }
            }
        }
        // H_M_S.ulg and HH:MM:SS
        let h = digits(i, 3);
        if (1..=2).contains(&h) {
            for sep in [b'_', b':'] {
                if b.get(i + h) != Some(&sep) {
                    continue;
                }
                let m = digits(i + h + 1, 3);
                if !(1..=2).contains(&m) || b.get(i + h + 1 + m) != Some(&sep) {
                    continue;
                }
                let s = digits(i + h + 2 + m, 3);
                let end = i + h + 2 + m + s;
                let ulg = text[end..].starts_with(".ulg");
                if (1..=2).contains(&s) && (sep == b':' && s == 2 || ulg) {
                    out.push(text[i..end].to_string());
                }
            }
        }
    }
    out.retain(|s| s.bytes().any(|c| (b'1'..=b'9').contains(&c)));
    out
}

/// After `anonymise --zero-utc`, a scan of every corpus log the tests have (each
/// numeric field of each row in degrees, radians and 1e-7 degrees, each parameter,
/// each string) finds no position within 0.01° of where the vehicle was, and no date
/// or time of day of the original's strings is left anywhere in the file.
#[test]
fn no_value_of_any_corpus_log_is_left_near_where_it_flew_nor_a_date() {
    let mut logs_with_positions = 0;
    let mut values = 0;
    let mut dates = 0;
    let mut failures = Vec::new();
    let mut origin_params = 0;
    for path in corpus_files() {
        let name = stem(&path);
        let bytes = std::fs::read(&path).unwrap();
        let origins = Origins::of(&ULog::parse(&bytes).unwrap());
        // The estimator's origin where the flight began, as in a real flight's log.
        let bytes = match origins.first.and_then(|at| with_origin_params(&bytes, at)) {
            Some(set) => {
                origin_params += 1;
                set
            }
            None => bytes,
        };
        let log = ULog::parse(&bytes).unwrap();
        let mut out = Vec::new();
        Anonymise::new()
            .to(-33.9, 151.2)
            .zero_utc(true)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        let anon = ULog::parse(&out).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            anon.findings().iter().all(|f| !f.is_damage()),
            "{name}: {:?}",
            anon.findings()
        );
        if origins.count > 0 {
            logs_with_positions += 1;
            // The scan finds the positions of the original: it can fail.
            assert!(!scan(&origins, &log).0.is_empty(), "{name}");
            let (found, seen) = scan(&origins, &anon);
            values += seen;
            failures.extend(found.into_iter().map(|f| format!("{name}: {f}")));
        }
        let originals: HashSet<String> = strings(&log)
            .iter()
            .flat_map(|s| dates_and_times(s))
            .collect();
        for d in &originals {
            dates += 1;
            if out.windows(d.len()).any(|w| w == d.as_bytes()) {
                failures.push(format!("{name}: `{d}` left in the file"));
            }
        }
        // The anonymised strings hold no date or time of their own either.
        for s in strings(&anon) {
            for d in dates_and_times(&s) {
                failures.push(format!(
                    "{name}: `{d}` in `{}`",
                    String::from_utf8_lossy(&s)
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} left:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        logs_with_positions > 0 && values > 100_000,
        "{logs_with_positions} logs, {values} values"
    );
    eprintln!("{logs_with_positions} logs with positions, {values} values scanned, {dates} dates and times");
    if ulog_tests::FULL_CORPUS {
        assert!(
            dates > 20,
            "{dates} dates and times in the corpus's strings"
        );
        assert!(origin_params > 0, "no log with LPE_LAT and positions");
    }
}

/// `bytes` with every value of the parameters `LPE_LAT` and `LPE_LON` (`float`: the
/// local position estimator's origin, initial, changed or default) set to `at`, when
/// the log has both. The corpus's logs hold PX4's defaults there (40.43° N 86.93° W,
/// far from where they flew); a vehicle's own log holds where it was.
fn with_origin_params(bytes: &[u8], at: (f64, f64)) -> Option<Vec<u8>> {
    let mut out = bytes.to_vec();
    let mut set = [0, 0];
    for (k, (name, v)) in [("LPE_LAT", at.0), ("LPE_LON", at.1)]
        .into_iter()
        .enumerate()
    {
        // The key with its length byte, as a parameter message holds it.
        let key = format!("float {name}");
        let needle = [&[key.len() as u8][..], key.as_bytes()].concat();
        let mut i = 0;
        while let Some(found) = out[i..].windows(needle.len()).position(|w| w == needle) {
            let value = i + found + needle.len();
            out[value..value + 4].copy_from_slice(&(v as f32).to_le_bytes());
            set[k] += 1;
            i = value;
        }
    }
    (set[0] > 0 && set[1] > 0).then_some(out)
}

/// The position pairs of a topic named by the library's own lists: latitude and
/// longitude readers.
fn named_pairs(topic: &Topic<'_, '_>) -> Vec<(FieldReader, FieldReader)> {
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

/// Whether a value that changed held a coordinate: within 0.1° of where the vehicle
/// was, in latitude or longitude, in a unit its type may hold one in.
fn was_coordinate(origins: &Origins, v: &Value<'_>) -> bool {
    as_coordinates(v)
        .iter()
        .any(|&(_, d)| origins.lat_near(d, 0.1) || origins.lon_near(d, 0.1))
}

#[test]
#[cfg_attr(
    not(full_corpus),
    ignore = "needs the full corpus (../shared/corpus): its logs with GPS and a sys_uuid"
)]
fn anonymised_logs_hold_no_identity_keep_distances_and_change_nothing_else() {
    let mut positions = 0usize;
    let mut uuids = 0;
    for path in corpus_files() {
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        let name = stem(&path);
        let origins = Origins::of(&log);
        let mut out = Vec::new();
        Anonymise::new()
            .to(-33.9, 151.2)
            .edit(&log)
            .write(&log, &mut out)
            .unwrap();
        let anon = ULog::parse(&out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let contains = |needle: &[u8]| out.windows(needle.len()).any(|w| w == needle);
        let mut doubles: HashMap<u64, String> = HashMap::new();

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
            // Nothing but coordinates and strings changed.
            let fields = topic.fields().unwrap();
            for (row, (p, q)) in topic.payloads().zip(moved.payloads()).enumerate() {
                if p == q {
                    continue;
                }
                for f in &fields {
                    let (a, b) = (f.read(p).unwrap(), f.read(q).unwrap());
                    if a.to_string() != b.to_string() {
                        assert!(
                            matches!(f.shape(), FieldShape::String(_))
                                || was_coordinate(&origins, &a),
                            "{what} row {row}: {} changed from {a} to {b}",
                            f.path()
                        );
                    }
                }
            }
            let pairs = named_pairs(&topic);
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

fn f64s(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A log flown at 47.3977° N 8.5456° E, with what names a position and what holds one
/// under other names: the estimator's origin as parameters (named `LPE_LAT`/`LPE_LON`,
/// and a pair of parameters whose names say nothing), a target estimate
/// (`lat_est`/`lon_est`), a fake position's `observation[2]`, a custom topic in
/// radians and one in 1e-7 degrees, positions and dates in logged strings, in a
/// `char[N]` field and in multi-information split across parts; and what must not
/// move: a float near the latitude alone, and a pair of fields that is near the
/// position in one row of a hundred.
fn built() -> Vec<u8> {
    let (lat, lon) = (47.397742f64, 8.545594f64);
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "PX4");
    b.info_str("log_file", "/fs/microsd/log/2021-05-22/19_41_57.ulg");
    for (i, part) in [
        "[hardfault] -- 2000-0",
        "1-01-00:00:36 at 47.39",
        "7742, 8.54559",
    ]
    .iter()
    .enumerate()
    {
        let key = format!("char[{}] perf", part.len());
        b.multi_info(i > 0, &key, part.as_bytes());
    }
    b.param("float LPE_LAT", &(lat as f32).to_le_bytes());
    b.param("float LPE_LON", &(lon as f32).to_le_bytes());
    b.param("double XYZ_ORIGIN_A", &(lat + 0.001).to_le_bytes());
    b.param("double XYZ_ORIGIN_B", &(lon + 0.002).to_le_bytes());
    b.param("float MPC_XY_VEL_MAX", &47.4f32.to_le_bytes());
    b.format("vehicle_global_position:uint64_t timestamp;double lat;double lon;float alt;");
    b.format(
        "follow_target_estimator:uint64_t timestamp;double lat_est;double lon_est;float alt_est;",
    );
    b.format(
        "estimator_aid_src_fake_pos:uint64_t timestamp;double[2] observation;float[2] innovation;",
    );
    b.format("custom_rad:uint64_t timestamp;float a;float b;float c;");
    b.format("custom_e7:uint64_t timestamp;int32_t y;int32_t x;");
    b.format("battery_status:uint64_t timestamp;float voltage_v;float current_a;");
    b.format("mavlink_log:uint64_t timestamp;char[40] text;uint8_t severity;");
    for (i, name) in [
        "vehicle_global_position",
        "follow_target_estimator",
        "estimator_aid_src_fake_pos",
        "custom_rad",
        "custom_e7",
        "battery_status",
        "mavlink_log",
    ]
    .iter()
    .enumerate()
    {
        b.subscribe(0, i as u16, name);
    }
    b.log(
        b'6',
        1,
        "[logger] Opened full log file: /fs/microsd/log/2021-05-22/19_41_57.ulg",
    );
    b.log(b'6', 2, "opening log file 2026-8-20/6_5_17.ulg");
    b.log(b'6', 3, "home set: 47.3977420, 8.5455940 (alt 488.1)");
    for n in 0..100u64 {
        let t = 1_000 + n * 10_000;
        let d = n as f64 * 1e-5;
        let ts = t.to_le_bytes();
        b.data(
            0,
            &[&ts[..], &f64s(&[lat + d, lon + d]), &488.0f32.to_le_bytes()].concat(),
        );
        b.data(
            1,
            &[
                &ts[..],
                &f64s(&[lat - d, lon + 2.0 * d]),
                &490.0f32.to_le_bytes(),
            ]
            .concat(),
        );
        b.data(
            2,
            &[&ts[..], &f64s(&[lat + 2.0 * d, lon - d]), &[0u8; 8]].concat(),
        );
        let rad = [
            (lat + d).to_radians() as f32,
            0.5,
            (lon - d).to_radians() as f32,
        ];
        b.data(
            3,
            &[
                &ts[..],
                &rad.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>()[..],
            ]
            .concat(),
        );
        let e7 = [((lat + d) * 1e7) as i32, ((lon + d) * 1e7) as i32];
        b.data(
            4,
            &[
                &ts[..],
                &e7.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>()[..],
            ]
            .concat(),
        );
        // A voltage near the latitude in degrees in every row; a current near the
        // longitude in one row only.
        let current = if n == 50 {
            lon as f32
        } else {
            3.0 + n as f32 * 0.1
        };
        let volts = [(lat as f32) - 0.001 * n as f32, current];
        b.data(
            5,
            &[
                &ts[..],
                &volts
                    .iter()
                    .flat_map(|v| v.to_le_bytes())
                    .collect::<Vec<_>>()[..],
            ]
            .concat(),
        );
    }
    let mut text = [0u8; 40];
    let msg = b"landed 2024-03-01 06:46:06";
    text[..msg.len()].copy_from_slice(msg);
    b.data(6, &[&5_000u64.to_le_bytes()[..], &text, &[6]].concat());
    b.into_bytes()
}

#[test]
fn positions_under_other_names_move_and_near_values_that_are_not_positions_stay() {
    let bytes = built();
    let log = ULog::parse(&bytes).unwrap();
    assert!(log.findings().is_empty(), "{:?}", log.findings());
    let origins = Origins::of(&log);
    assert!(origins.count >= 100);
    let mut out = Vec::new();
    Anonymise::new()
        .to(-33.9, 151.2)
        .zero_utc(true)
        .edit(&log)
        .write(&log, &mut out)
        .unwrap();
    let anon = ULog::parse(&out).unwrap();
    let (found, _) = scan(&origins, &anon);
    assert!(found.is_empty(), "{found:#?}");
    let texts: Vec<String> = strings(&anon)
        .iter()
        .map(|s| String::from_utf8_lossy(s).into_owned())
        .collect();
    for s in &texts {
        assert!(dates_and_times(s.as_bytes()).is_empty(), "{s}");
    }
    // What moved, moved where the rotation takes it: near 33.9° S 151.2° E.
    let near_target = |lat: f64, lon: f64| (lat + 33.9).abs() < 0.01 && (lon - 151.2).abs() < 0.01;
    let param = |n: &str| anon.initial_param(n).and_then(|v| v.as_f64()).unwrap();
    assert!(near_target(param("LPE_LAT"), param("LPE_LON")));
    assert!(near_target(param("XYZ_ORIGIN_A"), param("XYZ_ORIGIN_B")));
    assert_eq!(param("MPC_XY_VEL_MAX"), f64::from(47.4f32));
    let first = |topic: &str, a: &str, b: &str, scale: f64| {
        let t = anon.topic(topic, 0).unwrap();
        let p = t.payload(0).unwrap();
        let v = |f: &str| {
            t.field(f)
                .unwrap()
                .read(p)
                .and_then(|v| v.as_f64())
                .unwrap()
                * scale
        };
        (v(a), v(b))
    };
    for (topic, a, b, scale) in [
        ("follow_target_estimator", "lat_est", "lon_est", 1.0),
        (
            "estimator_aid_src_fake_pos",
            "observation[0]",
            "observation[1]",
            1.0,
        ),
        ("custom_rad", "a", "c", 180.0 / std::f64::consts::PI),
        ("custom_e7", "y", "x", 1e-7),
    ] {
        let (lat, lon) = first(topic, a, b, scale);
        assert!(near_target(lat, lon), "{topic}: {lat} {lon}");
    }
    // Not positions: unchanged, every row.
    let same = |topic: &str| {
        let (t, u) = (log.topic(topic, 0).unwrap(), anon.topic(topic, 0).unwrap());
        t.payloads().eq(u.payloads())
    };
    assert!(same("battery_status"));
    assert_eq!(first("custom_rad", "b", "b", 1.0).0, 0.5);
    // Text: positions moved, dates and times zeros.
    assert!(
        texts
            .iter()
            .any(|s| s == "home set: -33.9000000, 151.2000000 (alt 488.1)"),
        "{texts:#?}"
    );
    assert!(texts
        .iter()
        .any(|s| s == "[logger] Opened full log file: /fs/microsd/log/0000-00-00/00_00_00.ulg"));
    assert!(texts
        .iter()
        .any(|s| s == "opening log file 0000-0-00/0_0_00.ulg"));
    assert!(texts
        .iter()
        .any(|s| s.starts_with("landed 0000-00-00 00:00:00")));
    let perf: Vec<String> = anon.multi_info()[0].entries[0]
        .iter()
        .map(|kv| kv.value().as_str().unwrap().to_string())
        .collect();
    // Split over three messages: every replacement as long as what it replaces.
    assert_eq!(
        perf.concat(),
        "[hardfault] -- 0000-00-00-00:00:00 at -33.90000, 151.200"
    );
    assert_eq!(
        perf.iter().map(String::len).collect::<Vec<_>>(),
        [21, 22, 13]
    );
}
