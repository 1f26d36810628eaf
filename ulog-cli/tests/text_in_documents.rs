//! Text a log holds, in every XML, JSON and HTML document `ulog` writes: a log whose
//! file name, topic name, information key and value, parameter name and logged
//! messages hold control characters (some that XML 1.0 cannot hold at all), `<`, `&`,
//! quotes and non-ASCII text.
//!
//! - XML (KML, GPX, SVG plots): each file parses with Python's `xml.etree` (expat),
//!   and the text reads back, with what XML cannot hold as U+FFFD.
//! - HTML (the flight report): read with Python's `html.parser`, the text reads back
//!   the same way, and no character HTML takes for a parse error is left raw; in
//!   headless Chromium the page has no console error, and its title and cells read back
//!   too.
//! - JSON (`info --json`, `check --json`, `dump --json`, GeoJSON, a `--per-log`
//!   export's `metadata.json`, MCAP's JSON messages and schemas): each parses with
//!   Python's `json` (MCAP with Foxglove's reader), and the text reads back exactly.

mod common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use serde_json::Value as Json;
use ulog_core::testing::LogBuilder;

/// Characters XML 1.0 cannot hold (U+0001, U+000B, U+001F, U+FFFE), DEL and a C1
/// control, markup, quotes and non-ASCII text.
const HOSTILE: &str = "a\u{1}b\u{b}c\u{1f}d\u{7f}e\u{85} <i>&amp; \"q\" 'x' é\u{fffe}ü";
/// A logged message (ERROR, so that plots mark it), short enough to be shown whole,
/// with terminal colours (ESC, which XML cannot hold; the reader takes no other control
/// character in a logged string's first 128 bytes, where it tells text from binary).
const MESSAGE: &str = "\u{1b}[1;31merr <b>&\"q\"'é\u{1b}[0m";
/// Names hold no control character (the reader refuses a key with one), but markup,
/// quotes and non-ASCII text.
const KEY: &str = "note <&\"'é>";
const PARAM: &str = "P<&\"'é>";
/// A subscription's name (no format has it): the reader takes any byte in a name past
/// the first 128, where it tells names from binary.
fn topic() -> String {
    format!("t{}\u{1}<&\"'é>", "_".repeat(127))
}
/// The log's file stem (the caption and title of the KML, GPX, plot and report).
const STEM: &str = "fl\u{1}<&'\"é";

/// `s` as XML and HTML documents hold it: what they cannot hold as U+FFFD (the rule
/// the README states: C0 controls but tab, line feed and carriage return; DEL; C1;
/// noncharacters).
fn shown(s: &str) -> String {
    s.chars()
        .map(|c| {
            let n = c as u32;
            let unfit = (c.is_control() && !matches!(c, '\t' | '\n' | '\r'))
                || (0xFDD0..=0xFDEF).contains(&n)
                || n & 0xFFFE == 0xFFFE;
            if unfit {
                '\u{fffd}'
            } else {
                c
            }
        })
        .collect()
}

/// Bytes read one character per byte (ISO 8859-1), as exports read `char[N]` values.
fn latin1(s: &str) -> String {
    s.bytes().map(char::from).collect()
}

/// A logged message (INFO) whose first 128 bytes are plain: [`HOSTILE`] after them.
fn long_message() -> String {
    format!("{}{HOSTILE}", "x".repeat(128))
}

/// The log, in `dir`: GPS for ten seconds (a track to draw), the hostile texts.
fn hostile_log(dir: &Path) -> PathBuf {
    let mut b = LogBuilder::new(1, 0);
    b.info_str("sys_name", "PX4");
    b.info_str("ver_hw", HOSTILE);
    b.info_str(KEY, HOSTILE);
    b.param(&format!("int32_t {PARAM}"), &1i32.to_le_bytes());
    b.format("vehicle_gps_position:uint64_t timestamp;uint64_t time_utc_usec;int32_t lat;int32_t lon;int32_t alt;uint8_t fix_type;");
    b.format("vehicle_status:uint64_t timestamp;uint8_t nav_state;");
    b.subscribe(0, 0, "vehicle_gps_position");
    b.subscribe(0, 1, "vehicle_status");
    b.subscribe(0, 2, &topic());
    b.data(1, &[&0u64.to_le_bytes()[..], &[4]].concat());
    for i in 0..100u64 {
        let t = i * 100_000;
        if t == 2_000_000 {
            b.log(b'3', t, MESSAGE);
            b.log(b'6', t, &long_message());
        }
        if t == 5_000_000 {
            b.param(&format!("int32_t {PARAM}"), &2i32.to_le_bytes());
        }
        let lat = 473_977_420 + i as i32 * 37;
        let lon = 85_455_940 - i as i32 * 53;
        b.data(
            0,
            &[
                &t.to_le_bytes()[..],
                &(1_700_000_000_000_000 + t).to_le_bytes(),
                &lat.to_le_bytes(),
                &lon.to_le_bytes(),
                &488_000i32.to_le_bytes(),
                &[3],
            ]
            .concat(),
        );
    }
    let path = dir.join(format!("{STEM}.ulg"));
    std::fs::write(&path, b.bytes()).unwrap();
    path
}

/// Reads `FILE` as `KIND` with Python's own parsers and prints what it holds as JSON:
/// `xml`, every text and attribute value of every element; `html`, the text between
/// tags (character references resolved); `json`, the document; `jsonl`, one document
/// per line; `mcap`, every schema and message of a JSON MCAP file by channel.
const READ: &str = r#"
import json, sys
kind, path = sys.argv[1], sys.argv[2]
if kind == 'xml':
    import xml.etree.ElementTree as ET
    out = []
    for el in ET.parse(path).getroot().iter():
        out.extend(t for t in [el.text, el.tail, *el.attrib.values()] if t and t.strip())
elif kind == 'html':
    from html.parser import HTMLParser
    class Texts(HTMLParser):
        def __init__(self):
            super().__init__(convert_charrefs=True)
            self.out = []
        def handle_data(self, data):
            self.out.append(data)
        def handle_starttag(self, tag, attrs):
            self.out.extend(v for _, v in attrs if v)
    p = Texts()
    with open(path, encoding='utf-8') as f:
        p.feed(f.read())
    p.close()
    out = p.out
elif kind == 'json':
    with open(path, encoding='utf-8') as f:
        out = json.load(f)
elif kind == 'jsonl':
    with open(path, encoding='utf-8') as f:
        out = [json.loads(line) for line in f]
elif kind == 'mcap':
    from mcap.reader import make_reader
    out = {}
    with open(path, 'rb') as f:
        for schema, channel, message in make_reader(f).iter_messages():
            c = out.setdefault(channel.topic, {'schema': json.loads(schema.data), 'messages': []})
            c['messages'].append(json.loads(message.data))
print(json.dumps(out))
"#;

fn read(kind: &str, path: &Path) -> Json {
    let out = common::python([
        OsStr::new("-c"),
        OsStr::new(READ),
        OsStr::new(kind),
        path.as_os_str(),
    ]);
    serde_json::from_slice(&out).expect("the reader's JSON")
}

/// The strings of a read document.
fn texts(doc: &Json) -> Vec<&str> {
    doc.as_array()
        .expect("a list of texts")
        .iter()
        .map(|t| t.as_str().unwrap())
        .collect()
}

fn run(args: &[&OsStr]) -> String {
    common::ulog_ok(args)
}

/// The texts of a read document but numbers (a plot's coordinates) and colours, trimmed.
fn words(doc: &Json) -> Vec<&str> {
    texts(doc)
        .into_iter()
        .map(str::trim)
        .filter(|t| {
            !t.starts_with('#') && !t.chars().all(|c| c.is_ascii_digit() || " .,-".contains(c))
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs python3 (with pyulog, pip install pyulog==1.3.0): reads the files with its parsers"
)]
fn kml_gpx_and_svg_parse_as_xml_and_hold_the_text() {
    let dir = common::scratch("text-xml");
    let log = hostile_log(&dir);
    let (kml, gpx, svg) = (dir.join("t.kml"), dir.join("t.gpx"), dir.join("t.svg"));
    run(&[
        "kml".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        kml.as_os_str(),
    ]);
    run(&[
        "kml".as_ref(),
        "--gpx".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        gpx.as_os_str(),
    ]);
    run(&[
        "plot".as_ref(),
        log.as_os_str(),
        "vehicle_gps_position.lat".as_ref(),
        "-o".as_ref(),
        svg.as_os_str(),
    ]);
    // The track's name, the document's and the GPX track's: the log's stem.
    for path in [&kml, &gpx] {
        let doc = read("xml", path);
        let words = words(&doc);
        assert!(
            words.contains(&shown(STEM).as_str()),
            "{}: {words:?}",
            path.display()
        );
    }
    // The caption (the file name), the logged error and the parameter change.
    let doc = read("xml", &svg);
    let words = words(&doc);
    for want in [
        shown(&format!("{STEM}.ulg")),
        shown(MESSAGE),
        format!("{PARAM}=2"),
    ] {
        assert!(words.contains(&want.as_str()), "{want:?} in {words:?}");
    }
}

/// The report's cells, read back with Python's `html.parser`.
#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs python3 (with pyulog, pip install pyulog==1.3.0): reads the files with its parsers"
)]
fn the_report_holds_the_text_as_html_reads_it() {
    let dir = common::scratch("text-html");
    let log = hostile_log(&dir);
    let page = dir.join("t.html");
    run(&[
        "report".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        page.as_os_str(),
    ]);
    let raw = std::fs::read_to_string(&page).unwrap();
    let bad: Vec<char> = raw
        .chars()
        .filter(|&c| shown(&c.to_string()) != c.to_string())
        .collect();
    assert!(bad.is_empty(), "characters HTML cannot hold: {bad:?}");
    let doc = read("html", &page);
    let texts = texts(&doc);
    for want in [
        format!("{}.ulg — flight report", shown(STEM)),
        shown(MESSAGE),
        shown(&long_message()),
        shown(HOSTILE),
        KEY.to_owned(),
        PARAM.to_owned(),
    ] {
        assert!(
            texts.contains(&want.as_str()),
            "{want:?} not in the page's texts"
        );
    }
}

/// The report in headless Chromium (`scripts/report_check.js`): no console error, and
/// the title and the cells read back.
#[test]
#[cfg_attr(
    not(chromium),
    ignore = "needs /usr/bin/chromium with playwright-core in target/node (.ci/run installs \
              both)"
)]
fn the_report_holds_the_text_as_chromium_reads_it() {
    let dir = common::scratch("text-chromium");
    let log = hostile_log(&dir);
    let page = dir.join("t.html");
    run(&[
        "report".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        page.as_os_str(),
    ]);
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/report_check.js");
    let out = std::process::Command::new("node")
        .arg(script)
        .arg(&page)
        .arg("")
        .env("NODE_PATH", env!("ULOG_TESTS_NODE_PATH"))
        .output()
        .expect("run node");
    assert!(
        out.status.success(),
        "report_check.js failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Json = serde_json::from_slice(&out.stdout).expect("the script's JSON");
    assert_eq!(r["errors"], serde_json::json!([]), "console errors");
    assert_eq!(r["title"], format!("{}.ulg — flight report", shown(STEM)));
    let cells: Vec<&str> = texts(&r["cells"]);
    for want in [
        shown(MESSAGE),
        shown(&long_message()),
        shown(HOSTILE),
        KEY.to_owned(),
        PARAM.to_owned(),
    ] {
        assert!(cells.contains(&want.as_str()), "{want:?} in {cells:?}");
    }
}

#[test]
#[cfg_attr(
    not(pyulog),
    ignore = "needs python3 (with pyulog, pip install pyulog==1.3.0): reads the files with its parsers"
)]
fn json_outputs_parse_and_hold_the_text_exactly() {
    let dir = common::scratch("text-json");
    let log = hostile_log(&dir);
    let file = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let quoted = |s: &str| serde_json::to_string(s).unwrap();

    let info = run(&["info".as_ref(), "--json".as_ref(), log.as_os_str()]);
    let info = read("json", &file("info.json", info));
    assert_eq!(info["info"]["ver_hw"], HOSTILE);
    assert_eq!(info["info"][KEY], HOSTILE);

    // `check` exits 1 for the log's damage (no flag bits): its JSON is what counts.
    let check = common::ulog(["check".as_ref(), "--json".as_ref(), log.as_os_str()]);
    let check = read(
        "json",
        &file("check.json", String::from_utf8(check.stdout).unwrap()),
    );
    assert_eq!(check["files"][0]["file"], log.to_str().unwrap());

    let dump = run(&["dump".as_ref(), "--json".as_ref(), log.as_os_str()]);
    let dump = read("jsonl", &file("dump.jsonl", dump)).to_string();
    for want in [HOSTILE, MESSAGE, &long_message(), &topic(), KEY, PARAM] {
        assert!(dump.contains(&quoted(want)), "{want:?} not in dump --json");
    }

    let geojson = dir.join("t.geojson");
    run(&[
        "kml".as_ref(),
        "--geojson".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        geojson.as_os_str(),
    ]);
    assert_eq!(read("json", &geojson)["type"], "FeatureCollection");

    // A per-log export's metadata: `char[N]` text one character per byte.
    let export = dir.join("export");
    run(&[
        "parquet".as_ref(),
        "--per-log".as_ref(),
        "-q".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        export.as_os_str(),
    ]);
    let folder = std::fs::read_dir(&export)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let meta = read("json", &folder.join("metadata.json"));
    assert_eq!(meta["info"]["ver_hw"], latin1(HOSTILE));
    assert_eq!(meta["info"][KEY], latin1(HOSTILE));
    assert_eq!(meta["parameters"][PARAM], 1);
    let logged: Vec<&Json> = meta["logged_messages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| &m["text"])
        .collect();
    assert_eq!(
        logged,
        [
            &Json::from(latin1(MESSAGE)),
            &Json::from(latin1(&long_message()))
        ]
    );
    let topics: Vec<&Json> = meta["topics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| &t["name"])
        .collect();
    assert!(topics.contains(&&Json::from(topic())), "{topics:?}");
}

/// MCAP's JSON messages and schemas, read with Foxglove's reader.
#[test]
#[cfg_attr(
    not(mcap_readers),
    ignore = "needs Foxglove's MCAP readers and jsonschema: pip install mcap mcap-ros2-support rosbags jsonschema"
)]
fn mcap_json_messages_parse_and_hold_the_text_exactly() {
    let dir = common::scratch("text-mcap");
    let log = hostile_log(&dir);
    let out = dir.join("t.mcap");
    run(&[
        "mcap".as_ref(),
        "-q".as_ref(),
        "--encoding".as_ref(),
        "json".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let channels = read("mcap", &out);
    let logged: Vec<&Json> = channels["/rosout"]["messages"]
        .as_array()
        .expect("/rosout")
        .iter()
        .map(|m| &m["msg"])
        .collect();
    assert_eq!(logged, [&Json::from(MESSAGE), &Json::from(long_message())]);
    let names: Vec<&Json> = channels["/ulog/parameters"]["messages"]
        .as_array()
        .expect("/ulog/parameters")
        .iter()
        .map(|m| &m["name"])
        .collect();
    assert_eq!(names, [&Json::from(PARAM), &Json::from(PARAM)]);
}
