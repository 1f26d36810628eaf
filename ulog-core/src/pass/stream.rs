//! The incremental reader: messages yielded as they complete, from chunks pushed in
//! (a socket, a log still being written) or pulled from any `Read`, in bounded memory.
//!
//! [`PushReader`] takes chunks as they come; [`StreamReader`] pulls them from a `Read`.
//! Both run the same framing as [`ULog::parse`](crate::ULog::parse), so they take the
//! same decisions on damaged input. It holds at most the bytes framing still needs: one
//! unfinished message, plus, while it judges damage, the next two messages it checks
//! (at most 3 × 65,538 bytes), plus the caller's chunk.

use std::io::Read;
use std::sync::Arc;

use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::framing::{Framer, Header, Record, Step};
use crate::log::message::Message;
use crate::log::messages::MessageAt;
use crate::pass::source::read_some;

/// What [`PushReader::advance`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// A message is ready: read it with [`PushReader::current`].
    Ready,
    /// More bytes are needed (or [`PushReader::finish`] if there are none).
    NeedMore,
    /// The end: every message has been yielded.
    End,
}

/// An incremental reader fed the log's bytes as they arrive (a socket, a log still
/// being written): each message is yielded once its bytes are there.
///
/// ```
/// use ulog_core::stream::{Progress, PushReader};
/// # let bytes = ulog_core::testing::sample_log();
/// let mut reader = PushReader::new();
/// let mut count = 0;
/// for chunk in bytes.chunks(100) {
///     reader.push(chunk);
///     while reader.advance()? == Progress::Ready {
///         count += 1;
///     }
/// }
/// reader.finish();
/// while reader.advance()? == Progress::Ready {
///     count += 1;
/// }
/// assert_eq!(count, ulog_core::ULog::parse(&bytes)?.message_count());
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub struct PushReader {
    buf: Vec<u8>,
    base: u64,
    eof: bool,
    framer: Framer,
    current: Option<Record>,
    ended: bool,
}

impl Default for PushReader {
    fn default() -> PushReader {
        PushReader::new()
    }
}

impl PushReader {
    /// A reader that has seen no bytes yet.
    pub fn new() -> PushReader {
        PushReader {
            buf: Vec::new(),
            base: 0,
            eof: false,
            framer: Framer::new(),
            current: None,
            ended: false,
        }
    }

    /// Adds the next bytes of the file. (The message of the last
    /// [`advance`](PushReader::advance) is no longer available after this.)
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
    pub fn advance(&mut self) -> Result<Progress, ReadError> {
        self.current = None;
        if self.ended {
            return Ok(Progress::End);
        }
        match self.framer.step(&self.buf, self.base, self.eof)? {
            Step::Record(r) => {
                self.current = Some(r);
                Ok(Progress::Ready)
            }
            Step::NeedMore => Ok(Progress::NeedMore),
            Step::End => {
                self.ended = true;
                Ok(Progress::End)
            }
        }
    }

    /// The message that the last [`advance`](PushReader::advance) made ready.
    pub fn current(&self) -> Option<MessageAt<'_>> {
        let r = self.current?;
        let payload = r.payload(&self.buf, self.base);
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

    /// The subscription that data messages of `msg_id` belong to now.
    pub fn subscription(&self, msg_id: u16) -> Option<&Arc<Subscription>> {
        let i = self.framer.defs.sub_index(msg_id)?;
        Some(&self.framer.defs.subscriptions()[i as usize])
    }

    /// The layout of format `name` as the formats met so far define it; `None` when
    /// none of them has that name.
    pub(crate) fn layout_of(
        &self,
        name: &str,
    ) -> Option<Result<Arc<ulog_format::Layout>, ulog_format::LayoutError>> {
        self.framer.defs.layout_of(name)
    }

    /// Every subscription met so far, in the order of their first `A` messages.
    pub(crate) fn subscriptions(&self) -> &[Arc<Subscription>] {
        self.framer.defs.subscriptions()
    }

    /// Bytes currently buffered (for checking the memory bound).
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }
}

/// An incremental reader pulling every message from any `Read` (a pipe, a socket),
/// in bounded memory.
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut reader = ulog_core::stream::StreamReader::new(&bytes[..]);
/// let mut data_messages = 0;
/// while let Some(m) = reader.next_message()? {
///     if let ulog_core::Message::Data { .. } = m.message {
///         data_messages += 1;
///     }
/// }
/// assert!(data_messages > 0);
/// # Ok::<(), ulog_core::ReadError>(())
/// ```
pub struct StreamReader<R> {
    src: R,
    inner: PushReader,
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
            inner: PushReader::new(),
            chunk: vec![0; chunk.max(1)],
        }
    }

    /// The next message, or `None` at the end.
    pub fn next_message(&mut self) -> Result<Option<MessageAt<'_>>, ReadError> {
        loop {
            match self.inner.advance()? {
                Progress::Ready => break,
                Progress::End => return Ok(None),
                Progress::NeedMore => {
                    let at = self.inner.base + self.inner.buf.len() as u64;
                    let n = read_some(&mut self.src, &mut self.chunk)
                        .map_err(|e| ReadError::io(e, Some(at)))?;
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
    pub fn state(&self) -> &PushReader {
        &self.inner
    }
}

#[cfg(test)]
mod thread_tests {
    /// The readers can be sent to, and shared with, other threads: framing keeps no
    /// state behind a `RefCell` or the like.
    #[test]
    fn readers_are_send_and_sync() {
        fn send_sync<T: Send + Sync>() {}
        send_sync::<super::PushReader>();
        send_sync::<super::StreamReader<std::fs::File>>();
        send_sync::<crate::read::Messages<'static>>();
    }
}
