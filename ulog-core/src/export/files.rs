//! Writing Parquet files: one per topic instance, and a whole log into a directory.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_schema::Schema;

use parquet::basic::Compression as ParquetCompression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::{EnabledStatistics, WriterProperties};

use super::error::{ExportError, ExportErrorKind};
use crate::access::topic::Topic;

type Result<T, E = ExportError> = core::result::Result<T, E>;
use crate::log::ulog::ULog;

use super::arrow::TopicTable;
use super::leaves::LeafWriter;
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
    pub error: ExportError,
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
/// # Ok::<(), Box<dyn std::error::Error>>(())
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
    std::fs::create_dir_all(dir).map_err(|e| ExportError::io(e, dir))?;
    let mut jobs = Vec::with_capacity(topics.len());
    let mut skipped = Vec::new();
    let mut names = std::collections::HashSet::new();
    for topic in &topics {
        // The table is built again when the topic is written: built for every topic
        // here, they would all be held at once (some kilobytes per leaf column).
        let leaves = match table_of(topic, options) {
            Ok(table) => leaves(table.schema.fields()),
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
                topic.subscription().msg_id()
            );
            names.insert(name.clone());
        }
        jobs.push((topic, leaves, dir.join(name)));
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

/// Writes the tables of `jobs` (topic, leaf columns, path): the wide ones first, one at
/// a time on this thread, then the others on up to [`Options::threads`] threads,
/// largest topics first; the files come back in the order of `jobs`. The first failure (in that
/// order) is returned; no new file is started after a failure.
fn write_tables(
    jobs: &[(&Topic<'_, '_>, usize, PathBuf)],
    options: &Options,
    written: impl FnMut(&Written) + Send,
) -> Result<Vec<Written>> {
    let written = std::sync::Mutex::new(written);
    let job = |i: usize| {
        let (topic, _, path) = &jobs[i];
        let table = table_of(topic, options)?;
        let file = write_table(topic, &table, path, options)?;
        (written.lock().unwrap_or_else(|p| p.into_inner()))(&file);
        Ok(file)
    };
    let (wide, narrow): (Vec<usize>, Vec<usize>) =
        (0..jobs.len()).partition(|&i| jobs[i].1 > WIDE_LEAVES);
    let mut results: Vec<Option<Result<Written>>> = (0..jobs.len()).map(|_| None).collect();
    // Wide tables one at a time, on this thread, and one at a time in the process
    // (several logs exported at once): a file's writer keeps some kilobytes of
    // metadata per leaf column until its footer, most of a wide table's memory, and
    // memory a thread frees stays with that thread's allocator arena for its next
    // allocations, not another thread's (bench/README.md).
    let mut failed = false;
    for &i in &wide {
        let result = {
            let _alone = WIDE_TABLE.lock().unwrap_or_else(|p| p.into_inner());
            job(i)
        };
        failed = result.is_err();
        results[i] = Some(result);
        if failed {
            break;
        }
    }
    if !failed {
        let costs: Vec<u64> = narrow
            .iter()
            .map(|&i| {
                let topic = jobs[i].0;
                let row = topic.layout().map_or(0, |l| l.size());
                (topic.len() * (row + 16)) as u64
            })
            .collect();
        let done = crate::parallel::largest_first(&costs, options.threads, |k| job(narrow[k]));
        for (k, result) in done.into_iter().enumerate() {
            results[narrow[k]] = result;
        }
    }
    let mut files = Vec::with_capacity(jobs.len());
    for result in results {
        match result {
            Some(Ok(file)) => files.push(file),
            Some(Err(e)) => return Err(e),
            // Not started after another file failed: that failure is returned.
            None => {}
        }
    }
    Ok(files)
}

/// Held while a wide table (more than [`WIDE_LEAVES`] leaf columns) is written.
static WIDE_TABLE: std::sync::Mutex<()> = std::sync::Mutex::new(());

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
        return Err(ExportError::new(ExportErrorKind::NoValues {
            topic: topic.name().to_owned(),
        })
        .at(topic.subscription().offset()));
    }
    Ok(table)
}

/// Payload bytes of a row group at most (and [`Options::row_group_rows`] rows): its
/// record batch is built whole before its columns are written, so this bounds the
/// memory of a topic being written, with one column writer at a time.
const ROW_GROUP_BYTES: usize = 16 << 20;

/// A column chunk's dictionary page at most, after which its values are written
/// plain: a column of distinct values (timestamps, most floats) stops paying for a
/// dictionary sooner than with the default 1 MiB, and row groups cut by
/// [`ROW_GROUP_BYTES`] get files a little smaller than the default's (bench/README.md).
const DICTIONARY_PAGE_BYTES: usize = 256 << 10;

/// Tables with more leaf columns than this are written without dictionary encoding
/// and without page statistics: each column's dictionary encoder holds tens of KB
/// whatever the row count, and its column index more metadata until the footer,
/// which for very wide formats is most of the export's memory (bench/README.md). PX4
/// topics have a few hundred leaves at most, and keep both.
const WIDE_LEAVES: usize = 1024;

/// The number of leaf columns (Parquet columns) of `fields`.
fn leaves(fields: &arrow_schema::Fields) -> usize {
    use arrow_schema::DataType;
    fn of(t: &DataType) -> usize {
        match t {
            DataType::Struct(fields) => leaves(fields),
            DataType::List(f) | DataType::LargeList(f) | DataType::FixedSizeList(f, _) => {
                of(f.data_type())
            }
            _ => 1,
        }
    }
    fields.iter().map(|f| of(f.data_type())).sum()
}

fn write_table(
    topic: &Topic<'_, '_>,
    table: &TopicTable,
    path: &Path,
    options: &Options,
) -> Result<Written> {
    let narrow = leaves(table.schema.fields()) <= WIDE_LEAVES;
    let compression = match options.compression {
        Compression::Uncompressed => ParquetCompression::UNCOMPRESSED,
        Compression::Snappy => ParquetCompression::SNAPPY,
        Compression::Zstd => ParquetCompression::ZSTD(Default::default()),
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
        .set_dictionary_enabled(narrow)
        .set_dictionary_page_size_limit(DICTIONARY_PAGE_BYTES)
        // Page statistics (the column index) are more metadata per column held until
        // the footer; wide tables keep the statistics of each column chunk only.
        .set_statistics_enabled(if narrow {
            EnabledStatistics::Page
        } else {
            EnabledStatistics::Chunk
        })
        .build();

    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = PathBuf::from(tmp);
    let file = File::create(&tmp).map_err(|e| ExportError::io(e, &tmp))?;
    let result = (|| {
        // The schema's metadata goes in the Parquet key-value metadata (sorted), not
        // in the encoded Arrow schema, where it would be in hash order: the files are
        // the same from run to run. Readers merge the two.
        let schema = Arc::new(Schema::new(table.schema.fields().clone()));
        let mut writer =
            LeafWriter::try_new(BufWriter::with_capacity(1 << 20, file), schema, props)
                .map_err(|e| write_error(&tmp, e))?;
        let offsets = topic.message_offsets();
        let row_size = topic.layout().map_or(1, |l| l.size().max(1));
        let step = options
            .row_group_rows
            .clamp(1, (ROW_GROUP_BYTES / row_size).max(1));
        for start in (0..topic.len()).step_by(step) {
            let end = (start + step).min(topic.len());
            let payloads: Vec<&[u8]> = topic.payloads_in(start..end).collect();
            let batch = table.batch(&payloads, offsets.slice(start..end))?;
            writer
                .write_row_group(&batch)
                .map_err(|e| write_error(&tmp, e))?;
        }
        writer.close().map_err(|e| write_error(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| ExportError::io(e, path))
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
fn write_error(path: &Path, e: parquet::errors::ParquetError) -> ExportError {
    match e {
        parquet::errors::ParquetError::External(inner) => {
            match inner.downcast::<std::io::Error>() {
                Ok(io) => ExportError::io(*io, path),
                Err(other) => ExportError::encoding(ExternalError(other)).in_file(path),
            }
        }
        e => ExportError::encoding(e).in_file(path),
    }
}

/// An error Parquet passed on from elsewhere.
#[derive(Debug)]
struct ExternalError(Box<dyn std::error::Error + Send + Sync>);

impl std::fmt::Display for ExternalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for ExternalError {}
