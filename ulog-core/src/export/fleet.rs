//! The fleet layout of a [`Dataset`](super::Dataset): a topic's rows of many logs per
//! file, in Hive-style partitions ([`DatasetLayout::Fleet`]).
//!
//! A conversion writes each new log's topic files as the file-per-log layout does,
//! into the dataset's folder [`PENDING_DIR`] (which engines skip: it starts with `_`);
//! [`compact`] then puts each topic's new rows into files of about
//! [`FleetLayout::file_bytes`], row groups of whole logs (`ROW_GROUP_BYTES`), logs
//! in `log_id` order and each log's rows in `timestamp` order, in a folder per partition
//! (`<topic>/month=2024-05/…`). A file holds the logs of one conversion, one format of
//! the topic, and is named after its first log (`<log_id>.parquet`): a file whose
//! first log the table of logs does not list was left by a conversion that died before
//! its commit, and the next one removes it as it removes a log's own file. Files are
//! not rewritten: adding logs adds files, until a conversion asks for the small ones to
//! be merged ([`Options::compact`](super::Options::compact), `compaction.rs`).

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{TimestampMicrosecondType, UInt64Type};
use arrow_array::{Array, RecordBatch};
use arrow_schema::{Schema, SchemaRef};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::file::metadata::KeyValue;

use super::error::{ExportError, ExportErrorKind};
use super::files::write_error;
use super::lock::partial_name;
use super::Compression;
use crate::log::utc::UtcTime;

type Result<T, E = ExportError> = core::result::Result<T, E>;

/// The folder of a fleet-layout dataset where a conversion puts its logs' topic files
/// until [`Dataset::finish`](super::Dataset::finish) compacts them.
pub const PENDING_DIR: &str = "_pending";

/// The value of a partition key a log does not have (no UTC time, no `sys_uuid`), as
/// Hive writes it: DuckDB and Spark read it as NULL.
pub const NULL_PARTITION: &str = "__HIVE_DEFAULT_PARTITION__";

/// Key-value metadata of a fleet file: the XXH3-64 of the topic's format (as the logs
/// define it, `ulog.format`), in 16 hex digits.
pub const FORMAT_HASH_KEY: &str = "ulog.format_hash";
/// Key-value metadata of a fleet file: the firmware versions of its logs
/// (`ver_sw_release`, else `ver_sw`), sorted, comma-separated.
pub const FIRMWARE_KEY: &str = "ulog.firmware";
/// Key-value metadata of a fleet file: its logs' ids, comma-separated, in the order of
/// its rows.
pub const LOG_IDS_KEY: &str = "ulog.log_ids";

/// How a dataset's topic files are laid out ([`Options::layout`](super::Options::layout)).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum DatasetLayout {
    /// `<topic>/<log_id>.parquet`: a file per topic and log, written as the log is
    /// read. Simple, and byte for byte the same whatever the order logs come in; at
    /// thousands of logs, many small files.
    #[default]
    FilePerLog,
    /// `<topic>/<key>=<value>/…/<log_id>.parquet`: a topic's rows of many logs per file.
    Fleet(FleetLayout),
}

/// The fleet layout's choices ([`DatasetLayout::Fleet`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FleetLayout {
    /// The partition folders of each topic, outermost first: the partitions a query's
    /// filter on these columns prunes to. Recorded in the dataset: the logs added
    /// later go into the same partitions.
    pub partition_by: Vec<PartitionKey>,
    /// A file is closed once it holds this many bytes (a log is never split over
    /// files). Engines read files of 100 MB to 1 GB best.
    pub file_bytes: u64,
}

impl Default for FleetLayout {
    fn default() -> FleetLayout {
        FleetLayout {
            partition_by: vec![PartitionKey::Month],
            file_bytes: 128 << 20,
        }
    }
}

/// A column of the table of logs that partitions a fleet layout's topic files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum PartitionKey {
    /// `month=YYYY-MM`: the month of the log's `start_utc`.
    Month,
    /// `vehicle=<sys_uuid>` (percent-escaped as Hive does).
    Vehicle,
}

impl PartitionKey {
    /// The folder's key (`month`, `vehicle`): the column engines make of it.
    pub fn name(self) -> &'static str {
        match self {
            PartitionKey::Month => "month",
            PartitionKey::Vehicle => "vehicle",
        }
    }

    /// The key named `name`.
    pub fn parse(name: &str) -> Option<PartitionKey> {
        match name {
            "month" => Some(PartitionKey::Month),
            "vehicle" => Some(PartitionKey::Vehicle),
            _ => None,
        }
    }
}

impl DatasetLayout {
    /// The layout of a conversion's options by name, as `ulog parquet --layout
    /// --partition-by --file-size` and `ulog_rs.convert(layout=, partition_by=,
    /// file_size_mb=)` take them: `name` `"file-per-log"` or `"fleet"` (`None`: the
    /// dataset's own, or file per log for a new one); the fleet layout's partition
    /// keys by [name](PartitionKey::name), outermost first (default `month`; `"none"`
    /// is no key), and its file size in MB (default 128, at least 1). An error (what is
    /// wrong, in words) for an unknown name, a key given twice, a size of 0, or keys or
    /// a size without the fleet layout.
    ///
    /// ```
    /// use ulog_core::export::{DatasetLayout, FleetLayout, PartitionKey};
    ///
    /// let fleet = DatasetLayout::from_names(Some("fleet"), Some(&["vehicle", "month"]), Some(64));
    /// let keys = vec![PartitionKey::Vehicle, PartitionKey::Month];
    /// assert_eq!(
    ///     fleet,
    ///     Ok(Some(DatasetLayout::Fleet(FleetLayout { partition_by: keys, file_bytes: 64 << 20 })))
    /// );
    /// assert!(DatasetLayout::from_names(None, Some(&["month"]), None).is_err());
    /// assert!(DatasetLayout::from_names(Some("fleet"), Some(&["month", "month"]), None).is_err());
    /// ```
    pub fn from_names(
        name: Option<&str>,
        partition_by: Option<&[&str]>,
        file_size_mb: Option<u64>,
    ) -> Result<Option<DatasetLayout>, String> {
        if name != Some("fleet") && (partition_by.is_some() || file_size_mb.is_some()) {
            return Err(
                "the partition keys and the file size are options of the fleet layout".to_owned(),
            );
        }
        match name {
            None => Ok(None),
            Some("file-per-log") => Ok(Some(DatasetLayout::FilePerLog)),
            Some("fleet") => {
                let mut keys = Vec::new();
                for &key in partition_by.unwrap_or(&["month"]) {
                    if key == "none" {
                        continue;
                    }
                    let parsed = PartitionKey::parse(key).ok_or_else(|| {
                        format!("partition key `{key}`: `month`, `vehicle` or `none`")
                    })?;
                    if keys.contains(&parsed) {
                        return Err(format!("partition key `{key}` is given twice"));
                    }
                    keys.push(parsed);
                }
                let mb = file_size_mb.unwrap_or(FleetLayout::default().file_bytes >> 20);
                if mb == 0 {
                    return Err("the file size is at least 1 MB".to_owned());
                }
                Ok(Some(DatasetLayout::Fleet(FleetLayout {
                    partition_by: keys,
                    file_bytes: mb << 20,
                })))
            }
            Some(other) => Err(format!("layout `{other}`: `file-per-log` or `fleet`")),
        }
    }

    /// How the tables record it (`ulog.layout`): `file-per-log`, or `fleet` and its
    /// partition keys (`fleet:month,vehicle`). The file size is not recorded: each
    /// conversion may choose its own.
    pub(super) fn recorded(&self) -> String {
        match self {
            DatasetLayout::FilePerLog => "file-per-log".to_owned(),
            DatasetLayout::Fleet(fleet) => {
                let keys: Vec<&str> = fleet.partition_by.iter().map(|k| k.name()).collect();
                format!("fleet:{}", keys.join(","))
            }
        }
    }

    /// The layout a table recorded ([`DatasetLayout::recorded`]), with `file_bytes`.
    pub(super) fn from_recorded(text: &str, file_bytes: u64) -> Option<DatasetLayout> {
        if text == "file-per-log" {
            return Some(DatasetLayout::FilePerLog);
        }
        let keys = text.strip_prefix("fleet:")?;
        let partition_by = keys
            .split(',')
            .filter(|k| !k.is_empty())
            .map(PartitionKey::parse)
            .collect::<Option<Vec<_>>>()?;
        Some(DatasetLayout::Fleet(FleetLayout {
            partition_by,
            file_bytes,
        }))
    }

    /// Whether `other` lays files out in the same folders (the file size aside).
    pub(super) fn same_folders(&self, other: &DatasetLayout) -> bool {
        self.recorded() == other.recorded()
    }
}

/// What a log's row of the table of logs says that places its rows.
#[derive(Debug, Clone, Default)]
pub(super) struct LogPlace {
    /// `start_utc`, µs since the Unix epoch.
    pub start_utc: Option<i64>,
    pub sys_uuid: Option<String>,
    /// `ver_sw_release`, else `ver_sw`.
    pub firmware: Option<String>,
}

impl LogPlace {
    /// The place of each log of the table of logs' `rows` (by log id).
    pub(super) fn of_logs(rows: &BTreeMap<String, Vec<RecordBatch>>) -> BTreeMap<String, LogPlace> {
        let mut places = BTreeMap::new();
        for (id, batches) in rows {
            let Some(batch) = batches.iter().find(|b| b.num_rows() > 0) else {
                continue;
            };
            let text = |name: &str| {
                let column = batch.column_by_name(name)?.as_string_opt::<i32>()?;
                (!column.is_null(0)).then(|| column.value(0).to_owned())
            };
            let start_utc = batch
                .column_by_name("start_utc")
                .and_then(|c| c.as_primitive_opt::<TimestampMicrosecondType>())
                .and_then(|c| (!c.is_null(0)).then(|| c.value(0)));
            places.insert(
                id.clone(),
                LogPlace {
                    start_utc,
                    sys_uuid: text("sys_uuid"),
                    firmware: text("ver_sw_release").or_else(|| text("ver_sw")),
                },
            );
        }
        places
    }

    /// The log's partition folder, `month=2024-05/vehicle=…` (empty without keys).
    fn folder(&self, keys: &[PartitionKey]) -> PathBuf {
        let mut folder = PathBuf::new();
        for key in keys {
            let value = match key {
                PartitionKey::Month => self
                    .start_utc
                    .map(|us| UtcTime(us).to_string()[..7].to_owned()),
                PartitionKey::Vehicle => self.sys_uuid.as_deref().map(hive_escape),
            };
            let value = value.unwrap_or_else(|| NULL_PARTITION.to_owned());
            folder.push(format!("{}={value}", key.name()));
        }
        folder
    }
}

/// `value` as a Hive partition folder's value: bytes other than ASCII letters, digits,
/// `-`, `_` and `.` as `%XX`; nothing empty.
fn hive_escape(value: &str) -> String {
    if value.is_empty() {
        return NULL_PARTITION.to_owned();
    }
    let mut out = String::with_capacity(value.len());
    for b in value.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.') {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

/// A fleet file's row group is closed after the log that brings it to this many bytes
/// (as the writer estimates them encoded). Not a row group per log: a footer has
/// metadata per row group and column, and most logs' rows of most topics are a few
/// kilobytes: with a row group per log, the footers were 95 MB of the 1,550 MB of a
/// fleet of 2,000 logs (`bench/fleet.py`), and 0.8 MB of a 2.2 MB file of
/// `vehicle_status` (420 logs).
const ROW_GROUP_BYTES: usize = 4 << 20;

/// One log's file of a topic, waiting in [`PENDING_DIR`].
struct Pending<'a> {
    log_id: String,
    path: PathBuf,
    schema: SchemaRef,
    place: &'a LogPlace,
}

/// Compacts the pending topic files of `new` (by topic folder: `<log_id>.parquet`
/// files) into fleet files below `dir` (see the [module](self)); the files written,
/// by topic folder. The pending files are removed as their rows land.
pub(super) fn compact(
    dir: &Path,
    new: &BTreeMap<String, Vec<PathBuf>>,
    places: &BTreeMap<String, LogPlace>,
    layout: &FleetLayout,
    compression: Compression,
) -> Result<BTreeMap<String, Vec<PathBuf>>> {
    // A topic per thread at a time: compaction decodes and encodes every new row again.
    let folders: Vec<(&String, &Vec<PathBuf>)> = new.iter().collect();
    let results = each_folder(&folders, |(folder, files)| {
        let out = compact_folder(dir, folder, files, places, layout, compression)?;
        Ok(((*folder).clone(), out))
    });
    let mut written = BTreeMap::new();
    for result in results {
        let (folder, files) = result?;
        written.insert(folder, files);
    }
    Ok(written)
}

/// `work` of each item of `items`, on as many threads as there are CPUs (an item per
/// thread at a time): the results, in no particular order.
pub(super) fn each_folder<T: Sync, R: Send>(
    items: &[T],
    work: impl Fn(&T) -> Result<R> + Sync,
) -> Vec<Result<R>> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(items.len())
        .max(1);
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(item) = items.get(i) else {
                            return done;
                        };
                        done.push(work(item));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a compaction thread does not panic"))
            .collect()
    })
}

/// Compacts the pending files of one topic folder: the files written.
fn compact_folder(
    dir: &Path,
    folder: &str,
    files: &[PathBuf],
    places: &BTreeMap<String, LogPlace>,
    layout: &FleetLayout,
    compression: Compression,
) -> Result<Vec<PathBuf>> {
    let none = LogPlace::default();
    // By partition folder, then by schema (a file has one): the logs in id order.
    let mut groups: BTreeMap<PathBuf, Vec<Vec<Pending<'_>>>> = BTreeMap::new();
    let mut sorted: Vec<&PathBuf> = files.iter().collect();
    sorted.sort();
    for path in sorted {
        let log_id = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let place = places.get(&log_id).unwrap_or(&none);
        let schema = file_schema(path)?;
        let part = groups
            .entry(place.folder(&layout.partition_by))
            .or_default();
        let pending = Pending {
            log_id,
            path: path.clone(),
            schema,
            place,
        };
        by_format(part, pending, |p| &p.schema);
    }
    let mut out = Vec::new();
    for (partition, part) in groups {
        let target = dir.join(folder).join(&partition);
        std::fs::create_dir_all(&target).map_err(|e| ExportError::io(e, &target))?;
        for group in part {
            write_group(&target, &group, layout.file_bytes, compression, &mut out)?;
        }
    }
    Ok(out)
}

/// Puts `item` into the group of `groups` whose format (`schema`) is its own, or into
/// a new one.
pub(super) fn by_format<T>(groups: &mut Vec<Vec<T>>, item: T, schema: impl Fn(&T) -> &SchemaRef) {
    match groups
        .iter_mut()
        .find(|g| same_format(schema(&g[0]), schema(&item)))
    {
        Some(group) => group.push(item),
        None => groups.push(vec![item]),
    }
}

/// Whether two logs' files of a topic can share a file: the same columns, and the same
/// format as the logs define it.
fn same_format(a: &Schema, b: &Schema) -> bool {
    a.fields() == b.fields() && a.metadata().get("ulog.format") == b.metadata().get("ulog.format")
}

/// The Arrow schema of a Parquet file (its key-value metadata as the schema's).
pub(super) fn file_schema(path: &Path) -> Result<SchemaRef> {
    let file = File::open(path).map_err(|e| ExportError::io(e, path))?;
    let builder =
        ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| unreadable(path, e))?;
    Ok(builder.schema().clone())
}

pub(super) fn unreadable(path: &Path, e: impl std::fmt::Display) -> ExportError {
    ExportError::new(ExportErrorKind::Dataset {
        what: format!("a topic file to compact cannot be read back: {e}"),
    })
    .in_file(path)
}

/// Writes the logs of `group` (one topic, partition and format; in id order) into
/// files of about `file_bytes` in `target`, appending their paths to `out`.
fn write_group(
    target: &Path,
    group: &[Pending<'_>],
    file_bytes: u64,
    compression: Compression,
    out: &mut Vec<PathBuf>,
) -> Result<()> {
    let format = FileFormat::of(&group[0].schema, compression);
    let mut open: Option<Open> = None;
    for pending in group {
        let file = match &mut open {
            Some(file) => file,
            None => open.insert(Open::create(target, &pending.log_id, &format)?),
        };
        let rows = sorted_rows(&pending.path, &format.schema)?;
        file.push_log(&pending.log_id, &rows, pending.place.firmware.as_deref())?;
        if file.size() >= file_bytes {
            out.push(open.take().expect("open").close()?);
        }
    }
    if let Some(file) = open {
        out.push(file.close()?);
    }
    for pending in group {
        std::fs::remove_file(&pending.path).map_err(|e| ExportError::io(e, &pending.path))?;
    }
    Ok(())
}

/// The schema and writer properties of the fleet files of one topic format.
pub(super) struct FileFormat {
    /// The columns, without metadata (that goes into the file's key-value metadata).
    pub schema: SchemaRef,
    props: parquet::file::properties::WriterProperties,
}

impl FileFormat {
    /// The format of files holding rows of `schema` (a log's file of the topic, or a
    /// fleet file): the topic's metadata and its format's hash ([`FORMAT_HASH_KEY`]),
    /// less what is a log's or a file's own (its instance, logs, firmware versions).
    pub fn of(schema: &Schema, compression: Compression) -> FileFormat {
        let mut metadata = schema.metadata().clone();
        for key in ["ulog.multi_id", FIRMWARE_KEY, LOG_IDS_KEY, "ARROW:schema"] {
            metadata.remove(key);
        }
        if let Some(format) = metadata.get("ulog.format") {
            let hash = xxhash_rust::xxh3::xxh3_64(format.as_bytes());
            metadata.insert(FORMAT_HASH_KEY.to_owned(), format!("{hash:016x}"));
        }
        let described = Schema::new_with_metadata(schema.fields().clone(), metadata);
        // The metadata as the file's key-value metadata (sorted), not inside the
        // encoded Arrow schema, whose map has no order: the file is the same from run
        // to run.
        FileFormat {
            props: super::writer_properties(&described, compression),
            schema: Arc::new(Schema::new(schema.fields().clone())),
        }
    }
}

/// A fleet file being written.
pub(super) struct Open {
    path: PathBuf,
    partial: PathBuf,
    /// `None` once closed.
    writer: Option<ArrowWriter<std::io::BufWriter<File>>>,
    logs: Vec<String>,
    firmware: BTreeSet<String>,
}

impl Open {
    pub fn create(target: &Path, first: &str, format: &FileFormat) -> Result<Open> {
        let path = target.join(format!("{first}.parquet"));
        let partial = target.join(partial_name(&format!("{first}.parquet")));
        let file = File::create(&partial).map_err(|e| ExportError::io(e, &path))?;
        let writer = ArrowWriter::try_new(
            std::io::BufWriter::new(file),
            format.schema.clone(),
            Some(format.props.clone()),
        )
        .map_err(|e| write_error(&path, e))?;
        Ok(Open {
            path,
            partial,
            writer: Some(writer),
            logs: Vec::new(),
            firmware: BTreeSet::new(),
        })
    }

    /// Closes the file, with its logs and firmware versions in its metadata, and
    /// renames it into place.
    pub fn close(self) -> Result<PathBuf> {
        self.close_with(false)
    }

    /// [`Open::close`], the file's bytes on disk before the rename and the rename on
    /// disk after it (the folder synced): for a file that replaces others, whose
    /// removal comes next.
    pub fn close_durably(self) -> Result<PathBuf> {
        self.close_with(true)
    }

    fn close_with(mut self, durable: bool) -> Result<PathBuf> {
        let firmware: Vec<&str> = self.firmware.iter().map(String::as_str).collect();
        let mut writer = self.writer.take().expect("closed once");
        writer
            .append_key_value_metadata(KeyValue::new(FIRMWARE_KEY.to_owned(), firmware.join(",")));
        writer
            .append_key_value_metadata(KeyValue::new(LOG_IDS_KEY.to_owned(), self.logs.join(",")));
        let closed = writer
            .into_inner()
            .map_err(|e| write_error(&self.path, e))
            .and_then(|file| {
                let file = file
                    .into_inner()
                    .map_err(|e| ExportError::io(e.into_error(), &self.path))?;
                if durable {
                    file.sync_all()
                        .map_err(|e| ExportError::io(e, &self.path))?;
                }
                drop(file);
                std::fs::rename(&self.partial, &self.path)
                    .map_err(|e| ExportError::io(e, &self.path))?;
                if durable {
                    if let Some(folder) = self.path.parent() {
                        File::open(folder)
                            .and_then(|f| f.sync_all())
                            .map_err(|e| ExportError::io(e, folder))?;
                    }
                }
                Ok(())
            });
        if closed.is_err() {
            let _ = std::fs::remove_file(&self.partial);
        }
        closed.map(|()| std::mem::take(&mut self.path))
    }

    fn writer(&mut self) -> &mut ArrowWriter<std::io::BufWriter<File>> {
        self.writer.as_mut().expect("open until closed")
    }

    /// Appends the rows of the log `id` (all of them, in order), whose firmware
    /// version is `firmware`.
    pub fn push_log(
        &mut self,
        id: &str,
        rows: &[RecordBatch],
        firmware: Option<&str>,
    ) -> Result<()> {
        for batch in rows {
            self.writer()
                .write(batch)
                .map_err(|e| write_error(&self.path, e))?;
        }
        // Row groups of whole logs, closed after the log that fills one: a log's rows
        // are one row group (or several, past the writer's row limit) unless it is
        // small, and then they share one with the next logs, in id order, so the
        // `log_id` statistics still prune to it.
        if self.writer().in_progress_size() >= ROW_GROUP_BYTES {
            self.writer()
                .flush()
                .map_err(|e| write_error(&self.path, e))?;
        }
        self.logs.push(id.to_owned());
        if let Some(firmware) = firmware {
            self.firmware.insert(firmware.to_owned());
        }
        Ok(())
    }

    /// Its bytes so far, as the writer estimates them encoded.
    pub fn size(&self) -> u64 {
        let writer = self.writer.as_ref().expect("open until closed");
        (writer.bytes_written() + writer.in_progress_size()) as u64
    }
}

impl Drop for Open {
    fn drop(&mut self) {
        // A file given up part way (an error): its partial file goes; a closed one
        // was renamed already.
        if self.writer.is_some() {
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}

/// The rows of a log's topic file, in `timestamp` order (stable: rows of one time keep
/// the log's order), as batches of `schema`. Already in order, as most are, they are
/// passed on as read.
fn sorted_rows(path: &Path, schema: &SchemaRef) -> Result<Vec<RecordBatch>> {
    let file = File::open(path).map_err(|e| ExportError::io(e, path))?;
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.build())
        .map_err(|e| unreadable(path, e))?;
    let mut batches = Vec::new();
    for batch in reader {
        let batch = batch.map_err(|e| unreadable(path, e))?;
        let batch = RecordBatch::try_new(schema.clone(), batch.columns().to_vec())
            .map_err(|e| unreadable(path, e))?;
        batches.push(batch);
    }
    let times: Vec<u64> = match batches
        .iter()
        .map(|b| {
            b.column_by_name("timestamp")
                .and_then(|c| c.as_primitive_opt::<UInt64Type>())
                .filter(|c| c.null_count() == 0)
                .map(|c| c.values().to_vec())
        })
        .collect::<Option<Vec<_>>>()
    {
        Some(parts) => parts.concat(),
        None => return Ok(batches),
    };
    if times.windows(2).all(|w| w[0] <= w[1]) {
        return Ok(batches);
    }
    let all =
        arrow_select::concat::concat_batches(schema, &batches).map_err(ExportError::encoding)?;
    let mut order: Vec<u32> = (0..times.len() as u32).collect();
    order.sort_by_key(|&i| times[i as usize]);
    let indices = arrow_array::UInt32Array::from(order);
    let sorted =
        arrow_select::take::take_record_batch(&all, &indices).map_err(ExportError::encoding)?;
    Ok(vec![sorted])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_folders_name_month_and_vehicle() {
        let place = LogPlace {
            // 2024-02-06T16:27:02Z
            start_utc: Some(1_707_236_822_000_000),
            sys_uuid: Some("0001 a/b".to_owned()),
            firmware: None,
        };
        let keys = [PartitionKey::Month, PartitionKey::Vehicle];
        assert_eq!(
            place.folder(&keys),
            Path::new("month=2024-02").join("vehicle=0001%20a%2Fb")
        );
        assert_eq!(
            LogPlace::default().folder(&keys),
            Path::new("month=__HIVE_DEFAULT_PARTITION__")
                .join("vehicle=__HIVE_DEFAULT_PARTITION__")
        );
    }

    #[test]
    fn the_recorded_layout_reads_back() {
        let fleet = DatasetLayout::Fleet(FleetLayout {
            partition_by: vec![PartitionKey::Vehicle, PartitionKey::Month],
            file_bytes: 7,
        });
        assert_eq!(fleet.recorded(), "fleet:vehicle,month");
        assert_eq!(
            DatasetLayout::from_recorded("fleet:vehicle,month", 7),
            Some(fleet)
        );
        let flat = DatasetLayout::from_recorded("fleet:", 1).unwrap();
        assert_eq!(flat.recorded(), "fleet:");
        assert_eq!(
            DatasetLayout::from_recorded("file-per-log", 1),
            Some(DatasetLayout::FilePerLog)
        );
        assert_eq!(DatasetLayout::from_recorded("fleet:day", 1), None);
    }
}
