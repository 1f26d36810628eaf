//! `ULogMessage`: a Rust type bound to a ULog message format.

use ulog_format::Layout;
use zerocopy::{FromZeros, IntoBytes};

use super::schema::Schema;
use super::wire::WireField;

/// A Rust struct bound to a ULog message: its name, its format and the nested
/// formats it needs, and the conversion from and to payload bytes.
///
/// Derive it (`#[derive(ULogMessage)]`, feature `derive`) rather than implementing it
/// by hand. Read logs through a [`Plan`](super::Plan), which checks a log's format
/// against the type once and then decodes each payload.
pub trait ULogMessage: WireField {
    /// The ULog message name (`vehicle_attitude`).
    const NAME: &'static str;

    /// The format, nested formats and layout of the binding, built on first use.
    fn schema() -> &'static Schema;

    /// The binding's layout.
    fn layout() -> &'static Layout {
        Self::schema().layout()
    }

    /// A value with every byte zero (numbers 0, `false`, empty strings).
    fn zeroed() -> Self {
        Self::from_wire(&<Self::Wire as FromZeros>::new_zeroed())
    }

    /// The length of an encoded payload: the full size without trailing padding,
    /// which PX4 does not write.
    fn encoded_len() -> usize {
        Self::layout().min_size()
    }

    /// Appends the payload bytes of `self` (without trailing padding) to `out`.
    fn encode_into(&self, out: &mut Vec<u8>) {
        let wire = self.to_wire();
        let bytes = wire.as_bytes();
        out.extend_from_slice(&bytes[..Self::encoded_len().min(bytes.len())]);
    }

    /// The payload bytes of `self`, without trailing padding.
    fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(Self::encoded_len());
        self.encode_into(&mut out);
        out
    }
}
