//! `ULogMessage::visit_fields` as the derive generates it: leaf paths as the reader
//! names columns (nested, arrays element by element, `char[N]` whole, padding left
//! out), with the runtime crate renamed and no prelude.
#![deny(warnings)]
#![no_implicit_prelude]

extern crate std;

use ::renamed_ulog::typed::CharArray;
use ::renamed_ulog::ULogMessage;
use std::borrow::ToOwned;
use std::iter::{IntoIterator, Iterator};
use std::string::String;
use std::vec::Vec;
use std::{assert_eq, format, vec};

#[derive(ULogMessage)]
#[ulog(crate = "::renamed_ulog")]
struct Report {
    rpm: i32,
    _padding0: [u8; 4],
}

#[derive(ULogMessage)]
#[ulog(crate = "::renamed_ulog", name = "esc_status")]
struct Esc {
    timestamp: u64,
    #[ulog(name = "esc")]
    reports: [Report; 2],
    label: CharArray<4>,
    #[ulog(char)]
    code: [u8; 2],
    #[ulog(char)]
    one: u8,
    flags: [bool; 2],
    #[ulog(name = "type")]
    kind: u8,
}

#[test]
fn paths_and_values() {
    let esc = Esc {
        timestamp: 7,
        reports: [
            Report {
                rpm: -1,
                _padding0: [0; 4],
            },
            Report {
                rpm: 2,
                _padding0: [0; 4],
            },
        ],
        label: CharArray::from_str_truncated("ab"),
        code: *b"xy",
        one: b'z',
        flags: [true, false],
        kind: 3,
    };
    let mut seen: Vec<String> = Vec::new();
    esc.visit_fields(&mut |path, value| seen.push(format!("{path}={value:?}")));
    let expected: Vec<String> = vec![
        "timestamp=U64(7)",
        "esc[0].rpm=I32(-1)",
        "esc[1].rpm=I32(2)",
        "label=Str(\"ab\\0\\0\")",
        "code=Str(\"xy\")",
        "one=Char(122)",
        "flags[0]=Bool(true)",
        "flags[1]=Bool(false)",
        "type=U8(3)",
    ]
    .into_iter()
    .map(|s: &str| s.to_owned())
    .collect();
    assert_eq!(seen, expected);
}
