//! `ulog kml` and `ulog gps-dump`, against pyulog 1.3's `ulog2kml` and
//! `extract_gps_dump`.
//!
//! - KML: on every corpus log with a GPS topic, the placemarks `ulog2kml` writes (its
//!   KML made with simplekml) and ours, both read with Python's `xml.etree`: same
//!   names in order, same colours, same number of coordinates per line, each equal
//!   within 1e-9 relative.
//! - GPX and GeoJSON (read with Python's `xml.etree` and `json`): the same lines and
//!   points as our KML, UTC times in increasing order.
//! - gps-dump: logs written with our writer, two receivers and both directions: the
//!   files equal `extract_gps_dump`'s byte for byte.

mod common;

use std::ffi::OsStr;
use std::path::Path;
use std::process::Command;

use serde_json::Value as Json;
use ulog_core::track::{Track, TrackOptions};
use ulog_core::{LogWriter, ULog};

/// Prints a KML, GPX or GeoJSON file as JSON (`python3 - KIND FILE`), read with
/// Python's own parsers: KML placemarks with their colour (inline, or simplekml's
/// shared style) and coordinates; GPX segments of `[lat, lon, ele, time or null]`
/// (time as seconds since the epoch); GeoJSON as `json` reads it.
const NORMALISE: &str = r#"
import json, sys, datetime
import xml.etree.ElementTree as ET

KML = '{http://www.opengis.net/kml/2.2}'
GPX = '{http://www.topografix.com/GPX/1/1}'

def coords(text):
    text = (text or '').strip()
    # simplekml writes the coordinates of a line without points as this placeholder
    if text in ('', '0.0, 0.0, 0.0'):
        return []
    return [[float(x) for x in c.split(',')] for c in text.split()]

def kml(path):
    root = ET.parse(path).getroot()
    doc = root.find(KML + 'Document')
    styles = {}
    for st in doc.findall(KML + 'Style'):
        c = st.find(KML + 'LineStyle/' + KML + 'color')
        styles['#' + st.get('id')] = c.text if c is not None else None
    out = []
    for pm in doc.findall(KML + 'Placemark'):
        color = None
        url = pm.find(KML + 'styleUrl')
        if url is not None:
            color = styles.get(url.text)
        inline = pm.find(KML + 'Style/' + KML + 'LineStyle/' + KML + 'color')
        if inline is not None:
            color = inline.text
        line = pm.find(KML + 'LineString')
        geom = line if line is not None else pm.find(KML + 'Point')
        out.append({'name': pm.findtext(KML + 'name'), 'color': color,
                    'kind': 'line' if line is not None else 'point',
                    'altitude_mode': geom.findtext(KML + 'altitudeMode'),
                    'coords': coords(geom.findtext(KML + 'coordinates'))})
    return {'root': root.tag, 'placemarks': out}

def gpx(path):
    root = ET.parse(path).getroot()
    def time(p):
        s = p.findtext(GPX + 'time')
        if s is None:
            return None
        return datetime.datetime.fromisoformat(s.replace('Z', '+00:00')).timestamp()
    segments = [[[float(p.get('lat')), float(p.get('lon')), float(p.findtext(GPX + 'ele')), time(p)]
                 for p in seg.findall(GPX + 'trkpt')]
                for trk in root.findall(GPX + 'trk') for seg in trk.findall(GPX + 'trkseg')]
    return {'root': root.tag, 'version': root.get('version'),
            'tracks': len(root.findall(GPX + 'trk')), 'segments': segments}

def geojson(path):
    with open(path) as f:
        return json.load(f)

print(json.dumps({'kml': kml, 'gpx': gpx, 'geojson': geojson}[sys.argv[1]](sys.argv[2])))
"#;

/// A file read by [`NORMALISE`].
fn normalised(kind: &str, path: &Path) -> Json {
    let out = Command::new("python3")
        .args(["-c", NORMALISE, kind])
        .arg(path)
        .output()
        .expect("run python3");
    assert!(
        out.status.success(),
        "{}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON")
}

/// The corpus logs ulog2kml draws: a `vehicle_gnss` or `vehicle_gps_position` with
/// data.
fn gps_logs() -> Vec<(String, std::path::PathBuf)> {
    common::corpus_logs(&common::corpus())
        .into_iter()
        .filter(|(_, path)| {
            let bytes = std::fs::read(path).unwrap();
            let Ok(log) = ULog::parse(&bytes) else {
                return false;
            };
            ["vehicle_gnss", "vehicle_gps_position"]
                .iter()
                .any(|n| log.topic_instances(n).iter().any(|t| !t.is_empty()))
        })
        .collect()
}

fn coords(placemark: &Json) -> Vec<Vec<f64>> {
    points(&placemark["coords"])
}

/// An array of coordinate arrays.
fn points(list: &Json) -> Vec<Vec<f64>> {
    list.as_array()
        .unwrap()
        .iter()
        .map(|c| {
            c.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

#[test]
#[cfg_attr(
    not(all(simplekml, full_corpus)),
    ignore = "needs pyulog and simplekml (pip install pyulog==1.3.0 simplekml==1.3.6) and the full corpus (../shared/corpus)"
)]
fn kml_equals_ulog2kml_on_corpus_logs_with_gps() {
    let dir = common::scratch("kml_equals_ulog2kml");
    let (mut logs, mut lines, mut points) = (0, 0, 0);
    for (stem, path) in gps_logs() {
        let (l, p) = compare_with_ulog2kml(&stem, &path, &dir, None);
        lines += l;
        points += p;
        logs += 1;
    }
    eprintln!("{logs} logs, {lines} lines, {points} points equal to ulog2kml's");
    assert!(logs >= 10, "{logs} corpus logs with GPS compared");
}

/// Runs `ulog2kml` and `ulog kml` (with `camera` as the camera trigger topic) on the
/// log at `path`, and compares their placemarks; returns the number of placemarks
/// and of coordinates compared.
fn compare_with_ulog2kml(
    stem: &str,
    path: &Path,
    dir: &Path,
    camera: Option<&str>,
) -> (usize, usize) {
    let theirs = dir.join(format!("{stem}_pyulog.kml"));
    let py = Command::new("python3")
        .args([
            "-c",
            "import sys\nfrom pyulog.ulog2kml import convert_ulog2kml\n\
             convert_ulog2kml(sys.argv[1], sys.argv[2], camera_trigger_topic_name=sys.argv[3] or None)\n",
        ])
        .arg(path)
        .arg(&theirs)
        .arg(camera.unwrap_or(""))
        .output()
        .expect("run python3");
    assert!(
        py.status.success(),
        "{stem}: {}",
        String::from_utf8_lossy(&py.stderr)
    );
    let ours = dir.join(format!("{stem}.kml"));
    let mut args: Vec<&OsStr> = vec![
        "kml".as_ref(),
        path.as_os_str(),
        "-o".as_ref(),
        ours.as_os_str(),
    ];
    if let Some(c) = camera {
        args.extend([OsStr::new("--camera-trigger"), OsStr::new(c)]);
    }
    common::ulog_ok(args);
    let (t, o) = (normalised("kml", &theirs), normalised("kml", &ours));
    assert_eq!(o["root"], "{http://www.opengis.net/kml/2.2}kml", "{stem}");
    let (t, o) = (
        t["placemarks"].as_array().unwrap(),
        o["placemarks"].as_array().unwrap(),
    );
    let names = |v: &[Json]| -> Vec<String> {
        v.iter()
            .map(|p| p["name"].as_str().unwrap().to_owned())
            .collect()
    };
    let colors = |v: &[Json]| -> Vec<Json> { v.iter().map(|p| p["color"].clone()).collect() };
    assert_eq!(names(o), names(t), "{stem}: placemark names");
    assert_eq!(colors(o), colors(t), "{stem}: colours");
    // Where this reader recovers rows pyulog skips, ulog2kml's points are ours with
    // those left out.
    let recovers = common::RECOVERS_ROWS.contains(&stem);
    let mut points = 0;
    for (a, b) in t.iter().zip(o) {
        let name = a["name"].as_str().unwrap();
        assert_eq!(a["kind"], b["kind"], "{stem}: {name}");
        if b["kind"] == "line" {
            assert_eq!(b["altitude_mode"], "absolute", "{stem}: {name}");
        }
        let (ca, cb) = (coords(a), coords(b));
        let same = |x: &Vec<f64>, y: &Vec<f64>| {
            x.len() == 3 && y.len() == 3 && x.iter().zip(y).all(|(u, v)| close(*u, *v))
        };
        if recovers {
            let mut ours = cb.iter();
            for c in &ca {
                assert!(
                    ours.any(|d| same(c, d)),
                    "{stem}: {name}: ulog2kml's {c:?} is not among ours in order"
                );
            }
        } else {
            assert_eq!(ca.len(), cb.len(), "{stem}: {name}: coordinates");
            for (i, (c, d)) in ca.iter().zip(&cb).enumerate() {
                assert!(same(c, d), "{stem}: {name}: coordinate {i}: {c:?} vs {d:?}");
            }
        }
        points += ca.len();
    }
    (t.len(), points)
}

/// A log with what ulog2kml reads: GPS every 50 ms for 12 s (no fix in the first
/// second, and from 6 to 6.5 s), flight modes changing, camera triggers (a `float`
/// altitude) every second.
fn flight_log(path: &Path) {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    w.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;int32_t lat;int32_t lon;int32_t alt;uint8_t fix_type;")
        .unwrap();
    w.format("vehicle_status:uint64_t timestamp;uint8_t nav_state;")
        .unwrap();
    w.format("camera_capture:uint64_t timestamp;double lat;double lon;float alt;uint32_t seq;")
        .unwrap();
    let gps = w.subscribe_raw("vehicle_gps_position", 0).unwrap();
    let status = w.subscribe_raw("vehicle_status", 0).unwrap();
    let camera = w.subscribe_raw("camera_capture", 0).unwrap();
    let mut data = w.start_data().unwrap();
    // (µs, nav_state): the first (timestamp 0) is left out by ulog2kml, 3 again is
    // no change, 17 and 2 both come before the next point.
    let modes = [
        (0u64, 4u8),
        (2_000_000, 3),
        (2_500_000, 3),
        (5_000_000, 17),
        (5_020_000, 2),
        (8_000_000, 18),
        (8_300_000, 4),
    ];
    let mut modes = modes.iter().peekable();
    let mut seq = 0u32;
    // The last row, 0.55 s after the others, is the log's last timestamp: mode -1.
    for i in (0..240u64).chain([251]) {
        let t = 50_000 * i;
        let s = t as f64 / 1e6;
        while let Some((at, mode)) = modes.next_if(|m| m.0 <= t) {
            data.write_raw(&status, &[&at.to_le_bytes()[..], &[*mode]].concat())
                .unwrap();
        }
        let fix: u8 = if s < 1.0 || (6.0..6.5).contains(&s) {
            2
        } else {
            3
        };
        let lat = 473_977_420 + (i as i32) * 37;
        let lon = 85_455_940 - (i as i32) * 53;
        let alt = 488_000 + (i as i32) * 101;
        let utc = 1_700_000_000_000_000 + t;
        data.write_raw(
            &gps,
            &[
                &t.to_le_bytes()[..],
                &utc.to_le_bytes(),
                &lat.to_le_bytes(),
                &lon.to_le_bytes(),
                &alt.to_le_bytes(),
                &[fix],
            ]
            .concat(),
        )
        .unwrap();
        if i % 20 == 10 {
            seq += 1;
            let alt = 500.0f32 + i as f32 / 7.0;
            data.write_raw(
                &camera,
                &[
                    &t.to_le_bytes()[..],
                    &(f64::from(lat) / 1e7).to_le_bytes(),
                    &(f64::from(lon) / 1e7).to_le_bytes(),
                    &alt.to_le_bytes(),
                    &seq.to_le_bytes(),
                ]
                .concat(),
            )
            .unwrap();
        }
    }
    std::fs::write(path, data.finish().unwrap()).unwrap();
}

#[test]
#[cfg_attr(
    not(simplekml),
    ignore = "needs pyulog and simplekml (pip install pyulog==1.3.0 simplekml==1.3.6)"
)]
fn kml_with_mode_changes_and_camera_triggers_equals_ulog2kml() {
    let dir = common::scratch("kml_camera_triggers");
    let path = dir.join("flight.ulg");
    flight_log(&path);
    let (placemarks, points) = compare_with_ulog2kml("flight", &path, &dir, Some("camera_capture"));
    // Modes 3, 17, 2, 18, 4 and -1 (the last point), 12 triggers.
    assert_eq!(placemarks, 6 + 12);
    assert!(points > 60, "{points}");
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs python3 (with pyulog, pip install pyulog==1.3.0): reads the files with its parsers"
)]
fn gpx_and_geojson_hold_the_kml_track() {
    let dir = common::scratch("kml_gpx_geojson");
    let logs = gps_logs();
    assert!(!logs.is_empty(), "the corpus has logs with GPS");
    let mut timed = 0;
    for (stem, path) in logs {
        let file = |ext: &str| dir.join(format!("{stem}.{ext}"));
        let run = |flag: Option<&str>, out: &Path| {
            let mut args = vec![
                "kml".as_ref(),
                path.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
            ];
            args.extend(flag.map(std::ffi::OsStr::new));
            common::ulog_ok(args);
        };
        run(None, &file("kml"));
        run(Some("--gpx"), &file("gpx"));
        run(Some("--geojson"), &file("geojson"));
        let kml = normalised("kml", &file("kml"));
        let lines: Vec<&Json> = kml["placemarks"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["kind"] == "line")
            .collect();

        let gpx = normalised("gpx", &file("gpx"));
        assert_eq!(
            gpx["root"], "{http://www.topografix.com/GPX/1/1}gpx",
            "{stem}"
        );
        assert_eq!(gpx["version"], "1.1", "{stem}");
        assert_eq!(gpx["tracks"], 1, "{stem}");
        let segments = gpx["segments"].as_array().unwrap();
        assert_eq!(segments.len(), lines.len(), "{stem}: one trkseg per line");
        // The times: each point's own receiver time, as the library reads it.
        let bytes = std::fs::read(&path).unwrap();
        let track =
            Track::from_log(&ULog::parse(&bytes).unwrap(), &TrackOptions::default()).unwrap();
        let mut utc = track
            .segments
            .iter()
            .flat_map(|s| &s.points)
            .map(|p| p.time_utc_usec);
        let mut last_time = f64::NEG_INFINITY;
        for (seg, line) in segments.iter().zip(&lines) {
            let points = seg.as_array().unwrap();
            let kml_points = coords(line);
            assert_eq!(points.len(), kml_points.len(), "{stem}: {}", line["name"]);
            for (p, k) in points.iter().zip(&kml_points) {
                let p = p.as_array().unwrap();
                let v = |i: usize| p[i].as_f64().unwrap();
                assert_eq!([v(1), v(0), v(2)], k[..], "{stem}: lon, lat, ele");
                let want = utc.next().expect("as many points as the track");
                assert_eq!(
                    p[3].is_null(),
                    want.is_none(),
                    "{stem}: a time where there is one"
                );
                if let (Some(t), Some(us)) = (p[3].as_f64(), want) {
                    assert!(close(t, us as f64 / 1e6), "{stem}: {t} is {us} µs");
                    assert!(t >= last_time, "{stem}: times in increasing order");
                    last_time = t;
                    timed += 1;
                }
            }
        }

        let geo = normalised("geojson", &file("geojson"));
        assert_eq!(geo["type"], "FeatureCollection", "{stem}");
        let features = geo["features"].as_array().unwrap();
        assert_eq!(features.len(), lines.len(), "{stem}: one feature per line");
        for (f, line) in features.iter().zip(&lines) {
            assert_eq!(f["type"], "Feature");
            assert_eq!(f["geometry"]["type"], "LineString");
            assert_eq!(f["properties"]["name"], line["name"]);
            assert_eq!(f["properties"]["color"], line["color"]);
            let name = line["name"].as_str().unwrap();
            let (topic, mode) = name.rsplit_once(':').unwrap();
            assert_eq!(f["properties"]["topic"], topic);
            assert_eq!(f["properties"]["nav_state"].to_string(), mode);
            let c = points(&f["geometry"]["coordinates"]);
            assert_eq!(c, coords(line), "{stem}: {name}: coordinates");
            if !c.is_empty() {
                assert!(f["properties"]["start_timestamp"].as_u64().unwrap() > 0);
                assert!(
                    f["properties"]["end_timestamp"].as_u64()
                        >= f["properties"]["start_timestamp"].as_u64()
                );
            }
        }
    }
    assert!(timed > 0, "some points have the receiver's UTC time");
}

#[test]
fn a_log_without_gps_is_a_clear_error() {
    let path = common::sample_file("kml_without_gps");
    let out = common::ulog(["kml".as_ref(), path.as_os_str()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(
        err.contains("no GPS position topic with data in the log")
            && err.contains("`vehicle_gps_position`"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let out = common::ulog([
        "kml".as_ref(),
        path.as_os_str(),
        "--topic".as_ref(),
        "esc_statu".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(
        err.contains("no topic `esc_statu`") && err.contains("esc_status"),
        "{err}"
    );
    // A topic without positions names the fields it looked for.
    let out = common::ulog([
        "kml".as_ref(),
        path.as_os_str(),
        "--topic".as_ref(),
        "esc_status".as_ref(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(err.contains("`lon` or `longitude_deg`"), "{err}");
    // gps-dump says so too.
    let out = common::ulog(["gps-dump".as_ref(), path.as_os_str()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(5), "{err}");
    assert!(err.contains("no topic `gps_dump` in the log"), "{err}");
}

#[test]
#[cfg_attr(not(full_corpus), ignore = "needs the full corpus (../shared/corpus)")]
fn corpus_logs_without_gps_fail_cleanly() {
    let corpus = common::corpus();
    for stem in ["powers", "sample"] {
        let path = corpus.join("files").join(format!("{stem}.ulg"));
        let out = common::ulog([
            "kml".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            "-".as_ref(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(5), "{stem}: {err}");
        assert!(err.contains("no GPS position topic"), "{stem}: {err}");
        assert!(
            out.stdout.is_empty() && !err.contains("panicked"),
            "{stem}: {err}"
        );
    }
}

/// PX4's `gps_dump` format (`instance`, `len`: bit 7 to the device, `data`).
const GPS_DUMP: &str =
    "gps_dump:uint64_t timestamp;uint8_t instance;uint8_t len;uint8_t[79] data;uint8_t[7] _padding0;";

/// A `gps_dump` payload (the trailing padding left out, as PX4 writes it).
fn dump_row(timestamp: u64, instance: u8, len: u8, seed: u32) -> Vec<u8> {
    let mut p = timestamp.to_le_bytes().to_vec();
    p.extend_from_slice(&[instance, len]);
    let mut x = seed.wrapping_mul(2_654_435_761).wrapping_add(1);
    for _ in 0..79 {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        p.push(x as u8);
    }
    p
}

/// A log of `rows` (instance, len) of `gps_dump`, instance 0 of the topic.
fn dump_log(path: &Path, rows: &[(u8, u8)]) {
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    w.format(GPS_DUMP).unwrap();
    let h = w.subscribe_raw("gps_dump", 0).unwrap();
    let mut data = w.start_data().unwrap();
    for (i, &(instance, len)) in rows.iter().enumerate() {
        let i = i as u32;
        data.write_raw(&h, &dump_row(1_000 * u64::from(i + 1), instance, len, i))
            .unwrap();
    }
    std::fs::write(path, data.finish().unwrap()).unwrap();
}

/// Rows of two receivers, both directions, lengths 0 to 79.
fn two_receivers() -> Vec<(u8, u8)> {
    (0..200u32)
        .map(|i| {
            let instance = (i % 3 == 0) as u8;
            let to_device = if i % 5 == 1 { 0x80 } else { 0 };
            (instance, to_device | ((i * 37) % 80) as u8)
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs pyulog (pip install pyulog==1.3.0): compares with its extract_gps_dump"
)]
fn gps_dump_equals_extract_gps_dump() {
    let dir = common::scratch("gps_dump_equals_pyulog");
    let log = dir.join("dump.ulg");
    dump_log(&log, &two_receivers());
    let (ours, theirs) = (dir.join("ours"), dir.join("theirs"));
    std::fs::create_dir_all(&theirs).unwrap();
    // Every instance at once, then one at a time (and one the log does not have).
    let all = common::ulog_ok([
        "gps-dump".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        ours.as_os_str(),
    ]);
    assert_eq!(all.lines().count(), 4, "{all}");
    for instance in ["0", "1", "7"] {
        let py = Command::new("python3")
            .args([
                "-c",
                "import sys\nfrom pyulog.extract_gps_dump import main\nsys.argv = ['extract_gps_dump'] + sys.argv[1:]\nmain()\n",
            ])
            .arg(&log)
            .args(["-o".as_ref(), theirs.as_os_str(), "-i".as_ref(), instance.as_ref()])
            .output()
            .expect("run python3");
        assert!(
            py.status.success(),
            "{}",
            String::from_utf8_lossy(&py.stderr)
        );
        let one = dir.join(format!("ours_{instance}"));
        common::ulog_ok([
            "gps-dump".as_ref(),
            log.as_os_str(),
            "-o".as_ref(),
            one.as_os_str(),
            "-i".as_ref(),
            instance.as_ref(),
        ]);
        for which in ["to", "from"] {
            let name = format!("dump_{instance}_{which}_device.dat");
            let t = std::fs::read(theirs.join(&name)).expect("pyulog's file");
            assert_eq!(std::fs::read(one.join(&name)).unwrap(), t, "{name} (-i)");
            if instance == "7" {
                assert!(t.is_empty(), "{name}");
                assert!(!ours.join(&name).exists(), "{name}: no such instance");
            } else {
                assert!(t.len() > 100, "{name}: {} bytes", t.len());
                assert_eq!(std::fs::read(ours.join(&name)).unwrap(), t, "{name}");
            }
        }
    }
}

#[test]
fn gps_dump_clamps_a_len_beyond_the_data_and_reads_every_topic_instance() {
    let dir = common::scratch("gps_dump_clamps");
    // len 127 to the device: 79 bytes are there.
    let log = dir.join("long.ulg");
    dump_log(&log, &[(0, 5), (0, 0x80 | 127), (0, 3)]);
    let out = common::ulog([
        "gps-dump".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        dir.as_os_str(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("gps_dump message 1 (instance 0): len 127 is more than its data's 79 bytes"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.join("long_0_to_device.dat"))
            .unwrap()
            .len(),
        79
    );
    let from = std::fs::read(dir.join("long_0_from_device.dat")).unwrap();
    let row = |i: u32, n: usize| dump_row(0, 0, 0, i)[10..10 + n].to_vec();
    assert_eq!(from, [row(0, 5), row(2, 3)].concat());

    // Two topic instances without an `instance` field: the receiver is the topic
    // instance; rows of both in file order.
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    w.format("gps_dump:uint64_t timestamp;uint8_t len;uint8_t[4] data;")
        .unwrap();
    let a = w.subscribe_raw("gps_dump", 0).unwrap();
    let mut data = w.start_data().unwrap();
    let b = data.subscribe_raw("gps_dump", 1).unwrap();
    let row = |t: u64, len: u8, bytes: [u8; 4]| [&t.to_le_bytes()[..], &[len], &bytes].concat();
    data.write_raw(&a, &row(1, 2, [1, 2, 9, 9])).unwrap();
    data.write_raw(&b, &row(2, 0x81, [3, 9, 9, 9])).unwrap();
    data.write_raw(&a, &row(3, 1, [4, 9, 9, 9])).unwrap();
    data.write_raw(&b, &row(4, 0x83, [5, 6, 7, 9])).unwrap();
    let multi = dir.join("multi.ulog");
    std::fs::write(&multi, data.finish().unwrap()).unwrap();
    let out = common::ulog_ok([
        "gps-dump".as_ref(),
        multi.as_os_str(),
        "-o".as_ref(),
        dir.as_os_str(),
    ]);
    assert_eq!(out.lines().count(), 4, "{out}");
    let read = |n: &str| std::fs::read(dir.join(n)).unwrap();
    assert_eq!(read("multi_0_from_device.dat"), [1, 2, 4]);
    assert!(read("multi_0_to_device.dat").is_empty());
    assert_eq!(read("multi_1_to_device.dat"), [3, 5, 6, 7]);
    assert!(read("multi_1_from_device.dat").is_empty());
}
