//! Every numeric column of a layout read into an `f64` row in one call.
//!
//! [`FieldReader`] reads one field: a type dispatch per value. A [`NumericRow`] groups a
//! layout's numeric columns by type once, into runs of adjacent values of one type
//! (`float[3]` followed by `float x` is one run of four), and reads a payload type by
//! type: one dispatch per type group, then straight loads and conversions.
//!
//! A [`NumericBlock`] goes further for a stream of one topic's payloads: it gathers
//! them (a copy of each) and reads the block one column (or two adjacent columns of
//! one type) at a time, so that the type dispatch is paid once per block and every
//! inner loop is a strided load and convert.
//! Over a whole log, a block per subscription, this costs a copy of each payload; on
//! large logs it saves more than it costs, on a few MB that stay in the CPU's caches
//! about as much (`cargo bench -p ulog-benches --bench read` measures both ways,
//! "numbers only"; `ULOG_BENCH_FILE` for a large log).

use ulog_format::{BasicType, Layout};

use crate::access::field::{FieldReader, FieldShape};

/// Calls `$fill` with the function that reads one value of type `$ty` from its
/// little-endian bytes (a `[u8; N]` of the type's size).
macro_rules! dispatch {
    ($ty:expr, |$read:ident| $fill:expr) => {
        match $ty {
            BasicType::Int8 => {
                let $read = |b: [u8; 1]| f64::from(b[0] as i8);
                $fill
            }
            BasicType::UInt8 | BasicType::Char => {
                let $read = |b: [u8; 1]| f64::from(b[0]);
                $fill
            }
            BasicType::Bool => {
                let $read = |b: [u8; 1]| f64::from(u8::from(b[0] != 0));
                $fill
            }
            BasicType::Int16 => {
                let $read = |b: [u8; 2]| f64::from(i16::from_le_bytes(b));
                $fill
            }
            BasicType::UInt16 => {
                let $read = |b: [u8; 2]| f64::from(u16::from_le_bytes(b));
                $fill
            }
            BasicType::Int32 => {
                let $read = |b: [u8; 4]| f64::from(i32::from_le_bytes(b));
                $fill
            }
            BasicType::UInt32 => {
                let $read = |b: [u8; 4]| f64::from(u32::from_le_bytes(b));
                $fill
            }
            BasicType::Float => {
                let $read = |b: [u8; 4]| f64::from(f32::from_le_bytes(b));
                $fill
            }
            BasicType::Int64 => {
                let $read = |b: [u8; 8]| i64::from_le_bytes(b) as f64;
                $fill
            }
            BasicType::UInt64 => {
                let $read = |b: [u8; 8]| u64::from_le_bytes(b) as f64;
                $fill
            }
            BasicType::Double => {
                let $read = |b: [u8; 8]| f64::from_le_bytes(b);
                $fill
            }
        }
    };
}

/// The numeric columns (numbers, booleans and single `char`s; `char[N]` strings and
/// padding left out) of a layout, read from a payload into an `f64` row.
///
/// Column `i` of the row is [`NumericRow::columns`]`[i]`, in payload order. Booleans
/// read as 0 or 1, 64-bit integers are rounded to the nearest `f64`.
///
/// ```
/// use ulog_core::format::{Format, Resolver};
/// let f = Format::parse("t:uint64_t timestamp;float[2] v;int16_t k;char[3] s;bool b;").unwrap();
/// let layout = Resolver::default().resolve("t", &[f][..]).unwrap();
/// let numbers = ulog_core::columns::NumericRow::of(&layout);
/// let paths: Vec<&str> = numbers.columns().iter().map(|c| c.path()).collect();
/// assert_eq!(paths, ["timestamp", "v[0]", "v[1]", "k", "b"]);
///
/// let mut payload = Vec::new();
/// payload.extend(7u64.to_le_bytes());
/// payload.extend(1.5f32.to_le_bytes());
/// payload.extend((-2.0f32).to_le_bytes());
/// payload.extend((-3i16).to_le_bytes());
/// payload.extend(b"abc");
/// payload.push(1);
/// let mut row = vec![0.0; numbers.width()];
/// assert!(numbers.read(&payload, &mut row));
/// assert_eq!(row, [7.0, 1.5, -2.0, -3.0, 1.0]);
/// ```
#[derive(Debug, Clone)]
pub struct NumericRow {
    columns: Vec<FieldReader>,
    groups: Vec<Group>,
    /// Where the last numeric column ends: a payload this long holds them all.
    end: usize,
}

/// The runs of one type.
#[derive(Debug, Clone)]
struct Group {
    ty: BasicType,
    runs: Vec<Run>,
}

/// `count` adjacent values of one type: payload bytes from `offset`, row slots from
/// `column`.
#[derive(Debug, Clone, Copy)]
struct Run {
    offset: usize,
    column: usize,
    count: usize,
}

impl NumericRow {
    /// The numeric columns of `layout`, grouped by type.
    pub fn of(layout: &Layout) -> NumericRow {
        let columns: Vec<FieldReader> = FieldReader::all(layout)
            .into_iter()
            .filter(|c| c.shape() == FieldShape::Scalar)
            .collect();
        let mut groups: Vec<Group> = Vec::new();
        for (column, c) in columns.iter().enumerate() {
            let ty = c.ty();
            let at = match groups.iter().position(|g| g.ty == ty) {
                Some(at) => at,
                None => {
                    groups.push(Group {
                        ty,
                        runs: Vec::new(),
                    });
                    groups.len() - 1
                }
            };
            let runs = &mut groups[at].runs;
            match runs.last_mut() {
                Some(r)
                    if r.column + r.count == column
                        && r.offset + r.count * ty.size() == c.offset() =>
                {
                    r.count += 1
                }
                _ => runs.push(Run {
                    offset: c.offset(),
                    column,
                    count: 1,
                }),
            }
        }
        let end = columns
            .iter()
            .map(|c| c.offset() + c.ty().size())
            .max()
            .unwrap_or(0);
        NumericRow {
            columns,
            groups,
            end,
        }
    }

    /// Number of numeric columns: the length of a row.
    pub fn width(&self) -> usize {
        self.columns.len()
    }

    /// The readers of the numeric columns, in row order (for their paths and types).
    pub fn columns(&self) -> &[FieldReader] {
        &self.columns
    }

    /// Reads every numeric column of every payload into `values` (set to
    /// `payloads.len() × width` values, row-major), column by column: the type
    /// dispatch is paid once for all the payloads (see [`NumericBlock`], which gathers
    /// them). A value past a payload's end reads as NaN.
    ///
    /// ```
    /// use ulog_core::format::{Format, Resolver};
    /// let f = Format::parse("t:uint64_t timestamp;int8_t k;").unwrap();
    /// let layout = Resolver::default().resolve("t", &[f][..]).unwrap();
    /// let numbers = ulog_core::columns::NumericRow::of(&layout);
    /// let (a, b) = ([&5u64.to_le_bytes()[..], &[0xff]].concat(), 6u64.to_le_bytes());
    /// let mut values = Vec::new();
    /// numbers.read_rows(&[&a[..], &b[..]], &mut values);
    /// assert_eq!(values[..3], [5.0, -1.0, 6.0]);
    /// assert!(values[3].is_nan(), "the second payload stops before `k`");
    /// ```
    pub fn read_rows(&self, payloads: &[&[u8]], values: &mut Vec<f64>) {
        // Every value is written: only a change of length is filled.
        values.resize(payloads.len() * self.columns.len(), 0.0);
        self.fill(payloads.iter().copied(), values);
    }

    /// Reads the payloads into `values` (of their number × width), column by column.
    #[inline]
    fn fill<'p>(&self, payloads: impl Iterator<Item = &'p [u8]> + Clone, values: &mut [f64]) {
        let width = self.columns.len();
        if width == 0 {
            return;
        }
        for g in &self.groups {
            dispatch!(g.ty, |read| fill_rows(
                &g.runs,
                payloads.clone(),
                width,
                values,
                read
            ));
        }
    }

    /// Reads payloads of `stride` bytes each, laid end to end in `bytes`, into `values`
    /// (of their number × width), column by column. Every column lies inside a payload
    /// when `stride` reaches `end` (a block's stride, the layout's minimum size, does);
    /// a shorter stride reads as [`NumericRow::fill`] does, NaN past the end.
    #[inline]
    fn fill_block(&self, bytes: &[u8], stride: usize, values: &mut [f64]) {
        let width = self.columns.len();
        if width == 0 || stride < self.end {
            return self.fill(bytes.chunks_exact(stride.max(1)), values);
        }
        for g in &self.groups {
            dispatch!(g.ty, |read| fill_strided(
                &g.runs, bytes, stride, width, values, read
            ));
        }
    }

    /// Reads every numeric column of `payload` into `row[..width]`. A column the
    /// payload is too short for (a message cut short) reads as NaN, and the result is
    /// then `false`.
    ///
    /// # Panics
    /// If `row` is shorter than [`NumericRow::width`].
    #[inline]
    pub fn read(&self, payload: &[u8], row: &mut [f64]) -> bool {
        let row = &mut row[..self.columns.len()];
        let mut whole = true;
        for g in &self.groups {
            whole &= dispatch!(g.ty, |read| fill(&g.runs, payload, row, read));
        }
        whole
    }
}

/// Payloads of one layout gathered into a block, then read into `f64` rows all at once,
/// column by column (see the module documentation).
///
/// Each payload is copied up to the layout's [`Layout::min_size`] (its trailing padding
/// left out): every numeric column lies inside. A shorter payload (a message cut short)
/// reads as NaN in the columns it does not reach.
///
/// ```
/// use ulog_core::format::{Format, Resolver};
/// let f = Format::parse("t:uint64_t timestamp;int16_t[2] v;").unwrap();
/// let layout = Resolver::default().resolve("t", &[f][..]).unwrap();
/// let mut block = ulog_core::columns::NumericBlock::with_capacity(&layout, 2);
/// let payload = |t: u64, a: i16, b: i16| -> Vec<u8> {
///     [&t.to_le_bytes()[..], &a.to_le_bytes(), &b.to_le_bytes()].concat()
/// };
/// assert!(!block.push(&payload(10, 1, -1)));
/// assert!(block.push(&payload(20, 2, -2)), "full after two");
/// let rows = block.decode();
/// assert_eq!(rows.values(), [10.0, 1.0, -1.0, 20.0, 2.0, -2.0]);
/// assert_eq!(rows.row(1), [20.0, 2.0, -2.0]);
/// assert!(block.is_empty(), "decoding empties the block");
/// ```
#[derive(Debug, Clone)]
pub struct NumericBlock {
    numbers: NumericRow,
    /// Bytes kept per payload.
    stride: usize,
    capacity: usize,
    /// Payloads gathered, `rows × stride` bytes.
    bytes: Vec<u8>,
    rows: usize,
    /// Payloads shorter than the stride: (row, length).
    short: Vec<(usize, usize)>,
    /// The rows last decoded (kept while no payload is pending: `bytes` and `short`
    /// then hold their payloads, until the next push).
    values: Vec<f64>,
}

/// Rows a block holds by default.
const BLOCK_ROWS: usize = 64;

/// The most a block holds in payload bytes and values, whatever its capacity in rows
/// (a wide format gets fewer rows, at least one).
const BLOCK_BYTES: usize = 64 << 10;

impl NumericBlock {
    /// A block of 64 payloads of `layout` (fewer for payloads over 1 KiB: a block
    /// holds at most 64 KiB of payloads and values).
    pub fn new(layout: &Layout) -> NumericBlock {
        NumericBlock::with_capacity(layout, BLOCK_ROWS)
    }

    /// A block of `capacity` payloads of `layout`: at least one, and no more than fit
    /// in 64 KiB of payloads and values. Memory is taken at the first push.
    pub fn with_capacity(layout: &Layout, capacity: usize) -> NumericBlock {
        let stride = layout.min_size();
        let numbers = NumericRow::of(layout);
        let row_bytes = stride.saturating_add(numbers.width().saturating_mul(8));
        let capacity = capacity.min(BLOCK_BYTES / row_bytes.max(1)).max(1);
        NumericBlock {
            bytes: Vec::new(),
            values: Vec::new(),
            numbers,
            stride,
            capacity,
            rows: 0,
            short: Vec::new(),
        }
    }

    /// Payloads the block holds when full.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// The numeric columns a row holds.
    pub fn numbers(&self) -> &NumericRow {
        &self.numbers
    }

    /// Payloads gathered and not yet decoded.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// Whether no payload waits to be decoded.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// Adds a payload; `true` when the block is then full (decode it before the next
    /// push, or that push decodes nothing and grows the block past its capacity).
    #[inline]
    pub fn push(&mut self, payload: &[u8]) -> bool {
        if self.rows == 0 {
            self.forget_decoded();
            if self.bytes.capacity() == 0 {
                self.bytes.reserve_exact(self.stride * self.capacity);
            }
        }
        match payload.get(..self.stride) {
            Some(kept) => self.bytes.extend_from_slice(kept),
            None => {
                self.short.push((self.rows, payload.len()));
                self.bytes.extend_from_slice(payload);
                let end = self.bytes.len() + self.stride - payload.len();
                self.bytes.resize(end, 0);
            }
        }
        self.rows += 1;
        self.rows >= self.capacity
    }

    /// Reads every payload gathered into rows, and empties the block. The rows (and the
    /// payloads they were read from) stay readable until the block is next changed.
    pub fn decode(&mut self) -> NumericRows<'_> {
        if self.rows == 0 {
            self.forget_decoded();
        }
        let width = self.numbers.width();
        let n = self.rows;
        // Every value is written below: only a change of length is filled.
        self.values.resize(n * width, 0.0);
        if width > 0 && self.stride > 0 {
            self.numbers.fill_block(
                &self.bytes[..n * self.stride],
                self.stride,
                &mut self.values,
            );
            // A short payload was zero-filled to the stride: read again as it came
            // (NaN past its end).
            for &(row, len) in &self.short {
                let payload = &self.bytes[row * self.stride..row * self.stride + len];
                self.numbers.read(payload, &mut self.values[row * width..]);
            }
        }
        self.rows = 0;
        NumericRows {
            width,
            stride: self.stride,
            count: n,
            values: &self.values,
            bytes: &self.bytes,
            short: &self.short,
            end: self.numbers.end,
        }
    }
}

impl NumericBlock {
    /// Drops the payloads of the rows last decoded (called with no payload pending).
    #[inline]
    fn forget_decoded(&mut self) {
        self.bytes.clear();
        self.short.clear();
    }
}

/// The rows a [`NumericBlock`] decoded: `len() × width()` values, row-major.
#[derive(Debug, Clone, Copy)]
pub struct NumericRows<'b> {
    width: usize,
    stride: usize,
    count: usize,
    values: &'b [f64],
    bytes: &'b [u8],
    /// Rows whose payload was shorter than the stride: (row, length), by row.
    short: &'b [(usize, usize)],
    /// Where the last numeric column ends.
    end: usize,
}

impl<'b> NumericRows<'b> {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Values per row (the block's [`NumericRow::width`]).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Every value, row after row.
    pub fn values(&self) -> &'b [f64] {
        self.values
    }

    /// Row `i`.
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn row(&self, i: usize) -> &'b [f64] {
        assert!(i < self.count, "row {i} of {}", self.count);
        &self.values[i * self.width..(i + 1) * self.width]
    }

    /// The payload row `i` was read from, as kept: its first [`Layout::min_size`] bytes
    /// (its trailing padding left out), or all of it if shorter; for its `char[N]`
    /// strings.
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn payload(&self, i: usize) -> &'b [u8] {
        assert!(i < self.count, "row {i} of {}", self.count);
        let len = match self.short.binary_search_by_key(&i, |&(row, _)| row) {
            Ok(at) => self.short[at].1,
            Err(_) => self.stride,
        };
        &self.bytes[i * self.stride..i * self.stride + len]
    }

    /// Whether row `i`'s payload held every numeric column (`false`: a message cut
    /// short, whose missing values read as NaN).
    ///
    /// # Panics
    /// If `i >= len()`.
    pub fn is_whole(&self, i: usize) -> bool {
        assert!(i < self.count, "row {i} of {}", self.count);
        self.payload(i).len() >= self.end
    }
}

/// Reads the runs of one type whose values are `N` bytes from every payload into its
/// row (`width` values each), column by column; a value past a payload's end reads
/// as NaN.
#[inline(always)]
fn fill_rows<'p, const N: usize>(
    runs: &[Run],
    payloads: impl Iterator<Item = &'p [u8]> + Clone,
    width: usize,
    values: &mut [f64],
    read: impl Fn([u8; N]) -> f64,
) {
    for r in runs {
        for k in 0..r.count {
            let at = r.offset + k * N;
            let column = r.column + k;
            for (p, row) in payloads.clone().zip(values.chunks_exact_mut(width)) {
                row[column] = match p.get(at..at + N) {
                    Some(b) => read(b.try_into().unwrap_or([0; N])),
                    None => f64::NAN,
                };
            }
        }
    }
}

/// [`fill_rows`] over payloads of `stride` bytes that all hold every run, so that no
/// value needs a NaN fallback (a run outside the stride would be a bug here, and
/// panics), two adjacent columns of a run at a time: one load of both, and on x86_64
/// one conversion of two `float`s (bench/README.md has what it saved).
#[inline(always)]
fn fill_strided<const N: usize>(
    runs: &[Run],
    bytes: &[u8],
    stride: usize,
    width: usize,
    values: &mut [f64],
    read: impl Fn([u8; N]) -> f64,
) {
    let get = |b: &[u8]| -> [u8; N] { b.try_into().unwrap_or([0; N]) };
    for r in runs {
        let mut k = 0;
        while k < r.count {
            let at = r.offset + k * N;
            let column = r.column + k;
            let rows = bytes
                .chunks_exact(stride)
                .zip(values.chunks_exact_mut(width));
            if k + 1 < r.count {
                for (p, row) in rows {
                    let (b, slots) = (&p[at..at + 2 * N], &mut row[column..column + 2]);
                    slots[0] = read(get(&b[..N]));
                    slots[1] = read(get(&b[N..]));
                }
                k += 2;
            } else {
                for (p, row) in rows {
                    row[column] = read(get(&p[at..at + N]));
                }
                k += 1;
            }
        }
    }
}

/// Reads the runs of one type whose values are `N` bytes; `false` if some value is
/// past the payload's end (NaN in its slot).
#[inline(always)]
fn fill<const N: usize>(
    runs: &[Run],
    payload: &[u8],
    row: &mut [f64],
    read: impl Fn([u8; N]) -> f64,
) -> bool {
    let mut whole = true;
    for r in runs {
        let slots = &mut row[r.column..r.column + r.count];
        match payload.get(r.offset..r.offset + r.count * N) {
            Some(bytes) if r.count == 1 => slots[0] = read(bytes.try_into().unwrap_or([0; N])),
            Some(bytes) => {
                for (slot, b) in slots.iter_mut().zip(bytes.chunks_exact(N)) {
                    *slot = read(b.try_into().unwrap_or([0; N]));
                }
            }
            None => {
                whole = false;
                for (k, slot) in slots.iter_mut().enumerate() {
                    let at = r.offset + k * N;
                    *slot = match payload.get(at..at + N) {
                        Some(b) => read(b.try_into().unwrap_or([0; N])),
                        None => f64::NAN,
                    };
                }
            }
        }
    }
    whole
}

#[cfg(test)]
mod tests {
    use super::*;
    use ulog_format::{Format, Resolver};

    fn layout(text: &str, nested: &[&str]) -> std::sync::Arc<Layout> {
        let mut formats = vec![Format::parse(text).unwrap()];
        formats.extend(nested.iter().map(|n| Format::parse(n).unwrap()));
        let name = text.split(':').next().unwrap();
        Resolver::default().resolve(name, &formats[..]).unwrap()
    }

    /// Deterministic pseudo-random bytes.
    fn bytes(n: usize, mut seed: u64) -> Vec<u8> {
        (0..n)
            .map(|_| {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                seed as u8
            })
            .collect()
    }

    /// The row equals the one-field-at-a-time readers' values, bit for bit.
    fn check_against_readers(l: &Layout, payload: &[u8]) -> bool {
        let numbers = NumericRow::of(l);
        let mut row = vec![0.0; numbers.width() + 2];
        let whole = numbers.read(payload, &mut row);
        assert_eq!(row[numbers.width()..], [0.0, 0.0], "nothing past the width");
        for (c, v) in numbers.columns().iter().zip(&row) {
            match c.read_f64(payload) {
                Some(want) => assert_eq!(v.to_bits(), want.to_bits(), "{}", c.path()),
                None => assert!(v.is_nan(), "{}", c.path()),
            }
        }
        whole
    }

    #[test]
    fn every_type_nested_arrays_and_padding_read_as_field_readers_do() {
        let l = layout(
            "t:uint64_t timestamp;int8_t a;uint8_t b;int16_t c;uint16_t d;int32_t e;\
             uint32_t f;int64_t g;float[3] h;double i;bool j;char k;char[5] s;\
             inner[2] n;uint8_t[3] _padding0;float tail;",
            &["inner:float x;uint8_t y;uint8_t[3] _padding0;float z;"],
        );
        let numbers = NumericRow::of(&l);
        assert_eq!(numbers.width(), FieldReader::all(&l).len() - 1);
        for seed in 1..200 {
            let payload = bytes(l.size(), seed);
            assert!(check_against_readers(&l, &payload));
        }
    }

    #[test]
    fn adjacent_values_of_one_type_form_one_run() {
        let l = layout(
            "t:uint64_t timestamp;float[3] a;float b;uint32_t c;float[2] d;inner[2] n;",
            &["inner:float x;float y;"],
        );
        let numbers = NumericRow::of(&l);
        let runs: Vec<(BasicType, usize, usize, usize)> = numbers
            .groups
            .iter()
            .flat_map(|g| g.runs.iter().map(|r| (g.ty, r.offset, r.column, r.count)))
            .collect();
        assert_eq!(
            runs,
            [
                (BasicType::UInt64, 0, 0, 1),
                (BasicType::Float, 8, 1, 4),
                (BasicType::Float, 28, 6, 6),
                (BasicType::UInt32, 24, 5, 1),
            ]
        );
    }

    #[test]
    fn a_short_payload_reads_what_it_has_and_nan_for_the_rest() {
        let l = layout("t:uint64_t timestamp;float[4] q;uint16_t k;", &[]);
        let full = bytes(l.size(), 9);
        for len in 0..l.size() {
            let whole = check_against_readers(&l, &full[..len]);
            assert_eq!(whole, len == l.size(), "{len}");
        }
        assert!(check_against_readers(&l, &full));
    }

    #[test]
    fn a_layout_without_numbers_has_an_empty_row() {
        let l = layout("t:char[8] name;", &[]);
        let numbers = NumericRow::of(&l);
        assert_eq!(numbers.width(), 0);
        assert!(numbers.read(b"abcdefgh", &mut []));
    }

    /// Decodes `payloads` through a block of `capacity`, decoding whenever it reports
    /// full and at the end; every row must equal [`NumericRow::read`] of its payload, bit
    /// for bit (NaN where the row reader gives NaN), and keep the payload's bytes.
    fn check_block(l: &Layout, payloads: &[Vec<u8>], capacity: usize) {
        let numbers = NumericRow::of(l);
        let mut block = NumericBlock::with_capacity(l, capacity);
        let mut seen = 0;
        let check = |rows: NumericRows<'_>, seen: &mut usize| {
            assert_eq!(rows.width(), numbers.width());
            assert_eq!(rows.values().len(), rows.len() * rows.width());
            for i in 0..rows.len() {
                let p = &payloads[*seen];
                let mut want = vec![0.0; numbers.width()];
                let whole = numbers.read(p, &mut want);
                assert_eq!(rows.is_whole(i), whole, "payload {seen}");
                let got: Vec<u64> = rows.row(i).iter().map(|v| v.to_bits()).collect();
                let want: Vec<u64> = want.iter().map(|v| v.to_bits()).collect();
                assert_eq!(got, want, "payload {seen}");
                assert_eq!(rows.payload(i), &p[..p.len().min(l.min_size())]);
                *seen += 1;
            }
        };
        for p in payloads {
            let full = block.push(p);
            assert_eq!(full, block.len() == block.capacity());
            if full {
                check(block.decode(), &mut seen);
                assert!(block.is_empty());
            }
        }
        check(block.decode(), &mut seen);
        assert_eq!(seen, payloads.len());
        assert!(block.decode().is_empty(), "a second decode has nothing");
    }

    #[test]
    fn a_block_reads_as_a_row_per_payload_does() {
        let l = layout(
            "t:uint64_t timestamp;int8_t a;uint8_t b;int16_t c;uint16_t d;int32_t e;\
             uint32_t f;int64_t g;float[3] h;double i;bool j;char k;char[5] s;\
             inner[2] n;uint8_t[3] _padding0;float tail;uint8_t[5] _padding1;",
            &["inner:float x;uint8_t y;uint8_t[3] _padding0;float z;"],
        );
        assert!(
            l.min_size() < l.size(),
            "the trailing padding may be left out"
        );
        // Full payloads, payloads without their trailing padding, and short ones.
        let mut payloads = Vec::new();
        for seed in 1..300u64 {
            let len = match seed % 7 {
                0 => (seed as usize * 13) % l.min_size(),
                1 | 2 => l.min_size(),
                _ => l.size(),
            };
            payloads.push(bytes(len, seed));
        }
        for capacity in [0, 1, 2, 5, 64, 1000, usize::MAX] {
            check_block(&l, &payloads, capacity);
        }
    }

    #[test]
    fn a_block_reads_runs_of_every_length_and_type_as_rows_do() {
        // Runs of one to five values of every type (read two columns at a time with
        // one left over, or not), at odd offsets too: a `char` between them; and runs of
        // `char`s.
        let types = [
            "int8_t", "uint8_t", "bool", "int16_t", "uint16_t", "int32_t", "uint32_t", "float",
            "int64_t", "uint64_t", "double",
        ];
        let mut text = String::from("t:uint64_t timestamp;");
        for (i, ty) in types.iter().enumerate() {
            for n in 1..=5 {
                text += &format!("{ty}[{n}] a{i}_{n};char b{i}_{n};");
            }
        }
        text += "char c0;float f;char d0;char d1;char d2;";
        let l = layout(&text, &[]);
        let numbers = NumericRow::of(&l);
        assert_eq!(
            numbers.end,
            l.min_size(),
            "every payload of the stride holds every run"
        );
        assert_eq!(numbers.groups.len(), types.len() + 1, "and the `char`s");
        for g in &numbers.groups {
            let counts: Vec<usize> = g.runs.iter().map(|r| r.count).collect();
            assert!(counts.iter().any(|c| c % 2 == 0), "{:?}: {counts:?}", g.ty);
            assert!(counts.iter().any(|c| c % 2 == 1 && *c > 1), "{:?}", g.ty);
        }
        let mut payloads = Vec::new();
        for seed in 1..200u64 {
            let len = match seed % 5 {
                0 => (seed as usize * 31) % l.min_size(),
                _ => l.size(),
            };
            payloads.push(bytes(len, seed));
        }
        for capacity in [1, 3, 64] {
            check_block(&l, &payloads, capacity);
        }
    }

    /// Payloads laid end to end with a stride shorter than the numeric columns (which a
    /// block never has) read as a row per payload does: NaN past each one's end.
    #[test]
    fn a_stride_short_of_the_columns_reads_nan_past_it() {
        let l = layout("t:uint64_t timestamp;float[3] v;int16_t k;", &[]);
        let numbers = NumericRow::of(&l);
        for stride in [1, 9, 13, 17, 21] {
            assert!(stride < numbers.end);
            let bytes = bytes(stride * 5, stride as u64);
            let mut values = vec![7.0; 5 * numbers.width()];
            numbers.fill_block(&bytes, stride, &mut values);
            for (p, got) in bytes
                .chunks_exact(stride)
                .zip(values.chunks_exact(numbers.width()))
            {
                let mut want = vec![0.0; numbers.width()];
                assert!(!numbers.read(p, &mut want));
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(got), bits(&want), "stride {stride}");
            }
        }
    }

    #[test]
    fn a_block_without_numbers_keeps_the_strings() {
        let l = layout("t:char[4] name;", &[]);
        let mut block = NumericBlock::with_capacity(&l, 3);
        block.push(b"abcd");
        block.push(b"xy");
        let rows = block.decode();
        assert_eq!((rows.len(), rows.width()), (2, 0));
        assert_eq!(rows.payload(0), b"abcd");
        assert_eq!(rows.payload(1), b"xy");
        assert!(rows.is_whole(1), "no numbers to miss");
        assert!(rows.row(1).is_empty());
    }

    #[test]
    fn a_block_holds_at_most_64_kib() {
        let small = layout("t:uint64_t timestamp;float[4] q;", &[]);
        assert_eq!(NumericBlock::new(&small).capacity(), 64);
        assert_eq!(NumericBlock::with_capacity(&small, 5).capacity(), 5);
        // 24 payload bytes and 5 values a row: 64 KiB / 64 bytes.
        assert_eq!(
            NumericBlock::with_capacity(&small, usize::MAX).capacity(),
            1024
        );
        let wide = layout("t:uint64_t timestamp;uint8_t[60000] x;", &[]);
        let mut block = NumericBlock::new(&wide);
        assert_eq!(block.capacity(), 1);
        let payload = bytes(wide.size(), 3);
        assert!(block.push(&payload));
        let rows = block.decode();
        assert_eq!((rows.len(), rows.width()), (1, 60001));
        assert_eq!(rows.row(0)[60000], f64::from(payload[60007]));
    }

    #[test]
    fn a_row_is_whole_when_only_strings_or_padding_are_cut() {
        let l = layout("t:uint64_t timestamp;char[6] s;", &[]);
        let mut block = NumericBlock::new(&l);
        for len in [14, 8, 7, 0] {
            block.push(&bytes(len, 5)[..]);
        }
        let rows = block.decode();
        let whole: Vec<bool> = (0..rows.len()).map(|i| rows.is_whole(i)).collect();
        assert_eq!(whole, [true, true, false, false]);
        assert!(rows.row(2)[0].is_nan());
        assert_eq!(rows.payload(2).len(), 7);
    }

    #[test]
    fn read_rows_reads_as_a_row_per_payload_does() {
        let l = layout(
            "t:uint64_t timestamp;int16_t[3] a;float b;bool c;char[3] s;double d;uint8_t[2] _padding0;",
            &[],
        );
        let numbers = NumericRow::of(&l);
        let payloads: Vec<Vec<u8>> = (0..100u64)
            .map(|seed| bytes((seed as usize * 7) % (l.size() + 5), seed + 1))
            .collect();
        let refs: Vec<&[u8]> = payloads.iter().map(Vec::as_slice).collect();
        // Stale values from a longer call are overwritten.
        let mut values = vec![7.0; 3 * refs.len() * numbers.width()];
        numbers.read_rows(&refs, &mut values);
        assert_eq!(values.len(), refs.len() * numbers.width());
        for (p, got) in refs.iter().zip(values.chunks_exact(numbers.width())) {
            let mut want = vec![0.0; numbers.width()];
            numbers.read(p, &mut want);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(got), bits(&want), "{} bytes", p.len());
        }
        numbers.read_rows(&[], &mut values);
        assert!(values.is_empty());
    }
}
