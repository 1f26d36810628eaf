//! The framing of a pass between windows of the file: what it hands out (a
//! [`DataRecord`]), what it skips, and what it saw besides ([`ScanSummary`]).

use std::sync::Arc;

use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::framing::{FlagBits, Framer, Header, Record, Step};
use crate::log::ulog::ULog;
use crate::pass::keep::LogMetadata;

/// A data message met by a pass: where it is, the topic instance it belongs to, and
/// its payload (after the msg_id).
#[derive(Debug, Clone, Copy)]
pub struct DataRecord<'r> {
    /// Byte offset of the message's 3-byte header.
    pub offset: u64,
    /// The msg_id it was logged with (that of its subscription, or of a later
    /// subscription of the same topic instance).
    pub msg_id: u16,
    /// Its subscription.
    pub topic: &'r Subscription,
    /// The payload after the msg_id.
    pub payload: &'r [u8],
}

/// What a pass saw besides the data messages it handed out.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanSummary {
    /// The file header.
    pub header: Header,
    /// The flag bits message, when the log has one.
    pub flag_bits: Option<FlagBits>,
    /// Messages framed (of every type).
    pub messages: u64,
    /// Data messages of known subscriptions framed, handed out or not (a pass that
    /// leaves topics out still frames and counts their messages).
    pub data_messages: u64,
    /// Every subscription met, in the order of their first `A` messages.
    pub topics: Vec<Arc<Subscription>>,
    /// What the reader found and stepped over, in file order.
    pub findings: Vec<Finding>,
    /// Whether the callback stopped the pass before the end of the log: the summary
    /// then covers what was framed until then.
    pub stopped: bool,
    /// Everything but the data messages, with what the data says of it, when the
    /// pass was asked to keep it ([`ScanOptions::keep_metadata`](crate::ScanOptions::keep_metadata)).
    pub metadata: Option<LogMetadata>,
}

impl ScanSummary {
    /// The summary of a log already parsed.
    pub(crate) fn of(log: &ULog<'_>) -> ScanSummary {
        ScanSummary {
            header: log.header(),
            flag_bits: log.flag_bits().copied(),
            messages: log.message_count(),
            data_messages: (0..log.subscriptions().len())
                .map(|i| log.index(i).offsets.len() as u64)
                .sum(),
            topics: log.subscriptions().to_vec(),
            findings: log.findings().to_vec(),
            stopped: false,
            metadata: None,
        }
    }
}

/// What a pass hands messages to: every data record, and (for those that ask) each
/// other message as framing meets it. A closure taking data records is one.
pub(crate) trait Visit {
    /// A data message of a known subscription.
    fn data(&mut self, record: DataRecord<'_>) -> Hand;

    /// A message other than data: its record, its payload, and framing as it stands
    /// after it. `false` stops the pass.
    #[inline(always)]
    fn other(&mut self, _record: &Record, _payload: &[u8], _framer: &Framer) -> bool {
        true
    }

    /// The end of a pass (one the visitor stopped too): framing as it stands there.
    #[inline(always)]
    fn end(&mut self, _framer: &Framer) {}
}

impl<F: FnMut(DataRecord<'_>) -> Hand> Visit for F {
    #[inline(always)]
    fn data(&mut self, record: DataRecord<'_>) -> Hand {
        self(record)
    }
}

/// What the driver does after handing out a record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Hand {
    /// Go on.
    Next,
    /// Hand out no more records of this record's subscription (they are still framed
    /// and counted).
    SkipTopic,
    /// Stop the pass.
    Stop,
}

impl Hand {
    /// [`Hand::Next`] when the callback said go on, else [`Hand::Stop`].
    #[inline(always)]
    pub(crate) fn go_on(go_on: bool) -> Hand {
        if go_on {
            Hand::Next
        } else {
            Hand::Stop
        }
    }
}

/// How a window's run of the driver ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ran {
    /// The end of the log.
    End,
    /// Framing needs the bytes after the window.
    NeedMore,
    /// The callback stopped the pass.
    Stopped,
}

/// The framing state of a pass between windows of the file.
pub(crate) struct Driver {
    pub framer: Framer,
    messages: u64,
    data: u64,
    /// Subscriptions whose records are no longer handed out.
    skip: Vec<bool>,
    stopped: bool,
}

/// Hands the data message at `offset` to `f` unless its subscription is skipped, and
/// skips the subscription from now on when `f` says so. `true`: go on.
#[inline(always)]
fn hand_out<F>(
    skip: &mut Vec<bool>,
    offset: u64,
    sub: u32,
    topic: &Subscription,
    payload: &[u8],
    f: &mut F,
) -> bool
where
    F: Visit + ?Sized,
{
    if skip.get(sub as usize) == Some(&true) {
        return true;
    }
    // Framing checked that a data message holds its msg_id.
    let record = DataRecord {
        offset,
        msg_id: u16::from_le_bytes([payload[0], payload[1]]),
        topic,
        payload: &payload[2..],
    };
    match f.data(record) {
        Hand::Next => true,
        Hand::SkipTopic => {
            skip_topic(skip, topic.index());
            true
        }
        Hand::Stop => false,
    }
}

#[cold]
fn skip_topic(skip: &mut Vec<bool>, sub: usize) {
    if skip.len() <= sub {
        skip.resize(sub + 1, false);
    }
    skip[sub] = true;
}

impl Driver {
    pub fn new() -> Driver {
        Driver {
            framer: Framer::new(),
            messages: 0,
            data: 0,
            skip: Vec::new(),
            stopped: false,
        }
    }

    /// Frames what `win` (the file from `base`) holds, handing each data message of
    /// a subscription not skipped to `f`.
    #[inline]
    pub fn run<F>(&mut self, win: &[u8], base: u64, eof: bool, f: &mut F) -> Result<Ran, ReadError>
    where
        F: Visit + ?Sized,
    {
        loop {
            let mut n = 0u64;
            let mut go_on = true;
            let skip = &mut self.skip;
            self.framer
                .plain_data_run(win, base, |offset, sub, topic, payload| {
                    n += 1;
                    go_on = hand_out(skip, offset, sub, topic, payload, f);
                    go_on
                });
            self.messages += n;
            self.data += n;
            if !go_on {
                return Ok(self.stop());
            }
            match self.framer.step(win, base, eof)? {
                Step::Record(r) => {
                    self.messages += 1;
                    if let (b'D', Some(sub)) = (r.msg_type, r.sub) {
                        self.data += 1;
                        let payload = r.payload(win, base);
                        let topic = &self.framer.defs.subscriptions()[sub as usize];
                        if !hand_out(&mut self.skip, r.offset, sub, topic, payload, f) {
                            return Ok(self.stop());
                        }
                    } else if r.msg_type != b'D' {
                        let payload = r.payload(win, base);
                        if !f.other(&r, payload, &self.framer) {
                            return Ok(self.stop());
                        }
                    }
                }
                Step::NeedMore => return Ok(Ran::NeedMore),
                Step::End => return Ok(Ran::End),
            }
        }
    }

    #[cold]
    fn stop(&mut self) -> Ran {
        self.stopped = true;
        Ran::Stopped
    }

    pub fn summary(mut self) -> ScanSummary {
        ScanSummary {
            header: self.framer.header.unwrap_or(Header {
                version: 0,
                timestamp: 0,
            }),
            flag_bits: self.framer.flag_bits,
            messages: self.messages,
            data_messages: self.data,
            topics: self.framer.defs.take_subscriptions(),
            findings: std::mem::take(&mut self.framer.findings),
            stopped: self.stopped,
            metadata: None,
        }
    }
}
