//! Every message of a byte slice in file order, with the reader's damage handling.

use std::sync::Arc;

use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::framing::{Framer, Header, Step};
use crate::log::message::Message;

/// A message with the byte offset of its header in the file.
#[derive(Debug, Clone, PartialEq)]
pub struct MessageAt<'a> {
    /// Byte offset of the message's 3-byte header.
    pub offset: u64,
    /// The message.
    pub message: Message<'a>,
}

/// Every message of a whole file in file order, with the reader's damage handling:
/// [`ULog::messages`](crate::ULog::messages), or [`Messages::new`] over bytes that were
/// not parsed. (A stream that is still being written or read is
/// [`StreamReader`](crate::stream::StreamReader)'s.)
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let mut it = ulog_core::read::Messages::new(&bytes);
/// let formats = it.by_ref().filter_map(Result::ok).filter(|m| m.message.msg_type() == b'F').count();
/// assert!(formats > 0);
/// assert!(it.findings().is_empty());
/// ```
#[derive(Clone)]
pub struct Messages<'a> {
    data: &'a [u8],
    framer: Framer,
    done: bool,
}

impl<'a> Messages<'a> {
    /// Frames `data`, a whole ULog file.
    pub fn new(data: &'a [u8]) -> Messages<'a> {
        Messages {
            data,
            framer: Framer::new(),
            done: false,
        }
    }

    /// The file header, once the first message has been asked for.
    pub fn header(&self) -> Option<Header> {
        self.framer.header
    }

    /// The rest of this iteration as if the file ended at byte `len`: what a reader of
    /// only the first `len` bytes gets from here on (a cut file, a download in
    /// progress). `None` when the iterator already needs bytes at or past `len`
    /// (it has framed past it, or is scanning a damaged stretch that reaches it).
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// let mut it = ulog_core::read::Messages::new(&bytes);
    /// let first = it.next().unwrap().unwrap();
    /// // Cut 5 bytes into the second message: nothing more, and the cut is reported.
    /// let end = first.offset as usize + 3 + u16::from_le_bytes([bytes[16], bytes[17]]) as usize;
    /// let mut cut = it.cut(end + 5).unwrap();
    /// assert!(cut.next().is_none());
    /// assert_eq!(cut.findings()[0].kind, ulog_core::read::FindingKind::Truncated);
    /// assert_eq!((cut.findings()[0].offset, cut.findings()[0].len), (end as u64, 5));
    /// ```
    pub fn cut(&self, len: usize) -> Option<Messages<'a>> {
        if len > self.data.len() || (len as u64) < self.framer.keep_from() {
            return None;
        }
        Some(Messages {
            data: &self.data[..len],
            framer: self.framer.clone(),
            done: self.done,
        })
    }

    /// The subscription that data messages of `msg_id` belong to at this point of the
    /// iteration (after the message last handed out): the same record, of the same
    /// topic instance, as in the [`ULog`](crate::ULog) of these bytes, including where
    /// a log subscribes one topic instance twice. `None`: no subscription.
    pub fn subscription(&self, msg_id: u16) -> Option<&Arc<Subscription>> {
        let i = self.framer.defs.sub_index(msg_id)?;
        self.framer.defs.subscriptions().get(i as usize)
    }

    /// What was found and stepped over so far.
    pub fn findings(&self) -> &[Finding] {
        &self.framer.findings
    }
}

impl<'a> Iterator for Messages<'a> {
    type Item = Result<MessageAt<'a>, ReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        match self.framer.step(self.data, 0, true) {
            Ok(Step::Record(r)) => {
                let payload = r.payload(self.data, 0);
                Some(Ok(MessageAt {
                    offset: r.offset,
                    message: Message::from_record(&r, payload, self.framer.flag_bits),
                }))
            }
            Ok(Step::End) | Ok(Step::NeedMore) => {
                self.done = true;
                None
            }
            Err(e) => {
                self.done = true;
                Some(Err(e))
            }
        }
    }
}
