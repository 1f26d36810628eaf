//! The incremental reader: messages yielded as they complete, from chunks pushed in
//! (a socket, a log still being written) or pulled from any `Read`, in bounded memory.
//!
//! It runs the same framing as [`ULog::parse`](crate::ULog::parse), so it takes the
//! same decisions on damaged input. It holds at most the bytes framing still needs: one
//! unfinished message, plus, while it judges damage, the next two messages it checks
//! (at most 3 × 65,538 bytes), plus the caller's chunk.

use std::io::Read;
use std::sync::Arc;

use ulog_format::Layout;

use crate::error::{Error, ErrorKind, Result};
use crate::finding::Finding;
use crate::read::framing::{Framer, Header, Record, Step, MSG_HEADER_LEN};
use crate::read::iter::MessageAt;
use crate::read::message::Message;
use crate::read::source::read_some;

/// What [`Incremental::advance`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// A message is ready: read it with [`Incremental::current`].
    Ready,
    /// More bytes are needed (or [`Incremental::finish`] if there are none).
    NeedMore,
    /// The end: every message has been yielded.
    End,
}

/// A push-driven incremental reader.
///
/// ```
/// use ulog_core::{Incremental, Status};
/// # let bytes = ulog_core::testing::sample_log();
/// let mut reader = Incremental::new();
/// let mut count = 0;
/// for chunk in bytes.chunks(100) {
///     reader.push(chunk);
///     while reader.advance()? == Status::Ready {
///         count += 1;
///     }
/// }
/// reader.finish();
/// while reader.advance()? == Status::Ready {
///     count += 1;
/// }
/// assert_eq!(count, ulog_core::ULog::parse(&bytes)?.message_count());
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub struct Incremental {
    buf: Vec<u8>,
    base: u64,
    eof: bool,
    framer: Framer,
    current: Option<Record>,
    ended: bool,
}

impl Default for Incremental {
    fn default() -> Incremental {
        Incremental::new()
    }
}

impl Incremental {
    /// A reader that has seen no bytes yet.
    pub fn new() -> Incremental {
        Incremental {
            buf: Vec::new(),
            base: 0,
            eof: false,
            framer: Framer::new(),
            current: None,
            ended: false,
        }
    }

    /// Adds the next bytes of the file. (The message of the last
    /// [`advance`](Incremental::advance) is no longer available after this.)
    pub fn push(&mut self, chunk: &[u8]) {
        self.current = None;
        self.compact();
        self.buf.extend_from_slice(chunk);
    }

    /// Says that no more bytes will come.
    pub fn finish(&mut self) {
        self.eof = true;
    }

    fn compact(&mut self) {
        let drop = self.framer.done_with(self.base, self.buf.len());
        if drop > 0 {
            self.buf.drain(..drop);
            self.base += drop as u64;
        }
    }

    /// Frames the next message, if the bytes so far hold it.
    pub fn advance(&mut self) -> Result<Status> {
        self.current = None;
        if self.ended {
            return Ok(Status::End);
        }
        match self.framer.step(&self.buf, self.base, self.eof)? {
            Step::Record(r) => {
                self.current = Some(r);
                Ok(Status::Ready)
            }
            Step::NeedMore => Ok(Status::NeedMore),
            Step::End => {
                self.ended = true;
                Ok(Status::End)
            }
        }
    }

    /// The message that the last [`advance`](Incremental::advance) made ready.
    pub fn current(&self) -> Option<MessageAt<'_>> {
        let r = self.current?;
        let start = (r.offset - self.base) as usize + MSG_HEADER_LEN;
        let payload = &self.buf[start..start + r.size as usize];
        Some(MessageAt {
            offset: r.offset,
            message: Message::from_record(&r, payload, self.framer.flag_bits),
        })
    }

    /// The file header, once read.
    pub fn header(&self) -> Option<Header> {
        self.framer.header
    }

    /// What was found and stepped over so far.
    pub fn findings(&self) -> &[Finding] {
        &self.framer.findings
    }

    /// The topic name, multi_id and layout of the subscription `msg_id` refers to now.
    pub fn subscription(&self, msg_id: u16) -> Option<(&str, u8, Option<&Arc<Layout>>)> {
        let i = self.framer.sub_index(msg_id)?;
        let s = &self.framer.subs[i as usize];
        Some((&s.name, s.multi_id, s.layout.as_ref().ok()))
    }

    /// Bytes currently buffered (for checking the memory bound).
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }
}

/// An incremental reader pulling from any `Read`.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut reader = ulog_core::StreamReader::new(&bytes[..]);
/// let mut data_messages = 0;
/// while let Some(m) = reader.next_message()? {
///     if let ulog_core::Message::Data { .. } = m.message {
///         data_messages += 1;
///     }
/// }
/// assert!(data_messages > 0);
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub struct StreamReader<R> {
    src: R,
    inner: Incremental,
    chunk: Vec<u8>,
}

impl<R: Read> StreamReader<R> {
    /// A reader over `src`, reading 64 KiB at a time.
    pub fn new(src: R) -> StreamReader<R> {
        StreamReader::with_chunk_size(src, 64 * 1024)
    }

    /// A reader over `src`, reading `chunk` bytes at a time.
    pub fn with_chunk_size(src: R, chunk: usize) -> StreamReader<R> {
        StreamReader {
            src,
            inner: Incremental::new(),
            chunk: vec![0; chunk.max(1)],
        }
    }

    /// The next message, or `None` at the end.
    pub fn next_message(&mut self) -> Result<Option<MessageAt<'_>>> {
        loop {
            match self.inner.advance()? {
                Status::Ready => break,
                Status::End => return Ok(None),
                Status::NeedMore => {
                    let n = read_some(&mut self.src, &mut self.chunk).map_err(|e| {
                        Error::new(
                            ErrorKind::Io(e.to_string()),
                            self.inner.base + self.inner.buf.len() as u64,
                        )
                    })?;
                    if n == 0 {
                        self.inner.finish();
                    } else {
                        self.inner.push(&self.chunk[..n]);
                    }
                }
            }
        }
        Ok(self.inner.current())
    }

    /// The underlying incremental reader (header, findings, subscriptions).
    pub fn state(&self) -> &Incremental {
        &self.inner
    }
}
