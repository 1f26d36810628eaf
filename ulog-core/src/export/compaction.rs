//! Compaction of a fleet-layout dataset ([`Options::compact`](super::Options::compact)):
//! the small files that conversions adding a few logs at a time leave in a partition
//! folder are merged into files of about [`FleetLayout::file_bytes`].
//!
//! A topic partition's files of one format that are smaller than half the target are
//! taken in name order (their first logs' order) into groups of at most the target's
//! bytes; each group of two or more becomes one file, its logs in `log_id` order and
//! each log's rows as they were (row groups of whole logs, as a conversion writes
//! them). The merged file is written under a temporary name and renamed over the
//! group's file with the smallest name (it is named after its first log, and so is
//! that one), then the group's other files are removed. Between the rename and the
//! last removal a log's rows are in two files: the marker [`COMPACTING`] says so, and
//! a dataset opened with it (a compaction that died) removes every file whose logs
//! another file of its folder holds too ([`remove_superseded`]).

use std::collections::{BTreeMap, BTreeSet};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::RecordBatch;
use arrow_schema::{Schema, SchemaRef};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

use super::error::{ExportError, ExportErrorKind};
use super::files::{topic_file_id, write_error};
use super::fleet::{
    by_format, each_folder, file_schema, unreadable, LogPlace, Open, FIRMWARE_KEY, FORMAT_HASH_KEY,
    LOG_IDS_KEY, ROW_GROUP_BYTES,
};
use super::{Compression, FleetLayout};

type Result<T, E = ExportError> = core::result::Result<T, E>;

/// The marker of a compaction under way, in the dataset's folder: written before the
/// first merged file replaces one, removed once every group's old files are gone.
pub const COMPACTING: &str = "_compacting";

/// What a compaction did ([`Finished::compacted`](super::Finished::compacted)).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Compacted {
    /// Files merged (read and removed).
    pub merged: usize,
    /// Files written in their place.
    pub written: usize,
    /// Topic files of the dataset after it (the tables and union schemas aside).
    pub files: usize,
}

/// A topic file of a partition folder.
struct Small {
    path: PathBuf,
    bytes: u64,
    schema: SchemaRef,
}

/// Merges the small files of every topic partition of the dataset in `dir` (see the
/// [module](self)).
pub(super) fn compact_small_files(
    dir: &Path,
    places: &BTreeMap<String, LogPlace>,
    layout: &FleetLayout,
    compression: Compression,
) -> Result<Compacted> {
    let mut folders = Vec::new();
    leaf_folders(dir, &mut folders)?;
    let marker = dir.join(COMPACTING);
    let mut marked = false;
    let mut done = Compacted::default();
    let results = each_folder(&folders, |folder| {
        let groups = groups(folder, layout.file_bytes)?;
        Ok((folder.clone(), groups))
    });
    let mut plans = Vec::new();
    for result in results {
        let (folder, groups) = result?;
        for group in groups {
            done.files += group.len();
            if group.len() > 1 {
                plans.push((folder.clone(), group));
            }
        }
    }
    if !plans.is_empty() {
        File::create(&marker).map_err(|e| ExportError::io(e, &marker))?;
        marked = true;
    }
    let merged = each_folder(&plans, |(folder, group)| {
        merge(folder, group, places, compression)?;
        Ok(group.len())
    });
    for result in merged {
        let n = result?;
        done.merged += n;
        done.written += 1;
        done.files = done.files + 1 - n;
    }
    if marked {
        std::fs::remove_file(&marker).map_err(|e| ExportError::io(e, &marker))?;
    }
    Ok(done)
}

/// The folders of the dataset in `dir` that hold topic files: each topic folder's
/// partition folders, innermost (and the topic folder itself, for files written
/// without partitions). Folders starting with `_` or `.` are not topics.
fn leaf_folders(dir: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let mut topics: Vec<PathBuf> = read_dir(dir)?
        .into_iter()
        .filter(|(name, is_dir, _)| *is_dir && !name.starts_with(['_', '.']))
        .map(|(_, _, path)| path)
        .collect();
    topics.sort();
    for topic in topics {
        walk_partitions(&topic, out)?;
    }
    Ok(())
}

fn walk_partitions(folder: &Path, out: &mut Vec<PathBuf>) -> Result<()> {
    let mut entries = read_dir(folder)?;
    entries.sort();
    if entries
        .iter()
        .any(|(name, is_dir, _)| !is_dir && name.ends_with(".parquet"))
    {
        out.push(folder.to_owned());
    }
    for (name, is_dir, path) in entries {
        if is_dir && name.contains('=') {
            walk_partitions(&path, out)?;
        }
    }
    Ok(())
}

/// `dir`'s entries: name, whether a folder, path.
fn read_dir(dir: &Path) -> Result<Vec<(String, bool, PathBuf)>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(ExportError::io(e, dir)),
    };
    Ok(entries
        .flatten()
        .map(|e| {
            let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
            (
                e.file_name().to_string_lossy().into_owned(),
                is_dir,
                e.path(),
            )
        })
        .collect())
}

/// The topic files (`<log_id>.parquet`) of one folder, in name order.
fn topic_files(folder: &Path) -> Result<Vec<(PathBuf, u64)>> {
    let mut files: Vec<(PathBuf, u64)> = Vec::new();
    for (name, is_dir, path) in read_dir(folder)? {
        if !is_dir && topic_file_id(&name).is_some() {
            let bytes = std::fs::metadata(&path)
                .map_err(|e| ExportError::io(e, &path))?
                .len();
            files.push((path, bytes));
        }
    }
    files.sort();
    Ok(files)
}

/// The files of `folder` by format, each format's files in name order and in groups
/// of at most `file_bytes`: a group of one is a file left as it is.
fn groups(folder: &Path, file_bytes: u64) -> Result<Vec<Vec<Small>>> {
    let mut formats: Vec<Vec<Small>> = Vec::new();
    for (path, bytes) in topic_files(folder)? {
        let schema = file_schema(&path)?;
        let small = Small {
            path,
            bytes,
            schema,
        };
        by_format(&mut formats, small, |s| &s.schema);
    }
    let mut groups = Vec::new();
    for format in formats {
        let mut group: Vec<Small> = Vec::new();
        let mut size = 0;
        for file in format {
            if file.bytes * 2 >= file_bytes {
                // Large enough already: left alone.
                groups.push(vec![file]);
                continue;
            }
            if size + file.bytes > file_bytes && !group.is_empty() {
                groups.push(std::mem::take(&mut group));
                size = 0;
            }
            size += file.bytes;
            group.push(file);
        }
        if !group.is_empty() {
            groups.push(group);
        }
    }
    Ok(groups)
}

/// Merges the files of `group` (one folder, one format) into one, named after its
/// first log: renamed over the group's first file, then the others removed.
fn merge(
    folder: &Path,
    group: &[Small],
    places: &BTreeMap<String, LogPlace>,
    compression: Compression,
) -> Result<()> {
    let schema = &group[0].schema;
    // The topic's metadata as the files have it, less what is the file's own.
    let mut metadata = schema.metadata().clone();
    for key in [FIRMWARE_KEY, LOG_IDS_KEY, "ARROW:schema"] {
        metadata.remove(key);
    }
    if let Some(format) = metadata.get("ulog.format") {
        let hash = xxhash_rust::xxh3::xxh3_64(format.as_bytes());
        metadata.insert(FORMAT_HASH_KEY.to_owned(), format!("{hash:016x}"));
    }
    let described = Schema::new_with_metadata(schema.fields().clone(), metadata);
    let props = super::writer_properties(&described, compression);
    let plain = Arc::new(Schema::new(schema.fields().clone()));

    // Every log's rows, by log id (a log is in one file of a folder; its rows are
    // together there, in timestamp order).
    let mut logs: BTreeMap<String, Vec<RecordBatch>> = BTreeMap::new();
    let mut from: BTreeMap<String, &Path> = BTreeMap::new();
    for file in group {
        for (id, rows) in log_slices(&file.path, &plain)? {
            // A log in two files would be merged twice: refused, not repaired here.
            if let Some(other) = from.insert(id.clone(), &file.path) {
                if other != file.path {
                    return Err(ExportError::new(ExportErrorKind::Dataset {
                        what: format!(
                            "log {id} is in two files of this folder (the other: {}); \
                             remove the one that should not hold it",
                            other.display()
                        ),
                    })
                    .in_file(&file.path));
                }
            }
            logs.entry(id).or_default().push(rows);
        }
    }
    // The merged file replaces the group's first (both are named after their first
    // log): the rule that finishes a compaction that died relies on it.
    let first = logs.keys().next().cloned().unwrap_or_default();
    if group[0].path.file_stem() != Some(std::ffi::OsStr::new(&first)) {
        return Err(ExportError::new(ExportErrorKind::Dataset {
            what: format!("a topic file to compact is not named after its first log ({first})"),
        })
        .in_file(&group[0].path));
    }
    let mut open = Open::create(folder, &first, &plain, &props)?;
    for (id, batches) in &logs {
        for batch in batches {
            open.writer()
                .write(batch)
                .map_err(|e| write_error(&open.path, e))?;
        }
        if open.writer().in_progress_size() >= ROW_GROUP_BYTES {
            open.writer()
                .flush()
                .map_err(|e| write_error(&open.path, e))?;
        }
        open.logs.push(id.clone());
        if let Some(firmware) = places.get(id).and_then(|p| p.firmware.as_ref()) {
            open.firmware.insert(firmware.clone());
        }
    }
    // On disk before its sources go: they are the only other copy of its rows.
    let written = open.close_durably()?;
    for file in group {
        if file.path != written {
            std::fs::remove_file(&file.path).map_err(|e| ExportError::io(e, &file.path))?;
        }
    }
    Ok(())
}

/// The rows of the topic file `path`, as batches of `schema`, cut where `log_id`
/// changes: each log's rows with its id.
fn log_slices(path: &Path, schema: &SchemaRef) -> Result<Vec<(String, RecordBatch)>> {
    let file = File::open(path).map_err(|e| ExportError::io(e, path))?;
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .and_then(|b| b.build())
        .map_err(|e| unreadable(path, e))?;
    let mut out: Vec<(String, RecordBatch)> = Vec::new();
    for batch in reader {
        let batch = batch.map_err(|e| unreadable(path, e))?;
        let batch = RecordBatch::try_new(schema.clone(), batch.columns().to_vec())
            .map_err(|e| unreadable(path, e))?;
        let ids = batch
            .column_by_name("log_id")
            .and_then(|c| c.as_string_opt::<i32>())
            .ok_or_else(|| unreadable(path, "no text column log_id"))?
            .clone();
        let mut start = 0;
        while start < batch.num_rows() {
            let id = ids.value(start);
            let mut end = start + 1;
            while end < batch.num_rows() && ids.value(end) == id {
                end += 1;
            }
            out.push((id.to_owned(), batch.slice(start, end - start)));
            start = end;
        }
    }
    Ok(out)
}

/// After a compaction that died ([`COMPACTING`] in `dir`): removes every topic file
/// whose logs (its [`LOG_IDS_KEY`]) another file of its folder holds too (the merged
/// file that replaced its group's first), then the marker. The number of files
/// removed.
pub(super) fn remove_superseded(dir: &Path) -> Result<usize> {
    let marker = dir.join(COMPACTING);
    if !marker.exists() {
        return Ok(0);
    }
    let mut folders = Vec::new();
    leaf_folders(dir, &mut folders)?;
    let mut removed = 0;
    for folder in folders {
        let mut files: Vec<(PathBuf, BTreeSet<String>)> = Vec::new();
        for (path, _) in topic_files(&folder)? {
            let schema = file_schema(&path)?;
            let ids = schema
                .metadata()
                .get(LOG_IDS_KEY)
                .map(|ids| ids.split(',').map(str::to_owned).collect())
                .unwrap_or_default();
            files.push((path, ids));
        }
        for (path, ids) in &files {
            let superseded = !ids.is_empty()
                && files.iter().any(|(other, theirs)| {
                    other != path && ids.is_subset(theirs) && theirs.len() > ids.len()
                });
            if superseded {
                std::fs::remove_file(path).map_err(|e| ExportError::io(e, path))?;
                removed += 1;
            }
        }
    }
    std::fs::remove_file(&marker).map_err(|e| ExportError::io(e, &marker))?;
    Ok(removed)
}

/// The error of a compaction asked of a dataset that is not in the fleet layout.
pub(super) fn not_fleet(dir: &Path) -> ExportError {
    ExportError::new(ExportErrorKind::Dataset {
        what: "compaction merges the files of a dataset in the fleet layout, and this one \
               has a file per topic and log (a new dataset takes the fleet layout when \
               asked; an existing one keeps its own)"
            .to_owned(),
    })
    .in_file(dir)
}
