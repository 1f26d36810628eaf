//! `ulog codegen`: the bindings it writes are current, compile, equal the macro's, and
//! cover every format of every corpus log.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use ulog_core::typed::{WireField, Writable};
use ulog_core::{ulog_module, ULogMessage};
use ulog_core::{LogWriter, ULog};

/// The checked-in output of `ulog codegen examples/data/reference.ulg` (not reformatted,
/// so that it stays byte-identical to fresh output).
#[rustfmt::skip]
#[path = "generated/reference.rs"]
mod generated;

ulog_module!(mod from_macro = "../examples/data/reference.ulg");

fn reference_log() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/data/reference.ulg")
}

#[test]
fn checked_in_bindings_are_current() {
    let fresh = common::ulog_ok(["codegen".as_ref(), reference_log().as_os_str()]);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/generated/reference.rs");
    if std::env::var_os("ULOG_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let checked_in = std::fs::read_to_string(&path).unwrap();
    assert!(
        checked_in == fresh,
        "tests/generated/reference.rs is stale: re-run with ULOG_BLESS=1"
    );
}

/// Writes rows through the generated binding `G` and reads them back with both `G` and
/// the macro's `M`: same name, same layout, same values.
fn round_trip<G, M>(rows: &[G])
where
    G: ULogMessage + WireField<Writability = Writable> + core::fmt::Debug,
    M: ULogMessage + core::fmt::Debug,
{
    assert_eq!(G::NAME, M::NAME);
    assert_eq!(G::layout(), M::layout());
    let mut w = LogWriter::new(Vec::new(), 0).unwrap();
    let h = w.subscribe::<G>(0).unwrap();
    let mut data = w.start_data().unwrap();
    for r in rows {
        data.write(&h, r).unwrap();
    }
    let bytes = data.finish().unwrap();
    let log = ULog::parse(&bytes).unwrap();
    let g = log.read::<G>(0).expect("generated binding fits");
    let m = log.read::<M>(0).expect("macro binding fits");
    assert_eq!(g.len(), rows.len());
    assert_eq!(m.len(), rows.len());
    for ((a, b), r) in g.iter().zip(m.iter()).zip(rows) {
        let (a, b) = (a.unwrap(), b.unwrap());
        assert_eq!(format!("{a:?}"), format!("{r:?}"));
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
    }
}

#[test]
fn checked_in_bindings_compile_and_equal_the_macro_s() {
    let rows: Vec<generated::VehicleLocalPosition> = (0..50u16)
        .map(|i| generated::VehicleLocalPosition {
            timestamp: 1_000 * u64::from(i),
            x: f32::from(i),
            y: -f32::from(i) / 3.0,
            z: 0.5,
            vx: 1.0,
            vy: 2.0,
            vz: -3.0,
            xy_valid: i % 2 == 0,
            ..Default::default()
        })
        .collect();
    round_trip::<_, from_macro::VehicleLocalPosition>(&rows);
    let esc = generated::EscStatus {
        timestamp: 7,
        esc_count: 2,
        esc: [
            generated::EscReport {
                timestamp: 5,
                esc_rpm: -1200,
                esc_voltage: 15.5,
            },
            generated::EscReport {
                timestamp: 6,
                esc_rpm: 1300,
                esc_voltage: 15.25,
            },
        ],
        ..Default::default()
    };
    round_trip::<_, from_macro::EscStatus>(&[esc, esc]);
    round_trip::<_, from_macro::BatteryStatus>(&[generated::BatteryStatus {
        timestamp: 9,
        voltage_v: 16.1,
        remaining: 0.75,
        cell_count: 4,
        ..Default::default()
    }]);

    // Both visit the same bindings in the same order, one per format of the log.
    struct Names(Vec<&'static str>);
    impl ulog_core::typed::BindingVisitor for Names {
        fn visit<T: ULogMessage>(&mut self) {
            self.0.push(T::NAME);
        }
    }
    let (mut a, mut b) = (Names(Vec::new()), Names(Vec::new()));
    generated::visit_bindings(&mut a);
    from_macro::visit_bindings(&mut b);
    assert_eq!(a.0, b.0);
    let bytes = std::fs::read(reference_log()).unwrap();
    let log = ULog::parse(&bytes).unwrap();
    assert_eq!(a.0.len(), log.formats().len());
}

#[test]
fn writes_to_a_file_and_names_the_runtime_crate() {
    let out = common::scratch("codegen_out").join("bindings.rs");
    let printed = common::ulog_ok([
        "codegen".as_ref(),
        reference_log().as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--crate".as_ref(),
        "::my_ulog".as_ref(),
    ]);
    assert!(printed.is_empty());
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("::my_ulog::typed::__private"));
    assert!(text.contains("::my_ulog::typed::BindingVisitor"));
    assert!(!text.contains("::ulog_core::"));
}

/// Every format of every corpus log that the reader can lay out gets a struct whose
/// documentation shows the format exactly as the reader reads it.
#[test]
fn every_format_of_every_corpus_log() {
    let dir = common::corpus();
    let mut structs = 0;
    for (stem, path) in common::corpus_logs(&dir) {
        let text = common::ulog_ok(["codegen".as_ref(), path.as_os_str()]);
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap();
        // Each struct's first doc line: "The ULog message `name`: `FORMAT`".
        let documented: BTreeSet<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("/// The ULog message `"))
            .filter_map(|l| l.split_once("`: `"))
            .filter_map(|(_, f)| f.strip_suffix('`'))
            .collect();
        for format in log.formats() {
            let canonical = format.to_string();
            let laid_out = log
                .topics()
                .find(|t| t.name() == format.name)
                .map_or(true, |t| t.layout().is_ok());
            if laid_out {
                assert!(
                    documented.contains(canonical.as_str()),
                    "{stem}: no binding for `{canonical}`"
                );
            }
        }
        let count = text.matches("\npub struct ").count();
        assert!(count >= log.formats().len() / 2, "{stem}: {count} structs");
        structs += count;
    }
    eprintln!("{structs} structs generated");
}

#[test]
fn refused_and_missing_files() {
    let dir = common::scratch("codegen_refused");
    let bad = dir.join("bad.ulg");
    std::fs::write(&bad, b"not a log").unwrap();
    let out = common::ulog(["codegen".as_ref(), bad.as_os_str()]);
    assert_eq!(out.status.code(), Some(4));
    let out = common::ulog(["codegen".as_ref(), dir.join("none.ulg").as_os_str()]);
    assert_eq!(out.status.code(), Some(3));
}

/// Formats that cannot be laid out are listed (in the header and on stderr) and not
/// counted among the bound ones; the others are bound.
#[test]
fn formats_that_cannot_be_bound_are_listed_and_not_counted() {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.format("ok:uint64_t timestamp;");
    b.format("broken:uint64_t timestamp;missing m;");
    b.format("uses_broken:uint64_t timestamp;broken[2] b;");
    let path = common::scratch("codegen_skipped").join("skipped.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let out = common::ulog(["codegen".as_ref(), path.as_os_str()]);
    assert!(out.status.success(), "{out:?}");
    let source = String::from_utf8(out.stdout).unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        source.starts_with("// Bindings for the 1 format of `skipped.ulg`"),
        "{source}"
    );
    assert!(source.contains("pub struct Ok "), "{source}");
    for name in ["broken", "uses_broken"] {
        let line = format!("// Not bound: format `{name}`:");
        assert!(source.contains(&line), "{name}: {source}");
        assert!(
            stderr.contains(&format!("not bound: format `{name}`")),
            "{stderr}"
        );
    }
}

/// Formats defined after data are bound; every format the command cannot bind is
/// named on stderr with why, the text that does not parse at its offset in the file.
#[test]
fn formats_after_data_are_bound_and_every_other_is_named() {
    let mut b = ulog_core::testing::LogBuilder::new(1, 0);
    b.format("first:uint64_t timestamp;");
    b.subscribe(0, 0, "first");
    b.data(0, &1u64.to_le_bytes());
    b.format("later:uint64_t timestamp;uint8_t x;");
    b.format("odd:uint64_t timestamp;float32 x;");
    let bad_at = b.bytes().len();
    b.format("no colon here");
    let invalid_at = b.bytes().len() + 3;
    b.format("bad name:uint8_t x;");
    let path = common::scratch("codegen_after_data").join("after_data.ulg");
    std::fs::write(&path, b.bytes()).unwrap();
    let out = common::ulog(["codegen".as_ref(), path.as_os_str()]);
    assert!(out.status.success(), "{out:?}");
    let source = String::from_utf8(out.stdout).unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        source.starts_with("// Bindings for the 2 formats of `after_data.ulg`"),
        "{source}"
    );
    assert!(source.contains("pub struct Later "), "{source}");
    assert!(
        stderr.contains("not bound: format `odd`: unknown type `float32` (did you mean `float`?)"),
        "{stderr}"
    );
    assert!(
        source.contains("// Not bound: format `odd`: unknown type `float32`"),
        "{source}"
    );
    assert!(
        stderr.contains(&format!(
            "not bound: the format at byte {bad_at}: malformed 'F' message"
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!(
            "not bound: the format at byte {invalid_at}: invalid format definition: character ' '"
        )),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 3, "{stderr}");
    assert!(
        source.contains("// Not bound: a format text that does not parse: character ' '"),
        "{source}"
    );

    // `--messages` picks formats (with the ones they nest); a name the log does not
    // have is refused with the nearest one.
    let out = common::ulog([
        "codegen".as_ref(),
        path.as_os_str(),
        "-m".as_ref(),
        "later".as_ref(),
    ]);
    assert!(out.status.success(), "{out:?}");
    let source = String::from_utf8(out.stdout).unwrap();
    assert!(
        source.starts_with("// Bindings for the 1 format of"),
        "{source}"
    );
    assert!(out.stderr.is_empty(), "{:?}", out.stderr);
    let out = common::ulog([
        "codegen".as_ref(),
        path.as_os_str(),
        "-m".as_ref(),
        "latr".as_ref(),
    ]);
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(!out.status.success());
    assert!(
        stderr.contains("the log has no format `latr` (did you mean `later`?)"),
        "{stderr}"
    );
}
