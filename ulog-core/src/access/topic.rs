//! Generic access to a topic: its data messages, and any field by path as a typed
//! value. A path is resolved once to an offset and a type; reading is then a load at
//! a fixed offset.

use std::sync::Arc;

use ulog_format::{BasicType, Layout, LayoutType, LeafKind};

use crate::error::{Error, ErrorKind, Result};
use crate::read::framing::MSG_HEADER_LEN;
use crate::read::log::{Subscription, ULog};
use crate::read::offsets::MessageOffsets;
use crate::read::timestamp::{TimestampField, Unwrapper};
use crate::value::{Array, Str, Value};

/// One topic instance of a log (a subscription and its data messages).
#[derive(Clone, Copy)]
pub struct Topic<'l, 'a> {
    log: &'l ULog<'a>,
    sub: &'l Subscription,
}

/// What a resolved field path reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldShape {
    /// One value.
    Scalar,
    /// A whole array of `n` values.
    Array(usize),
    /// A `char[n]` string.
    String(usize),
}

/// A field path resolved against a topic's layout: read it from any payload of that
/// topic with [`FieldReader::read`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldReader {
    path: String,
    offset: usize,
    ty: BasicType,
    shape: FieldShape,
}

impl FieldReader {
    /// The path it was resolved from.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Byte offset in the payload.
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// The basic (element) type.
    pub fn ty(&self) -> BasicType {
        self.ty
    }

    /// Scalar, array or string.
    pub fn shape(&self) -> FieldShape {
        self.shape
    }

    #[inline]
    fn size(&self) -> usize {
        match self.shape {
            FieldShape::Scalar => self.ty.size(),
            FieldShape::Array(n) | FieldShape::String(n) => n * self.ty.size(),
        }
    }

    /// The field's value in `payload`; `None` if the payload is too short (a field in
    /// omitted trailing padding).
    #[inline]
    pub fn read<'a>(&self, payload: &'a [u8]) -> Option<Value<'a>> {
        let b = payload.get(self.offset..self.offset + self.size())?;
        Some(match self.shape {
            FieldShape::Scalar => Value::read_scalar(self.ty, b),
            FieldShape::Array(_) => Value::Array(Array::new(self.ty, b)),
            FieldShape::String(_) => Value::Str(Str(b)),
        })
    }

    /// The field as `f64` (numbers and booleans).
    #[inline]
    pub fn read_f64(&self, payload: &[u8]) -> Option<f64> {
        if self.shape != FieldShape::Scalar {
            return None;
        }
        let b = payload.get(self.offset..self.offset + self.ty.size())?;
        Value::read_scalar(self.ty, b).as_f64()
    }
}

impl<'l, 'a> Topic<'l, 'a> {
    pub(crate) fn new(log: &'l ULog<'a>, sub: &'l Subscription) -> Topic<'l, 'a> {
        Topic { log, sub }
    }

    /// The topic (format) name.
    pub fn name(&self) -> &'l str {
        &self.sub.name
    }

    /// The instance number.
    pub fn multi_id(&self) -> u8 {
        self.sub.multi_id
    }

    /// The msg_id of its (first) subscription.
    pub fn msg_id(&self) -> u16 {
        self.sub.msg_id
    }

    /// Byte offset of the subscription message.
    pub fn subscription_offset(&self) -> u64 {
        self.sub.offset
    }

    /// The layout of the topic's format, or why there is none.
    pub fn layout(&self) -> Result<&'l Arc<Layout>> {
        self.sub
            .layout
            .as_ref()
            .map_err(|e| Error::new(ErrorKind::Layout(e.clone()), self.sub.offset))
    }

    /// Number of data messages.
    pub fn len(&self) -> usize {
        self.sub.records.len()
    }

    /// Whether the topic has no data messages.
    pub fn is_empty(&self) -> bool {
        self.sub.records.is_empty()
    }

    /// Byte offsets of the data messages (of their 3-byte headers), in file order.
    pub fn message_offsets(&self) -> MessageOffsets<'l> {
        self.sub.records.view()
    }

    /// The payload of data message `i` (after the msg_id).
    pub fn payload(&self, i: usize) -> Option<&'a [u8]> {
        self.message_offsets()
            .get(i)
            .map(|o| payload_at(self.log.data(), o))
    }

    /// The payloads of every data message, in file order, borrowed from the file.
    pub fn payloads(&self) -> impl ExactSizeIterator<Item = &'a [u8]> + 'l {
        self.payloads_in(0..self.len())
    }

    /// The payloads of data messages `rows`, in file order.
    ///
    /// # Panics
    /// If `rows` is out of bounds, as slicing is.
    pub fn payloads_in(
        &self,
        rows: core::ops::Range<usize>,
    ) -> impl ExactSizeIterator<Item = &'a [u8]> + 'l {
        let data = self.log.data();
        self.message_offsets()
            .slice(rows)
            .iter()
            .map(move |o| payload_at(data, o))
    }

    /// Where the timestamp field is, if the format has one.
    pub fn timestamp_field(&self) -> Option<TimestampField> {
        self.sub.timestamp
    }

    /// The timestamp of every data message in microseconds, narrow (version 0)
    /// timestamps unwrapped; empty if the format has no timestamp.
    pub fn timestamps(&self) -> Vec<u64> {
        let mut u = Unwrapper::new(self.sub.timestamp);
        self.payloads().filter_map(|p| u.push(p)).collect()
    }

    /// Resolves a field path (`timestamp`, `q`, `q[2]`, `esc[3].esc_rpm`) once, to read
    /// it from every payload.
    pub fn field(&self, path: &str) -> Result<FieldReader> {
        let layout = self.layout()?;
        let not_found = || {
            let suggestion =
                crate::suggest::closest(path, layout.columns().map(|c| c.path.as_str()));
            Error::new(
                ErrorKind::FieldNotFound {
                    topic: self.sub.name.clone(),
                    path: path.to_owned(),
                    suggestion,
                },
                self.sub.offset,
            )
        };
        let f = layout.find(path).ok_or_else(not_found)?;
        let ty = match f.ty {
            LayoutType::Basic(b) => b,
            LayoutType::Nested(_) => return Err(not_found()),
        };
        if path.split('.').any(ulog_format::is_padding_name) {
            return Err(not_found());
        }
        let shape = match (ty, f.is_array) {
            (BasicType::Char, true) => FieldShape::String(f.count),
            (_, true) => FieldShape::Array(f.count),
            (_, false) => FieldShape::Scalar,
        };
        Ok(FieldReader {
            path: path.to_owned(),
            offset: f.offset,
            ty,
            shape,
        })
    }

    /// Readers for every column (leaf field, padding left out) in pyulog's order:
    /// arrays element by element, `char[N]` as one string.
    pub fn columns(&self) -> Result<Vec<FieldReader>> {
        Ok(FieldReader::columns_of(self.layout()?))
    }
}

impl FieldReader {
    /// Readers for every column of `layout`, as [`Topic::columns`] gives them: for
    /// payloads met without a parsed log (the stream reader's subscriptions), resolved
    /// once per subscription.
    ///
    /// ```
    /// let layout = ulog_core::format::Resolver::default()
    ///     .resolve("t", &[ulog_core::format::Format::parse("t:uint64_t timestamp;float[2] v;").unwrap()][..])
    ///     .unwrap();
    /// let paths: Vec<String> = ulog_core::FieldReader::columns_of(&layout)
    ///     .iter()
    ///     .map(|c| c.path().to_owned())
    ///     .collect();
    /// assert_eq!(paths, ["timestamp", "v[0]", "v[1]"]);
    /// ```
    pub fn columns_of(layout: &Layout) -> Vec<FieldReader> {
        layout
            .columns()
            .map(|leaf| FieldReader {
                path: leaf.path.clone(),
                offset: leaf.offset,
                ty: leaf.ty,
                shape: if leaf.kind == LeafKind::String {
                    FieldShape::String(leaf.count)
                } else {
                    FieldShape::Scalar
                },
            })
            .collect()
    }
}

impl core::fmt::Debug for Topic<'_, '_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Topic")
            .field("name", &self.sub.name)
            .field("multi_id", &self.sub.multi_id)
            .field("msg_id", &self.sub.msg_id)
            .field("messages", &self.sub.records.len())
            .finish()
    }
}

fn payload_at(data: &[u8], offset: u64) -> &[u8] {
    let o = offset as usize;
    let size = u16::from_le_bytes([data[o], data[o + 1]]) as usize;
    // Skip the message header and the 2-byte msg_id.
    &data[o + MSG_HEADER_LEN + 2..o + MSG_HEADER_LEN + size]
}
