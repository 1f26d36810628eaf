//! Columns: every leaf field of a topic copied into a typed vector, one value per data
//! message, as a table of the topic (what pyulog's `ULog(path)` builds with numpy
//! arrays). [`load_columns`](crate::load_columns) loads every topic of a log.

use ulog_format::{BasicType, LeafKind};

use crate::access::lookup::LookupError;
use crate::access::topic::Topic;
use crate::value::{LogText, Value};

/// The values of one column, in the column's own type.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnData {
    /// `int8_t`
    I8(Vec<i8>),
    /// `uint8_t`
    U8(Vec<u8>),
    /// `int16_t`
    I16(Vec<i16>),
    /// `uint16_t`
    U16(Vec<u16>),
    /// `int32_t`
    I32(Vec<i32>),
    /// `uint32_t`
    U32(Vec<u32>),
    /// `int64_t`
    I64(Vec<i64>),
    /// `uint64_t`
    U64(Vec<u64>),
    /// `float`
    F32(Vec<f32>),
    /// `double`
    F64(Vec<f64>),
    /// `bool`
    Bool(Vec<bool>),
    /// A single `char` (an element of a nested array of chars is one).
    Char(Vec<u8>),
    /// `char[N]` strings: `width` bytes per row, the rows back to back.
    Str {
        /// Bytes per row (`N`).
        width: usize,
        /// `width × rows` bytes.
        bytes: Vec<u8>,
    },
}

impl ColumnData {
    fn with_capacity(ty: BasicType, kind: LeafKind, count: usize, rows: usize) -> ColumnData {
        if kind == LeafKind::String {
            return ColumnData::Str {
                width: count,
                bytes: Vec::with_capacity(count * rows),
            };
        }
        match ty {
            BasicType::Int8 => ColumnData::I8(Vec::with_capacity(rows)),
            BasicType::UInt8 => ColumnData::U8(Vec::with_capacity(rows)),
            BasicType::Int16 => ColumnData::I16(Vec::with_capacity(rows)),
            BasicType::UInt16 => ColumnData::U16(Vec::with_capacity(rows)),
            BasicType::Int32 => ColumnData::I32(Vec::with_capacity(rows)),
            BasicType::UInt32 => ColumnData::U32(Vec::with_capacity(rows)),
            BasicType::Int64 => ColumnData::I64(Vec::with_capacity(rows)),
            BasicType::UInt64 => ColumnData::U64(Vec::with_capacity(rows)),
            BasicType::Float => ColumnData::F32(Vec::with_capacity(rows)),
            BasicType::Double => ColumnData::F64(Vec::with_capacity(rows)),
            BasicType::Bool => ColumnData::Bool(Vec::with_capacity(rows)),
            BasicType::Char => ColumnData::Char(Vec::with_capacity(rows)),
        }
    }

    /// Appends the value at `offset` of every row of `rows` (rows of `stride` bytes
    /// that hold it: checked by the caller).
    fn extend_from_rows(&mut self, rows: &[u8], stride: usize, offset: usize) {
        let rows = rows.chunks_exact(stride);
        macro_rules! le {
            ($v:expr, $t:ty) => {{
                const N: usize = core::mem::size_of::<$t>();
                $v.extend(rows.map(|r| {
                    let mut a = [0u8; N];
                    a.copy_from_slice(&r[offset..offset + N]);
                    <$t>::from_le_bytes(a)
                }))
            }};
        }
        match self {
            ColumnData::I8(v) => v.extend(rows.map(|r| r[offset] as i8)),
            ColumnData::U8(v) | ColumnData::Char(v) => v.extend(rows.map(|r| r[offset])),
            ColumnData::I16(v) => le!(v, i16),
            ColumnData::U16(v) => le!(v, u16),
            ColumnData::I32(v) => le!(v, i32),
            ColumnData::U32(v) => le!(v, u32),
            ColumnData::I64(v) => le!(v, i64),
            ColumnData::U64(v) => le!(v, u64),
            ColumnData::F32(v) => le!(v, f32),
            ColumnData::F64(v) => le!(v, f64),
            ColumnData::Bool(v) => v.extend(rows.map(|r| r[offset] != 0)),
            ColumnData::Str { width, bytes } => {
                for r in rows {
                    bytes.extend_from_slice(&r[offset..offset + *width]);
                }
            }
        }
    }

    /// Rows and room for rows (of a `Str` column: in rows of its width).
    fn len_capacity(&self) -> (usize, usize) {
        macro_rules! lc {
            ($v:expr) => {
                ($v.len(), $v.capacity())
            };
        }
        match self {
            ColumnData::I8(v) => lc!(v),
            ColumnData::U8(v) | ColumnData::Char(v) => lc!(v),
            ColumnData::I16(v) => lc!(v),
            ColumnData::U16(v) => lc!(v),
            ColumnData::I32(v) => lc!(v),
            ColumnData::U32(v) => lc!(v),
            ColumnData::I64(v) => lc!(v),
            ColumnData::U64(v) => lc!(v),
            ColumnData::F32(v) => lc!(v),
            ColumnData::F64(v) => lc!(v),
            ColumnData::Bool(v) => lc!(v),
            ColumnData::Str { width, bytes } => (
                bytes.len().checked_div(*width).unwrap_or(0),
                bytes.capacity().checked_div(*width).unwrap_or(usize::MAX),
            ),
        }
    }

    /// Makes room for `rows` rows in all.
    fn reserve_rows(&mut self, rows: usize) {
        macro_rules! room {
            ($v:expr, $n:expr) => {
                $v.reserve_exact($n.saturating_sub($v.len()))
            };
        }
        match self {
            ColumnData::I8(v) => room!(v, rows),
            ColumnData::U8(v) | ColumnData::Char(v) => room!(v, rows),
            ColumnData::I16(v) => room!(v, rows),
            ColumnData::U16(v) => room!(v, rows),
            ColumnData::I32(v) => room!(v, rows),
            ColumnData::U32(v) => room!(v, rows),
            ColumnData::I64(v) => room!(v, rows),
            ColumnData::U64(v) => room!(v, rows),
            ColumnData::F32(v) => room!(v, rows),
            ColumnData::F64(v) => room!(v, rows),
            ColumnData::Bool(v) => room!(v, rows),
            ColumnData::Str { width, bytes } => room!(bytes, rows.saturating_mul(*width)),
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            ColumnData::I8(v) => v.len(),
            ColumnData::U8(v) | ColumnData::Char(v) => v.len(),
            ColumnData::I16(v) => v.len(),
            ColumnData::U16(v) => v.len(),
            ColumnData::I32(v) => v.len(),
            ColumnData::U32(v) => v.len(),
            ColumnData::I64(v) => v.len(),
            ColumnData::U64(v) => v.len(),
            ColumnData::F32(v) => v.len(),
            ColumnData::F64(v) => v.len(),
            ColumnData::Bool(v) => v.len(),
            ColumnData::Str { width, bytes } => bytes.len().checked_div(*width).unwrap_or(0),
        }
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The value of row `i`, as [`FieldReader::read`](crate::FieldReader::read) gives
    /// it (`char[N]` as [`Value::Str`]).
    pub fn get(&self, i: usize) -> Option<Value<'_>> {
        Some(match self {
            ColumnData::I8(v) => Value::I8(*v.get(i)?),
            ColumnData::U8(v) => Value::U8(*v.get(i)?),
            ColumnData::I16(v) => Value::I16(*v.get(i)?),
            ColumnData::U16(v) => Value::U16(*v.get(i)?),
            ColumnData::I32(v) => Value::I32(*v.get(i)?),
            ColumnData::U32(v) => Value::U32(*v.get(i)?),
            ColumnData::I64(v) => Value::I64(*v.get(i)?),
            ColumnData::U64(v) => Value::U64(*v.get(i)?),
            ColumnData::F32(v) => Value::F32(*v.get(i)?),
            ColumnData::F64(v) => Value::F64(*v.get(i)?),
            ColumnData::Bool(v) => Value::Bool(*v.get(i)?),
            ColumnData::Char(v) => Value::Char(*v.get(i)?),
            ColumnData::Str { width, bytes } => {
                let start = i.checked_mul(*width)?;
                Value::Str(LogText(bytes.get(start..start.checked_add(*width)?)?))
            }
        })
    }
}

/// One column of a topic: its path (as [`Topic::fields`] names it) and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The path, as pyulog names columns: `q[2]`, `esc[1].esc_rpm`.
    pub path: String,
    /// The values, one per data message in file order.
    pub data: ColumnData,
}

impl Topic<'_, '_> {
    /// Every column of the topic (leaf fields in pyulog's order, padding left out,
    /// `char[N]` as one string column) loaded into typed vectors, one value per data
    /// message. Fails only when the topic's format could not be laid out.
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes)?;
    /// let topic = log.topic("vehicle_attitude", 0)?;
    /// let columns = topic.columns()?;
    /// assert_eq!(columns[0].path, "timestamp");
    /// assert_eq!(columns[0].data.len(), topic.len());
    /// assert_eq!(columns[1].data.get(0), topic.field("q[0]")?.read(topic.payload(0).unwrap()));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn columns(&self) -> Result<Vec<Column>, LookupError> {
        let mut table = Table::new(self.layout()?, self.len());
        for p in self.payloads() {
            table.push(p, |_| 0);
        }
        Ok(table.finish())
    }
}

/// The columns of one topic while they are filled, one payload at a time. Rows are
/// gathered in a small row-major block first and moved into the columns a block at
/// a time, column by column: each column then receives a run of values at once
/// (one type dispatch per column and block, sequential writes) instead of one
/// value per row scattered over every column.
pub(crate) struct Table {
    paths: Vec<String>,
    data: Vec<ColumnData>,
    offsets: Vec<usize>,
    /// Every column lies within this many bytes; framing accepts only payloads of the
    /// full size or the size without trailing padding, which both hold them. A
    /// shorter payload (never framed, but cheap to survive) reads as zero-filled.
    needed: usize,
    /// Rows not yet moved into the columns, `needed` bytes each.
    block: Vec<u8>,
}

/// Bytes of rows gathered before they are moved into the columns (small enough to
/// stay in the first-level cache).
const BLOCK_BYTES: usize = 16 * 1024;

impl Table {
    /// Empty columns for `layout`, with room for `rows` rows.
    pub(crate) fn new(layout: &ulog_format::Layout, rows: usize) -> Table {
        let leaves: Vec<_> = layout.columns().collect();
        let needed = leaves
            .iter()
            .map(|l| l.offset + l.count * l.ty.size())
            .max()
            .unwrap_or(0);
        Table {
            data: leaves
                .iter()
                .map(|l| ColumnData::with_capacity(l.ty, l.kind, l.count, rows))
                .collect(),
            offsets: leaves.iter().map(|l| l.offset).collect(),
            paths: leaves.into_iter().map(|l| l.path.clone()).collect(),
            needed,
            block: Vec::new(),
        }
    }

    /// Appends the row of one payload, moving the gathered rows into the columns when
    /// the block is full. `total_rows` estimates how many rows the columns will hold
    /// in the end (0: no estimate): columns about to grow are given room for that
    /// many at once, so that they are not copied as they grow. (Room never written
    /// costs address space, not memory.)
    #[inline]
    pub(crate) fn push(&mut self, p: &[u8], total_rows: impl FnOnce(usize) -> usize) {
        if self.needed == 0 {
            return;
        }
        match p.get(..self.needed) {
            Some(row) => self.block.extend_from_slice(row),
            None => {
                let start = self.block.len();
                self.block.extend_from_slice(p);
                self.block.resize(start + self.needed, 0);
            }
        }
        if self.block.len() >= BLOCK_BYTES {
            let rows = self.block.len() / self.needed;
            let (len, capacity) = self.data.first().map_or((0, 0), |c| c.len_capacity());
            if len + rows > capacity {
                let total = total_rows(len + rows).max(len + rows);
                for column in &mut self.data {
                    column.reserve_rows(total);
                }
            }
            self.flush();
        }
    }

    /// Moves the gathered rows into the columns.
    fn flush(&mut self) {
        if self.block.is_empty() {
            return;
        }
        for (column, &offset) in self.data.iter_mut().zip(&self.offsets) {
            column.extend_from_rows(&self.block, self.needed, offset);
        }
        self.block.clear();
    }

    /// The columns, named.
    pub(crate) fn finish(mut self) -> Vec<Column> {
        self.flush();
        self.paths
            .into_iter()
            .zip(self.data)
            .map(|(path, data)| Column { path, data })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::log::ulog::ULog;
    use crate::testing::{sample_log, LogBuilder};

    #[test]
    fn columns_match_field_readers_for_every_row() {
        let bytes = sample_log();
        let log = ULog::parse(&bytes).unwrap();
        let mut checked = 0;
        for topic in log.topics() {
            let columns = topic.columns().unwrap();
            let readers = topic.fields().unwrap();
            assert_eq!(columns.len(), readers.len(), "{}", topic.name());
            for (c, r) in columns.iter().zip(&readers) {
                assert_eq!(c.path, r.path());
                assert_eq!(c.data.len(), topic.len());
                for (i, p) in topic.payloads().enumerate() {
                    assert_eq!(c.data.get(i), r.read(p), "{} row {i}", c.path);
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "only {checked} values checked");
    }

    #[test]
    fn every_type_and_strings_load_with_their_values() {
        let mut b = LogBuilder::new(1, 0);
        b.format(
            "t:uint64_t timestamp;int8_t a;uint8_t b;int16_t c;uint16_t d;int32_t e;uint32_t f;\
             int64_t g;float h;double i;bool j;char[3] s;uint8_t[2] _padding0;",
        );
        b.subscribe(0, 7, "t");
        for row in 0..3u8 {
            let mut p = Vec::new();
            p.extend_from_slice(&(100 + row as u64).to_le_bytes());
            p.push((-(row as i8)) as u8);
            p.push(row);
            p.extend_from_slice(&(-300i16 - row as i16).to_le_bytes());
            p.extend_from_slice(&(60_000u16 + row as u16).to_le_bytes());
            p.extend_from_slice(&(-70_000i32).to_le_bytes());
            p.extend_from_slice(&4_000_000_000u32.to_le_bytes());
            p.extend_from_slice(&(-5i64 * 1_000_000_000_000).to_le_bytes());
            p.extend_from_slice(&(row as f32 + 0.5).to_le_bytes());
            p.extend_from_slice(&(row as f64 * 1e300).to_le_bytes());
            p.push(row % 2);
            p.extend_from_slice(&[b'x', b'0' + row, 0]);
            if row != 1 {
                // Rows 0 and 2 with the trailing padding, row 1 without.
                p.extend_from_slice(&[0, 0]);
            }
            b.data(7, &p);
        }
        let log = ULog::parse(b.bytes()).unwrap();
        assert!(log.findings().is_empty(), "{:?}", log.findings());
        let topic = log.topic("t", 0).unwrap();
        let columns = topic.columns().unwrap();
        let paths: Vec<&str> = columns.iter().map(|c| c.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "timestamp",
                "a",
                "b",
                "c",
                "d",
                "e",
                "f",
                "g",
                "h",
                "i",
                "j",
                "s"
            ]
        );
        assert_eq!(columns[0].data, ColumnData::U64(vec![100, 101, 102]));
        assert_eq!(columns[1].data, ColumnData::I8(vec![0, -1, -2]));
        assert_eq!(columns[2].data, ColumnData::U8(vec![0, 1, 2]));
        assert_eq!(columns[3].data, ColumnData::I16(vec![-300, -301, -302]));
        assert_eq!(
            columns[4].data,
            ColumnData::U16(vec![60_000, 60_001, 60_002])
        );
        assert_eq!(columns[5].data, ColumnData::I32(vec![-70_000; 3]));
        assert_eq!(columns[6].data, ColumnData::U32(vec![4_000_000_000; 3]));
        assert_eq!(
            columns[7].data,
            ColumnData::I64(vec![-5_000_000_000_000; 3])
        );
        assert_eq!(columns[8].data, ColumnData::F32(vec![0.5, 1.5, 2.5]));
        assert_eq!(columns[9].data, ColumnData::F64(vec![0.0, 1e300, 2e300]));
        assert_eq!(columns[10].data, ColumnData::Bool(vec![false, true, false]));
        assert_eq!(
            columns[11].data,
            ColumnData::Str {
                width: 3,
                bytes: b"x0\0x1\0x2\0".to_vec()
            }
        );
        assert_eq!(columns[11].data.len(), 3);
        assert_eq!(columns[11].data.get(1), Some(Value::Str(LogText(b"x1\0"))));
        assert_eq!(columns[11].data.get(3), None);
    }
}
