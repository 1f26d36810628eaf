//! The framing of a pass between windows of the file: what it hands out (a
//! [`DataRecord`], to a [`Visit`]), what it skips, and what it saw besides
//! ([`ScanSummary`], made at its end).

use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::framing::{Framer, Header, Step};
use crate::pass::keep::ScanSummary;
use crate::pass::visit::{DataRecord, Hand, Visit};

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
        sub,
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
