//! What a pass hands out and to whom: a [`DataRecord`] per data message, to a
//! [`Visit`]or, which answers with a [`Hand`].

use crate::definitions::Subscription;
use crate::framing::{Framer, Record};

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
    /// `topic.index()`, which framing has at hand: a keeping pass reads it without
    /// reaching into the subscription (one load fewer per record on its path).
    pub(crate) sub: u32,
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
