//! `ulog_module!` and `ulog codegen` (one generator, `ulog-codegen`) see every format
//! the reader sees, anywhere in the file, and bind it or name it with why.

use std::collections::BTreeSet;
use std::path::Path;

use ulog_core::read::FindingKind;
use ulog_core::typed::BindingVisitor;
use ulog_core::{ulog_module, ULog, ULogMessage};
use ulog_tests::module_logs;

// Nothing of this log may be left out: `deny` makes a format not bound an error.
ulog_module!(unbound = deny; mod after_data = "logs/formats_after_data.ulg");

/// On every corpus log, the formats the generator binds or names by name are the
/// formats `ULog::parse` gives, and the format texts it names without binding because
/// they do not parse are the ones the reader has a finding for (`InvalidFormat`, or a
/// malformed `F` message), at the same offsets.
#[test]
fn the_generator_sees_every_format_the_reader_sees() {
    let files = ulog_tests::corpus_files();
    assert!(!files.is_empty());
    let mut formats = 0;
    for path in files {
        let stem = ulog_tests::stem(&path);
        let bytes = std::fs::read(&path).unwrap();
        let log = ULog::parse(&bytes).unwrap_or_else(|e| panic!("{stem}: {e}"));
        let generated =
            ulog_codegen::bindings_for_log(&bytes, &stem, &ulog_codegen::Options::default())
                .unwrap_or_else(|e| panic!("{stem}: {e}"));
        assert!(
            generated.problems.is_empty(),
            "{stem}: {:?}",
            generated.problems
        );
        // Where the reader says a format text starts that it could not read.
        let invalid: BTreeSet<usize> = log
            .findings()
            .iter()
            .filter_map(|f| {
                let at = usize::try_from(f.offset).unwrap();
                match f.kind {
                    FindingKind::InvalidFormat(_) => Some(at),
                    FindingKind::Malformed { msg_type: b'F', .. } => Some(at + 3),
                    _ => None,
                }
            })
            .collect();
        let (unparsed, named): (Vec<_>, Vec<_>) = generated
            .unbound
            .iter()
            .partition(|u| invalid.contains(&u.offset));
        let unparsed: BTreeSet<usize> = unparsed.iter().map(|u| u.offset).collect();
        assert_eq!(unparsed, invalid, "{stem}: texts that do not parse");
        let mut seen: BTreeSet<&str> = generated.bound.iter().map(String::as_str).collect();
        for u in &named {
            assert!(!u.reason.is_empty(), "{stem}: {u}");
            let name = u.name.as_deref().unwrap_or_else(|| panic!("{stem}: {u}"));
            assert!(seen.insert(name), "{stem}: `{name}` bound and not bound");
        }
        let read: BTreeSet<&str> = log.formats().iter().map(|f| f.name.as_str()).collect();
        assert_eq!(seen, read, "{stem}");
        formats += read.len();
    }
    assert!(formats > 0);
}

#[test]
fn the_committed_log_is_the_written_one() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("logs/formats_after_data.ulg");
    let written = module_logs::formats_after_data();
    if std::env::var_os("ULOG_BLESS").is_some() {
        std::fs::write(&path, &written).unwrap();
    }
    assert_eq!(
        std::fs::read(&path).unwrap(),
        written,
        "rewrite with ULOG_BLESS=1"
    );
}

/// The formats defined after data are bound by the macro, and their rows read through
/// the bindings as the reader's generic access reads them.
#[test]
fn formats_after_data_are_bound() {
    let bytes = module_logs::formats_after_data();
    let log = ULog::parse(&bytes).unwrap();
    // The formats come after the first data message.
    let first_data = log.topic("first", 0).unwrap().len();
    assert_eq!(first_data, 1);

    struct Names(Vec<&'static str>);
    impl BindingVisitor for Names {
        fn visit<T: ULogMessage>(&mut self) {
            self.0.push(T::NAME);
        }
    }
    let mut names = Names(Vec::new());
    after_data::visit_bindings(&mut names);
    let read: Vec<&str> = log.formats().iter().map(|f| f.name.as_str()).collect();
    let mut bound = names.0.clone();
    bound.sort_unstable();
    assert_eq!(bound, read);

    let later: Vec<after_data::Later> = log
        .read::<after_data::Later>(0)
        .unwrap()
        .iter()
        .collect::<Result<_, _>>()
        .unwrap();
    let topic = log.topic("later", 0).unwrap();
    let y = topic.field("y").unwrap();
    let generic: Vec<f64> = topic.payloads().map(|p| y.read_f64(p).unwrap()).collect();
    assert_eq!(later.len(), generic.len());
    for (row, y) in later.iter().zip(&generic) {
        assert_eq!(f64::from(row.y), *y);
    }
    let pairs: Vec<after_data::LaterPair> = log
        .read::<after_data::LaterPair>(0)
        .unwrap()
        .iter()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(pairs.len(), 3);
    for (p, l) in pairs.iter().zip(&later) {
        assert_eq!(p.pair[0], *l);
        assert_eq!(p.pair[1].timestamp, l.timestamp + 1);
    }
}

/// The generator lists every format it cannot bind with why, in file order.
#[test]
fn formats_that_cannot_be_bound_are_named_with_why() {
    let bytes = module_logs::unbindable();
    let generated =
        ulog_codegen::bindings_for_log(&bytes, "unbindable.ulg", &Default::default()).unwrap();
    assert_eq!(generated.bound, ["ok"]);
    let named: Vec<(Option<&str>, &str)> = generated
        .unbound
        .iter()
        .map(|u| (u.name.as_deref(), u.reason.as_str()))
        .collect();
    assert_eq!(named.len(), 3, "{named:?}");
    assert_eq!(named[0].0, Some("odd"));
    assert!(named[0].1.contains("float32"), "{named:?}");
    assert_eq!(named[1].0, Some("orphan"));
    assert!(named[1].1.contains("nowhere"), "{named:?}");
    assert_eq!(named[2].0, Some("clash"));
    assert!(named[2].1.contains("one Rust name"), "{named:?}");
    for u in &generated.unbound {
        assert!(
            generated.source.contains(&format!("// Not bound: {u}")),
            "{}",
            generated.source
        );
    }
}
