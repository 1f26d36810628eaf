//! Columnar load straight from a file: one pass in file order over bytes read from
//! disk (no memory map, no index), so that the memory held is the columns themselves
//! plus a few read buffers. On several threads, each thread reads the whole file and
//! fills the columns of its share of the topics.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::access::columns::{Column, Table};
use crate::error::{Error, ErrorKind, Result};
use crate::estimate::rows_at_end;
use crate::read::scan::{scan_range, ScanRecord, ScanSummary, ScanTopic};

/// The columns of one topic instance loaded by [`load_columns`] or
/// [`load_file_columns`].
#[derive(Debug, Clone, PartialEq)]
pub struct TopicColumns {
    /// The subscription.
    pub topic: ScanTopic,
    /// The columns (as [`Topic::load_columns`](crate::Topic::load_columns) gives
    /// them), or why there are none: a format that could not be laid out.
    pub columns: Result<Vec<Column>>,
}

/// Every topic of a log as columns, with what the scan saw.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedColumns {
    /// One entry per subscription, in the order of the `A` messages (topics without
    /// data messages have empty columns).
    pub topics: Vec<TopicColumns>,
    /// Header, flag bits, counts and findings of the whole file.
    pub summary: ScanSummary,
}

/// The tables of the topics one thread fills, by subscription index.
struct Tables {
    tables: Vec<Option<Table>>,
    /// The file's length (`u64::MAX` when unknown).
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
    fn push(&mut self, r: &ScanRecord<'_, '_>) {
        let len = self.len;
        match self.tables.get_mut(r.subscription) {
            // A topic's rows are about evenly spread over the file: room for its rows
            // so far scaled to the whole file.
            Some(Some(table)) => table.push(r.payload, |rows| rows_at_end(rows, r.offset, len)),
            _ => self.first(r),
        }
    }

    #[cold]
    fn first(&mut self, r: &ScanRecord<'_, '_>) {
        if r.subscription >= self.tables.len() {
            self.tables.resize_with(r.subscription + 1, || None);
        }
        // A subscription without a layout has no table; its records are left out
        // here and its entry says why.
        if let Some(layout) = r.layout {
            let mut table = Table::new(layout, 0);
            table.push(r.payload, |_| 0);
            self.tables[r.subscription] = Some(table);
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
            columns: match (&topic.layout, table) {
                (Err(e), _) => Err(Error::new(
                    ErrorKind::Layout(e.clone()),
                    topic.subscribed_at,
                )),
                (Ok(_), Some(table)) => Ok(table.finish()),
                (Ok(layout), None) => Ok(Table::new(layout, 0).finish()),
            },
        })
        .collect();
    LoadedColumns { topics, summary }
}

/// Every topic's columns, read in one pass from `src` (the whole file, from its
/// first byte).
///
/// ```
/// # let bytes = ulog_core::testing::sample_log();
/// let loaded = ulog_core::load_columns(&bytes[..])?;
/// let log = ulog_core::ULog::parse(&bytes)?;
/// for (topic, loaded) in log.topics().zip(&loaded.topics) {
///     assert_eq!(loaded.topic.name, topic.name());
///     assert_eq!(loaded.columns.as_ref().ok(), topic.load_columns().as_ref().ok());
/// }
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn load_columns<R: Read>(src: R) -> Result<LoadedColumns> {
    load_one(src, u64::MAX)
}

/// [`load_columns`] on this thread, of a file of `len` bytes (`u64::MAX`: unknown).
fn load_one<R: Read>(src: R, len: u64) -> Result<LoadedColumns> {
    let mut tables = Tables::new(len);
    let summary = scan_range(src, u64::MAX, |r| {
        tables.push(&r);
        true
    })?;
    Ok(finish(summary, vec![tables]))
}

/// Every topic's columns of the file at `path`, read on up to `threads` threads
/// (`0` or `1`: on this one): the same result as [`load_columns`]. Each thread reads
/// the whole file and fills the columns of its share of the topics; the shares are
/// balanced by how many values each topic has in the first 2% of the file.
///
/// ```no_run
/// let loaded = ulog_core::load_file_columns("flight.ulg", 2)?;
/// for t in &loaded.topics {
///     if let Ok(columns) = &t.columns {
///         println!("{} {}: {} columns", t.topic.name, t.topic.multi_id, columns.len());
///     }
/// }
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn load_file_columns(path: impl AsRef<Path>, threads: usize) -> Result<LoadedColumns> {
    let path = path.as_ref();
    let len = file_len(path)?;
    // Files smaller than this per thread are not worth more threads.
    const MIN_SHARE: u64 = 4 << 20;
    let threads = threads.clamp(1, 64).min((len / MIN_SHARE).max(1) as usize);
    load_shared(path, len, threads, (len / 50).max(1 << 20))
}

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> Error + Copy + '_ {
    move |e| Error::new(ErrorKind::Io(format!("{}: {e}", path.display())), 0)
}

/// The size of the file at `path`.
pub(crate) fn file_len(path: &Path) -> Result<u64> {
    Ok(std::fs::metadata(path).map_err(io_error(path))?.len())
}

/// Which thread fills which subscription's columns. Every thread keeps its own copy
/// and, seeing the same subscriptions in the same order, takes the same decisions.
#[derive(Clone)]
struct Shares {
    owner: Vec<Option<usize>>,
    load: Vec<u64>,
    /// The weight given to a subscription first met after the sample.
    typical: u64,
}

impl Shares {
    /// Shares balanced by the work of each subscription in the sample,
    /// largest first, each to the least loaded share.
    fn new(bytes: &[u64], threads: usize) -> Shares {
        let mut shares = Shares {
            owner: vec![None; bytes.len()],
            load: vec![0; threads],
            typical: 0,
        };
        let mut order: Vec<usize> = (0..bytes.len()).collect();
        order.sort_by_key(|&i| (core::cmp::Reverse(bytes[i]), i));
        for i in order {
            shares.assign(i, bytes[i]);
        }
        let total: u64 = bytes.iter().sum();
        shares.typical = total / bytes.len().max(1) as u64;
        shares
    }

    fn assign(&mut self, sub: usize, weight: u64) -> usize {
        let least = (0..self.load.len())
            .min_by_key(|&k| (self.load[k], k))
            .expect("at least one share");
        self.load[least] += weight;
        if sub >= self.owner.len() {
            self.owner.resize(sub + 1, None);
        }
        self.owner[sub] = Some(least);
        least
    }

    #[inline]
    fn owner(&mut self, sub: usize) -> usize {
        match self.owner.get(sub) {
            Some(&Some(k)) => k,
            _ => self.assign(sub, self.typical),
        }
    }
}

/// Loads on `threads` threads, the shares balanced on the file's first `sample`
/// bytes.
pub(crate) fn load_shared(
    path: &Path,
    len: u64,
    threads: usize,
    sample: u64,
) -> Result<LoadedColumns> {
    let io = io_error(path);
    if threads <= 1 {
        return load_one(File::open(path).map_err(io)?, len);
    }
    // The work of a row, in units of about a column value's: the row itself (its
    // hand-out and gathering; framing is the same for every thread) weighs about five
    // values, then its values and the copy of its bytes. (Five rather than one, after
    // timing each thread of a load of the two large benchmark logs.)
    let mut work: Vec<u64> = Vec::new();
    let mut per_row: Vec<u64> = Vec::new();
    scan_range(File::open(path).map_err(io)?, sample, |r| {
        if r.offset < sample {
            if r.subscription >= work.len() {
                work.resize(r.subscription + 1, 0);
                per_row.resize(r.subscription + 1, 0);
            }
            if per_row[r.subscription] == 0 {
                let columns = r.layout.map_or(0, |l| l.columns().count()) as u64;
                per_row[r.subscription] = 40 + 8 * columns + r.payload.len() as u64 / 4;
            }
            work[r.subscription] += per_row[r.subscription];
        }
        true
    })?;
    let shares = Shares::new(&work, threads);
    let results: Vec<Result<(ScanSummary, Tables)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|k| {
                let mut shares = shares.clone();
                s.spawn(move || {
                    let file = File::open(path).map_err(io)?;
                    let mut tables = Tables::new(len);
                    // Another thread's subscriptions are framed, not handed out.
                    let summary = scan_range(file, u64::MAX, |r| {
                        let mine = shares.owner(r.subscription) == k;
                        if mine {
                            tables.push(&r);
                        }
                        mine
                    })?;
                    Ok((summary, tables))
                })
            })
            .collect();
        handles
            .into_iter()
            // A panic in a worker is a bug of this function: pass it on.
            .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    let mut shared = Vec::with_capacity(threads);
    let mut summary = None;
    for r in results {
        let (s, tables) = r?;
        shared.push(tables);
        // Every thread framed the whole file.
        summary.get_or_insert(s);
    }
    Ok(finish(summary.expect("at least one thread"), shared))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::read::log::ULog;
    use crate::testing::sample_log;

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
            let id = |t: &ScanTopic| (t.name.clone(), t.multi_id, t.msg_id, t.subscribed_at);
            assert_eq!(id(&x.topic), id(&y.topic), "{what}");
            assert_eq!(
                format!("{:?}", x.columns),
                format!("{:?}", y.columns),
                "{what}"
            );
        }
        assert_eq!(a.summary, b.summary, "{what}");
    }

    #[test]
    fn one_pass_and_shared_threads_load_what_the_parse_loads() {
        let mut checked = 0;
        for (name, bytes) in logs() {
            let Ok(log) = ULog::parse(&bytes) else {
                assert!(load_columns(&bytes[..]).is_err(), "{name}");
                continue;
            };
            let indexed = log.load_all_columns(1);
            let one = load_columns(&bytes[..]).unwrap();
            assert_eq!(one.topics.len(), indexed.len(), "{name}");
            for ((t, loaded), expected) in log.topics().zip(&one.topics).zip(&indexed) {
                assert_eq!(
                    (loaded.topic.name.as_str(), loaded.topic.multi_id),
                    (t.name(), t.multi_id())
                );
                // Compared as text: NaN values are equal there.
                assert_eq!(
                    format!("{:?}", loaded.columns),
                    format!("{expected:?}"),
                    "{name}: {}",
                    t.name()
                );
            }
            assert_eq!(one.summary.messages, log.message_count(), "{name}");
            assert_eq!(one.summary.findings, log.findings(), "{name}");
            let path = temp_file(&bytes);
            // Shares balanced on samples of every size (none: every topic is first met
            // after it) give the same columns and findings.
            let len = bytes.len() as u64;
            for (threads, sample) in [(2, 0), (2, len / 3), (3, 17), (2, len), (1, 0)] {
                let shared = load_shared(&path, len, threads, sample).unwrap();
                same(
                    &shared,
                    &one,
                    &format!("{name}: {threads} threads, sample {sample}"),
                );
                checked += 1;
            }
            std::fs::remove_file(&path).unwrap();
        }
        assert!(checked >= 3);
    }

    #[test]
    fn a_file_that_is_not_ulog_or_missing_is_an_error() {
        let path = temp_file(b"PK\x03\x04 not a log at all");
        let e = load_file_columns(&path, 2).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::NotULog { .. }), "{e}");
        std::fs::remove_file(&path).unwrap();
        let e = load_file_columns(&path, 2).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::Io(_)), "{e}");
    }
}
