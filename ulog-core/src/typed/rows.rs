//! [`TypedRows`]: the rows of one topic instance of a parsed log, decoded into a
//! binding; [`ULog::read`] and [`ULog::read_instances`].

use crate::access::lookup::TopicNotFound;
use crate::access::topic::Topic;
use crate::log::ulog::ULog;

use super::error::TypedError;
use super::message::ULogMessage;
use super::plan::Plan;
use crate::audited::WireImage;

/// The rows of one topic instance decoded into `T` (see [`ULog::read`]).
pub struct TypedRows<'l, 'a, T> {
    topic: Topic<'l, 'a>,
    plan: Plan<T>,
}

impl<'l, 'a, T: ULogMessage> TypedRows<'l, 'a, T> {
    /// The topic instance.
    pub fn topic(&self) -> Topic<'l, 'a> {
        self.topic
    }

    /// The plan made for it (exact or mapped, which optional fields the log has).
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
    pub fn get(&self, i: usize) -> Option<Result<T, TypedError>> {
        let payload = self.topic.payload(i)?;
        Some(self.plan.decode(payload).map_err(|e| {
            // Row `i` has a payload, so it has an offset: looked up only for an error.
            let offset = self.topic.message_offsets().get(i).unwrap_or(0);
            TypedError::decode(self.topic.subscription(), offset, e)
        }))
    }

    /// Every row, decoded, in file order. Framing has checked each payload's size
    /// against the format, so decoding does not fail on a log this reader parsed.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Result<T, TypedError>> + '_ {
        let offsets = self.topic.message_offsets();
        let topic = self.topic.subscription();
        self.topic.payloads().zip(offsets).map(move |(p, o)| {
            self.plan
                .decode(p)
                .map_err(|e| TypedError::decode(topic, o, e))
        })
    }

    /// Every row borrowed in place as `&T`, without a copy.
    ///
    /// `T` must be a binding whose memory is its wire image: derive it with
    /// `#[ulog(view)]` and `#[repr(C)]` (Rust would reorder the fields otherwise), with
    /// fields of `u8`, `i8`, [`CharArray<N>`](super::CharArray), the [`le`](super::le)
    /// little-endian types (`le::U64`, `le::F32`, …), arrays of these, and nested such
    /// bindings (the derive checks it at compile time). And
    /// each row's payload must hold `T` where the log has it
    /// ([`PlanKind::Exact`](super::PlanKind::Exact)): the fields in the log's order,
    /// and no trailing padding that the log's writer left out (PX4 never writes it:
    /// leave the trailing `_paddingN` out of the struct). A row that cannot be
    /// borrowed is an error saying why.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::typed::le;
    ///
    /// #[derive(ulog_core::ULogMessage)]
    /// #[ulog(crate = "ulog_core", view)]
    /// #[repr(C)]
    /// struct VehicleAttitude { timestamp: le::U64, q: [le::F32; 4] }
    ///
    /// let bytes = ulog_core::testing::sample_log();
    /// let log = ulog_core::ULog::parse(&bytes).unwrap();
    /// let rows = log.read::<VehicleAttitude>(0).unwrap();
    /// let first: &VehicleAttitude = rows.views().next().unwrap().unwrap();
    /// assert_eq!(first.q[0].get(), 1.0);
    /// # }
    /// ```
    pub fn views(&self) -> impl ExactSizeIterator<Item = Result<&'a T, TypedError>> + '_
    where
        T: WireImage + 'a,
    {
        let offsets = self.topic.message_offsets();
        let topic = self.topic.subscription();
        self.topic.payloads().zip(offsets).map(move |(p, o)| {
            self.plan
                .view(p)
                .map_err(|e| TypedError::decode(topic, o, e))
        })
    }
}

impl<'l, 'a> Topic<'l, 'a> {
    /// The topic's rows decoded into `T`, its format checked against `T` once: an
    /// error lists every difference.
    pub fn read<T: ULogMessage>(&self) -> Result<TypedRows<'l, 'a, T>, TypedError> {
        let sub = self.subscription();
        let layout = sub.layout().map_err(|e| TypedError::no_layout(sub, e))?;
        let plan = Plan::new(layout).map_err(|m| TypedError::mismatch(sub, m))?;
        Ok(TypedRows { topic: *self, plan })
    }
}

impl<'a> ULog<'a> {
    /// Instance `multi_id` of the topic `T` binds, decoded into `T`.
    ///
    /// The topic is `T`'s ULog name: `#[ulog(name = "…")]`, or the struct's name in
    /// snake case (`VehicleLocalPosition` → `vehicle_local_position`). A name the log
    /// does not have is an error listing the closest topic names (and saying when the
    /// name came from the struct's name); a format that does not fit `T` lists every
    /// difference.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// #[derive(ulog_core::ULogMessage)]
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
    pub fn read<T: ULogMessage>(&self, multi_id: u8) -> Result<TypedRows<'_, 'a, T>, TypedError> {
        match self
            .topics()
            .find(|t| t.name() == T::NAME && t.multi_id() == multi_id)
        {
            Some(topic) => topic.read(),
            None => {
                let missing = TopicNotFound::in_log(self, T::NAME, Some(multi_id));
                Err(TypedError::not_found(missing, T::schema()))
            }
        }
    }

    /// Every instance of the topic `T` binds, by multi_id, each decoded into `T` or
    /// the error of that instance alone (the others are read whatever one of them
    /// holds). The outer error: the log has no instance of the topic at all.
    pub fn read_instances<T: ULogMessage>(
        &self,
    ) -> Result<Vec<Result<TypedRows<'_, 'a, T>, TypedError>>, TypedError> {
        let instances = self.topic_instances(T::NAME);
        if instances.is_empty() {
            let missing = TopicNotFound::in_log(self, T::NAME, None);
            return Err(TypedError::not_found(missing, T::schema()));
        }
        Ok(instances.iter().map(Topic::read).collect())
    }
}
