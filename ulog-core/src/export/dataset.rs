//! Many logs as one dataset: one Parquet file per topic and log, and four tables of
//! what the logs are (see [`Dataset`]).

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use arrow_array::builder::ArrayBuilder;
use arrow_array::builder::{
    BooleanBuilder, Float64Builder, StringBuilder, TimestampMicrosecondBuilder, UInt16Builder,
    UInt32Builder, UInt64Builder,
};
use arrow_array::{Array, ArrayRef, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema, SchemaRef, TimeUnit};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::file::metadata::KeyValue as ParquetKeyValue;
use sha2::{Digest, Sha256};

use super::compaction::{compact_small_files, not_fleet, remove_superseded, Compacted};
use super::error::{ExportError, ExportErrorKind};
use super::files::{compression_of, folder_files, topic_files, write_error};
use super::fleet::{compact, DatasetLayout, FleetLayout, LogPlace, PENDING_DIR};
use super::lock::{partial_name, DatasetLock};
use super::metadata::Facts;
use super::stream::{export, Layout};
use super::{Export, Options};
use crate::error::{ReadError, ReadErrorKind};
use crate::finding::{Finding, FindingKind};
use crate::log::message::KeyValue;
use crate::log::ulog::ULog;
use crate::log::utc::UtcClock;

type Result<T, E = ExportError> = core::result::Result<T, E>;

/// The dataset's table of logs, one row each.
pub const LOGS_FILE: &str = "logs.parquet";
/// The dataset's table of parameters.
pub const PARAMETERS_FILE: &str = "parameters.parquet";
/// The dataset's table of logged strings and PX4 events.
pub const MESSAGES_FILE: &str = "messages.parquet";
/// The dataset's table of message formats.
pub const FORMATS_FILE: &str = "formats.parquet";

/// How a log's `log_id` is made, as the tables record it ([`LOG_ID_KEY`]): the XXH3
/// 64-bit hash of the whole file, in 16 hex digits, so that one log has one id wherever
/// it is and whatever its name (two different logs share one with a chance of 1 in
/// 2^32 in a fleet of 2^16 logs). Not the SHA-256 (which [`LOGS_FILE`] has too): the
/// id is needed before the pass, for every row it writes, and the SHA-256 of a 300 MB
/// log took 0.15 s of one core ahead of it (perf, log_61 ×90); XXH3 reads it at memory
/// speed, and the SHA-256 is taken as the pass reads the file, on its read-ahead
/// thread (with the id again: a file that changed in between is an error). XXH3 is not
/// made to resist a crafted collision: a log made to take another's id would have that
/// one skipped, which `sha256` shows.
const LOG_ID_RULE: &str = "xxh3-64";

/// A folder of Parquet files that holds any number of logs, for engines that read a
/// folder of Parquet files as one table (DuckDB, DataFusion, Polars, Spark):
///
/// - `<topic>/<log_id>.parquet`: the rows of a topic in one log, all its instances,
///   with columns `log_id` and `multi_id` before the fields ([`Options::log_id`]), so
///   that `SELECT … FROM 'DATASET/vehicle_status/*.parquet'` spans every log;
/// - [`LOGS_FILE`]: one row per log: `log_id`, `path` (as given), `size`, `sha256`,
///   `start_timestamp` (µs since boot) and `duration_s` (the log's
///   [span](crate::ULog::span)), `start_utc` and `utc_source` (where the log
///   says it, by [`ULog::utc`]'s rule), `sys_name`, `ver_hw`, `ver_sw`,
///   `ver_sw_release`, `sys_uuid`, `vehicle_type` (from parameter `MAV_TYPE`),
///   `airframe` (`SYS_AUTOSTART`), `topics` (topic instances with data), `messages`
///   (data messages), and the damage: `truncated`, `damaged`, `corrupt_bytes` (bytes
///   stepped over), `findings`, `dropouts`, `dropout_ms`;
/// - [`PARAMETERS_FILE`]: `log_id`, `name`, `value` (as a double: every `int32_t`
///   and `float` is exact), `type`, `timestamp` (null but for changes), `kind`
///   (`initial`, `changed`, `default-system`, `default-configuration`);
/// - [`MESSAGES_FILE`]: `log_id`, `timestamp`, `kind` (`logged`, `tagged`, `event`),
///   `level`, `tag`, `text`, `event` (the event's name);
/// - [`FORMATS_FILE`]: `log_id`, `name`, `format` (as the log defines it);
/// - [`ANALYSIS_FILE`](super::ANALYSIS_FILE): the diagnostics of the flight analysis
///   ([`crate::analysis`], made in the same pass), one row per log and diagnostic;
///   [`FLIGHTS_FILE`](super::FLIGHTS_FILE): its flight statistics, one row per log
///   (a dataset written by an earlier version has neither: its logs have no rows
///   there).
///
/// In the fleet layout ([`Options::layout`], [`DatasetLayout::Fleet`]) a topic's files
/// hold many logs each instead, in partition folders
/// (`<topic>/month=2024-05/<log_id>.parquet`, named after their first log): the
/// logs' files are written into [`PENDING_DIR`](super::PENDING_DIR) as they are added
/// and compacted by [`Dataset::finish`]; a dataset keeps the layout it was made with.
/// With [`Options::compact`], `finish` then merges the small files that logs added a
/// few at a time leave ([`Finished::compacted`]).
///
/// - [`SCHEMAS_DIR`](super::SCHEMAS_DIR)`/<topic>.parquet`: each topic's union schema
///   over all its files ([`union_schema`](super::union_schema)), no rows, widened as
///   logs are added: for engines that take one schema for a folder of files.
///
/// `log_id` is the log's XXH3 64-bit hash in 16 hex digits: the same
/// log has the same id wherever it is, and converting it into a dataset that has it
/// already does nothing
/// ([`Added::Present`]). The four tables are sorted by `log_id`, each log's rows in
/// log order, and written again by [`Dataset::finish`] with the rows they had and the
/// new logs'; a topic's file is written once, when its log is added. The files are the
/// same byte for byte whatever the order the logs are added in, or the threads.
///
/// Logs are added with [`Dataset::add`], from any number of threads at once. A log
/// already there is skipped whatever the options are now ([`Options::topics`],
/// [`Options::utc`]); the tables record [`Options::flatten`] and how log ids are made,
/// and a dataset refuses to open with the other flattening or another rule.
///
/// One conversion writes a dataset at a time: [`Dataset::open`] takes its lock (the
/// file [`LOCK_FILE`](super::LOCK_FILE) in the folder) and the `Dataset` holds it
/// until [`Dataset::finish`] or until it is dropped; another process (or another
/// `Dataset` of the same folder) gets [`ExportErrorKind::Busy`] meanwhile, and can
/// open it once the first is done. Every file is written under a temporary name of
/// its writer's own (`….<pid>-<n>.partial`) and renamed when done; the temporary files
/// of a conversion that died are removed by the next `open`, and so are the topic
/// files of logs the table of logs does not list (a conversion killed after a log's
/// files were renamed into place and before its tables were written).
///
/// ```
/// use ulog_core::export::{Added, Dataset, Options};
/// let dir = std::env::temp_dir().join(format!("ulog-dataset-doc-{}", std::process::id()));
/// let log = dir.with_extension("ulg");
/// std::fs::write(&log, ulog_core::testing::sample_log())?;
///
/// let dataset = Dataset::open(&dir, &Options::default())?;
/// let Added::Written { log_id, export } = dataset.add(&log, None, |_| {})? else {
///     unreachable!("a new dataset has no log")
/// };
/// dataset.finish()?;
/// assert!(dir.join("esc_status").join(format!("{log_id}.parquet")).is_file());
/// assert!(dir.join("logs.parquet").is_file());
///
/// // Added again: already there.
/// let dataset = Dataset::open(&dir, &Options::default())?;
/// assert!(matches!(dataset.add(&log, None, |_| {})?, Added::Present { .. }));
/// # std::fs::remove_dir_all(&dir)?; std::fs::remove_file(&log)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Dataset {
    dir: PathBuf,
    options: Options,
    /// Its layout: as recorded, else as asked.
    layout: DatasetLayout,
    state: Mutex<State>,
    /// Held from `open` until the dataset is finished or dropped.
    _lock: DatasetLock,
}

#[derive(Debug, Default)]
struct State {
    /// The logs in the dataset, those being added included.
    ids: BTreeSet<String>,
    /// Each table's rows by log.
    tables: [BTreeMap<String, Vec<RecordBatch>>; 6],
    /// The topic files this conversion wrote or moved in, by topic folder: those
    /// topics' union schemas are brought up to date by `finish` (from these files,
    /// without a walk of the dataset).
    new: BTreeMap<String, Vec<PathBuf>>,
}

/// What [`Dataset::finish`] did besides writing the tables.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Finished {
    /// What the compaction asked for by [`Options::compact`] did.
    pub compacted: Option<Compacted>,
}

/// What [`Dataset::add`] did.
#[derive(Debug)]
#[non_exhaustive]
pub enum Added {
    /// The log's files were written.
    Written {
        /// Its id.
        log_id: String,
        /// The files written (in the fleet layout, in
        /// [`PENDING_DIR`](super::PENDING_DIR) until [`Dataset::finish`] compacts
        /// them).
        export: Export,
    },
    /// The dataset has the log already (or it was added by another thread meanwhile):
    /// nothing was written.
    Present {
        /// Its id.
        log_id: String,
    },
    /// The log's files were moved here from another dataset ([`Dataset::absorb`]).
    Moved {
        /// Its id.
        log_id: String,
        /// Its topic files moved.
        files: usize,
    },
}

impl Dataset {
    /// The dataset in `dir` (made if missing), locked for this conversion, with the
    /// tables it has read back. `options` are those of every log's files
    /// ([`Options::log_id`] is set for each).
    ///
    /// An error when another conversion holds the dataset ([`ExportErrorKind::Busy`]:
    /// open it again once that one is done), when a table cannot be read, or has
    /// other columns than this version writes.
    pub fn open(dir: impl AsRef<Path>, options: &Options) -> Result<Dataset> {
        let dir = dir.as_ref().to_owned();
        std::fs::create_dir_all(&dir).map_err(|e| ExportError::io(e, &dir))?;
        let lock = DatasetLock::take(&dir)?;
        lock.clear_leftovers(&dir);
        let mut state = State::default();
        for (i, (name, schema)) in tables().into_iter().enumerate() {
            let path = dir.join(name);
            if path.exists() {
                state.tables[i] = read_table(&path, &schema, options.flatten)?;
            }
        }
        state.ids = state.tables[0].keys().cloned().collect();
        let layout = resolve_layout(&dir, options.layout.as_ref())?;
        if options.compact && !matches!(layout, DatasetLayout::Fleet(_)) {
            return Err(not_fleet(&dir));
        }
        // A compaction that died between a merged file and the removal of its
        // sources: their logs are in the merged file.
        remove_superseded(&dir)?;
        remove_unlisted(&dir, &state.ids)?;
        // A conversion that died before it compacted its logs' files.
        let pending = dir.join(PENDING_DIR);
        if pending.exists() {
            std::fs::remove_dir_all(&pending).map_err(|e| ExportError::io(e, &pending))?;
        }
        Ok(Dataset {
            dir,
            layout,
            options: options.clone(),
            state: Mutex::new(state),
            _lock: lock,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// How its topic files are laid out (as it was written, for a dataset that has
    /// logs).
    pub fn layout(&self) -> &DatasetLayout {
        &self.layout
    }

    /// Where a log's topic files are written as it is added: the dataset's folder, or
    /// in the fleet layout the folder of files waiting for [`Dataset::finish`].
    fn files_dir(&self) -> PathBuf {
        match self.layout {
            DatasetLayout::FilePerLog => self.dir.clone(),
            DatasetLayout::Fleet(_) => self.dir.join(PENDING_DIR),
        }
    }

    /// The number of logs in the dataset (those being added included).
    pub fn len(&self) -> usize {
        self.lock().ids.len()
    }

    /// The ids of its logs (those being added included), sorted.
    pub fn log_ids(&self) -> Vec<String> {
        self.lock().ids.iter().cloned().collect()
    }

    /// Whether the dataset has no log.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the dataset has the log `log_id` (or is adding it).
    pub fn contains(&self, log_id: &str) -> bool {
        self.lock().ids.contains(log_id)
    }

    /// Adds the log at `path`: its id from its bytes, then, if the dataset lacks it, its
    /// topics' files and its rows of the four tables (written by
    /// [`Dataset::finish`]). `progress` is called with the bytes of the log read so far.
    ///
    /// A log that fails leaves no file of its own, and the dataset as it was.
    ///
    /// `utc`: the log's clock for a column `timestamp_utc` ([`Options::utc`]), if wanted
    /// (the pass meets the GPS time only as it goes, after rows are written: take it
    /// from [`ULog::utc`] first).
    pub fn add<'p>(
        &self,
        log: impl Into<LogPath<'p>>,
        utc: Option<UtcClock>,
        progress: impl FnMut(u64),
    ) -> Result<Added> {
        let LogPath { path, name } = log.into();
        let (log_id, size) = log_id(path)?;
        if !self.lock().ids.insert(log_id.clone()) {
            return Ok(Added::Present { log_id });
        }
        let mut options = Options {
            log_id: Some(log_id.clone()),
            utc,
            ..self.options.clone()
        };
        if let DatasetLayout::Fleet(_) = self.layout {
            // Read back once by the compaction, which compresses: not compressed twice.
            options.compression = super::Compression::Uncompressed;
        }
        // The SHA-256 taken as the pass reads the file (on its read-ahead thread), with
        // the id again, to know the pass read the file the id was taken of.
        let read = Arc::new(Mutex::new(Hashed::default()));
        let reading = read.clone();
        let source = crate::Source::file_observed(
            path,
            Box::new(move |bytes: &[u8]| {
                let mut read = reading.lock().unwrap_or_else(|p| p.into_inner());
                read.sha256.update(bytes);
                read.id.update(bytes);
                read.bytes += bytes.len() as u64;
            }),
        );
        let origin = Origin {
            log_id: log_id.clone(),
            path: name.map_or_else(|| path.display().to_string(), str::to_owned),
            size,
            read,
        };
        let tables = |log: &ULog<'_>, facts: &Facts<'_>, utc: Option<UtcClock>| {
            LogTables::new(log, facts, &origin, utc)
        };
        let exported = export(
            source,
            &self.files_dir(),
            &options,
            Layout::Dataset(&tables),
            progress,
        );
        match exported {
            Ok((export, Some(tables))) => {
                let mut state = self.lock();
                for (i, batch) in tables.0.into_iter().enumerate() {
                    state.tables[i].insert(log_id.clone(), vec![batch]);
                }
                for written in &export.files {
                    let folder = written.path.parent().and_then(Path::file_name);
                    if let Some(folder) = folder {
                        let folder = folder.to_string_lossy().into_owned();
                        state
                            .new
                            .entry(folder)
                            .or_default()
                            .push(written.path.clone());
                    }
                }
                Ok(Added::Written { log_id, export })
            }
            Ok((_, None)) => unreachable!("a dataset's export gives the log's tables"),
            Err(e) => {
                self.lock().ids.remove(&log_id);
                Err(e)
            }
        }
    }

    /// Takes the logs of `ids` as present: [`Dataset::add`] then skips them
    /// ([`Added::Present`]) without converting them. For a dataset made to be
    /// [absorbed](Dataset::absorb) into another that has them (a Spark executor's).
    pub fn assume_present(&self, ids: impl IntoIterator<Item = String>) {
        self.lock().ids.extend(ids);
    }

    /// Adds the logs of the dataset in the folder `other` (converted elsewhere: by a
    /// Spark executor, on another machine, with the same options) that this one
    /// lacks: their topic files are moved here (renamed, or copied then removed
    /// across file systems), and their rows of the tables taken, to be written by
    /// [`Dataset::finish`] as those of logs [added](Dataset::add) are. A log this
    /// dataset has is left where it is ([`Added::Present`]). `other` must not be in
    /// use (its lock is not taken): it is a dataset whose conversion has finished.
    ///
    /// ```
    /// use ulog_core::export::{Added, Dataset, Options};
    /// let root = std::env::temp_dir().join(format!("ulog-absorb-doc-{}", std::process::id()));
    /// let log = root.join("sample.ulg");
    /// std::fs::create_dir_all(&root)?;
    /// std::fs::write(&log, ulog_core::testing::sample_log())?;
    ///
    /// // Converted elsewhere…
    /// let part = Dataset::open(root.join("part"), &Options::default())?;
    /// part.add(&log, None, |_| {})?;
    /// part.finish()?;
    /// // …then taken into the dataset.
    /// let dataset = Dataset::open(root.join("dataset"), &Options::default())?;
    /// let moved = dataset.absorb(root.join("part"))?;
    /// assert!(matches!(moved[..], [Added::Moved { files, .. }] if files > 0));
    /// dataset.finish()?;
    /// assert!(root.join("dataset/esc_status").read_dir()?.next().is_some());
    /// # std::fs::remove_dir_all(&root)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn absorb(&self, other: impl AsRef<Path>) -> Result<Vec<Added>> {
        let other = other.as_ref();
        if let DatasetLayout::Fleet(_) = resolve_layout(other, None)? {
            return Err(ExportError::new(ExportErrorKind::Dataset {
                what: "a dataset in the fleet layout cannot be absorbed: its files hold \
                       many logs each"
                    .to_owned(),
            })
            .in_file(other));
        }
        let files_dir = self.files_dir();
        let mut taken: [BTreeMap<String, Vec<RecordBatch>>; 6] = Default::default();
        for (i, (name, schema)) in tables().into_iter().enumerate() {
            let path = other.join(name);
            if path.exists() {
                taken[i] = read_table(&path, &schema, self.options.flatten)?;
            }
        }
        let ids: Vec<String> = taken[0].keys().cloned().collect();
        let mut files = topic_files(other)?;
        let mut added = Vec::with_capacity(ids.len());
        for log_id in ids {
            if !self.lock().ids.insert(log_id.clone()) {
                added.push(Added::Present { log_id });
                continue;
            }
            let mine = files.remove(&log_id).unwrap_or_default();
            let count = mine.len();
            let mut placed = Vec::with_capacity(count);
            let moved = mine.iter().try_for_each(|(folder, from)| {
                let to = files_dir.join(folder);
                std::fs::create_dir_all(&to).map_err(|e| ExportError::io(e, &to))?;
                let to = to.join(format!("{log_id}.parquet"));
                move_file(from, &to)?;
                placed.push((folder.clone(), to));
                Ok(())
            });
            if let Err(e) = moved {
                self.lock().ids.remove(&log_id);
                return Err(e);
            }
            let mut state = self.lock();
            for (i, table) in taken.iter_mut().enumerate() {
                if let Some(rows) = table.remove(&log_id) {
                    state.tables[i].insert(log_id.clone(), rows);
                }
            }
            for (folder, path) in placed {
                state.new.entry(folder).or_default().push(path);
            }
            added.push(Added::Moved {
                log_id,
                files: count,
            });
        }
        Ok(added)
    }

    /// In the fleet layout, compacts the files of the logs added into the partition
    /// folders (and with [`Options::compact`], merges the small files of every
    /// partition); then writes the union schemas of their topics
    /// ([`SCHEMAS_DIR`](super::SCHEMAS_DIR)), then the tables: the rows they had and
    /// those of the logs added, the table of logs last.
    pub fn finish(self) -> Result<Finished> {
        let mut state = self.state.into_inner().unwrap_or_else(|p| p.into_inner());
        let mut finished = Finished::default();
        if let DatasetLayout::Fleet(fleet) = &self.layout {
            let places = LogPlace::of_logs(&state.tables[0]);
            state.new = compact(
                &self.dir,
                &state.new,
                &places,
                fleet,
                self.options.compression,
            )?;
            let pending = self.dir.join(PENDING_DIR);
            if pending.exists() {
                std::fs::remove_dir_all(&pending).map_err(|e| ExportError::io(e, &pending))?;
            }
        }
        write_union_schemas(&self.dir, &state.new, self.options.compression)?;
        let mut written: Vec<(PathBuf, PathBuf)> = Vec::new();
        let mut result = Ok(());
        for ((name, schema), rows) in tables().into_iter().zip(&state.tables) {
            let path = self.dir.join(name);
            match write_table(&path, &schema, rows, &self.options, &self.layout) {
                Ok(partial) => written.push((partial, path)),
                Err(e) => {
                    result = Err(e);
                    break;
                }
            }
        }
        // The table of logs last: a log it lists is one whose rows every table has
        // (a log it lacks is converted again next time).
        written.rotate_left(1);
        for (partial, path) in &written {
            if result.is_ok() {
                result = std::fs::rename(partial, path).map_err(|e| ExportError::io(e, path));
            }
            if result.is_err() {
                let _ = std::fs::remove_file(partial);
            }
        }
        result?;
        // After the commit: every log of the files it merges is listed, so that a
        // compaction that dies leaves no row of a log the dataset does not have.
        if let (DatasetLayout::Fleet(fleet), true) = (&self.layout, self.options.compact) {
            let places = LogPlace::of_logs(&state.tables[0]);
            finished.compacted = Some(
                compact_small_files(&self.dir, &places, fleet, self.options.compression)
                    .map_err(ExportError::compaction)?,
            );
        }
        Ok(finished)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// Brings up to date the union schema of each topic folder of `new` (the files this
/// conversion put there, by folder): the union of the schema it had and theirs (of every file of the
/// folder, for a dataset written before there were union schemas). Written under a
/// temporary name and renamed, before the tables: a union may be wider than the logs
/// the table of logs lists (a conversion that died after it), never narrower.
fn write_union_schemas(
    dir: &Path,
    new: &BTreeMap<String, Vec<PathBuf>>,
    compression: super::Compression,
) -> Result<()> {
    let schemas_dir = dir.join(super::SCHEMAS_DIR);
    for (folder, new_files) in new {
        let published = schemas_dir.join(format!("{folder}.parquet"));
        let mut schemas = Vec::new();
        if published.exists() {
            schemas.push(super::union::file_schema(&published)?);
            for path in new_files {
                schemas.push(super::union::file_schema(path)?);
            }
        } else {
            let mut paths: Vec<PathBuf> = Vec::new();
            folder_files(&dir.join(folder), &mut |_, path| paths.push(path))?;
            paths.sort();
            for path in &paths {
                schemas.push(super::union::file_schema(path)?);
            }
        }
        let topic = schemas
            .iter()
            .find_map(|s| {
                let m = s.metadata();
                m.get(super::union::TOPIC_KEY)
                    .or_else(|| m.get("ulog.topic"))
                    .cloned()
            })
            .unwrap_or_else(|| folder.clone());
        let union = super::union_schema(schemas.iter(), &topic);
        // The metadata as the file's key-value metadata (sorted), not inside the
        // encoded Arrow schema, whose map has no order: the file is the same from run
        // to run. Readers give it back as the schema's metadata.
        let props = super::writer_properties(&union, compression);
        let union = Arc::new(Schema::new(union.fields().clone()));
        std::fs::create_dir_all(&schemas_dir).map_err(|e| ExportError::io(e, &schemas_dir))?;
        let partial = schemas_dir.join(partial_name(&format!("{folder}.parquet")));
        let written = (|| {
            let file = File::create(&partial).map_err(|e| ExportError::io(e, &published))?;
            let writer =
                ArrowWriter::try_new(std::io::BufWriter::new(file), union.clone(), Some(props))
                    .map_err(|e| write_error(&published, e))?;
            writer.close().map_err(|e| write_error(&published, e))?;
            std::fs::rename(&partial, &published).map_err(|e| ExportError::io(e, &published))
        })();
        if written.is_err() {
            let _ = std::fs::remove_file(&partial);
        }
        written?;
    }
    Ok(())
}

/// The layout of the dataset in `dir`: as its table of logs records it (a table
/// written before there were layouts: file per log), else `asked`, else file per
/// log. An error when `asked` lays files out in other folders than the dataset's.
fn resolve_layout(dir: &Path, asked: Option<&DatasetLayout>) -> Result<DatasetLayout> {
    let path = dir.join(LOGS_FILE);
    let file_bytes = match asked {
        Some(DatasetLayout::Fleet(fleet)) => fleet.file_bytes,
        _ => FleetLayout::default().file_bytes,
    };
    let recorded = match File::open(&path) {
        Ok(file) => {
            let builder = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| {
                ExportError::new(ExportErrorKind::Dataset {
                    what: format!("a table of the dataset cannot be read back: {e}"),
                })
                .in_file(&path)
            })?;
            let text = builder
                .metadata()
                .file_metadata()
                .key_value_metadata()
                .and_then(|kv| kv.iter().find(|kv| kv.key == LAYOUT_KEY))
                .and_then(|kv| kv.value.clone())
                .unwrap_or_else(|| DatasetLayout::FilePerLog.recorded());
            let layout = DatasetLayout::from_recorded(&text, file_bytes).ok_or_else(|| {
                ExportError::new(ExportErrorKind::Dataset {
                    what: format!("the dataset's layout ({text}) is not one this version knows"),
                })
                .in_file(&path)
            })?;
            Some(layout)
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(ExportError::io(e, &path)),
    };
    match (recorded, asked) {
        (Some(recorded), Some(asked)) if !recorded.same_folders(asked) => {
            Err(ExportError::new(ExportErrorKind::Dataset {
                what: format!(
                    "the dataset's layout is {}, these logs would be laid out as {}: convert \
                     them without a layout (the dataset's is kept), or into another dataset",
                    recorded.recorded(),
                    asked.recorded()
                ),
            })
            .in_file(&path))
        }
        (Some(recorded), _) => Ok(recorded),
        (None, asked) => Ok(asked.cloned().unwrap_or_default()),
    }
}

/// Removes the topic files of logs the table of logs does not list (`ids`): a
/// conversion killed after it wrote a log's files and before its tables leaves
/// them, and a reader of a topic's folder would see rows of a log the dataset does
/// not have.
fn remove_unlisted(dir: &Path, ids: &BTreeSet<String>) -> Result<()> {
    for (id, files) in topic_files(dir)? {
        if !ids.contains(&id) {
            for (_, path) in files {
                std::fs::remove_file(&path).map_err(|e| ExportError::io(e, &path))?;
            }
        }
    }
    Ok(())
}

/// Moves the file `from` to `to`: a rename, or across file systems a copy under a
/// temporary name renamed into place, then the original removed.
fn move_file(from: &Path, to: &Path) -> Result<()> {
    if std::fs::rename(from, to).is_ok() {
        return Ok(());
    }
    let name = to
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let partial = to.with_file_name(partial_name(&name));
    std::fs::copy(from, &partial).map_err(|e| ExportError::io(e, &partial))?;
    std::fs::rename(&partial, to).map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        ExportError::io(e, to)
    })?;
    std::fs::remove_file(from).map_err(|e| ExportError::io(e, from))
}

/// The file of a log to add ([`Dataset::add`]), and the name [`LOGS_FILE`]'s `path`
/// gives it: its path, or another ([`LogPath::named`]).
#[derive(Debug, Clone, Copy)]
pub struct LogPath<'a> {
    path: &'a Path,
    name: Option<&'a str>,
}

impl<'a> LogPath<'a> {
    /// The file at `path`, recorded as `name` (a log downloaded from object storage
    /// is recorded by its URL, not by the temporary file read).
    pub fn named(path: &'a Path, name: &'a str) -> LogPath<'a> {
        LogPath {
            path,
            name: Some(name),
        }
    }
}

impl<'a, P: AsRef<Path> + ?Sized> From<&'a P> for LogPath<'a> {
    fn from(path: &'a P) -> LogPath<'a> {
        LogPath {
            path: path.as_ref(),
            name: None,
        }
    }
}

/// The file a log is read from, as [`LOGS_FILE`] describes it.
#[derive(Debug)]
struct Origin {
    log_id: String,
    path: String,
    size: u64,
    /// What the pass read of it.
    read: Arc<Mutex<Hashed>>,
}

/// The hashes of the bytes a pass read, as it reads them.
#[derive(Default)]
struct Hashed {
    sha256: Sha256,
    id: xxhash_rust::xxh3::Xxh3,
    bytes: u64,
}

impl core::fmt::Debug for Hashed {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Hashed({} bytes)", self.bytes)
    }
}

impl Origin {
    /// The SHA-256 of the file in hex, once the pass has read it to its end; an error
    /// when the pass did not read the bytes its id was taken of (the file changed in
    /// between: a log still being written or copied), whose rows would then not be
    /// those of the log the id names.
    fn sha256(&self) -> Result<String> {
        let read = self.read.lock().unwrap_or_else(|p| p.into_inner());
        if read.bytes != self.size || id_text(&read.id) != self.log_id {
            let changed = ReadError::new(ReadErrorKind::Changed, None);
            return Err(ExportError::read(changed.in_file(Path::new(&self.path))));
        }
        let hash = read.sha256.clone().finalize();
        Ok(hash.iter().map(|b| format!("{b:02x}")).collect())
    }
}

/// A log's rows of the four tables, in the order of [`tables`].
#[derive(Debug)]
struct LogTables([RecordBatch; 6]);

/// A `log_id` as written: the XXH3-64 of the bytes hashed, 16 hex digits.
fn id_text(hash: &xxhash_rust::xxh3::Xxh3) -> String {
    format!("{:016x}", hash.digest())
}

/// The `log_id` of a file ([`LOG_ID_RULE`]) and its size.
fn log_id(path: &Path) -> Result<(String, u64)> {
    let mut file = File::open(path).map_err(|e| ExportError::io(e, path))?;
    let mut hash = xxhash_rust::xxh3::Xxh3::new();
    let mut buffer = vec![0u8; 1 << 20];
    let mut size = 0u64;
    loop {
        let n = match file.read(&mut buffer) {
            Ok(0) => return Ok((id_text(&hash), size)),
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(ExportError::io(e, path)),
        };
        hash.update(&buffer[..n]);
        size += n as u64;
    }
}

fn field(name: &str, ty: DataType, nullable: bool) -> Field {
    Field::new(name, ty, nullable)
}

/// The four tables: file name and schema.
fn tables() -> [(&'static str, SchemaRef); 6] {
    let utc = DataType::Timestamp(TimeUnit::Microsecond, Some("UTC".into()));
    let text = |name| field(name, DataType::Utf8, true);
    let logs = Schema::new(vec![
        field("log_id", DataType::Utf8, false),
        field("path", DataType::Utf8, false),
        field("size", DataType::UInt64, false),
        field("sha256", DataType::Utf8, false),
        field("start_timestamp", DataType::UInt64, false),
        field("start_utc", utc, true),
        text("utc_source"),
        field("duration_s", DataType::Float64, false),
        text("sys_name"),
        text("ver_hw"),
        text("ver_sw"),
        text("ver_sw_release"),
        text("sys_uuid"),
        text("vehicle_type"),
        field("airframe", DataType::UInt32, true),
        field("topics", DataType::UInt32, false),
        field("messages", DataType::UInt64, false),
        field("truncated", DataType::Boolean, false),
        field("damaged", DataType::Boolean, false),
        field("corrupt_bytes", DataType::UInt64, false),
        field("findings", DataType::UInt32, false),
        field("dropouts", DataType::UInt32, false),
        field("dropout_ms", DataType::UInt64, false),
    ]);
    let parameters = Schema::new(vec![
        field("log_id", DataType::Utf8, false),
        field("name", DataType::Utf8, false),
        field("value", DataType::Float64, true),
        field("type", DataType::Utf8, false),
        field("timestamp", DataType::UInt64, true),
        field("kind", DataType::Utf8, false),
    ]);
    let messages = Schema::new(vec![
        field("log_id", DataType::Utf8, false),
        field("timestamp", DataType::UInt64, false),
        field("kind", DataType::Utf8, false),
        text("level"),
        field("tag", DataType::UInt16, true),
        field("text", DataType::Utf8, false),
        text("event"),
    ]);
    let formats = Schema::new(vec![
        field("log_id", DataType::Utf8, false),
        field("name", DataType::Utf8, false),
        field("format", DataType::Utf8, false),
    ]);
    let [analysis, flights] = super::flights::tables();
    [
        (LOGS_FILE, Arc::new(logs)),
        (PARAMETERS_FILE, Arc::new(parameters)),
        (MESSAGES_FILE, Arc::new(messages)),
        (FORMATS_FILE, Arc::new(formats)),
        analysis,
        flights,
    ]
}

/// The kind of vehicle of `MAV_TYPE` `n`, or `MAV_TYPE n`.
fn vehicle_type(n: i128) -> String {
    crate::log::params::vehicle_type(n).map_or_else(|| format!("MAV_TYPE {n}"), str::to_owned)
}

/// The text of an information value, if it is text.
fn info_text(log: &ULog<'_>, key: &str) -> Option<String> {
    let mut text = String::new();
    super::latin1(log.info_value(key)?.as_str()?.as_bytes(), &mut text);
    Some(text)
}

impl LogTables {
    /// The rows of a log read without its data (`log`, with what the pass learnt in
    /// `facts`); `utc` its clock.
    fn new(
        log: &ULog<'_>,
        facts: &Facts<'_>,
        origin: &Origin,
        utc: Option<UtcClock>,
    ) -> Result<LogTables> {
        let [logs, parameters, messages, formats, _, _] = tables().map(|(_, schema)| schema);
        let log_id = origin.log_id.as_str();
        let ids = |n: usize| -> ArrayRef {
            Arc::new(StringArray::from_iter_values(
                std::iter::repeat(log_id).take(n),
            ))
        };
        let batch = |schema: SchemaRef, columns: Vec<ArrayRef>| {
            RecordBatch::try_new(schema, columns).map_err(ExportError::encoding)
        };

        // logs: times by the log's span (`ULog::span`), which a stale or stray
        // timestamp does not stretch.
        let span = log.span();
        let start = span.start();
        let text = |v: Option<String>| -> ArrayRef { Arc::new(StringArray::from(vec![v])) };
        let mut start_utc = TimestampMicrosecondBuilder::new().with_timezone("UTC");
        start_utc.append_option(utc.as_ref().map(|c| c.at(start).micros()));
        let param = |name| log.initial_param(name).and_then(|v| v.as_i128());
        let damage = |f: &&Finding| f.is_damage() && f.kind != FindingKind::Truncated;
        let corrupt: u64 = facts.findings.iter().filter(damage).map(|f| f.len).sum();
        let dropout_ms: u64 = log
            .dropouts()
            .iter()
            .map(|d| u64::from(d.duration_ms))
            .sum();
        let logs = batch(
            logs,
            vec![
                ids(1),
                text(Some(origin.path.clone())),
                Arc::new(UInt64Builder::new().append_value_then(origin.size)),
                text(Some(origin.sha256()?)),
                Arc::new(UInt64Builder::new().append_value_then(start)),
                Arc::new(start_utc.finish()),
                text(utc.as_ref().map(|c| c.source().to_string())),
                Arc::new(Float64Builder::new().append_value_then(span.duration_s())),
                text(info_text(log, "sys_name")),
                text(info_text(log, "ver_hw")),
                text(info_text(log, "ver_sw")),
                text(log.release_version("ver_sw_release").map(|r| r.to_string())),
                text(info_text(log, "sys_uuid")),
                text(param("MAV_TYPE").map(vehicle_type)),
                Arc::new({
                    let mut b = UInt32Builder::new();
                    b.append_option(param("SYS_AUTOSTART").and_then(|n| u32::try_from(n).ok()));
                    b.finish()
                }),
                Arc::new(
                    UInt32Builder::new()
                        .append_value_then(facts.rows.iter().filter(|&&r| r > 0).count() as u32),
                ),
                Arc::new(
                    UInt64Builder::new().append_value_then(facts.rows.iter().sum::<usize>() as u64),
                ),
                Arc::new(
                    BooleanBuilder::new().append_value_then(
                        facts
                            .findings
                            .iter()
                            .any(|f| f.kind == FindingKind::Truncated),
                    ),
                ),
                Arc::new(
                    BooleanBuilder::new()
                        .append_value_then(facts.findings.iter().any(Finding::is_damage)),
                ),
                Arc::new(UInt64Builder::new().append_value_then(corrupt)),
                Arc::new(UInt32Builder::new().append_value_then(facts.findings.len() as u32)),
                Arc::new(UInt32Builder::new().append_value_then(log.dropouts().len() as u32)),
                Arc::new(UInt64Builder::new().append_value_then(dropout_ms)),
            ],
        )?;

        // parameters
        let mut p = Params::default();
        for kv in log.initial_params() {
            p.push(kv, None, "initial");
        }
        for c in log.param_changes() {
            p.push(&c.kv, Some(c.timestamp), "changed");
        }
        for d in log.default_params() {
            // Bit 0: the system's defaults, bit 1: the current configuration's.
            for (bit, kind) in [(1, "default-system"), (2, "default-configuration")] {
                if d.default_types & bit != 0 {
                    p.push(&d.kv, None, kind);
                }
            }
        }
        let n = p.name.len();
        let parameters = batch(
            parameters,
            vec![
                ids(n),
                Arc::new(p.name.finish()),
                Arc::new(p.value.finish()),
                Arc::new(p.ty.finish()),
                Arc::new(p.timestamp.finish()),
                Arc::new(p.kind.finish()),
            ],
        )?;

        // messages
        let mut m = Messages::default();
        let mut line = String::new();
        for s in log.logged_messages() {
            super::latin1(s.text.as_bytes(), &mut line);
            let kind = if s.tag.is_some() { "tagged" } else { "logged" };
            let level = s.level().map(|l| l.name().to_owned());
            m.push(s.timestamp, kind, level, s.tag, &line, None);
        }
        #[cfg(feature = "events")]
        for e in facts.events.iter().flat_map(|e| e.iter()) {
            let level = Some(e.level_name().to_owned());
            m.push(e.timestamp, "event", level, None, &e.text, e.name.clone());
        }
        let n = m.text.len();
        let messages = batch(
            messages,
            vec![
                ids(n),
                Arc::new(m.timestamp.finish()),
                Arc::new(m.kind.finish()),
                Arc::new(m.level.finish()),
                Arc::new(m.tag.finish()),
                Arc::new(m.text.finish()),
                Arc::new(m.event.finish()),
            ],
        )?;

        // formats
        let list = log.formats();
        let formats = batch(
            formats,
            vec![
                ids(list.len()),
                Arc::new(StringArray::from_iter_values(
                    list.iter().map(|f| f.name.as_str()),
                )),
                Arc::new(StringArray::from_iter_values(
                    list.iter().map(|f| f.to_string()),
                )),
            ],
        )?;
        let Some(flight) = facts.flight else {
            unreachable!("a dataset's pass analyses the log")
        };
        let [analysis, flights] = super::flights::batches(log_id, flight)?;
        Ok(LogTables([
            logs, parameters, messages, formats, analysis, flights,
        ]))
    }
}

/// One value appended, then the array.
trait AppendThen<T> {
    fn append_value_then(self, v: T) -> ArrayRef;
}

macro_rules! append_then {
    ($($builder:ty => $t:ty),*) => {$(
        impl AppendThen<$t> for $builder {
            fn append_value_then(mut self, v: $t) -> ArrayRef {
                self.append_value(v);
                Arc::new(self.finish())
            }
        }
    )*};
}
append_then!(UInt64Builder => u64, UInt32Builder => u32, Float64Builder => f64, BooleanBuilder => bool);

#[derive(Default)]
struct Params {
    name: StringBuilder,
    value: Float64Builder,
    ty: StringBuilder,
    timestamp: UInt64Builder,
    kind: StringBuilder,
}

impl Params {
    fn push(&mut self, kv: &KeyValue<'_>, timestamp: Option<u64>, kind: &str) {
        let key = kv.key.to_string_lossy();
        self.name.append_value(kv.name());
        self.value.append_option(kv.value().as_f64());
        // The key is `<type> <name>`.
        self.ty
            .append_value(key.split_once(' ').map_or(&*key, |(ty, _)| ty));
        self.timestamp.append_option(timestamp);
        self.kind.append_value(kind);
    }
}

#[derive(Default)]
struct Messages {
    timestamp: UInt64Builder,
    kind: StringBuilder,
    level: StringBuilder,
    tag: UInt16Builder,
    text: StringBuilder,
    event: StringBuilder,
}

impl Messages {
    fn push(
        &mut self,
        timestamp: u64,
        kind: &str,
        level: Option<String>,
        tag: Option<u16>,
        text: &str,
        event: Option<String>,
    ) {
        self.timestamp.append_value(timestamp);
        self.kind.append_value(kind);
        self.level.append_option(level);
        self.tag.append_option(tag);
        self.text.append_value(text);
        self.event.append_option(event);
    }
}

/// A table of the dataset read back: each log's rows by its id.
fn read_table(
    path: &Path,
    schema: &SchemaRef,
    flatten: bool,
) -> Result<BTreeMap<String, Vec<RecordBatch>>> {
    let bad = |what: String| {
        ExportError::new(ExportErrorKind::Dataset {
            what: format!("a table of the dataset cannot be read back: {what}"),
        })
        .in_file(path)
    };
    let file = File::open(path).map_err(|e| ExportError::io(e, path))?;
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| bad(e.to_string()))?;
    // A key of the file's metadata.
    let recorded = |key: &str| {
        builder
            .metadata()
            .file_metadata()
            .key_value_metadata()
            .and_then(|kv: &Vec<ParquetKeyValue>| kv.iter().find(|kv| kv.key == key))
            .and_then(|kv| kv.value.clone())
    };
    if let Some(flat) = recorded(FLATTEN_KEY) {
        if flat != flatten.to_string() {
            let (was, now) = if flatten {
                ("without", "with")
            } else {
                ("with", "without")
            };
            return Err(ExportError::new(ExportErrorKind::Dataset {
                what: format!(
                    "the dataset's topics were written {was} flattened columns, these logs \
                     would be {now}: convert them with the same options, or into another dataset"
                ),
            })
            .in_file(path));
        }
    }
    let rule = recorded(LOG_ID_KEY);
    if rule.as_deref() != Some(LOG_ID_RULE) {
        return Err(ExportError::new(ExportErrorKind::Dataset {
            what: format!(
                "the dataset's log ids were made by another rule ({}) than this version's \
                 ({LOG_ID_RULE}): the same log would be in it twice; convert into another \
                 dataset",
                rule.as_deref().unwrap_or("the SHA-256 of earlier versions")
            ),
        })
        .in_file(path));
    }
    if builder.schema().fields() != schema.fields() {
        return Err(bad(format!(
            "its columns are not those this version writes ({})",
            schema
                .fields()
                .iter()
                .map(|f| f.name().as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let reader = builder.build().map_err(|e| bad(e.to_string()))?;
    let mut rows = BTreeMap::new();
    for batch in reader {
        let batch = batch.map_err(|e| bad(e.to_string()))?;
        let batch = RecordBatch::try_new(schema.clone(), batch.columns().to_vec())
            .map_err(|e| bad(e.to_string()))?;
        let ids = batch
            .column(0)
            .as_any()
            .downcast_ref::<StringArray>()
            .ok_or_else(|| bad("its first column is not `log_id`".into()))?;
        // Each log's rows are together (the table is sorted by log_id).
        let mut at = 0;
        while at < ids.len() {
            let id = ids.value(at);
            let end = (at..ids.len())
                .find(|&i| ids.value(i) != id)
                .unwrap_or(ids.len());
            let piece = batch.slice(at, end - at);
            rows.entry(id.to_owned())
                .or_insert_with(Vec::new)
                .push(piece);
            at = end;
        }
    }
    Ok(rows)
}

/// Writes a table, every log's rows by log_id, to a partial file beside `path`, which
/// it returns.
fn write_table(
    path: &Path,
    schema: &SchemaRef,
    rows: &BTreeMap<String, Vec<RecordBatch>>,
    options: &Options,
    layout: &DatasetLayout,
) -> Result<PathBuf> {
    // One batch, however the rows came (read back or new): the writer's pages then do
    // not depend on it, and the file is the same byte for byte.
    let all = arrow_select::concat::concat_batches(schema, rows.values().flatten())
        .map_err(ExportError::encoding)?;
    let partial = path.with_file_name(partial_name(
        &path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
    ));
    let result = (|| {
        let file = File::create(&partial).map_err(|e| ExportError::io(e, path))?;
        let flatten = ParquetKeyValue::new(FLATTEN_KEY.to_owned(), options.flatten.to_string());
        let rule = ParquetKeyValue::new(LOG_ID_KEY.to_owned(), LOG_ID_RULE.to_owned());
        let props = parquet::file::properties::WriterProperties::builder()
            .set_compression(compression_of(options.compression))
            .set_key_value_metadata(Some(vec![
                flatten,
                rule,
                ParquetKeyValue::new(LAYOUT_KEY.to_owned(), layout.recorded()),
            ]))
            .build();
        let mut writer =
            ArrowWriter::try_new(std::io::BufWriter::new(file), schema.clone(), Some(props))
                .map_err(|e| write_error(path, e))?;
        writer.write(&all).map_err(|e| write_error(path, e))?;
        writer.close().map_err(|e| write_error(path, e))?;
        Ok(partial.clone())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&partial);
    }
    result
}

/// The key of the tables' metadata that says how log ids are made ([`LOG_ID_RULE`]):
/// a dataset of another rule would take a log it has as a new one.
const LOG_ID_KEY: &str = "ulog.log_id";

/// The key of the tables' metadata that says whether the topics' files have
/// flattened columns ([`Options::flatten`]): a dataset's files all have the same.
const FLATTEN_KEY: &str = "ulog.flatten";

/// The key of the tables' metadata that says how topic files are laid out
/// ([`DatasetLayout`]): the logs added later go where the others are.
const LAYOUT_KEY: &str = "ulog.layout";

#[cfg(test)]
mod tests {
    use super::*;

    /// An origin whose id and size were taken of `before`, and whose pass read `after`.
    fn origin(before: &[u8], after: &[u8]) -> Origin {
        let mut id = xxhash_rust::xxh3::Xxh3::new();
        id.update(before);
        let mut read = Hashed::default();
        read.sha256.update(after);
        read.id.update(after);
        read.bytes = after.len() as u64;
        Origin {
            log_id: id_text(&id),
            path: "flight.ulg".to_owned(),
            size: before.len() as u64,
            read: Arc::new(Mutex::new(read)),
        }
    }

    #[test]
    fn a_file_that_changed_between_its_id_and_its_pass_is_a_changed_file() {
        let log = b"ULog\x01\x12\x35\x01 some bytes of a log";
        let same = origin(log, log).sha256().unwrap();
        let expected: String = Sha256::digest(log)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(same, expected);
        let mut other = log.to_vec();
        other[20] ^= 1;
        for after in [&log[..20], &other[..]] {
            let e = origin(log, after).sha256().unwrap_err();
            assert_eq!(e.kind(), &ExportErrorKind::Read, "{e}");
            let source = std::error::Error::source(&e).and_then(|s| s.downcast_ref::<ReadError>());
            assert!(
                matches!(source.map(ReadError::kind), Some(ReadErrorKind::Changed)),
                "{e}"
            );
            assert!(e.to_string().contains("flight.ulg"), "{e}");
            assert!(e.to_string().contains("changed while it was read"), "{e}");
        }
    }
}
