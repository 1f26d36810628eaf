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

/// Bindings of known formats get `Debug` and `PartialEq` from one walk of their
/// schema (not from `#[derive]`, which compiles a body per field and binding): the
/// same text and the same answers as the derives give a struct of the same fields.
mod derives {
    ulog_core::ulog_structs!(
        "derive_outer:uint64_t timestamp;derive_inner[2] inner;char[3] text;bool ok;float f;double d;int8_t type;uint8_t self;int16_t[2] pair;char c;bool _padding1;uint8_t[1] _padding0;",
        "derive_inner:float x;int32_t y;"
    );

    /// The same fields with the derives, under the same names.
    mod mirror {
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct DeriveOuter {
            pub timestamp: u64,
            pub inner: [DeriveInner; 2],
            pub text: ulog_core::typed::CharArray<3>,
            pub ok: bool,
            pub f: f32,
            pub d: f64,
            pub r#type: i8,
            pub self_: u8,
            pub pair: [i16; 2],
            pub c: u8,
            pub _padding1: u8,
            pub _padding0: [u8; 1],
        }

        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct DeriveInner {
            pub x: f32,
            pub y: i32,
        }
    }

    fn mirrored(v: &DeriveOuter) -> mirror::DeriveOuter {
        let inner = v.inner.map(|i| mirror::DeriveInner { x: i.x, y: i.y });
        mirror::DeriveOuter {
            timestamp: v.timestamp,
            inner,
            text: v.text,
            ok: v.ok,
            f: v.f,
            d: v.d,
            r#type: v.r#type,
            self_: v.self_,
            pair: v.pair,
            c: v.c,
            _padding1: v._padding1,
            _padding0: v._padding0,
        }
    }

    fn values() -> Vec<DeriveOuter> {
        let base = DeriveOuter {
            timestamp: 1_700_000_000_123,
            inner: [
                DeriveInner { x: 1.5, y: -7 },
                DeriveInner {
                    x: -0.1,
                    y: i32::MAX,
                },
            ],
            text: ulog_core::typed::CharArray::from_bytes(*b"ab\0"),
            ok: true,
            f: 0.1,
            d: -2.5e-300,
            r#type: -128,
            self_: 255,
            pair: [i16::MIN, 3],
            c: b'x',
            _padding1: 0,
            _padding0: [0],
        };
        let mut out = vec![base, DeriveOuter::default()];
        let mut v = base;
        v.f = f32::NAN;
        out.push(v);
        v = base;
        v.f = -0.0;
        out.push(v);
        v = base;
        v.f = 0.0;
        out.push(v);
        v = base;
        v.d = f64::INFINITY;
        out.push(v);
        v = base;
        v.inner[1].y = 0;
        out.push(v);
        v = base;
        v.inner[0].x = f32::NAN;
        out.push(v);
        v = base;
        v.text = ulog_core::typed::CharArray::from_bytes(*b"abc");
        out.push(v);
        v = base;
        v.ok = false;
        out.push(v);
        v = base;
        v.pair[1] = 4;
        out.push(v);
        v = base;
        v.c = b'y';
        out.push(v);
        out
    }

    #[test]
    fn debug_prints_what_the_derive_prints() {
        for v in values() {
            let m = mirrored(&v);
            assert_eq!(format!("{v:?}"), format!("{m:?}"));
            assert_eq!(format!("{v:#?}"), format!("{m:#?}"));
            assert_eq!(format!("{:?}", v.inner[0]), format!("{:?}", m.inner[0]));
        }
        // The names are Rust's: the struct's, `self_` for `self`, `type` for `r#type`.
        let text = format!("{:?}", values()[0]);
        assert!(
            text.starts_with(
                "DeriveOuter { timestamp: 1700000000123, inner: [DeriveInner { x: 1.5,"
            ),
            "{text}"
        );
        assert!(text.contains(", type: -128, self_: 255, "), "{text}");
    }

    #[test]
    fn eq_answers_what_the_derive_answers() {
        let all = values();
        let mut differ = 0;
        for a in &all {
            for b in &all {
                let (ma, mb) = (mirrored(a), mirrored(b));
                assert_eq!(a == b, ma == mb, "{a:?} == {b:?}");
                assert_eq!(a != b, ma != mb);
                differ += usize::from(ma != mb);
            }
        }
        // NaN differs from itself; -0.0 equals 0.0 (the pair both ways).
        assert!(all[2] != all[2] && all[7] != all[7]);
        assert_eq!(all[3], all[4]);
        assert_eq!(all[4], all[3]);
        assert!(differ > all.len() * (all.len() - 2));
        #[allow(clippy::clone_on_copy)]
        let c = all[0].clone();
        assert_eq!(c, all[0]);
    }

    ulog_core::ulog_structs!(
        views;
        "derive_view:uint64_t timestamp;float f;bool ok;uint8_t[3] _padding0;"
    );

    /// A view's `ByteBool` compares by its byte, as its derive does (two true bools
    /// of other bytes differ); its fields print as numbers.
    #[test]
    fn views_compare_bools_by_their_byte() {
        use ulog_core::typed::{le, ByteBool};
        let view = |ok: u8| DeriveView {
            timestamp: le::U64::new(7),
            f: le::F32::new(0.5),
            ok: ByteBool(ok),
        };
        assert_eq!(view(1), view(1));
        assert_ne!(view(1), view(2));
        assert_ne!(view(0), view(1));
        assert_eq!(
            format!("{:?}", view(2)),
            "DeriveView { timestamp: 7, f: 0.5, ok: true }"
        );
    }
}
