//! Plans: exact, mapped, mismatched; borrowed views; encode → decode round trips over
//! every field type, arrays, nesting and padding.

use proptest::prelude::*;
use ulog_core::typed::le::{U16, U32};
use ulog_core::typed::{CharArray, DecodeErrorKind, DifferenceKind, Plan, PlanKind};
use ulog_core::ULogMessage;
use ulog_format::{Format, Layout};

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct Point {
    x: f32,
    flag: bool,
    _padding0: [u8; 3],
}

#[derive(ULogMessage, Debug, Clone, Copy, PartialEq)]
struct AllTypes {
    timestamp: u64,
    a: u8,
    b: i8,
    c: u16,
    d: i16,
    e: u32,
    f: i32,
    g: i64,
    h: f32,
    i: f64,
    j: bool,
    k: CharArray<5>,
    #[ulog(char)]
    l: [u8; 2],
    m: [u16; 3],
    n: [bool; 2],
    _padding0: [u8; 2],
    p: Point,
    q: [Point; 2],
    _padding1: [u8; 4],
}

fn layout(texts: &[&str], name: &str) -> Layout {
    let formats: Vec<Format> = texts.iter().map(|t| Format::parse(t).unwrap()).collect();
    Layout::resolve(name, &formats).unwrap()
}

fn point() -> impl Strategy<Value = Point> {
    (any::<f32>(), any::<bool>()).prop_map(|(x, flag)| Point {
        x,
        flag,
        _padding0: [0; 3],
    })
}

prop_compose! {
    fn all_types()(
        (timestamp, a, b, c, d, e, f, g) in (any::<u64>(), any::<u8>(), any::<i8>(), any::<u16>(), any::<i16>(), any::<u32>(), any::<i32>(), any::<i64>()),
        (h, i, j) in (any::<f32>(), any::<f64>(), any::<bool>()),
        (k, l, m, n) in (any::<[u8; 5]>(), any::<[u8; 2]>(), any::<[u16; 3]>(), any::<[bool; 2]>()),
        p in point(),
        q in [point(), point()],
    ) -> AllTypes {
        AllTypes { timestamp, a, b, c, d, e, f, g, h, i, j, k: CharArray(k), l, m, n, _padding0: [0; 2], p, q, _padding1: [0; 4] }
    }
}

fn same_bits(x: &AllTypes, y: &AllTypes) -> bool {
    // Floats compared by bits, so that NaN round trips count.
    x.encode() == y.encode()
}

proptest! {
    #[test]
    fn encode_then_decode_gives_back_the_value(v in all_types()) {
        let plan = Plan::<AllTypes>::new(AllTypes::layout()).unwrap();
        prop_assert_eq!(plan.kind(), PlanKind::Exact);
        let bytes = v.encode();
        prop_assert_eq!(bytes.len(), AllTypes::layout().min_size());
        let back = plan.decode(&bytes).unwrap();
        prop_assert!(same_bits(&back, &v));
        // With the trailing padding written too.
        let mut full = bytes.clone();
        full.extend_from_slice(&[0; 4]);
        prop_assert!(same_bits(&plan.decode(&full).unwrap(), &v));
        // Any other length is an error, never garbage.
        prop_assert!(plan.decode(&full[..full.len() - 1]).is_err());
    }

    #[test]
    fn a_shuffled_format_decodes_the_same(v in all_types()) {
        // The same fields in reverse order, with an extra field: a mapped plan.
        let own = AllTypes::schema();
        let mut shuffled = own.format().clone();
        shuffled.fields.reverse();
        shuffled.fields.retain(|f| !f.is_padding());
        let mut texts: Vec<String> = own.formats()[..own.formats().len() - 1].iter().map(|f| f.to_string()).collect();
        let text = format!("{shuffled}uint32_t extra;");
        texts.push(text);
        let refs: Vec<&str> = texts.iter().map(|s| s.as_str()).collect();
        let file = layout(&refs, "all_types");
        let plan = Plan::<AllTypes>::new(&file).unwrap();
        prop_assert_eq!(plan.kind(), PlanKind::Mapped);
        // Write the file's payload by placing each leaf of `v` at the file's offset.
        let mine = v.encode();
        let mut payload = vec![0u8; file.size()];
        for leaf in AllTypes::layout().leaves().iter().filter(|l| l.kind != ulog_format::LeafKind::Padding) {
            let there = file.leaves().iter().find(|f| f.path == leaf.path).unwrap();
            let n = leaf.count * leaf.ty.size();
            payload[there.offset..there.offset + n].copy_from_slice(&mine[leaf.offset..leaf.offset + n]);
        }
        prop_assert!(same_bits(&plan.decode(&payload).unwrap(), &v));
    }
}

#[test]
fn every_difference_is_listed_with_both_formats() {
    let file = layout(
        &[
            "point:float x;uint8_t flag;uint8_t[3] _padding0;",
            "all_types:uint64_t timestamp;float a;int8_t b;uint16_t[4] m;point p;uint8_t q;",
        ],
        "all_types",
    );
    let err = Plan::<AllTypes>::new(&file).unwrap_err();
    let kinds: Vec<(&str, &DifferenceKind)> = err
        .differences
        .iter()
        .map(|d| (d.path.as_str(), &d.kind))
        .collect();
    assert!(kinds.contains(&(
        "a",
        &DifferenceKind::Type {
            expected: "uint8_t".into(),
            found: "float".into()
        }
    )));
    assert!(kinds
        .iter()
        .any(|(p, k)| *p == "c" && matches!(k, DifferenceKind::MissingField { .. })));
    assert!(kinds.contains(&(
        "m",
        &DifferenceKind::ArrayLength {
            expected: Some(3),
            found: Some(4)
        }
    )));
    assert!(kinds.contains(&(
        "p.flag",
        &DifferenceKind::Type {
            expected: "bool".into(),
            found: "uint8_t".into()
        }
    )));
    // A nested format that differs is no difference of its own: the differences
    // inside it are listed, with their paths (`p.flag` above).
    assert!(!kinds.iter().any(|(p, _)| *p == "p"), "{kinds:?}");
    assert!(kinds.contains(&(
        "q",
        &DifferenceKind::ArrayLength {
            expected: Some(2),
            found: None
        }
    )));
    let text = err.to_string();
    assert!(
        text.starts_with("the log's format of `all_types` does not fit binding `AllTypes`"),
        "{text}"
    );
    assert!(
        text.contains("all_types:uint64_t timestamp;float a;"),
        "{text}"
    );
    assert!(
        text.contains("all_types:uint64_t timestamp;uint8_t a;int8_t b;"),
        "{text}"
    );
}

/// A binding whose memory is its payload: borrowed without a copy.
#[derive(ULogMessage, Debug, PartialEq)]
#[ulog(view)]
#[repr(C)]
struct Raw {
    id: u8,
    count: U16,
    total: U32,
    name: CharArray<3>,
    _padding0: [u8; 2],
}

#[test]
fn views_borrow_exact_full_payloads() {
    let plan = Plan::<Raw>::new(Raw::layout()).unwrap();
    let bytes = [7u8, 1, 2, 3, 0, 0, 0, b'a', b'b', b'c', 9, 9];
    let view = plan.view(&bytes).unwrap();
    assert_eq!(
        (view.id, view.count.get(), view.total.get()),
        (7, 0x0201, 3)
    );
    assert_eq!(view.name.as_str(), Ok("abc"));
    assert!(std::ptr::eq(
        view as *const Raw as *const u8,
        bytes.as_ptr()
    ));
    // Copies agree with views.
    assert_eq!(plan.decode(&bytes).unwrap().total, view.total);
    // Trailing padding left out: decodes, cannot be borrowed.
    assert_eq!(
        plan.view(&bytes[..10]).unwrap_err().kind,
        DecodeErrorKind::ViewNeedsLongerPayload { needed: 12 }
    );
    assert_eq!(plan.decode(&bytes[..10]).unwrap().name, view.name);
    // Another layout: no view.
    let other = layout(
        &["raw:uint16_t count;uint8_t id;uint32_t total;char[3] name;"],
        "raw",
    );
    let mapped = Plan::<Raw>::new(&other).unwrap();
    assert!(matches!(
        mapped.view(&[0; 10]).unwrap_err().kind,
        DecodeErrorKind::ViewNeedsExactLayout { why } if why.contains("`id`")
    ),);
}

#[test]
fn char_arrays_decode_as_text() {
    #[derive(ULogMessage, Debug)]
    struct Named {
        id: u8,
        name: CharArray<6>,
        #[ulog(char)]
        raw: [u8; 3],
    }
    let format = Format::parse("named:uint8_t id;char[6] name;char[3] raw;").unwrap();
    assert_eq!(Named::schema().format(), &format);
    let layout = Layout::resolve("named", &[format][..]).unwrap();
    let n = Plan::<Named>::new(&layout)
        .unwrap()
        .decode(b"\x07PX4\0\0\0abc")
        .unwrap();
    assert_eq!((n.id, n.name.as_str(), &n.raw), (7, Ok("PX4"), b"abc"));
}
