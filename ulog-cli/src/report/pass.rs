//! The report's passes over a log ([`Input`]): the first keeps everything but the
//! data (the metadata) and counts each subscription's rows; the second hands each data
//! message to what reads its subscription ([`Routes`]) and to the flight analysis. A
//! file is read in chunks, so the memory is what the page holds, not the log.

use ulog_core::analysis::FlightAnalyzer;
use ulog_core::read::LogMetadata;
use ulog_core::{ScanOptions, ScanSummary};

use crate::failure::Failure;
use crate::input::Input;

/// What the first pass found.
pub struct Survey {
    /// What framing saw (findings, counts).
    pub summary: ScanSummary,
    /// Everything but the data.
    pub metadata: LogMetadata,
    /// Per subscription, its data messages.
    pub rows: Vec<usize>,
    /// The file's size and time before the first pass ([`Input::stamp`]).
    stamp: Option<(u64, Option<std::time::SystemTime>)>,
}

/// Reads the next chunk while one is framed (a few MiB).
fn options() -> ScanOptions {
    ScanOptions::default().read_ahead(true)
}

/// The first pass: metadata and rows.
pub fn survey(input: &Input, name: &str) -> Result<Survey, Failure> {
    let mut rows: Vec<usize> = Vec::new();
    let keep = options().keep_metadata(true);
    let stamp = input.stamp();
    let mut summary = ulog_core::scan(input.source(), &keep, |r| {
        let i = r.topic.index();
        if rows.len() <= i {
            rows.resize(i + 1, 0);
        }
        rows[i] += 1;
    })
    .map_err(|e| input.failure(name, &e))?;
    rows.resize(summary.topics.len(), 0);
    let Some(metadata) = summary.metadata.take() else {
        unreachable!("a pass asked to keep the metadata keeps it")
    };
    Ok(Survey {
        summary,
        metadata,
        rows,
        stamp,
    })
}

/// What reads the data messages of a subscription in the second pass.
pub trait Rows {
    /// The payload (after the msg_id) of the subscription's next data message.
    fn push(&mut self, payload: &[u8]);
}

/// Per subscription (its index), what reads its data messages.
pub struct Routes<'c> {
    by_sub: Vec<Vec<&'c mut dyn Rows>>,
}

impl<'c> Routes<'c> {
    /// No routes yet, for a log of `subscriptions` subscriptions.
    pub fn new(subscriptions: usize) -> Routes<'c> {
        Routes {
            by_sub: (0..subscriptions).map(|_| Vec::new()).collect(),
        }
    }

    /// Hands the data messages of subscription `sub` to `rows` too.
    pub fn add(&mut self, sub: usize, rows: &'c mut dyn Rows) {
        if let Some(readers) = self.by_sub.get_mut(sub) {
            readers.push(rows);
        }
    }
}

/// A second pass: each data message to what reads its subscription. The log must be
/// the one the first pass (`survey`) read: one that changed meanwhile is a failure.
/// `analyzer`, where given, is handed every data message too.
pub fn read(
    input: &Input,
    name: &str,
    survey: &Survey,
    mut routes: Routes<'_>,
    mut analyzer: Option<&mut FlightAnalyzer>,
) -> Result<(), Failure> {
    if routes.by_sub.iter().all(Vec::is_empty) && analyzer.is_none() {
        return Ok(());
    }
    let summary = ulog_core::scan(input.source(), &options(), |r| {
        // Subscriptions the first pass did not see (the file grew) have no routes.
        if let Some(readers) = routes.by_sub.get_mut(r.topic.index()) {
            for rows in readers {
                rows.push(r.payload);
            }
        }
        if let Some(a) = analyzer.as_deref_mut() {
            a.push(r.topic, r.payload);
        }
    })
    .map_err(|e| input.failure(name, &e))?;
    let seen = |s: &ScanSummary| {
        (
            s.header,
            s.flag_bits,
            s.messages,
            s.data_messages,
            s.topics.clone(),
            s.findings.clone(),
        )
    };
    if seen(&summary) != seen(&survey.summary) || input.stamp() != survey.stamp {
        return Err(Failure::about(
            name,
            "the file changed while it was read (two passes over it framed different logs)",
        ));
    }
    Ok(())
}
