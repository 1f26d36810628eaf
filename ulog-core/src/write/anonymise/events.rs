//! Dates and times in the arguments of PX4 events (`logging: opening log file
//! 2026-8-20/6_5_17.ulg` is an event whose arguments are the year, the month…): an
//! event's message is its metadata's template filled in with the argument bytes, so
//! the bytes that make a date are found by filling it in again without each of them.

use std::collections::HashMap;

use super::text::date_time_spans;
use crate::access::field::FieldShape;
use crate::events::{EventOptions, Metadata};
use crate::ULog;

/// The rows of the `event` topic whose message shows a date or a time of day (not
/// zeros): each row's payload as logged, with the offsets of the argument bytes that
/// make it (those without which the message changes only between its first date or
/// time and its last). Empty without events or without metadata to decode them.
pub(super) fn dated_events(log: &ULog<'_>) -> HashMap<Vec<u8>, Vec<usize>> {
    let mut out = HashMap::new();
    let (Ok(topic), Some(Ok(metadata))) = (log.topic("event", 0), Metadata::from_log(log)) else {
        return out;
    };
    let Ok(arguments) = topic.field("arguments") else {
        return out;
    };
    let options = EventOptions::default().metadata(metadata);
    let decode = |payload: &[u8]| -> Option<String> {
        let events = log.decode_events(&topic, &options, std::iter::once((0, payload)));
        events.events.into_iter().next().map(|e| e.text)
    };
    let FieldShape::Array(n) = arguments.shape() else {
        return out;
    };
    let bytes = arguments.offset()..arguments.offset() + n * arguments.ty().size();
    for payload in topic.payloads() {
        let Some(text) = decode(payload) else {
            continue;
        };
        let spans: Vec<(usize, usize)> = date_time_spans(text.as_bytes())
            .into_iter()
            .filter(|&(a, b)| {
                text.as_bytes()[a..b]
                    .iter()
                    .any(|c| (b'1'..=b'9').contains(c))
            })
            .collect();
        let (Some(first), Some(last)) = (spans.first(), spans.last()) else {
            continue;
        };
        let (head, tail) = (&text[..first.0], &text[last.1..]);
        let mut trial = payload.to_vec();
        let mut dated = Vec::new();
        for j in bytes
            .clone()
            .filter(|&j| payload.get(j).is_some_and(|&b| b != 0))
        {
            trial[j] = 0;
            if let Some(other) = decode(&trial) {
                if other != text && other.starts_with(head) && other.ends_with(tail) {
                    dated.push(j);
                }
            }
            trial[j] = payload[j];
        }
        if !dated.is_empty() {
            out.insert(payload.to_vec(), dated);
        }
    }
    out
}
