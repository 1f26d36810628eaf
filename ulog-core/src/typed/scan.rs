//! [`scan_topics`]: several topics of a log decoded into a [`ULogTopics`] enum in one
//! pass, in file order or by timestamp.

use std::ops::Range;

use crate::definitions::timestamp::Unwrapper;
use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::pass::keep::ScanSummary;
use crate::pass::order::time_ordered;
use crate::pass::scan::{ScanFlow, ScanOptions, ScanOrder};
use crate::pass::source::{drive, drive_keeping, Source};
use crate::pass::visit::{DataRecord, Hand};

use super::error::TypedError;
use super::plans::Plans;
use super::topics::ULogTopics;

/// A data message met by [`scan_topics`]: decoded when the enum names its topic.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct TopicRecord<'r, E> {
    /// Byte offset of the message's 3-byte header.
    pub offset: u64,
    /// Its subscription (name, instance, layout).
    pub topic: &'r Subscription,
    /// Its timestamp in microseconds (narrow version 0 timestamps unwrapped); `None`
    /// when its topic's format has no timestamp field.
    pub timestamp: Option<u64>,
    /// The payload after the msg_id.
    pub payload: &'r [u8],
    /// The message decoded, when the enum names the topic and its format fits;
    /// `None` for the others, which come only with
    /// [`ScanOptions::raw_others`].
    pub message: Option<E>,
}

/// Hands the data messages of the topics a [`ULogTopics`] enum names to `f`, decoded,
/// in file order or by timestamp ([`ScanOptions::order`]); from any [`Source`], as
/// [`scan`](crate::scan) reads it.
///
/// Each subscription is planned once, at its first record, by the same rule as
/// [`ULog::read`](crate::ULog::read): each topic instance on its own, so one that does
/// not fit does not stop the others. A subscription whose format does not fit its
/// variant (or cannot be laid out) is an error handed to `f` once, before its first
/// record; its records are then left out, or handed out undecoded with
/// [`ScanOptions::raw_others`] (which also hands out the topics the enum does not
/// name). `f` returns `()`, or a [`ControlFlow`](std::ops::ControlFlow) to stop early.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::read::ScanOrder;
/// use ulog_core::{ScanOptions, ULogMessage, ULogTopics};
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct BatteryStatus { timestamp: u64, voltage_v: f32 }
///
/// #[derive(ULogTopics)]
/// #[ulog(crate = "ulog_core")]
/// enum Topics { Attitude(VehicleAttitude), Battery(BatteryStatus) }
///
/// let bytes = ulog_core::testing::sample_log();
/// let (mut norms, mut last_time) = (Vec::new(), 0);
/// let by_time = ScanOptions::default().order(ScanOrder::Timestamp);
/// ulog_core::scan_topics::<Topics>(&bytes, &by_time, |record| {
///     let record = record.unwrap();
///     assert!(record.timestamp.unwrap() >= last_time);
///     last_time = record.timestamp.unwrap();
///     if let Some(Topics::Attitude(a)) = record.message {
///         norms.push(a.q.iter().map(|v| v * v).sum::<f32>());
///     }
/// })
/// .unwrap();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// assert_eq!(norms.len(), log.topic("vehicle_attitude", 0).unwrap().len());
/// # }
/// ```
pub fn scan_topics<'s, E: ULogTopics>(
    source: impl Into<Source<'s>>,
    options: &ScanOptions,
    f: impl TopicHandler<E>,
) -> Result<ScanSummary, ReadError> {
    scan_with(source.into(), options, f)
}

/// What [`scan_topics`] hands its records to: any
/// `FnMut(Result<TopicRecord<'_, E>, TypedError>) -> R` where `R` is `()` or a
/// [`ControlFlow`](std::ops::ControlFlow) ([`ScanFlow`]). A trait of its own so that a
/// call names only the enum: `scan_topics::<Topics>(…)`.
pub trait TopicHandler<E>:
    FnMut(Result<TopicRecord<'_, E>, TypedError>) -> <Self as TopicHandler<E>>::Flow
{
    /// What the closure returns.
    type Flow: ScanFlow;
}

impl<E, R: ScanFlow, F: FnMut(Result<TopicRecord<'_, E>, TypedError>) -> R> TopicHandler<E> for F {
    type Flow = R;
}

/// [`scan_topics`], with the closure's type and return type named.
fn scan_with<E, F, R>(
    source: Source<'_>,
    options: &ScanOptions,
    mut f: F,
) -> Result<ScanSummary, ReadError>
where
    E: ULogTopics,
    F: FnMut(Result<TopicRecord<'_, E>, TypedError>) -> R,
    R: ScanFlow,
{
    let mut plans = Plans::<E>::new();
    let raw_others = options.raw_others;
    let window = options.window.clone();
    match options.order {
        ScanOrder::File if options.keep_metadata => {
            // Through a trait object, as below: the plain file-order loop keeps the
            // one direct call site of `f`.
            let f: &mut dyn Handler<E, R> = &mut f;
            drive_keeping(
                source,
                options.read_ahead,
                &options.keep_data,
                None,
                &mut |r: DataRecord<'_>| {
                    hand(&mut plans, raw_others, &window, f, &r, |u| {
                        u.push(r.payload)
                    })
                },
            )
        }
        ScanOrder::File => {
            drive(source, options.read_ahead, &mut |r: DataRecord<'_>| {
                // Each subscription's timestamps, unwrapped as its records come.
                hand(&mut plans, raw_others, &window, &mut f, &r, |u| {
                    u.push(r.payload)
                })
            })
        }
        ScanOrder::Timestamp => {
            // Through a trait object: `f` keeps one direct call site (the file-order
            // loop), where it can be inlined.
            let f: &mut dyn Handler<E, R> = &mut f;
            time_ordered(
                source,
                options.kept().map(|(keep, _)| (keep, None)),
                window.clone(),
                &mut |r, t| hand(&mut plans, raw_others, &window, f, &r, |_| t),
            )
        }
    }
}

/// One record of [`scan_topics`]: planned, decoded, handed to `f`. Inlined into
/// each order's loop, so that `f` has one direct call site (the file-order loop) and
/// can be inlined there; the record goes by reference and is built where it is
/// handed over, since each extra move of a decoded message is a copy per record
/// (bench/README.md has what each cost).
#[inline(always)]
fn hand<E, F, R>(
    plans: &mut Plans<E>,
    raw_others: bool,
    window: &Option<Range<u64>>,
    f: &mut F,
    r: &DataRecord<'_>,
    time: impl FnOnce(&mut Unwrapper) -> Option<u64>,
) -> Hand
where
    E: ULogTopics,
    F: Handler<E, R> + ?Sized,
    R: ScanFlow,
{
    let (plan, unwrap) = plans.next(r.topic);
    let timestamp = time(unwrap);
    // The first record of a topic that does not fit goes the cold way.
    let plan = match plan {
        Ok(plan) => plan,
        Err(e) => return unfit(e, r, timestamp, raw_others, f),
    };
    if let Some(w) = window {
        if !timestamp.is_some_and(|t| w.contains(&t)) {
            return Hand::Next;
        }
    }
    let item = match plan {
        Some(plan) => match E::decode(plan, r.payload) {
            Ok(message) => Ok(record(r, timestamp, Some(message))),
            Err(e) => Err(TypedError::decode(r.topic, r.offset, e)),
        },
        None if raw_others => Ok(record(r, timestamp, None)),
        None => return Hand::SkipTopic,
    };
    Hand::go_on(f(item).go_on())
}

/// The record of `r` handed to the caller.
#[inline(always)]
fn record<'r, E>(
    r: &DataRecord<'r>,
    timestamp: Option<u64>,
    message: Option<E>,
) -> TopicRecord<'r, E> {
    TopicRecord {
        offset: r.offset,
        topic: r.topic,
        timestamp,
        payload: r.payload,
        message,
    }
}

/// What [`scan_topics`] hands records to: named so that the time-order loop can
/// take it as a trait object.
trait Handler<E, R>: FnMut(Result<TopicRecord<'_, E>, TypedError>) -> R {}

impl<E, R, F: FnMut(Result<TopicRecord<'_, E>, TypedError>) -> R> Handler<E, R> for F {}

/// The first record of a subscription whose format does not fit its variant (or
/// cannot be laid out): the error, then (with `raw_others`) the record undecoded.
#[cold]
#[inline(never)]
fn unfit<E, F, R>(
    e: TypedError,
    r: &DataRecord<'_>,
    timestamp: Option<u64>,
    raw_others: bool,
    f: &mut F,
) -> Hand
where
    F: Handler<E, R> + ?Sized,
    R: ScanFlow,
{
    if !f(Err(e)).go_on() {
        return Hand::Stop;
    }
    if !raw_others {
        return Hand::SkipTopic;
    }
    Hand::go_on(f(Ok(record(r, timestamp, None))).go_on())
}
