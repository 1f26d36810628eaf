//! The plans of a [`ULogTopics`] enum for the subscriptions of one log: made once per
//! subscription, at its first record, by the one rule of [`Plan`](super::Plan), and
//! kept here for every typed reader of several topics.

use core::marker::PhantomData;

use super::error::TypedError;
use super::topics::{TopicPlan, ULogTopics};
use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;

/// What one subscription became.
enum Slot {
    /// Not met yet.
    Unplanned,
    /// A variant of the enum reads it.
    Planned(TopicPlan),
    /// Not read: the enum does not name it, or (reported once) its format does not
    /// fit or cannot be laid out.
    Unread,
}

/// One subscription's plan, beside the unwrapper of its timestamps: one vector, sized
/// at a subscription's first record, for both.
struct Entry {
    slot: Slot,
    unwrap: Option<Unwrapper>,
}

/// The plans of `E`, by subscription index.
pub(crate) struct Plans<E> {
    entries: Vec<Entry>,
    topics: PhantomData<fn() -> E>,
}

impl<E: ULogTopics> Plans<E> {
    pub fn new() -> Plans<E> {
        Plans {
            entries: Vec::new(),
            topics: PhantomData,
        }
    }

    /// Plans `topic` at its first record: a format that does not fit its variant, or
    /// cannot be laid out, is the error of that first call, and the topic is not read.
    #[inline]
    pub fn meet(&mut self, topic: &Subscription) -> Result<(), TypedError> {
        match self.entries.get(topic.index()) {
            Some(Entry {
                slot: Slot::Planned(_) | Slot::Unread,
                ..
            }) => Ok(()),
            _ => self.plan(topic),
        }
    }

    /// The plan that decodes the records of subscription `i` (met before), or `None`
    /// where they are not read.
    #[inline]
    pub fn get(&self, i: usize) -> Option<&TopicPlan> {
        match &self.entries[i].slot {
            Slot::Planned(plan) => Some(plan),
            _ => None,
        }
    }

    /// The timestamp of `payload`, the next record of `topic` (met before) in file
    /// order, narrow timestamps unwrapped.
    #[inline]
    pub fn time(&mut self, topic: &Subscription, payload: &[u8]) -> Option<u64> {
        self.entries[topic.index()]
            .unwrap
            .get_or_insert_with(|| Unwrapper::new(topic.timestamp_field()))
            .push(payload)
    }

    #[cold]
    fn plan(&mut self, topic: &Subscription) -> Result<(), TypedError> {
        let i = topic.index();
        if i >= self.entries.len() {
            self.entries.resize_with(i + 1, || Entry {
                slot: Slot::Unplanned,
                unwrap: None,
            });
        }
        self.entries[i].slot = Slot::Unread;
        let Some(variant) = E::variant_of(topic.name()) else {
            return Ok(());
        };
        let layout = topic
            .layout()
            .map_err(|e| TypedError::no_layout(topic, e))?;
        match E::plan(variant, layout) {
            Some(Ok(plan)) => self.entries[i].slot = Slot::Planned(plan),
            Some(Err(m)) => return Err(TypedError::mismatch(topic, m)),
            None => {}
        }
        Ok(())
    }
}
