//! Several topics at once: an enum with one variant per binding
//! (`#[derive(ULogTopics)]`), a dispatcher that plans each subscription once, and
//! [`walk`], the glue over the records of a log.

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::Layout;

use super::error::{DecodeError, Mismatch};
use super::message::ULogMessage;
use super::plan::RawPlan;

/// An enum of bindings, one tuple variant per ULog message, derived with
/// `#[derive(ULogTopics)]`.
pub trait ULogTopics: Sized {
    /// The message names of the variants, in declaration order.
    const NAMES: &'static [&'static str];

    /// Plans variant `variant` (an index into [`NAMES`](Self::NAMES)) for a
    /// subscription's layout; `None` if there is no such variant.
    fn plan(variant: usize, layout: &Layout) -> Option<Result<TopicPlan, Mismatch>>;

    /// Decodes a payload with a plan made by [`plan`](Self::plan).
    fn decode(plan: &TopicPlan, payload: &[u8]) -> Result<Self, DecodeError>;

    /// The variant bound to message `name`.
    fn variant_of(name: &str) -> Option<usize> {
        Self::NAMES.iter().position(|n| *n == name)
    }
}

/// The plan of one variant of a [`ULogTopics`] enum for one subscription.
#[derive(Debug, Clone)]
pub struct TopicPlan {
    variant: usize,
    raw: RawPlan,
}

impl TopicPlan {
    /// Plans binding `T` as variant `variant`.
    pub fn new<T: ULogMessage>(variant: usize, layout: &Layout) -> Result<TopicPlan, Mismatch> {
        RawPlan::new::<T>(layout).map(|raw| TopicPlan { variant, raw })
    }

    /// The variant this plan decodes.
    pub fn variant(&self) -> usize {
        self.variant
    }

    /// Decodes a payload as `T`: the binding of this plan's variant (generated code
    /// calls it with the right type; another type decodes other bytes, safely).
    pub fn decode_as<T: ULogMessage>(&self, payload: &[u8]) -> Result<T, DecodeError> {
        self.raw.decode::<T>(payload)
    }
}

/// What a subscription became in a [`TopicDispatcher`].
#[derive(Debug, Clone)]
pub enum Subscription {
    /// A variant of the enum reads it.
    Planned(TopicPlan),
    /// The enum names the message, but the log's format does not fit.
    Mismatched(Arc<Mismatch>),
    /// The enum does not name the message.
    Unnamed,
}

impl Subscription {
    /// What a subscription of message `name` with the log's `layout` becomes for the
    /// enum `E`.
    pub(crate) fn of<E: ULogTopics>(name: &str, layout: &Layout) -> Subscription {
        match E::variant_of(name) {
            None => Subscription::Unnamed,
            Some(variant) => match E::plan(variant, layout) {
                Some(Ok(plan)) => Subscription::Planned(plan),
                Some(Err(mismatch)) => Subscription::Mismatched(Arc::new(mismatch)),
                None => Subscription::Unnamed,
            },
        }
    }
}

/// Plans of one [`ULogTopics`] enum for the subscriptions of one log, made once per
/// subscription. The reader keeps the returned index per `msg_id`, so decoding a
/// record looks nothing up by name.
#[derive(Debug)]
pub struct TopicDispatcher<E> {
    slots: Vec<Subscription>,
    topics: core::marker::PhantomData<fn() -> E>,
}

impl<E: ULogTopics> Default for TopicDispatcher<E> {
    fn default() -> Self {
        TopicDispatcher {
            slots: Vec::new(),
            topics: core::marker::PhantomData,
        }
    }
}

impl<E: ULogTopics> TopicDispatcher<E> {
    /// An empty dispatcher.
    pub fn new() -> Self {
        Self::default()
    }

    /// Plans a subscription of message `name` with the log's `layout`; returns the
    /// slot to decode its records with.
    pub fn subscribe(&mut self, name: &str, layout: &Layout) -> usize {
        self.slots.push(Subscription::of::<E>(name, layout));
        self.slots.len() - 1
    }

    /// What the subscription in `slot` became.
    pub fn subscription(&self, slot: usize) -> Option<&Subscription> {
        self.slots.get(slot)
    }

    /// Decodes a record of the subscription in `slot`: `None` when the slot is not
    /// planned (unnamed or mismatched; see [`subscription`](Self::subscription)).
    pub fn decode(&self, slot: usize, payload: &[u8]) -> Option<Result<E, DecodeError>> {
        match self.slots.get(slot)? {
            Subscription::Planned(plan) => Some(E::decode(plan, payload)),
            _ => None,
        }
    }
}

/// One record of a walk over a log with a [`ULogTopics`] enum.
#[derive(Debug)]
pub enum TopicRecord<'a, E> {
    /// A message the enum names, decoded.
    Message {
        /// The subscription's multi-instance id.
        multi_id: u8,
        /// The decoded message.
        message: E,
    },
    /// A message the enum does not name (or whose format does not fit: that is
    /// reported once, as [`TopicError::Mismatch`], then its records come raw).
    Raw {
        /// The message name.
        name: &'a str,
        /// The subscription's multi-instance id.
        multi_id: u8,
        /// The payload.
        payload: &'a [u8],
    },
}

/// A message of a topic a [`ULogTopics`] enum names, decoded, as
/// [`scan_topics_only`](crate::scan_topics_only) hands it out.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct TopicMessage<E> {
    /// Byte offset of the data message's 3-byte header.
    pub offset: u64,
    /// The subscription's multi-instance id.
    pub multi_id: u8,
    /// The decoded message.
    pub message: E,
}

/// What went wrong with one record of a walk.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum TopicError<'a> {
    /// The log's format of a named message does not fit its binding (reported at the
    /// subscription's first record only).
    Mismatch {
        /// The message name.
        name: &'a str,
        /// The subscription's multi-instance id.
        multi_id: u8,
        /// Every difference.
        mismatch: Arc<Mismatch>,
    },
    /// A payload could not be decoded.
    Decode {
        /// The message name.
        name: &'a str,
        /// The subscription's multi-instance id.
        multi_id: u8,
        /// Why.
        error: DecodeError,
    },
}

impl core::fmt::Display for TopicError<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TopicError::Mismatch {
                name,
                multi_id,
                mismatch,
            } => write!(f, "topic `{name}` instance {multi_id}: {mismatch}"),
            TopicError::Decode {
                name,
                multi_id,
                error,
            } => write!(f, "topic `{name}` instance {multi_id}: {error}"),
        }
    }
}

impl std::error::Error for TopicError<'_> {}

/// READER GLUE: walks the data records of a log, given in file order as
/// `(message name, multi_id, the subscription's layout, payload)`, decoding the
/// messages `E` names and handing the others over raw.
///
/// Plans are made at the first record of each `(name, multi_id)` and kept; the
/// per-record cost is one map lookup by name. A reader that knows its subscriptions
/// should use a [`TopicDispatcher`] per `msg_id` instead and look nothing up.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::{walk, TopicRecord, ULogMessage, ULogTopics};
/// use ulog_format::{Format, Layout};
///
/// #[derive(ULogMessage, Debug)]
/// #[ulog(crate = "ulog_core")]
/// struct Cpuload { timestamp: u64, load: f32 }
///
/// #[derive(ULogTopics, Debug)]
/// #[ulog(crate = "ulog_core")]
/// enum Topics { Cpu(Cpuload) }
///
/// let cpu = Layout::resolve("cpuload", &[Format::parse("cpuload:uint64_t timestamp;float load;").unwrap()][..]).unwrap();
/// let other = Layout::resolve("other", &[Format::parse("other:uint8_t x;").unwrap()][..]).unwrap();
/// let payload: Vec<u8> = [&5u64.to_le_bytes()[..], &0.5f32.to_le_bytes()].concat();
/// let records = vec![("cpuload", 0u8, &cpu, &payload[..]), ("other", 0, &other, &[7u8][..])];
/// let mut seen = Vec::new();
/// for record in walk::<Topics, _>(records) {
///     match record.unwrap() {
///         TopicRecord::Message { message: Topics::Cpu(c), .. } => seen.push(c.load),
///         TopicRecord::Raw { name, .. } => assert_eq!(name, "other"),
///     }
/// }
/// assert_eq!(seen, [0.5]);
/// # }
/// ```
pub fn walk<'a, E, I>(
    records: I,
) -> impl Iterator<Item = Result<TopicRecord<'a, E>, TopicError<'a>>>
where
    E: ULogTopics,
    I: IntoIterator<Item = (&'a str, u8, &'a Layout, &'a [u8])>,
{
    let mut plans: HashMap<&'a str, Vec<(u8, Option<TopicPlan>)>> = HashMap::new();
    records
        .into_iter()
        .map(move |(name, multi_id, layout, payload)| {
            let instances = plans.entry(name).or_default();
            let slot = match instances.iter().position(|(id, _)| *id == multi_id) {
                Some(i) => &instances[i].1,
                None => {
                    let planned = E::variant_of(name).and_then(|v| E::plan(v, layout));
                    let (plan, mismatch) = match planned {
                        Some(Ok(plan)) => (Some(plan), None),
                        Some(Err(m)) => (None, Some(m)),
                        None => (None, None),
                    };
                    instances.push((multi_id, plan));
                    if let Some(m) = mismatch {
                        return Err(TopicError::Mismatch {
                            name,
                            multi_id,
                            mismatch: Arc::new(m),
                        });
                    }
                    &instances[instances.len() - 1].1
                }
            };
            match slot {
                Some(plan) => E::decode(plan, payload)
                    .map(|message| TopicRecord::Message { multi_id, message })
                    .map_err(|error| TopicError::Decode {
                        name,
                        multi_id,
                        error,
                    }),
                None => Ok(TopicRecord::Raw {
                    name,
                    multi_id,
                    payload,
                }),
            }
        })
}
