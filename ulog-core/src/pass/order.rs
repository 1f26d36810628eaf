//! The records of a parsed log by timestamp: a merge of every topic's rows, each
//! topic in its own (file) order, keyed by its unwrapped timestamps.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::ops::Range;

use ulog_format::BasicType;

use crate::bytes::data_payload_at;
use crate::definitions::timestamp::Unwrapper;
use crate::error::ReadError;
use crate::log::ulog::ULog;
use crate::pass::keep::ScanSummary;
use crate::pass::source::{drive_keeping, Inner, Source};
use crate::pass::visit::{DataRecord, Hand};

/// The next row of one topic, ordered by its key (timestamp, or the log's time where
/// it stands), then by file offset.
#[derive(PartialEq, Eq, PartialOrd, Ord)]
struct Cursor {
    key: u64,
    offset: u64,
    sub: usize,
    row: usize,
    /// The row's own timestamp (`None`: the topic has none).
    timestamp: Option<u64>,
}

/// Hands every data message of `source`'s log to `f` by timestamp (see
/// [`ScanOrder::Timestamp`](crate::read::ScanOrder::Timestamp)), with the record's
/// timestamp; a source that is not parsed is parsed first.
/// With `keep`, the summary has the log's metadata (and the data of the topics it
/// names), kept by a second framing of the parsed log's bytes. With a `window`, only
/// the rows from its start on are merged (each topic's first found by binary search),
/// and the pass ends at the first record at or after its end.
pub(crate) fn time_ordered<F>(
    source: Source<'_>,
    keep: Option<(&[String], Option<&[String]>)>,
    window: Option<Range<u64>>,
    f: &mut F,
) -> Result<ScanSummary, ReadError>
where
    F: FnMut(DataRecord<'_>, Option<u64>) -> Hand,
{
    if let Inner::Parsed(log) = source.inner {
        return walk_keeping(log, keep, window, f);
    }
    let path = source.inner.path().map(|p| p.to_owned());
    let bytes = source.inner.read_all()?;
    let log = ULog::parse(&bytes).map_err(|e| match &path {
        Some(p) => e.in_file(p),
        None => e,
    })?;
    walk_keeping(&log, keep, window, f)
}

/// [`walk`], and with `keep` the metadata of `log` in the summary (with the data of
/// the topics `keep` names).
fn walk_keeping<F>(
    log: &ULog<'_>,
    keep: Option<(&[String], Option<&[String]>)>,
    window: Option<Range<u64>>,
    f: &mut F,
) -> Result<ScanSummary, ReadError>
where
    F: FnMut(DataRecord<'_>, Option<u64>) -> Hand,
{
    let mut summary = walk(log, window, f);
    if let Some((topics, only)) = keep {
        let kept = drive_keeping(
            Source::from(log),
            false,
            topics,
            only,
            &mut |_: DataRecord<'_>| Hand::Next,
        )?;
        summary.metadata = kept.metadata;
    }
    Ok(summary)
}

fn walk<F>(log: &ULog<'_>, window: Option<Range<u64>>, f: &mut F) -> ScanSummary
where
    F: FnMut(DataRecord<'_>, Option<u64>) -> Hand,
{
    let data = log.data();
    let topics = log.subscriptions();
    let mut unwrap: Vec<Unwrapper> = topics
        .iter()
        .map(|t| Unwrapper::new(t.timestamp_field()))
        .collect();
    let mut heap = BinaryHeap::with_capacity(topics.len());
    // The cursor of `sub`'s row `row`, if it has one; its timestamp is unwrapped as
    // the topic's rows come, in order.
    let cursor = |sub: usize, row: usize, unwrap: &mut [Unwrapper]| -> Option<Cursor> {
        let index = log.index(sub);
        let offset = index.offsets.view().get(row)?;
        let timestamp = unwrap[sub].push(data_payload_at(data, offset));
        let key = match timestamp {
            Some(t) => t,
            None => index.log_time.get(row).copied().unwrap_or(0),
        };
        Some(Cursor {
            key,
            offset,
            sub,
            row,
            timestamp,
        })
    };
    // Topics whose rows' times never go back in file order (the parse says so) start
    // at the window's start and end at its end; the others (damage, a stale row) are
    // walked whole and filtered, so that a window is exactly the whole pass's records
    // in it.
    let ordered = |sub: usize| !log.index(sub).goes_back;
    for sub in 0..topics.len() {
        let first = match &window {
            Some(w) if ordered(sub) => first_at_or_after(log, sub, w.start),
            _ => 0,
        };
        if let Some(c) = cursor(sub, first, &mut unwrap) {
            heap.push(Reverse(c));
        }
    }
    let mut stopped = false;
    while let Some(Reverse(c)) = heap.pop() {
        if window.as_ref().is_some_and(|w| c.key >= w.end) {
            // Past the end: a topic in time order has no more rows in the window.
            if !ordered(c.sub) {
                if let Some(next) = cursor(c.sub, c.row + 1, &mut unwrap) {
                    heap.push(Reverse(next));
                }
            }
            continue;
        }
        let at = c.offset as usize + 3;
        let record = DataRecord {
            offset: c.offset,
            msg_id: u16::from_le_bytes([data[at], data[at + 1]]),
            topic: &topics[c.sub],
            payload: data_payload_at(data, c.offset),
            sub: c.sub as u32,
        };
        match f(record, c.timestamp) {
            Hand::Next => {
                if let Some(next) = cursor(c.sub, c.row + 1, &mut unwrap) {
                    heap.push(Reverse(next));
                }
            }
            Hand::SkipTopic => {}
            Hand::Stop => {
                stopped = true;
                break;
            }
        }
    }
    ScanSummary {
        stopped,
        ..ScanSummary::of(log)
    }
}

/// The first row of subscription `sub` (its rows in time order: not
/// [`goes_back`](crate::log::ulog::TopicIndex::goes_back))
/// whose timestamp is `start` or later, by binary search. Rows whose timestamps must
/// be unwrapped (narrow version 0 ones) are searched from the first, and a topic
/// without timestamps starts at its first row.
fn first_at_or_after(log: &ULog<'_>, sub: usize, start: u64) -> usize {
    let Some(field) = log.subscriptions()[sub].timestamp_field() else {
        return 0;
    };
    if start == 0 || field.ty != BasicType::UInt64 {
        return 0;
    }
    let offsets = log.index(sub).offsets.view();
    let data = log.data();
    let (mut lo, mut hi) = (0, offsets.len());
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        let t = offsets
            .get(mid)
            .and_then(|o| field.raw(data_payload_at(data, o)));
        // A row too short for its timestamp counts as before the start.
        if t.is_some_and(|t| t >= start) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}
