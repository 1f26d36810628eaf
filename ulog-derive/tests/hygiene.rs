//! Generated code names nothing it was not given: it builds with the runtime crate
//! renamed (`renamed_ulog`, no `ulog_core` in scope), under `#![deny(warnings)]` and
//! `#![no_implicit_prelude]`.
#![deny(warnings)]
#![no_implicit_prelude]

extern crate std;

use ::renamed_ulog::typed::{le, Plan, PlanKind};
use ::renamed_ulog::{ULogMessage, ULogTopics};
use std::assert_eq;

/// A nested type.
#[derive(ULogMessage, std::fmt::Debug, std::cmp::PartialEq)]
#[ulog(crate = "::renamed_ulog")]
pub struct Inner {
    /// A value.
    pub a: i16,
    /// Padding in the middle.
    pub _padding0: [u8; 2],
    /// Text.
    pub name: ::renamed_ulog::typed::CharArray<4>,
}

/// The outer type.
#[derive(ULogMessage, std::fmt::Debug, std::cmp::PartialEq)]
#[ulog(crate = "::renamed_ulog", name = "outer_message")]
pub struct Outer {
    /// Time.
    pub timestamp: u64,
    /// Nested.
    pub inner: [Inner; 2],
    /// Flags.
    pub flags: [bool; 3],
    /// A renamed field.
    #[ulog(name = "type", alias = "kind")]
    pub ty: u8,
    /// Trailing padding.
    pub _padding1: [u8; 5],
}

/// Optional fields, a default and an alias.
#[derive(ULogMessage, std::fmt::Debug, std::cmp::PartialEq)]
#[ulog(crate = "::renamed_ulog", name = "outer_message")]
pub struct Optional {
    /// Time.
    pub timestamp: u64,
    /// Not in every log.
    pub inner: std::option::Option<[Inner; 2]>,
    /// A value when the log lacks it.
    #[ulog(default = 9)]
    pub missing: u8,
    /// A default of the type.
    #[ulog(default, alias = "kind")]
    pub r#type: u8,
}

/// A binding borrowed from payloads.
#[derive(ULogMessage, std::fmt::Debug)]
#[ulog(crate = "::renamed_ulog", name = "outer_view", view)]
#[repr(C)]
pub struct View {
    /// Time.
    pub timestamp: le::U64,
    /// A value.
    pub value: le::F32,
}

/// Two topics.
#[derive(ULogTopics, std::fmt::Debug)]
#[ulog(crate = "::renamed_ulog")]
pub enum Topics {
    /// One.
    Outer(Outer),
    /// Two.
    Inner(Inner),
}

::renamed_ulog::ulog_structs!(
    views;
    crate = ::renamed_ulog;
    "view_outer:uint64_t timestamp;view_inner[2] inner;bool ok;uint8_t[3] _padding0;",
    "view_inner:float x;int8_t type;uint8_t[3] _padding0;"
);

::renamed_ulog::ulog_structs!(
    crate = ::renamed_ulog;
    "gen_outer:uint64_t timestamp;gen_inner[2] inner;char[3] text;bool ok;uint8_t[4] _padding0;",
    "gen_inner:float x;int8_t type;uint8_t[3] _padding0;"
);

#[test]
fn renamed_crate_builds_and_decodes() {
    assert_eq!(
        Outer::schema().formats_text(),
        "inner:int16_t a;uint8_t[2] _padding0;char[4] name;\nouter_message:uint64_t timestamp;inner[2] inner;bool[3] flags;uint8_t type;uint8_t[5] _padding1;"
    );
    let plan = Plan::<Outer>::new(<Outer as ULogMessage>::layout()).unwrap();
    assert_eq!(plan.kind(), PlanKind::Exact);
    let value = Outer {
        timestamp: 9,
        inner: [
            Inner {
                a: -3,
                _padding0: [0; 2],
                name: ::renamed_ulog::typed::CharArray::from_str_truncated("ab"),
            },
            Inner {
                a: 4,
                _padding0: [0; 2],
                name: ::renamed_ulog::typed::CharArray::from_str_truncated("cdef"),
            },
        ],
        flags: [true, false, true],
        ty: 7,
        _padding1: [0; 5],
    };
    let bytes = value.encode();
    assert_eq!(bytes.len(), 8 + 2 * 8 + 3 + 1);
    assert_eq!(plan.decode(&bytes).unwrap(), value);
    assert_eq!(<Topics as ULogTopics>::NAMES, &["outer_message", "inner"]);
    let g = <GenOuter as ::std::default::Default>::default();
    assert_eq!(g.inner[1].r#type, 0);
    assert_eq!(
        GenOuter::schema().format_text(),
        "gen_outer:uint64_t timestamp;gen_inner[2] inner;char[3] text;bool ok;uint8_t[4] _padding0;"
    );
    let optional = Plan::<Optional>::new(<Outer as ULogMessage>::layout()).unwrap();
    let read = optional.decode(&bytes).unwrap();
    assert_eq!((read.missing, read.r#type), (9, 7));
    assert_eq!(read.inner.map(|i| i[1].a), std::option::Option::Some(4));
    const _: () = ::std::assert!(<View as ::renamed_ulog::typed::WireField>::IS_WIRE);
    // A generated view leaves out the trailing padding of a topic, not of a nested type.
    assert_eq!(::std::mem::size_of::<ViewOuter>(), 8 + 2 * 8 + 1);
    assert_eq!(::std::mem::size_of::<ViewInner>(), 8);
}
