//! A topic's rows as the export holds them: in blocks of [`BLOCK_BYTES`], each a
//! whole number of rows, not in one buffer.
//!
//! One buffer per row group grew by doubling to 16 MiB and was copied at each step;
//! it held up to twice the bytes the budget counted, and the allocator kept the freed
//! buffers of every size as the export went (peak RSS 1.6× the live heap on the
//! ≈300 MB logs: bench/README.md). Full blocks are all allocated at [`BLOCK_BYTES`],
//! so the allocator hands a freed one to the next block made; they are never copied,
//! and a row group of rows put aside is joined to the rows held by chaining blocks.
//! Only a topic's first block grows (and is copied) with its rows, so that a topic
//! with few rows holds few bytes. Each topic holds at most one block not full, on top
//! of the bytes its rows take.

use std::io::Read;

/// The size of a full block. Rows never straddle blocks, so a full block holds the
/// whole rows that fit (a ULog row is at most 65,535 bytes: a block holds one or
/// more). Each topic has begun one block at most; against 256 KiB, the export's peak
/// was 6–16 MiB lower on the ≈300 MB logs (bench/README.md).
pub(super) const BLOCK_BYTES: usize = 64 << 10;

/// Rows of `stride` bytes, in order, in blocks.
pub(crate) struct Rows {
    blocks: Vec<Vec<u8>>,
    stride: usize,
    /// Bytes of rows in a full block: the rows that fit in [`BLOCK_BYTES`].
    full: usize,
    /// Bytes held.
    bytes: usize,
    /// Blocks are made full size at once: this topic filled one before. A topic
    /// with few rows gets a block that grows with them, as a vector does.
    busy: bool,
}

impl Rows {
    /// No rows of `stride` bytes (at least 1).
    pub(crate) fn new(stride: usize) -> Rows {
        let stride = stride.max(1);
        Rows {
            blocks: Vec::new(),
            stride,
            full: (BLOCK_BYTES / stride).max(1) * stride,
            bytes: 0,
            busy: false,
        }
    }

    /// Bytes of a row.
    pub(crate) fn stride(&self) -> usize {
        self.stride
    }

    /// Bytes held.
    pub(crate) fn bytes(&self) -> usize {
        self.bytes
    }

    /// Rows held.
    pub(crate) fn len(&self) -> usize {
        self.bytes / self.stride
    }

    /// No rows held.
    pub(crate) fn is_empty(&self) -> bool {
        self.bytes == 0
    }

    /// Appends `row`, [`Rows::stride`] bytes.
    #[inline]
    pub(crate) fn push(&mut self, row: &[u8]) {
        debug_assert_eq!(row.len(), self.stride);
        let (stride, full) = (self.stride, self.full);
        let block = match self.blocks.last_mut() {
            Some(b) if b.len() + stride <= full => b,
            _ => self.new_block(),
        };
        if block.len() + row.len() > block.capacity() {
            // A block growing with a topic's first rows: doubling, up to full size.
            let to = (block.capacity() * 2).max(8 * stride).min(full);
            block.reserve_exact(to - block.len());
        }
        block.extend_from_slice(row);
        self.bytes += row.len();
    }

    #[cold]
    fn new_block(&mut self) -> &mut Vec<u8> {
        if !self.blocks.is_empty() {
            self.busy = true;
        }
        let capacity = if self.busy { self.block_capacity() } else { 0 };
        self.blocks.push(Vec::with_capacity(capacity));
        self.blocks.last_mut().expect("just pushed")
    }

    /// The allocation of a full block: [`BLOCK_BYTES`], or one row larger than that.
    fn block_capacity(&self) -> usize {
        self.full.max(BLOCK_BYTES)
    }

    /// The rows held, leaving none (and remembering whether blocks are made full size).
    pub(crate) fn take(&mut self) -> Rows {
        let left = Rows {
            busy: self.busy,
            ..Rows::new(self.stride)
        };
        std::mem::replace(self, left)
    }

    /// Appends the rows of `other` (of the same stride) after these.
    pub(crate) fn append(&mut self, mut other: Rows) {
        debug_assert_eq!(other.stride, self.stride);
        self.bytes += other.bytes;
        self.blocks.append(&mut other.blocks);
    }

    /// The blocks, in order: each a whole number of rows.
    pub(crate) fn blocks(&self) -> impl Iterator<Item = &[u8]> {
        self.blocks.iter().map(Vec::as_slice)
    }

    /// Each row, in order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &[u8]> + Clone {
        let stride = self.stride;
        self.blocks.iter().flat_map(move |b| b.chunks_exact(stride))
    }

    /// Reads `bytes` bytes of rows of `stride` bytes from `from` (rows earlier written
    /// from [`Rows::blocks`]); `bytes` not a whole number of rows is an error.
    pub(crate) fn read(from: &mut impl Read, bytes: usize, stride: usize) -> std::io::Result<Rows> {
        let mut rows = Rows::new(stride);
        rows.busy = true;
        if bytes % rows.stride != 0 {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("{bytes} bytes are not a whole number of rows of {stride} bytes"),
            ));
        }
        let mut left = bytes;
        while left > 0 {
            let mut block = Vec::with_capacity(rows.block_capacity());
            block.resize(left.min(rows.full), 0);
            from.read_exact(&mut block)?;
            left -= block.len();
            rows.bytes += block.len();
            rows.blocks.push(block);
        }
        Ok(rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(stride: usize, n: usize) -> Rows {
        let mut rows = Rows::new(stride);
        for i in 0..n {
            let row: Vec<u8> = (0..stride).map(|j| (i * 7 + j) as u8).collect();
            rows.push(&row);
        }
        rows
    }

    #[test]
    fn rows_come_back_in_order_and_never_straddle_blocks() {
        // 100,000 rows of 13 bytes: the first block grown, then full ones.
        let held = rows(13, 100_000);
        assert_eq!(held.len(), 100_000);
        assert_eq!(held.bytes(), 1_300_000);
        let full = BLOCK_BYTES / 13 * 13;
        let sizes: Vec<usize> = held.blocks().map(<[u8]>::len).collect();
        assert_eq!(sizes.len(), 1_300_000_usize.div_ceil(full));
        assert!(sizes.iter().all(|s| s % 13 == 0 && *s <= full), "{sizes:?}");
        assert!(held
            .blocks
            .iter()
            .skip(1)
            .all(|b| b.capacity() == BLOCK_BYTES));
        for (i, row) in held.iter().enumerate() {
            let expected: Vec<u8> = (0..13).map(|j| (i * 7 + j) as u8).collect();
            assert_eq!(row, expected, "row {i}");
        }
    }

    #[test]
    fn a_topic_with_few_rows_holds_a_small_block() {
        let held = rows(40, 3);
        assert!(
            held.blocks[0].capacity() < 4096,
            "{}",
            held.blocks[0].capacity()
        );
    }

    #[test]
    fn taken_appended_and_read_back_rows_keep_their_order() {
        let mut held = rows(9, 70_000);
        let first = held.take();
        assert!(held.is_empty());
        assert!(held.busy, "a topic that filled a block makes full ones");
        let mut bytes = Vec::new();
        for b in first.blocks() {
            bytes.extend_from_slice(b);
        }
        let mut back = Rows::read(&mut &bytes[..], bytes.len(), 9).unwrap();
        back.append(rows(9, 5));
        assert_eq!(back.len(), 70_005);
        let again: Vec<&[u8]> = back.iter().collect();
        assert_eq!(again[..70_000], first.iter().collect::<Vec<_>>()[..]);
        assert_eq!(
            again[70_000],
            &(0..9).map(|j| j as u8).collect::<Vec<_>>()[..]
        );
        let Err(error) = Rows::read(&mut &bytes[..], 10, 9) else {
            panic!("10 bytes read as rows of 9");
        };
        assert_eq!(error.kind(), std::io::ErrorKind::InvalidData);
    }

    #[test]
    fn rows_of_a_whole_block_fit_one_to_a_block() {
        let held = rows(BLOCK_BYTES, 3);
        assert_eq!(held.blocks().count(), 3);
        let wide = rows(65_535, 9);
        let per_block = (BLOCK_BYTES / 65_535).max(1);
        assert_eq!(wide.blocks().count(), 9_usize.div_ceil(per_block));
        assert!(wide.blocks().all(|b| b.len() % 65_535 == 0));
    }
}
