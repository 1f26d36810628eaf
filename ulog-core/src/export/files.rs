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

use super::error::{ExportError, ExportErrorKind};
use crate::access::topic::Topic;

type Result<T, E = ExportError> = core::result::Result<T, E>;
use crate::log::ulog::ULog;

use super::arrow::TopicTable;
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
                topic.subscription().msg_id()
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
    let costs: Vec<u64> = jobs
        .iter()
        .map(|(topic, ..)| {
            let row = topic.layout().map_or(0, |l| l.size());
            (topic.len() * (row + 16)) as u64
        })
        .collect();
    let written = std::sync::Mutex::new(written);
    let results = crate::parallel::largest_first(&costs, options.threads, |i| {
        let (topic, table, path) = &jobs[i];
        let file = write_table(topic, table, path, options)?;
        (written.lock().unwrap_or_else(|p| p.into_inner()))(&file);
        Ok(file)
    });
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

/// Tables with more leaf columns than this are written without dictionary encoding:
/// each column's dictionary encoder holds tens of KB whatever the row count, which
/// for very wide formats is most of the export's memory (bench/README.md). PX4 topics
/// have a few hundred leaves at most, and keep it.
const DICTIONARY_LEAVES: usize = 1024;

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
        .set_dictionary_enabled(leaves(table.schema.fields()) <= DICTIONARY_LEAVES)
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
