//! [`Topic`]: one topic instance of a parsed log, its data messages, and any field by
//! path. A path is resolved once to an offset and a type; reading is then a load at a
//! fixed offset.

use std::sync::Arc;

use ulog_format::{BasicType, Layout, LayoutType};

use crate::access::field::{FieldReader, FieldShape};
use crate::access::lookup::{LookupError, TopicNotFound};
use crate::bytes::data_payload_at;
use crate::definitions::timestamp::{TimestampField, Unwrapper};
use crate::definitions::Subscription;
use crate::log::offsets::{MessageOffsets, OffsetsIter};
use crate::log::ulog::ULog;

/// One topic instance of a log (a subscription and its data messages).
#[derive(Clone, Copy)]
pub struct Topic<'l, 'a> {
    log: &'l ULog<'a>,
    sub: &'l Arc<Subscription>,
}

impl<'l, 'a> Topic<'l, 'a> {
    /// The log it is of.
    pub fn log(&self) -> &'l ULog<'a> {
        self.log
    }

    /// Its subscription (name, instance, msg_id, layout, where it was subscribed).
    pub fn subscription(&self) -> &'l Arc<Subscription> {
        self.sub
    }

    /// The topic (format) name.
    pub fn name(&self) -> &'l str {
        self.sub.name()
    }

    /// The instance number.
    pub fn multi_id(&self) -> u8 {
        self.sub.multi_id()
    }

    /// The layout of the topic's format, or why there is none.
    pub fn layout(&self) -> Result<&'l Arc<Layout>, LookupError> {
        self.sub
            .layout()
            .map_err(|e| LookupError::layout(self.sub, e))
    }

    /// Number of data messages.
    pub fn len(&self) -> usize {
        self.log.index(self.sub.index()).offsets.len()
    }

    /// Whether the topic has no data messages.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Byte offsets of the data messages (of their 3-byte headers), in file order.
    pub fn message_offsets(&self) -> MessageOffsets<'l> {
        self.log.index(self.sub.index()).offsets.view()
    }

    /// The payload of data message `i` (after the msg_id).
    pub fn payload(&self, i: usize) -> Option<&'a [u8]> {
        let data = self.log.data();
        self.message_offsets()
            .get(i)
            .map(|o| data_payload_at(data, o))
    }

    /// The payloads of every data message, in file order, borrowed from the file.
    pub fn payloads(&self) -> Payloads<'l, 'a> {
        self.payloads_in(0..self.len())
    }

    /// The payloads of data messages `rows`, in file order.
    ///
    /// # Panics
    /// If `rows` is out of bounds, as slicing is.
    pub fn payloads_in(&self, rows: core::ops::Range<usize>) -> Payloads<'l, 'a> {
        let offsets = self.message_offsets().slice(rows).iter();
        Payloads {
            data: self.log.data(),
            ahead: offsets.clone(),
            offsets,
            span: 0,
        }
    }

    /// Where the timestamp field is, if the format has one.
    pub fn timestamp_field(&self) -> Option<TimestampField> {
        self.sub.timestamp_field()
    }

    /// The timestamp of every data message in microseconds, narrow (version 0)
    /// timestamps unwrapped; empty if the format has no timestamp.
    pub fn timestamps(&self) -> Vec<u64> {
        let mut u = Unwrapper::new(self.sub.timestamp_field());
        self.payloads().filter_map(|p| u.push(p)).collect()
    }

    /// Resolves a field path (`timestamp`, `q`, `q[2]`, `esc[3].esc_rpm`) once, to read
    /// it from every payload.
    pub fn field(&self, path: &str) -> Result<FieldReader, LookupError> {
        field_in(self.name(), self.layout()?, path)
    }

    /// Readers for every leaf field (padding left out) in pyulog's column order:
    /// arrays element by element, `char[N]` as one string.
    pub fn fields(&self) -> Result<Vec<FieldReader>, LookupError> {
        Ok(FieldReader::all(self.layout()?))
    }
}

/// The payloads of a topic's data messages, in file order, borrowed from the file
/// ([`Topic::payloads`], [`Topic::payloads_in`]).
#[derive(Debug, Clone)]
pub struct Payloads<'l, 'a> {
    data: &'a [u8],
    offsets: OffsetsIter<'l>,
    /// The offsets of the rows to ask the cache for, `rows` ahead of `offsets`.
    ahead: OffsetsIter<'l>,
    /// Bytes to ask for from each (0: none).
    span: usize,
}

impl Payloads<'_, '_> {
    /// Asks the processor for each payload `rows` rows before it is handed out. A
    /// topic's messages are scattered over the file, between those of the other
    /// topics: a loop over one topic's payloads that does little with each waits for
    /// memory at every row otherwise (BENCHMARKS.md has what it saves for the CSV
    /// export).
    pub fn prefetch(mut self, rows: usize) -> Self {
        let first = self.offsets.clone().next();
        self.span = first.map_or(0, |o| {
            let o = o as usize;
            crate::bytes::MESSAGE_HEADER_SIZE + usize::from(crate::bytes::u16_at(self.data, o))
        });
        self.ahead = self.offsets.clone();
        for _ in 0..rows {
            self.ahead.next();
        }
        self
    }
}

impl<'a> Iterator for Payloads<'_, 'a> {
    type Item = &'a [u8];

    // Always: the typed rows' cursor calls it from code compiled once for every
    // binding, where LLVM otherwise kept the call (bench/README.md, what
    // `ulog_module!` costs a crate: the cost at run time).
    #[inline(always)]
    fn next(&mut self) -> Option<&'a [u8]> {
        let o = self.offsets.next()?;
        if self.span > 0 {
            if let Some(a) = self.ahead.next() {
                crate::audited::prefetch_span(self.data, a as usize, self.span);
            }
        }
        Some(data_payload_at(self.data, o))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.offsets.size_hint()
    }
}

impl ExactSizeIterator for Payloads<'_, '_> {}

impl core::fmt::Debug for Topic<'_, '_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Topic")
            .field("name", &self.name())
            .field("multi_id", &self.multi_id())
            .field("msg_id", &self.sub.msg_id())
            .field("messages", &self.len())
            .finish()
    }
}

impl<'a> ULog<'a> {
    /// Every topic instance (one per subscription), in subscription order.
    pub fn topics(&self) -> impl ExactSizeIterator<Item = Topic<'_, 'a>> {
        self.subscriptions()
            .iter()
            .map(move |sub| Topic { log: self, sub })
    }

    /// The topic of subscription `index` (an index into [`ULog::subscriptions`]).
    ///
    /// # Panics
    /// If there is no such subscription.
    pub fn topic_at(&self, index: usize) -> Topic<'_, 'a> {
        Topic {
            log: self,
            sub: &self.subscriptions()[index],
        }
    }

    /// Topic `name`, instance `multi_id`. An error says what the log has instead:
    /// the instances of `name`, or the closest topic names.
    pub fn topic(&self, name: &str, multi_id: u8) -> Result<Topic<'_, 'a>, LookupError> {
        self.topics()
            .find(|t| t.name() == name && t.multi_id() == multi_id)
            .ok_or_else(|| LookupError::Topic(TopicNotFound::in_log(self, name, Some(multi_id))))
    }

    /// Every instance of topic `name`, by multi_id (empty when the log has none).
    pub fn topic_instances(&self, name: &str) -> Vec<Topic<'_, 'a>> {
        let mut v: Vec<_> = self.topics().filter(|t| t.name() == name).collect();
        v.sort_by_key(|t| t.multi_id());
        v
    }
}

/// Resolves field `path` in `layout`, the format of topic `topic` (named in the error):
/// [`Topic::field`], for a layout known without a log.
pub(crate) fn field_in(
    topic: &str,
    layout: &Layout,
    path: &str,
) -> Result<FieldReader, LookupError> {
    let not_found = || {
        let closest = crate::suggest::closest(path, layout.columns().map(|c| c.path.as_str()));
        // Nothing close (`roll` of a topic that holds a quaternion): what it has.
        let fields = match closest {
            Some(_) => Vec::new(),
            None => layout
                .fields()
                .iter()
                .filter(|f| !f.is_padding())
                .map(|f| match f.array_len {
                    Some(n) => format!("{}[{n}]", f.name),
                    None => f.name.clone(),
                })
                .collect(),
        };
        LookupError::Field {
            topic: topic.to_owned(),
            path: path.to_owned(),
            closest,
            fields,
        }
    };
    let f = layout.find(path).ok_or_else(not_found)?;
    let ty = match f.ty {
        LayoutType::Basic(b) => b,
        LayoutType::Nested(_) => return Err(not_found()),
    };
    if path.split('.').any(ulog_format::is_padding_name) {
        return Err(not_found());
    }
    let shape = match (ty, f.is_array) {
        (BasicType::Char, true) => FieldShape::String(f.count),
        (_, true) => FieldShape::Array(f.count),
        (_, false) => FieldShape::Scalar,
    };
    Ok(FieldReader {
        path: path.to_owned(),
        offset: f.offset,
        ty,
        shape,
    })
}
