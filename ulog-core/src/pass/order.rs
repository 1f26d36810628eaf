//! The records of a parsed log by timestamp: a merge of every topic's rows, each
//! topic in its own (file) order, keyed by its unwrapped timestamps.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::bytes::data_payload_at;
use crate::definitions::timestamp::Unwrapper;
use crate::error::ReadError;
use crate::log::ulog::ULog;
use crate::pass::driver::{DataRecord, Hand, ScanSummary};
use crate::pass::source::{drive_keeping, Inner, Source};

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
/// With `keep`, the summary has the log's metadata, kept by a second framing of the
/// parsed log's bytes.
pub(crate) fn time_ordered<F>(
    source: Source<'_>,
    keep: bool,
    f: &mut F,
) -> Result<ScanSummary, ReadError>
where
    F: FnMut(DataRecord<'_>, Option<u64>) -> Hand,
{
    if let Inner::Parsed(log) = source.inner {
        return walk_keeping(log, keep, f);
    }
    let path = source.inner.path().map(|p| p.to_owned());
    let bytes = source.inner.read_all()?;
    let log = ULog::parse(&bytes).map_err(|e| match &path {
        Some(p) => e.in_file(p),
        None => e,
    })?;
    walk_keeping(&log, keep, f)
}

/// [`walk`], and with `keep` the metadata of `log` in the summary.
fn walk_keeping<F>(log: &ULog<'_>, keep: bool, f: &mut F) -> Result<ScanSummary, ReadError>
where
    F: FnMut(DataRecord<'_>, Option<u64>) -> Hand,
{
    let mut summary = walk(log, f);
    if keep {
        let kept = drive_keeping(Source::from(log), false, &mut |_: DataRecord<'_>| {
            Hand::Next
        })?;
        summary.metadata = kept.metadata;
    }
    Ok(summary)
}

fn walk<F>(log: &ULog<'_>, f: &mut F) -> ScanSummary
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
    for sub in 0..topics.len() {
        if let Some(c) = cursor(sub, 0, &mut unwrap) {
            heap.push(Reverse(c));
        }
    }
    let mut stopped = false;
    while let Some(Reverse(c)) = heap.pop() {
        let at = c.offset as usize + 3;
        let record = DataRecord {
            offset: c.offset,
            msg_id: u16::from_le_bytes([data[at], data[at + 1]]),
            topic: &topics[c.sub],
            payload: data_payload_at(data, c.offset),
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
