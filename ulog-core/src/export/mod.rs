//! Export of a log to Apache Arrow record batches and Parquet files (feature
//! `parquet`), for query engines that read Parquet (DataFusion, DuckDB, Spark, Polars).
//!
//! [`write_parquet`] reads a log once, from any [`Source`](crate::Source) (a file is
//! read in chunks, never held whole: the rows held are bounded by
//! [`Options::buffer_bytes`], not the size of the log; the messages other than data,
//! information, parameters and logged strings, are kept for the metadata), and writes
//! one Parquet file per topic instance with data, named
//! [`file_name`] (`<topic>_<multi_id>.parquet`; a topic name that a file system
//! would refuse or fold is escaped by the rule of [`crate::naming`]), and
//! a [`METADATA_FILE`] (`metadata.json`, see [`metadata_json`]) with the log's
//! information, parameters, logged messages, dropouts and findings.
//!
//! A [`Dataset`] holds any number of logs in one folder that query engines read across
//! logs in one statement: `<topic>/<log_id>.parquet` per topic and log (the folder
//! named by [`crate::naming::folder_name`]; the same
//! columns, with `log_id` and `multi_id` first) and four tables of what the logs are
//! ([`LOGS_FILE`], [`PARAMETERS_FILE`], [`MESSAGES_FILE`], [`FORMATS_FILE`]).
//!
//! # Columns
//!
//! Columns have the log's types: `uint8_t`…`uint64_t` are `UInt8`…`UInt64`, `int8_t`…
//! `int64_t` are `Int8`…`Int64`, `float` is `Float32`, `double` is `Float64`, `bool`
//! is `Boolean` (any non-zero byte is true), a lone `char` is its byte (`UInt8`).
//! `char[N]` is a `Utf8` string: the bytes with trailing NULs removed, each byte one
//! character (ISO 8859-1), so no byte is lost even when the text is not UTF-8 (ASCII
//! reads as itself; encode the text as Latin-1 to get the bytes back). No column of a
//! topic's table is nullable (a column of rows that may be absent, [`field_array`],
//! has nulls).
//!
//! By default ([`Options::flatten`] false) there is one column per top-level field, in
//! format order: arrays are `FixedSizeList` columns, nested formats `Struct` columns
//! (arrays of them, lists of structs). With `flatten`, the columns are pyulog's:
//! one per leaf, named by path (`q[0]`, `esc[3].esc_rpm`), `timestamp` first, as
//! `ulog2csv` writes them. Padding fields are left out, nested ones too, as are fields
//! with no values (zero-length arrays, nested formats of padding only).
//!
//! The `timestamp` column stays as logged (microseconds; milliseconds for the
//! `uint8_t` timestamps of version 0 logs), with field metadata `unit` = `us` / `ms`.
//! Every other top-level field (every column, flattened) has metadata `ulog.type`, its
//! type as in the format string (`float[4]`, `char[16]`, `esc_report[8]`). The schema
//! has metadata `ulog.topic`, `ulog.multi_id` and `ulog.format` (the formats the
//! topic uses, one per line, nested ones first) and, for each field whose name says
//! its unit ([`crate::units`]), `ulog.unit.<field>` with the field's path without
//! array indices (`ulog.unit.accelerometer_m_s2` = `m/s²`, `ulog.unit.esc.esc_rpm` =
//! `rpm`); in the Parquet files these are
//! key-value metadata, which Arrow readers put back in the schema. The files are the
//! same byte for byte from run to run.
//!
//! ```
//! use ulog_core::export::{self, Options};
//! let bytes = ulog_core::testing::sample_log();
//! let log = ulog_core::ULog::parse(&bytes)?;
//! let topic = log.topic("esc_status", 0)?;
//! let batch = export::topic_record_batch(&topic, &Options::default())?;
//! assert_eq!(batch.num_rows(), topic.len());
//! assert_eq!(batch.schema().field(0).name(), "timestamp");
//!
//! let flat = Options { flatten: true, ..Options::default() };
//! let batch = export::topic_record_batch(&topic, &flat)?;
//! assert!(batch.schema().field_with_name("esc[1].esc_rpm").is_ok());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod arrow;
mod compaction;
mod dataset;
mod error;
mod files;
mod fleet;
mod flights;
mod lazy_file;
mod leaves;
pub(crate) mod lock;
mod metadata;
mod rows;
mod stream;
#[cfg(test)]
mod tests;
mod union;

pub use arrow_array;
pub use arrow_schema;
pub use parquet;

use arrow_array::RecordBatch;
use arrow_schema::SchemaRef;

pub use compaction::{Compacted, COMPACTING};
pub use dataset::{
    Added, Dataset, Finished, LogPath, FORMATS_FILE, LOGS_FILE, MESSAGES_FILE, PARAMETERS_FILE,
};
pub use files::{write_topic, writer_properties, Export, Skipped, Written};
pub use fleet::{
    DatasetLayout, FleetLayout, PartitionKey, FIRMWARE_KEY, FORMAT_HASH_KEY, LOG_IDS_KEY,
    NULL_PARTITION, PENDING_DIR,
};
pub use flights::{ANALYSIS_FILE, FLIGHTS_FILE};
pub use lock::LOCK_FILE;
pub use metadata::{metadata_json, write_metadata, METADATA_FILE};
pub use stream::{write_parquet, write_parquet_with};
pub use union::{union_schema, CONFLICTS_KEY, SCHEMAS_DIR};

use crate::access::field::FieldReader;
use crate::access::topic::Topic;
pub use error::{ExportError, ExportErrorKind};

type Result<T, E = ExportError> = core::result::Result<T, E>;
use crate::log::ulog::ULog;
use crate::log::utc::UtcClock;
use arrow::TopicTable;

/// The compression of the Parquet files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compression {
    /// No compression.
    Uncompressed,
    /// Snappy (fast; read by every Parquet engine).
    #[default]
    Snappy,
    /// Zstandard at the Parquet writer's default level (1): smaller files than Snappy,
    /// for keeping; read by every current engine (DuckDB, DataFusion, Polars, Spark).
    Zstd,
}

/// What to export, and how.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// Flatten to pyulog's columns (`a.b[3].c`) instead of struct and list columns.
    pub flatten: bool,
    /// Only these topics (every instance of each); `None`: every topic. A name that is
    /// not in the log is an error ([`ExportErrorKind::Lookup`]), known once the whole
    /// log has been read (a subscription may come at any point), unless
    /// [`Options::skip_missing_topics`].
    pub topics: Option<Vec<String>>,
    /// Compression of the Parquet files.
    pub compression: Compression,
    /// Rows per record batch of [`topic_record_batches`]; at least 1.
    pub batch_rows: usize,
    /// Rows per Parquet row group at most, when writing; a row group also holds at
    /// most 16 MiB of payload (its record batch is built whole: this bounds the
    /// memory used per topic). At least 1.
    pub row_group_rows: usize,
    /// Threads writing row groups while the log is read (`0` or `1`: on the calling
    /// thread, between reads). The files are the same whatever the number.
    pub threads: usize,
    /// Bytes of rows [`write_parquet`] holds for all topics together: past it, the
    /// topic holding the most writes them out, as a row group when they make 4 MiB or
    /// more, else into a temporary file beside the output, read back when they make
    /// one (each topic's row group is also written when it is full). With the row
    /// groups on their way (one per thread, one waiting for a thread and one being
    /// handed over, at most 16 MiB of rows each) and the one block of 64 KiB at most
    /// that each topic has begun, this bounds the memory of an export whatever the
    /// size of the log. At least 1; default 24 MiB (bench/README.md gives
    /// the peaks and file sizes of other budgets).
    pub buffer_bytes: usize,
    /// A name of [`Options::topics`] that the log lacks is listed in
    /// [`Export::missing_topics`] instead of failing the export (which still fails
    /// when the log has none of the names).
    pub skip_missing_topics: bool,
    /// Add a column `timestamp_utc` after `timestamp` (`uint64_t` timestamps only):
    /// each row's time in UTC by this clock ([`ULog::utc`](crate::ULog::utc)), an
    /// Arrow `Timestamp(Microsecond, "UTC")`, with field metadata `ulog.utc_source`
    /// saying where the time comes from.
    pub utc: Option<UtcClock>,
    /// Add columns `log_id` (this text, in every row) and `multi_id` (the topic's
    /// instance, `UInt8`) before the fields, as the files of a [`Dataset`] have them;
    /// the schema's metadata then has no `ulog.multi_id`, so the instances of a topic
    /// share one schema.
    pub log_id: Option<String>,
    /// How a [`Dataset`] lays out its topic files; `None`: as the dataset has them, or
    /// [`DatasetLayout::FilePerLog`] for a new one. A dataset refuses another layout
    /// than its own (the file size of [`FleetLayout`] may change from one conversion
    /// to the next). Not used outside a dataset.
    pub layout: Option<DatasetLayout>,
    /// In a fleet-layout dataset, [`Dataset::finish`] also merges each topic
    /// partition's files smaller than half of [`FleetLayout::file_bytes`] into files of
    /// about that size ([`Compacted`]): the small files that adding a few logs at a
    /// time leaves. Without it, no file is ever rewritten. An error for a dataset with
    /// a file per log. Not used outside a dataset.
    pub compact: bool,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            flatten: false,
            topics: None,
            compression: Compression::Snappy,
            batch_rows: 65_536,
            row_group_rows: 1 << 20,
            threads: 1,
            buffer_bytes: 24 << 20,
            skip_missing_topics: false,
            utc: None,
            log_id: None,
            layout: None,
            compact: false,
        }
    }
}

/// The Arrow schema of a topic (see the [module docs](self) for the columns).
pub fn topic_schema(topic: &Topic<'_, '_>, options: &Options) -> Result<SchemaRef> {
    Ok(TopicTable::new(topic.subscription(), options)?.schema)
}

/// Every row of a topic as one record batch.
pub fn topic_record_batch(topic: &Topic<'_, '_>, options: &Options) -> Result<RecordBatch> {
    let table = TopicTable::new(topic.subscription(), options)?;
    let payloads: Vec<&[u8]> = topic.payloads().collect();
    let offsets = topic.message_offsets();
    table.batch(&payloads, |i| offsets.get(i).unwrap_or(0))
}

/// The rows of a topic as record batches of at most [`Options::batch_rows`] rows.
pub fn topic_record_batches<'l, 'a>(
    topic: &Topic<'l, 'a>,
    options: &Options,
) -> Result<RecordBatches<'l, 'a>> {
    Ok(RecordBatches {
        table: TopicTable::new(topic.subscription(), options)?,
        topic: *topic,
        next: 0,
        batch_rows: options.batch_rows.max(1),
    })
}

/// The Arrow type of the column a field reader reads, as a flattened table types it
/// ([`Options::flatten`]; the [module docs](self) list the types): `char[N]` is
/// `Utf8`, a value its own type, a whole array a `FixedSizeList` of its values.
///
/// ```
/// use ulog_core::export::{self, arrow_schema::DataType};
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let topic = log.topic("vehicle_attitude", 0)?;
/// assert_eq!(export::field_data_type(&topic.field("q[0]")?), DataType::Float32);
/// assert_eq!(export::field_data_type(&topic.field("timestamp")?), DataType::UInt64);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn field_data_type(reader: &FieldReader) -> arrow_schema::DataType {
    arrow::field_data_type(reader)
}

/// The values a field reader reads in payloads of its topic, as an Arrow array of
/// [`field_data_type`], values read as the export reads them (text as the module
/// docs say): null where a row is `None` (a table that has no row there, such as a
/// topic [aligned](crate::align) at a step it has no value for) or too short for the
/// field.
///
/// ```
/// use ulog_core::export::{self, arrow_array::Array};
/// let bytes = ulog_core::testing::sample_log();
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let topic = log.topic("vehicle_attitude", 0)?;
/// let rows = [topic.payload(0), None, topic.payload(1)];
/// let q0 = export::field_array(&topic.field("q[0]")?, &rows)?;
/// assert_eq!((q0.len(), q0.null_count()), (3, 1));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn field_array(reader: &FieldReader, rows: &[Option<&[u8]>]) -> Result<arrow_array::ArrayRef> {
    arrow::field_array(reader, rows)
}

/// The record batches of one topic, in row order (see [`topic_record_batches`]).
#[derive(Debug)]
pub struct RecordBatches<'l, 'a> {
    table: TopicTable,
    topic: Topic<'l, 'a>,
    next: usize,
    batch_rows: usize,
}

impl RecordBatches<'_, '_> {
    /// The schema of every batch.
    pub fn schema(&self) -> SchemaRef {
        self.table.schema.clone()
    }
}

impl Iterator for RecordBatches<'_, '_> {
    type Item = Result<RecordBatch>;

    fn next(&mut self) -> Option<Result<RecordBatch>> {
        let n = self.topic.len();
        if self.next >= n {
            return None;
        }
        let end = (self.next + self.batch_rows).min(n);
        let payloads: Vec<&[u8]> = self.topic.payloads_in(self.next..end).collect();
        let offsets = self.topic.message_offsets().slice(self.next..end);
        self.next = end;
        Some(self.table.batch(&payloads, |i| offsets.get(i).unwrap_or(0)))
    }
}

/// The topic instances [`write_parquet`] exports: those with data messages, of the
/// topics named in [`Options::topics`] (all when `None`), sorted by name and multi_id.
///
/// An error names the first topic of the list that is not in the log (with the
/// closest name, when one is close).
pub fn selected_topics<'l, 'a>(log: &'l ULog<'a>, options: &Options) -> Result<Vec<Topic<'l, 'a>>> {
    if let Some(names) = &options.topics {
        for name in names {
            if log.topic_instances(name).is_empty() {
                // Gives the error with its suggestion.
                log.topic(name, 0)?;
            }
        }
    }
    let mut topics: Vec<Topic<'l, 'a>> = log
        .topics()
        .filter(|t| !t.is_empty())
        .filter(|t| {
            options
                .topics
                .as_ref()
                .map_or(true, |names| names.iter().any(|n| n == t.name()))
        })
        .collect();
    topics.sort_by(|a, b| (a.name(), a.multi_id()).cmp(&(b.name(), b.multi_id())));
    Ok(topics)
}

/// The file name of a topic instance in its log's folder: `<topic>_<multi_id>.parquet`,
/// the topic's name as [`LogNames`](crate::naming::LogNames) gives it for the topics
/// of its log (as it is for every PX4 topic; escaped when a file system would refuse
/// or fold it: [`crate::naming`]).
pub fn file_name(topic: &Topic<'_, '_>) -> String {
    let names = crate::naming::LogNames::new(topic.log().topics().map(|t| t.name()));
    name_of(&names.file_part(topic.name()), topic.multi_id())
}

/// The file name of topic instance `multi_id` whose name in file names is `part`.
pub(crate) fn name_of(part: &str, multi_id: u8) -> String {
    format!("{part}_{multi_id}.parquet")
}

/// Appends the text of a `char[N]` value to `out` (cleared first): the bytes up to the
/// last non-NUL byte, each byte one character (ISO 8859-1, lossless).
pub(crate) fn latin1(bytes: &[u8], out: &mut String) {
    out.clear();
    let end = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    out.extend(bytes[..end].iter().map(|&b| char::from(b)));
}
