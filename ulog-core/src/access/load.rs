//! [`load_columns`]: every topic of a log as typed columns, from any source, on one
//! thread or several.
//!
//! From a parsed log, each topic's columns are filled from its index, topics shared
//! between threads. From any other source the log is read in one pass, without an
//! index, so that the memory held is the columns themselves plus a few read buffers;
//! on several threads each thread reads the whole log and fills the columns of its
//! share of the topics (a source that cannot be read twice, a reader, is read on one
//! thread).

use std::path::Path;
use std::sync::Arc;

use crate::access::columns::{Column, Table};
use crate::access::lookup::LookupError;
use crate::definitions::Subscription;
use crate::error::{ReadError, ReadErrorKind};
use crate::estimate::rows_at_end;
use crate::log::ulog::ULog;
use crate::parallel::Shares;
use crate::pass::keep::ScanSummary;
use crate::pass::scan::ScanOptions;
use crate::pass::source::{drive, Inner, Source};
use crate::pass::visit::{DataRecord, Hand};

/// The columns of one topic instance.
#[derive(Debug, Clone, PartialEq)]
pub struct TopicColumns {
    /// The subscription.
    pub topic: Arc<Subscription>,
    /// The columns (as [`Topic::columns`](crate::Topic::columns) gives them), or why
    /// there are none: a format that could not be laid out.
    pub columns: Result<Vec<Column>, LookupError>,
}

/// Every topic of a log as columns, with what the pass saw.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedColumns {
    /// One entry per subscription, in the order of their `A` messages (topics without
    /// data messages have empty columns).
    pub topics: Vec<TopicColumns>,
    /// Header, flag bits, counts and findings of the whole log.
    pub summary: ScanSummary,
}

/// Every topic's columns (leaf fields in pyulog's order, padding left out, `char[N]`
/// as one string column), on up to [`ScanOptions::threads`] threads.
///
/// ```
/// use ulog_core::{ScanOptions, Source};
/// # let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let two = ScanOptions::default().threads(2);
/// let indexed = ulog_core::load_columns(&log, &two)?;
/// let one_pass = ulog_core::load_columns(Source::reader(&bytes[..]), &ScanOptions::default())?;
/// for ((topic, a), b) in log.topics().zip(&indexed.topics).zip(&one_pass.topics) {
///     assert_eq!(a.topic.name(), topic.name());
///     assert_eq!(a.columns, topic.columns());
///     assert_eq!(b.columns, a.columns);
/// }
/// assert_eq!(one_pass.summary, indexed.summary);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn load_columns<'s>(
    source: impl Into<Source<'s>>,
    options: &ScanOptions,
) -> Result<LoadedColumns, ReadError> {
    let source = source.into();
    let threads = options.threads.clamp(1, 64);
    match &source.inner {
        Inner::Parsed(log) => return Ok(from_index(log, threads)),
        Inner::Reader(_) => return load_one(source, options.read_ahead, u64::MAX),
        Inner::Bytes(..) | Inner::File(_) => {}
    }
    let len = match &source.inner {
        Inner::Bytes(bytes, _) => bytes.len() as u64,
        Inner::File(path) => file_len(path)?,
        _ => u64::MAX,
    };
    // Logs smaller than this per thread are not worth more threads.
    const MIN_SHARE: u64 = 4 << 20;
    let threads = threads.min((len / MIN_SHARE).max(1) as usize);
    if threads == 1 {
        return load_one(source, options.read_ahead, len);
    }
    load_shared(&source, len, threads, (len / 50).max(1 << 20))
}

/// The columns of a parsed log, topics shared between threads by their bytes.
fn from_index(log: &ULog<'_>, threads: usize) -> LoadedColumns {
    let topics: Vec<_> = log.topics().collect();
    let costs: Vec<u64> = topics
        .iter()
        .map(|t| (t.len() * (t.layout().map_or(0, |l| l.size()) + 16)) as u64)
        .collect();
    let loaded = crate::parallel::largest_first(&costs, threads, |i| {
        Ok::<_, core::convert::Infallible>(topics[i].columns())
    });
    LoadedColumns {
        topics: topics
            .iter()
            .zip(loaded)
            .map(|(t, columns)| TopicColumns {
                topic: t.subscription().clone(),
                columns: match columns {
                    Some(Ok(c)) => c,
                    // Every job runs (none can fail).
                    _ => unreachable!("every topic is loaded"),
                },
            })
            .collect(),
        summary: ScanSummary::of(log),
    }
}

/// The size of the file at `path`.
pub(crate) fn file_len(path: &Path) -> Result<u64, ReadError> {
    let meta = std::fs::metadata(path).map_err(|e| ReadError::io(e, None).in_file(path))?;
    Ok(meta.len())
}

/// The tables of the topics one thread fills, by subscription index.
struct Tables {
    tables: Vec<Option<Table>>,
    /// The log's length (`u64::MAX` when unknown).
    len: u64,
}

impl Tables {
    fn new(len: u64) -> Tables {
        Tables {
            tables: Vec::new(),
            len,
        }
    }

    #[inline]
    fn push(&mut self, r: &DataRecord<'_>) {
        let len = self.len;
        match self.tables.get_mut(r.topic.index()) {
            // A topic's rows are about evenly spread over the file: room for its rows
            // so far scaled to the whole file.
            Some(Some(table)) => table.push(r.payload, |rows| rows_at_end(rows, r.offset, len)),
            _ => self.first(r),
        }
    }

    #[cold]
    fn first(&mut self, r: &DataRecord<'_>) {
        let sub = r.topic.index();
        if sub >= self.tables.len() {
            self.tables.resize_with(sub + 1, || None);
        }
        // A subscription without a layout has no table; its records are left out
        // here and its entry says why.
        if let Ok(layout) = r.topic.layout() {
            let mut table = Table::new(layout, 0);
            table.push(r.payload, |_| 0);
            self.tables[sub] = Some(table);
        }
    }
}

/// The topics of `summary` with their tables, taken from the shares that filled
/// them (each subscription is filled by one share at most).
fn finish(summary: ScanSummary, shares: Vec<Tables>) -> LoadedColumns {
    let mut joined: Vec<Option<Table>> = Vec::new();
    for tables in shares {
        for (i, table) in tables.tables.into_iter().enumerate() {
            if i >= joined.len() {
                joined.resize_with(i + 1, || None);
            }
            if joined[i].is_none() {
                joined[i] = table;
            }
        }
    }
    joined.resize_with(summary.topics.len(), || None);
    let topics = summary
        .topics
        .iter()
        .zip(joined)
        .map(|(topic, table)| TopicColumns {
            topic: topic.clone(),
            columns: match (topic.layout(), table) {
                (Err(e), _) => Err(LookupError::layout(topic, e)),
                (Ok(_), Some(table)) => Ok(table.finish()),
                (Ok(layout), None) => Ok(Table::new(layout, 0).finish()),
            },
        })
        .collect();
    LoadedColumns { topics, summary }
}

/// One pass on this thread over a log of `len` bytes (`u64::MAX`: unknown).
pub(crate) fn load_one(
    source: Source<'_>,
    read_ahead: bool,
    len: u64,
) -> Result<LoadedColumns, ReadError> {
    let mut tables = Tables::new(len);
    let summary = drive(source, read_ahead, &mut |r: DataRecord<'_>| {
        tables.push(&r);
        Hand::Next
    })?;
    Ok(finish(summary, vec![tables]))
}

/// Whether two passes over a file framed the same log.
fn same_log(a: &ScanSummary, b: &ScanSummary) -> bool {
    (a.messages, a.data_messages, a.topics.len(), &a.findings)
        == (b.messages, b.data_messages, b.topics.len(), &b.findings)
}

/// A source like `source` for one more pass: the same bytes, or the file opened again.
fn again<'s>(source: &Source<'s>) -> Source<'s> {
    match &source.inner {
        Inner::Bytes(bytes, path) => Source {
            inner: Inner::Bytes(bytes, *path),
            observer: None,
        },
        Inner::File(path) => Source::file(path),
        Inner::Parsed(log) => Source {
            inner: Inner::Parsed(log),
            observer: None,
        },
        Inner::Reader(_) => unreachable!("a reader is read once"),
    }
}

/// Loads `source` (a log of `len` bytes, read as many times as there are threads) on
/// `threads` threads, the shares balanced on its first `sample` bytes.
pub(crate) fn load_shared(
    source: &Source<'_>,
    len: u64,
    threads: usize,
    sample: u64,
) -> Result<LoadedColumns, ReadError> {
    if threads <= 1 {
        return load_one(again(source), false, len);
    }
    // The work of a row, in units of about a column value's: the row itself (its
    // hand-out and gathering; framing is the same for every thread) weighs about five
    // values, then its values and the copy of its bytes. (Five rather than one, after
    // timing each thread of a load of the two large benchmark logs.)
    let mut work: Vec<u64> = Vec::new();
    let mut per_row: Vec<u64> = Vec::new();
    drive(again(source), false, &mut |r: DataRecord<'_>| {
        if r.offset >= sample {
            return Hand::Stop;
        }
        let sub = r.topic.index();
        if sub >= work.len() {
            work.resize(sub + 1, 0);
            per_row.resize(sub + 1, 0);
        }
        if per_row[sub] == 0 {
            let columns = r.topic.layout().map_or(0, |l| l.columns().count()) as u64;
            per_row[sub] = 40 + 8 * columns + r.payload.len() as u64 / 4;
        }
        work[sub] += per_row[sub];
        Hand::Next
    })?;
    let shares = Shares::new(&work, threads);
    let results: Vec<Result<(ScanSummary, Tables), ReadError>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|k| {
                let mut shares = shares.clone();
                let mine = again(source);
                s.spawn(move || {
                    let mut tables = Tables::new(len);
                    // Another thread's subscriptions are framed, not handed out.
                    let summary = drive(mine, false, &mut |r: DataRecord<'_>| {
                        if shares.owner(r.topic.index()) == k {
                            tables.push(&r);
                            Hand::Next
                        } else {
                            Hand::SkipTopic
                        }
                    })?;
                    Ok((summary, tables))
                })
            })
            .collect();
        // A panic in a worker is a bug of this function: passed on.
        crate::parallel::join_all(handles)
    });
    let mut shared = Vec::with_capacity(threads);
    let mut summary: Option<ScanSummary> = None;
    for r in results {
        let (s, tables) = r?;
        shared.push(tables);
        // Every thread framed the whole file: the same log, unless the file changed
        // between their reads (a logger writing it, a sync rewriting it).
        match &summary {
            Some(first) if !same_log(first, &s) => {
                let e = ReadError::new(ReadErrorKind::Changed, None);
                return Err(match source.inner.path() {
                    Some(path) => e.in_file(path),
                    None => e,
                });
            }
            Some(_) => {}
            None => summary = Some(s),
        }
    }
    Ok(finish(summary.expect("at least one thread"), shared))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{sample_log, LogBuilder};

    /// Logs to load: the sample, and the shared corpus when it is there.
    fn logs() -> Vec<(String, Vec<u8>)> {
        let mut logs = vec![("sample".to_owned(), sample_log())];
        let corpus = std::env::var_os("ULOG_CORPUS")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus"));
        if let Ok(dir) = std::fs::read_dir(corpus.join("files")) {
            for entry in dir.flatten() {
                let p = entry.path();
                if p.extension().is_some_and(|e| e == "ulg") {
                    logs.push((p.display().to_string(), std::fs::read(&p).unwrap()));
                }
            }
        }
        logs
    }

    fn temp_file(bytes: &[u8]) -> std::path::PathBuf {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "ulog-load-{}-{}.ulg",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::write(&path, bytes).unwrap();
        path
    }

    /// The same topics, columns (compared as text: NaN values are equal there) and
    /// summary.
    fn same(a: &LoadedColumns, b: &LoadedColumns, what: &str) {
        assert_eq!(a.topics.len(), b.topics.len(), "{what}");
        for (x, y) in a.topics.iter().zip(&b.topics) {
            assert_eq!(x.topic, y.topic, "{what}");
            assert_eq!(
                format!("{:?}", x.columns),
                format!("{:?}", y.columns),
                "{what}"
            );
        }
        assert_eq!(a.summary, b.summary, "{what}");
    }

    #[test]
    fn every_source_and_thread_count_loads_what_the_index_loads() {
        let mut checked = 0;
        let one = ScanOptions::default();
        for (name, bytes) in logs() {
            let Ok(log) = ULog::parse(&bytes) else {
                let e = load_columns(&bytes, &one).unwrap_err();
                assert_eq!(Err(e), ULog::parse(&bytes).map(|_| ()), "{name}");
                continue;
            };
            let indexed = load_columns(&log, &one).unwrap();
            assert_eq!(indexed.topics.len(), log.subscriptions().len(), "{name}");
            for (t, loaded) in log.topics().zip(&indexed.topics) {
                assert_eq!(&loaded.topic, t.subscription());
                // Compared as text: NaN values are equal there.
                assert_eq!(
                    format!("{:?}", loaded.columns),
                    format!("{:?}", t.columns()),
                    "{name}: {}",
                    t.name()
                );
            }
            for threads in [2, 3] {
                let options = ScanOptions::default().threads(threads);
                same(
                    &load_columns(&log, &options).unwrap(),
                    &indexed,
                    &format!("{name}: indexed, {threads} threads"),
                );
            }
            let pass = load_columns(Source::reader(&bytes[..]), &one).unwrap();
            same(&pass, &indexed, &format!("{name}: one pass"));
            assert_eq!(pass.summary.messages, log.message_count(), "{name}");
            assert_eq!(pass.summary.findings, log.findings(), "{name}");
            let path = temp_file(&bytes);
            // Shares balanced on samples of every size (none: every topic is first met
            // after it) give the same columns and findings, over the bytes and over a
            // file read once per thread.
            let len = bytes.len() as u64;
            for (threads, sample) in [(2, 0), (2, len / 3), (3, 17), (2, len), (1, 0)] {
                let what = format!("{name}: {threads} threads, sample {sample}");
                let over_bytes = load_shared(&Source::from(&bytes), len, threads, sample);
                same(&over_bytes.unwrap(), &pass, &what);
                let over_file = load_shared(&Source::file(&path), len, threads, sample);
                same(&over_file.unwrap(), &pass, &what);
                checked += 1;
            }
            std::fs::remove_file(&path).unwrap();
        }
        assert!(checked >= 3);
    }

    #[test]
    fn a_file_that_is_not_ulog_or_missing_is_an_error_naming_it() {
        let path = temp_file(b"PK\x03\x04 not a log at all");
        let two = ScanOptions::default().threads(2);
        let e = load_columns(Source::file(&path), &two).unwrap_err();
        assert!(
            matches!(e.kind(), crate::error::ReadErrorKind::NotULog { .. }),
            "{e}"
        );
        assert_eq!(e.path(), Some(path.as_path()));
        std::fs::remove_file(&path).unwrap();
        let e = load_columns(Source::file(&path), &two).unwrap_err();
        assert!(
            matches!(e.kind(), crate::error::ReadErrorKind::Io(_)),
            "{e}"
        );
        assert_eq!(e.path(), Some(path.as_path()));
    }

    #[test]
    fn a_topic_without_layout_is_an_error_and_others_still_load() {
        let mut b = LogBuilder::new(1, 0);
        b.format("good:uint64_t timestamp;float x;");
        b.format("bad:uint64_t timestamp;missing_type y;");
        b.subscribe(0, 0, "good");
        b.subscribe(0, 1, "bad");
        b.data(
            0,
            &[&5u64.to_le_bytes()[..], &1.5f32.to_le_bytes()].concat(),
        );
        let log = ULog::parse(b.bytes()).unwrap();
        for threads in [1, 2] {
            let all = load_columns(&log, &ScanOptions::default().threads(threads)).unwrap();
            assert_eq!(all.topics.len(), 2);
            let good = all.topics[0].columns.as_ref().unwrap();
            assert_eq!(
                good[1].data,
                crate::access::columns::ColumnData::F32(vec![1.5])
            );
            let err = all.topics[1].columns.as_ref().unwrap_err();
            assert!(err.to_string().contains("missing_type"), "{err}");
            assert_eq!(err.position(), Some(log.subscriptions()[1].offset()));
        }
    }
}
