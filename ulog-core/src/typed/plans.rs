//! The plans of a [`ULogTopics`] enum for the subscriptions of one log: made once per
//! subscription, at its first record, by the one rule of [`Plan`](super::Plan), and
//! kept here for every typed reader of several topics.

use core::marker::PhantomData;

use super::error::TypedError;
use super::topics::{TopicPlan, ULogTopics};
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

/// The plans of `E`, by subscription index.
pub(crate) struct Plans<E> {
    slots: Vec<Slot>,
    topics: PhantomData<fn() -> E>,
}

impl<E: ULogTopics> Plans<E> {
    pub fn new() -> Plans<E> {
        Plans {
            slots: Vec::new(),
            topics: PhantomData,
        }
    }

    /// The plan that decodes `topic`'s records (`None`: they are not read), made at
    /// its first record. A format that does not fit its variant, or cannot be laid
    /// out, is the error of that first call; later calls say `None`.
    #[inline]
    pub fn get(&mut self, topic: &Subscription) -> Result<Option<&TopicPlan>, TypedError> {
        let i = topic.index();
        if !matches!(self.slots.get(i), Some(Slot::Planned(_) | Slot::Unread)) {
            self.plan(topic)?;
        }
        Ok(match &self.slots[i] {
            Slot::Planned(plan) => Some(plan),
            _ => None,
        })
    }

    #[cold]
    fn plan(&mut self, topic: &Subscription) -> Result<(), TypedError> {
        let i = topic.index();
        if i >= self.slots.len() {
            self.slots.resize_with(i + 1, || Slot::Unplanned);
        }
        self.slots[i] = Slot::Unread;
        let Some(variant) = E::variant_of(topic.name()) else {
            return Ok(());
        };
        let layout = topic
            .layout()
            .map_err(|e| TypedError::no_layout(topic, e))?;
        match E::plan(variant, layout) {
            Some(Ok(plan)) => self.slots[i] = Slot::Planned(plan),
            Some(Err(m)) => return Err(TypedError::mismatch(topic, m)),
            None => {}
        }
        Ok(())
    }
}
