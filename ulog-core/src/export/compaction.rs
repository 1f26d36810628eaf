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

use arrow_array::cast::AsArray;
use arrow_array::RecordBatch;
use arrow_schema::SchemaRef;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

use super::error::{ExportError, ExportErrorKind};
use super::files::topic_files;
use super::fleet::{
    by_format, each_folder, file_schema, unreadable, FileFormat, LogPlace, Open, LOG_IDS_KEY,
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
    let folders = files_by_folder(dir)?;
    let marker = dir.join(COMPACTING);
    let mut marked = false;
    let mut done = Compacted::default();
    let results = each_folder(&folders, |(folder, files)| {
        Ok((folder.clone(), groups(files, layout.file_bytes)?))
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

/// The topic files of the dataset in `dir` by the folder holding them (a topic folder,
/// or its innermost partition folders), each folder's in name order.
fn files_by_folder(dir: &Path) -> Result<Vec<(PathBuf, Vec<PathBuf>)>> {
    let mut folders: BTreeMap<PathBuf, Vec<PathBuf>> = BTreeMap::new();
    for (_, path) in topic_files(dir)?.into_values().flatten() {
        let folder = path.parent().map(Path::to_owned).unwrap_or_default();
        folders.entry(folder).or_default().push(path);
    }
    for files in folders.values_mut() {
        files.sort();
    }
    Ok(folders.into_iter().collect())
}

/// The topic files of a folder (in name order) by format, each format's files in
/// groups of at most `file_bytes`: a group of one is a file left as it is.
fn groups(files: &[PathBuf], file_bytes: u64) -> Result<Vec<Vec<Small>>> {
    let mut formats: Vec<Vec<Small>> = Vec::new();
    for path in files {
        let path = path.clone();
        let bytes = std::fs::metadata(&path)
            .map_err(|e| ExportError::io(e, &path))?
            .len();
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
    let format = FileFormat::of(&group[0].schema, compression);

    // Every log's rows, by log id (a log is in one file of a folder; its rows are
    // together there, in timestamp order).
    let mut logs: BTreeMap<String, (&Path, Vec<RecordBatch>)> = BTreeMap::new();
    for file in group {
        for (id, rows) in log_slices(&file.path, &format.schema)? {
            let (from, batches) = logs.entry(id.clone()).or_insert((&file.path, Vec::new()));
            // A log in two files would be merged twice: refused, not repaired here.
            if *from != file.path {
                return Err(ExportError::new(ExportErrorKind::Dataset {
                    what: format!(
                        "log {id} is in two files of this folder (the other: {}); \
                         remove the one that should not hold it",
                        from.display()
                    ),
                })
                .in_file(&file.path));
            }
            batches.push(rows);
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
    let mut open = Open::create(folder, &first, &format)?;
    for (id, (_, rows)) in &logs {
        let firmware = places.get(id).and_then(|p| p.firmware.as_deref());
        open.push_log(id, rows, firmware)?;
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
/// file that replaced its group's first), then the marker.
pub(super) fn remove_superseded(dir: &Path) -> Result<()> {
    let marker = dir.join(COMPACTING);
    if !marker.exists() {
        return Ok(());
    }
    for (_, paths) in files_by_folder(dir)? {
        let mut files: Vec<(PathBuf, BTreeSet<String>)> = Vec::new();
        for path in paths {
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
            }
        }
    }
    std::fs::remove_file(&marker).map_err(|e| ExportError::io(e, &marker))
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
