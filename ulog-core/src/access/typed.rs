//! Typed access: a topic read through a binding (a struct implementing
//! [`ULogMessage`]), checked against the log's format once per subscription; and a
//! walk over several topics at once with a [`ULogTopics`] enum, in file order or
//! merged by timestamp.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::access::topic::Topic;
use crate::error::{Error, ErrorKind, Result};
use crate::read::log::ULog;
use crate::read::scan::{scan, scan_filtered, ScanRecord, ScanSummary};
use crate::typed::{
    Mismatch, Plan, Subscription, TopicDispatcher, TopicMessage, TopicPlan, TopicRecord,
    ULogMessage, ULogTopics,
};

/// The rows of one topic instance decoded into `T` (see [`Topic::decode`]).
pub struct TypedRows<'l, 'a, T> {
    topic: Topic<'l, 'a>,
    plan: Plan<T>,
}

impl<'l, 'a, T: ULogMessage> TypedRows<'l, 'a, T> {
    /// The topic instance.
    pub fn topic(&self) -> Topic<'l, 'a> {
        self.topic
    }

    /// The plan made for it (exact copy or field mapping).
    pub fn plan(&self) -> &Plan<T> {
        &self.plan
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.topic.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.topic.is_empty()
    }

    /// Row `i`, decoded.
    pub fn get(&self, i: usize) -> Option<Result<T>> {
        let payload = self.topic.payload(i)?;
        Some(self.plan.decode(payload).map_err(|e| {
            // Row `i` has a payload, so it has an offset: looked up only for an error.
            let offset = self.topic.message_offsets().get(i).unwrap_or(0);
            Error::new(ErrorKind::Decode(e), offset)
        }))
    }

    /// Every row, decoded, in file order. Framing has checked each payload's size
    /// against the format, so decoding fails only for formats that could not be laid
    /// out.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Result<T>> + '_ {
        let offsets = self.topic.message_offsets();
        self.topic.payloads().zip(offsets).map(move |(p, o)| {
            self.plan
                .decode(p)
                .map_err(|e| Error::new(ErrorKind::Decode(e), o))
        })
    }

    /// Every row borrowed in place as `&T`, where the binding's layout is the file's
    /// exactly and its fields have alignment 1 (see [`Plan::view`]).
    pub fn views(&self) -> impl ExactSizeIterator<Item = Result<&'a T>> + '_
    where
        T: zerocopy::FromBytes
            + zerocopy::KnownLayout
            + zerocopy::Immutable
            + zerocopy::Unaligned
            + 'a,
    {
        let offsets = self.topic.message_offsets();
        self.topic.payloads().zip(offsets).map(move |(p, o)| {
            self.plan
                .view(p)
                .map_err(|e| Error::new(ErrorKind::Decode(e), o))
        })
    }
}

impl<'l, 'a> Topic<'l, 'a> {
    /// Checks the topic's format against binding `T` once: an exact match, a
    /// compatible one (fields found by name or alias elsewhere), or an error listing
    /// every difference.
    pub fn plan<T: ULogMessage>(&self) -> Result<Plan<T>> {
        let layout = self.layout()?;
        Plan::new(layout)
            .map_err(|m| Error::new(ErrorKind::Mismatch(Box::new(m)), self.subscription_offset()))
    }

    /// The topic's rows decoded into `T`.
    pub fn decode<T: ULogMessage>(&self) -> Result<TypedRows<'l, 'a, T>> {
        Ok(TypedRows {
            topic: *self,
            plan: self.plan()?,
        })
    }
}

/// The order of a walk over several topics.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Order {
    /// As the messages stand in the file.
    File,
    /// By timestamp, ties in file order (each topic's own order is kept).
    Timestamp,
}

impl<'a> ULog<'a> {
    /// Instance `multi_id` of the topic `T` binds (by its ULog name), decoded into `T`.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::typed::ULogMessage;
    ///
    /// #[derive(ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct BatteryStatus { timestamp: u64, voltage_v: f32, remaining: f32 }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let rows = log.read::<BatteryStatus>(1).unwrap();
    /// let first = rows.iter().next().unwrap().unwrap();
    /// assert_eq!(first.voltage_v, 16.7);
    /// # }
    /// ```
    pub fn read<T: ULogMessage>(&self, multi_id: u8) -> Result<TypedRows<'_, 'a, T>> {
        self.topic(T::NAME, multi_id)?.decode()
    }

    /// Every instance of the topic `T` binds, each decoded into `T`, by multi_id.
    pub fn read_instances<T: ULogMessage>(&self) -> Result<Vec<TypedRows<'_, 'a, T>>> {
        self.topic_instances(T::NAME)
            .into_iter()
            .map(|t| t.decode())
            .collect()
    }

    /// Walks the data of every topic once with a [`ULogTopics`] enum: the topics it
    /// names come decoded (plans made once per subscription), the others raw. A topic
    /// whose format does not fit its variant yields one error (every difference), then
    /// all its records raw.
    pub fn walk<E: ULogTopics>(&self, order: Order) -> Walk<'_, 'a, E> {
        let mut dispatcher = TopicDispatcher::new();
        let mut slots = Vec::new();
        let mut times = Vec::new();
        for topic in self.topics() {
            slots.push(
                topic
                    .layout()
                    .ok()
                    .map(|l| dispatcher.subscribe(topic.name(), l)),
            );
            // Narrow (version 0) timestamps are unwrapped per series before merging.
            times.push(match order {
                Order::File => Vec::new(),
                Order::Timestamp => {
                    let t = topic.timestamps();
                    if t.len() == topic.len() {
                        t
                    } else {
                        vec![0; topic.len()]
                    }
                }
            });
        }
        let mut walk = Walk {
            log: self,
            dispatcher,
            slots,
            times,
            reported: Vec::new(),
            cursors: BinaryHeap::new(),
        };
        for sub in 0..self.subscriptions().len() {
            walk.push_cursor(sub, 0);
        }
        walk
    }
}

#[derive(PartialEq, Eq, PartialOrd, Ord)]
struct Cursor {
    key: u64,
    offset: u64,
    sub: usize,
    row: usize,
}

/// The walk of [`ULog::walk`].
pub struct Walk<'l, 'a, E> {
    log: &'l ULog<'a>,
    dispatcher: TopicDispatcher<E>,
    slots: Vec<Option<usize>>,
    times: Vec<Vec<u64>>,
    reported: Vec<usize>,
    cursors: BinaryHeap<Reverse<Cursor>>,
}

impl<'l, 'a, E> Walk<'l, 'a, E> {
    fn push_cursor(&mut self, sub: usize, row: usize) {
        let topic = self.log.topic_at(sub);
        let Some(offset) = topic.message_offsets().get(row) else {
            return;
        };
        let key = self.times[sub].get(row).copied().unwrap_or(offset);
        self.cursors.push(Reverse(Cursor {
            key,
            offset,
            sub,
            row,
        }));
    }
}

impl<'l, 'a, E: ULogTopics> Iterator for Walk<'l, 'a, E> {
    type Item = Result<TopicRecord<'l, E>>;

    fn next(&mut self) -> Option<Self::Item> {
        let Reverse(c) = self.cursors.pop()?;
        let topic = self.log.topic_at(c.sub);
        // A subscription that does not fit its variant is reported once, before its
        // first record, which then comes raw like the rest: nothing is lost.
        if let Some(slot) = self.slots[c.sub] {
            if let Some(Subscription::Mismatched(m)) = self.dispatcher.subscription(slot) {
                if !self.reported.contains(&c.sub) {
                    self.reported.push(c.sub);
                    let e = mismatch_error(m, topic.subscription_offset());
                    self.cursors.push(Reverse(c));
                    return Some(Err(e));
                }
            }
        }
        self.push_cursor(c.sub, c.row + 1);
        let payload = topic.payload(c.row).expect("row exists");
        let raw = TopicRecord::Raw {
            name: topic.name(),
            multi_id: topic.multi_id(),
            payload,
        };
        let Some(slot) = self.slots[c.sub] else {
            return Some(Ok(raw));
        };
        match self.dispatcher.decode(slot, payload) {
            None => Some(Ok(raw)),
            Some(Ok(message)) => Some(Ok(TopicRecord::Message {
                multi_id: topic.multi_id(),
                message,
            })),
            Some(Err(e)) => Some(Err(Error::new(ErrorKind::Decode(e), c.offset))),
        }
    }
}

/// One pass over a whole file (a buffer or a memory map) with a [`ULogTopics`] enum,
/// in file order, keeping no index: [`ULog::walk`] in [`Order::File`] without the
/// parse, for reading each message once. The topics the enum names come decoded
/// (plans made once per subscription), the others raw. A subscription whose format
/// does not fit its variant yields one error (every difference) before its first
/// record, which then comes raw like the rest. When the other topics are not needed,
/// [`scan_topics_only`] leaves them out, which is faster.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::{TopicRecord, ULogMessage, ULogTopics};
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
///
/// #[derive(ULogTopics)]
/// #[ulog(crate = "ulog_core")]
/// enum Topics { Attitude(VehicleAttitude) }
///
/// let bytes = ulog_core::testing::sample_log();
/// let mut norms = Vec::new();
/// ulog_core::scan_topics::<Topics, _>(&bytes, |record| {
///     if let Ok(TopicRecord::Message { message: Topics::Attitude(a), .. }) = record {
///         norms.push(a.q.iter().map(|v| v * v).sum::<f32>());
///     }
/// })
/// .unwrap();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// assert_eq!(norms.len(), log.topic("vehicle_attitude", 0).unwrap().len());
/// # }
/// ```
pub fn scan_topics<E, F>(data: &[u8], mut f: F) -> Result<ScanSummary>
where
    E: ULogTopics,
    F: FnMut(Result<TopicRecord<'_, E>>),
{
    let mut dispatcher = TopicDispatcher::<E>::new();
    // Per subscription: its dispatcher slot (`None` inside: no layout), made at its
    // first record.
    let mut slots: Vec<Option<Option<usize>>> = Vec::new();
    scan(data, |r| {
        let slot = match slots.get(r.subscription) {
            Some(&Some(slot)) => slot,
            _ => first_record(&mut dispatcher, &mut slots, &r, &mut f),
        };
        let decoded = slot.and_then(|s| dispatcher.decode(s, r.payload));
        f(match decoded {
            None => Ok(TopicRecord::Raw {
                name: r.name,
                multi_id: r.multi_id,
                payload: r.payload,
            }),
            Some(Ok(message)) => Ok(TopicRecord::Message {
                multi_id: r.multi_id,
                message,
            }),
            Some(Err(e)) => Err(Error::new(ErrorKind::Decode(e), r.offset)),
        })
    })
}

/// Plans a subscription of [`scan_topics`] at its first record, reporting a format
/// that does not fit its variant.
#[cold]
fn first_record<E, F>(
    dispatcher: &mut TopicDispatcher<E>,
    slots: &mut Vec<Option<Option<usize>>>,
    r: &ScanRecord<'_, '_>,
    f: &mut F,
) -> Option<usize>
where
    E: ULogTopics,
    F: FnMut(Result<TopicRecord<'_, E>>),
{
    if r.subscription >= slots.len() {
        slots.resize(r.subscription + 1, None);
    }
    let slot = r.layout.map(|l| dispatcher.subscribe(r.name, l));
    slots[r.subscription] = Some(slot);
    if let Some(Subscription::Mismatched(m)) = slot.and_then(|s| dispatcher.subscription(s)) {
        f(Err(mismatch_error(m, r.subscribed_at)));
    }
    slot
}

/// [`scan_topics`] for the topics the enum names only: their messages come decoded,
/// in file order, and the records of every other subscription are framed (and
/// counted in the summary) but not handed out, which is cheaper. A subscription whose
/// format does not fit its variant yields one error (every difference), at its first
/// record, and is skipped from then on; one whose format could not be laid out is
/// skipped (the summary's findings say why).
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::{ULogMessage, ULogTopics};
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
///
/// #[derive(ULogTopics)]
/// #[ulog(crate = "ulog_core")]
/// enum Topics { Attitude(VehicleAttitude) }
///
/// let bytes = ulog_core::testing::sample_log();
/// let mut stamps = Vec::new();
/// ulog_core::scan_topics_only::<Topics, _>(&bytes, |m| {
///     let Topics::Attitude(a) = m.unwrap().message;
///     stamps.push(a.timestamp);
/// })
/// .unwrap();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// let topic = log.topic("vehicle_attitude", 0).unwrap();
/// assert_eq!(stamps, topic.decode::<VehicleAttitude>().unwrap().iter()
///     .map(|a| a.unwrap().timestamp).collect::<Vec<_>>());
/// # }
/// ```
pub fn scan_topics_only<E, F>(data: &[u8], mut f: F) -> Result<ScanSummary>
where
    E: ULogTopics,
    F: FnMut(Result<TopicMessage<E>>),
{
    // Per subscription: its plan, made at its first record (subscriptions without one
    // are skipped after it, so they never come back here).
    let mut plans: Vec<Option<TopicPlan>> = Vec::new();
    scan_filtered(data, |r| {
        let plan = match plans.get(r.subscription) {
            Some(Some(plan)) => plan,
            _ => match plan_only::<E, F>(&mut plans, &r, &mut f) {
                Some(plan) => plan,
                None => return false,
            },
        };
        f(match E::decode(plan, r.payload) {
            Ok(message) => Ok(TopicMessage {
                offset: r.offset,
                multi_id: r.multi_id,
                message,
            }),
            Err(e) => Err(Error::new(ErrorKind::Decode(e), r.offset)),
        });
        true
    })
}

/// Plans a subscription of [`scan_topics_only`] at its first record, reporting a
/// format that does not fit its variant; `None`: the subscription is not read.
#[cold]
fn plan_only<'p, E, F>(
    plans: &'p mut Vec<Option<TopicPlan>>,
    r: &ScanRecord<'_, '_>,
    f: &mut F,
) -> Option<&'p TopicPlan>
where
    E: ULogTopics,
    F: FnMut(Result<TopicMessage<E>>),
{
    let plan = match Subscription::of::<E>(r.name, r.layout?) {
        Subscription::Planned(plan) => plan,
        Subscription::Mismatched(m) => {
            f(Err(mismatch_error(&m, r.subscribed_at)));
            return None;
        }
        Subscription::Unnamed => return None,
    };
    if r.subscription >= plans.len() {
        plans.resize(r.subscription + 1, None);
    }
    plans[r.subscription] = Some(plan);
    plans[r.subscription].as_ref()
}

/// The error reporting that a subscription (its `A` message at `at`) does not fit
/// its binding.
fn mismatch_error(m: &Mismatch, at: u64) -> Error {
    Error::new(ErrorKind::Mismatch(Box::new(m.clone())), at)
}
