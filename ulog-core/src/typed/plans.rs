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
    unwrap: Unwrapper,
}

impl Slot {
    #[inline(always)]
    fn plan(&self) -> Option<&TopicPlan> {
        match self {
            Slot::Planned(plan) => Some(plan),
            _ => None,
        }
    }
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

    /// The plan of `topic`'s records (`None` where they are not read) and the
    /// unwrapper of its timestamps, in one lookup: the hot path of every record. At
    /// a subscription's first record it is planned; a format that does not fit its
    /// variant, or cannot be laid out, is the error of that first call, and the topic
    /// is not read.
    #[inline]
    pub fn next(
        &mut self,
        topic: &Subscription,
    ) -> (Result<Option<&TopicPlan>, TypedError>, &mut Unwrapper) {
        let i = topic.index();
        if !matches!(
            self.entries.get(i),
            Some(Entry {
                slot: Slot::Planned(_) | Slot::Unread,
                ..
            })
        ) {
            let planned = self.plan(topic);
            let entry = &mut self.entries[i];
            return (planned.map(|()| entry.slot.plan()), &mut entry.unwrap);
        }
        let entry = &mut self.entries[i];
        (Ok(entry.slot.plan()), &mut entry.unwrap)
    }

    #[cold]
    fn plan(&mut self, topic: &Subscription) -> Result<(), TypedError> {
        let i = topic.index();
        if i >= self.entries.len() {
            self.entries.resize_with(i + 1, || Entry {
                slot: Slot::Unplanned,
                unwrap: Unwrapper::new(None),
            });
        }
        self.entries[i] = Entry {
            slot: Slot::Unread,
            unwrap: Unwrapper::new(topic.timestamp_field()),
        };
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
