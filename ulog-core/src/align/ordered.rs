//! [`TimeOrdered`]: the rows of several topics merged by time, decoded into a
//! [`ULogTopics`] enum, pulled one at a time and repositioned by time in O(log n).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::access::topic::Topic;
use crate::log::ulog::ULog;
use crate::typed::error::TypedError;
use crate::typed::topics::{TopicPlan, ULogTopics};

use super::TimeIndex;

/// One topic instance of a [`TimeOrdered`]: its rows by time and its plan.
#[derive(Debug)]
struct Lane<'l, 'a> {
    topic: Topic<'l, 'a>,
    index: TimeIndex,
    plan: TopicPlan,
}

/// The next row of a lane: ordered by time, then file offset.
type Next = Reverse<(u64, u64, usize, usize)>;

/// The rows of every instance of the topics a [`ULogTopics`] enum names, merged by
/// time (equal times in file order), decoded one at a time
/// ([`ULog::time_ordered`]): an iterator of `(time, instance, message)`, and a
/// [`Timeline`](crate::replay::Timeline) a player can seek in.
///
/// Each topic's rows are taken by their [`TimeIndex`] (sorted by time, as an
/// alignment takes them): a row that goes back in time comes where its time puts
/// it. Rows without a timestamp, or shorter than the format, are left out
/// ([`left_out`](Self::left_out)).
#[derive(Debug)]
pub struct TimeOrdered<'l, 'a, E> {
    lanes: Vec<Lane<'l, 'a>>,
    heap: BinaryHeap<Next>,
    left_out: usize,
    topics: core::marker::PhantomData<fn() -> E>,
}

impl<'a> ULog<'a> {
    /// The rows of the topics `E` names (every instance, by name or alias), merged by
    /// time: each subscription is checked against its variant here, once (the first
    /// that does not fit is the error).
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::{ULogMessage, ULogTopics};
    ///
    /// #[derive(ULogMessage, Debug)]
    /// #[ulog(crate = "ulog_core")]
    /// struct VehicleAttitude { timestamp: u64 }
    /// #[derive(ULogMessage, Debug)]
    /// #[ulog(crate = "ulog_core")]
    /// struct BatteryStatus { timestamp: u64, voltage_v: f32 }
    /// #[derive(ULogTopics, Debug)]
    /// #[ulog(crate = "ulog_core")]
    /// enum Topics { Attitude(VehicleAttitude), Battery(BatteryStatus) }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let mut rows = log.time_ordered::<Topics>().unwrap();
    /// // From 5 s after the start of the log.
    /// rows.seek(log.span().at(5.0));
    /// let (t, instance, first) = rows.next().unwrap();
    /// assert_eq!(t, log.span().at(5.0));
    /// assert!(matches!(first, Topics::Attitude(_)) && instance == 0);
    /// assert!(rows.all(|(u, _, _)| u >= t));
    /// # }
    /// ```
    pub fn time_ordered<E: ULogTopics>(&self) -> Result<TimeOrdered<'_, 'a, E>, TypedError> {
        let mut lanes = Vec::new();
        let mut left_out = 0;
        for topic in self.topics() {
            let Some(variant) = E::variant_of(topic.name()) else {
                continue;
            };
            let sub = topic.subscription();
            let layout = sub.layout().map_err(|e| TypedError::no_layout(sub, e))?;
            let plan = match E::plan(variant, layout) {
                Some(Ok(plan)) => plan,
                Some(Err(m)) => return Err(TypedError::mismatch(sub, m)),
                None => continue,
            };
            let min = layout.min_size();
            let index = TimeIndex::of(&topic, |p| p.len() >= min);
            left_out += topic.len() - index.len();
            lanes.push(Lane { topic, index, plan });
        }
        let mut rows = TimeOrdered {
            lanes,
            heap: BinaryHeap::new(),
            left_out,
            topics: core::marker::PhantomData,
        };
        rows.seek(0);
        Ok(rows)
    }
}

impl<'l, 'a, E: ULogTopics> TimeOrdered<'l, 'a, E> {
    /// Repositions so that the next row is the first at or after `t_us` (boot
    /// microseconds): a binary search in each topic's time index.
    pub fn seek(&mut self, t_us: u64) {
        self.heap.clear();
        for lane in 0..self.lanes.len() {
            let pos = self.lanes[lane].index.seek(t_us);
            self.push(lane, pos);
        }
    }

    /// How many rows are left out: without a timestamp, or shorter than the format.
    pub fn left_out(&self) -> usize {
        self.left_out
    }

    /// Queues row `pos` (in time order) of `lane`, if it has one.
    fn push(&mut self, lane: usize, pos: usize) {
        let l = &self.lanes[lane];
        let (Some(&t), Some(&row)) = (l.index.times.get(pos), l.index.rows.get(pos)) else {
            return;
        };
        let offset = l.topic.message_offsets().get(row as usize).unwrap_or(0);
        self.heap.push(Reverse((t, offset, lane, pos)));
    }
}

impl<E: ULogTopics> Iterator for TimeOrdered<'_, '_, E> {
    type Item = (u64, u8, E);
    fn next(&mut self) -> Option<(u64, u8, E)> {
        loop {
            let Reverse((t, _, lane, pos)) = self.heap.pop()?;
            self.push(lane, pos + 1);
            let l = &self.lanes[lane];
            let row = l.index.rows[pos] as usize;
            let Some(payload) = l.topic.payload(row) else {
                continue;
            };
            // Rows shorter than the format are not indexed: this decodes.
            if let Ok(message) = E::decode(&l.plan, payload) {
                return Some((t, l.topic.multi_id(), message));
            }
        }
    }
}

/// A player replays the rows by time ([`Player`](crate::replay::Player)): each item is
/// the instance and the message.
impl<E: ULogTopics> crate::replay::Timeline for TimeOrdered<'_, '_, E> {
    type Item = (u8, E);
    fn advance(&mut self) -> Option<(u64, (u8, E))> {
        self.next().map(|(t, i, m)| (t, (i, m)))
    }
    fn seek(&mut self, t_us: u64) {
        TimeOrdered::seek(self, t_us)
    }
}
