//! A binding implemented by hand, for the typed module's tests: neither derived nor
//! generated, so it is decoded from its wire bytes (`WireField::READS_IMAGE` false).

use std::sync::OnceLock;

use ulog_format::BasicType;

use super::message::ULogMessage;
use super::{FieldDef, FieldKind, Present, Schema, WireField, Writable};

/// A binding implemented by hand, not derived: it keeps `WireField`'s default of
/// one payload offset, where its schema has two fields.
#[derive(Debug, PartialEq)]
pub(crate) struct Pair {
    pub(crate) a: u32,
    pub(crate) b: u16,
}

impl WireField for Pair {
    type Wire = [u8; 6];
    type Writability = Writable;
    const KIND: FieldKind = FieldKind::Nested(<Pair as ULogMessage>::schema);
    fn from_wire(w: &[u8; 6], _: Present<'_>) -> Pair {
        Pair {
            a: u32::from_le_bytes([w[0], w[1], w[2], w[3]]),
            b: u16::from_le_bytes([w[4], w[5]]),
        }
    }
    fn to_wire(&self) -> [u8; 6] {
        let mut w = [0; 6];
        w[..4].copy_from_slice(&self.a.to_le_bytes());
        w[4..].copy_from_slice(&self.b.to_le_bytes());
        w
    }
}

impl ULogMessage for Pair {
    const NAME: &'static str = "pair";
    fn schema() -> &'static Schema {
        static FIELDS: [FieldDef; 2] = [
            FieldDef::new("a", &[], FieldKind::Basic(BasicType::UInt32), None),
            FieldDef::new("b", &[], FieldKind::Basic(BasicType::UInt16), None),
        ];
        static SCHEMA: OnceLock<Schema> = OnceLock::new();
        SCHEMA.get_or_init(|| Schema::build("pair", &FIELDS))
    }
}
