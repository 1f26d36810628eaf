//! Writing Parquet files: one per topic instance, and a whole log into a directory.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_schema::Schema;

use parquet::arrow::ArrowWriter;
use parquet::basic::Compression as ParquetCompression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;

use crate::access::topic::Topic;
use crate::error::{Error, ErrorKind, Result};
use crate::read::log::ULog;

use super::arrow::{export_error, TopicTable};
use super::{file_name, selected_topics, write_metadata, Compression, Options, METADATA_FILE};

/// A Parquet file written for a topic instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    /// The topic name.
    pub topic: String,
    /// Its instance.
    pub multi_id: u8,
    /// The file.
    pub path: PathBuf,
    /// Rows written (the topic's data messages).
    pub rows: usize,
}

/// A topic instance that was not written, and why (its format could not be laid out,
/// or it has no field with values).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Skipped {
    /// The topic name.
    pub topic: String,
    /// Its instance.
    pub multi_id: u8,
    /// Why.
    pub error: Error,
}

/// What [`write_parquet`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Export {
    /// The Parquet files, in the order of [`super::selected_topics`].
    pub files: Vec<Written>,
    /// Topic instances with data that could not be exported.
    pub skipped: Vec<Skipped>,
    /// The metadata file.
    pub metadata: PathBuf,
}

fn io_error(path: &Path, e: &dyn std::fmt::Display) -> Error {
    Error::new(ErrorKind::Io(format!("{}: {e}", path.display())), 0)
}

/// Writes every selected topic instance of `log` (see [`super::selected_topics`]) to
/// its own Parquet file in `dir` (created when missing), named by [`super::file_name`],
/// and the metadata file [`METADATA_FILE`]. Files of those names already there are
/// replaced; other files in `dir` are left as they are.
///
/// A topic whose format cannot be laid out, or that has no field with values, is
/// left out and listed in [`Export::skipped`]. Errors: a topic of
/// [`Options::topics`] that is not in the log (before anything is written), and
/// failures to write.
///
/// ```
/// use ulog_core::export::{self, Options};
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let dir = std::env::temp_dir().join(format!("ulog-doc-{}", std::process::id()));
/// let written = export::write_parquet(&log, &dir, &Options::default())?;
/// assert!(written.files.iter().any(|f| f.path.ends_with("battery_status_1.parquet")));
/// assert!(written.metadata.ends_with("metadata.json"));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), ulog_core::Error>(())
/// ```
pub fn write_parquet(log: &ULog<'_>, dir: &Path, options: &Options) -> Result<Export> {
    write_parquet_with(log, dir, options, |_| {})
}

/// [`write_parquet`], calling `written` after each Parquet file is written (to show
/// progress; with [`Options::threads`] above 1, from the thread that wrote it, in the
/// order the files are done).
pub fn write_parquet_with(
    log: &ULog<'_>,
    dir: &Path,
    options: &Options,
    written: impl FnMut(&Written) + Send,
) -> Result<Export> {
    let topics = selected_topics(log, options)?;
    std::fs::create_dir_all(dir).map_err(|e| io_error(dir, &e))?;
    let mut jobs = Vec::with_capacity(topics.len());
    let mut skipped = Vec::new();
    let mut names = std::collections::HashSet::new();
    for topic in &topics {
        let table = match table_of(topic, options) {
            Ok(t) => t,
            Err(error) => {
                skipped.push(Skipped {
                    topic: topic.name().to_owned(),
                    multi_id: topic.multi_id(),
                    error,
                });
                continue;
            }
        };
        let mut name = file_name(topic);
        // Two subscriptions of one name and instance (damaged logs): one file each.
        if !names.insert(name.clone()) {
            name = format!(
                "{}_msg{}.parquet",
                name.trim_end_matches(".parquet"),
                topic.msg_id()
            );
            names.insert(name.clone());
        }
        jobs.push((topic, table, dir.join(name)));
    }
    let files = write_tables(&jobs, options, written)?;
    let metadata = dir.join(METADATA_FILE);
    write_metadata(log, &metadata)?;
    Ok(Export {
        files,
        skipped,
        metadata,
    })
}

/// Writes the tables of `jobs` on up to [`Options::threads`] threads, largest topics
/// first; the files come back in the order of `jobs`. The first failure (in that
/// order) is returned; no new file is started after a failure.
fn write_tables(
    jobs: &[(&Topic<'_, '_>, TopicTable, PathBuf)],
    options: &Options,
    written: impl FnMut(&Written) + Send,
) -> Result<Vec<Written>> {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    use std::sync::Mutex;

    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&i| {
        let (topic, ..) = &jobs[i];
        let row = topic.layout().map_or(0, |l| l.size());
        core::cmp::Reverse(topic.len() * (row + 16))
    });
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let written = Mutex::new(written);
    let results: Mutex<Vec<Option<Result<Written>>>> =
        Mutex::new((0..jobs.len()).map(|_| None).collect());
    let work = || loop {
        if failed.load(Ordering::Relaxed) {
            break;
        }
        let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
            break;
        };
        let (topic, table, path) = &jobs[i];
        let result = write_table(topic, table, path, options);
        match &result {
            Ok(file) => (written.lock().unwrap_or_else(|p| p.into_inner()))(file),
            Err(_) => failed.store(true, Ordering::Relaxed),
        }
        results.lock().unwrap_or_else(|p| p.into_inner())[i] = Some(result);
    };
    let threads = options.threads.clamp(1, jobs.len().max(1));
    if threads == 1 {
        work();
    } else {
        std::thread::scope(|s| {
            for _ in 0..threads {
                s.spawn(work);
            }
        });
    }
    let mut files = Vec::with_capacity(jobs.len());
    for result in results.into_inner().unwrap_or_else(|p| p.into_inner()) {
        match result {
            Some(Ok(file)) => files.push(file),
            Some(Err(e)) => return Err(e),
            // Not started after another file failed: that failure is returned.
            None => {}
        }
    }
    Ok(files)
}

/// Writes the rows of one topic instance to a Parquet file at `path` (replaced if it
/// exists; written under a temporary name first, so a failed write leaves no partial
/// file at `path`).
pub fn write_topic(topic: &Topic<'_, '_>, path: &Path, options: &Options) -> Result<Written> {
    let table = table_of(topic, options)?;
    write_table(topic, &table, path, options)
}

fn table_of(topic: &Topic<'_, '_>, options: &Options) -> Result<TopicTable> {
    let table = TopicTable::new(topic, options)?;
    if table.schema.fields().is_empty() {
        return Err(Error::new(
            ErrorKind::Export(format!("topic `{}` has no field with values", topic.name())),
            topic.subscription_offset(),
        ));
    }
    Ok(table)
}

fn write_table(
    topic: &Topic<'_, '_>,
    table: &TopicTable,
    path: &Path,
    options: &Options,
) -> Result<Written> {
    let compression = match options.compression {
        Compression::Uncompressed => ParquetCompression::UNCOMPRESSED,
        Compression::Snappy => ParquetCompression::SNAPPY,
    };
    let mut metadata: Vec<KeyValue> = table
        .schema
        .metadata()
        .iter()
        .map(|(k, v)| KeyValue::new(k.clone(), v.clone()))
        .collect();
    metadata.sort_by(|a, b| a.key.cmp(&b.key));
    let props = WriterProperties::builder()
        .set_compression(compression)
        .set_created_by(concat!("ulog-core ", env!("CARGO_PKG_VERSION")).to_owned())
        .set_key_value_metadata(Some(metadata))
        .build();

    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = PathBuf::from(tmp);
    let file = File::create(&tmp).map_err(|e| io_error(&tmp, &e))?;
    let result = (|| {
        // The schema's metadata goes in the Parquet key-value metadata (sorted), not
        // in the encoded Arrow schema, where it would be in hash order: the files are
        // the same from run to run. Readers merge the two.
        let schema = Arc::new(Schema::new(table.schema.fields().clone()));
        let mut writer =
            ArrowWriter::try_new(BufWriter::with_capacity(1 << 20, file), schema, Some(props))
                .map_err(|e| write_error(&tmp, e))?;
        let payloads: Vec<&[u8]> = topic.payloads().collect();
        let offsets = topic.message_offsets();
        let step = options.batch_rows.max(1);
        for start in (0..payloads.len()).step_by(step) {
            let end = (start + step).min(payloads.len());
            let batch = table.batch(&payloads[start..end], offsets.slice(start..end))?;
            writer.write(&batch).map_err(|e| write_error(&tmp, e))?;
        }
        writer.close().map_err(|e| write_error(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| io_error(path, &e))
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    Ok(Written {
        topic: topic.name().to_owned(),
        multi_id: topic.multi_id(),
        path: path.to_owned(),
        rows: topic.len(),
    })
}

/// A Parquet error: an I/O error about `path`, or an export error.
fn write_error(path: &Path, e: parquet::errors::ParquetError) -> Error {
    match e {
        parquet::errors::ParquetError::External(inner) => io_error(path, &inner),
        e => export_error(&e),
    }
}
