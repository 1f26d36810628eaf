//! A topic as an Arrow schema and record batches.
//!
//! The schema is compiled once per topic from its layout into a tree of column
//! readers (a value at a fixed offset, a `char[N]` string, a fixed-size list, a
//! struct); each batch is then built column by column from the payloads, borrowed
//! from the log.

use std::collections::HashMap;
use std::sync::Arc;

use arrow_array::builder::StringBuilder;
use arrow_array::types::{
    Float32Type, Float64Type, Int16Type, Int32Type, Int64Type, Int8Type, UInt16Type, UInt32Type,
    UInt64Type, UInt8Type,
};
use arrow_array::{
    ArrayRef, ArrowPrimitiveType, BooleanArray, FixedSizeListArray, PrimitiveArray, RecordBatch,
    RecordBatchOptions, StringArray, StructArray, TimestampMicrosecondArray, UInt8Array,
};
use arrow_schema::{DataType, Field, Fields, Schema, SchemaRef, TimeUnit};
use ulog_format::{BasicType, LayoutField, LayoutType};

use super::error::{ExportError, ExportErrorKind};
use crate::access::field::{FieldReader, FieldShape};
use crate::access::lookup::LookupError;
use crate::definitions::Subscription;
use crate::units::unit_of;

type Result<T, E = ExportError> = core::result::Result<T, E>;

use super::rows::Rows;
use super::{latin1, Options};

/// How one column (or a part of one) is read from a payload. Offsets are relative
/// to the start of the enclosing value (the payload, a struct, a list element).
#[derive(Debug, Clone)]
enum Node {
    /// One value of a basic type.
    Value { ty: BasicType, offset: usize },
    /// A `char[len]` string.
    Text { offset: usize, len: usize },
    /// `len` elements, `stride` bytes apart.
    List {
        offset: usize,
        len: usize,
        stride: usize,
        item: Box<Node>,
    },
    /// The fields of a nested format.
    Struct {
        offset: usize,
        fields: Fields,
        children: Vec<Node>,
    },
    /// The UTC time of the `uint64_t` timestamp at `offset`, `boot_us` microseconds
    /// since the Unix epoch at timestamp 0.
    Utc { offset: usize, boot_us: i64 },
    /// The same text in every row (a dataset's `log_id`).
    SameText(Arc<str>),
    /// The same byte in every row (a dataset's `multi_id`).
    SameByte(u8),
}

impl Node {
    /// The reader of the one column `reader` reads: a `char[N]` as text, a value, a
    /// whole array as a fixed-size list.
    fn of_reader(reader: &FieldReader) -> Node {
        let offset = reader.offset();
        match reader.shape() {
            FieldShape::String(len) => Node::Text { offset, len },
            FieldShape::Scalar => Node::Value {
                ty: reader.ty(),
                offset,
            },
            FieldShape::Array(len) => Node::List {
                offset,
                len,
                stride: reader.ty().size(),
                item: Box::new(Node::Value {
                    ty: reader.ty(),
                    offset: 0,
                }),
            },
        }
    }

    /// The Arrow type of the column.
    fn data_type(&self) -> DataType {
        match self {
            Node::Value { ty, .. } => basic_data_type(*ty),
            Node::Text { .. } => DataType::Utf8,
            Node::List { len, item, .. } => {
                DataType::FixedSizeList(Arc::new(item_field(item)), *len as i32)
            }
            Node::Struct { fields, .. } => DataType::Struct(fields.clone()),
            Node::Utc { .. } => DataType::Timestamp(TimeUnit::Microsecond, Some("UTC".into())),
            Node::SameText(_) => DataType::Utf8,
            Node::SameByte(_) => DataType::UInt8,
        }
    }

    /// One past the last byte this node reads, relative to its base.
    fn end(&self) -> usize {
        match self {
            Node::Value { ty, offset } => offset + ty.size(),
            Node::Utc { offset, .. } => offset + 8,
            Node::SameText(_) | Node::SameByte(_) => 0,
            Node::Text { offset, len } => offset + len,
            Node::List {
                offset,
                len,
                stride,
                item,
            } => match len {
                0 => 0,
                n => offset + (n - 1) * stride + item.end(),
            },
            Node::Struct {
                offset, children, ..
            } => offset + children.iter().map(Node::end).max().unwrap_or(0),
        }
    }
}

fn item_field(item: &Node) -> Field {
    Field::new("item", item.data_type(), false)
}

/// The Arrow type of a basic ULog type: the same width and signedness; a lone `char`
/// is its byte.
fn basic_data_type(ty: BasicType) -> DataType {
    match ty {
        BasicType::Int8 => DataType::Int8,
        BasicType::UInt8 | BasicType::Char => DataType::UInt8,
        BasicType::Int16 => DataType::Int16,
        BasicType::UInt16 => DataType::UInt16,
        BasicType::Int32 => DataType::Int32,
        BasicType::UInt32 => DataType::UInt32,
        BasicType::Int64 => DataType::Int64,
        BasicType::UInt64 => DataType::UInt64,
        BasicType::Float => DataType::Float32,
        BasicType::Double => DataType::Float64,
        BasicType::Bool => DataType::Boolean,
    }
}

/// The reader of a field of a layout; `None` for padding, and for fields that hold
/// no value (zero-length arrays, nested formats made of padding only).
fn node_of(f: &LayoutField) -> Option<Node> {
    if f.is_padding() {
        return None;
    }
    let offset = f.offset;
    match (&f.ty, f.array_len) {
        (LayoutType::Basic(BasicType::Char), Some(len)) => Some(Node::Text { offset, len }),
        (LayoutType::Basic(_), Some(0)) | (LayoutType::Nested(_), Some(0)) => None,
        (LayoutType::Basic(ty), Some(len)) => Some(Node::List {
            offset,
            len,
            stride: ty.size(),
            item: Box::new(Node::Value { ty: *ty, offset: 0 }),
        }),
        (LayoutType::Basic(ty), None) => Some(Node::Value { ty: *ty, offset }),
        (LayoutType::Nested(inner), array_len) => {
            let (fields, children) = struct_of(inner.fields(), |_| HashMap::new());
            if children.is_empty() {
                return None;
            }
            let element = |offset| Node::Struct {
                offset,
                fields: fields.clone(),
                children: children.clone(),
            };
            Some(match array_len {
                Some(len) => Node::List {
                    offset,
                    len,
                    stride: inner.size(),
                    item: Box::new(element(0)),
                },
                None => element(offset),
            })
        }
    }
}

/// The Arrow fields and readers of a list of layout fields, padding left out;
/// `metadata` gives each field's Arrow metadata.
fn struct_of(
    fields: &[LayoutField],
    metadata: impl Fn(&LayoutField) -> HashMap<String, String>,
) -> (Fields, Vec<Node>) {
    let mut arrow = Vec::new();
    let mut nodes = Vec::new();
    for f in fields {
        if let Some(node) = node_of(f) {
            arrow.push(
                Field::new(f.name.clone(), node.data_type(), false).with_metadata(metadata(f)),
            );
            nodes.push(node);
        }
    }
    (Fields::from(arrow), nodes)
}

/// A column path without its array indices: `esc[2].esc_rpm` → `esc.esc_rpm`.
fn without_indices(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    let mut depth = 0;
    for c in path.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// The text of a field's type as in a format string: `float[4]`, `esc_report[8]`.
fn type_text(f: &LayoutField) -> String {
    match f.array_len {
        Some(n) => format!("{}[{n}]", f.ty.name()),
        None => f.ty.name().to_owned(),
    }
}

/// A topic's schema with the readers of its columns.
#[derive(Debug, Clone)]
pub(crate) struct TopicTable {
    pub(crate) schema: SchemaRef,
    columns: Vec<Node>,
    /// The payload size every column needs.
    needed: usize,
    name: String,
}

impl TopicTable {
    /// Compiles the schema of `topic`: nested (one column per top-level field) or
    /// flattened to pyulog's columns.
    pub(crate) fn new(topic: &Subscription, options: &Options) -> Result<TopicTable> {
        let layout = topic.layout().map_err(|e| LookupError::layout(topic, e))?;
        let ts = topic.timestamp_field();
        // One metadata entry per field: Arrow writes metadata maps in hash order, and
        // one entry keeps the files byte for byte the same from run to run.
        let metadata = |name: &str, ty: String| -> HashMap<String, String> {
            match ts {
                Some(t) if name == "timestamp" => HashMap::from([(
                    "unit".to_owned(),
                    if t.unit_us() == 1 { "us" } else { "ms" }.to_owned(),
                )]),
                _ => HashMap::from([("ulog.type".to_owned(), ty)]),
            }
        };
        let (fields, columns) = if options.flatten {
            let mut readers = FieldReader::all(layout);
            // pyulog's tables (and ulog2csv) put `timestamp` first.
            if let Some(i) = readers.iter().position(|r| r.path() == "timestamp") {
                let t = readers.remove(i);
                readers.insert(0, t);
            }
            let mut fields = Vec::with_capacity(readers.len());
            let mut nodes = Vec::with_capacity(readers.len());
            for r in readers {
                let node = Node::of_reader(&r);
                let ty = match r.shape() {
                    FieldShape::String(len) => format!("char[{len}]"),
                    _ => r.ty().name().to_owned(),
                };
                fields.push(
                    Field::new(r.path(), node.data_type(), false)
                        .with_metadata(metadata(r.path(), ty)),
                );
                nodes.push(node);
            }
            (Fields::from(fields), nodes)
        } else {
            struct_of(layout.fields(), |f| metadata(&f.name, type_text(f)))
        };
        let (mut fields, mut columns) = (fields.to_vec(), columns);
        if let Some(clock) = &options.utc {
            let at = fields.iter().position(|f| f.name() == "timestamp");
            if let (Some(at), Some(t)) = (at, ts.filter(|t| t.ty == BasicType::UInt64)) {
                let node = Node::Utc {
                    offset: t.offset,
                    boot_us: clock.boot_us(),
                };
                let source =
                    HashMap::from([("ulog.utc_source".to_owned(), clock.source().to_string())]);
                fields.insert(
                    at + 1,
                    Arc::new(
                        Field::new("timestamp_utc", node.data_type(), false).with_metadata(source),
                    ),
                );
                columns.insert(at + 1, node);
            }
        }
        if let Some(log_id) = &options.log_id {
            // First, so that a dataset's rows say whose they are before what they hold.
            fields.insert(0, Arc::new(Field::new("log_id", DataType::Utf8, false)));
            columns.insert(0, Node::SameText(Arc::from(log_id.as_str())));
            fields.insert(1, Arc::new(Field::new("multi_id", DataType::UInt8, false)));
            columns.insert(1, Node::SameByte(topic.multi_id()));
        }
        let fields = Fields::from(fields);
        let formats: Vec<String> = layout.formats().iter().map(|f| f.to_string()).collect();
        let mut metadata = HashMap::from([
            ("ulog.topic".to_owned(), topic.name().to_owned()),
            ("ulog.format".to_owned(), formats.join("\n")),
        ]);
        // With `multi_id` a column, the instances of a topic share one schema (and file).
        if options.log_id.is_none() {
            metadata.insert("ulog.multi_id".to_owned(), topic.multi_id().to_string());
        }
        // Units in the schema's metadata, one key per field (indices left out: every
        // element of an array has its unit): a field's metadata keeps one entry, as
        // Arrow writes those in hash order.
        for r in FieldReader::all(layout) {
            if let Some(unit) = unit_of(topic.name(), r.path()) {
                metadata.insert(
                    format!("ulog.unit.{}", without_indices(r.path())),
                    unit.to_owned(),
                );
            }
        }
        let needed = columns.iter().map(Node::end).max().unwrap_or(0);
        Ok(TopicTable {
            schema: Arc::new(Schema::new_with_metadata(fields, metadata)),
            columns,
            needed,
            name: topic.name().to_owned(),
        })
    }

    /// The bytes of a payload that the columns read (those before are all a row needs).
    pub(crate) fn needed(&self) -> usize {
        self.needed
    }

    /// Column `i` of `rows` (each at least [`TopicTable::needed`] bytes), read from
    /// the rows where they are.
    pub(crate) fn column_of_rows(&self, i: usize, rows: &Rows) -> Result<ArrayRef> {
        build(&self.columns[i], self.schema.field(i).data_type(), rows)
    }

    /// The record batch of `payloads` (rows of the topic, in order); `offset` gives the
    /// file offset of a row (for errors).
    pub(crate) fn batch(
        &self,
        payloads: &[&[u8]],
        offset: impl Fn(usize) -> u64,
    ) -> Result<RecordBatch> {
        for (i, p) in payloads.iter().enumerate() {
            if p.len() < self.needed {
                return Err(ExportError::new(ExportErrorKind::ShortPayload {
                    topic: self.name.clone(),
                    needed: self.needed,
                    found: p.len(),
                })
                .at(offset(i)));
            }
        }
        let bases: Vec<(&[u8], usize)> = payloads.iter().map(|&p| (p, 0)).collect();
        let bases = &bases[..];
        let arrays: Vec<ArrayRef> = self
            .columns
            .iter()
            .zip(self.schema.fields())
            .map(|(node, field)| build(node, field.data_type(), bases))
            .collect::<Result<_>>()?;
        RecordBatch::try_new_with_options(
            self.schema.clone(),
            arrays,
            &RecordBatchOptions::new().with_row_count(Some(payloads.len())),
        )
        .map_err(ExportError::encoding)
    }
}

/// The Arrow type of the column `reader` reads, as a flattened table types it.
pub(crate) fn field_data_type(reader: &FieldReader) -> DataType {
    Node::of_reader(reader).data_type()
}

/// The values `reader` reads in `rows`, of [`field_data_type`]: null where a row is
/// `None` or too short for the field.
pub(crate) fn field_array(reader: &FieldReader, rows: &[Option<&[u8]>]) -> Result<ArrayRef> {
    let node = Node::of_reader(reader);
    let end = node.end();
    // An absent row reads as zeros (a value, an empty text), then is masked: one pass
    // over the rows builds the column as the export builds its own.
    let zeros = vec![0u8; end];
    let mut absent = Vec::with_capacity(rows.len());
    let bases: Vec<(&[u8], usize)> = rows
        .iter()
        .map(|row| match row {
            Some(p) if p.len() >= end => {
                absent.push(false);
                (*p, 0)
            }
            _ => {
                absent.push(true);
                (&zeros[..], 0)
            }
        })
        .collect();
    let values = build(&node, &node.data_type(), &bases[..])?;
    if !absent.contains(&true) {
        return Ok(values);
    }
    arrow_select::nullif::nullif(&values, &BooleanArray::from(absent))
        .map_err(ExportError::encoding)
}

/// Where the values of a node are: payloads, and the offset of the enclosing value
/// in each. The rows of a row group are their own bases (offset 0): no list of them
/// is made (one was 24 bytes a row, more than many rows); the values inside a
/// nested format, or inside a list of them, are listed as they are built.
trait Bases {
    fn len(&self) -> usize;
    fn iter(&self) -> impl Iterator<Item = (&[u8], usize)> + Clone;
}

impl Bases for Rows {
    fn len(&self) -> usize {
        Rows::len(self)
    }
    fn iter(&self) -> impl Iterator<Item = (&[u8], usize)> + Clone {
        Rows::iter(self).map(|p| (p, 0))
    }
}

impl Bases for [(&[u8], usize)] {
    fn len(&self) -> usize {
        <[_]>::len(self)
    }
    fn iter(&self) -> impl Iterator<Item = (&[u8], usize)> + Clone {
        <[_]>::iter(self).copied()
    }
}

/// The values of `node` at every base. The payloads were checked to be long enough.
fn build(node: &Node, ty: &DataType, bases: &(impl Bases + ?Sized)) -> Result<ArrayRef> {
    Ok(match node {
        Node::Value { ty, offset } => values(
            *ty,
            bases.len(),
            bases.iter().map(|(p, b)| &p[b + offset..]),
        ),
        Node::Text { offset, len } => {
            let mut text = String::new();
            let mut strings = StringBuilder::with_capacity(bases.len(), bases.len() * len);
            for (p, b) in bases.iter() {
                latin1(&p[b + offset..b + offset + len], &mut text);
                strings.append_value(&text);
            }
            Arc::new(strings.finish())
        }
        Node::List {
            offset,
            len,
            stride,
            item,
        } => {
            let DataType::FixedSizeList(item_field, _) = ty else {
                unreachable!("a list node has a list type")
            };
            let (len, offset, stride) = (*len, *offset, *stride);
            let child = match **item {
                // An array of values (most arrays: `float[3]`, `q[4]`) read in place.
                Node::Value { ty, offset: at } => values(
                    ty,
                    bases.len() * len,
                    bases.iter().flat_map(|(p, b)| {
                        (0..len).map(move |j| &p[b + offset + j * stride + at..])
                    }),
                ),
                _ => {
                    let inner: Vec<(&[u8], usize)> = bases
                        .iter()
                        .flat_map(|(p, b)| (0..len).map(move |j| (p, b + offset + j * stride)))
                        .collect();
                    build(item, item_field.data_type(), &inner[..])?
                }
            };
            Arc::new(
                FixedSizeListArray::try_new(item_field.clone(), len as i32, child, None)
                    .map_err(ExportError::encoding)?,
            )
        }
        Node::Struct {
            offset,
            fields,
            children,
        } => {
            let inner: Vec<(&[u8], usize)> = bases.iter().map(|(p, b)| (p, b + offset)).collect();
            let arrays = children
                .iter()
                .zip(fields.iter())
                .map(|(c, f)| build(c, f.data_type(), &inner[..]))
                .collect::<Result<Vec<_>>>()?;
            Arc::new(
                StructArray::try_new(fields.clone(), arrays, None)
                    .map_err(ExportError::encoding)?,
            )
        }
        Node::Utc { offset, boot_us } => Arc::new(
            TimestampMicrosecondArray::from_iter_values(bases.iter().map(|(p, b)| {
                let mut a = [0u8; 8];
                a.copy_from_slice(&p[b + offset..b + offset + 8]);
                let t = u64::from_le_bytes(a).min(i64::MAX as u64) as i64;
                boot_us.saturating_add(t)
            }))
            .with_timezone("UTC"),
        ),
        Node::SameText(text) => Arc::new(StringArray::from_iter_values(
            std::iter::repeat(&**text).take(bases.len()),
        )),
        Node::SameByte(byte) => Arc::new(UInt8Array::from_value(*byte, bases.len())),
    })
}

/// The `len` values that start the slices of `at`, in order.
fn primitive<'a, T: ArrowPrimitiveType, const N: usize>(
    len: usize,
    at: impl Iterator<Item = &'a [u8]>,
    from: fn([u8; N]) -> T::Native,
) -> ArrayRef {
    let mut values: Vec<T::Native> = Vec::with_capacity(len);
    // `for_each`, not `extend`: the rows of blocks and a list's items in each are
    // nested iterators, which `for_each` runs as loops within loops (`extend` calls
    // `next`, with its branches between blocks and rows, for each value).
    at.for_each(|s| {
        let mut a = [0u8; N];
        a.copy_from_slice(&s[..N]);
        values.push(from(a));
    });
    Arc::new(PrimitiveArray::<T>::new(values.into(), None))
}

/// The `len` values of type `ty` that start the slices of `at`, in order.
fn values<'a>(ty: BasicType, len: usize, at: impl Iterator<Item = &'a [u8]>) -> ArrayRef {
    match ty {
        BasicType::Int8 => primitive::<Int8Type, 1>(len, at, i8::from_le_bytes),
        BasicType::UInt8 | BasicType::Char => primitive::<UInt8Type, 1>(len, at, u8::from_le_bytes),
        BasicType::Int16 => primitive::<Int16Type, 2>(len, at, i16::from_le_bytes),
        BasicType::UInt16 => primitive::<UInt16Type, 2>(len, at, u16::from_le_bytes),
        BasicType::Int32 => primitive::<Int32Type, 4>(len, at, i32::from_le_bytes),
        BasicType::UInt32 => primitive::<UInt32Type, 4>(len, at, u32::from_le_bytes),
        BasicType::Int64 => primitive::<Int64Type, 8>(len, at, i64::from_le_bytes),
        BasicType::UInt64 => primitive::<UInt64Type, 8>(len, at, u64::from_le_bytes),
        BasicType::Float => primitive::<Float32Type, 4>(len, at, f32::from_le_bytes),
        BasicType::Double => primitive::<Float64Type, 8>(len, at, f64::from_le_bytes),
        BasicType::Bool => {
            let mut bits = arrow_buffer::BooleanBufferBuilder::new(len);
            at.for_each(|s| bits.append(s[0] != 0));
            Arc::new(BooleanArray::new(bits.finish(), None))
        }
    }
}
