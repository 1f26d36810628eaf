//! Writing Parquet files: one per topic instance, and a whole log into a directory.

use std::collections::BTreeMap;
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
use crate::access::lookup::LookupError;

use super::arrow::TopicTable;
use super::leaves::LeafWriter;
use super::{Compression, Options};

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

/// What [`write_parquet`](super::write_parquet) wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Export {
    /// The Parquet files, sorted by topic name and instance.
    pub files: Vec<Written>,
    /// Topic instances with data that could not be exported, sorted the same way.
    pub skipped: Vec<Skipped>,
    /// The names of [`Options::topics`] the log does not have (with
    /// [`Options::skip_missing_topics`]; otherwise such a name is an error).
    pub missing_topics: Vec<LookupError>,
    /// The metadata file (of a [`Dataset`](super::Dataset): its table of logs,
    /// written by [`Dataset::finish`](super::Dataset::finish)).
    pub metadata: PathBuf,
}

/// Writes the rows of one topic instance to a Parquet file at `path` (replaced if it
/// exists; written under a temporary name first, so a failed write leaves no partial
/// file at `path`).
pub fn write_topic(topic: &Topic<'_, '_>, path: &Path, options: &Options) -> Result<Written> {
    let table = table_of(topic, options)?;
    write_table(topic, &table, path, options)
}

fn table_of(topic: &Topic<'_, '_>, options: &Options) -> Result<TopicTable> {
    let table = TopicTable::new(topic.subscription(), options)?;
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
pub(super) const ROW_GROUP_BYTES: usize = 16 << 20;

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
pub(super) const WIDE_LEAVES: usize = 1024;

/// The number of leaf columns (Parquet columns) of `fields`.
pub(super) fn leaves(fields: &arrow_schema::Fields) -> usize {
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
    let props = properties(table, options);
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
            let rows = offsets.slice(start..end);
            let batch = table.batch(&payloads, |i| rows.get(i).unwrap_or(0))?;
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

/// The writer properties of a table's files: its compression, its schema's metadata
/// as the files' key-value metadata (sorted: the files are the same from run to run),
/// no dictionary for float, double and timestamp columns, no statistics for float and
/// double columns, and, for wide tables, no dictionaries and chunk statistics only.
pub(super) fn properties(table: &TopicTable, options: &Options) -> WriterProperties {
    writer_properties(&table.schema, options.compression)
}

/// The writer properties of a Parquet file of `schema` as the export writes its
/// files: `compression`, the schema's metadata as the file's key-value metadata
/// (sorted), no dictionary for float, double and timestamp columns, no statistics
/// for float and double columns, and, for tables of more than 1,024 leaf columns, no
/// dictionaries and column chunk statistics only.
pub fn writer_properties(schema: &Schema, compression: Compression) -> WriterProperties {
    let narrow = leaves(schema.fields()) <= WIDE_LEAVES;
    let compression = compression_of(compression);
    let mut metadata: Vec<KeyValue> = schema
        .metadata()
        .iter()
        .map(|(k, v)| KeyValue::new(k.clone(), v.clone()))
        .collect();
    metadata.sort_by(|a, b| a.key.cmp(&b.key));
    let mut builder = WriterProperties::builder();
    // Float and double columns without a dictionary: sensor values seldom repeat, and
    // interning values into dictionaries that are then given up was 12% of a
    // one-thread export's time (perf, events×200, flattened). On the two ≈300 MB logs
    // (zstd, flattened): 0.83x the time (log_61), files 9% smaller (events) and 5%
    // larger (log_61). Times neither (`timestamp` and the relative times beside it):
    // each is another microsecond (files 7% smaller on log_61 ×90).
    //
    // Nor minimum and maximum statistics for floats: the writer compares every value
    // (NaN-aware, through the column's logical type), which was 13% of the export's
    // user CPU on log_61 ×90, and a sensor value's range within a row group seldom
    // lets an engine skip it. Times, ids and integer fields (modes, states, counts:
    // what queries filter on) keep theirs. It also keeps DuckDB from answering a
    // filter on NaN from statistics that leave NaN out (README, "Fleet analysis").
    if narrow {
        if let Ok(parquet) = parquet::arrow::ArrowSchemaConverter::new().convert(schema) {
            use parquet::basic::Type;
            for column in parquet.columns() {
                let float = matches!(column.physical_type(), Type::FLOAT | Type::DOUBLE);
                let time = matches!(column.physical_type(), Type::INT64 | Type::INT32)
                    && column.name().contains("timestamp");
                if float || time {
                    builder = builder.set_column_dictionary_enabled(column.path().clone(), false);
                }
                if float {
                    builder = builder.set_column_statistics_enabled(
                        column.path().clone(),
                        EnabledStatistics::None,
                    );
                }
            }
        }
    }
    builder
        .set_compression(compression)
        .set_created_by(concat!("ulog-core ", env!("CARGO_PKG_VERSION")).to_owned())
        .set_key_value_metadata(Some(metadata))
        .set_dictionary_enabled(narrow)
        .set_dictionary_page_size_limit(DICTIONARY_PAGE_BYTES)
        // Pages cut by their size only (1 MiB), not also every 20,000 rows: each page
        // is compressed alone, and 20,000 floats are too little for zstd to find much.
        // Flattened zstd files half as large (log_61 ×90: 26.2 MB against 51.3 MB;
        // events ×200: 19.9 against 31.9), and fewer pages to compress.
        .set_data_page_row_count_limit(usize::MAX)
        // Page statistics (the column index) are more metadata per column held until
        // the footer; wide tables keep the statistics of each column chunk only.
        .set_statistics_enabled(if narrow {
            EnabledStatistics::Page
        } else {
            EnabledStatistics::Chunk
        })
        .build()
}

/// The Parquet codec of a [`Compression`].
pub(super) fn compression_of(compression: Compression) -> ParquetCompression {
    match compression {
        Compression::Uncompressed => ParquetCompression::UNCOMPRESSED,
        Compression::Snappy => ParquetCompression::SNAPPY,
        Compression::Zstd => ParquetCompression::ZSTD(Default::default()),
    }
}

/// A Parquet error: an I/O error about `path`, or an export error.
pub(super) fn write_error(path: &Path, e: parquet::errors::ParquetError) -> ExportError {
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

/// Whether `name` is a topic file of a dataset, `<log_id>.parquet` (in the fleet layout
/// named after its first log): that id.
pub(super) fn topic_file_id(name: &str) -> Option<&str> {
    let id = name.strip_suffix(".parquet")?;
    (id.len() == 16 && id.bytes().all(|b| b.is_ascii_hexdigit())).then_some(id)
}

/// The topic files in the dataset folder `dir` (`<folder>/<log_id>.parquet`), by
/// log: each one's folder name and path. Folders whose names start with `_` or `.`
/// are not topics (a Spark conversion's staging).
pub(super) fn topic_files(dir: &Path) -> Result<BTreeMap<String, Vec<(String, PathBuf)>>> {
    let mut files: BTreeMap<String, Vec<(String, PathBuf)>> = BTreeMap::new();
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(files),
        Err(e) => return Err(ExportError::io(e, dir)),
    };
    let mut folders: Vec<_> = entries
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path()))
        .filter(|(name, _)| !name.starts_with(['_', '.']))
        .collect();
    folders.sort();
    for (folder, path) in folders {
        folder_files(&path, &mut |id, path| {
            files
                .entry(id.to_owned())
                .or_default()
                .push((folder.clone(), path));
        })?;
    }
    Ok(files)
}

/// Calls `found` with the id and path of each topic file (`<log_id>.parquet`) in the
/// topic folder `dir` and its partition folders (`<key>=<value>/`, the fleet layout).
pub(super) fn folder_files(dir: &Path, found: &mut dyn FnMut(&str, PathBuf)) -> Result<()> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(ExportError::io(e, dir)),
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            if name.contains('=') {
                folder_files(&entry.path(), found)?;
            }
        } else if let Some(id) = topic_file_id(&name) {
            found(id, entry.path());
        }
    }
    Ok(())
}
