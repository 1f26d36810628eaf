//! [`Subscription`]: one topic instance of a log, the one record of it that every
//! reader shares.

use std::sync::Arc;

use ulog_format::{Layout, LayoutError};

use super::timestamp::TimestampField;

/// A subscription (`A` message): a topic instance of the log, with the layout of its
/// format. Framing makes one record per subscription and every reader borrows or
/// shares it ([`ULog::subscriptions`](crate::ULog::subscriptions),
/// [`ScanSummary::topics`](crate::ScanSummary::topics), each
/// [`DataRecord`](crate::DataRecord)).
///
/// The same topic subscribed again with the same format (under another msg_id, or in
/// appended data) continues the same subscription: its data is one topic instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Subscription {
    index: usize,
    msg_id: u16,
    multi_id: u8,
    name: String,
    offset: u64,
    layout: Result<Arc<Layout>, LayoutError>,
    timestamp: Option<TimestampField>,
}

impl Subscription {
    pub(crate) fn new(
        index: usize,
        msg_id: u16,
        multi_id: u8,
        name: String,
        offset: u64,
        layout: Result<Arc<Layout>, LayoutError>,
    ) -> Subscription {
        let timestamp = layout.as_ref().ok().and_then(|l| TimestampField::of(l));
        Subscription {
            index,
            msg_id,
            multi_id,
            name,
            offset,
            layout,
            timestamp,
        }
    }

    /// Its place among the log's subscriptions, in the order of their `A` messages.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The topic (format) name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The instance number.
    pub fn multi_id(&self) -> u8 {
        self.multi_id
    }

    /// The msg_id of its first `A` message.
    pub fn msg_id(&self) -> u16 {
        self.msg_id
    }

    /// Byte offset of its first `A` message.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// The layout of the topic's format, or why there is none (an unknown nested
    /// type, a cycle, a limit; a format that was never defined).
    pub fn layout(&self) -> Result<&Arc<Layout>, &LayoutError> {
        self.layout.as_ref()
    }

    /// Where its timestamp is, if the format has a `timestamp` field of a timestamp
    /// type.
    pub fn timestamp_field(&self) -> Option<TimestampField> {
        self.timestamp
    }

    /// Whether `other` continues this subscription: the same topic, instance and
    /// format.
    pub(crate) fn same_topic(&self, layout: &Result<Arc<Layout>, LayoutError>) -> bool {
        match (&self.layout, layout) {
            (Ok(a), Ok(b)) => Arc::ptr_eq(a, b) || a == b,
            (Err(a), Err(b)) => a == b,
            _ => false,
        }
    }
}
