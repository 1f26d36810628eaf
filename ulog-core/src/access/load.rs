//! Columnar load straight from a file: one pass in file order over bytes read from
//! disk (no memory map, no index), so that the memory held is the columns themselves
//! plus a few read buffers. On several threads the file is cut into byte ranges:
//! each thread frames the file up to the end of its range and fills columns from the
//! data messages in it, and the ranges' columns are joined in order.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::access::columns::{Column, Table};
use crate::error::{Error, ErrorKind, Result};
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

/// The tables of one byte range, by subscription index.
#[derive(Default)]
struct Tables(Vec<Option<Table>>);

impl Tables {
    #[inline]
    fn push(&mut self, r: &ScanRecord<'_, '_>) {
        match self.0.get_mut(r.subscription) {
            Some(Some(table)) => table.push(r.payload),
            _ => self.first(r),
        }
    }

    #[cold]
    fn first(&mut self, r: &ScanRecord<'_, '_>) {
        if r.subscription >= self.0.len() {
            self.0.resize_with(r.subscription + 1, || None);
        }
        // A subscription without a layout has no table; its records are left out
        // here and its entry says why.
        if let Some(layout) = r.layout {
            let mut table = Table::new(layout, 0);
            table.push(r.payload);
            self.0[r.subscription] = Some(table);
        }
    }
}

fn finish(summary: ScanSummary, ranges: Vec<Tables>) -> LoadedColumns {
    let mut joined: Vec<Option<Table>> = Vec::new();
    for tables in ranges {
        for (i, table) in tables.0.into_iter().enumerate() {
            if i >= joined.len() {
                joined.resize_with(i + 1, || None);
            }
            match (&mut joined[i], table) {
                (Some(t), Some(more)) => t.append(more),
                (slot @ None, more) => *slot = more,
                (Some(_), None) => {}
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
    let mut tables = Tables::default();
    let summary = scan_range(src, u64::MAX, |r| tables.push(&r))?;
    Ok(finish(summary, vec![tables]))
}

/// Every topic's columns of the file at `path`, read on up to `threads` threads
/// (`0` or `1`: on this one), each reading the file itself: the same result as
/// [`load_columns`] on one thread.
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
    let io = |e: std::io::Error| Error::new(ErrorKind::Io(format!("{}: {e}", path.display())), 0);
    let file = File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    // Ranges smaller than this are not worth a thread.
    const MIN_RANGE: u64 = 4 << 20;
    let threads = threads.clamp(1, 64).min((len / MIN_RANGE).max(1) as usize);
    if threads == 1 {
        return load_columns(file);
    }
    let ends: Vec<u64> = (1..threads as u64)
        .map(|k| len / threads as u64 * k)
        .chain([u64::MAX])
        .collect();
    load_ranges(path, &ends)
}

/// Loads the byte ranges ending at `ends` (the last one `u64::MAX`) on a thread each,
/// and joins them.
fn load_ranges(path: &Path, ends: &[u64]) -> Result<LoadedColumns> {
    let io = |e: std::io::Error| Error::new(ErrorKind::Io(format!("{}: {e}", path.display())), 0);
    let results: Vec<Result<(ScanSummary, Tables)>> = std::thread::scope(|s| {
        let handles: Vec<_> = ends
            .iter()
            .enumerate()
            .map(|(k, &end)| {
                let start = if k == 0 { 0 } else { ends[k - 1] };
                s.spawn(move || {
                    let file = File::open(path).map_err(io)?;
                    let mut tables = Tables::default();
                    let summary = scan_range(file, end, |r| {
                        if r.offset >= start && r.offset < end {
                            tables.push(&r);
                        }
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
    let mut ranges = Vec::with_capacity(results.len());
    let mut last = None;
    for r in results {
        let (summary, tables) = r?;
        ranges.push(tables);
        last = Some(summary);
    }
    // The last range's scan framed the whole file.
    let summary = last.expect("at least one range");
    Ok(finish(summary, ranges))
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
    fn one_pass_and_byte_ranges_load_what_the_parse_loads() {
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
            // Byte ranges cut anywhere (inside messages, damaged stretches, headers)
            // join into the same columns and findings.
            let path = temp_file(&bytes);
            let len = bytes.len() as u64;
            for cuts in [
                vec![len / 2],
                vec![1, 17, len / 3, len / 3 + 1, len - 1],
                vec![len / 7, 2 * len / 7, 3 * len / 7, 5 * len / 7],
            ] {
                let ends: Vec<u64> = cuts.into_iter().chain([u64::MAX]).collect();
                let ranged = load_ranges(&path, &ends).unwrap();
                same(&ranged, &one, &format!("{name}: ranges ending at {ends:?}"));
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
